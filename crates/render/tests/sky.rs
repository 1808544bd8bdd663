//! `Sky`: the procedural sky fills exactly the pixels the G-buffer left
//! empty, with the zenith above the horizon, the ground below, and the sun's
//! disk where the light comes from; bad settings never make NaN.

use std::sync::Arc;

use glam::Vec3;
use spreadlight_render::camera::CameraInput;
use spreadlight_render::environment::{Sky, SkySettings};
use spreadlight_render::gbuffer::GBuffer;
use spreadlight_render::readback::{ImageF32, render_and_read};
use spreadlight_render::renderer::test_renderer;
use spreadlight_render::scenes::balls_on_floor;
use spreadlight_render::texture::{GpuTexture, StaticTexture};
use spreadlight_render::{Renderer, SizeRule};

const SIZE: (u32, u32) = (64, 64);

/// A ball at the origin, seen level from +z: sky above, a far floor below.
fn gbuffer(renderer: &Renderer) -> Arc<GBuffer> {
    let layer =
        balls_on_floor(renderer, &[(Vec3::new(0.0, 1.0, 0.0), 0.5)], 4.0, 24).expect("upload");
    let camera = CameraInput {
        view: glam::camera::rh::view::look_at_mat4(
            Vec3::new(0.0, 1.0, 4.0),
            Vec3::new(0.0, 1.0, 0.0),
            Vec3::Y,
        ),
        projection: glam::camera::rh::proj::directx::perspective(1.2, 1.0, 0.1, 100.0),
    };
    GBuffer::new(
        renderer,
        None,
        vec![layer],
        camera,
        None,
        SizeRule::Relative(1.0),
    )
}

fn sky(renderer: &Renderer, settings: SkySettings) -> (ImageF32, ImageF32) {
    let g = gbuffer(renderer);
    // The "lit image": constant magenta, to see what passes through.
    let lit = StaticTexture::new(GpuTexture::from_rgba32f(
        &renderer.gpu,
        SIZE.0,
        SIZE.1,
        &vec![[1.0, 0.0, 1.0, 1.0]; (SIZE.0 * SIZE.1) as usize],
        "lit",
    ));
    let sky = Sky::new(renderer, None, g.clone(), lit.texture_ref(), settings);
    let (report, images) = render_and_read(
        renderer,
        sky.as_ref(),
        SIZE,
        &[&sky.output, &g.targets.depth],
    )
    .expect("renders");
    assert!(report.errors.is_empty(), "{:?}", report.errors);
    let mut images = images.into_iter();
    (images.next().expect("sky"), images.next().expect("depth"))
}

#[test]
fn the_sky_fills_only_empty_depth_with_zenith_horizon_and_ground() {
    let renderer = test_renderer();
    let settings = SkySettings {
        zenith: Vec3::new(0.0, 0.0, 1.0),
        horizon: Vec3::new(1.0, 1.0, 1.0),
        ground: Vec3::new(0.0, 1.0, 0.0),
        // The sun behind the camera: no disk in view.
        sun_direction: Vec3::new(0.0, -0.3, -1.0),
        ..Default::default()
    };
    let (image, depth) = sky(&renderer, settings);
    assert!(image.all_finite());
    let px = |x: u32, y: u32| image.pixels[(y * SIZE.0 + x) as usize];
    for (p, d) in image.pixels.iter().zip(&depth.pixels) {
        if d[0] > 0.0 {
            assert_eq!(p[..3], [1.0, 0.0, 1.0], "geometry keeps the lit image");
        } else {
            assert!(
                p[0] != 1.0 || p[1] != 0.0 || p[2] != 1.0,
                "empty depth gets the sky"
            );
        }
    }
    // Top of the image: near the zenith (blue dominates); just above the
    // horizon (the middle row, left edge, past the ball): near white.
    let top = px(2, 0);
    assert!(top[2] > top[0] + 0.2, "{top:?}");
    let horizon = px(2, SIZE.1 / 2 - 1);
    assert!(horizon[0] > 0.8 && horizon[1] > 0.8, "{horizon:?}");
}

#[test]
fn the_sun_disk_sits_opposite_the_light_and_bad_settings_stay_finite() {
    let renderer = test_renderer();
    // Light travelling towards +z and down a little: the sun is ahead of the camera, up and to the front.
    let settings = SkySettings {
        sun_direction: Vec3::new(0.0, -0.3, 1.0),
        sun_radius: 0.05,
        sun_color: Vec3::splat(100.0),
        ..Default::default()
    };
    let (image, _) = sky(&renderer, settings);
    let brightest = image.pixels.iter().map(|p| p[0]).fold(0.0f32, f32::max);
    assert!(brightest > 50.0, "the disk is in view: {brightest}");
    for bad in [
        SkySettings {
            sun_direction: Vec3::ZERO,
            ..Default::default()
        },
        SkySettings {
            zenith: Vec3::splat(f32::NAN),
            sun_color: Vec3::splat(f32::INFINITY),
            sun_radius: f32::NAN,
            glow: f32::INFINITY,
            ..Default::default()
        },
        SkySettings {
            sun_color: Vec3::splat(1e9),
            sun_radius: 10.0,
            ..Default::default()
        },
    ] {
        let (image, _) = sky(&renderer, bad);
        assert!(image.all_finite(), "{bad:?}");
        assert!(image.pixels.iter().all(|p| p[0] <= 65000.0), "{bad:?}");
    }
}
