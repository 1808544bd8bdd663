//! Vector join and split: `Vector (2d Join)` .. `Vector (4d Join)` build
//! Vec2/Vec3/Vec4 spreads from Float components, `Vector (2d Split)` ..
//! `Vector (4d Split)` take them apart again; all in the "Vector" category.
//!
//! Vector arithmetic (`Add (Vector 3d)`, `Cross (Vector 3d)`, `Normalize`, ...) is in
//! `vector/maths.rs`.
//!
//! Joins spread like every per-slice node (the longest component decides the
//! count, shorter ones wrap); splits output one slice per input vector.

use glam::{Vec2, Vec3, Vec4};
use spreadlight_graph::spread::map1;
use spreadlight_graph::{EvalContext, NodeDef, NodeError, Registry};

const CATEGORY: &str = "Vector";

pub mod maths;

pub fn register(r: &mut Registry) {
    maths::register(r);
    register_join_split(r);
}

/// This file's nodes alone.
pub fn register_join_split(r: &mut Registry) {
    r.add(
        NodeDef::new(
            "Vector (2d Join)",
            CATEGORY,
            "Builds 2d vectors from X and Y, slice by slice.",
        )
        .input("X", 0.0f32)
        .input("Y", 0.0f32)
        .output::<Vec2>("Output")
        .per_slice2(|x: &f32, y: &f32| Vec2::new(*x, *y)),
    );
    r.add(
        NodeDef::new(
            "Vector (3d Join)",
            CATEGORY,
            "Builds 3d vectors from X, Y and Z, slice by slice.",
        )
        .input("X", 0.0f32)
        .input("Y", 0.0f32)
        .input("Z", 0.0f32)
        .output::<Vec3>("Output")
        .per_slice3(|x: &f32, y: &f32, z: &f32| Vec3::new(*x, *y, *z)),
    );
    r.add(
        NodeDef::new(
            "Vector (4d Join)",
            CATEGORY,
            "Builds 4d vectors from X, Y, Z and W, slice by slice.",
        )
        .input("X", 0.0f32)
        .input("Y", 0.0f32)
        .input("Z", 0.0f32)
        .input("W", 0.0f32)
        .output::<Vec4>("Output")
        .per_slice4(|x: &f32, y: &f32, z: &f32, w: &f32| Vec4::new(*x, *y, *z, *w)),
    );
    r.add(
        NodeDef::new(
            "Vector (2d Split)",
            CATEGORY,
            "Splits 2d vectors into their X and Y components.",
        )
        .input("Input", Vec2::ZERO)
        .output::<f32>("X")
        .output::<f32>("Y")
        .evaluate(split2),
    );
    r.add(
        NodeDef::new(
            "Vector (3d Split)",
            CATEGORY,
            "Splits 3d vectors into their X, Y and Z components.",
        )
        .input("Input", Vec3::ZERO)
        .output::<f32>("X")
        .output::<f32>("Y")
        .output::<f32>("Z")
        .evaluate(split3),
    );
    r.add(
        NodeDef::new(
            "Vector (4d Split)",
            CATEGORY,
            "Splits 4d vectors into their X, Y, Z and W components.",
        )
        .input("Input", Vec4::ZERO)
        .output::<f32>("X")
        .output::<f32>("Y")
        .output::<f32>("Z")
        .output::<f32>("W")
        .evaluate(split4),
    );
}

fn split2(cx: &mut EvalContext<'_>) -> Result<(), NodeError> {
    let v = cx.slices::<Vec2>(0)?;
    let (x, y) = (map1(v, |v| v.x), map1(v, |v| v.y));
    cx.set(0, x);
    cx.set(1, y);
    Ok(())
}

fn split3(cx: &mut EvalContext<'_>) -> Result<(), NodeError> {
    let v = cx.slices::<Vec3>(0)?;
    let (x, y, z) = (map1(v, |v| v.x), map1(v, |v| v.y), map1(v, |v| v.z));
    cx.set(0, x);
    cx.set(1, y);
    cx.set(2, z);
    Ok(())
}

fn split4(cx: &mut EvalContext<'_>) -> Result<(), NodeError> {
    let v = cx.slices::<Vec4>(0)?;
    let (x, y, z, w) = (
        map1(v, |v| v.x),
        map1(v, |v| v.y),
        map1(v, |v| v.z),
        map1(v, |v| v.w),
    );
    cx.set(0, x);
    cx.set(1, y);
    cx.set(2, z);
    cx.set(3, w);
    Ok(())
}

#[cfg(test)]
mod tests {
    use glam::{Vec2, Vec3, Vec4};
    use spreadlight_graph::Spread;

    use crate::testing::{eval, eval_out, floats};

    #[test]
    fn joins_spread_and_wrap() {
        let v: Vec<Vec2> = eval_out(
            "Vector (2d Join)",
            &[("X", floats(&[1.0, 2.0, 3.0])), ("Y", floats(&[10.0]))],
            "Output",
        );
        assert_eq!(
            v,
            vec![
                Vec2::new(1.0, 10.0),
                Vec2::new(2.0, 10.0),
                Vec2::new(3.0, 10.0)
            ]
        );
        let v: Vec<Vec3> = eval_out(
            "Vector (3d Join)",
            &[
                ("X", floats(&[1.0, 2.0])),
                ("Y", floats(&[3.0])),
                ("Z", floats(&[4.0, 5.0])),
            ],
            "Output",
        );
        assert_eq!(v, vec![Vec3::new(1.0, 3.0, 4.0), Vec3::new(2.0, 3.0, 5.0)]);
        let v: Vec<Vec4> = eval_out(
            "Vector (4d Join)",
            &[("X", floats(&[1.0])), ("W", floats(&[7.0, 8.0]))],
            "Output",
        );
        assert_eq!(
            v,
            vec![Vec4::new(1.0, 0.0, 0.0, 7.0), Vec4::new(1.0, 0.0, 0.0, 8.0)]
        );
        let v: Vec<Vec2> = eval_out("Vector (2d Join)", &[("X", floats(&[]))], "Output");
        assert!(v.is_empty());
    }

    #[test]
    fn splits_give_components() {
        let out = eval(
            "Vector (2d Split)",
            &[(
                "Input",
                Spread::Vec2(vec![Vec2::new(1.0, 2.0), Vec2::new(3.0, 4.0)]),
            )],
        )
        .expect("2d split");
        assert_eq!(out, vec![floats(&[1.0, 3.0]), floats(&[2.0, 4.0])]);
        let out = eval(
            "Vector (3d Split)",
            &[("Input", Spread::Vec3(vec![Vec3::new(1.0, 2.0, 3.0)]))],
        )
        .expect("3d split");
        assert_eq!(out, vec![floats(&[1.0]), floats(&[2.0]), floats(&[3.0])]);
        let out = eval(
            "Vector (4d Split)",
            &[("Input", Spread::Vec4(vec![Vec4::new(1.0, 2.0, 3.0, 4.0)]))],
        )
        .expect("4d split");
        assert_eq!(
            out,
            vec![
                floats(&[1.0]),
                floats(&[2.0]),
                floats(&[3.0]),
                floats(&[4.0])
            ]
        );
        let out = eval("Vector (3d Split)", &[("Input", Spread::Vec3(vec![]))]).expect("empty");
        assert!(out.iter().all(Spread::is_empty));
    }
}
