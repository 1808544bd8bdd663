//! AO's and SSGI's depth- and normal-aware blur against the CPU: the x pass
//! over the unblurred image, then the y pass over its result, with the same
//! Gaussian and the same weights for view-distance and normal difference
//! (shaders/ssao/blur.wgsl, shaders/lighting/ssgi.wgsl's BLUR). At a
//! size that is a multiple of 8 neither way, workgroups end at the image's
//! edge. The blurs read the packed surface by default (the renderer's
//! choice, crate::packed_surface); the last test holds them to the G-buffer
//! way within the packed normal's error.

use std::sync::Arc;

use crate::occlusion_scene;

use glam::Vec3;
use spreadlight_render::FrameReport;
use spreadlight_render::camera::reverse_z;
use spreadlight_render::frame_graph::FrameGraph;
use spreadlight_render::gbuffer::GBuffer;
use spreadlight_render::lighting::{Ssgi, SsgiSettings};
use spreadlight_render::packed_surface::{
    PACKED_SURFACES, PASS_STEP, Reader, SurfaceInputs, set_inputs,
};
use spreadlight_render::readback::{ImageF32, render_and_read};
use spreadlight_render::recipe::Recipe;
use spreadlight_render::renderer::Renderer;
use spreadlight_render::renderer::test_renderer;
use spreadlight_render::resolution::Resolution;
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
    reference_blur_at(sharp, depth, normals, radius, values, 1)
}

