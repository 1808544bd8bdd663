//! Screen-space ambient occlusion (render::occlusion) and SSGI, which
//! marches the same rays: every AO estimator
//! darkens a ball's contact with the floor and leaves open floor and sky
//! alone; the stochastic one agrees with ray-cast AO (spreadlight_reference::ssao);
//! temporal accumulation lowers the error of few samples; history survives
//! neither a NaN, a reset, a stale camera nor a resize; hard settings
//! (radius 0 and huge, sky, back-facing normals) stay finite. SSGI under
//! a uniformly lit scene gathers that light exactly where ray-cast AO says
//! rays are blocked.

use crate::occlusion_scene;

use std::sync::Arc;

use glam::Vec3;
use spreadlight_reference::shadows::Sphere;
use spreadlight_reference::ssao::{Occluders, visibility_image};
use spreadlight_render::camera::reverse_z;
use spreadlight_render::gbuffer::GBuffer;
use spreadlight_render::lighting::{SSGI_GATHER_TEMPORAL, Ssgi, SsgiSettings, Ssss, SsssQuality};
use spreadlight_render::material::{Feature, Material, MaterialWorld};
use spreadlight_render::readback::{ImageF32, render_and_read};
use spreadlight_render::renderer::test_renderer;
use spreadlight_render::resolution::Resolution;
use spreadlight_render::ssao::{AmbientOcclusion, AoMode, AoSettings, ESTIMATE_TEMPORAL};
use spreadlight_render::{FrameReport, Recipe, Renderer};

use occlusion_scene::{BALL, FLOOR, camera, constant, eye, gbuffer};

const SIZE: (u32, u32) = (96, 64);
fn ao(
    renderer: &Renderer,
    g: Arc<GBuffer>,
    settings: AoSettings,
    size: (u32, u32),
) -> (FrameReport, ImageF32, ImageF32) {
    let ao = AmbientOcclusion::new(renderer, Some(7), g.clone(), settings, None);
    let (report, images) =
        render_and_read(renderer, ao.as_ref(), size, &[&ao.output, &g.targets.depth])
            .expect("renders");
    assert!(report.errors.is_empty(), "{:?}", report.errors);
    let mut images = images.into_iter();
    (
        report,
        images.next().expect("ao"),
        images.next().expect("depth"),
    )
}

fn single_frame(mode: AoMode, samples: u32) -> AoSettings {
    AoSettings {
        mode,
        radius: 1.0,
        samples,
        steps: 8,
        temporal_blend: 0.0,
        blur_radius: 0,
        ..Default::default()
    }
}

/// The pixel a world point lands on.
fn pixel_of(p: Vec3, size: (u32, u32)) -> (u32, u32) {
    let c = camera(eye(), size.0 as f32 / size.1 as f32);
    let clip = reverse_z(c.projection) * c.view * p.extend(1.0);
    let ndc = clip.truncate() / clip.w;
    (
        ((ndc.x * 0.5 + 0.5) * size.0 as f32) as u32,
        ((0.5 - ndc.y * 0.5) * size.1 as f32) as u32,
    )
}

/// Ray-cast AO of radius 1 under every pixel with geometry (None: sky).
fn reference(depth: &ImageF32, size: (u32, u32), rays: u32) -> Vec<Option<f32>> {
    let c = camera(eye(), size.0 as f32 / size.1 as f32);
    let occluders = Occluders {
        spheres: vec![Sphere {
            center: BALL.0,
            radius: BALL.1,
        }],
        floor: Some(FLOOR / 2.0),
    };
    let depths: Vec<f32> = depth.pixels.iter().map(|p| p[0]).collect();
    let inverse = (reverse_z(c.projection) * c.view).inverse();
    visibility_image(&depths, size, inverse, &occluders, 1.0, rays)
}

/// Fill a persistent RGBA16F history with half-float NaN and infinity.
fn poison(renderer: &Renderer, name: &str) {
    let history = renderer
        .persistent_texture(name)
        .expect("the history exists after a frame");
    let size = history.size();
    let texels: Vec<u16> = (0..size.width * size.height * 4)
        .map(|i| if i % 8 < 4 { 0x7e00 } else { 0x7c00 })
        .collect();
    renderer.gpu.queue.write_texture(
        history.as_image_copy(),
        bytemuck::cast_slice(&texels),
        wgpu::TexelCopyBufferLayout {
            offset: 0,
            bytes_per_row: Some(size.width * 8),
            rows_per_image: None,
        },
        size,
    );
}

fn rmse(image: &ImageF32, truth: &[Option<f32>]) -> f32 {
    let (sum, n) = truth
        .iter()
        .zip(&image.pixels)
        .filter_map(|(t, p)| t.map(|t| (p[0] - t).powi(2)))
        .fold((0.0, 0), |(s, n), e| (s + e, n + 1));
    (sum / n as f32).sqrt()
}

