//! AO's and SSGI's depth- and normal-aware blur against the CPU: the x pass
//! over the unblurred image, then the y pass over its result, with the same
//! Gaussian and the same weights for view-distance and normal difference
//! (shaders/ssao/blur.wgsl, shaders/lighting/ssgi.wgsl's BLUR). At a
//! size that is a multiple of 8 neither way, workgroups end at the image's
//! edge.

use crate::occlusion_scene;

use glam::Vec3;
use spreadlight_render::FrameReport;
use spreadlight_render::camera::reverse_z;
use spreadlight_render::lighting::{Ssgi, SsgiSettings};
use spreadlight_render::readback::{ImageF32, render_and_read};
use spreadlight_render::renderer::test_renderer;
use spreadlight_render::ssao::{AmbientOcclusion, AoMode, AoSettings};

use occlusion_scene::{camera, constant, eye, gbuffer, image};

/// Not a multiple of 8 either way.
const SIZE: (u32, u32) = (150, 90);

/// How a tap's value counts.
#[derive(Clone, Copy)]
enum Values {
    /// AO: one channel clamped to 0..1; a tap that is not finite is left out,
    /// and a centre that is not finite with no tap counts as unoccluded.
    Occlusion,
    /// SSGI: four channels of light, each cleaned (finite, non-negative,
    /// below 65000; the escaped share in 0..1).
    Light,
}

impl Values {
    fn tap(self, v: [f32; 4]) -> Option<[f32; 4]> {
        match self {
            Values::Occlusion => v[0]
                .is_finite()
                .then(|| [v[0].clamp(0.0, 1.0), 0.0, 0.0, 0.0]),
            Values::Light => {
                let clean = |c: f32| {
                    if (0.0..=3e38).contains(&c) {
                        c.min(65000.0)
                    } else {
                        0.0
                    }
                };
                let share = if v[3].abs() <= 1.0 {
                    v[3].clamp(0.0, 1.0)
                } else {
                    1.0
                };
                Some([clean(v[0]), clean(v[1]), clean(v[2]), share])
            }
        }
    }

    fn lone(self, v: [f32; 4]) -> [f32; 4] {
        self.tap(v).unwrap_or([1.0, 0.0, 0.0, 0.0])
    }
}

/// The two-pass blur on the CPU.
fn reference_blur(
    sharp: &[[f32; 4]],
    depth: &ImageF32,
    normals: &ImageF32,
    radius: i32,
    values: Values,
) -> Vec<[f32; 4]> {
    let c = camera(eye(), SIZE.0 as f32 / SIZE.1 as f32);
    let inverse = reverse_z(c.projection).inverse();
    let (w, h) = (SIZE.0 as i32, SIZE.1 as i32);
    let at = |x: i32, y: i32| (y * w + x) as usize;
    let distance = |x: i32, y: i32| {
        let d = depth.pixels[at(x, y)][0];
        let ndc = glam::Vec2::new(
            (x as f32 + 0.5) / SIZE.0 as f32 * 2.0 - 1.0,
            1.0 - (y as f32 + 0.5) / SIZE.1 as f32 * 2.0,
        );
        let p = inverse * glam::Vec4::new(ndc.x, ndc.y, d, 1.0);
        -p.z / p.w
    };
    let normal = |x: i32, y: i32, fallback: Vec3| {
        let n = Vec3::from_slice(&normals.pixels[at(x, y)][..3]);
        if n.length_squared() > 1e-20 {
            n.normalize()
        } else {
            fallback
        }
    };
    let sigma = (radius.max(1) as f32) * 0.5;
    let pass = |image: &[[f32; 4]], axis: (i32, i32)| -> Vec<[f32; 4]> {
        let mut out = image.to_vec();
        for y in 0..h {
            for x in 0..w {
                if depth.pixels[at(x, y)][0] <= 0.0 {
                    continue;
                }
                let (z0, n0) = (distance(x, y), normal(x, y, Vec3::Z));
                let (mut sum, mut weights) = ([0.0f32; 4], 0.0f32);
                for o in -radius..=radius {
                    let (qx, qy) = (x + axis.0 * o, y + axis.1 * o);
                    if qx < 0 || qy < 0 || qx >= w || qy >= h || depth.pixels[at(qx, qy)][0] <= 0.0
                    {
                        continue;
                    }
                    let Some(v) = values.tap(image[at(qx, qy)]) else {
                        continue;
                    };
                    let (zq, nq) = (distance(qx, qy), normal(qx, qy, n0));
                    let similarity =
                        (-(zq - z0).abs() / (0.03 * z0 + 1e-6)).exp() * n0.dot(nq).max(0.0).powi(8);
                    let weight = (-((o * o) as f32) / (2.0 * sigma * sigma)).exp() * similarity;
                    for k in 0..4 {
                        sum[k] += weight * v[k];
                    }
                    weights += weight;
                }
                let mut v = if weights > 1e-6 {
                    sum.map(|s| s / weights)
                } else {
                    values.lone(image[at(x, y)])
                };
                if let Values::Occlusion = values {
                    v[0] = v[0].clamp(0.0, 1.0);
                }
                out[at(x, y)] = v;
            }
        }
        out
    };
    pass(&pass(sharp, (1, 0)), (0, 1))
}

