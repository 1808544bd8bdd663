//! Whole-spread maths on values: `Sort` (values and strings), `Sum`, `Mean`,
//! `Bounds`, `Integral` and `Differential`, each per bin (see `bins`).

use std::cmp::Ordering;

use spreadlight_graph::{NodeDef, Registry};

use super::bins::bins_of;
use crate::typed::Value;

const CATEGORY: &str = "Spreads";

pub fn register(r: &mut Registry) {
    r.add(sort(
        "Sort (Spreads)",
        "Input sorted ascending (a stable sort: equal values keep their order). Former Index \
         gives, for each output slice, where it was in Input, to sort other spreads the same \
         way with GetSlice.",
        0.0f32,
        |a, b| a.total_cmp(b),
    ));
    r.add(sort(
        "Sort (String)",
        "Input sorted alphabetically (by Unicode code points; stable). Former Index gives, \
         for each output slice, where it was in Input.",
        String::new(),
        |a, b| a.cmp(b),
    ));
    r.add(per_bin(
        "Sum (Spreads)",
        "The sum of each bin of Input (Bin Size -1, the default: of the whole spread). An \
         empty bin sums to 0.",
        |bin, out| out.push(bin.iter().map(|&x| f64::from(x)).sum::<f64>() as f32),
    ));
    r.add(per_bin(
        "Mean (Spreads)",
        "The arithmetic mean of each bin of Input (Bin Size -1: of the whole spread). An \
         empty bin has mean 0.",
        |bin, out| {
            out.push(if bin.is_empty() {
                0.0
            } else {
                (bin.iter().map(|&x| f64::from(x)).sum::<f64>() / bin.len() as f64) as f32
            })
        },
    ));
    r.add(
        NodeDef::new(
            "Bounds (Spreads)",
            CATEGORY,
            "The smallest and largest slice of each bin of Input, its center and width (Bin \
             Size -1: of the whole spread). An empty bin gives 0 for all four.",
        )
        .with_pins(|p| {
            let input = p.input("Input", 0.0f32);
            let bin_size = p.input("Bin Size", -1i64);
            let outputs =
                ["Minimum", "Maximum", "Center", "Width"].map(|name| p.output::<f32>(name));
            move |cx| {
                let input = cx.get(input)?;
                let mut outs: [Vec<f32>; 4] = Default::default();
                for bin in bins_of(cx, input.len(), bin_size)? {
                    let bin = &input[bin];
                    let (lo, hi) = if bin.is_empty() {
                        (0.0, 0.0)
                    } else {
                        bin.iter()
                            .fold((f32::INFINITY, f32::NEG_INFINITY), |(lo, hi), &x| {
                                (lo.min(x), hi.max(x))
                            })
                    };
                    for (out, v) in outs.iter_mut().zip([lo, hi, (lo + hi) / 2.0, hi - lo]) {
                        out.push(v);
                    }
                }
                for (pin, out) in outputs.into_iter().zip(outs) {
                    cx.put(pin, out);
                }
                Ok(())
            }
        }),
    );
    r.add(per_bin(
        "Integral (Spreads)",
        "Running sum within each bin of Input: slice i is the sum of slices 0 to i of its \
         bin (Bin Size -1: of the whole spread).",
        |bin, out| {
            let mut sum = 0.0f64;
            out.extend(bin.iter().map(|&x| {
                sum += f64::from(x);
                sum as f32
            }));
        },
    ));
    r.add(per_bin(
        "Differential (Spreads)",
        "Differences of neighbours within each bin of Input: slice i is Input[i + 1] - \
         Input[i], so a bin of n slices gives n - 1 (Bin Size -1: the whole spread).",
        |bin, out| out.extend(bin.windows(2).map(|w| w[1] - w[0])),
    ));
}

