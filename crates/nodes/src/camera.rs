//! Cameras, in the "Camera" category: the orbit `Camera` node, which turns
//! a target, orbit angles and lens parameters into the View and Projection
//! matrices a renderer needs, plus the camera's Position.
//!
//! Conventions, shared with the renderer: right-handed world, view space
//! looking down -Z with +Y up, and a standard (not reversed) perspective
//! projection with depth 0 at the near plane and 1 at the far plane (wgpu's
//! and Direct3D's clip space). Angles are in cycles, as in vvvv.

use std::f32::consts::TAU;

use glam::camera::rh::{proj::directx::perspective, view::look_to_mat4};
use glam::{Mat4, Vec2, Vec3};
use spreadlight_graph::spread::{slice_count, wrapped};
use spreadlight_graph::{EvalContext, In, NodeDef, NodeError, Out, Registry};
use spreadlight_render::Renderer;
use spreadlight_render::camera::{jitter_ndc, jittered};
use spreadlight_render::renderer::DEFAULT_OUTPUT_SIZE;

const CATEGORY: &str = "Camera";

/// Pitch is held this far inside ±0.25 cycles (±90 degrees), so the camera never
/// looks exactly along its up axis and never flips over the pole.
pub const PITCH_LIMIT: f32 = 0.249;

/// The smallest orbit distance; anything closer (or negative) is held here.
pub const MIN_DISTANCE: f32 = 1e-3;

/// The Camera's pins.
#[derive(Clone, Copy)]
struct CameraPins {
    target: In<Vec3>,
    yaw: In<f32>,
    pitch: In<f32>,
    distance: In<f32>,
    fov: In<f32>,
    aspect: In<f32>,
    near: In<f32>,
    far: In<f32>,
    jitter: In<bool>,
    frame: In<i64>,
    resolution: In<Vec2>,
    view: Out<Mat4>,
    projection: Out<Mat4>,
    position: Out<Vec3>,
    jitter_out: Out<Vec2>,
}

pub fn register(r: &mut Registry) {
    r.add(
        NodeDef::new(
            "Camera",
            CATEGORY,
            "An orbit camera around Target. Yaw turns it around the vertical (Y) axis, \
             counter-clockwise seen from above: at 0 it looks from +Z towards -Z, at 0.25 from \
             +X. Pitch raises it above (positive) or below (negative) the target; it is held \
             just short of ±0.25 (straight down or up) so the view never flips. Distance is \
             held above 0. FOV is the vertical field of view, Aspect Ratio is width / height. \
             Outputs the View matrix (right-handed, looking down -Z), the Projection (standard \
             perspective, depth 0 at Near and 1 at Far, as wgpu expects) and the camera's \
             Position. Angles are in cycles. FOV must lie strictly between 0 and 0.5, Aspect \
             Ratio and Near must be above 0 and Far above Near, or the node reports an error \
             on that pin. Every pin spreads, giving one camera per slice. \
             Jitter (for TAA) moves the projection by a sub-pixel offset each frame, Halton (2, 3) over \
             8 frames, for a target of Resolution pixels ((0, 0): the renderer's output size), at Frame \
             (-1: the clock's frame); the Jitter output is that offset in NDC, for TAA's Jitter pin.",
        )
        .with_pins(|p| {
            let pins = CameraPins {
                target: p.input("Target", Vec3::ZERO),
                yaw: p.input("Yaw", 0.0f32),
                pitch: p.input("Pitch", 0.0f32),
                distance: p.input("Distance", 5.0f32),
                fov: p.input("FOV", 1.0f32 / 6.0),
                aspect: p.input("Aspect Ratio", 16.0f32 / 9.0),
                near: p.input("Near", 0.1f32),
                far: p.input("Far", 100.0f32),
                jitter: p.input("Jitter", false),
                frame: p.input("Frame", -1i64),
                resolution: p.input("Resolution", Vec2::ZERO),
                view: p.output::<Mat4>("View"),
                projection: p.output::<Mat4>("Projection"),
                position: p.output::<Vec3>("Position"),
                jitter_out: p.output::<Vec2>("Jitter"),
            };
            move |cx| camera(cx, pins)
        }),
    );
}

