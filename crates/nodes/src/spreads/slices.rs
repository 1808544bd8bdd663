//! Reading and writing slices by index: `GetSlice`, `SetSlice`, `GetSpread`,
//! `Select`, `Reverse` and `Shift`, one node type per slice type (see
//! `typed!`). Indices wrap around, as everywhere in vvvv: -1 is the last slice.

use spreadlight_graph::spread::{slice_count, wrapped};
use spreadlight_graph::typed_pins::InputPin;
use spreadlight_graph::{NodeDef, NodeError, Registry};

use super::MAX_SLICES;
use super::bins::bins_of;
use crate::typed::Value;

const CATEGORY: &str = "Spreads";

pub fn register(r: &mut Registry) {
    typed!(r, get_slice, "GetSlice", "Spreads");
    typed!(r, set_slice, "SetSlice", "Spreads");
    typed!(r, get_spread, "GetSpread", "Spreads");
    typed!(r, select, "Select", "Spreads");
    typed!(r, reverse, "Reverse", "Spreads");
    typed!(r, shift, "Shift", "Spreads");
}

/// Index `i` into `len` slices, wrapping (negative counts from the end).
pub(crate) fn wrap_index(i: i64, len: usize) -> usize {
    // `len` fits in i64 for any spread that fits in memory.
    i.rem_euclid(len as i64) as usize
}

/// Refuse outputs over [`MAX_SLICES`] slices, naming the pin that asked for them.
fn check_total(
    cx: &spreadlight_graph::EvalContext<'_>,
    pin: impl InputPin,
    total: usize,
) -> Result<(), NodeError> {
    if total > MAX_SLICES {
        return Err(cx.error(pin, format!("asks for more than {MAX_SLICES} slices")));
    }
    Ok(())
}

fn get_slice<T: Value>(name: &'static str, default: T) -> NodeDef {
    NodeDef::new(
        name,
        CATEGORY,
        "The bins of Input at Index, one after the other. Bin Size cuts Input into bins (1: \
         every slice its own bin; sizes wrap, so 2, 3 alternates; -1: the whole spread as one \
         bin; -k: k equal bins). Indices wrap around: -1 is the last bin. Output Bin Size says \
         how many slices each index gave. An empty Input gives an empty Output.",
    )
    .with_pins(|p| {
        let input_pin = p.input("Input", default);
        let bin_size = p.input("Bin Size", 1i64);
        let index_pin = p.input("Index", 0i64);
        let output = p.output::<T>("Output");
        let output_bin_size = p.output::<i64>("Output Bin Size");
        move |cx| {
            let input = cx.get(input_pin)?;
            let index = cx.get(index_pin)?;
            let bins = bins_of(cx, input.len(), bin_size)?;
            let (mut out, mut sizes) = (Vec::new(), Vec::with_capacity(index.len()));
            if !input.is_empty() && !bins.is_empty() {
                for &i in index {
                    let bin = bins[wrap_index(i, bins.len())].clone();
                    sizes.push(bin.len() as i64);
                    out.extend_from_slice(&input[bin]);
                    check_total(cx, index_pin, out.len())?;
                }
            }
            cx.put(output, out);
            cx.put(output_bin_size, sizes);
            Ok(())
        }
    })
}

fn set_slice<T: Value>(name: &'static str, default: T) -> NodeDef {
    NodeDef::new(
        name,
        CATEGORY,
        "Spread with the slices at Index replaced by Input: Input and Index spread together \
         (the longer decides how many slices are written, in order, so a later write to the \
         same index wins). Indices wrap around Spread's count. An empty Spread, Input or Index \
         changes nothing.",
    )
    .with_pins(|p| {
        let spread = p.input("Spread", default.clone());
        let input = p.input("Input", default);
        let index = p.input("Index", 0i64);
        let output = p.output::<T>("Output");
        move |cx| {
            let mut out = cx.get(spread)?.to_vec();
            let input = cx.get(input)?;
            let index = cx.get(index)?;
            if !out.is_empty() {
                let len = out.len();
                for k in 0..slice_count([input.len(), index.len()]) {
                    out[wrap_index(*wrapped(index, k), len)] = wrapped(input, k).clone();
                }
            }
            cx.put(output, out);
            Ok(())
        }
    })
}