/// A stable sort of Input by `cmp`, with each output slice's former index.
fn sort<T: Value>(
    name: &'static str,
    help: &'static str,
    default: T,
    cmp: fn(&T, &T) -> Ordering,
) -> NodeDef {
    NodeDef::new(name, CATEGORY, help).with_pins(|p| {
        let input = p.input("Input", default);
        let output = p.output::<T>("Output");
        let former_index = p.output::<i64>("Former Index");
        move |cx| {
            let input = cx.get(input)?;
            let mut order: Vec<usize> = (0..input.len()).collect();
            order.sort_by(|&a, &b| cmp(&input[a], &input[b]));
            let out: Vec<T> = order.iter().map(|&i| input[i].clone()).collect();
            cx.put(output, out);
            cx.put(former_index, order.into_iter().map(|i| i as i64).collect());
            Ok(())
        }
    })
}

/// A node with Input and Bin Size that runs `f` over each bin of Input,
/// appending what it gives to Output.
fn per_bin(name: &'static str, help: &'static str, f: fn(&[f32], &mut Vec<f32>)) -> NodeDef {
    NodeDef::new(name, CATEGORY, help).with_pins(|p| {
        let input = p.input("Input", 0.0f32);
        let bin_size = p.input("Bin Size", -1i64);
        let output = p.output::<f32>("Output");
        move |cx| {
            let input = cx.get(input)?;
            let mut out = Vec::new();
            for bin in bins_of(cx, input.len(), bin_size)? {
                f(&input[bin], &mut out);
            }
            cx.put(output, out);
            Ok(())
        }
    })
}

#[cfg(test)]
mod tests {
    use spreadlight_graph::Spread;

    use crate::testing::{eval, eval_out, floats, ints};

    #[test]
    fn sort_is_stable_and_reports_former_index() {
        let out = eval(
            "Sort (Spreads)",
            &[("Input", floats(&[3.0, -1.0, 2.0, -1.0]))],
        )
        .expect("sort");
        assert_eq!(out[0], floats(&[-1.0, -1.0, 2.0, 3.0]));
        assert_eq!(out[1], ints(&[1, 3, 2, 0]));
        let s: Vec<String> = eval_out(
            "Sort (String)",
            &[(
                "Input",
                Spread::String(vec!["b".into(), "a".into(), "C".into()]),
            )],
            "Output",
        );
        assert_eq!(s, ["C", "a", "b"]);
    }

    #[test]
    fn sum_mean_per_bin() {
        let input = ("Input", floats(&[1.0, 2.0, 3.0, 4.0, 5.0]));
        let sum: Vec<f32> = eval_out("Sum (Spreads)", std::slice::from_ref(&input), "Output");
        assert_eq!(sum, [15.0]);
        let sum: Vec<f32> = eval_out(
            "Sum (Spreads)",
            &[input.clone(), ("Bin Size", ints(&[2]))],
            "Output",
        );
        assert_eq!(sum, [3.0, 7.0, 5.0]);
        let mean: Vec<f32> = eval_out("Mean (Spreads)", &[input], "Output");
        assert_eq!(mean, [3.0]);
        let mean: Vec<f32> = eval_out("Mean (Spreads)", &[("Input", floats(&[]))], "Output");
        assert_eq!(mean, [0.0]);
    }

    #[test]
    fn bounds_integral_differential() {
        let input = ("Input", floats(&[2.0, -1.0, 5.0, 4.0]));
        let out = eval("Bounds (Spreads)", std::slice::from_ref(&input)).expect("bounds");
        assert_eq!(
            out,
            [
                floats(&[-1.0]),
                floats(&[5.0]),
                floats(&[2.0]),
                floats(&[6.0])
            ]
        );
        let out: Vec<f32> = eval_out(
            "Integral (Spreads)",
            &[input.clone(), ("Bin Size", ints(&[2]))],
            "Output",
        );
        assert_eq!(out, [2.0, 1.0, 5.0, 9.0]);
        let out: Vec<f32> = eval_out("Differential (Spreads)", &[input], "Output");
        assert_eq!(out, [-3.0, 6.0, -1.0]);
    }
}