/// Checks `blurred` against the CPU blur of `sharp` channel by channel
/// (`channels`), with a tolerance relative to the value; returns how many
/// pixels the blur changed.
fn check(
    what: &str,
    blurred: &ImageF32,
    expected: &[[f32; 4]],
    sharp: &[[f32; 4]],
    channels: usize,
) -> usize {
    let mut changed = 0;
    for (i, (got, want)) in blurred.pixels.iter().zip(expected).enumerate() {
        for k in 0..channels {
            assert!(
                (got[k] - want[k]).abs() < 2e-3 * want[k].abs().max(1.0),
                "{what}, pixel ({}, {}), channel {k}: {} against {}",
                i % SIZE.0 as usize,
                i / SIZE.0 as usize,
                got[k],
                want[k]
            );
        }
        changed += usize::from((0..channels).any(|k| (sharp[i][k] - want[k]).abs() > 1e-2));
    }
    changed
}

/// The blur ran as two passes, x then y.
fn assert_passes(report: &FrameReport, radius: u32, what: &str) {
    for axis in ["x", "y"] {
        let named = report
            .passes
            .iter()
            .filter(|p| p.step.as_deref() == Some(format!("blur {axis}").as_str()))
            .count();
        assert_eq!(named, 1, "{what}, radius {radius}: blur {axis}");
    }
}

#[test]
fn the_ao_blur_is_the_depth_aware_gaussian_of_its_input() {
    // The same node id on a new renderer: the same frame index, the same noise.
    let frame = |blur_radius: u32, combine: bool| {
        let renderer = test_renderer();
        let g = gbuffer(&renderer, eye(), None, SIZE);
        let settings = AoSettings {
            mode: AoMode::Stochastic,
            radius: 1.0,
            samples: 8,
            steps: 8,
            temporal_blend: 0.0,
            blur_radius,
            ..Default::default()
        };
        // HBAO unblurred, multiplied in by the last pass.
        let other = combine.then(|| {
            let hbao = AoSettings {
                mode: AoMode::Hbao,
                blur_radius: 0,
                ..settings
            };
            AmbientOcclusion::new(&renderer, Some(8), g.clone(), hbao, None)
        });
        let ao = AmbientOcclusion::new(
            &renderer,
            Some(7),
            g.clone(),
            settings,
            other.as_ref().map(|o| o.texture()),
        );
        let mut read = vec![ao.output.as_str(), &g.targets.depth, &g.targets.normals];
        read.extend(other.as_ref().map(|o| o.output.as_str()));
        let (report, images) =
            render_and_read(&renderer, ao.as_ref(), SIZE, &read).expect("renders");
        assert!(report.errors.is_empty(), "{:?}", report.errors);
        (report, images)
    };
    let (_, images) = frame(0, false);
    let sharp: Vec<[f32; 4]> = images[0].pixels.clone();
    let (depth, normals) = (&images[1], &images[2]);
    for (radius, combine) in [
        (1, false),
        (2, false),
        (4, false),
        (4, true),
        (6, false),
        (16, false),
    ] {
        let (report, images) = frame(radius, combine);
        assert_passes(&report, radius, "AO");
        let mut expected = reference_blur(&sharp, depth, normals, radius as i32, Values::Occlusion);
        if combine {
            for (e, other) in expected.iter_mut().zip(&images[3].pixels) {
                e[0] = (e[0] * other[0].clamp(0.0, 1.0)).clamp(0.0, 1.0);
            }
        }
        let what = format!("AO, radius {radius}, combined {combine}");
        let changed = check(&what, &images[0], &expected, &sharp, 1);
        assert!(changed > 500, "{what}: the blur changed {changed} pixels");
    }
}

