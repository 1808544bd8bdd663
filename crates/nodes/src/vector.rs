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
use spreadlight_graph::{NodeDef, Registry};

use crate::typed::Value;

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
    r.add(split(
        "Vector (2d Split)",
        "Splits 2d vectors into their X and Y components.",
        Vec2::ZERO,
        ["X", "Y"],
        |v| v.to_array(),
    ));
    r.add(split(
        "Vector (3d Split)",
        "Splits 3d vectors into their X, Y and Z components.",
        Vec3::ZERO,
        ["X", "Y", "Z"],
        |v| v.to_array(),
    ));
    r.add(split(
        "Vector (4d Split)",
        "Splits 4d vectors into their X, Y, Z and W components.",
        Vec4::ZERO,
        ["X", "Y", "Z", "W"],
        |v| v.to_array(),
    ));
}

/// A split node: Input, then one Float output per component, named `components`.
fn split<V: Value + Copy, const N: usize>(
    name: &'static str,
    help: &'static str,
    default: V,
    components: [&'static str; N],
    parts: fn(&V) -> [f32; N],
) -> NodeDef {
    NodeDef::new(name, CATEGORY, help).with_pins(|p| {
        let input = p.input("Input", default);
        let outputs = components.map(|name| p.output::<f32>(name));
        move |cx| {
            let v = cx.get(input)?;
            let columns: [Vec<f32>; N] = std::array::from_fn(|k| map1(v, |v| parts(v)[k]));
            for (pin, column) in outputs.into_iter().zip(columns) {
                cx.put(pin, column);
            }
            Ok(())
        }
    })
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
