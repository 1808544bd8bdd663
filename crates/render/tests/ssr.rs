//! SSR: a mirror floor reflects the ball where the CPU ray tracer says,
//! misses and rays leaving the screen fall back, nothing non-finite reaches
//! a target, the history survives a NaN, a cut and a resize, the passes
//! run only when a material reflects and the output is wanted, and a
//! mirror clear coat over a rough floor reflects the ball as its own lobe
//! (the coat's Fresnel) where the rough base alone shows nothing.

use crate::reflection_scene;

use std::sync::Arc;

use glam::Vec3;
use reflection_scene::*;
use spreadlight_reference::reflection::{BallsScene, Surface};
use spreadlight_reference::shadows::Sphere;
use spreadlight_render::Renderer;
use spreadlight_render::environment::{Ssr, SsrSettings};
use spreadlight_render::frame_graph::TextureDesc;
use spreadlight_render::gbuffer::GBuffer;
use spreadlight_render::material::{Feature, Material, MaterialWorld};
use spreadlight_render::readback::{ImageF32, render_and_read};
use spreadlight_render::renderer::test_renderer;
use spreadlight_render::static_texture::StaticTexture;

const BALL: (Vec3, f32) = (Vec3::new(0.0, 0.6, 0.0), 0.6);

fn constant(renderer: &Renderer, size: (u32, u32), c: [f32; 4]) -> Arc<StaticTexture> {
    StaticTexture::from_rgba32f(
        &renderer.gpu,
        size.0,
        size.1,
        &vec![c; (size.0 * size.1) as usize],
        "constant",
    )
}

/// The lit image a test gives SSR: the ball red, the floor dark blue, the sky black.
fn lit_image(renderer: &Renderer, g: &Arc<GBuffer>) -> Arc<StaticTexture> {
    let (_, images) =
        render_and_read(renderer, g.as_ref(), SIZE, &[&g.targets.depth]).expect("renders");
    let depth = &images[0];
    let mut pixels = Vec::new();
    for y in 0..SIZE.1 {
        for x in 0..SIZE.0 {
            let d = depth.pixel(x, y)[0];
            pixels.push(if d <= 0.0 {
                [0.0, 0.0, 0.0, 1.0]
            } else if world_position(g, x, y, d).distance(BALL.0) < BALL.1 * 1.05 {
                [1.0, 0.0, 0.0, 1.0]
            } else {
                [0.0, 0.0, 0.2, 1.0]
            });
        }
    }
    StaticTexture::from_rgba32f(&renderer.gpu, SIZE.0, SIZE.1, &pixels, "lit")
}

fn ssr_frame(
    renderer: &Renderer,
    g: &Arc<GBuffer>,
    world: Vec<Material>,
    fallback: [f32; 4],
    settings: SsrSettings,
    owner: Option<u32>,
    size: (u32, u32),
) -> (spreadlight_render::FrameReport, ImageF32, Arc<Ssr>) {
    let lit = if size == SIZE {
        lit_image(renderer, g)
    } else {
        constant(renderer, size, [1.0, 0.0, 0.0, 1.0])
    };
    let fallback = constant(renderer, size, fallback);
    let materials = MaterialWorld::new(renderer, world);
    let ssr = Ssr::new(
        renderer,
        owner,
        g.clone(),
        materials,
        lit.texture_ref(),
        fallback.texture_ref(),
        settings,
    );
    let (report, images) =
        render_and_read(renderer, ssr.as_ref(), size, &[&ssr.output]).expect("renders");
    assert!(report.errors.is_empty(), "{:?}", report.errors);
    (report, images.into_iter().next().expect("output"), ssr)
}

fn plain() -> Material {
    Material::default_material()
}