/// The unit vector from the target towards an orbit camera at `yaw` and `pitch` (cycles).
fn orbit_direction(yaw: f32, pitch: f32) -> Vec3 {
    let yaw = yaw.rem_euclid(1.0) * TAU;
    let pitch = pitch.clamp(-PITCH_LIMIT, PITCH_LIMIT) * TAU;
    let (sin_yaw, cos_yaw) = yaw.sin_cos();
    let (sin_pitch, cos_pitch) = pitch.sin_cos();
    Vec3::new(sin_yaw * cos_pitch, sin_pitch, cos_yaw * cos_pitch).normalize_or(Vec3::Z)
}

fn camera(cx: &mut EvalContext<'_>, pins: CameraPins) -> Result<(), NodeError> {
    let jitter = jitter_offset(cx, pins)?;
    let target = cx.get(pins.target)?;
    let mut params: [&[f32]; 7] = [&[]; 7];
    let floats = [
        pins.yaw,
        pins.pitch,
        pins.distance,
        pins.fov,
        pins.aspect,
        pins.near,
        pins.far,
    ];
    for (slot, pin) in params.iter_mut().zip(floats) {
        *slot = cx.get(pin)?;
    }
    let n = slice_count(
        [target.len()]
            .into_iter()
            .chain(params.iter().map(|p| p.len())),
    );
    let (mut views, mut projections, mut positions) = (
        Vec::with_capacity(n),
        Vec::with_capacity(n),
        Vec::with_capacity(n),
    );
    for i in 0..n {
        let target = *wrapped(target, i);
        let [yaw, pitch, distance, fov, aspect, near, far] = params.map(|p| *wrapped(p, i));
        if !(fov > 0.0 && fov < 0.5) {
            return Err(cx.error(
                pins.fov,
                format!("slice {i}: {fov} is not between 0 and 0.5 cycles (0 and 180 degrees)"),
            ));
        }
        if aspect <= 0.0 {
            return Err(cx.error(pins.aspect, format!("slice {i}: {aspect} is not above 0")));
        }
        if near <= 0.0 {
            return Err(cx.error(pins.near, format!("slice {i}: {near} is not above 0")));
        }
        if far <= near {
            return Err(cx.error(
                pins.far,
                format!("slice {i}: {far} is not beyond Near ({near})"),
            ));
        }
        let direction = orbit_direction(yaw, pitch);
        let position = target + direction * distance.max(MIN_DISTANCE);
        // Looking along -direction, not at `target - position`: that is exact even
        // where the distance is too small to tell the two points apart.
        let view = look_to_mat4(position, -direction, Vec3::Y);
        if !view.is_finite() || !position.is_finite() {
            return Err(cx.error(
                pins.distance,
                format!("slice {i}: the camera position is out of range"),
            ));
        }
        let projection = perspective(fov * TAU, aspect, near, far);
        if !projection.is_finite() {
            return Err(cx.error(
                pins.fov,
                format!("slice {i}: the lens gives no finite projection"),
            ));
        }
        views.push(view);
        projections.push(jittered(projection, jitter));
        positions.push(position);
    }
    cx.put(pins.view, views);
    cx.put(pins.projection, projections);
    cx.put(pins.position, positions);
    cx.put(pins.jitter_out, vec![jitter]);
    Ok(())
}

/// This frame's jitter in NDC (zero when off). With it on, the node runs
/// every frame: the offset changes though no input does.
fn jitter_offset(cx: &mut EvalContext<'_>, pins: CameraPins) -> Result<Vec2, NodeError> {
    if !cx.first(pins.jitter, false)? {
        return Ok(Vec2::ZERO);
    }
    cx.reevaluate_next_frame();
    let frame = cx.first(pins.frame, -1)?;
    let frame = u64::try_from(frame).unwrap_or(cx.clock.frame);
    let resolution = cx.first(pins.resolution, Vec2::ZERO)?;
    if !resolution.is_finite() || resolution.min_element() < 0.0 {
        return Err(cx.error(pins.resolution, "must be finite and not negative"));
    }
    let size = if resolution.min_element() >= 1.0 {
        (resolution.x as u32, resolution.y as u32)
    } else {
        cx.service::<Renderer>()
            .map_or(DEFAULT_OUTPUT_SIZE, |r| r.output_size())
    };
    Ok(jitter_ndc(frame, size))
}

#[cfg(test)]
mod tests {
    use glam::{Mat4, Vec3};
    use spreadlight_graph::Spread;

    use super::{MIN_DISTANCE, PITCH_LIMIT};
    use crate::testing::{eval, eval_err, eval_out, floats};

