//! Where shadow maps look from: one view per map layer. A spot has one (its
//! own projector), a point light six (cube faces), a sun one per cascade,
//! fitted to a slice of the camera's frustum. All projections write
//! conventional depth (0 near, 1 far), which the shader linearizes with the
//! layer's near and far.

use glam::{Mat4, Vec3, Vec4};

use crate::camera::CameraInput;

/// One layer of a shadow map: what the depth pass renders and the shader samples.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct LayerView {
    pub view_projection: Mat4,
    pub near: f32,
    pub far: f32,
    /// World size of a texel: at distance 1 for a perspective view (times the
    /// distance at the receiver), everywhere for an orthographic one.
    pub texel: f32,
    pub orthographic: bool,
    /// Sun cascades: the camera view depth where this cascade ends.
    pub split: f32,
}

/// Matches `ShadowView` in shaders/lighting/shadow_sampling.wgsl.
#[repr(C)]
#[derive(Clone, Copy, Debug, bytemuck::Pod, bytemuck::Zeroable)]
pub(crate) struct GpuLayerView {
    view_projection: [f32; 16],
    /// near, far, texel, orthographic (0/1)
    depth: [f32; 4],
    /// split, 0, 0, 0
    split: [f32; 4],
}

impl LayerView {
    pub(crate) fn to_gpu(self) -> GpuLayerView {
        GpuLayerView {
            view_projection: self.view_projection.to_cols_array(),
            depth: [
                self.near,
                self.far,
                self.texel,
                if self.orthographic { 1.0 } else { 0.0 },
            ],
            split: [self.split, 0.0, 0.0, 0.0],
        }
    }
}

/// A spot's view: its own projector, with near and far read off its projection.
pub fn spot(view: Mat4, projection: Mat4, resolution: u32) -> Option<LayerView> {
    let (near, far) = near_far(projection)?;
    // Half the frustum's width at distance 1, from the projection's x scale.
    let tan_half = 1.0 / projection.x_axis.x.abs().max(1e-6);
    Some(LayerView {
        view_projection: projection * view,
        near,
        far,
        texel: 2.0 * tan_half / resolution.max(1) as f32,
        orthographic: false,
        split: 0.0,
    })
}

/// The six cube faces of a point light (+X, -X, +Y, -Y, +Z, -Z, as a cube
/// map orders them), each a 90-degree frustum out to `range`.
pub fn point(position: Vec3, range: f32, resolution: u32) -> [LayerView; 6] {
    let far = range.max(1e-3);
    let near = (far * 1e-3).max(1e-4);
    let projection =
        glam::camera::rh::proj::directx::perspective(std::f32::consts::FRAC_PI_2, 1.0, near, far);
    let faces = [
        (Vec3::X, Vec3::NEG_Y),
        (Vec3::NEG_X, Vec3::NEG_Y),
        (Vec3::Y, Vec3::Z),
        (Vec3::NEG_Y, Vec3::NEG_Z),
        (Vec3::Z, Vec3::NEG_Y),
        (Vec3::NEG_Z, Vec3::NEG_Y),
    ];
    faces.map(|(dir, up)| LayerView {
        view_projection: projection * glam::camera::rh::view::look_to_mat4(position, dir, up),
        near,
        far,
        texel: 2.0 / resolution.max(1) as f32,
        orthographic: false,
        split: 0.0,
    })
}

/// The distances where each of `count` cascades ends, between the camera's
/// `near` and `far`: `lambda` 0 splits evenly, 1 logarithmically (the
/// practical split scheme of Zhang et al. blends the two).
pub fn cascade_splits(near: f32, far: f32, count: u32, lambda: f32) -> Vec<f32> {
    let count = count.clamp(1, 4);
    let lambda = if lambda.is_finite() {
        lambda.clamp(0.0, 1.0)
    } else {
        0.5
    };
    (1..=count)
        .map(|i| {
            let t = i as f32 / count as f32;
            let log = near * (far / near).powf(t);
            let uniform = near + (far - near) * t;
            lambda * log + (1.0 - lambda) * uniform
        })
        .collect()
}