#[test]
fn a_mirror_floor_reflects_the_ball_where_the_reference_says() {
    let renderer = test_renderer();
    let g = gbuffer(&renderer);
    let settings = SsrSettings {
        max_steps: 256,
        temporal: false,
        ..Default::default()
    };
    // Only the floor reflects (a mirror, F0 = 0.8); misses fall back to black.
    let (_, image, _) = ssr_frame(
        &renderer,
        &g,
        vec![plain(), reflective(0.0, 1.0)],
        [0.0; 4],
        settings,
        None,
        SIZE,
    );
    assert!(image.all_finite());
    let (_, images) =
        render_and_read(&renderer, g.as_ref(), SIZE, &[&g.targets.depth]).expect("renders");
    let depth = &images[0];
    let scene = BallsScene {
        balls: vec![Sphere {
            center: BALL.0,
            radius: BALL.1,
        }],
        floor: 8.0,
    };
    let (mut agree, mut total, mut ball_hits) = (0, 0, 0);
    for y in 0..SIZE.1 {
        for x in 0..SIZE.0 {
            let d = depth.pixel(x, y)[0];
            if d <= 0.0 {
                continue;
            }
            let p = world_position(&g, x, y, d);
            if p.y.abs() > 1e-3 {
                continue;
            }
            let v = (EYE - p).normalize();
            let r = Vec3::new(-v.x, v.y, -v.z);
            let sees_ball = matches!(scene.trace(p + Vec3::Y * 1e-3, r), Some(h) if h.surface == Surface::Ball(0));
            let red = image.pixel(x, y)[0];
            // The reflected ball is red times F0 (0.8); elsewhere nothing.
            let gpu_ball = red > 0.3;
            total += 1;
            ball_hits += usize::from(sees_ball);
            agree += usize::from(gpu_ball == sees_ball);
        }
    }
    assert!(ball_hits > 20, "the ball is reflected in view: {ball_hits}");
    assert!(
        agree as f32 >= 0.93 * total as f32,
        "{agree} of {total} floor pixels agree with the reference"
    );
}

#[test]
fn ssr_misses_and_rays_leaving_the_screen_fall_back_at_roughness_0_and_1() {
    let renderer = test_renderer();
    // Looking down at the floor from high up, away from the ball: every reflection leaves the screen.
    let g = gbuffer_from(
        &renderer,
        Vec3::new(3.0, 4.0, 3.0),
        Vec3::new(3.0, 0.0, 2.0),
    );
    for roughness in [0.0, 1.0] {
        for temporal in [false, true] {
            let settings = SsrSettings {
                temporal,
                rays: 4,
                ..Default::default()
            };
            let (_, image, _) = ssr_frame(
                &renderer,
                &g,
                vec![reflective(roughness, 1.0), reflective(roughness, 1.0)],
                [0.0, 1.0, 0.0, 1.0],
                settings,
                None,
                SIZE,
            );
            assert!(image.all_finite());
            let centre = image.pixel(SIZE.0 / 2, SIZE.1 / 2);
            assert!(
                (centre[1] - 1.0).abs() < 1e-3 && centre[0] < 1e-3,
                "roughness {roughness}: {centre:?}"
            );
        }
    }
}

#[test]
fn ssr_stays_finite_on_sky_edges_and_surfaces_facing_away() {
    let renderer = test_renderer();
    for (eye, target) in [
        (EYE, Vec3::ZERO),
        (Vec3::new(0.5, -2.0, 3.0), Vec3::new(0.0, 0.5, 0.0)),
        (Vec3::new(0.0, 0.02, 6.0), Vec3::ZERO),
        (Vec3::new(2.0, 0.6, 0.0), Vec3::new(-1.0, 0.6, 0.0)),
    ] {
        let g = gbuffer_from(&renderer, eye, target);
        for roughness in [0.0, 0.5, 1.0] {
            let settings = SsrSettings {
                rays: 2,
                temporal: false,
                ..Default::default()
            };
            let (_, image, _) = ssr_frame(
                &renderer,
                &g,
                vec![reflective(roughness, 1.0), reflective(roughness, 0.0)],
                [f32::NAN, f32::INFINITY, 1.0, 1.0],
                settings,
                None,
                SIZE,
            );
            assert!(image.all_finite(), "{eye} roughness {roughness}");
            assert!(
                image
                    .pixels
                    .iter()
                    .all(|p| p[..3].iter().all(|c| (0.0..=65000.0).contains(c)))
            );
        }
    }
}

