//! Weighted blended transparency: alpha 0 leaves the opaque image exactly,
//! alpha 1 covers it, alpha 0.5 front and back faces reveal a quarter of it;
//! the opaque depth hides what is behind; 100 overlapping layers, and
//! layers at the near and far planes, neither overflow nor make NaN.

mod post_common;

use std::sync::Arc;

use glam::{Mat4, Vec3};
use post_common::*;
use spreadlight_render::Renderer;
use spreadlight_render::gbuffer::{DrawBatch, InstanceInput, Layer, LayerFeatures};
use spreadlight_render::mesh::primitives::{SphereParams, sphere};
use spreadlight_render::post::transparency::{DRAWN, SKIPPED};
use spreadlight_render::post::{Transparency, TransparencySettings};
use spreadlight_render::readback::ImageF32;
use spreadlight_render::renderer::test_renderer;

const SIZE: (u32, u32) = (48, 48);
const GREEN: [f32; 4] = [0.0, 1.0, 0.0, 1.0];

/// Transparent spheres (centre, radius, colour with alpha).
fn glass(renderer: &Renderer, spheres: &[(Vec3, f32, [f32; 4])]) -> Arc<Layer> {
    let mesh = renderer
        .meshes
        .upload(
            &renderer.gpu,
            &sphere(SphereParams {
                radius: 1.0,
                sectors: 24,
                stacks: 12,
            }),
        )
        .expect("upload");
    let instances = spheres
        .iter()
        .map(|&(c, r, color)| {
            let t = Mat4::from_translation(c) * Mat4::from_scale(Vec3::splat(r));
            InstanceInput {
                transform: t,
                previous_transform: t,
                color,
                material_id: 0,
                object_id: 0,
            }
        })
        .collect();
    Arc::new(
        Layer::new(
            None,
            vec![DrawBatch { mesh, instances }],
            LayerFeatures::default(),
            None,
        )
        .expect("layer"),
    )
}

/// Unlit: ambient 1, no key light, so a layer shows exactly its colour.
fn unlit() -> TransparencySettings {
    TransparencySettings {
        ambient: Vec3::ONE,
        light_color: Vec3::ZERO,
        ..Default::default()
    }
}

/// An opaque ball (radius 0.5 at the origin, seen from z = 8) under a green "lit" image, with `spheres` over it.
fn composite(
    spheres: &[(Vec3, f32, [f32; 4])],
    settings: TransparencySettings,
) -> (ImageF32, u64, u64) {
    let renderer = test_renderer();
    let opaque = balls(&renderer, &[Ball::still(Vec3::ZERO, 0.5)]);
    let g = gbuffer(
        &renderer,
        opaque,
        look(Vec3::new(0.0, 0.0, 8.0), Vec3::ZERO, 0.6, 1.0),
        None,
    );
    let lit = image(&renderer, SIZE, |_, _| GREEN);
    let layers = if spheres.is_empty() {
        vec![]
    } else {
        vec![glass(&renderer, spheres)]
    };
    let pass = Transparency::new(&renderer, None, lit.texture_ref(), g, layers, settings);
    let (report, out) = render(&renderer, pass.as_ref(), &pass.output, SIZE);
    (out, report.counter(DRAWN), report.counter(SKIPPED))
}

fn at(image: &ImageF32, x: u32, y: u32) -> [f32; 4] {
    image.pixels[(y * SIZE.0 + x) as usize]
}

#[test]
fn alpha_zero_changes_nothing_and_nothing_transparent_costs_a_copy() {
    let (out, drawn, skipped) = composite(
        &[(Vec3::new(0.0, 0.0, 2.0), 1.0, [1.0, 0.0, 0.0, 0.0])],
        unlit(),
    );
    assert_eq!((drawn, skipped), (1, 0));
    assert!(out.pixels.iter().all(|p| p[..3] == GREEN[..3]));
    let (out, drawn, skipped) = composite(&[], unlit());
    assert_eq!((drawn, skipped), (0, 1));
    assert!(out.pixels.iter().all(|p| p[..3] == GREEN[..3]));
}

