//! Vector maths for 2d, 3d and 4d vectors: `Add`, `Subtract`, `Multiply`
//! (component-wise), `Scale` (by a value), `Dot`, `Length`, `Distance`,
//! `Normalize`, `Lerp`, and `Cross (Vector 3d)`. All pure and spreading
//! slice by slice; a zero vector normalizes to zero, never NaN.

use std::ops::{Add, Mul, Sub};

use glam::{Vec2, Vec3, Vec4};
use spreadlight_graph::{NodeDef, Registry, SliceValue};

const CATEGORY: &str = "Vector";

/// What the nodes here need of a vector type.
trait VectorMaths:
    SliceValue
    + Copy
    + Add<Output = Self>
    + Sub<Output = Self>
    + Mul<Output = Self>
    + Mul<f32, Output = Self>
{
    const ZERO: Self;
    const ONE: Self;
    fn dot(self, other: Self) -> f32;
    fn length(self) -> f32;
    fn normalize_or_zero(self) -> Self;
}

macro_rules! vector_maths {
    ($t:ty) => {
        impl VectorMaths for $t {
            const ZERO: Self = <$t>::ZERO;
            const ONE: Self = <$t>::ONE;
            fn dot(self, other: Self) -> f32 {
                <$t>::dot(self, other)
            }
            fn length(self) -> f32 {
                <$t>::length(self)
            }
            fn normalize_or_zero(self) -> Self {
                <$t>::normalize_or_zero(self)
            }
        }
    };
}
vector_maths!(Vec2);
vector_maths!(Vec3);
vector_maths!(Vec4);

/// Register `make` for 2d, 3d and 4d vectors, named `Base (Vector 2d)` and so on.
macro_rules! per_size {
    ($r:expr, $make:ident, $base:literal) => {
        $r.add($make::<Vec2>(concat!($base, " (Vector 2d)")));
        $r.add($make::<Vec3>(concat!($base, " (Vector 3d)")));
        $r.add($make::<Vec4>(concat!($base, " (Vector 4d)")));
    };
}

pub fn register(r: &mut Registry) {
    per_size!(r, add, "Add");
    per_size!(r, subtract, "Subtract");
    per_size!(r, multiply, "Multiply");
    per_size!(r, scale, "Scale");
    per_size!(r, dot, "Dot");
    per_size!(r, length, "Length");
    per_size!(r, distance, "Distance");
    per_size!(r, normalize, "Normalize");
    per_size!(r, lerp, "Lerp");
    r.add(
        NodeDef::new(
            "Cross (Vector 3d)",
            CATEGORY,
            "The cross product Input 1 x Input 2, slice by slice: perpendicular to both, as long \
             as the area they span (right-handed).",
        )
        .input("Input 1", Vec3::X)
        .input("Input 2", Vec3::Y)
        .output::<Vec3>("Output")
        .per_slice2(|a: &Vec3, b: &Vec3| a.cross(*b)),
    );
}

fn binary<T: VectorMaths>(
    name: &'static str,
    help: &'static str,
    a: T,
    b: T,
    f: fn(T, T) -> T,
) -> NodeDef {
    NodeDef::new(name, CATEGORY, help)
        .input("Input 1", a)
        .input("Input 2", b)
        .output::<T>("Output")
        .per_slice2(move |x: &T, y: &T| f(*x, *y))
}

fn add<T: VectorMaths>(name: &'static str) -> NodeDef {
    binary(
        name,
        "Input 1 + Input 2, slice by slice.",
        T::ZERO,
        T::ZERO,
        |a, b| a + b,
    )
}

fn subtract<T: VectorMaths>(name: &'static str) -> NodeDef {
    binary(
        name,
        "Input 1 - Input 2, slice by slice.",
        T::ZERO,
        T::ZERO,
        |a, b| a - b,
    )
}

fn multiply<T: VectorMaths>(name: &'static str) -> NodeDef {
    binary(
        name,
        "Input 1 x Input 2 component by component, slice by slice.",
        T::ONE,
        T::ONE,
        |a, b| a * b,
    )
}

fn scale<T: VectorMaths>(name: &'static str) -> NodeDef {
    NodeDef::new(
        name,
        CATEGORY,
        "Input times the value Factor, slice by slice.",
    )
    .input("Input", T::ONE)
    .input("Factor", 1.0f32)
    .output::<T>("Output")
    .per_slice2(|v: &T, s: &f32| *v * *s)
}

fn dot<T: VectorMaths>(name: &'static str) -> NodeDef {
    NodeDef::new(
        name,
        CATEGORY,
        "The dot product of Input 1 and Input 2, slice by slice.",
    )
    .input("Input 1", T::ONE)
    .input("Input 2", T::ONE)
    .output::<f32>("Output")
    .per_slice2(|a: &T, b: &T| a.dot(*b))
}