#[test]
fn every_mode_darkens_the_contact_and_leaves_open_floor_and_sky_alone() {
    let renderer = test_renderer();
    let contact = pixel_of(Vec3::new(0.0, 0.05, 1.05), SIZE);
    let open = pixel_of(Vec3::new(3.5, 0.0, 1.0), SIZE);
    for mode in [AoMode::Stochastic, AoMode::Sao, AoMode::Hbao] {
        let g = gbuffer(&renderer, eye(), None, SIZE);
        let (_, image, depth) = ao(&renderer, g, single_frame(mode, 16), SIZE);
        assert!(image.all_finite(), "{mode:?}");
        let at = |(x, y): (u32, u32)| image.pixel(x, y)[0];
        assert!(at(contact) < 0.8, "{mode:?}: contact {}", at(contact));
        assert!(at(open) > 0.9, "{mode:?}: open floor {}", at(open));
        for (p, d) in image.pixels.iter().zip(&depth.pixels) {
            assert!((0.0..=1.0).contains(&p[0]), "{mode:?}: {p:?}");
            if d[0] <= 0.0 {
                assert_eq!(p[0], 1.0, "{mode:?}: the sky is never occluded");
            }
        }
    }
}

#[test]
fn stochastic_ao_agrees_with_ray_cast_ao() {
    let renderer = test_renderer();
    let g = gbuffer(&renderer, eye(), None, SIZE);
    let (_, image, depth) = ao(&renderer, g, single_frame(AoMode::Stochastic, 64), SIZE);
    let truth = reference(&depth, SIZE, 256);
    let e = rmse(&image, &truth);
    // What remains is what the screen cannot see (the ball's hidden side,
    // thickness guesses): about 0.04 on lavapipe; the bound leaves room for drivers.
    assert!(e < 0.1, "RMSE against ray-cast AO: {e}");
    let white = rmse(
        &ImageF32 {
            pixels: vec![[1.0; 4]; image.pixels.len()],
            ..image.clone()
        },
        &truth,
    );
    assert!(e < white * 0.5, "better than no AO at all: {e} vs {white}");
}

/// `frames` frames of one node's AO under a still camera; the last frame's image and report.
fn still_frames(
    renderer: &Renderer,
    settings: AoSettings,
    frames: usize,
) -> (FrameReport, ImageF32, ImageF32) {
    let c = camera(eye(), SIZE.0 as f32 / SIZE.1 as f32);
    let mut last = None;
    for _ in 0..frames {
        let g = gbuffer(renderer, eye(), Some(c.view_projection()), SIZE);
        last = Some(ao(renderer, g, settings, SIZE));
    }
    last.expect("at least one frame")
}

#[test]
fn temporal_accumulation_beats_one_frame_of_few_samples() {
    let renderer = test_renderer();
    let few = AoSettings {
        samples: 2,
        ..single_frame(AoMode::Stochastic, 2)
    };
    let (_, one, depth) = still_frames(&renderer, few, 1);
    let truth = reference(&depth, SIZE, 256);
    let renderer = test_renderer();
    let (report, many, _) = still_frames(
        &renderer,
        AoSettings {
            temporal_blend: 0.9,
            ..few
        },
        24,
    );
    assert!(many.all_finite());
    assert_eq!(
        report.counter("AO history reset"),
        0,
        "a still camera keeps its history"
    );
    let (e1, e24) = (rmse(&one, &truth), rmse(&many, &truth));
    assert!(
        e24 < e1 * 0.7,
        "24 accumulated frames ({e24}) against one ({e1})"
    );
}

/// The estimate blends its history in its own pass (no raw target, no
/// temporal pass), at full resolution and at half (the half chain: into a
/// half-size history, before the half-size blur and the upsample). Either
/// way a fresh history keeps the estimate: the first frame is the image
/// without accumulation, to the history's half-float precision.
#[test]
fn ao_accumulates_in_the_estimate_at_full_resolution_and_at_half_size_at_half() {
    for resolution in [Resolution::Full, Resolution::Half] {
        let settings = |temporal_blend| AoSettings {
            temporal_blend,
            resolution,
            blur_radius: 2,
            ..single_frame(AoMode::Hbao, 8)
        };
        // A renderer each: the node's frame count (its noise) starts alike.
        let run = |temporal_blend| {
            let renderer = test_renderer();
            let g = gbuffer(&renderer, eye(), None, SIZE);
            ao(&renderer, g, settings(temporal_blend), SIZE)
        };
        let (accumulated, image, _) = run(0.9);
        let (alone, reference, _) = run(0.0);
        let temporal_passes = accumulated
            .passes
            .iter()
            .filter(|p| p.step.as_deref().is_some_and(|s| s.starts_with("temporal")))
            .count();
        assert_eq!(accumulated.counter(ESTIMATE_TEMPORAL), 1, "{resolution:?}");
        assert_eq!(temporal_passes, 0, "{resolution:?}");
        assert_eq!(alone.counter(ESTIMATE_TEMPORAL), 0);
        assert!(image.all_finite());
        let worst = image
            .pixels
            .iter()
            .zip(&reference.pixels)
            .map(|(a, b)| (a[0] - b[0]).abs())
            .fold(0.0f32, f32::max);
        assert!(worst <= 1e-3, "{resolution:?}: {worst}");
    }
}

