//! DOF keeps what is in focus sharp and blurs what is not, without halos:
//! a sharp ball keeps its edge against a blurred sky (far field), a blurred
//! ball spreads over a sharp sky (near field). Autofocus finds the ball's
//! distance and eases towards a new one over time. A lens that cannot blur
//! half a pixel costs a copy, and the frame report says so.

use crate::post_common;

use glam::{Vec2, Vec3};
use post_common::*;
use spreadlight_render::post::dof::{BLURRED, SKIPPED};
use spreadlight_render::post::{Autofocus, Dof, DofSettings, Focus};
use spreadlight_render::readback::ImageF32;
use spreadlight_render::renderer::test_renderer;
use spreadlight_render::resolution::Resolution;
use spreadlight_render::{Renderer, TextureRef};

const SIZE: (u32, u32) = (64, 64);
const RED: [f32; 4] = [1.0, 0.0, 0.0, 1.0];
const BLACK: [f32; 4] = [0.0, 0.0, 0.0, 1.0];
const BLUE: [f32; 4] = [0.0, 0.0, 1.0, 1.0];
const DIM_BLUE: [f32; 4] = [0.0, 0.0, 0.2, 1.0];

/// A ball of radius 0.5, 8 units ahead (its front 7.5 away), against the sky.
fn ball_scene(renderer: &Renderer) -> std::sync::Arc<spreadlight_render::gbuffer::GBuffer> {
    let layer = balls(renderer, &[Ball::still(Vec3::ZERO, 0.5)]);
    gbuffer(
        renderer,
        layer,
        look(Vec3::new(0.0, 0.0, 8.0), Vec3::ZERO, 0.4, 1.0),
        None,
    )
}

/// Red/black checker on the ball, blue/dim blue on the sky; and the ball's mask.
fn source(renderer: &Renderer) -> (TextureRef, Vec<bool>) {
    let g = ball_scene(renderer);
    let (_, depth) = render(renderer, g.as_ref(), &g.targets.depth, SIZE);
    let mask: Vec<bool> = depth.pixels.iter().map(|p| p[0] > 0.0).collect();
    assert!(
        mask.iter().filter(|m| **m).count() > 100,
        "the ball is in view"
    );
    let texture = image(renderer, SIZE, |x, y| {
        if mask[(y * SIZE.0 + x) as usize] {
            checker(x, y, RED, BLACK)
        } else {
            checker(x, y, BLUE, DIM_BLUE)
        }
    });
    (texture.texture_ref(), mask)
}

/// A 1 m telephoto at f/2: at 64 pixels, the sky blurs by about 10 pixels when focused on the ball.
fn telephoto() -> DofSettings {
    DofSettings {
        focal_length_mm: 1000.0,
        f_stop: 2.0,
        samples: 64,
        max_radius: 16.0,
        ..Default::default()
    }
}

fn dof(
    renderer: &Renderer,
    focus: Focus,
    settings: DofSettings,
) -> (ImageF32, Vec<bool>, u64, u64) {
    let (input, mask) = source(renderer);
    let g = ball_scene(renderer);
    let pass = Dof::new(renderer, None, input, g, focus, None, settings);
    let (report, out) = render(renderer, pass.as_ref(), &pass.output, SIZE);
    (out, mask, report.counter(BLURRED), report.counter(SKIPPED))
}

/// Distance in pixels from (x, y) to the nearest pixel of the ball.
fn distance_to_ball(mask: &[bool], x: u32, y: u32) -> f32 {
    let mut best = f32::INFINITY;
    for (i, m) in mask.iter().enumerate() {
        if *m {
            let (bx, by) = ((i as u32 % SIZE.0) as f32, (i as u32 / SIZE.0) as f32);
            best = best.min(((bx - x as f32).powi(2) + (by - y as f32).powi(2)).sqrt());
        }
    }
    best
}