/// How a sun's shadow is cut into cascades.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Cascades {
    /// 1 to 4.
    pub count: u32,
    /// 0 even splits .. 1 logarithmic.
    pub split_lambda: f32,
    /// How far from the camera sun shadows reach.
    pub distance: f32,
    /// 0: each cascade follows the camera texel by texel (re-rendered
    /// whenever the camera moves). Above 0 (up to 0.5): a cascade is wider
    /// by this share of its width on each side and moves only in steps of
    /// that share, so its view (and its map, if its casters are still)
    /// holds while the camera moves within a step.
    pub step: f32,
}

impl Cascades {
    /// The step as a share of a cascade's width: 0 where not finite, at most 0.5.
    fn step_share(&self) -> f32 {
        if self.step.is_finite() {
            self.step.clamp(0.0, 0.5)
        } else {
            0.0
        }
    }
}

/// A sun's cascades: each an orthographic box around the bounding sphere of
/// its slice of the camera frustum, snapped to whole texels so the map does
/// not shimmer as the camera moves, and deep enough to hold every caster
/// between it and the sun: `casters` is a sphere (centre, radius) around them.
pub fn sun(
    direction: Vec3,
    camera: &CameraInput,
    cascades: Cascades,
    casters: (Vec3, f32),
    resolution: u32,
) -> Vec<LayerView> {
    sun_held(direction, camera, cascades, casters, resolution, &[]).0
}

/// Where a texel-by-texel cascade's box was placed: its half width and its
/// snapped centre in the light's view space.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct CascadeBox {
    pub radius: f32,
    pub center: Vec3,
}