#[test]
fn a_nan_in_the_history_does_not_spread() {
    let renderer = test_renderer();
    let settings = AoSettings {
        temporal_blend: 0.9,
        blur_radius: 2,
        ..single_frame(AoMode::Stochastic, 4)
    };
    still_frames(&renderer, settings, 2);
    let g = gbuffer(&renderer, eye(), None, SIZE);
    let name = AmbientOcclusion::new(&renderer, Some(7), g, settings, None).history_name();
    // Half-float NaN (0x7e00) and infinity (0x7c00) over the whole history.
    poison(&renderer, &name);
    for _ in 0..3 {
        let (_, image, _) = still_frames(&renderer, settings, 1);
        assert!(image.all_finite(), "NaN history reached the output");
        assert!(image.pixels.iter().all(|p| (0.0..=1.0).contains(&p[0])));
    }
}

#[test]
fn reset_stale_camera_and_resize_drop_the_history() {
    let renderer = test_renderer();
    let settings = AoSettings {
        temporal_blend: 0.9,
        ..single_frame(AoMode::Hbao, 4)
    };
    let (first, ..) = still_frames(&renderer, settings, 1);
    assert_eq!(
        first.counter("AO history reset"),
        1,
        "a fresh history is no history"
    );
    let (kept, ..) = still_frames(&renderer, settings, 1);
    assert_eq!(kept.counter("AO history reset"), 0);
    let (reset, image, _) = still_frames(
        &renderer,
        AoSettings {
            reset: true,
            ..settings
        },
        1,
    );
    assert_eq!(reset.counter("AO history reset"), 1, "Reset");
    assert!(image.all_finite());
    // A camera cut: the G-buffer's previous camera is not the one last frame saw.
    let elsewhere = Vec3::new(4.0, 1.0, -3.0);
    let g = gbuffer(
        &renderer,
        elsewhere,
        Some(camera(elsewhere, 1.5).view_projection()),
        SIZE,
    );
    let (cut, image, _) = ao(&renderer, g, settings, SIZE);
    assert_eq!(cut.counter("AO history reset"), 1, "camera cut");
    assert!(image.all_finite());
    // A resize makes a new history.
    let small = (48, 32);
    let g = gbuffer(
        &renderer,
        elsewhere,
        Some(camera(elsewhere, 1.5).view_projection()),
        small,
    );
    let (resized, image, _) = ao(&renderer, g, settings, small);
    assert_eq!(resized.counter("AO history reset"), 1, "resize");
    assert!(image.all_finite() && image.width == 48);
}

#[test]
fn radius_zero_and_huge_stay_finite_in_every_mode() {
    let renderer = test_renderer();
    for mode in [AoMode::Stochastic, AoMode::Sao, AoMode::Hbao] {
        for radius in [0.0, 1e5, f32::NAN, -3.0] {
            let g = gbuffer(&renderer, eye(), None, SIZE);
            let settings = AoSettings {
                radius,
                blur_radius: 3,
                ..single_frame(mode, 8)
            };
            let (report, image, _) = ao(&renderer, g, settings, SIZE);
            assert!(image.all_finite(), "{mode:?} radius {radius}");
            if radius.is_nan() || radius <= 0.0 {
                // Nothing to occlude: the raw pass writes 1, the last pass copies it.
                assert_eq!(report.counter("AO off: radius 0"), 1);
                let passes: Vec<&str> = report
                    .passes
                    .iter()
                    .map(|p| p.name.as_str())
                    .filter(|n| n.contains(" #7:"))
                    .collect();
                assert_eq!(passes.len(), 2, "{passes:?}");
            }
            assert!(
                image.pixels.iter().all(|p| (0.0..=1.0).contains(&p[0])),
                "{mode:?} radius {radius}"
            );
            if radius == 0.0 || radius.is_nan() || radius < 0.0 {
                assert!(
                    image.pixels.iter().all(|p| p[0] == 1.0),
                    "{mode:?}: radius {radius} occludes nothing"
                );
            }
        }
    }
}