    /// View, Projection and Position of a one-slice camera.
    fn camera(values: &[(&str, Spread)]) -> (Mat4, Mat4, Vec3) {
        let out = eval("Camera", values).expect("camera");
        match &out[..] {
            [Spread::Mat4(v), Spread::Mat4(p), Spread::Vec3(pos), _] if v.len() == 1 => {
                (v[0], p[0], pos[0])
            }
            other => panic!("unexpected outputs {other:?}"),
        }
    }

    #[test]
    fn default_camera_looks_at_the_origin_from_plus_z() {
        let (view, _, position) = camera(&[]);
        assert!(
            position.abs_diff_eq(Vec3::new(0.0, 0.0, 5.0), 1e-6),
            "{position}"
        );
        let target = view.transform_point3(Vec3::ZERO);
        assert!(
            target.abs_diff_eq(Vec3::new(0.0, 0.0, -5.0), 1e-5),
            "{target}"
        );
        // World up stays up on screen.
        assert!(view.transform_vector3(Vec3::Y).abs_diff_eq(Vec3::Y, 1e-6));
    }

    #[test]
    fn yaw_and_pitch_orbit_the_target() {
        let target = Spread::Vec3(vec![Vec3::new(1.0, 2.0, 3.0)]);
        let (view, _, position) = camera(&[
            ("Target", target.clone()),
            ("Yaw", floats(&[0.25])),
            ("Distance", floats(&[2.0])),
        ]);
        assert!(
            position.abs_diff_eq(Vec3::new(3.0, 2.0, 3.0), 1e-5),
            "{position}"
        );
        let ahead = view.transform_point3(Vec3::new(1.0, 2.0, 3.0));
        assert!(
            ahead.abs_diff_eq(Vec3::new(0.0, 0.0, -2.0), 1e-5),
            "{ahead}"
        );
        let (_, _, position) = camera(&[
            ("Target", target),
            ("Pitch", floats(&[1.0 / 12.0])),
            ("Distance", floats(&[2.0])),
        ]);
        // 30 degrees up: height 2 * sin 30 = 1.
        assert!(
            position.abs_diff_eq(Vec3::new(1.0, 3.0, 3.0 + 3f32.sqrt()), 1e-5),
            "{position}"
        );
    }

    #[test]
    fn pitch_is_held_short_of_the_poles_and_distance_above_zero() {
        for pitch in [0.25, -0.25, 0.3, 7.0, -100.0] {
            let (view, _, position) = camera(&[("Pitch", floats(&[pitch]))]);
            assert!(view.is_finite(), "{pitch}: {view}");
            let limit = (PITCH_LIMIT * std::f32::consts::TAU).sin() * 5.0;
            assert!(
                (position.y.abs() - limit).abs() < 1e-4,
                "{pitch}: {position}"
            );
            assert!(position.y.signum() == pitch.signum());
            // Still a rigid transform with the target straight ahead.
            let ahead = view.transform_point3(Vec3::ZERO);
            assert!(
                ahead.abs_diff_eq(Vec3::new(0.0, 0.0, -5.0), 1e-4),
                "{pitch}: {ahead}"
            );
        }
        for distance in [0.0, -3.0] {
            let (view, _, position) = camera(&[
                ("Distance", floats(&[distance])),
                ("Target", Spread::Vec3(vec![Vec3::splat(1e6)])),
            ]);
            assert!(view.is_finite(), "{distance}: {view}");
            assert!(position.is_finite());
            assert!((position - Vec3::splat(1e6)).length() <= MIN_DISTANCE * 1.01 + 0.1);
        }
    }

    #[test]
    fn projection_maps_near_to_depth_0_and_far_to_1() {
        for (near, far) in [(0.1, 100.0), (1.0, 2.0), (0.01, 10000.0)] {
            let (view, projection, _) = camera(&[
                ("Near", floats(&[near])),
                ("Far", floats(&[far])),
                ("Distance", floats(&[3.0])),
                ("Yaw", floats(&[0.1])),
                ("Pitch", floats(&[0.05])),
            ]);
            let depth = |z: f32| projection.project_point3(Vec3::new(0.0, 0.0, -z)).z;
            assert!(depth(near).abs() < 1e-5, "near {near}: {}", depth(near));
            assert!((depth(far) - 1.0).abs() < 1e-5, "far {far}: {}", depth(far));
            assert!(depth((near + far) / 2.0) > 0.0 && depth((near + far) / 2.0) < 1.0);
            // The target, 3 units ahead, lands in the middle of the screen.
            let clip = (projection * view).project_point3(Vec3::ZERO);
            assert!(clip.truncate().length() < 1e-5, "{clip}");
        }
    }