#[test]
fn focused_on_the_ball_the_ball_stays_sharp_and_the_sky_blurs_without_a_red_halo() {
    let renderer = test_renderer();
    let (out, mask, blurred, skipped) = dof(&renderer, Focus::Distance(7.7), telephoto());
    assert_eq!((blurred, skipped), (1, 0));
    for y in 0..SIZE.1 {
        for x in 0..SIZE.0 {
            let i = (y * SIZE.0 + x) as usize;
            let p = out.pixels[i];
            if mask[i] {
                // In focus, up to its silhouette: the checker survives.
                let want = checker(x, y, RED, BLACK);
                assert!((p[0] - want[0]).abs() < 0.02, "ball ({x}, {y}): {p:?}");
                assert!(p[2] < 0.02, "ball ({x}, {y}) took sky colour: {p:?}");
            } else {
                // The far field never spreads over the ball, nor takes its colour.
                assert!(p[0] < 0.02, "sky ({x}, {y}) has a red halo: {p:?}");
                let inside = (8..SIZE.0 - 8).contains(&x) && (8..SIZE.1 - 8).contains(&y);
                if distance_to_ball(&mask, x, y) > 8.0 && inside {
                    assert!(
                        (p[2] - 0.6).abs() < 0.15,
                        "sky ({x}, {y}) not blurred: {p:?}"
                    );
                }
            }
        }
    }
}

/// At full resolution the tiles and the blur make each pixel's circle of
/// confusion from the depth where they read it: no pass writes a CoC
/// target. At half resolution the upsample reads that target, so a pass
/// makes it. (The images are the tests above.)
#[test]
fn only_half_resolution_writes_a_circle_of_confusion_target() {
    let renderer = test_renderer();
    for (resolution, coc_passes) in [(Resolution::Full, 0), (Resolution::Half, 1)] {
        let (input, _) = source(&renderer);
        let g = ball_scene(&renderer);
        let settings = DofSettings {
            resolution,
            ..telephoto()
        };
        let pass = Dof::new(
            &renderer,
            None,
            input,
            g,
            Focus::Distance(7.7),
            None,
            settings,
        );
        let (report, _) = render(&renderer, pass.as_ref(), &pass.output, SIZE);
        let named = |what: &str| passes_named(&report, what);
        assert_eq!(named("circle of confusion"), coc_passes, "{resolution:?}");
        assert_eq!(
            (named("tiles"), report.counter(BLURRED)),
            (1, 1),
            "{resolution:?}"
        );
    }
}

#[test]
fn focused_at_infinity_the_near_ball_blurs_over_the_sharp_sky() {
    let renderer = test_renderer();
    let (out, mask, _, _) = dof(&renderer, Focus::Distance(f32::INFINITY), telephoto());
    let mut spilled = 0;
    for y in 0..SIZE.1 {
        for x in 0..SIZE.0 {
            let i = (y * SIZE.0 + x) as usize;
            let p = out.pixels[i];
            if mask[i] {
                continue;
            }
            let d = distance_to_ball(&mask, x, y);
            if d <= 2.0 && p[0] > 0.05 {
                spilled += 1;
            }
            if d > 12.0 {
                // The sky is in focus: its checker is untouched.
                let want = checker(x, y, BLUE, DIM_BLUE);
                assert!((p[2] - want[2]).abs() < 0.02, "sky ({x}, {y}): {p:?}");
            }
        }
    }
    assert!(
        spilled > 20,
        "only {spilled} sky pixels beside the ball took its blur"
    );
    // And the ball itself is blurred: its checker flattens towards 0.5.
    let flat = mask
        .iter()
        .zip(&out.pixels)
        .filter(|(m, p)| **m && (p[0] - 0.5).abs() < 0.2)
        .count();
    assert!(flat > mask.iter().filter(|m| **m).count() / 2, "{flat}");
}

#[test]
fn a_pinhole_lens_costs_a_copy_and_says_so() {
    let renderer = test_renderer();
    let pinhole = DofSettings {
        f_stop: 1e6,
        ..telephoto()
    };
    let (out, mask, blurred, skipped) = dof(&renderer, Focus::Distance(7.7), pinhole);
    assert_eq!((blurred, skipped), (0, 1));
    for (i, p) in out.pixels.iter().enumerate() {
        let (x, y) = (i as u32 % SIZE.0, i as u32 / SIZE.0);
        let want = if mask[i] {
            checker(x, y, RED, BLACK)
        } else {
            checker(x, y, BLUE, DIM_BLUE)
        };
        assert!(
            p.iter().zip(want).all(|(a, b)| (a - b).abs() < 1e-3),
            "({x}, {y}): {p:?} vs {want:?}"
        );
    }
}