#[test]
fn the_blur_keeps_the_silhouette_and_combine_multiplies() {
    let renderer = test_renderer();
    let g = gbuffer(&renderer, eye(), None, SIZE);
    let (_, sharp, depth) = ao(
        &renderer,
        g.clone(),
        single_frame(AoMode::Stochastic, 8),
        SIZE,
    );
    let blurred_settings = AoSettings {
        blur_radius: 6,
        ..single_frame(AoMode::Stochastic, 8)
    };
    let (_, blurred, _) = ao(&renderer, g.clone(), blurred_settings, SIZE);
    // Blurring lowers the pixel-to-pixel noise on the floor...
    let roughness = |img: &ImageF32| {
        let mut sum = 0.0;
        for y in 0..SIZE.1 {
            for x in 1..SIZE.0 {
                let (a, b) = (img.pixel(x - 1, y)[0], img.pixel(x, y)[0]);
                if depth.pixel(x - 1, y)[0] > 0.0 && depth.pixel(x, y)[0] > 0.0 {
                    sum += (a - b).abs();
                }
            }
        }
        sum
    };
    assert!(roughness(&blurred) < roughness(&sharp) * 0.8);
    // ...and never pulls occlusion onto the sky.
    for (p, d) in blurred.pixels.iter().zip(&depth.pixels) {
        if d[0] <= 0.0 {
            assert_eq!(p[0], 1.0);
        }
    }
    // HBAO with the wide-range AO multiplied in is darker than either.
    let wide = AmbientOcclusion::new(
        &renderer,
        Some(8),
        g.clone(),
        single_frame(AoMode::Stochastic, 8),
        None,
    );
    let local = AmbientOcclusion::new(
        &renderer,
        Some(9),
        g.clone(),
        single_frame(AoMode::Hbao, 8),
        Some(wide.texture()),
    );
    let (report, images) = render_and_read(
        &renderer,
        local.as_ref(),
        SIZE,
        &[&local.output, &wide.output],
    )
    .expect("renders");
    assert!(report.errors.is_empty(), "{:?}", report.errors);
    let (both, wide_only) = (&images[0], &images[1]);
    // The same node id on a new renderer: the same frame index, the same noise.
    let renderer = test_renderer();
    let g = gbuffer(&renderer, eye(), None, SIZE);
    let alone = AmbientOcclusion::new(&renderer, Some(9), g, single_frame(AoMode::Hbao, 8), None);
    let (_, images) =
        render_and_read(&renderer, alone.as_ref(), SIZE, &[&alone.output]).expect("renders");
    let hbao_only = &images[0];
    for i in 0..both.pixels.len() {
        let expected = wide_only.pixels[i][0] * hbao_only.pixels[i][0];
        assert!(
            (both.pixels[i][0] - expected).abs() < 0.01,
            "pixel {i}: {} vs {expected}",
            both.pixels[i][0]
        );
    }
}

#[test]
fn back_facing_normals_and_depth_edges_stay_finite() {
    // Seen from inside the ball: every normal faces away from the eye.
    let renderer = test_renderer();
    let inside = Vec3::new(0.0, 1.0, 0.3);
    for mode in [AoMode::Stochastic, AoMode::Sao, AoMode::Hbao] {
        let g = gbuffer(&renderer, inside, None, SIZE);
        let settings = AoSettings {
            temporal_blend: 0.5,
            blur_radius: 4,
            ..single_frame(mode, 8)
        };
        let (_, image, _) = ao(&renderer, g, settings, SIZE);
        assert!(image.all_finite(), "{mode:?}");
    }
}

fn ssgi(
    renderer: &Renderer,
    settings: SsgiSettings,
    ambient: bool,
    frames: usize,
) -> (FrameReport, ImageF32, ImageF32) {
    ssgi_lit(renderer, settings, ambient, frames, [1.0, 0.5, 0.0])
}

/// SSGI over a lit image of constant `lit` colour, `frames` frames of one node.
fn ssgi_lit(
    renderer: &Renderer,
    settings: SsgiSettings,
    ambient: bool,
    frames: usize,
    lit: [f32; 3],
) -> (FrameReport, ImageF32, ImageF32) {
    let c = camera(eye(), SIZE.0 as f32 / SIZE.1 as f32);
    let lit = constant(renderer, lit, SIZE, "lit");
    let sky = constant(renderer, [0.0, 0.0, 0.25], SIZE, "ambient");
    let mut last = None;
    for _ in 0..frames {
        let g = gbuffer(renderer, eye(), Some(c.view_projection()), SIZE);
        let gi = Ssgi::new(
            renderer,
            Some(11),
            g.clone(),
            lit.texture_ref(),
            ambient.then(|| sky.texture_ref()),
            settings,
        );
        let (report, images) =
            render_and_read(renderer, gi.as_ref(), SIZE, &[&gi.output, &g.targets.depth])
                .expect("renders");
        assert!(report.errors.is_empty(), "{:?}", report.errors);
        let mut images = images.into_iter();
        last = Some((
            report,
            images.next().expect("gi"),
            images.next().expect("depth"),
        ));
    }
    last.expect("a frame")
}