/// [`sun`], each texel-by-texel cascade (a Cascade Step of 0) holding the
/// box it had (`held[k]`, as this returned it last time) while that box
/// still holds the cascade's slice of the frustum: its slice's sphere within
/// a texel and a half of the held centre across (the box has two texels of
/// room), the same size and depth. A camera's sub-pixel jitter (TAA) moves
/// the slices by a fraction of a texel every frame; snapped afresh, a
/// cascade whose centre lies near a texel's edge flipped between two places
/// and its map was drawn or scrolled every frame of a still camera. Returns
/// the views and each cascade's box (None for a stepped cascade).
pub fn sun_held(
    direction: Vec3,
    camera: &CameraInput,
    cascades: Cascades,
    casters: (Vec3, f32),
    resolution: u32,
    held: &[Option<CascadeBox>],
) -> (Vec<LayerView>, Vec<Option<CascadeBox>>) {
    let (near, far) = near_far(camera.projection).unwrap_or((0.1, 100.0));
    let distance = if cascades.distance.is_finite() {
        cascades.distance
    } else {
        far
    };
    let far = far.min(distance.max(near * 2.0));
    let splits = cascade_splits(near, far, cascades.count, cascades.split_lambda);
    let to_world = crate::camera::safe_inverse(camera.view);
    let unproject = crate::camera::safe_inverse(camera.projection);
    // View-space rays through the frustum's corners, at depth 1.
    let rays: Vec<Vec3> = [(-1.0, -1.0), (1.0, -1.0), (-1.0, 1.0), (1.0, 1.0)]
        .iter()
        .map(|&(x, y)| {
            let h = unproject * Vec4::new(x, y, 1.0, 1.0);
            let p = h.truncate() / h.w;
            p / (-p.z).max(1e-6)
        })
        .collect();
    let direction = direction.try_normalize().unwrap_or(Vec3::NEG_Y);
    let up = if direction.y.abs() > 0.99 {
        Vec3::Z
    } else {
        Vec3::Y
    };
    let res = resolution.max(1) as f32;
    let step_share = cascades.step_share();
    let mut start = near;
    splits
        .into_iter()
        .enumerate()
        .map(|(k, end)| {
            let corners = rays
                .iter()
                .flat_map(|r| [*r * start, *r * end])
                .map(|p| to_world.transform_point3(p));
            let corners: Vec<Vec3> = corners.collect();
            let center = corners.iter().copied().sum::<Vec3>() / corners.len() as f32;
            // The slice's sphere.
            let reach = corners
                .iter()
                .map(|c| c.distance(center))
                .fold(0.0f32, f32::max)
                .max(1e-3);
            // Two texels of room: snapping the centre moves it by up to one.
            let mut radius = reach * (1.0 + 4.0 / res);
            let light_view = glam::camera::rh::view::look_to_mat4(Vec3::ZERO, direction, up);
            let c = light_view.transform_point3(center);
            // The box is placed in the light's view space (not through a
            // world-space round trip), so that a box that holds its size and
            // depth gives a view-projection that differs from the last only
            // by whole texels across: what lets a moving camera scroll a
            // cascade's map instead of drawing it again (`texel_shift`).
            let (snapped, room) = if step_share > 0.0 {
                // Stepped: wider by a step on each side, and the centre snapped
                // to whole steps (whole texels) in all three of the light's
                // axes, so the box (depth range too) holds while the camera
                // moves within a step. The sphere is within a step of the
                // snapped centre along each axis: the step of room holds it.
                // The radius rounded up to 6 significant bits: a frustum's
                // sphere is the same size wherever the camera is, but its
                // float rounding is not, and a view must hold bit for bit.
                let unit = (radius.log2().floor() - 5.0).exp2();
                radius = (radius / unit).ceil() * unit;
                let step = 2.0 * step_share * radius;
                radius += step;
                let texel = 2.0 * radius / res;
                let step = (step / texel).floor().max(1.0) * texel;
                ((c / step).floor() * step, 0.0)
            } else {
                // Following the camera texel by texel: the radius rounded up
                // to 10 significant bits (at most 0.1% wider) so that it holds
                // bit for bit, the centre snapped to whole texels across, and
                // along the light to whole radii, with a radius of room
                // towards the sun: the depth range holds while the
                // camera moves within it, so moves across scroll the map.
                let unit = (radius.log2().floor() - 9.0).exp2();
                radius = (radius / unit).ceil() * unit;
                let texel = 2.0 * radius / res;
                let along = radius;
                let fresh = Vec3::new(
                    (c.x / texel).floor() * texel,
                    (c.y / texel).floor() * texel,
                    (c.z / along).floor() * along,
                );
                // The held box while it holds the slice's sphere across (a
                // tenth of a texel to spare) and along the light as a fresh
                // one would (its centre within the box's first radius), and
                // is at most a percent larger than a fresh one.
                let kept = held.get(k).copied().flatten().filter(|b| {
                    let spare = 0.2 * b.radius / res;
                    b.radius <= radius * 1.01
                        && (c.x - b.center.x).abs() + reach <= b.radius - spare
                        && (c.y - b.center.y).abs() + reach <= b.radius - spare
                        && c.z >= b.center.z
                        && c.z < b.center.z + b.radius
                });
                match kept {
                    Some(b) => {
                        radius = b.radius;
                        (b.center, b.radius)
                    }
                    None => (fresh, along),
                }
            };
            let texel = 2.0 * radius / res;
            // Back to the farthest caster towards the sun (at least the
            // cascade's own sphere): the sun lies along +z in the light's view.
            let (caster_center, caster_radius) = casters;
            let reach = light_view.transform_point3(caster_center).z - snapped.z + caster_radius;
            let back = (radius + room).max(if reach.is_finite() { reach } else { 0.0 });
            let eye = snapped + Vec3::new(0.0, 0.0, back);
            let view = Mat4::from_translation(-eye) * light_view;
            let depth = back + radius;
            let projection = glam::camera::rh::proj::directx::orthographic(
                -radius, radius, -radius, radius, 0.0, depth,
            );
            start = end;
            let placed = (step_share <= 0.0).then_some(CascadeBox {
                radius,
                center: snapped,
            });
            (
                LayerView {
                    view_projection: projection * view,
                    near: 0.0,
                    far: depth,
                    texel,
                    orthographic: true,
                    split: end,
                },
                placed,
            )
        })
        .unzip()
}

