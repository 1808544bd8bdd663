//! Joining spreads and taking them apart: `Zip`/`Unzip` (two ways),
//! `Stallone` split and join (four ways), `Cons` (concatenation) and `Count`.
//! One node type per slice type (see `typed!`), except `Count`, which takes
//! a spread of any type.

use spreadlight_graph::spread::{cycled, slice_count};
use spreadlight_graph::{NodeDef, PinType, Registry, Spread};

use super::MAX_SLICES;
use crate::typed::Value;

const CATEGORY: &str = "Spreads";

/// How many ways `Stallone` splits and joins.
const STALLONE_WAYS: usize = 4;
const STALLONE_INPUTS: [&str; STALLONE_WAYS] = ["Input 1", "Input 2", "Input 3", "Input 4"];
const STALLONE_OUTPUTS: [&str; STALLONE_WAYS] = ["Output 1", "Output 2", "Output 3", "Output 4"];

pub fn register(r: &mut Registry) {
    typed!(r, zip, "Zip", "Spreads");
    typed!(r, unzip, "Unzip", "Spreads");
    typed!(r, stallone_join, "Stallone", "Spreads", "Join");
    typed!(r, stallone_split, "Stallone", "Spreads", "Split");
    typed!(r, cons, "Cons", "Spreads");
    r.add(
        NodeDef::new(
            "Count (Spreads)",
            CATEGORY,
            "The number of slices of Input, whatever its type.",
        )
        .with_pins(|p| {
            let input = p.input_any("Input", PinType::Any, Spread::Float(Vec::new()));
            let count = p.output::<i64>("Count");
            move |cx| {
                let n = cx.spread(input).len() as i64;
                cx.put(count, vec![n]);
                Ok(())
            }
        }),
    );
}

/// Interleave `inputs` slice by slice, spreading them to the longest (nothing if any is empty).
fn interleave<T: Clone>(inputs: &[&[T]]) -> Vec<T> {
    let n = slice_count(inputs.iter().map(|s| s.len()));
    let mut iters: Vec<_> = inputs.iter().map(|s| cycled(s, n)).collect();
    let mut out = Vec::with_capacity(n * inputs.len());
    for _ in 0..n {
        for it in &mut iters {
            out.extend(it.next().cloned());
        }
    }
    out
}

/// Deal the slices of `input` to `ways` outputs in turn, `bin` slices at a time.
fn deal<T: Clone>(input: &[T], ways: usize, bin: usize) -> Vec<Vec<T>> {
    let mut outs = vec![Vec::with_capacity(input.len() / ways + 1); ways];
    for (k, chunk) in input.chunks(bin.max(1)).enumerate() {
        outs[k % ways].extend_from_slice(chunk);
    }
    outs
}

fn zip<T: Value>(name: &'static str, default: T) -> NodeDef {
    NodeDef::new(
        name,
        CATEGORY,
        "Interleaves Input 1 and Input 2: slice 0 of each, then slice 1 of each, and so on. \
         The shorter input wraps around; an empty one gives an empty Output.",
    )
    .with_pins(|p| {
        let a = p.input("Input 1", default.clone());
        let b = p.input("Input 2", default);
        let output = p.output::<T>("Output");
        move |cx| {
            let out = interleave(&[cx.get(a)?, cx.get(b)?]);
            cx.put(output, out);
            Ok(())
        }
    })
}

fn unzip<T: Value>(name: &'static str, default: T) -> NodeDef {
    NodeDef::new(
        name,
        CATEGORY,
        "Takes Input apart in turn, Bin Size slices at a time: the even bins go to Output 1, \
         the odd ones to Output 2 (Zip's inverse). A Bin Size below 1 counts as 1.",
    )
    .with_pins(|p| {
        let input = p.input("Input", default);
        let bin_size = p.input("Bin Size", 1i64);
        let outputs = [p.output::<T>("Output 1"), p.output::<T>("Output 2")];
        move |cx| {
            let bin = cx.first(bin_size, 1)?;
            let outs = deal(cx.get(input)?, 2, usize::try_from(bin).unwrap_or(1));
            for (pin, out) in outputs.into_iter().zip(outs) {
                cx.put(pin, out);
            }
            Ok(())
        }
    })
}

fn stallone_join<T: Value>(name: &'static str, default: T) -> NodeDef {
    NodeDef::new(
        name,
        CATEGORY,
        "Joins four spreads into one by taking a slice of each in turn (Input 1, 2, 3, 4, then \
         again), as vvvv's Stallone with four inputs: Zip for four. Shorter inputs wrap; an \
         empty one gives an empty Output.",
    )
    .with_pins(|p| {
        let inputs = STALLONE_INPUTS.map(|pin| p.input(pin, default.clone()));
        let output = p.output::<T>("Output");
        move |cx| {
            let inputs = inputs
                .iter()
                .map(|&pin| cx.get(pin))
                .collect::<Result<Vec<_>, _>>()?;
            let out = interleave(&inputs);
            cx.put(output, out);
            Ok(())
        }
    })
}