#[test]
fn ssgi_gathers_light_where_ray_cast_rays_are_blocked() {
    let renderer = test_renderer();
    let settings = SsgiSettings {
        radius: 1.0,
        samples: 32,
        steps: 8,
        temporal_blend: 0.0,
        blur_radius: 0,
        ..Default::default()
    };
    let (_, gi, depth) = ssgi(&renderer, settings, false, 1);
    assert!(gi.all_finite());
    // The bounce carries the lit colour: orange, no blue.
    assert!(
        gi.pixels
            .iter()
            .all(|p| p[2] == 0.0 && (p[1] - 0.5 * p[0]).abs() < 1e-2)
    );
    let truth = reference(&depth, SIZE, 256);
    let blocked: Vec<Option<f32>> = truth.iter().map(|t| t.map(|v| 1.0 - v)).collect();
    let e = rmse(&gi, &blocked);
    assert!(
        e < 0.1,
        "RMSE of the gathered share against ray-cast blocked rays: {e}"
    );
    // With an ambient texture (here: blue), it comes in along the rays that
    // escape: the share the bounce leaves in alpha, which is ray-cast AO's
    // visibility. A new renderer: the same frame, the same noise.
    let renderer = test_renderer();
    let (_, with_ambient, _) = ssgi(&renderer, settings, true, 1);
    for (a, b) in with_ambient.pixels.iter().zip(&gi.pixels) {
        assert!(
            (a[2] - (b[2] + 0.25 * b[3])).abs() < 1e-3 && (a[0] - b[0]).abs() < 1e-3,
            "{a:?} {b:?}"
        );
    }
    let visible = ImageF32 {
        pixels: with_ambient
            .pixels
            .iter()
            .map(|p| [p[2] / 0.25; 4])
            .collect(),
        ..with_ambient.clone()
    };
    let e = rmse(&visible, &truth);
    assert!(
        e < 0.1,
        "RMSE of the environment's share against ray-cast AO: {e}"
    );
}

#[test]
fn ssgi_accumulates_and_survives_a_nan_history_and_hard_settings() {
    let renderer = test_renderer();
    let settings = SsgiSettings {
        radius: 1.0,
        samples: 2,
        steps: 6,
        temporal_blend: 0.9,
        blur_radius: 2,
        ..Default::default()
    };
    let (first, ..) = ssgi(&renderer, settings, true, 1);
    assert_eq!(first.counter("SSGI history reset"), 1);
    let (later, image, _) = ssgi(&renderer, settings, true, 3);
    assert_eq!(later.counter("SSGI history reset"), 0);
    assert!(image.all_finite());
    let g = gbuffer(&renderer, eye(), None, SIZE);
    let lit = constant(&renderer, [1.0; 3], SIZE, "lit");
    let name = Ssgi::new(&renderer, Some(11), g, lit.texture_ref(), None, settings).history_name();
    poison(&renderer, &name);
    let (_, image, _) = ssgi(&renderer, settings, true, 2);
    assert!(image.all_finite(), "a NaN history spread");
    for radius in [0.0, 1e5] {
        let (_, image, _) = ssgi(&renderer, SsgiSettings { radius, ..settings }, false, 1);
        assert!(image.all_finite(), "radius {radius}");
        assert!(image.pixels.iter().all(|p| p[0] >= 0.0 && p[0] <= 65000.0));
    }
}

/// A texture lit 1 on the left half of the screen and 0 on the right (the SSS term to scatter).
fn half_lit(
    renderer: &Renderer,
    value: f32,
) -> Arc<spreadlight_render::static_texture::StaticTexture> {
    let pixels: Vec<[f32; 4]> = (0..SIZE.0 * SIZE.1)
        .map(|i| {
            if i % SIZE.0 < SIZE.0 / 2 {
                [value, value, value, 1.0]
            } else {
                [0.0, 0.0, 0.0, 1.0]
            }
        })
        .collect();
    spreadlight_render::static_texture::StaticTexture::from_rgba32f(
        &renderer.gpu,
        SIZE.0,
        SIZE.1,
        &pixels,
        "sss",
    )
}