/// The two-pass blur on the CPU over an image of one texel per `stride` x
/// `stride` block (2: the half chain's), each texel at its block's
/// top-left full pixel: its surface read there, taps `stride` full pixels
/// apart, the radius ceil(radius / stride) texels and sigma divided by
/// `stride`, so the Gaussian covers the same screen extent.
fn reference_blur_at(
    sharp: &[[f32; 4]],
    depth: &ImageF32,
    normals: &ImageF32,
    radius: i32,
    values: Values,
    stride: i32,
) -> Vec<[f32; 4]> {
    let c = camera(eye(), SIZE.0 as f32 / SIZE.1 as f32);
    let inverse = reverse_z(c.projection).inverse();
    let full_w = SIZE.0 as i32;
    let (w, h) = (
        (SIZE.0 as i32 + stride - 1) / stride,
        (SIZE.1 as i32 + stride - 1) / stride,
    );
    // A texel of the image, and the full pixel (of depth and normals) it stands at.
    let at = |x: i32, y: i32| (y * w + x) as usize;
    let full = |x: i32, y: i32| (y * stride * full_w + x * stride) as usize;
    let distance = |x: i32, y: i32| {
        let d = depth.pixels[full(x, y)][0];
        let (px, py) = (x * stride, y * stride);
        let ndc = glam::Vec2::new(
            (px as f32 + 0.5) / SIZE.0 as f32 * 2.0 - 1.0,
            1.0 - (py as f32 + 0.5) / SIZE.1 as f32 * 2.0,
        );
        let p = inverse * glam::Vec4::new(ndc.x, ndc.y, d, 1.0);
        -p.z / p.w
    };
    let normal = |x: i32, y: i32, fallback: Vec3| {
        let n = Vec3::from_slice(&normals.pixels[full(x, y)][..3]);
        if n.length_squared() > 1e-20 {
            n.normalize()
        } else {
            fallback
        }
    };
    let sigma = (radius.max(1) as f32) * 0.5 / stride as f32;
    let radius = (radius + stride - 1) / stride;
    let pass = |image: &[[f32; 4]], axis: (i32, i32)| -> Vec<[f32; 4]> {
        let mut out = image.to_vec();
        for y in 0..h {
            for x in 0..w {
                if depth.pixels[full(x, y)][0] <= 0.0 {
                    continue;
                }
                let (z0, n0) = (distance(x, y), normal(x, y, Vec3::Z));
                let (mut sum, mut weights) = ([0.0f32; 4], 0.0f32);
                for o in -radius..=radius {
                    let (qx, qy) = (x + axis.0 * o, y + axis.1 * o);
                    if qx < 0
                        || qy < 0
                        || qx >= w
                        || qy >= h
                        || depth.pixels[full(qx, qy)][0] <= 0.0
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
    assert_eq!(blurred.pixels.len(), expected.len(), "{what}: size");
    let width = blurred.width as usize;
    let mut changed = 0;
    for (i, (got, want)) in blurred.pixels.iter().zip(expected).enumerate() {
        for k in 0..channels {
            assert!(
                (got[k] - want[k]).abs() < 2e-3 * want[k].abs().max(1.0),
                "{what}, pixel ({}, {}), channel {k}: {} against {}",
                i % width,
                i / width,
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

/// The AO node of `settings` (node 7) and, with `combine`, an unblurred
/// full-resolution HBAO (node 8) that its last pass multiplies in.
fn ao_node(
    renderer: &Renderer,
    g: &Arc<GBuffer>,
    settings: AoSettings,
    combine: bool,
) -> (Arc<AmbientOcclusion>, Option<Arc<AmbientOcclusion>>) {
    let other = combine.then(|| {
        let hbao = AoSettings {
            mode: AoMode::Hbao,
            blur_radius: 0,
            resolution: Resolution::Full,
            ..settings
        };
        AmbientOcclusion::new(renderer, Some(8), g.clone(), hbao, None)
    });
    let ao = AmbientOcclusion::new(
        renderer,
        Some(7),
        g.clone(),
        settings,
        other.as_ref().map(|o| o.texture()),
    );
    (ao, other)
}

/// The plain estimator's settings the blur tests compare against the CPU:
/// one frame (no temporal blend), blurred at `blur_radius`.
fn one_frame_ao(blur_radius: u32) -> AoSettings {
    AoSettings {
        mode: AoMode::Stochastic,
        radius: 1.0,
        samples: 8,
        steps: 8,
        temporal_blend: 0.0,
        blur_radius,
        ..Default::default()
    }
}

#[test]
fn the_ao_blur_is_the_depth_aware_gaussian_of_its_input() {
    // The same node id on a new renderer: the same frame index, the same noise.
    let frame = |blur_radius: u32, combine: bool| {
        let renderer = test_renderer();
        let g = gbuffer(&renderer, eye(), None, SIZE);
        let settings = one_frame_ao(blur_radius);
        let (ao, other) = ao_node(&renderer, &g, settings, combine);
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

/// Light in stripes of three colours, so the bounce differs from pixel to
/// pixel and the blur has something to smooth, and the sky's colour.
fn striped_light() -> (Vec<[f32; 4]>, [f32; 3]) {
    let lit = (0..SIZE.0 * SIZE.1)
        .map(|i| match (i % SIZE.0 / 3) % 3 {
            0 => [2.0, 0.2, 0.1, 1.0],
            1 => [0.1, 1.5, 0.3, 1.0],
            _ => [0.2, 0.3, 3.0, 1.0],
        })
        .collect();
    (lit, [0.0, 0.1, 0.4])
}

#[test]
fn the_ssgi_blur_is_the_depth_aware_gaussian_of_its_input() {
    let (lit, sky) = striped_light();
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

/// Two effects declared in one frame.
struct Both(std::sync::Arc<AmbientOcclusion>, std::sync::Arc<Ssgi>);

impl Recipe for Both {
    fn declare<'a>(&'a self, renderer: &'a Renderer, fg: &mut FrameGraph<'a>) {
        self.0.declare(renderer, fg);
        self.1.declare(renderer, fg);
    }
}

/// The blurs over the packed surface (view distance and an octahedron
/// normal in one texel) against the G-buffer way (depth and normals per
/// tap) on the same input: the same pixels to within the normal's 16-bit
/// encoding (stated in docs/indirect-light.md: at most one step of a half
/// float per pass that writes them), one packed surface for every blur of a G-buffer, and
/// none in the G-buffer way.
#[test]
fn the_packed_surface_blurs_as_the_gbuffer_does() {
    let lit: Vec<[f32; 4]> = (0..SIZE.0 * SIZE.1)
        .map(|i| match (i % SIZE.0 / 3) % 3 {
            0 => [2.0, 0.2, 0.1, 1.0],
            1 => [0.1, 1.5, 0.3, 1.0],
            _ => [0.2, 0.3, 3.0, 1.0],
        })
        .collect();
    let frame = |inputs: SurfaceInputs| {
        let renderer = test_renderer();
        set_inputs(&renderer, Reader::Blurs, inputs);
        // The rays the G-buffer way in both frames: the surface is the blurs' alone.
        set_inputs(&renderer, Reader::Rays, SurfaceInputs::GBuffer);
        let g = gbuffer(&renderer, eye(), None, SIZE);
        let settings = one_frame_ao(4);
        // HBAO blurred too, multiplied in: two AO blurs on one G-buffer.
        let hbao = AoSettings {
            mode: AoMode::Hbao,
            blur_radius: 2,
            ..settings
        };
        let other = AmbientOcclusion::new(&renderer, Some(8), g.clone(), hbao, None);
        let ao = AmbientOcclusion::new(
            &renderer,
            Some(7),
            g.clone(),
            settings,
            Some(other.texture()),
        );
        let lit = image(&renderer, &lit, SIZE, "lit");
        let gi = Ssgi::new(
            &renderer,
            Some(11),
            g.clone(),
            lit.texture_ref(),
            None,
            SsgiSettings {
                radius: 1.0,
                samples: 2,
                temporal_blend: 0.0,
                blur_radius: 5,
                ..Default::default()
            },
        );
        let read = [ao.output.as_str(), gi.output.as_str()];
        // One recipe declares both: the AO, then the SSGI over the same G-buffer.
        let both = Both(ao.clone(), gi.clone());
        let (report, images) = render_and_read(&renderer, &both, SIZE, &read).expect("renders");
        assert!(report.errors.is_empty(), "{:?}", report.errors);
        (report, images)
    };
    let (packed_report, packed) = frame(SurfaceInputs::Packed);
    let (gbuffer_report, gbuffer_way) = frame(SurfaceInputs::GBuffer);
    assert_eq!(packed_report.counter(PACKED_SURFACES), 1);
    assert_eq!(packed_report.passes_of("MRE", Some(PASS_STEP)).count(), 1);
    assert_eq!(gbuffer_report.counter(PACKED_SURFACES), 0);
    assert_eq!(gbuffer_report.passes_of("MRE", Some(PASS_STEP)).count(), 0);
    // The outputs are half floats: a gap in the f32 sums under the normal's
    // encoding shows, where it shows at all, as one step of a half float per
    // pass that writes them.
    let half_step = |v: f32| {
        let v = v.abs();
        if v < 6.1e-5 {
            2f32.powi(-24)
        } else {
            2f32.powi(v.log2().floor() as i32 - 10)
        }
    };
    let mut steps = [0.0f32; 2];
    let mut differ = 0;
    for (k, (a, b)) in packed.iter().zip(&gbuffer_way).enumerate() {
        for (p, q) in a.pixels.iter().zip(&b.pixels) {
            for c in 0..4 {
                let gap = (p[c] - q[c]).abs() / half_step(q[c]);
                steps[k] = steps[k].max(gap);
                differ += usize::from(gap > 0.0);
            }
        }
    }
    let worst = steps;
    assert!(
        worst[0] <= 1.0,
        "AO: packed against the G-buffer way, {} half-float steps",
        worst[0]
    );
    // SSGI's x pass writes half floats too: a step there, and one in y.
    assert!(
        worst[1] <= 2.0,
        "SSGI: packed against the G-buffer way, {} half-float steps",
        worst[1]
    );
    eprintln!(
        "packed surface: at most {} (AO) and {} (SSGI) half-float steps off, {differ} channels of {} differ",
        worst[0],
        worst[1],
        2 * 4 * SIZE.0 * SIZE.1
    );
}

/// Pass steps of a report, for messages.
fn steps(report: &FrameReport) -> Vec<String> {
    report.passes.iter().map(|p| p.name.clone()).collect()
}

/// The half chain ran its blur at half size (no full-size blur pass) and
/// upsampled once.
fn assert_half_passes(report: &FrameReport, what: &str) {
    for step in ["blur x (half)", "blur y (half)", "upsample"] {
        let named = report
            .passes
            .iter()
            .filter(|p| p.step.as_deref() == Some(step))
            .count();
        assert_eq!(named, 1, "{what}: {step} in {:?}", steps(report));
    }
    for step in ["blur x", "blur y"] {
        assert!(
            !report
                .passes
                .iter()
                .any(|p| p.step.as_deref() == Some(step)),
            "{what}: no full-size {step} in {:?}",
            steps(report)
        );
    }
}

/// Every full pixel on an even row and column is a half texel: the
/// upsample's bilinear weight there is the texel's alone, so the output is
/// `expect(texel, pixel)` up to the RGBA16F output's rounding.
fn check_even_pixels(
    what: &str,
    output: &ImageF32,
    half: &ImageF32,
    channels: usize,
    expect: impl Fn([f32; 4], usize) -> [f32; 4],
) {
    for ty in 0..half.height {
        for tx in 0..half.width {
            let (x, y) = (tx * 2, ty * 2);
            let i = (y * SIZE.0 + x) as usize;
            let want = expect(half.pixel(tx, ty), i);
            let got = output.pixel(x, y);
            for k in 0..channels {
                assert!(
                    (got[k] - want[k]).abs() < 2e-3 * want[k].abs().max(1.0),
                    "{what}, pixel ({x}, {y}), channel {k}: {} against {}",
                    got[k],
                    want[k]
                );
            }
        }
    }
}

/// AO's half chain (Resolution::Half, no temporal blend): both blur passes
/// run on the half-size estimate, each half texel reading the G-buffer at
/// its own full pixel with taps two full pixels apart and the radius and
/// sigma halved (the CPU's `reference_blur_at` with stride 2), and the
/// upsample writes it (times the combined AO) to the full-size output,
/// exactly at the pixels that are half texels. Depth edges (the balls) and
/// the empty background (the sky, visibility 1) are in the frame; nothing
/// is NaN or infinite.
#[test]
fn the_half_chain_ao_blur_is_the_gaussian_at_half_size() {
    for (radius, combine) in [(1u32, false), (4, false), (4, true), (7, false)] {
        let renderer = test_renderer();
        let g = gbuffer(&renderer, eye(), None, SIZE);
        let settings = AoSettings {
            resolution: Resolution::Half,
            ..one_frame_ao(radius)
        };
        let (ao, other) = ao_node(&renderer, &g, settings, combine);
        let [raw, blurred] = ao.half_targets();
        let mut read = vec![
            raw.as_str(),
            blurred.as_str(),
            ao.output.as_str(),
            &g.targets.depth,
            &g.targets.normals,
        ];
        read.extend(other.as_ref().map(|o| o.output.as_str()));
        let (report, images) =
            render_and_read(&renderer, ao.as_ref(), SIZE, &read).expect("renders");
        assert!(report.errors.is_empty(), "{:?}", report.errors);
        let what = format!("AO half chain, radius {radius}, combined {combine}");
        assert_half_passes(&report, &what);
        let (raw, blurred, output) = (&images[0], &images[1], &images[2]);
        let (depth, normals) = (&images[3], &images[4]);
        assert_eq!(
            (raw.width, raw.height),
            (SIZE.0.div_ceil(2), SIZE.1.div_ceil(2))
        );
        for image in [raw, blurred, output] {
            assert!(image.all_finite(), "{what}");
        }
        let expected = reference_blur_at(
            &raw.pixels,
            depth,
            normals,
            radius as i32,
            Values::Occlusion,
            2,
        );
        let changed = check(&what, blurred, &expected, &raw.pixels, 1);
        // Radius 1 is sigma 0.5 pixel: at taps two pixels apart its weight
        // is e^-8, nothing to see; from 4 on the blur shows.
        assert!(
            radius < 4 || changed > 150,
            "{what}: the blur changed {changed} texels"
        );
        let sky = depth.pixels.iter().filter(|d| d[0] <= 0.0).count();
        assert!(sky > 100, "{what}: the sky is in the frame ({sky} pixels)");
        check_even_pixels(&what, output, blurred, 4, |t, i| {
            let other = images
                .get(5)
                .map_or(1.0, |o| o.pixels[i][0].clamp(0.0, 1.0));
            let v = t[0].clamp(0.0, 1.0) * other;
            // The sky: nothing occludes it (visibility 1, times the other AO).
            let v = if depth.pixels[i][0] <= 0.0 { other } else { v };
            [v, v, v, 1.0]
        });
        assert!(
            output.pixels.iter().all(|p| (0.0..=1.0).contains(&p[0])),
            "{what}: visibility in 0..1"
        );
    }
}

/// SSGI's half chain: the same blur on its four channels at half size,
/// then the upsample adds the ambient times the escaped share (alpha 1),
/// the sky taking the ambient alone.
#[test]
fn the_half_chain_ssgi_blur_is_the_gaussian_at_half_size() {
    let (lit, sky) = striped_light();
    for (radius, ambient) in [(1u32, false), (4, true), (9, true)] {
        let renderer = test_renderer();
        let g = gbuffer(&renderer, eye(), None, SIZE);
        let lit = image(&renderer, &lit, SIZE, "lit");
        let sky_texture = constant(&renderer, sky, SIZE, "ambient");
        let settings = SsgiSettings {
            radius: 1.0,
            samples: 2,
            temporal_blend: 0.0,
            blur_radius: radius,
            resolution: Resolution::Half,
            ..Default::default()
        };
        let gi = Ssgi::new(
            &renderer,
            Some(11),
            g.clone(),
            lit.texture_ref(),
            ambient.then(|| sky_texture.texture_ref()),
            settings,
        );
        let [raw, blurred] = gi.half_targets();
        let read = [
            raw.as_str(),
            blurred.as_str(),
            gi.output.as_str(),
            &g.targets.depth,
            &g.targets.normals,
        ];
        let (report, images) =
            render_and_read(&renderer, gi.as_ref(), SIZE, &read).expect("renders");
        assert!(report.errors.is_empty(), "{:?}", report.errors);
        let what = format!("SSGI half chain, radius {radius}, ambient {ambient}");
        assert_half_passes(&report, &what);
        let (raw, blurred, output) = (&images[0], &images[1], &images[2]);
        let (depth, normals) = (&images[3], &images[4]);
        for image in [raw, blurred, output] {
            assert!(image.all_finite(), "{what}");
        }
        let expected =
            reference_blur_at(&raw.pixels, depth, normals, radius as i32, Values::Light, 2);
        let changed = check(&what, blurred, &expected, &raw.pixels, 4);
        // Radius 1 is sigma 0.5 pixel: at taps two pixels apart its weight
        // is e^-8, nothing to see; from 4 on the blur shows.
        assert!(
            radius < 4 || changed > 150,
            "{what}: the blur changed {changed} texels"
        );
        check_even_pixels(&what, output, blurred, 4, |t, i| {
            if !ambient {
                return t;
            }
            if depth.pixels[i][0] <= 0.0 {
                [sky[0], sky[1], sky[2], 1.0]
            } else {
                let [r, g, b] = [0, 1, 2].map(|k| (t[k] + sky[k] * t[3]).min(65000.0));
                [r, g, b, 1.0]
            }
        });
    }
}
