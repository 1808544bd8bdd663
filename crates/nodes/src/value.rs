//! Value maths on Float spreads: arithmetic (`Add`, `Subtract`, `Multiply`,
//! `Divide`, `Pow`), trigonometry in cycles (`Sin`, `Cos`) and ranges
//! (`Clamp`, `Map`), all in the "Value" category.
//!
//! More one-function nodes (`Abs`, `Min`, `Modulo`, `Lerp`, ...) are in
//! `value/functions.rs`.
//!
//! Every node here is pure and spreads slice by slice with the runtime's rule
//! (output count = the largest input count, 0 when any input is empty,
//! shorter inputs wrap). Where the maths has no finite answer (division by
//! zero, a negative base to a fractional power, a zero source range) the node
//! outputs a documented finite value instead of NaN or infinity.

use std::f64::consts::TAU;

use spreadlight_graph::spread::{slice_count, wrapped};
use spreadlight_graph::{Choices, NodeDef, Registry};

const CATEGORY: &str = "Value";

/// The mapping modes of `Map (Value)`, as vvvv names them.
pub static MAPPING: Choices<Mapping> = Choices::new(
    "Mapping",
    &["Float", "Clamp", "Wrap", "Mirror"],
    &[
        Mapping::Float,
        Mapping::Clamp,
        Mapping::Wrap,
        Mapping::Mirror,
    ],
);

pub mod functions;

pub fn register(r: &mut Registry) {
    functions::register(r);
    register_basics(r);
}

/// This file's nodes alone.
pub fn register_basics(r: &mut Registry) {
    r.add(
        NodeDef::new(
            "Add (Value)",
            CATEGORY,
            "Output = Input 1 + Input 2, slice by slice.",
        )
        .input("Input 1", 0.0f32)
        .input("Input 2", 0.0f32)
        .output::<f32>("Output")
        .per_slice2(|a: &f32, b: &f32| a + b),
    );
    r.add(
        NodeDef::new(
            "Subtract (Value)",
            CATEGORY,
            "Output = Input 1 - Input 2, slice by slice.",
        )
        .input("Input 1", 0.0f32)
        .input("Input 2", 0.0f32)
        .output::<f32>("Output")
        .per_slice2(|a: &f32, b: &f32| a - b),
    );
    r.add(
        NodeDef::new(
            "Multiply (Value)",
            CATEGORY,
            "Output = Input 1 * Input 2, slice by slice.",
        )
        .input("Input 1", 1.0f32)
        .input("Input 2", 1.0f32)
        .output::<f32>("Output")
        .per_slice2(|a: &f32, b: &f32| a * b),
    );
    r.add(
        NodeDef::new(
            "Divide (Value)",
            CATEGORY,
            "Output = Input 1 / Input 2, slice by slice. Division by zero (and any quotient \
             too large to represent) outputs 0, never NaN or infinity.",
        )
        .input("Input 1", 0.0f32)
        .input("Input 2", 1.0f32)
        .output::<f32>("Output")
        .per_slice2(divide),
    );
    r.add(
        NodeDef::new(
            "Sin (Value)",
            CATEGORY,
            "Sine of Input given in cycles, as in vvvv: Output = sin(2π · Input), so 0.25 gives 1 \
             and 1 is a full turn.",
        )
        .input("Input", 0.0f32)
        .output::<f32>("Output")
        .per_slice1(|x: &f32| sin_cycles(*x)),
    );
    r.add(
        NodeDef::new(
            "Cos (Value)",
            CATEGORY,
            "Cosine of Input given in cycles, as in vvvv: Output = cos(2π · Input), so 0.5 gives \
             -1 and 1 is a full turn.",
        )
        .input("Input", 0.0f32)
        .output::<f32>("Output")
        .per_slice1(|x: &f32| cos_cycles(*x)),
    );
    r.add(
        NodeDef::new(
            "Pow (Value)",
            CATEGORY,
            "Output = Base raised to Exponent. Where the real result is undefined or infinite \
             (a negative Base with a fractional Exponent, 0 to a negative Exponent, overflow) \
             the Output is 0. A negative Base with a whole Exponent works as usual: \
             (-2)^3 = -8.",
        )
        .input("Base", 1.0f32)
        .input("Exponent", 1.0f32)
        .output::<f32>("Output")
        .per_slice2(pow),
    );
    r.add(
        NodeDef::new(
            "Clamp (Value)",
            CATEGORY,
            "Limits Input to the range [Minimum, Maximum]. When Minimum is greater than \
             Maximum the two are swapped.",
        )
        .input("Input", 0.0f32)
        .input("Minimum", 0.0f32)
        .input("Maximum", 1.0f32)
        .output::<f32>("Output")
        .per_slice3(|x: &f32, lo: &f32, hi: &f32| clamp(*x, *lo, *hi)),
    );
    r.add(
        NodeDef::new(
            "Map (Value)",
            CATEGORY,
            "Maps Input from the source range [Source Minimum, Source Maximum] to the \
             destination range [Destination Minimum, Destination Maximum]. Mapping says what \
             happens outside the source range: Float extrapolates, Clamp holds at the ends, \
             Wrap repeats the range, Mirror runs it back and forth. A zero-width source range \
             outputs Destination Minimum.",
        )
        .with_pins(|p| {
            let input = p.input("Input", 0.0f32);
            let src_min = p.input("Source Minimum", 0.0f32);
            let src_max = p.input("Source Maximum", 1.0f32);
            let dst_min = p.input("Destination Minimum", 0.0f32);
            let dst_max = p.input("Destination Maximum", 1.0f32);
            let mapping = p.input_choice("Mapping", &MAPPING, Mapping::Float);
            let output = p.output::<f32>("Output");
            move |cx| {
                let input = cx.get(input)?;
                let src_min = cx.get(src_min)?;
                let src_max = cx.get(src_max)?;
                let dst_min = cx.get(dst_min)?;
                let dst_max = cx.get(dst_max)?;
                let modes = cx.choices(mapping)?;
                let n = slice_count([
                    input.len(),
                    src_min.len(),
                    src_max.len(),
                    dst_min.len(),
                    dst_max.len(),
                    modes.len(),
                ]);
                let out: Vec<f32> = (0..n)
                    .map(|i| {
                        map_value(
                            *wrapped(input, i),
                            *wrapped(src_min, i),
                            *wrapped(src_max, i),
                            *wrapped(dst_min, i),
                            *wrapped(dst_max, i),
                            *wrapped(&modes, i),
                        )
                    })
                    .collect();
                cx.put(output, out);
                Ok(())
            }
        }),
    );
}