#[test]
fn alpha_one_covers_and_alpha_half_front_and_back_reveal_a_quarter() {
    let (out, _, _) = composite(
        &[(Vec3::new(0.0, 0.0, 2.0), 0.5, [1.0, 0.0, 0.0, 1.0])],
        unlit(),
    );
    let c = at(&out, 24, 24);
    assert!((c[0] - 1.0).abs() < 0.01 && c[1].abs() < 0.01, "{c:?}");
    assert_eq!(at(&out, 1, 1)[..3], GREEN[..3], "outside the sphere");
    let (out, _, _) = composite(
        &[(Vec3::new(0.0, 0.0, 2.0), 0.5, [1.0, 0.0, 0.0, 0.5])],
        unlit(),
    );
    let c = at(&out, 24, 24);
    // Two faces of alpha 0.5: 1/4 of the green shows through.
    assert!(
        (c[0] - 0.75).abs() < 0.02 && (c[1] - 0.25).abs() < 0.02,
        "{c:?}"
    );
}

#[test]
fn the_opaque_depth_hides_what_is_behind() {
    // A red sphere behind the opaque ball, wider than it: red around the ball, none on it.
    let (out, _, _) = composite(
        &[(Vec3::new(0.0, 0.0, -3.0), 1.5, [1.0, 0.0, 0.0, 1.0])],
        unlit(),
    );
    let center = at(&out, 24, 24);
    assert_eq!(
        center[..3],
        GREEN[..3],
        "the ball hides the sphere: {center:?}"
    );
    let beside = (0..SIZE.0)
        .map(|x| at(&out, x, 24)[0])
        .fold(0.0f32, f32::max);
    assert!(beside > 0.99, "the sphere shows beside the ball: {beside}");
}

#[test]
fn a_hundred_layers_and_the_near_and_far_planes_stay_finite() {
    // 100 bright layers at the same place, the worst case for the weight sum.
    let hundred: Vec<_> = (0..100)
        .map(|i| {
            (
                Vec3::new(0.0, 0.0, 2.0 + i as f32 * 1e-3),
                1.0,
                [600.0, 600.0, 600.0, 1.0],
            )
        })
        .collect();
    let (out, drawn, _) = composite(&hundred, unlit());
    assert_eq!(drawn, 100);
    let (lo, hi) = range(&out);
    assert!(lo >= 0.0 && hi <= 65000.0, "{lo}..{hi}");
    assert!(
        (at(&out, 24, 24)[0] - 600.0).abs() < 5.0,
        "{:?}",
        at(&out, 24, 24)
    );
    // 100 layers of alpha 0.5: the green is all but gone, and every colour is the layers'.
    let half: Vec<_> = (0..100)
        .map(|i| {
            (
                Vec3::new(0.0, 0.0, 2.0 + i as f32 * 1e-2),
                1.0,
                [1.0, 0.0, 1.0, 0.5],
            )
        })
        .collect();
    let (out, _, _) = composite(&half, unlit());
    let c = at(&out, 24, 24);
    assert!((c[0] - 1.0).abs() < 0.02 && c[1] < 0.01, "{c:?}");
    // Layers at the near plane (the camera inside a sphere) and at the far plane.
    let planes = [
        (Vec3::new(0.0, 0.0, 8.0), 0.1001, [1.0, 0.0, 0.0, 0.5]),
        (Vec3::new(0.0, 0.0, -91.0), 3.0, [0.0, 0.0, 1.0, 0.5]),
        (Vec3::new(0.0, 0.0, 7.85), 0.06, [1e6, 1e6, 1e6, 1.0]),
    ];
    let (out, _, _) = composite(&planes, TransparencySettings::default());
    let (lo, hi) = range(&out);
    assert!(lo >= 0.0 && hi <= 65000.0, "{lo}..{hi}");
}