#[test]
fn ssr_history_survives_a_nan_a_camera_cut_and_a_resize() {
    let renderer = test_renderer();
    let g = gbuffer(&renderer);
    let world = || vec![reflective(0.3, 1.0), reflective(0.1, 1.0)];
    let settings = SsrSettings {
        temporal: true,
        ..Default::default()
    };
    let owner = Some(901);
    let (first, ..) = ssr_frame(&renderer, &g, world(), [0.1; 4], settings, owner, SIZE);
    assert_eq!(first.counter("ssr history reset"), 1);
    let (second, _, ssr) = ssr_frame(&renderer, &g, world(), [0.1; 4], settings, owner, SIZE);
    assert_eq!(second.counter("ssr history used"), 1);

    // Poison the history: a pass writing NaN into it under its name (and
    // the desc SSR gives it, or the graph would make a new one).
    let history = ssr.history.clone();
    let desc = TextureDesc::history(wgpu::TextureFormat::Rgba16Float);
    let mut graph = spreadlight_render::FrameGraph::new(SIZE);
    let mut pass = graph.pass("poison", None);
    let poisoned = pass.write(&history, desc);
    pass.run(move |cx| {
        let texture = cx.texture(poisoned)?;
        let nan = half::f16::NAN.to_bits().to_le_bytes();
        let data: Vec<u8> = (0..SIZE.0 * SIZE.1 * 4).flat_map(|_| nan).collect();
        cx.gpu.queue.write_texture(
            texture.as_image_copy(),
            &data,
            wgpu::TexelCopyBufferLayout {
                offset: 0,
                bytes_per_row: Some(SIZE.0 * 8),
                rows_per_image: None,
            },
            texture.size(),
        );
        Ok(())
    });
    graph.request(&history);
    let (report, _) = graph.execute(&renderer).expect("runs");
    assert!(report.errors.is_empty(), "{:?}", report.errors);
    let (third, image, _) = ssr_frame(&renderer, &g, world(), [0.1; 4], settings, owner, SIZE);
    assert_eq!(
        third.counter("ssr history used"),
        1,
        "the poisoned history was read"
    );
    assert!(image.all_finite(), "a NaN in the history does not spread");

    // A camera cut resets the history; so does a resize.
    renderer.reset_history();
    let (cut, image, _) = ssr_frame(&renderer, &g, world(), [0.1; 4], settings, owner, SIZE);
    assert_eq!(cut.counter("ssr history reset"), 1);
    assert!(image.all_finite());
    let bigger = (80, 60);
    let (resized, image, _) = ssr_frame(&renderer, &g, world(), [0.1; 4], settings, owner, bigger);
    assert_eq!(resized.counter("ssr history reset"), 1);
    assert!(image.all_finite());
    let (kept, ..) = ssr_frame(&renderer, &g, world(), [0.1; 4], settings, owner, bigger);
    assert_eq!(kept.counter("ssr history used"), 1);
    // Reset drops it too.
    let reset = SsrSettings {
        reset: true,
        ..settings
    };
    let (dropped, image, _) = ssr_frame(&renderer, &g, world(), [0.1; 4], reset, owner, bigger);
    assert_eq!(dropped.counter("ssr history reset"), 1);
    assert!(image.all_finite());
}

#[test]
fn ssr_runs_only_when_a_material_reflects_and_its_output_is_wanted() {
    let renderer = test_renderer();
    let g = gbuffer(&renderer);
    let (report, image, _) = ssr_frame(
        &renderer,
        &g,
        vec![plain(), plain()],
        [1.0; 4],
        SsrSettings::default(),
        Some(3),
        SIZE,
    );
    assert_eq!(report.counter("ssr skipped"), 1);
    assert_eq!(report.counter("ssr traced"), 0);
    assert!(!report.passes.iter().any(|p| {
        p.kind == "SSR"
            && p.step
                .as_deref()
                .is_some_and(|s| s.starts_with("trace") || s == "hi-z")
    }));
    assert!(image.pixels.iter().all(|p| p[..3] == [0.0; 3]));
    // Wired, not requested: culled.
    let lit = constant(&renderer, SIZE, [1.0; 4]);
    let materials = MaterialWorld::new(&renderer, vec![reflective(0.0, 1.0)]);
    let ssr = Ssr::new(
        &renderer,
        None,
        g.clone(),
        materials,
        lit.texture_ref(),
        lit.texture_ref(),
        SsrSettings::default(),
    );
    let mut graph = spreadlight_render::FrameGraph::new(SIZE);
    spreadlight_render::Recipe::declare(ssr.as_ref(), &renderer, &mut graph);
    graph.request(&g.targets.color);
    let (report, _) = graph.execute(&renderer).expect("runs");
    assert_eq!(report.passes_of("SSR", None).count(), 0);
    assert_eq!(report.counter("ssr traced"), 0);
}