fn get_spread<T: Value>(name: &'static str, default: T) -> NodeDef {
    NodeDef::new(
        name,
        CATEGORY,
        "Count slices of Input starting at Offset, wrapping around the end. Offset and Count \
         spread: each pair gives a sub-spread and they are output one after the other. A \
         negative Count is an error.",
    )
    .with_pins(|p| {
        let input = p.input("Input", default);
        let offset = p.input("Offset", 0i64);
        let count_pin = p.input("Count", 1i64);
        let output = p.output::<T>("Output");
        move |cx| {
            let input = cx.get(input)?;
            let (offset, count) = (cx.get(offset)?, cx.get(count_pin)?);
            let mut out = Vec::new();
            if !input.is_empty() {
                for k in 0..slice_count([offset.len(), count.len()]) {
                    let c = *wrapped(count, k);
                    if c < 0 {
                        return Err(cx.error(count_pin, format!("slice {k}: {c} is negative")));
                    }
                    check_total(cx, count_pin, out.len().saturating_add(c as usize))?;
                    let start = *wrapped(offset, k);
                    out.extend((0..c).map(|j| input[wrap_index(start + j, input.len())].clone()));
                }
            }
            cx.put(output, out);
            Ok(())
        }
    })
}

fn select<T: Value>(name: &'static str, default: T) -> NodeDef {
    NodeDef::new(
        name,
        CATEGORY,
        "Repeats each slice of Input as often as Select says (0 or less drops it), spreading \
         Input and Select together. Former Slice gives, for each output slice, the index of \
         the Input slice it came from.",
    )
    .with_pins(|p| {
        let input = p.input("Input", default);
        let select_pin = p.input("Select", 1i64);
        let output = p.output::<T>("Output");
        let former_slice = p.output::<i64>("Former Slice");
        move |cx| {
            let input = cx.get(input)?;
            let select = cx.get(select_pin)?;
            let n = slice_count([input.len(), select.len()]);
            let total = (0..n).fold(0usize, |t, k| {
                t.saturating_add(usize::try_from(*wrapped(select, k)).unwrap_or(0))
            });
            check_total(cx, select_pin, total)?;
            let (mut out, mut former) = (Vec::with_capacity(total), Vec::with_capacity(total));
            for k in 0..n {
                let times = usize::try_from(*wrapped(select, k)).unwrap_or(0);
                let source = k % input.len();
                out.extend(std::iter::repeat_n(input[source].clone(), times));
                former.extend(std::iter::repeat_n(source as i64, times));
            }
            cx.put(output, out);
            cx.put(former_slice, former);
            Ok(())
        }
    })
}

fn reverse<T: Value>(name: &'static str, default: T) -> NodeDef {
    NodeDef::new(
        name,
        CATEGORY,
        "Input in reverse order. With a Bin Size, the slices are reversed within each bin \
         and the bins stay in place (-1, the default: the whole spread is one bin).",
    )
    .with_pins(|p| {
        let input = p.input("Input", default);
        let bin_size = p.input("Bin Size", -1i64);
        let output = p.output::<T>("Output");
        move |cx| {
            let input = cx.get(input)?;
            let bins = bins_of(cx, input.len(), bin_size)?;
            let out: Vec<T> = bins
                .into_iter()
                .flat_map(|b| input[b].iter().rev().cloned())
                .collect();
            cx.put(output, out);
            Ok(())
        }
    })
}

