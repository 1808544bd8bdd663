//! Transforms, in the "Transform" category: `Translate`, `Rotate`, `Scale`,
//! the all-in-one `Transform (Transform 3d)`, `Multiply (Transform)`,
//! `LookAt (Transform)` and `Perspective (Transform)`, all on Mat4 spreads.
//!
//! Conventions: glam's column vectors (a point `p` transforms as `M * p`) in
//! a right-handed space, angles in cycles as in vvvv (1 = a full turn).
//! Like vvvv, a node applies its own transform *after* the one arriving at
//! Transform In: `Transform Out = Own * Transform In`. So chaining
//! `Scale -> Rotate -> Translate` scales first, then rotates, then moves.

use std::f32::consts::TAU;

use glam::{Mat4, Vec3};
use spreadlight_graph::spread::{slice_count, wrapped};
use spreadlight_graph::{NodeDef, Registry};

const CATEGORY: &str = "Transform";

pub fn register(r: &mut Registry) {
    r.add(
        NodeDef::new(
            "Translate (Transform)",
            CATEGORY,
            "Moves by (X, Y, Z), applied after Transform In: Transform Out = T * Transform In.",
        )
        .with_pins(|p| xyz_transform(p, 0.0, |x, y, z| Mat4::from_translation(Vec3::new(x, y, z)))),
    );
    r.add(
        NodeDef::new(
            "Rotate (Transform)",
            CATEGORY,
            "Rotates about the X, Y and Z axes by angles in cycles (0.25 = 90 degrees, \
             counter-clockwise looking down the axis), applied after Transform In. The three \
             turns are applied as vvvv's yaw-pitch-roll: first Z (roll), then X (pitch), then \
             Y (yaw), i.e. R = Ry * Rx * Rz.",
        )
        .with_pins(|p| xyz_transform(p, 0.0, rotation)),
    );
    r.add(
        NodeDef::new(
            "Scale (Transform)",
            CATEGORY,
            "Scales by (X, Y, Z) about the origin, applied after Transform In.",
        )
        .with_pins(|p| xyz_transform(p, 1.0, |x, y, z| Mat4::from_scale(Vec3::new(x, y, z)))),
    );
    r.add(
        NodeDef::new(
            "Transform (Transform 3d)",
            CATEGORY,
            "Scale, rotate and translate in one node, applied after Transform In in that \
             order: Transform Out = T * R * S * Transform In. Rotations are in cycles and \
             turn as in Rotate (Transform): Z, then X, then Y.",
        )
        .with_pins(|p| {
            let transform_in = p.input("Transform In", Mat4::IDENTITY);
            let params = [
                ("Translate X", 0.0f32),
                ("Translate Y", 0.0),
                ("Translate Z", 0.0),
                ("Scale X", 1.0),
                ("Scale Y", 1.0),
                ("Scale Z", 1.0),
                ("Rotate X", 0.0),
                ("Rotate Y", 0.0),
                ("Rotate Z", 0.0),
            ]
            .map(|(name, default)| p.input(name, default));
            let transform_out = p.output::<Mat4>("Transform Out");
            move |cx| {
                let input = cx.get(transform_in)?;
                let mut slices: [&[f32]; 9] = [&[]; 9];
                for (slot, pin) in slices.iter_mut().zip(params) {
                    *slot = cx.get(pin)?;
                }
                let n = slice_count(
                    [input.len()]
                        .into_iter()
                        .chain(slices.iter().map(|p| p.len())),
                );
                let out: Vec<Mat4> = (0..n)
                    .map(|i| {
                        let [tx, ty, tz, sx, sy, sz, rx, ry, rz] = slices.map(|p| *wrapped(p, i));
                        Mat4::from_translation(Vec3::new(tx, ty, tz))
                            * rotation(rx, ry, rz)
                            * Mat4::from_scale(Vec3::new(sx, sy, sz))
                            * *wrapped(input, i)
                    })
                    .collect();
                cx.put(transform_out, out);
                Ok(())
            }
        }),
    );
    r.add(
        NodeDef::new(
            "Multiply (Transform)",
            CATEGORY,
            "Chains two transforms: Transform In 1 is applied first, then Transform In 2 \
             (vvvv's order). In column-vector terms Transform Out = In 2 * In 1.",
        )
        .input("Transform In 1", Mat4::IDENTITY)
        .input("Transform In 2", Mat4::IDENTITY)
        .output::<Mat4>("Transform Out")
        .per_slice2(|first: &Mat4, second: &Mat4| *second * *first),
    );
    r.add(
        NodeDef::new(
            "LookAt (Transform)",
            CATEGORY,
            "A right-handed view matrix for a camera at Position looking at Target, with Up \
             as the rough up direction (view space: X right, Y up, looking down -Z). If Up is \
             zero or parallel to the view direction, world +Y is used instead, or +Z when \
             looking straight up or down. If Position equals Target there is no direction: \
             the camera looks down -Z from Position.",
        )
        .input("Position", Vec3::new(0.0, 0.0, 1.0))
        .input("Target", Vec3::ZERO)
        .input("Up", Vec3::Y)
        .output::<Mat4>("Transform Out")
        .per_slice3(|p: &Vec3, t: &Vec3, up: &Vec3| look_at(*p, *t, *up)),
    );
    r.add(
        NodeDef::new(
            "Perspective (Transform)",
            CATEGORY,
            "A perspective projection (depth 0 at Near, 1 at Far, as wgpu expects) with a vertical \
             field of view in cycles (0.25 = 90 degrees) and an aspect ratio: a spot light's cone \
             or a camera's lens. FOV is kept within 0.0001..0.4999 cycles, Aspect Ratio within \
             1e-4..1e4, Near within 1e-6..1e6 and Far beyond Near (up to 1e9), so the matrix is \
             always invertible.",
        )
        .input("FOV", 0.125f32)
        .input("Aspect Ratio", 1.0f32)
        .input("Near", 0.05f32)
        .input("Far", 20.0f32)
        .output::<Mat4>("Transform Out")
        .per_slice4(|fov: &f32, aspect: &f32, near: &f32, far: &f32| {
            perspective(*fov, *aspect, *near, *far)
        }),
    );
}