fn stallone_split<T: Value>(name: &'static str, default: T) -> NodeDef {
    NodeDef::new(
        name,
        CATEGORY,
        "Splits Input four ways, as vvvv's Stallone with four outputs: bin 0 (Bin Size slices) \
         goes to Output 1, bin 1 to Output 2, bin 2 to Output 3, bin 3 to Output 4, bin 4 to \
         Output 1 again, and so on. A Bin Size below 1 counts as 1.",
    )
    .with_pins(|p| {
        let input = p.input("Input", default);
        let bin_size = p.input("Bin Size", 1i64);
        let outputs = STALLONE_OUTPUTS.map(|pin| p.output::<T>(pin));
        move |cx| {
            let bin = cx.first(bin_size, 1)?;
            let outs = deal(
                cx.get(input)?,
                STALLONE_WAYS,
                usize::try_from(bin).unwrap_or(1),
            );
            for (pin, out) in outputs.into_iter().zip(outs) {
                cx.put(pin, out);
            }
            Ok(())
        }
    })
}

fn cons<T: Value>(name: &'static str, default: T) -> NodeDef {
    NodeDef::new(
        name,
        CATEGORY,
        "Concatenates Input 1 and Input 2: all of Input 1, then all of Input 2 (an empty input \
         adds nothing). Output Bin Size gives the two counts, to take the result apart again \
         with GetSlice's Bin Size.",
    )
    .with_pins(|p| {
        let first = p.input("Input 1", default.clone());
        let second = p.input("Input 2", default);
        let output = p.output::<T>("Output");
        let output_bin_size = p.output::<i64>("Output Bin Size");
        move |cx| {
            let (a, b) = (cx.get(first)?, cx.get(second)?);
            if a.len().saturating_add(b.len()) > MAX_SLICES {
                return Err(cx.error(second, format!("more than {MAX_SLICES} slices")));
            }
            let sizes = vec![a.len() as i64, b.len() as i64];
            let out = [a, b].concat();
            cx.put(output, out);
            cx.put(output_bin_size, sizes);
            Ok(())
        }
    })
}

#[cfg(test)]
mod tests {
    use glam::Vec2;
    use spreadlight_graph::{Color, Spread};

    use crate::testing::{eval, eval_out, floats, ints};

    #[test]
    fn zip_and_unzip_are_inverse() {
        let zipped: Vec<f32> = eval_out(
            "Zip (Spreads)",
            &[
                ("Input 1", floats(&[1.0, 2.0, 3.0])),
                ("Input 2", floats(&[10.0])),
            ],
            "Output",
        );
        assert_eq!(zipped, [1.0, 10.0, 2.0, 10.0, 3.0, 10.0]);
        let out = eval("Unzip (Spreads)", &[("Input", floats(&zipped))]).expect("unzip");
        assert_eq!(out, [floats(&[1.0, 2.0, 3.0]), floats(&[10.0, 10.0, 10.0])]);
        let out = eval(
            "Unzip (Spreads)",
            &[
                ("Input", floats(&[1.0, 2.0, 3.0, 4.0, 5.0])),
                ("Bin Size", ints(&[2])),
            ],
        )
        .expect("unzip bins");
        assert_eq!(out, [floats(&[1.0, 2.0, 5.0]), floats(&[3.0, 4.0])]);
        let empty: Vec<f32> = eval_out("Zip (Spreads)", &[("Input 2", floats(&[]))], "Output");
        assert!(empty.is_empty());
    }

    #[test]
    fn stallone_splits_and_joins_four_ways() {
        let input = Spread::Vec2((0..6).map(|i| Vec2::splat(i as f32)).collect());
        let out = eval("Stallone (Vector 2d Split)", &[("Input", input.clone())]).expect("split");
        let v = |xs: &[f32]| Spread::Vec2(xs.iter().map(|&x| Vec2::splat(x)).collect());
        assert_eq!(out, [v(&[0.0, 4.0]), v(&[1.0, 5.0]), v(&[2.0]), v(&[3.0])]);
        let joined: Vec<Vec2> = eval_out(
            "Stallone (Vector 2d Join)",
            &[
                ("Input 1", out[0].clone()),
                ("Input 2", out[1].clone()),
                ("Input 3", v(&[2.0, 6.0])),
                ("Input 4", v(&[3.0, 7.0])),
            ],
            "Output",
        );
        assert_eq!(
            joined,
            [0.0, 1.0, 2.0, 3.0, 4.0, 5.0, 6.0, 7.0].map(Vec2::splat)
        );
    }

    #[test]
    fn cons_concatenates_with_bin_sizes() {
        let out = eval(
            "Cons (Color)",
            &[
                ("Input 1", Spread::Color(vec![Color::BLACK; 2])),
                ("Input 2", Spread::Color(vec![])),
            ],
        )
        .expect("cons");
        assert_eq!(out[0], Spread::Color(vec![Color::BLACK; 2]));
        assert_eq!(out[1], ints(&[2, 0]));
    }

    #[test]
    fn count_takes_any_type() {
        let n: Vec<i64> = eval_out(
            "Count (Spreads)",
            &[("Input", floats(&[1.0, 2.0]))],
            "Count",
        );
        assert_eq!(n, [2]);
        let n: Vec<i64> = eval_out(
            "Count (Spreads)",
            &[("Input", Spread::String(vec![String::new(); 5]))],
            "Count",
        );
        assert_eq!(n, [5]);
    }
}