#[test]
fn the_ssgi_blur_is_the_depth_aware_gaussian_of_its_input() {
    // Light in stripes of three colours, so the bounce differs from pixel to
    // pixel and the blur has something to smooth.
    let lit: Vec<[f32; 4]> = (0..SIZE.0 * SIZE.1)
        .map(|i| match (i % SIZE.0 / 3) % 3 {
            0 => [2.0, 0.2, 0.1, 1.0],
            1 => [0.1, 1.5, 0.3, 1.0],
            _ => [0.2, 0.3, 3.0, 1.0],
        })
        .collect();
    let sky = [0.0, 0.1, 0.4];
    let frame = |blur_radius: u32, ambient: bool| {
        let renderer = test_renderer();
        let g = gbuffer(&renderer, eye(), None, SIZE);
        let lit = image(&renderer, &lit, SIZE, "lit");
        let sky = constant(&renderer, sky, SIZE, "ambient");
        let settings = SsgiSettings {
            radius: 1.0,
            samples: 2,
            temporal_blend: 0.0,
            blur_radius,
            ..Default::default()
        };
        let gi = Ssgi::new(
            &renderer,
            Some(11),
            g.clone(),
            lit.texture_ref(),
            ambient.then(|| sky.texture_ref()),
            settings,
        );
        let read = [gi.output.as_str(), &g.targets.depth, &g.targets.normals];
        let (report, images) =
            render_and_read(&renderer, gi.as_ref(), SIZE, &read).expect("renders");
        assert!(report.errors.is_empty(), "{:?}", report.errors);
        (report, images)
    };
    let (_, images) = frame(0, false);
    let sharp: Vec<[f32; 4]> = images[0].pixels.clone();
    let (depth, normals) = (&images[1], &images[2]);
    for (radius, ambient) in [(1, false), (3, false), (4, true), (6, false), (9, true)] {
        let (report, images) = frame(radius, ambient);
        assert_passes(&report, radius, "SSGI");
        let mut expected = reference_blur(&sharp, depth, normals, radius as i32, Values::Light);
        if ambient {
            // The environment's light arrives along the rays that escaped.
            for (e, d) in expected.iter_mut().zip(&depth.pixels) {
                let [r, g, b] = if d[0] > 0.0 {
                    [0, 1, 2].map(|k| (e[k] + sky[k] * e[3]).min(65000.0))
                } else {
                    sky
                };
                *e = [r, g, b, 1.0];
            }
        }
        let what = format!("SSGI, radius {radius}, ambient {ambient}");
        let changed = check(
            &what,
            &images[0],
            &expected,
            &sharp,
            if ambient { 3 } else { 4 },
        );
        assert!(changed > 500, "{what}: the blur changed {changed} pixels");
    }
}