fn shift<T: Value>(name: &'static str, default: T) -> NodeDef {
    NodeDef::new(
        name,
        CATEGORY,
        "Rotates Input by Offset slices: slice i moves to i + Offset, and what falls off the \
         end comes back at the start (-1 moves every slice one step towards the start). With \
         a Bin Size each bin rotates on its own, by its own slice of Offset (wrapping).",
    )
    .with_pins(|p| {
        let input = p.input("Input", default);
        let offset = p.input("Offset", 1i64);
        let bin_size = p.input("Bin Size", -1i64);
        let output = p.output::<T>("Output");
        move |cx| {
            let input = cx.get(input)?;
            let offset = cx.get(offset)?;
            let bins = bins_of(cx, input.len(), bin_size)?;
            let mut out = Vec::with_capacity(input.len());
            if !offset.is_empty() {
                for (b, bin) in bins.into_iter().enumerate() {
                    let slices = &input[bin];
                    let len = slices.len();
                    let by = if len == 0 {
                        0
                    } else {
                        wrap_index(*wrapped(offset, b), len)
                    };
                    out.extend((0..len).map(|i| slices[(i + len - by) % len].clone()));
                }
            }
            cx.put(output, out);
            Ok(())
        }
    })
}

#[cfg(test)]
mod tests {
    use glam::Vec3;
    use spreadlight_graph::Spread;

    use crate::testing::{eval, eval_err, eval_out, floats, ints, strings_of as strings};

    #[test]
    fn get_slice_wraps_indices_and_reads_bins() {
        let input = ("Input", floats(&[10.0, 11.0, 12.0, 13.0, 14.0]));
        let get = |values: &[(&str, Spread)]| -> Vec<f32> {
            let mut v = vec![input.clone()];
            v.extend_from_slice(values);
            eval_out("GetSlice (Spreads)", &v, "Output")
        };
        assert_eq!(get(&[("Index", ints(&[0, -1, 7]))]), [10.0, 14.0, 12.0]);
        assert_eq!(
            get(&[("Index", ints(&[1])), ("Bin Size", ints(&[2]))]),
            [12.0, 13.0]
        );
        // Bins 2, 3: index 1 is the second bin, three slices.
        let out = eval(
            "GetSlice (Spreads)",
            &[
                input.clone(),
                ("Bin Size", ints(&[2, 3])),
                ("Index", ints(&[1, 0])),
            ],
        )
        .expect("get slice");
        assert_eq!(out[0], floats(&[12.0, 13.0, 14.0, 10.0, 11.0]));
        assert_eq!(out[1], ints(&[3, 2]));
        let empty: Vec<f32> = eval_out("GetSlice (Spreads)", &[("Input", floats(&[]))], "Output");
        assert!(empty.is_empty());
    }

    #[test]
    fn get_slice_is_typed_per_variant() {
        let v: Vec<Vec3> = eval_out(
            "GetSlice (Vector 3d)",
            &[
                ("Input", Spread::Vec3(vec![Vec3::X, Vec3::Y, Vec3::Z])),
                ("Index", ints(&[2, 0])),
            ],
            "Output",
        );
        assert_eq!(v, [Vec3::Z, Vec3::X]);
        let s: Vec<String> = eval_out(
            "GetSlice (String)",
            &[("Input", strings(&["a", "b"])), ("Index", ints(&[-1]))],
            "Output",
        );
        assert_eq!(s, ["b"]);
    }

    /// Sort's Former Index through GetSlice (Integer) stays Int, so it can index again.
    #[test]
    fn integer_variants_keep_indices_linkable() {
        use spreadlight_graph::{FrameClock, NodeDoc, NodeId, Patch, Runtime};
        let mut p = Patch::default();
        p.add(NodeDoc::new(1, "Sort (Spreads)").with("Input", vec![3.0f32, 1.0, 2.0]));
        p.add(NodeDoc::new(2, "Reverse (Integer)"));
        p.add(NodeDoc::new(3, "GetSlice (String)").with("Input", strings(&["a", "b", "c"])));
        p.add(NodeDoc::new(4, "Probe"));
        p.link(1, "Former Index", 2, "Input");
        p.link(2, "Output", 3, "Index");
        p.link(3, "Output", 4, "Input");
        let mut rt = Runtime::new(crate::registry());
        assert!(rt.load(&p).is_empty(), "{:?}", rt.problems());
        rt.evaluate(FrameClock::fixed(0, 60.0));
        let out = rt.output(NodeId(3), "Output").expect("output");
        // Sorted descending by value: 3.0 (a), 2.0 (c), 1.0 (b).
        assert_eq!(**out, strings(&["a", "c", "b"]));
    }