    #[test]
    fn fov_is_vertical_in_cycles_and_aspect_is_width_over_height() {
        let (_, projection, _) =
            camera(&[("FOV", floats(&[0.25])), ("Aspect Ratio", floats(&[2.0]))]);
        // 90 degrees vertically: the top edge of the view is at y = -z.
        let top = projection.project_point3(Vec3::new(0.0, 1.0, -1.0));
        assert!((top.y - 1.0).abs() < 1e-5, "{top}");
        let right = projection.project_point3(Vec3::new(2.0, 0.0, -1.0));
        assert!((right.x - 1.0).abs() < 1e-5, "{right}");
    }

    #[test]
    fn bad_lens_parameters_are_input_errors() {
        eval_err("Camera", &[("Near", floats(&[0.0]))], "Near");
        eval_err("Camera", &[("Near", floats(&[-1.0]))], "Near");
        eval_err("Camera", &[("Far", floats(&[0.1]))], "Far");
        eval_err(
            "Camera",
            &[("Near", floats(&[5.0])), ("Far", floats(&[1.0]))],
            "Far",
        );
        eval_err(
            "Camera",
            &[("Aspect Ratio", floats(&[0.0]))],
            "Aspect Ratio",
        );
        eval_err(
            "Camera",
            &[("Aspect Ratio", floats(&[-1.0]))],
            "Aspect Ratio",
        );
        eval_err("Camera", &[("FOV", floats(&[0.0]))], "FOV");
        eval_err("Camera", &[("FOV", floats(&[0.5]))], "FOV");
        // A bad slice anywhere in the spread fails the node.
        eval_err("Camera", &[("Near", floats(&[0.1, 0.0]))], "Near");
        eval_err(
            "Camera",
            &[
                ("Target", Spread::Vec3(vec![Vec3::splat(f32::MAX)])),
                ("Distance", floats(&[1e38])),
            ],
            "Distance",
        );
    }

    #[test]
    fn jitter_moves_the_projection_by_under_half_a_pixel_per_frame() {
        let (_, still, _) = camera(&[]);
        let jitter = |frame: f32| {
            let values = [
                ("Jitter", Spread::Bool(vec![true])),
                ("Frame", Spread::Int(vec![frame as i64])),
                (
                    "Resolution",
                    Spread::Vec2(vec![glam::Vec2::new(100.0, 50.0)]),
                ),
            ];
            let (_, moved, _) = camera(&values);
            let offset: Vec<glam::Vec2> = eval_out("Camera", &values, "Jitter");
            (moved, offset[0])
        };
        let (a, ja) = jitter(0.0);
        let (b, jb) = jitter(1.0);
        assert_ne!(ja, jb);
        for (m, j) in [(a, ja), (b, jb)] {
            let p = Vec3::new(0.2, 0.1, -3.0);
            let d = m.project_point3(p) - still.project_point3(p);
            assert!((d.truncate() - j).length() < 1e-5, "{d} vs {j}");
            // Under half a pixel of the 100x50 target.
            assert!(j.x.abs() < 1.0 / 100.0 && j.y.abs() < 1.0 / 50.0, "{j}");
        }
        let offset: Vec<glam::Vec2> = eval_out("Camera", &[], "Jitter");
        assert_eq!(offset, vec![glam::Vec2::ZERO]);
    }

    #[test]
    fn cameras_spread_over_their_pins() {
        let positions: Vec<Vec3> = eval_out(
            "Camera",
            &[
                ("Yaw", floats(&[0.0, 0.25, 0.5])),
                ("Distance", floats(&[1.0])),
            ],
            "Position",
        );
        let want = [Vec3::Z, Vec3::X, -Vec3::Z];
        assert_eq!(positions.len(), 3);
        for (p, w) in positions.iter().zip(want) {
            assert!(p.abs_diff_eq(w, 1e-6), "{p} vs {w}");
        }
        let views: Vec<Mat4> = eval_out("Camera", &[("Far", floats(&[]))], "View");
        assert!(views.is_empty());
    }
}