fn length<T: VectorMaths>(name: &'static str) -> NodeDef {
    NodeDef::new(name, CATEGORY, "The length of each vector.")
        .input("Input", T::ONE)
        .output::<f32>("Output")
        .per_slice1(|v: &T| v.length())
}

fn distance<T: VectorMaths>(name: &'static str) -> NodeDef {
    NodeDef::new(
        name,
        CATEGORY,
        "The distance between Input 1 and Input 2, slice by slice.",
    )
    .input("Input 1", T::ZERO)
    .input("Input 2", T::ONE)
    .output::<f32>("Output")
    .per_slice2(|a: &T, b: &T| (*a - *b).length())
}

fn normalize<T: VectorMaths>(name: &'static str) -> NodeDef {
    NodeDef::new(
        name,
        CATEGORY,
        "Each vector scaled to length 1; a zero (or non-finite) vector gives zero.",
    )
    .input("Input", T::ONE)
    .output::<T>("Output")
    .per_slice1(|v: &T| v.normalize_or_zero())
}

fn lerp<T: VectorMaths>(name: &'static str) -> NodeDef {
    NodeDef::new(
        name,
        CATEGORY,
        "Mixes Input 1 and Input 2: Amount 0 gives Input 1, 1 gives Input 2, in between a linear \
         mix, outside it extrapolates. Slice by slice.",
    )
    .input("Input 1", T::ZERO)
    .input("Input 2", T::ONE)
    .input("Amount", 0.5f32)
    .output::<T>("Output")
    .per_slice3(|a: &T, b: &T, t: &f32| *a + (*b - *a) * *t)
}

#[cfg(test)]
mod tests {
    use glam::{Vec2, Vec3, Vec4};
    use spreadlight_graph::Spread;

    use crate::testing::{eval_out, floats};

    fn v3(v: &[Vec3]) -> Spread {
        Spread::Vec3(v.to_vec())
    }

    #[test]
    fn arithmetic_spreads_and_wraps() {
        let out: Vec<Vec3> = eval_out(
            "Add (Vector 3d)",
            &[
                ("Input 1", v3(&[Vec3::X, Vec3::Y])),
                ("Input 2", v3(&[Vec3::Z])),
            ],
            "Output",
        );
        assert_eq!(out, [Vec3::new(1.0, 0.0, 1.0), Vec3::new(0.0, 1.0, 1.0)]);
        let out: Vec<Vec2> = eval_out(
            "Scale (Vector 2d)",
            &[
                ("Input", Spread::Vec2(vec![Vec2::new(1.0, 2.0)])),
                ("Factor", floats(&[2.0, -1.0])),
            ],
            "Output",
        );
        assert_eq!(out, [Vec2::new(2.0, 4.0), Vec2::new(-1.0, -2.0)]);
        let out: Vec<Vec4> = eval_out(
            "Multiply (Vector 4d)",
            &[
                ("Input 1", Spread::Vec4(vec![Vec4::new(1.0, 2.0, 3.0, 4.0)])),
                ("Input 2", Spread::Vec4(vec![Vec4::splat(2.0)])),
            ],
            "Output",
        );
        assert_eq!(out, [Vec4::new(2.0, 4.0, 6.0, 8.0)]);
    }

    #[test]
    fn products_lengths_and_normalizing() {
        let out: Vec<Vec3> = eval_out("Cross (Vector 3d)", &[], "Output");
        assert_eq!(out, [Vec3::Z]);
        let d: Vec<f32> = eval_out(
            "Dot (Vector 3d)",
            &[
                ("Input 1", v3(&[Vec3::new(1.0, 2.0, 3.0)])),
                ("Input 2", v3(&[Vec3::new(4.0, 5.0, 6.0)])),
            ],
            "Output",
        );
        assert_eq!(d, [32.0]);
        let l: Vec<f32> = eval_out(
            "Length (Vector 2d)",
            &[("Input", Spread::Vec2(vec![Vec2::new(3.0, 4.0)]))],
            "Output",
        );
        assert_eq!(l, [5.0]);
        let n: Vec<Vec3> = eval_out(
            "Normalize (Vector 3d)",
            &[("Input", v3(&[Vec3::new(0.0, 0.0, 2.0), Vec3::ZERO]))],
            "Output",
        );
        assert_eq!(n, [Vec3::Z, Vec3::ZERO]);
        let m: Vec<Vec3> = eval_out("Lerp (Vector 3d)", &[("Amount", floats(&[0.25]))], "Output");
        assert_eq!(m, [Vec3::splat(0.25)]);
        let dist: Vec<f32> = eval_out(
            "Distance (Vector 3d)",
            &[("Input 2", v3(&[Vec3::new(0.0, 3.0, 4.0)]))],
            "Output",
        );
        assert_eq!(dist, [5.0]);
    }
}