/// A non-finite result becomes 0: the value nodes' answer where the maths has none.
fn finite_or_zero(x: f32) -> f32 {
    if x.is_finite() { x } else { 0.0 }
}

fn divide(a: &f32, b: &f32) -> f32 {
    finite_or_zero(a / b)
}

fn pow(base: &f32, exponent: &f32) -> f32 {
    finite_or_zero(base.powf(*exponent))
}

/// An angle in cycles to radians, reduced to one turn first so large inputs keep their precision.
fn cycles_to_radians(x: f32) -> f64 {
    f64::from(x).rem_euclid(1.0) * TAU
}

pub(crate) fn sin_cycles(x: f32) -> f32 {
    finite_or_zero(cycles_to_radians(x).sin() as f32)
}

pub(crate) fn cos_cycles(x: f32) -> f32 {
    finite_or_zero(cycles_to_radians(x).cos() as f32)
}

fn clamp(x: f32, min: f32, max: f32) -> f32 {
    let (lo, hi) = if min <= max { (min, max) } else { (max, min) };
    // Not f32::clamp: that panics when its bounds are out of order or NaN.
    x.max(lo).min(hi)
}

/// What `Map (Value)` does outside its source range (see [`MAPPING`] for the names).
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Mapping {
    Float,
    Clamp,
    Wrap,
    Mirror,
}

fn map_value(x: f32, src_min: f32, src_max: f32, dst_min: f32, dst_max: f32, mode: Mapping) -> f32 {
    let range = src_max - src_min;
    let t = if range == 0.0 {
        0.0
    } else {
        finite_or_zero((x - src_min) / range)
    };
    let t = match mode {
        Mapping::Float => t,
        Mapping::Clamp => t.clamp(0.0, 1.0),
        Mapping::Wrap => t - t.floor(),
        Mapping::Mirror => {
            let m = t.rem_euclid(2.0);
            if m > 1.0 { 2.0 - m } else { m }
        }
    };
    finite_or_zero(dst_min + t * (dst_max - dst_min))
}

#[cfg(test)]
mod tests {
    use spreadlight_graph::Spread;

    use crate::testing::{assert_close, eval, eval_out, floats, option};

    fn binary(name: &str, a: &[f32], b: &[f32]) -> Vec<f32> {
        eval_out(
            name,
            &[("Input 1", floats(a)), ("Input 2", floats(b))],
            "Output",
        )
    }

    #[test]
    fn add_spreads_and_wraps() {
        assert_eq!(
            binary("Add (Value)", &[1.0, 2.0, 3.0], &[10.0]),
            vec![11.0, 12.0, 13.0]
        );
        assert_eq!(
            binary("Add (Value)", &[1.0, 2.0, 3.0], &[10.0, 20.0]),
            vec![11.0, 22.0, 13.0]
        );
        assert!(binary("Add (Value)", &[1.0, 2.0], &[]).is_empty());
    }

    #[test]
    fn subtract_multiply() {
        assert_eq!(
            binary("Subtract (Value)", &[5.0, 1.0], &[2.0]),
            vec![3.0, -1.0]
        );
        assert_eq!(
            binary("Multiply (Value)", &[1.5, -2.0], &[2.0, 3.0]),
            vec![3.0, -6.0]
        );
    }

    #[test]
    fn int_inputs_are_converted_like_links() {
        let out: Vec<f32> = eval_out(
            "Add (Value)",
            &[
                ("Input 1", Spread::Int(vec![1, 2])),
                ("Input 2", floats(&[0.5])),
            ],
            "Output",
        );
        assert_eq!(out, vec![1.5, 2.5]);
    }

