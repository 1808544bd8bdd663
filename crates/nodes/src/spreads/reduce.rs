//! Whole-spread maths on values: `Sort` (values and strings), `Sum`, `Mean`,
//! `Bounds`, `Integral` and `Differential`, each per bin (see `bins`).

use std::cmp::Ordering;

use spreadlight_graph::{EvalContext, NodeDef, NodeError, Registry};

use super::bins::bins_of;

const CATEGORY: &str = "Spreads";

pub fn register(r: &mut Registry) {
    r.add(
        NodeDef::new(
            "Sort (Spreads)",
            CATEGORY,
            "Input sorted ascending (a stable sort: equal values keep their order). Former Index \
             gives, for each output slice, where it was in Input, to sort other spreads the same \
             way with GetSlice.",
        )
        .input("Input", 0.0f32)
        .output::<f32>("Output")
        .output::<i64>("Former Index")
        .evaluate(|cx| sort_by(cx, |a: &f32, b: &f32| a.total_cmp(b))),
    );
    r.add(
        NodeDef::new(
            "Sort (String)",
            CATEGORY,
            "Input sorted alphabetically (by Unicode code points; stable). Former Index gives, \
             for each output slice, where it was in Input.",
        )
        .input("Input", String::new())
        .output::<String>("Output")
        .output::<i64>("Former Index")
        .evaluate(|cx| sort_by(cx, |a: &String, b: &String| a.cmp(b))),
    );
    r.add(per_bin(
        "Sum (Spreads)",
        "The sum of each bin of Input (Bin Size -1, the default: of the whole spread). An \
         empty bin sums to 0.",
        |bin| bin.iter().map(|&x| f64::from(x)).sum::<f64>() as f32,
    ));
    r.add(per_bin(
        "Mean (Spreads)",
        "The arithmetic mean of each bin of Input (Bin Size -1: of the whole spread). An \
         empty bin has mean 0.",
        |bin| {
            if bin.is_empty() {
                0.0
            } else {
                (bin.iter().map(|&x| f64::from(x)).sum::<f64>() / bin.len() as f64) as f32
            }
        },
    ));
    r.add(
        NodeDef::new(
            "Bounds (Spreads)",
            CATEGORY,
            "The smallest and largest slice of each bin of Input, its center and width (Bin \
             Size -1: of the whole spread). An empty bin gives 0 for all four.",
        )
        .input("Input", 0.0f32)
        .input("Bin Size", -1i64)
        .output::<f32>("Minimum")
        .output::<f32>("Maximum")
        .output::<f32>("Center")
        .output::<f32>("Width")
        .evaluate(bounds),
    );
    r.add(
        NodeDef::new(
            "Integral (Spreads)",
            CATEGORY,
            "Running sum within each bin of Input: slice i is the sum of slices 0 to i of its \
             bin (Bin Size -1: of the whole spread).",
        )
        .input("Input", 0.0f32)
        .input("Bin Size", -1i64)
        .output::<f32>("Output")
        .evaluate(|cx| {
            per_bin_map(cx, |bin, out| {
                let mut sum = 0.0f64;
                out.extend(bin.iter().map(|&x| {
                    sum += f64::from(x);
                    sum as f32
                }));
            })
        }),
    );
    r.add(
        NodeDef::new(
            "Differential (Spreads)",
            CATEGORY,
            "Differences of neighbours within each bin of Input: slice i is Input[i + 1] - \
             Input[i], so a bin of n slices gives n - 1 (Bin Size -1: the whole spread).",
        )
        .input("Input", 0.0f32)
        .input("Bin Size", -1i64)
        .output::<f32>("Output")
        .evaluate(|cx| {
            per_bin_map(cx, |bin, out| {
                out.extend(bin.windows(2).map(|w| w[1] - w[0]));
            })
        }),
    );
}

fn sort_by<T: spreadlight_graph::SliceValue>(
    cx: &mut EvalContext<'_>,
    cmp: impl Fn(&T, &T) -> Ordering,
) -> Result<(), NodeError> {
    let input = cx.slices::<T>(0)?;
    let mut order: Vec<usize> = (0..input.len()).collect();
    order.sort_by(|&a, &b| cmp(&input[a], &input[b]));
    let out: Vec<T> = order.iter().map(|&i| input[i].clone()).collect();
    cx.set(0, out);
    cx.set(1, order.into_iter().map(|i| i as i64).collect());
    Ok(())
}

/// A node with Input and Bin Size giving one value per bin.
fn per_bin(name: &'static str, help: &'static str, f: fn(&[f32]) -> f32) -> NodeDef {
    NodeDef::new(name, CATEGORY, help)
        .input("Input", 0.0f32)
        .input("Bin Size", -1i64)
        .output::<f32>("Output")
        .construct(move || PerBin(f))
}

struct PerBin(fn(&[f32]) -> f32);

impl spreadlight_graph::Node for PerBin {
    fn evaluate(&mut self, cx: &mut EvalContext<'_>) -> Result<(), NodeError> {
        let f = self.0;
        per_bin_map(cx, |bin, out| out.push(f(bin)))
    }
}

/// Run `f` over each bin of input 0 (cut by input 1), appending to output 0.
fn per_bin_map(
    cx: &mut EvalContext<'_>,
    mut f: impl FnMut(&[f32], &mut Vec<f32>),
) -> Result<(), NodeError> {
    let input = cx.slices::<f32>(0)?;
    let mut out = Vec::new();
    for bin in bins_of(cx, input.len(), 1)? {
        f(&input[bin], &mut out);
    }
    cx.set(0, out);
    Ok(())
}

fn bounds(cx: &mut EvalContext<'_>) -> Result<(), NodeError> {
    let input = cx.slices::<f32>(0)?;
    let mut outs: [Vec<f32>; 4] = Default::default();
    for bin in bins_of(cx, input.len(), 1)? {
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
    for (k, out) in outs.into_iter().enumerate() {
        cx.set(k, out);
    }
    Ok(())
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
