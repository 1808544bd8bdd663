//! MotionBlur smears along the velocity only, extends a moving silhouette
//! over the still background, keeps still tiles exact, and costs a copy
//! (counted) when nothing moves.

use crate::post_common;

use glam::Vec3;
use post_common::*;
use spreadlight_render::post::motion_blur::{BLURRED, SKIPPED};
use spreadlight_render::post::{MotionBlur, MotionBlurSettings};
use spreadlight_render::readback::ImageF32;
use spreadlight_render::renderer::test_renderer;

const SIZE: (u32, u32) = (64, 64);

/// A white ball moving from `previous` to the origin against a black sky;
/// the blurred image, the ball's mask, and the report's counters.
fn blur(previous: Vec3, settings: MotionBlurSettings) -> (ImageF32, Vec<bool>, u64, u64) {
    let renderer = test_renderer();
    let layer = balls(
        &renderer,
        &[Ball {
            center: Vec3::ZERO,
            previous,
            radius: 0.5,
        }],
    );
    let camera = look(Vec3::new(0.0, 0.0, 8.0), Vec3::ZERO, 0.4, 1.0);
    let g = gbuffer(&renderer, layer, camera, None);
    let (_, depth) = render(&renderer, g.as_ref(), &g.targets.depth, SIZE);
    let mask: Vec<bool> = depth.pixels.iter().map(|p| p[0] > 0.0).collect();
    let input = image(&renderer, SIZE, |x, y| {
        if mask[(y * SIZE.0 + x) as usize] {
            [1.0; 4]
        } else {
            [0.0, 0.0, 0.0, 1.0]
        }
    });
    let pass = MotionBlur::new(&renderer, None, input.texture_ref(), g, settings);
    let (report, out) = render(&renderer, pass.as_ref(), &pass.output, SIZE);
    (out, mask, report.counter(BLURRED), report.counter(SKIPPED))
}

fn rows_of(mask: &[bool]) -> (u32, u32) {
    let rows: Vec<u32> = mask
        .iter()
        .enumerate()
        .filter(|(_, m)| **m)
        .map(|(i, _)| i as u32 / SIZE.0)
        .collect();
    (
        *rows.iter().min().expect("ball"),
        *rows.iter().max().expect("ball"),
    )
}

#[test]
fn a_ball_moving_sideways_smears_sideways_only() {
    // Half a unit in x a frame: about ten pixels.
    let (out, mask, blurred, skipped) = blur(
        Vec3::new(-0.5, 0.0, 0.0),
        MotionBlurSettings {
            shutter_angle: 360.0,
            ..Default::default()
        },
    );
    assert_eq!((blurred, skipped), (1, 0));
    let (top, bottom) = rows_of(&mask);
    let at = |x: u32, y: u32| out.pixels[(y * SIZE.0 + x) as usize];
    let mut extended = 0;
    for y in 0..SIZE.1 {
        for x in 0..SIZE.0 {
            let i = (y * SIZE.0 + x) as usize;
            let p = at(x, y);
            if y + 1 < top || y > bottom + 1 {
                // Above and below the ball nothing moves across: exactly black.
                assert_eq!(p[0], 0.0, "({x}, {y}) above or below the ball: {p:?}");
            } else if !mask[i] && p[0] > 0.05 {
                extended += 1;
            }
        }
    }
    // The silhouette extends over the still sky beside it, on both sides.
    assert!(
        extended > 40,
        "only {extended} sky pixels beside the ball took its blur"
    );
    let middle = (top + bottom) / 2;
    let row: Vec<f32> = (0..SIZE.0).map(|x| at(x, middle)[0]).collect();
    let left = row.iter().position(|v| *v > 0.05).expect("ball in the row");
    let right = row
        .iter()
        .rposition(|v| *v > 0.05)
        .expect("ball in the row");
    let (ball_left, ball_right) = (
        (0..SIZE.0)
            .position(|x| mask[(middle * SIZE.0 + x) as usize])
            .expect("ball"),
        (0..SIZE.0)
            .rposition(|x| mask[(middle * SIZE.0 + x) as usize])
            .expect("ball"),
    );
    assert!(
        left + 2 < ball_left && right > ball_right + 2,
        "{left}..{right} vs ball {ball_left}..{ball_right}"
    );
    // And the edges became ramps, not steps.
    assert!(
        row.iter().filter(|v| **v > 0.1 && **v < 0.9).count() >= 4,
        "{row:?}"
    );
}

#[test]
fn nothing_moving_costs_a_copy() {
    let (out, mask, blurred, skipped) = blur(Vec3::ZERO, MotionBlurSettings::default());
    assert_eq!((blurred, skipped), (0, 1));
    for (p, m) in out.pixels.iter().zip(&mask) {
        assert_eq!(p[0], if *m { 1.0 } else { 0.0 });
    }
}

#[test]
fn a_closed_shutter_costs_a_copy() {
    let (_, _, blurred, skipped) = blur(
        Vec3::new(-0.5, 0.0, 0.0),
        MotionBlurSettings {
            shutter_angle: 0.0,
            ..Default::default()
        },
    );
    assert_eq!((blurred, skipped), (0, 1));
}

#[test]
fn thousands_of_pixels_a_frame_blur_no_further_than_a_tile() {
    let settings = MotionBlurSettings {
        shutter_angle: 360.0,
        ..Default::default()
    };
    let (out, mask, blurred, _) = blur(Vec3::new(-1000.0, 300.0, 0.0), settings);
    assert_eq!(blurred, 1);
    let (lo, hi) = range(&out);
    assert!(lo >= 0.0 && hi <= 1.0 + 1e-3, "{lo}..{hi}");
    // Nothing further than one tile (plus the neighbour-max tile) from the ball moved.
    let k = settings.tile_size as f32 * 2.0;
    for (i, p) in out.pixels.iter().enumerate() {
        let (x, y) = ((i as u32 % SIZE.0) as f32, (i as u32 / SIZE.0) as f32);
        let near = mask.iter().enumerate().any(|(j, m)| {
            *m && ((j as u32 % SIZE.0) as f32 - x).abs() <= k
                && ((j as u32 / SIZE.0) as f32 - y).abs() <= k
        });
        if !near {
            assert_eq!(p[0], 0.0, "({x}, {y})");
        }
    }
}
