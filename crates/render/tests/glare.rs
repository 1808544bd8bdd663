//! Glare: a bright spot glows, fading with distance; below the threshold
//! nothing glows; chromatic aberration parts red from blue radially; with
//! nothing to add it costs a counted copy.

mod post_common;

use post_common::*;
use spreadlight_render::post::glare::SKIPPED;
use spreadlight_render::post::{Glare, GlareSettings};
use spreadlight_render::readback::ImageF32;
use spreadlight_render::renderer::test_renderer;

const SIZE: (u32, u32) = (64, 64);

fn spot(x: u32, y: u32) -> [f32; 4] {
    if x.abs_diff(16) <= 1 && y.abs_diff(32) <= 1 {
        [50.0, 50.0, 50.0, 1.0]
    } else {
        [0.0, 0.0, 0.0, 1.0]
    }
}

fn glare(settings: GlareSettings) -> (ImageF32, u64) {
    let renderer = test_renderer();
    let input = image(&renderer, SIZE, spot);
    let pass = Glare::new(&renderer, None, input.texture_ref(), settings);
    let (report, out) = render(&renderer, pass.as_ref(), &pass.output, SIZE);
    (out, report.counter(SKIPPED))
}

#[test]
fn a_bright_spot_glows_less_with_distance() {
    let (out, skipped) = glare(GlareSettings {
        threshold: 1.0,
        intensity: 1.0,
        spread: 0.8,
        aberration: 0.0,
        levels: 5,
    });
    assert_eq!(skipped, 0);
    let at = |x: u32| out.pixels[(32 * SIZE.0 + x) as usize][1];
    assert!(
        at(20) > at(26) && at(26) > at(34) && at(34) > 0.0,
        "{} {} {}",
        at(20),
        at(26),
        at(34)
    );
    // Energy is spread, not made: the glow beside the spot is far below it.
    assert!(at(20) < 10.0, "{}", at(20));
    // The spot itself stays (source plus glow).
    assert!(at(16) >= 50.0);
}

#[test]
fn below_the_threshold_nothing_glows() {
    let (out, _) = glare(GlareSettings {
        threshold: 100.0,
        intensity: 1.0,
        aberration: 0.0,
        ..Default::default()
    });
    for (i, p) in out.pixels.iter().enumerate() {
        let want = spot(i as u32 % SIZE.0, i as u32 / SIZE.0);
        assert_eq!(p[..3], want[..3], "pixel {i}");
    }
}

#[test]
fn aberration_parts_red_from_blue_radially() {
    let (out, _) = glare(GlareSettings {
        threshold: 1000.0,
        intensity: 0.0,
        aberration: 0.1,
        ..Default::default()
    });
    let centroid = |c: usize| {
        let (mut sum, mut weight) = (0.0, 0.0);
        for (i, p) in out.pixels.iter().enumerate() {
            sum += (i as u32 % SIZE.0) as f32 * p[c];
            weight += p[c];
        }
        sum / weight
    };
    let (r, g, b) = (centroid(0), centroid(1), centroid(2));
    assert!((g - 16.0).abs() < 0.5, "green stays: {g}");
    // Red is read from further out, so it lands nearer the centre (x = 32); blue the other way.
    assert!(r > g + 1.0 && b < g - 1.0, "r {r} g {g} b {b}");
}

#[test]
fn nothing_to_add_costs_a_copy() {
    let (out, skipped) = glare(GlareSettings {
        intensity: 0.0,
        aberration: 0.0,
        ..Default::default()
    });
    assert_eq!(skipped, 1);
    assert_eq!(out.pixels[(32 * SIZE.0 + 16) as usize][0], 50.0);
}