fn focus_value(renderer: &Renderer, point: Vec2, speed: f32, delta: f64, history: &str) -> f32 {
    let g = ball_scene(renderer);
    let af = Autofocus::with_history(renderer, None, g, point, speed, delta, history.to_owned());
    let (_, out) = render(renderer, af.as_ref(), &af.output, SIZE);
    out.pixels[0][0]
}

#[test]
fn autofocus_finds_the_ball_and_eases_towards_the_sky() {
    let renderer = test_renderer();
    let history = "autofocus test";
    let first = focus_value(&renderer, Vec2::splat(0.5), 1.0, 0.0, history);
    // The ball's front is 7.5 away; the 5x5 window sees a little further.
    assert!((7.45..7.6).contains(&(1.0 / first)), "{}", 1.0 / first);
    // Half a second at speed 1 towards the sky: the far plane, 100 away.
    let second = focus_value(&renderer, Vec2::splat(0.02), 1.0, 0.5, history);
    let want = 0.01 + (first - 0.01) * (-0.5f32).exp();
    assert!((second - want).abs() < 1e-3 * first, "{second} vs {want}");
    // Infinitely fast: no smoothing.
    let third = focus_value(&renderer, Vec2::splat(0.5), f32::INFINITY, 0.5, history);
    assert!((third - first).abs() < 1e-4, "{third} vs {first}");
}

#[test]
fn dof_reads_autofocus_on_the_gpu_and_focuses_on_the_ball() {
    let renderer = test_renderer();
    let (input, mask) = source(&renderer);
    let g = ball_scene(&renderer);
    let af = Autofocus::new(&renderer, None, g.clone(), Vec2::splat(0.5), 1.0, 0.0);
    let pass = Dof::new(
        &renderer,
        None,
        input,
        g,
        Focus::Texture(af.texture()),
        None,
        telephoto(),
    );
    let (report, out) = render(&renderer, pass.as_ref(), &pass.output, SIZE);
    assert_eq!(report.counter(BLURRED), 1);
    let sharp = mask
        .iter()
        .zip(&out.pixels)
        .enumerate()
        .filter(|(i, (m, p))| {
            let (x, y) = (*i as u32 % SIZE.0, *i as u32 / SIZE.0);
            **m && (p[0] - checker(x, y, RED, BLACK)[0]).abs() < 0.05
        })
        .count();
    assert!(
        sharp * 10 >= mask.iter().filter(|m| **m).count() * 9,
        "{sharp}"
    );
    let blurred_sky = mask
        .iter()
        .zip(&out.pixels)
        .filter(|(m, p)| !**m && (p[2] - 0.6).abs() < 0.2)
        .count();
    assert!(blurred_sky > 1000, "{blurred_sky}");
}

#[test]
fn a_bokeh_texture_shapes_the_blur() {
    let renderer = test_renderer();
    // One bright pixel of sky, focus on the ball: its blur takes the bokeh's shape.
    let g = ball_scene(&renderer);
    let spot = image(&renderer, SIZE, |x, y| {
        if (x, y) == (10, 10) {
            [100.0, 100.0, 100.0, 1.0]
        } else {
            BLACK
        }
    });
    // A bokeh that is only the left half of the disk.
    let half = image(
        &renderer,
        (16, 16),
        |x, _| if x < 8 { [1.0; 4] } else { BLACK },
    );
    let pass = Dof::new(
        &renderer,
        None,
        spot.texture_ref(),
        g,
        Focus::Distance(7.7),
        Some(half.texture_ref()),
        telephoto(),
    );
    let (_, out) = render(&renderer, pass.as_ref(), &pass.output, SIZE);
    let at = |x: u32, y: u32| out.pixels[(y * SIZE.0 + x) as usize][0];
    let (left, right): (f32, f32) = (
        (3..10).map(|x| at(x, 10)).sum(),
        (11..18).map(|x| at(x, 10)).sum(),
    );
    assert!(left + right > 0.5, "the spot spread: {left} {right}");
    // The gather reads the kernel mirrored (q covers p where p - q is in the shape), so
    // a left-half shape puts the spot's light to its left.
    assert!(left > 4.0 * right, "left {left} right {right}");
}