/// How far every point moved in a layer's map, in whole texels (right,
/// down), between view-projections `old` and `new` (column-major): Some where
/// the two are the same orthographic box moved across the light by whole
/// texels (a sun's cascade following the camera: the same size, depth range
/// and direction), so the old map shifted by it is the new one but for the
/// strips it uncovers. None for any other change, and for a move of a whole
/// map or more (nothing would be kept).
pub(crate) fn texel_shift(old: &[f32; 16], new: &[f32; 16], resolution: u32) -> Option<(i32, i32)> {
    // Orthographic: no perspective row, so a move across is a shift.
    let affine = old[3] == 0.0 && old[7] == 0.0 && old[11] == 0.0 && old[15] == 1.0;
    // Everything but the translation across (12, 13) the same, bit for bit
    // (NaN is never equal: a broken view never scrolls).
    let same = (0..16)
        .filter(|&i| i != 12 && i != 13)
        .all(|i| old[i] == new[i]);
    if !affine || !same {
        return None;
    }
    // A point's NDC moves by the translation's change; NDC spans 2 over the map.
    let half = resolution as f32 * 0.5;
    let whole = |ndc: f32| {
        let texels = ndc * half;
        let k = texels.round();
        (texels.is_finite() && (texels - k).abs() <= 1e-2 && k.abs() < resolution as f32)
            .then_some(k as i32)
    };
    // NDC y points up, texel rows down.
    Some((whole(new[12] - old[12])?, whole(old[13] - new[13])?))
}

/// Near and far of a conventional (0..1 depth) perspective projection.
pub fn near_far(projection: Mat4) -> Option<(f32, f32)> {
    let (a, b) = (projection.z_axis.z, projection.w_axis.z);
    let near = b / a;
    let far = b / (a + 1.0);
    (near.is_finite() && far.is_finite() && near > 0.0 && far > near).then_some((near, far))
}

/// The texels of a map of `resolution` a side seen through `view_projection`
/// that a sphere may cover, a texel wider on each side (empty where it lies
/// beside the map): the box of its bounding cube's corners, projected.
/// None where that cannot bound it (a corner at or behind a perspective
/// view's eye, or anything not finite).
pub(super) fn sphere_texels(
    view_projection: Mat4,
    center: Vec3,
    radius: f32,
    resolution: u32,
) -> Option<super::scroll::Rect> {
    let (mut lo, mut hi) = (
        glam::Vec2::splat(f32::INFINITY),
        glam::Vec2::splat(f32::NEG_INFINITY),
    );
    for k in 0..8 {
        let corner = center
            + radius
                * Vec3::new(
                    if k & 1 == 0 { -1.0 } else { 1.0 },
                    if k & 2 == 0 { -1.0 } else { 1.0 },
                    if k & 4 == 0 { -1.0 } else { 1.0 },
                );
        let clip = view_projection * corner.extend(1.0);
        // NaN fails the finiteness test, so the comparison needs no negation.
        if !clip.is_finite() || clip.w <= 1e-6 {
            return None;
        }
        let ndc = glam::Vec2::new(clip.x, clip.y) / clip.w;
        // Texels run right and down from the top left (strip_projection).
        let texel = glam::Vec2::new(ndc.x * 0.5 + 0.5, 0.5 - ndc.y * 0.5) * resolution as f32;
        lo = lo.min(texel);
        hi = hi.max(texel);
    }
    let r = resolution as f32;
    let (x0, y0) = (
        (lo.x.floor() - 1.0).clamp(0.0, r),
        (lo.y.floor() - 1.0).clamp(0.0, r),
    );
    let (x1, y1) = (
        (hi.x.ceil() + 1.0).clamp(0.0, r),
        (hi.y.ceil() + 1.0).clamp(0.0, r),
    );
    Some(super::scroll::Rect {
        x: x0 as u32,
        y: y0 as u32,
        w: (x1 - x0).max(0.0) as u32,
        h: (y1 - y0).max(0.0) as u32,
    })
}