/// `Perspective (Transform)` with its inputs kept where the matrix exists.
fn perspective(fov: f32, aspect: f32, near: f32, far: f32) -> Mat4 {
    let finite = |v: f32, fallback: f32| if v.is_finite() { v } else { fallback };
    let fov = finite(fov, 0.125).clamp(1e-4, 0.4999) * TAU;
    // Bounds where every entry of the matrix and its inverse stays finite in f32.
    let aspect = finite(aspect, 1.0).abs().clamp(1e-4, 1e4);
    let near = finite(near, 0.05).clamp(1e-6, 1e6);
    let far = finite(far, 20.0).clamp(near * 1.001, 1e9);
    glam::camera::rh::proj::directx::perspective(fov, aspect, near, far)
}

/// An angle in cycles to radians, reduced to one turn first so large inputs keep their precision.
fn radians(cycles: f32) -> f32 {
    cycles.rem_euclid(1.0) * TAU
}

/// The rotation of `Rotate (Transform)`: Z first, then X, then Y (angles in cycles).
pub(crate) fn rotation(x: f32, y: f32, z: f32) -> Mat4 {
    Mat4::from_rotation_y(radians(y))
        * Mat4::from_rotation_x(radians(x))
        * Mat4::from_rotation_z(radians(z))
}