#[test]
fn at_full_resolution_the_trace_blends_its_history_in_as_a_resolve_pass_would() {
    use spreadlight_render::environment::TRACE_TEMPORAL;
    use spreadlight_render::resolution::Resolution;
    // The same owner on two renderers: the same frame counts, the same jitter.
    let owner = Some(902);
    let frames = |temporal: bool| {
        let renderer = test_renderer();
        let g = gbuffer(&renderer);
        let settings = SsrSettings {
            temporal,
            rays: 2,
            ..Default::default()
        };
        let world = || vec![reflective(0.3, 1.0), reflective(0.1, 1.0)];
        (0..3)
            .map(|_| ssr_frame(&renderer, &g, world(), [0.1; 4], settings, owner, SIZE))
            .map(|(report, image, _)| (report, image))
            .collect::<Vec<_>>()
    };
    let blended = frames(true);
    let traced = frames(false);
    for (report, _) in &blended {
        assert_eq!(report.counter(TRACE_TEMPORAL), 1);
        assert!(
            report.passes_of("SSR", Some("resolve")).count() == 0,
            "{:?}",
            report.passes
        );
    }
    let blend = SsrSettings::default().blend;
    let close = |a: f32, b: f32| (a - b).abs() <= 2e-3 * b.abs().max(1.0);
    let mut mixed = 0;
    // Frame 1 has no history: the trace alone, with the view distance in
    // alpha (0 on the sky). Frames 2 and 3: last frame's result blended with
    // the trace where the surface is the same (a still camera: every
    // surface pixel), the trace alone on the sky.
    for i in 0..blended[0].1.pixels.len() {
        let first = &blended[0].1.pixels[i];
        for (got, want) in first[..3].iter().zip(&traced[0].1.pixels[i]) {
            assert!(close(*got, *want), "pixel {i}");
        }
        for frame in 1..3 {
            let (got, last) = (&blended[frame].1.pixels[i], &blended[frame - 1].1.pixels[i]);
            let now = &traced[frame].1.pixels[i];
            let sky = last[3] == 0.0;
            for k in 0..3 {
                let want = if sky {
                    now[k]
                } else {
                    last[k] + (now[k] - last[k]) * blend
                };
                assert!(
                    close(got[k], want),
                    "frame {frame}, pixel {i}, channel {k}: {} against {want}",
                    got[k]
                );
            }
            assert_eq!(got[3], first[3], "the view distance stays");
            mixed += usize::from(!sky && (now[0] - last[0]).abs() > 1e-3);
        }
    }
    assert!(mixed > 20, "the jitter moves {mixed} pixels between frames");

    // At half resolution the blend follows the upsample, in its own pass.
    let renderer = test_renderer();
    let g = gbuffer(&renderer);
    let half = SsrSettings {
        temporal: true,
        resolution: Resolution::Half,
        ..Default::default()
    };
    let world = vec![reflective(0.3, 1.0), reflective(0.1, 1.0)];
    let (report, image, _) = ssr_frame(&renderer, &g, world, [0.1; 4], half, owner, SIZE);
    assert_eq!(report.counter(TRACE_TEMPORAL), 0);
    assert_eq!(report.passes_of("SSR", Some("resolve")).count(), 1);
    assert!(image.all_finite());
}