/// Whether a sphere touches the frustum of `view_projection` (conventional
/// or reversed depth: only the side planes and the near plane are tested,
/// which is conservative).
pub fn sphere_in_frustum(view_projection: Mat4, center: Vec3, radius: f32) -> bool {
    let m = view_projection.transpose();
    let (r0, r1, r3) = (m.x_axis, m.y_axis, m.w_axis);
    let planes = [r3 + r0, r3 - r0, r3 + r1, r3 - r1];
    planes.iter().all(|p| {
        let n = p.truncate();
        let len = n.length();
        len <= 0.0 || (n.dot(center) + p.w) / len >= -radius
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_sphere_covers_the_texels_of_its_projected_box_a_texel_wider() {
        use super::super::scroll::Rect;
        // Identity: NDC -0.5..0.5 is texels 25..75 of 100, y down.
        let rect = sphere_texels(Mat4::IDENTITY, Vec3::new(0.0, 0.2, 0.0), 0.5, 100);
        assert_eq!(
            rect,
            Some(Rect {
                x: 24,
                y: 14,
                w: 52,
                h: 52
            })
        );
        // Beside the map: nothing; half over its edge: clipped to it.
        let beside = sphere_texels(Mat4::IDENTITY, Vec3::new(3.0, 0.0, 0.0), 0.5, 100);
        assert!(beside.is_some_and(|r| r.is_empty()), "{beside:?}");
        let edge = sphere_texels(Mat4::IDENTITY, Vec3::new(1.0, 0.0, 0.0), 0.5, 100);
        assert_eq!(edge.map(|r| (r.x, r.x + r.w)), Some((74, 100)));
        // Behind a perspective view's eye, or not finite: no bound.
        let view = glam::camera::rh::view::look_at_mat4(Vec3::ZERO, Vec3::NEG_Z, Vec3::Y);
        let projection = glam::camera::rh::proj::directx::perspective(1.0, 1.0, 0.1, 100.0);
        let vp = projection * view;
        assert!(sphere_texels(vp, Vec3::new(0.0, 0.0, -5.0), 1.0, 64).is_some());
        assert_eq!(sphere_texels(vp, Vec3::new(0.0, 0.0, 0.5), 1.0, 64), None);
        assert_eq!(
            sphere_texels(vp, Vec3::new(f32::NAN, 0.0, -5.0), 1.0, 64),
            None
        );
    }

    #[test]
    fn splits_run_from_even_to_logarithmic_and_end_at_far() {
        let even = cascade_splits(1.0, 100.0, 4, 0.0);
        assert_eq!(even, [25.75, 50.5, 75.25, 100.0]);
        let log = cascade_splits(1.0, 100.0, 4, 1.0);
        assert!((log[1] - 10.0).abs() < 1e-3 && (log[3] - 100.0).abs() < 1e-3);
        assert_eq!(cascade_splits(1.0, 100.0, 9, 0.5).len(), 4);
        assert!(
            cascade_splits(1.0, 100.0, 2, f32::NAN)
                .iter()
                .all(|s| s.is_finite())
        );
    }

    #[test]
    fn every_cascade_holds_its_slice_of_the_camera_frustum() {
        for step in [0.0, 0.1, 0.25, 0.5] {
            for eye in [
                Vec3::new(0.0, 5.0, 10.0),
                Vec3::new(0.37, 5.11, 9.6),
                Vec3::new(-13.2, 4.0, 31.7),
            ] {
                cascades_hold_their_slices(step, eye);
            }
        }
    }

    /// Every corner of each cascade's slice of the frustum (and its centre
    /// line) lies in the cascade's box, sides and depth.
    fn cascades_hold_their_slices(step: f32, eye: Vec3) {
        let view = glam::camera::rh::view::look_at_mat4(eye, Vec3::ZERO, Vec3::Y);
        let projection = glam::camera::rh::proj::directx::perspective(1.0, 1.5, 0.1, 200.0);
        let cascades = sun(
            Vec3::new(-0.3, -1.0, -0.2),
            &CameraInput { view, projection },
            Cascades {
                count: 4,
                split_lambda: 0.7,
                distance: 60.0,
                step,
            },
            (Vec3::ZERO, 20.0),
            1024,
        );
        assert_eq!(cascades.len(), 4);
        let to_world = view.inverse();
        let unproject = projection.inverse();
        let mut start = 0.1;
        for c in &cascades {
            for (x, y) in [(-1.0, -1.0), (1.0, 1.0), (-1.0, 1.0), (0.0, 0.0)] {
                for d in [start, c.split] {
                    let h = unproject * Vec4::new(x, y, 1.0, 1.0);
                    let ray = h.truncate() / h.w;
                    let p = to_world.transform_point3(ray / -ray.z * d);
                    let ndc = c.view_projection.project_point3(p);
                    assert!(
                        ndc.x.abs() <= 1.0 + 1e-3 && ndc.y.abs() <= 1.0 + 1e-3,
                        "step {step}, eye {eye}: {ndc}"
                    );
                    assert!(
                        (0.0..=1.0).contains(&ndc.z),
                        "step {step}, eye {eye}: {ndc}"
                    );
                }
            }
            start = c.split;
        }
    }

    #[test]
    fn a_jittering_still_camera_keeps_its_cascades_and_they_keep_holding_its_slices() {
        let view =
            glam::camera::rh::view::look_at_mat4(Vec3::new(3.0, 12.0, 30.0), Vec3::ZERO, Vec3::Y);
        let base = glam::camera::rh::proj::directx::perspective(0.6, 16.0 / 9.0, 0.1, 1000.0);
        let cascades = Cascades {
            count: 4,
            split_lambda: 0.7,
            distance: 60.0,
            step: 0.0,
        };
        let direction = Vec3::new(-0.5, -1.0, -0.25);
        let place = |frame: u64, held: &[Option<CascadeBox>]| {
            let projection =
                crate::camera::jittered(base, crate::camera::jitter_ndc(frame, (1920, 1080)));
            let camera = CameraInput { view, projection };
            let (views, boxes) =
                sun_held(direction, &camera, cascades, (Vec3::ZERO, 80.0), 1024, held);
            (camera, views, boxes)
        };
        let (_, first, mut held) = place(0, &[]);
        assert!(
            held.iter().all(Option::is_some),
            "texel by texel: every box is known"
        );
        // TAA's eight jitters: every cascade holds its box, bit for bit, and
        // the box still holds the jittered frustum's slice.
        for frame in 1..16 {
            let (camera, views, boxes) = place(frame, &held);
            for (k, (a, b)) in first.iter().zip(&views).enumerate() {
                assert_eq!(
                    a.view_projection, b.view_projection,
                    "frame {frame}, cascade {k}"
                );
            }
            let to_world = camera.view.inverse();
            let unproject = camera.projection.inverse();
            let mut start = 0.1;
            for v in &views {
                for (x, y) in [(-1.0, -1.0), (1.0, 1.0), (-1.0, 1.0), (1.0, -1.0)] {
                    for d in [start, v.split] {
                        let h = unproject * Vec4::new(x, y, 1.0, 1.0);
                        let ray = h.truncate() / h.w;
                        let p = to_world.transform_point3(ray / -ray.z * d);
                        let ndc = v.view_projection.project_point3(p);
                        assert!(
                            ndc.x.abs() <= 1.0 && ndc.y.abs() <= 1.0,
                            "frame {frame}: {ndc}"
                        );
                    }
                }
                start = v.split;
            }
            held = boxes;
        }
        // A box that no longer holds its slice is placed afresh: a box held
        // four texels to one side (a box has two to two and a half texels of
        // room).
        let shifted: Vec<Option<CascadeBox>> = held
            .iter()
            .zip(&first)
            .map(|(b, v)| {
                b.map(|b| CascadeBox {
                    center: b.center + Vec3::new(4.0 * v.texel, 0.0, 0.0),
                    ..b
                })
            })
            .collect();
        let (_, views, _) = place(0, &shifted);
        for (k, (a, b)) in first.iter().zip(&views).enumerate() {
            assert_eq!(
                a.view_projection, b.view_projection,
                "cascade {k} placed afresh"
            );
        }
    }

    #[test]
    fn stepped_cascades_hold_their_views_while_the_camera_moves_within_a_step() {
        let at = |x: f32| {
            let eye = Vec3::new(x, 5.0, 10.0);
            CameraInput {
                view: glam::camera::rh::view::look_at_mat4(
                    eye,
                    eye - Vec3::new(0.0, 5.0, 10.0),
                    Vec3::Y,
                ),
                projection: glam::camera::rh::proj::directx::perspective(1.0, 1.5, 0.1, 200.0),
            }
        };
        let views = |step: f32, x: f32| -> Vec<Mat4> {
            let cascades = Cascades {
                count: 3,
                split_lambda: 0.6,
                distance: 40.0,
                step,
            };
            sun(
                Vec3::new(-0.3, -1.0, -0.2),
                &at(x),
                cascades,
                (Vec3::ZERO, 20.0),
                512,
            )
            .iter()
            .map(|v| v.view_projection)
            .collect()
        };
        // Following the camera texel by texel: the finest cascade moves with
        // nearly every small move, and a cascade that moves across the
        // light moves by whole texels of the same box (its map scrolls);
        // only where the camera crosses a radius along the light does the
        // depth range change (drawn whole), seldom.
        let (mut shifted, mut redrawn, mut kept) = (0, 0, 0);
        for k in 1..=20 {
            let before = views(0.0, (k - 1) as f32 * 0.05);
            let after = views(0.0, k as f32 * 0.05);
            for (b, a) in before.iter().zip(&after) {
                match texel_shift(&b.to_cols_array(), &a.to_cols_array(), 512) {
                    _ if a == b => kept += 1,
                    Some((x, y)) => {
                        assert!((x, y) != (0, 0) && x.abs() < 512 && y.abs() < 512);
                        shifted += 1;
                    }
                    None => redrawn += 1,
                }
            }
        }
        assert!(
            shifted >= 25 && redrawn <= 3,
            "shifted {shifted}, drawn whole {redrawn}, kept {kept}"
        );
        // Stepped: moves much smaller than a step leave most cascades where
        // they were, bit for bit; over 20 small moves the first cascade (the
        // finest, steps of about 1.3 units here) steps a few times at most.
        let mut steps = 0;
        let mut held = 0;
        for k in 1..=20 {
            let (before, after) = (
                views(0.25, (k - 1) as f32 * 0.05),
                views(0.25, k as f32 * 0.05),
            );
            for (b, a) in before.iter().zip(&after) {
                if a == b {
                    held += 1;
                } else {
                    steps += 1;
                }
            }
        }
        assert!(held >= 50 && steps <= 10, "held {held}, stepped {steps}");
    }

    #[test]
    fn texel_shift_finds_whole_texel_moves_of_one_box_and_nothing_else() {
        let p = glam::camera::rh::proj::directx::orthographic(-2.0, 2.0, -2.0, 2.0, 0.0, 10.0);
        let texel = 4.0 / 64.0;
        let at = |x: f32, y: f32, z: f32| {
            (p * Mat4::from_translation(Vec3::new(-x, -y, -z))).to_cols_array()
        };
        let a = at(0.0, 0.0, 0.0);
        // The box moves right and down: what it sees moves left and up.
        assert_eq!(
            texel_shift(&a, &at(3.0 * texel, -2.0 * texel, 0.0), 64),
            Some((-3, -2))
        );
        assert_eq!(texel_shift(&a, &a, 64), Some((0, 0)));
        // Half a texel, a move along the light (another depth range), a
        // whole map or more, a perspective view, NaN: drawn whole.
        assert_eq!(texel_shift(&a, &at(0.5 * texel, 0.0, 0.0), 64), None);
        assert_eq!(texel_shift(&a, &at(0.0, 0.0, 0.5), 64), None);
        assert_eq!(texel_shift(&a, &at(64.0 * texel, 0.0, 0.0), 64), None);
        let perspective = glam::camera::rh::proj::directx::perspective(1.0, 1.0, 0.1, 10.0);
        let q = |x: f32| {
            (perspective * Mat4::from_translation(Vec3::new(-x, 0.0, 0.0))).to_cols_array()
        };
        assert_eq!(texel_shift(&q(0.0), &q(1.0), 64), None);
        assert_eq!(texel_shift(&a, &at(f32::NAN, 0.0, 0.0), 64), None);
    }

    #[test]
    fn cascades_reach_back_to_casters_far_towards_the_sun() {
        let view = glam::camera::rh::view::look_at_mat4(
            Vec3::new(0.0, 1.5, 25.0),
            Vec3::new(0.0, 1.5, 0.0),
            Vec3::Y,
        );
        let projection = glam::camera::rh::proj::directx::perspective(1.0, 1.5, 0.1, 200.0);
        // A low sun: light travels towards +z; a caster at the origin, far up-sun of the near cascade.
        let direction = Vec3::new(0.0, -0.05, 1.0).normalize();
        let cascades = sun(
            direction,
            &CameraInput { view, projection },
            Cascades {
                count: 4,
                split_lambda: 0.7,
                distance: 60.0,
                step: 0.0,
            },
            (Vec3::ZERO, 0.87),
            1024,
        );
        let ndc = cascades[0].view_projection.project_point3(Vec3::ZERO);
        assert!(
            (0.0..=1.0).contains(&ndc.z),
            "the caster lies within the first cascade's depth: {ndc}"
        );
    }

    #[test]
    fn cube_faces_cover_every_direction_once() {
        let faces = point(Vec3::new(1.0, 2.0, 3.0), 10.0, 256);
        for dir in [
            Vec3::X,
            Vec3::NEG_X,
            Vec3::Y,
            Vec3::NEG_Y,
            Vec3::Z,
            Vec3::NEG_Z,
            Vec3::new(1.0, 0.5, -0.2),
        ] {
            let p = Vec3::new(1.0, 2.0, 3.0) + dir.normalize() * 5.0;
            let inside = faces
                .iter()
                .filter(|f| {
                    let ndc = f.view_projection.project_point3(p);
                    ndc.x.abs() < 1.0 && ndc.y.abs() < 1.0 && (0.0..1.0).contains(&ndc.z)
                })
                .count();
            assert!(inside >= 1, "{dir}: {inside}");
        }
    }

    #[test]
    fn spheres_outside_the_frustum_are_culled() {
        let view = glam::camera::rh::view::look_at_mat4(Vec3::ZERO, Vec3::NEG_Z, Vec3::Y);
        let vp = glam::camera::rh::proj::directx::perspective(1.0, 1.0, 0.1, 100.0) * view;
        assert!(sphere_in_frustum(vp, Vec3::new(0.0, 0.0, -10.0), 1.0));
        assert!(
            !sphere_in_frustum(vp, Vec3::new(0.0, 0.0, 10.0), 1.0),
            "behind"
        );
        assert!(
            !sphere_in_frustum(vp, Vec3::new(50.0, 0.0, -10.0), 1.0),
            "beside"
        );
        assert!(
            sphere_in_frustum(vp, Vec3::new(0.0, 0.0, 10.0), 11.0),
            "reaching in from behind"
        );
    }
}

/// The layout the shader sees (shaders/layout.rs).
#[cfg(test)]
mod wgsl_layout {
    use super::*;

    #[test]
    fn gpu_layer_view_matches_shadowview_in_the_shader() {
        crate::assert_wgsl_layout!(
            GpuLayerView,
            "lighting/shadow_sampling.wgsl",
            ["SHADOWS"],
            "ShadowView",
            [view_projection, depth, split]
        );
    }
}