fn scatter(
    renderer: &Renderer,
    materials: Arc<MaterialWorld>,
    value: f32,
) -> (FrameReport, ImageF32, ImageF32) {
    let g = gbuffer(renderer, eye(), None, SIZE);
    let sss = half_lit(renderer, value);
    let out = Ssss::texture(
        renderer,
        Some(3),
        g.clone(),
        sss.texture_ref(),
        Some(materials),
        0.5,
        SsssQuality::High,
    );
    if out.name == sss.texture_ref().name {
        // Skipped: the input itself (a static texture that cannot be read back).
        let mut graph = spreadlight_render::FrameGraph::new(SIZE);
        g.declare(renderer, &mut graph);
        out.recipe.declare(renderer, &mut graph);
        graph.request(&g.targets.depth);
        let (report, _) = graph.execute(renderer).expect("renders");
        let empty = ImageF32 {
            width: 0,
            height: 0,
            pixels: vec![],
        };
        return (report, empty.clone(), empty);
    }
    // The G-buffer declared beside: a skipped SSSS declares nothing of its own.
    let mut graph = spreadlight_render::FrameGraph::new(SIZE);
    g.declare(renderer, &mut graph);
    out.recipe.declare(renderer, &mut graph);
    graph.request(&out.name);
    graph.request(&g.targets.depth);
    let (report, outputs) = graph.execute(renderer).expect("renders");
    assert!(report.errors.is_empty(), "{:?}", report.errors);
    let read = |name: &str| {
        spreadlight_render::readback::read_texture(&renderer.gpu, &outputs[name]).expect("reads")
    };
    (report, read(&out.name), read(&g.targets.depth))
}

/// One material with FakeSSS, red scattering farthest (as skin does).
fn skin(renderer: &Renderer) -> Arc<MaterialWorld> {
    MaterialWorld::new(
        renderer,
        vec![
            Material::default_material()
                .with(Feature::FakeSss, &[[1.0, 0.3, 0.1, 1.0]])
                .expect("valid"),
        ],
    )
}

#[test]
fn ssss_scatters_red_farthest_and_only_where_a_material_has_fake_sss() {
    let renderer = test_renderer();
    let skin = skin(&renderer);
    let (report, image, depth) = scatter(&renderer, skin.clone(), 1.0);
    assert!(image.all_finite());
    assert!(report.passes_of("SSSS", None).next().is_some());
    // Just right of the edge, on the floor: light has crept in, red farther than blue.
    let y = SIZE.1 - 4;
    let x = SIZE.0 / 2 + 1;
    assert!(depth.pixel(x, y)[0] > 0.0);
    let p = image.pixel(x, y);
    assert!(p[0] > 0.05 && p[0] > p[2] * 1.5, "{p:?}");
    // Energy is moved, not made: nothing brighter than the input.
    assert!(image.pixels.iter().all(|p| p[0] <= 1.0 + 1e-3));
    // The sky passes through.
    for (p, d) in image
        .pixels
        .iter()
        .zip(&depth.pixels)
        .take((SIZE.0 * 3) as usize)
    {
        if d[0] <= 0.0 {
            assert!(p[0] == 0.0 || p[0] == 1.0);
        }
    }
    // 1e6 in: finite, below half-float overflow.
    let (_, bright, _) = scatter(&renderer, skin, 1e6);
    assert!(bright.all_finite() && bright.pixels.iter().all(|p| p[0] <= 65000.0));
    // No material with FakeSSS: no pass, the input itself, and the report says why.
    let plain = MaterialWorld::new(&renderer, vec![Material::default_material()]);
    let (report, image, _) = scatter(&renderer, plain, 1.0);
    assert_eq!(
        report.counter("SSSS culled: no subsurface material or width 0"),
        1
    );
    assert!(report.passes_of("SSSS", None).next().is_none());
    assert!(image.pixels.is_empty(), "the input is passed on as it is");
}

/// FakeSSS at strength 0 makes no subsurface term: a world of only such
/// materials gets no SSSS passes, and a pixel of one passes through while
/// another material scatters.
#[test]
fn fake_sss_of_strength_zero_scatters_nothing_and_costs_no_taps() {
    let renderer = test_renderer();
    let still = |strength: f32| {
        Material::default_material()
            .with(Feature::FakeSss, &[[1.0, 0.3, 0.1, strength]])
            .expect("valid")
    };
    let only_still = MaterialWorld::new(&renderer, vec![still(0.0)]);
    assert!(!only_still.scatters_subsurface());
    let (report, image, _) = scatter(&renderer, only_still, 1.0);
    assert_eq!(
        report.counter("SSSS culled: no subsurface material or width 0"),
        1
    );
    assert!(image.pixels.is_empty(), "the input is passed on as it is");

    // The scene is material 0; material 1 scatters, so the passes run, and
    // material 0's pixels keep the input exactly: no light creeps past the edge.
    let mixed = MaterialWorld::new(&renderer, vec![still(0.0), still(1.0)]);
    assert!(mixed.scatters_subsurface());
    let (report, image, depth) = scatter(&renderer, mixed, 1.0);
    assert!(report.passes_of("SSSS", None).next().is_some());
    let mut covered = 0;
    for (i, (p, d)) in image.pixels.iter().zip(&depth.pixels).enumerate() {
        let lit = (i as u32 % SIZE.0) < SIZE.0 / 2;
        assert_eq!(p[0], if lit { 1.0 } else { 0.0 }, "pixel {i}");
        covered += usize::from(d[0] > 0.0);
    }
    assert!(
        covered > image.pixels.len() / 2,
        "the floor and ball cover the frame"
    );
}