/// The clear coat in SSR: a floor whose base is rough (roughness 1) and
/// reflects little (f0 0: its split sum is at most 0.01 where N.V > 0.3)
/// under a mirror coat of factor 1. Uncoated, no floor pixel shows the ball
/// (red under 0.4 x the coat's Fresnel S(0.04, N.V) wherever the mirror ray
/// meets the ball); coated, the pixels whose mirror ray meets the ball (the
/// CPU ray tracer's) are the ones showing it, at about the coat's Fresnel
/// times the ball's radiance (1): the coat's lobe is traced on its own
/// normal and roughness, one mirror ray, over the dimmed base. The fallback
/// is black, so only hits count. SSR compiles CLEARCOAT only for the world
/// with a coat.
#[test]
fn a_mirror_coat_over_a_rough_floor_reflects_the_ball_in_ssr() {
    let renderer = test_renderer();
    let g = gbuffer(&renderer);
    let settings = SsrSettings {
        max_steps: 256,
        rays: 1,
        temporal: false,
        ..Default::default()
    };
    let floor = |coat: f32| {
        let m = Material::new()
            .with(Feature::CookTorrance, &[[1.0, 0.0, 0.0, 0.0]])
            .and_then(|m| m.with(Feature::Reflection, &[[1.0, 0.0, 0.0, 0.0]]))
            .expect("valid");
        if coat > 0.0 {
            m.with(Feature::Clearcoat, &[[coat, 0.0, 0.0, 0.0]])
                .expect("valid")
        } else {
            m
        }
    };
    let coat_keys = |renderer: &Renderer| {
        renderer
            .shaders()
            .compiled_keys()
            .filter(|k| k.path() == "environment/ssr.wgsl" && k.features.contains("CLEARCOAT"))
            .count()
    };
    let (_, images) =
        render_and_read(&renderer, g.as_ref(), SIZE, &[&g.targets.depth]).expect("renders");
    let depth = &images[0];
    let scene = BallsScene {
        balls: vec![Sphere {
            center: BALL.0,
            radius: BALL.1,
        }],
        floor: 8.0,
    };
    let schlick = |n_dot_v: f32| 0.04 + 0.96 * (1.0 - n_dot_v).powi(5);
    for coat in [0.0, 1.0] {
        let (_, image, _) = ssr_frame(
            &renderer,
            &g,
            vec![plain(), floor(coat)],
            [0.0; 4],
            settings,
            None,
            SIZE,
        );
        assert!(image.all_finite());
        assert_eq!(
            coat_keys(&renderer) > 0,
            coat > 0.0,
            "CLEARCOAT only with a coat"
        );
        let (mut agree, mut total, mut ball_hits) = (0, 0, 0);
        for y in 0..SIZE.1 {
            for x in 0..SIZE.0 {
                let d = depth.pixel(x, y)[0];
                if d <= 0.0 {
                    continue;
                }
                let p = world_position(&g, x, y, d);
                let v = (EYE - p).normalize();
                if p.y.abs() > 1e-3 || v.y < 0.3 {
                    continue;
                }
                let r = Vec3::new(-v.x, v.y, -v.z);
                let sees_ball = matches!(scene.trace(p + Vec3::Y * 1e-3, r), Some(h) if h.surface == Surface::Ball(0));
                let red = image.pixel(x, y)[0];
                let lobe = coat * schlick(v.y);
                if coat == 0.0 {
                    assert!(
                        red < 0.4 * schlick(v.y),
                        "uncoated ({x}, {y}): the rough base shows {red}"
                    );
                    continue;
                }
                assert!(
                    red < 1.2 * lobe + 0.01,
                    "({x}, {y}): {red}, more than the coat's lobe {lobe}"
                );
                total += 1;
                ball_hits += usize::from(sees_ball);
                agree += usize::from((red > 0.4 * lobe) == sees_ball);
            }
        }
        if coat > 0.0 {
            assert!(ball_hits > 20, "the ball is reflected in view: {ball_hits}");
            assert!(
                agree as f32 >= 0.9 * total as f32,
                "{agree} of {total} floor pixels agree with the reference"
            );
        }
    }
}