    #[test]
    fn divide_by_zero_is_zero_not_nan() {
        assert_eq!(
            binary(
                "Divide (Value)",
                &[1.0, 6.0, 0.0, -3.0],
                &[0.0, 3.0, 0.0, -0.0]
            ),
            vec![0.0, 2.0, 0.0, 0.0]
        );
        // A quotient that overflows is not finite either.
        assert_eq!(binary("Divide (Value)", &[f32::MAX], &[0.5]), vec![0.0]);
    }

    #[test]
    fn sin_and_cos_take_cycles() {
        let x = floats(&[0.0, 0.25, 0.5, 0.75, 1.0, -0.25, 1000.25]);
        let sin: Vec<f32> = eval_out("Sin (Value)", &[("Input", x.clone())], "Output");
        assert_close(&sin, &[0.0, 1.0, 0.0, -1.0, 0.0, -1.0, 1.0], 1e-6);
        let cos: Vec<f32> = eval_out("Cos (Value)", &[("Input", x)], "Output");
        assert_close(&cos, &[1.0, 0.0, -1.0, 0.0, 1.0, 0.0, 0.0], 1e-6);
    }

    #[test]
    fn pow_guards_undefined_results_with_zero() {
        let out: Vec<f32> = eval_out(
            "Pow (Value)",
            &[
                ("Base", floats(&[2.0, 9.0, -2.0, -8.0, 0.0, 0.0, 10.0])),
                (
                    "Exponent",
                    floats(&[3.0, 0.5, 3.0, 1.0 / 3.0, -1.0, 0.0, 100.0]),
                ),
            ],
            "Output",
        );
        assert_close(&out, &[8.0, 3.0, -8.0, 0.0, 0.0, 1.0, 0.0], 1e-6);
    }

    #[test]
    fn clamp_swaps_reversed_bounds() {
        let out: Vec<f32> = eval_out(
            "Clamp (Value)",
            &[
                ("Input", floats(&[-1.0, 0.5, 2.0, -1.0, 0.5, 2.0])),
                ("Minimum", floats(&[0.0, 0.0, 0.0, 1.0, 1.0, 1.0])),
                ("Maximum", floats(&[1.0, 1.0, 1.0, 0.0, 0.0, 0.0])),
            ],
            "Output",
        );
        assert_eq!(out, vec![0.0, 0.5, 1.0, 0.0, 0.5, 1.0]);
    }

    fn map(input: &[f32], mode: &str) -> Vec<f32> {
        eval_out(
            "Map (Value)",
            &[
                ("Input", floats(input)),
                ("Source Minimum", floats(&[0.0])),
                ("Source Maximum", floats(&[10.0])),
                ("Destination Minimum", floats(&[100.0])),
                ("Destination Maximum", floats(&[200.0])),
                ("Mapping", option(mode)),
            ],
            "Output",
        )
    }

    #[test]
    fn map_modes_follow_vvvv() {
        let input = [5.0, 15.0, -5.0, 25.0];
        assert_close(&map(&input, "Float"), &[150.0, 250.0, 50.0, 350.0], 1e-4);
        assert_close(&map(&input, "Clamp"), &[150.0, 200.0, 100.0, 200.0], 1e-4);
        assert_close(&map(&input, "Wrap"), &[150.0, 150.0, 150.0, 150.0], 1e-4);
        assert_close(
            &map(&[5.0, 12.0, -2.0, 22.0], "Mirror"),
            &[150.0, 180.0, 120.0, 120.0],
            1e-4,
        );
    }

    #[test]
    fn map_with_zero_source_range_outputs_destination_minimum() {
        for mode in ["Float", "Clamp", "Wrap", "Mirror"] {
            let out: Vec<f32> = eval_out(
                "Map (Value)",
                &[
                    ("Input", floats(&[0.0, 3.0, -7.0])),
                    ("Source Minimum", floats(&[2.0])),
                    ("Source Maximum", floats(&[2.0])),
                    ("Destination Minimum", floats(&[-1.0])),
                    ("Mapping", option(mode)),
                ],
                "Output",
            );
            assert_eq!(out, vec![-1.0; 3], "{mode}");
        }
    }

    #[test]
    fn map_spreads_its_mapping_pin() {
        let out: Vec<f32> = eval_out(
            "Map (Value)",
            &[
                ("Input", floats(&[2.0])),
                (
                    "Mapping",
                    Spread::Enum(vec!["Float".into(), "Clamp".into()]),
                ),
            ],
            "Output",
        );
        assert_eq!(out, vec![2.0, 1.0]);
    }

    #[test]
    fn map_rejects_an_unknown_mapping() {
        let e = eval("Map (Value)", &[("Mapping", option("Bounce"))]);
        assert!(
            matches!(&e, Err(spreadlight_graph::NodeError::Input { pin, .. }) if pin == "Mapping"),
            "{e:?}"
        );
    }
}