/// At full resolution the gather blends its history in the same pass: no
/// raw target, no temporal pass. On a fresh history the blend keeps the
/// gather as it is, so the first frame is the image without accumulation.
#[test]
fn ssgi_gathers_and_accumulates_in_one_pass_with_the_image_of_the_gather_alone() {
    let renderer = test_renderer();
    let settings = |temporal_blend| SsgiSettings {
        radius: 1.0,
        samples: 8,
        steps: 8,
        temporal_blend,
        blur_radius: 2,
        ..Default::default()
    };
    let (fused, image, _) = ssgi(&renderer, settings(0.9), true, 1);
    // A renderer of its own: the node's frame count (its noise) starts alike.
    let (alone, reference, _) = ssgi(&test_renderer(), settings(0.0), true, 1);
    assert_eq!(fused.counter(SSGI_GATHER_TEMPORAL), 1);
    assert_eq!(alone.counter(SSGI_GATHER_TEMPORAL), 0);
    // Its own passes (the temporal blend also makes the G-buffer resolve motion).
    let ssgi_passes = |r: &FrameReport| -> Vec<String> {
        r.passes
            .iter()
            .filter(|p| p.kind == "SSGI")
            .map(|p| p.name.clone())
            .collect()
    };
    assert_eq!(
        ssgi_passes(&fused),
        ssgi_passes(&alone),
        "a temporal SSGI costs no pass more than one without"
    );
    assert!(image.all_finite());
    assert!(
        image.pixels == reference.pixels,
        "the first frame is the gather's"
    );
}

#[test]
fn ssgi_temporal_accumulation_beats_one_frame_and_hdr_input_stays_finite() {
    let few = SsgiSettings {
        radius: 1.0,
        samples: 2,
        steps: 8,
        temporal_blend: 0.0,
        blur_radius: 0,
        ..Default::default()
    };
    let renderer = test_renderer();
    let (_, one, depth) = ssgi(&renderer, few, false, 1);
    let truth: Vec<Option<f32>> = reference(&depth, SIZE, 256)
        .iter()
        .map(|t| t.map(|v| 1.0 - v))
        .collect();
    let renderer = test_renderer();
    let (_, many, _) = ssgi(
        &renderer,
        SsgiSettings {
            temporal_blend: 0.9,
            ..few
        },
        false,
        24,
    );
    let (e1, e24) = (rmse(&one, &truth), rmse(&many, &truth));
    assert!(
        e24 < e1 * 0.7,
        "24 accumulated frames ({e24}) against one ({e1})"
    );
    // A lit image of 1e6, and one of NaN: finite, below half-float overflow.
    for lit in [[1e6f32; 3], [f32::NAN; 3], [f32::INFINITY; 3]] {
        let renderer = test_renderer();
        let (_, image, _) = ssgi_lit(
            &renderer,
            SsgiSettings {
                temporal_blend: 0.9,
                blur_radius: 2,
                ..few
            },
            true,
            2,
            lit,
        );
        assert!(image.all_finite(), "lit {lit:?}");
        assert!(
            image
                .pixels
                .iter()
                .all(|p| p[..3].iter().all(|c| (0.0..=65000.0).contains(c))),
            "lit {lit:?}"
        );
    }
}

/// "Temporal history exists only for effects that run": switched to a
/// single-frame setting, a node's history texture goes after a while.
#[test]
fn a_history_no_pass_writes_any_more_is_dropped() {
    let renderer = test_renderer();
    let temporal = AoSettings {
        temporal_blend: 0.9,
        ..single_frame(AoMode::Stochastic, 2)
    };
    still_frames(&renderer, temporal, 1);
    let g = gbuffer(&renderer, eye(), None, SIZE);
    let name = AmbientOcclusion::new(&renderer, Some(7), g, temporal, None).history_name();
    assert!(renderer.persistent_texture(&name).is_some());
    let mut dropped = 0;
    for _ in 0..=spreadlight_render::renderer::PERSISTENT_IDLE_GRAPHS {
        let (report, ..) = still_frames(&renderer, single_frame(AoMode::Stochastic, 2), 1);
        dropped += report.counter("histories dropped");
    }
    assert_eq!(dropped, 1);
    assert!(renderer.persistent_texture(&name).is_none());
}

