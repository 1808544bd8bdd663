//! More value maths, one function each: `Abs`, `Sign`, `Floor`, `Ceil`,
//! `Round`, `Frac`, `Sqrt`, `Min`, `Max`, `Modulo`, `Lerp`, `Atan2`, `Tan`.
//! Where the maths has no finite answer the output is 0, as elsewhere in
//! the Value family.

use spreadlight_graph::{NodeDef, Registry};

const CATEGORY: &str = "Value";

fn finite(x: f32) -> f32 {
    if x.is_finite() { x } else { 0.0 }
}

fn unary(name: &'static str, help: &'static str, f: fn(f32) -> f32) -> NodeDef {
    NodeDef::new(name, CATEGORY, help)
        .input("Input", 0.0f32)
        .output::<f32>("Output")
        .per_slice1(move |x: &f32| finite(f(*x)))
}

fn binary(name: &'static str, help: &'static str, b: f32, f: fn(f32, f32) -> f32) -> NodeDef {
    NodeDef::new(name, CATEGORY, help)
        .input("Input 1", 0.0f32)
        .input("Input 2", b)
        .output::<f32>("Output")
        .per_slice2(move |x: &f32, y: &f32| finite(f(*x, *y)))
}

pub fn register(r: &mut Registry) {
    r.add(unary(
        "Abs (Value)",
        "The absolute value of Input.",
        f32::abs,
    ));
    r.add(unary(
        "Sign (Value)",
        "-1 for negative Input, 1 for positive, 0 for 0.",
        |x| if x == 0.0 { 0.0 } else { x.signum() },
    ));
    r.add(unary(
        "Floor (Value)",
        "The largest whole number not above Input.",
        f32::floor,
    ));
    r.add(unary(
        "Ceil (Value)",
        "The smallest whole number not below Input.",
        f32::ceil,
    ));
    r.add(unary(
        "Round (Value)",
        "Input rounded to the nearest whole number (halves away from zero).",
        f32::round,
    ));
    r.add(unary(
        "Frac (Value)",
        "The fractional part of Input, in [0, 1): Input - Floor(Input) (so -0.25 gives 0.75).",
        |x| x - x.floor(),
    ));
    r.add(unary(
        "Sqrt (Value)",
        "The square root of Input; a negative Input gives 0.",
        |x| x.max(0.0).sqrt(),
    ));
    r.add(unary(
        "Tan (Value)",
        "Tangent of Input given in cycles, as Sin and Cos (0.125 gives 1); at the poles 0.",
        |x| (f64::from(x).rem_euclid(1.0) * std::f64::consts::TAU).tan() as f32,
    ));
    r.add(binary(
        "Min (Value)",
        "The smaller of Input 1 and Input 2.",
        0.0,
        f32::min,
    ));
    r.add(binary(
        "Max (Value)",
        "The larger of Input 1 and Input 2.",
        0.0,
        f32::max,
    ));
    r.add(binary(
        "Modulo (Value)",
        "Input 1 modulo Input 2, with the sign of Input 2 as in vvvv (-1 mod 3 is 2); modulo 0 \
         gives 0.",
        1.0,
        f32::rem_euclid,
    ));
    r.add(binary(
        "Atan2 (Value)",
        "The angle of the point (X = Input 2, Y = Input 1) in cycles, in (-0.5, 0.5]: Atan2(1, \
         0) is 0.25.",
        1.0,
        |y, x| y.atan2(x) / std::f32::consts::TAU,
    ));
    r.add(
        NodeDef::new(
            "Lerp (Value)",
            CATEGORY,
            "Mixes Input 1 and Input 2: Amount 0 gives Input 1, 1 gives Input 2, in between a \
             linear mix, outside it extrapolates.",
        )
        .input("Input 1", 0.0f32)
        .input("Input 2", 1.0f32)
        .input("Amount", 0.5f32)
        .output::<f32>("Output")
        .per_slice3(|a: &f32, b: &f32, t: &f32| finite(a + (b - a) * t)),
    );
}

#[cfg(test)]
mod tests {
    use crate::testing::{assert_close, eval_out, floats};

    fn unary(name: &str, x: &[f32]) -> Vec<f32> {
        eval_out(name, &[("Input", floats(x))], "Output")
    }

    fn binary(name: &str, a: &[f32], b: &[f32]) -> Vec<f32> {
        eval_out(
            name,
            &[("Input 1", floats(a)), ("Input 2", floats(b))],
            "Output",
        )
    }

    #[test]
    fn rounding_and_signs() {
        assert_eq!(unary("Abs (Value)", &[-2.0, 3.0]), [2.0, 3.0]);
        assert_eq!(unary("Sign (Value)", &[-2.0, 0.0, 5.0]), [-1.0, 0.0, 1.0]);
        assert_eq!(unary("Floor (Value)", &[-1.5, 1.5]), [-2.0, 1.0]);
        assert_eq!(unary("Ceil (Value)", &[-1.5, 1.5]), [-1.0, 2.0]);
        assert_eq!(unary("Round (Value)", &[-1.5, 1.4]), [-2.0, 1.0]);
        assert_eq!(unary("Frac (Value)", &[-0.25, 1.75]), [0.75, 0.75]);
        assert_eq!(unary("Sqrt (Value)", &[9.0, -1.0]), [3.0, 0.0]);
        assert_close(&unary("Tan (Value)", &[0.125, 0.0]), &[1.0, 0.0], 1e-6);
    }

    #[test]
    fn two_input_functions() {
        assert_eq!(binary("Min (Value)", &[1.0, 5.0], &[3.0]), [1.0, 3.0]);
        assert_eq!(binary("Max (Value)", &[1.0, 5.0], &[3.0]), [3.0, 5.0]);
        assert_eq!(
            binary("Modulo (Value)", &[-1.0, 7.0, 1.0], &[3.0, 3.0, 0.0]),
            [2.0, 1.0, 0.0]
        );
        assert_close(
            &binary("Atan2 (Value)", &[1.0, 0.0], &[0.0, -1.0]),
            &[0.25, 0.5],
            1e-6,
        );
        let out: Vec<f32> = eval_out(
            "Lerp (Value)",
            &[("Amount", floats(&[0.25, 2.0]))],
            "Output",
        );
        assert_eq!(out, [0.25, 2.0]);
    }
}