    #[test]
    fn set_slice_writes_in_order() {
        let out: Vec<f32> = eval_out(
            "SetSlice (Spreads)",
            &[
                ("Spread", floats(&[0.0, 0.0, 0.0, 0.0])),
                ("Input", floats(&[1.0, 2.0])),
                ("Index", ints(&[1, -1, 5])),
            ],
            "Output",
        );
        // Writes 1 -> slice 1, 2 -> slice 3, then 1 -> slice 5 % 4 = 1 again.
        assert_eq!(out, [0.0, 1.0, 0.0, 2.0]);
        let out: Vec<f32> = eval_out("SetSlice (Spreads)", &[("Spread", floats(&[]))], "Output");
        assert!(out.is_empty());
    }

    #[test]
    fn get_spread_takes_runs_with_wrapping() {
        let out: Vec<String> = eval_out(
            "GetSpread (String)",
            &[
                ("Input", strings(&["a", "b", "c", "d"])),
                ("Offset", ints(&[3, 0])),
                ("Count", ints(&[3, 1])),
            ],
            "Output",
        );
        assert_eq!(out, ["d", "a", "b", "a"]);
        eval_err("GetSpread (Spreads)", &[("Count", ints(&[-1]))], "Count");
    }

    #[test]
    fn select_repeats_and_reports_former_slices() {
        let out = eval(
            "Select (Spreads)",
            &[
                ("Input", floats(&[1.0, 2.0, 3.0])),
                ("Select", ints(&[2, 0, 1])),
            ],
        )
        .expect("select");
        assert_eq!(out[0], floats(&[1.0, 1.0, 3.0]));
        assert_eq!(out[1], ints(&[0, 0, 2]));
        eval_err(
            "Select (Spreads)",
            &[("Select", ints(&[i64::MAX]))],
            "Select",
        );
    }

    #[test]
    fn reverse_whole_and_per_bin() {
        let input = ("Input", floats(&[1.0, 2.0, 3.0, 4.0, 5.0, 6.0]));
        let whole: Vec<f32> = eval_out("Reverse (Spreads)", std::slice::from_ref(&input), "Output");
        assert_eq!(whole, [6.0, 5.0, 4.0, 3.0, 2.0, 1.0]);
        let bins: Vec<f32> = eval_out(
            "Reverse (Spreads)",
            &[input, ("Bin Size", ints(&[3]))],
            "Output",
        );
        assert_eq!(bins, [3.0, 2.0, 1.0, 6.0, 5.0, 4.0]);
    }

    #[test]
    fn shift_rotates_both_ways() {
        let shift = |offset: i64, bin: i64| -> Vec<f32> {
            eval_out(
                "Shift (Spreads)",
                &[
                    ("Input", floats(&[1.0, 2.0, 3.0, 4.0])),
                    ("Offset", ints(&[offset])),
                    ("Bin Size", ints(&[bin])),
                ],
                "Output",
            )
        };
        assert_eq!(shift(1, -1), [4.0, 1.0, 2.0, 3.0]);
        assert_eq!(shift(-1, -1), [2.0, 3.0, 4.0, 1.0]);
        assert_eq!(shift(5, -1), [4.0, 1.0, 2.0, 3.0]);
        assert_eq!(shift(1, 2), [2.0, 1.0, 4.0, 3.0]);
    }
}