#[test]
fn ssss_blurs_up_to_three_terms_in_one_pass_pair_with_the_images_of_one_each() {
    let renderer = test_renderer();
    let skin = skin(&renderer);
    let g = gbuffer(&renderer, eye(), None, SIZE);
    // Three terms (as CookTorrance gives one per light type) and a fourth,
    // which starts a second pass pair.
    let terms: Vec<_> = [1.0, 0.5, 3.0, 0.25]
        .into_iter()
        .map(|v| half_lit(&renderer, v))
        .collect();
    let refs: Vec<_> = terms.iter().map(|t| t.texture_ref()).collect();
    let run = |outs: &[spreadlight_render::TextureRef]| {
        let mut graph = spreadlight_render::FrameGraph::new(SIZE);
        for out in outs {
            out.recipe.declare(&renderer, &mut graph);
            graph.request(&out.name);
        }
        let (report, outputs) = graph.execute(&renderer).expect("renders");
        assert!(report.errors.is_empty(), "{:?}", report.errors);
        let images: Vec<ImageF32> = outs
            .iter()
            .map(|o| {
                spreadlight_render::readback::read_texture(&renderer.gpu, &outputs[&o.name])
                    .expect("reads")
            })
            .collect();
        (report, images)
    };
    let together = Ssss::textures(
        &renderer,
        Some(5),
        g.clone(),
        refs.clone(),
        Some(skin.clone()),
        0.5,
        SsssQuality::High,
    );
    let (report, images) = run(&together);
    let ssss_passes = report.passes.iter().filter(|p| p.kind == "SSSS").count();
    assert_eq!(
        ssss_passes, 4,
        "two pass pairs for four terms, not eight passes"
    );
    for (k, r) in refs.iter().enumerate() {
        let alone = Ssss::texture(
            &renderer,
            Some(5),
            g.clone(),
            r.clone(),
            Some(skin.clone()),
            0.5,
            SsssQuality::High,
        );
        let (_, image) = run(std::slice::from_ref(&alone));
        assert_eq!(images[k].pixels, image[0].pixels, "term {k} blurred alone");
    }
    // And the blur did something: light crept past the lit half's edge.
    let (x, y) = (SIZE.0 / 2 + 1, SIZE.1 - 4);
    assert!(
        images[2].pixel(x, y)[0] > 0.05,
        "{:?}",
        images[2].pixel(x, y)
    );
}

/// SSAO's and SSGI's rays over the packed view z, four steps' reads at a
/// time (screen.wgsl's march_packed), against the G-buffer way (depth and an
/// inverse projection a step): the same pixels, bit for bit, at full and
/// half resolution, with the temporal blend in the pass and without, for
/// step counts that fill the batches of four and that do not.
#[test]
fn rays_over_the_packed_view_z_hit_what_they_hit_over_the_depth() {
    use spreadlight_render::packed_surface::{PACKED_SURFACES, Reader, SurfaceInputs, set_inputs};
    let cases = [
        (3, 0.0, Resolution::Full),
        (8, 0.0, Resolution::Full),
        (6, 0.9, Resolution::Full),
        (5, 0.0, Resolution::Half),
    ];
    for (steps, temporal_blend, resolution) in cases {
        let frame = |inputs: SurfaceInputs| {
            let renderer = test_renderer();
            set_inputs(&renderer, Reader::Rays, inputs);
            let g = gbuffer(&renderer, eye(), None, SIZE);
            let settings = AoSettings {
                steps,
                temporal_blend,
                resolution,
                ..single_frame(AoMode::Stochastic, 8)
            };
            let (report, ao, _) = ao(&renderer, g, settings, SIZE);
            let gi = SsgiSettings {
                radius: 1.0,
                samples: 4,
                steps,
                temporal_blend,
                blur_radius: 0,
                resolution,
                ..Default::default()
            };
            let (gi_report, gi, _) = ssgi_lit(&renderer, gi, false, 1, [1.0, 0.5, 0.25]);
            let packed = [&report, &gi_report].map(|r| r.counter(PACKED_SURFACES));
            (ao, gi, packed)
        };
        let (ao_packed, gi_packed, counted) = frame(SurfaceInputs::Packed);
        let (ao_depth, gi_depth, none) = frame(SurfaceInputs::GBuffer);
        let what = format!("{steps} steps, blend {temporal_blend}, {resolution}");
        assert_eq!(counted, [1, 1], "{what}: the packed surface is written");
        assert_eq!(none, [0, 0], "{what}: no packed surface the G-buffer way");
        assert!(
            ao_packed.pixels == ao_depth.pixels,
            "{what}: SSAO differs over the packed view z"
        );
        assert!(
            gi_packed.pixels == gi_depth.pixels,
            "{what}: SSGI differs over the packed view z"
        );
        // Not a trivial image: the ball's contact is occluded.
        assert!(ao_packed.pixels.iter().any(|p| p[0] < 0.5), "{what}");
        assert!(gi_packed.pixels.iter().any(|p| p[3] < 0.5), "{what}");
    }
}
