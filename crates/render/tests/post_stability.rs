//! The post nodes' numerical stability: HDR input of 0, 1e6, NaN and
//! infinity through every node; focus at 0 and at infinity; the smallest
//! f-stop; velocities of thousands of pixels a frame; glare threshold 0. No
//! NaN or infinity reaches any target, and nothing exceeds half-float range.

use crate::post_common;

use std::sync::Arc;

use glam::{Vec2, Vec3};
use post_common::*;
use spreadlight_render::gbuffer::GBuffer;
use spreadlight_render::post::dof::MIN_F_STOP;
use spreadlight_render::post::{
    Autofocus, Dof, DofSettings, Focus, Fxaa, FxaaQuality, Glare, GlareSettings, MotionBlur,
    MotionBlurSettings, Taa, TaaSettings, Transparency, TransparencySettings,
};
use spreadlight_render::readback::ImageF32;
use spreadlight_render::renderer::test_renderer;
use spreadlight_render::{Renderer, TextureRef};

const SIZE: (u32, u32) = (48, 32);

/// A near ball flying sideways thousands of pixels a frame before a far one, against the sky.
fn scene(renderer: &Renderer) -> Arc<GBuffer> {
    let layer = balls(
        renderer,
        &[
            Ball {
                center: Vec3::new(0.0, 0.0, 2.0),
                previous: Vec3::new(-500.0, 20.0, 2.0),
                radius: 0.5,
            },
            Ball::still(Vec3::new(1.0, 0.0, -20.0), 3.0),
        ],
    );
    gbuffer(
        renderer,
        layer,
        look(Vec3::new(0.0, 0.0, 6.0), Vec3::ZERO, 0.8, 1.5),
        None,
    )
}

fn constant(renderer: &Renderer, value: f32) -> TextureRef {
    image(renderer, SIZE, move |x, y| {
        // Half the pixels the value, half 1: edges for every filter to work on.
        let v = if (x / 4 + y / 4).is_multiple_of(2) {
            value
        } else {
            1.0
        };
        [v, v * 0.5, v, 1.0]
    })
    .texture_ref()
}

fn check(name: &str, image: &ImageF32) {
    assert!(image.all_finite(), "{name}: NaN or infinity");
    let (lo, hi) = range(image);
    assert!(
        lo >= -65000.0 && hi <= 65000.0,
        "{name}: {lo}..{hi} beyond half floats"
    );
}

/// Every post node over `input`: each one's output checked.
fn every_node(renderer: &Renderer, input: TextureRef, label: &str) {
    let g = scene(renderer);
    let dof = Dof::new(
        renderer,
        None,
        input.clone(),
        g.clone(),
        Focus::Distance(4.0),
        None,
        DofSettings {
            focal_length_mm: 200.0,
            f_stop: MIN_F_STOP,
            ..Default::default()
        },
    );
    check(
        &format!("{label} DOF"),
        &render(renderer, dof.as_ref(), &dof.output, SIZE).1,
    );
    let af = Autofocus::new(renderer, None, g.clone(), Vec2::splat(0.5), 2.0, 1.0 / 60.0);
    let auto = Dof::new(
        renderer,
        None,
        input.clone(),
        g.clone(),
        Focus::Texture(af.texture()),
        None,
        DofSettings::default(),
    );
    check(
        &format!("{label} DOF autofocus"),
        &render(renderer, auto.as_ref(), &auto.output, SIZE).1,
    );
    let blur = MotionBlur::new(
        renderer,
        None,
        input.clone(),
        g.clone(),
        MotionBlurSettings {
            shutter_angle: 360.0,
            ..Default::default()
        },
    );
    check(
        &format!("{label} MotionBlur"),
        &render(renderer, blur.as_ref(), &blur.output, SIZE).1,
    );
    for threshold in [0.0, 1.0] {
        let glare = Glare::new(
            renderer,
            None,
            input.clone(),
            GlareSettings {
                threshold,
                intensity: 10.0,
                levels: 8,
                ..Default::default()
            },
        );
        check(
            &format!("{label} Glare {threshold}"),
            &render(renderer, glare.as_ref(), &glare.output, SIZE).1,
        );
    }
    let taa = Taa::new(
        renderer,
        None,
        input.clone(),
        g.clone(),
        TaaSettings {
            sharpen: 2.0,
            ..Default::default()
        },
        None,
    );
    check(
        &format!("{label} TAA"),
        &render(renderer, taa.as_ref(), &taa.output, SIZE).1,
    );
    let glass = balls(renderer, &[Ball::still(Vec3::new(0.0, 0.0, 3.0), 1.0)]);
    let layers = vec![glass];
    let clear = Transparency::new(
        renderer,
        None,
        input.clone(),
        g.clone(),
        layers,
        TransparencySettings::default(),
    );
    check(
        &format!("{label} Transparency"),
        &render(renderer, clear.as_ref(), &clear.output, SIZE).1,
    );
    let fxaa = Fxaa::new(renderer, None, input, FxaaQuality::High, 0.75);
    check(
        &format!("{label} FXAA"),
        &render(renderer, fxaa.as_ref(), &fxaa.output, SIZE).1,
    );
}

#[test]
fn hdr_zero_huge_nan_and_infinity_through_every_node() {
    let renderer = test_renderer();
    for value in [0.0, 1e6, f32::NAN, f32::INFINITY, -1e6] {
        every_node(
            &renderer,
            constant(&renderer, value),
            &format!("input {value}"),
        );
    }
}

#[test]
fn focus_at_zero_and_infinity_and_the_widest_aperture_stay_finite() {
    let renderer = test_renderer();
    let g = scene(&renderer);
    let input = constant(&renderer, 2.0);
    for focus in [0.0, -1.0, f32::INFINITY, 1e-20, 1e20] {
        for f_stop in [MIN_F_STOP, 0.0, f32::INFINITY] {
            let settings = DofSettings {
                focal_length_mm: 300.0,
                f_stop,
                samples: 8,
                max_radius: 128.0,
                ..Default::default()
            };
            let dof = Dof::new(
                &renderer,
                None,
                input.clone(),
                g.clone(),
                Focus::Distance(focus),
                None,
                settings,
            );
            check(
                &format!("focus {focus} f/{f_stop}"),
                &render(&renderer, dof.as_ref(), &dof.output, SIZE).1,
            );
        }
    }
}

#[test]
fn bloom_of_a_huge_image_stays_within_half_floats() {
    let renderer = test_renderer();
    let input = image(&renderer, SIZE, |_, _| [1e6, 1e6, 1e6, 1.0]).texture_ref();
    let glare = Glare::new(
        &renderer,
        None,
        input,
        GlareSettings {
            threshold: 0.0,
            intensity: 1000.0,
            spread: 1.0,
            levels: 12,
            ..Default::default()
        },
    );
    let (_, out) = render(&renderer, glare.as_ref(), &glare.output, SIZE);
    check("huge bloom", &out);
    assert!(
        out.pixels
            .iter()
            .all(|p| p[0] == 65000.0 || (p[0] - 65000.0).abs() < 64.0),
        "saturates, never overflows"
    );
}