/// The pins of a node with Transform In and three Float pins X, Y, Z
/// (`default` each), and its evaluation:
/// `Transform Out = own(x, y, z) * Transform In`, spread slice by slice.
fn xyz_transform(
    p: &mut spreadlight_graph::Pins<'_>,
    default: f32,
    own: fn(f32, f32, f32) -> Mat4,
) -> impl Fn(&mut spreadlight_graph::EvalContext<'_>) -> Result<(), spreadlight_graph::NodeError>
+ Clone
+ Send
+ Sync
+ use<> {
    let transform_in = p.input("Transform In", Mat4::IDENTITY);
    let xyz = ["X", "Y", "Z"].map(|name| p.input(name, default));
    let transform_out = p.output::<Mat4>("Transform Out");
    move |cx| {
        let input = cx.get(transform_in)?;
        let [x, y, z] = [cx.get(xyz[0])?, cx.get(xyz[1])?, cx.get(xyz[2])?];
        let n = slice_count([input.len(), x.len(), y.len(), z.len()]);
        let out: Vec<Mat4> = (0..n)
            .map(|i| own(*wrapped(x, i), *wrapped(y, i), *wrapped(z, i)) * *wrapped(input, i))
            .collect();
        cx.put(transform_out, out);
        Ok(())
    }
}

/// A right-handed view matrix that never holds NaN: see `LookAt (Transform)`'s help
/// for what it does where the inputs leave the view undefined.
pub(crate) fn look_at(position: Vec3, target: Vec3, up: Vec3) -> Mat4 {
    let Some(forward) = (target - position).try_normalize() else {
        return Mat4::from_translation(-position);
    };
    // An up axis at least ~0.006 degrees away from the view direction; of +Y
    // and +Z, at most one can be parallel to it, so one always qualifies.
    let up = [up, Vec3::Y, Vec3::Z]
        .into_iter()
        .filter_map(Vec3::try_normalize)
        .find(|u| forward.cross(*u).length_squared() > 1e-8)
        .unwrap_or(Vec3::Y);
    let view = glam::camera::rh::view::look_to_mat4(position, forward, up);
    if view.is_finite() {
        view
    } else {
        Mat4::from_translation(-position)
    }
}

#[cfg(test)]
mod tests {
    use glam::{Mat4, Vec3};
    use spreadlight_graph::Spread;

    use super::{look_at, perspective};
    use crate::testing::{eval_out, floats};

    fn mats(v: &[Mat4]) -> Spread {
        Spread::Mat4(v.to_vec())
    }

    #[track_caller]
    fn assert_point(m: &Mat4, p: Vec3, want: Vec3) {
        let got = m.transform_point3(p);
        assert!(got.abs_diff_eq(want, 1e-5), "{p} -> {got}, want {want}");
    }

    fn one(name: &str, values: &[(&str, Spread)]) -> Mat4 {
        let out: Vec<Mat4> = eval_out(name, values, "Transform Out");
        assert_eq!(out.len(), 1, "{name}: {out:?}");
        out[0]
    }

    #[test]
    fn translate_scale_rotate_move_points() {
        let t = one(
            "Translate (Transform)",
            &[
                ("X", floats(&[1.0])),
                ("Y", floats(&[2.0])),
                ("Z", floats(&[3.0])),
            ],
        );
        assert_point(&t, Vec3::ZERO, Vec3::new(1.0, 2.0, 3.0));
        let s = one(
            "Scale (Transform)",
            &[("X", floats(&[2.0])), ("Z", floats(&[-1.0]))],
        );
        assert_point(&s, Vec3::ONE, Vec3::new(2.0, 1.0, -1.0));
        // A quarter turn about Z takes +X to +Y (counter-clockwise, right-handed).
        let r = one("Rotate (Transform)", &[("Z", floats(&[0.25]))]);
        assert_point(&r, Vec3::X, Vec3::Y);
        let r = one("Rotate (Transform)", &[("Y", floats(&[0.25]))]);
        assert_point(&r, Vec3::Z, Vec3::X);
        let r = one("Rotate (Transform)", &[("X", floats(&[0.25]))]);
        assert_point(&r, Vec3::Y, Vec3::Z);
    }

    #[test]
    fn rotate_applies_z_then_x_then_y() {
        let r = one(
            "Rotate (Transform)",
            &[
                ("X", floats(&[0.25])),
                ("Y", floats(&[0.25])),
                ("Z", floats(&[0.25])),
            ],
        );
        // +X -Rz-> +Y -Rx-> +Z -Ry-> +X.
        assert_point(&r, Vec3::X, Vec3::X);
        // +Y -Rz-> -X -Rx-> -X -Ry-> +Z.
        assert_point(&r, Vec3::Y, Vec3::Z);
    }

    #[test]
    fn a_node_applies_its_transform_after_the_incoming_one() {
        let scaled = Mat4::from_scale(Vec3::splat(2.0));
        let t = one(
            "Translate (Transform)",
            &[("Transform In", mats(&[scaled])), ("X", floats(&[1.0]))],
        );
        // Scale first (1 -> 2), then move (2 -> 3); not move then scale (4).
        assert_point(&t, Vec3::X, Vec3::new(3.0, 0.0, 0.0));
    }

    #[test]
    fn transform_3d_equals_scale_then_rotate_then_translate() {
        let input = Mat4::from_translation(Vec3::new(0.5, 0.0, 0.0));
        let all = one(
            "Transform (Transform 3d)",
            &[
                ("Transform In", mats(&[input])),
                ("Translate X", floats(&[1.0])),
                ("Translate Y", floats(&[2.0])),
                ("Translate Z", floats(&[3.0])),
                ("Scale X", floats(&[2.0])),
                ("Scale Y", floats(&[3.0])),
                ("Scale Z", floats(&[4.0])),
                ("Rotate X", floats(&[0.1])),
                ("Rotate Y", floats(&[0.2])),
                ("Rotate Z", floats(&[0.3])),
            ],
        );
        let s = one(
            "Scale (Transform)",
            &[
                ("Transform In", mats(&[input])),
                ("X", floats(&[2.0])),
                ("Y", floats(&[3.0])),
                ("Z", floats(&[4.0])),
            ],
        );
        let r = one(
            "Rotate (Transform)",
            &[
                ("Transform In", mats(&[s])),
                ("X", floats(&[0.1])),
                ("Y", floats(&[0.2])),
                ("Z", floats(&[0.3])),
            ],
        );
        let t = one(
            "Translate (Transform)",
            &[
                ("Transform In", mats(&[r])),
                ("X", floats(&[1.0])),
                ("Y", floats(&[2.0])),
                ("Z", floats(&[3.0])),
            ],
        );
        assert!(all.abs_diff_eq(t, 1e-5), "{all} vs {t}");
    }

    #[test]
    fn transforms_spread_over_their_pins() {
        let out: Vec<Mat4> = eval_out(
            "Translate (Transform)",
            &[("X", floats(&[1.0, 2.0, 3.0]))],
            "Transform Out",
        );
        assert_eq!(out.len(), 3);
        assert_point(&out[2], Vec3::ZERO, Vec3::new(3.0, 0.0, 0.0));
        let out: Vec<Mat4> = eval_out(
            "Translate (Transform)",
            &[("Transform In", mats(&[]))],
            "Transform Out",
        );
        assert!(out.is_empty());
    }

    #[test]
    fn multiply_applies_input_1_first() {
        let scale = Mat4::from_scale(Vec3::splat(2.0));
        let shift = Mat4::from_translation(Vec3::X);
        let out = one(
            "Multiply (Transform)",
            &[
                ("Transform In 1", mats(&[scale])),
                ("Transform In 2", mats(&[shift])),
            ],
        );
        assert_point(&out, Vec3::X, Vec3::new(3.0, 0.0, 0.0));
    }

    #[test]
    fn look_at_matches_a_regular_view_matrix() {
        let m = one(
            "LookAt (Transform)",
            &[
                ("Position", Spread::Vec3(vec![Vec3::new(0.0, 0.0, 5.0)])),
                ("Target", Spread::Vec3(vec![Vec3::ZERO])),
            ],
        );
        // The target lies straight ahead, 5 units down -Z in view space.
        assert_point(&m, Vec3::ZERO, Vec3::new(0.0, 0.0, -5.0));
        assert_point(&m, Vec3::new(0.0, 1.0, 0.0), Vec3::new(0.0, 1.0, -5.0));
        let m = look_at(Vec3::new(3.0, 4.0, 5.0), Vec3::new(-1.0, 0.5, 2.0), Vec3::Y);
        let forward = (Vec3::new(-1.0, 0.5, 2.0) - Vec3::new(3.0, 4.0, 5.0)).normalize();
        let target_in_view = m.transform_point3(Vec3::new(-1.0, 0.5, 2.0));
        assert!(
            target_in_view.truncate().length() < 1e-5,
            "{target_in_view}"
        );
        assert!(target_in_view.z < 0.0);
        // View-space up stays in the plane of world up and the view direction.
        let up_in_world = m.inverse().transform_vector3(Vec3::Y);
        assert!(up_in_world.dot(forward).abs() < 1e-5);
        assert!(up_in_world.y > 0.0);
    }

    #[test]
    fn perspective_is_invertible_whatever_its_pins_say() {
        let bad = [0.0, -1.0, f32::NAN, f32::INFINITY, 1e30, 0.5];
        for fov in bad {
            for near in bad {
                for far in bad {
                    let m = perspective(fov, near, near, far);
                    assert!(m.is_finite(), "{fov} {near} {far}: {m}");
                    assert!(
                        m.determinant().abs() > 0.0 && m.inverse().is_finite(),
                        "{fov} {near} {far}"
                    );
                }
            }
        }
        // A regular one: depth 0 at Near, 1 at Far.
        let m = perspective(0.25, 1.0, 0.5, 10.0);
        let depth = |z: f32| m.project_point3(Vec3::new(0.0, 0.0, -z)).z;
        assert!(depth(0.5).abs() < 1e-6 && (depth(10.0) - 1.0).abs() < 1e-6);
    }

    #[test]
    fn degenerate_look_at_stays_finite() {
        let cases = [
            // Position == target.
            (Vec3::ONE, Vec3::ONE, Vec3::Y),
            // Up parallel to the view direction, both ways.
            (Vec3::ZERO, Vec3::new(0.0, 5.0, 0.0), Vec3::Y),
            (Vec3::ZERO, Vec3::new(0.0, -5.0, 0.0), Vec3::Y),
            (Vec3::ZERO, Vec3::new(0.0, 0.0, -2.0), Vec3::Z),
            // Zero up.
            (Vec3::ZERO, Vec3::X, Vec3::ZERO),
            // Everything degenerate at once.
            (Vec3::ZERO, Vec3::ZERO, Vec3::ZERO),
        ];
        for (position, target, up) in cases {
            let m = look_at(position, target, up);
            assert!(m.is_finite(), "{position} {target} {up}: {m}");
            // Still a rigid transform: it keeps lengths.
            let d = m.transform_vector3(Vec3::new(1.0, 2.0, 3.0)).length();
            assert!(
                (d - 14f32.sqrt()).abs() < 1e-4,
                "{position} {target} {up}: {m}"
            );
            if position != target {
                let ahead = m.transform_point3(target);
                assert!(ahead.truncate().length() < 1e-4 && ahead.z < 0.0, "{ahead}");
            }
        }
        assert_eq!(
            look_at(Vec3::ONE, Vec3::ONE, Vec3::Y),
            Mat4::from_translation(-Vec3::ONE)
        );
        let out: Vec<Mat4> = eval_out(
            "LookAt (Transform)",
            &[
                ("Position", Spread::Vec3(vec![Vec3::ZERO])),
                ("Target", Spread::Vec3(vec![Vec3::ZERO])),
                ("Up", Spread::Vec3(vec![Vec3::ZERO])),
            ],
            "Transform Out",
        );
        assert_eq!(Spread::Mat4(out).first_non_finite(), None);
    }
}
