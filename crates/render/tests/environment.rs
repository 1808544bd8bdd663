//! The environment passes. `Sky`: the procedural sky fills exactly the
//! pixels the G-buffer left empty, with the zenith above the horizon, the
//! ground below, and the sun's disk where the light comes from. `Fog`: its
//! closed form matches a numerical integral of its density along each ray.
//! Bad settings never make NaN.

use std::sync::Arc;

use glam::Vec3;
use spreadlight_render::camera::CameraInput;
use spreadlight_render::environment::{Fog, FogSettings, Sky, SkySettings};
use spreadlight_render::gbuffer::GBuffer;
use spreadlight_render::readback::{ImageF32, render_and_read};
use spreadlight_render::renderer::test_renderer;
use spreadlight_render::scenes::balls_on_floor;
use spreadlight_render::static_texture::StaticTexture;
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

/// The "lit image" the environment passes run over, at `SIZE`.
fn lit_image(renderer: &Renderer, pixels: Vec<[f32; 4]>) -> Arc<StaticTexture> {
    StaticTexture::from_rgba32f(&renderer.gpu, SIZE.0, SIZE.1, &pixels, "lit")
}

fn sky(renderer: &Renderer, settings: SkySettings) -> (ImageF32, ImageF32) {
    let g = gbuffer(renderer);
    // The "lit image": constant magenta, to see what passes through.
    let lit = lit_image(
        renderer,
        vec![[1.0, 0.0, 1.0, 1.0]; (SIZE.0 * SIZE.1) as usize],
    );
    let sky = Sky::pass(renderer, None, g.clone(), lit.texture_ref(), settings);
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

/// The fog over a white image with black fog: each pixel is its transmittance.
fn fog_over_white(
    renderer: &Renderer,
    settings: FogSettings,
) -> (ImageF32, ImageF32, Arc<GBuffer>) {
    let g = gbuffer(renderer);
    let lit = lit_image(
        renderer,
        vec![[1.0, 1.0, 1.0, 1.0]; (SIZE.0 * SIZE.1) as usize],
    );
    let fog = Fog::pass(renderer, None, g.clone(), lit.texture_ref(), settings);
    let (report, images) = render_and_read(
        renderer,
        fog.as_ref(),
        SIZE,
        &[&fog.output, &g.targets.depth],
    )
    .expect("renders");
    assert!(report.errors.is_empty(), "{:?}", report.errors);
    let mut images = images.into_iter();
    (
        images.next().expect("fog"),
        images.next().expect("depth"),
        g,
    )
}

#[test]
fn fog_matches_a_numerical_integral_of_its_density_along_each_ray() {
    let renderer = test_renderer();
    let settings = FogSettings {
        color: Vec3::ZERO,
        density: 0.3,
        height_falloff: 0.8,
        base_height: 0.5,
        start: 0.5,
    };
    let (image, depth, g) = fog_over_white(&renderer, settings);
    let camera = g.camera;
    let inverse =
        (spreadlight_render::camera::reverse_z(camera.projection) * camera.view).inverse();
    let eye = camera.view.inverse().w_axis.truncate();
    let mut checked = 0;
    for y in (0..SIZE.1).step_by(5) {
        for x in (0..SIZE.0).step_by(5) {
            let i = (y * SIZE.0 + x) as usize;
            let d = depth.pixels[i][0];
            if d <= 0.0 {
                assert_eq!(image.pixels[i][0], 1.0, "the sky passes through");
                continue;
            }
            let ndc = glam::Vec4::new(
                (x as f32 + 0.5) / SIZE.0 as f32 * 2.0 - 1.0,
                1.0 - (y as f32 + 0.5) / SIZE.1 as f32 * 2.0,
                d,
                1.0,
            );
            let h = inverse * ndc;
            let p = h.truncate() / h.w;
            // Midpoint rule, 4,000 steps from the start distance to the surface.
            let (dir, length) = ((p - eye).normalize(), (p - eye).length());
            let steps = 4000;
            let span = (length - settings.start).max(0.0);
            let dt = span / steps as f32;
            let depth_sum: f32 = (0..steps)
                .map(|k| {
                    let q = eye + dir * (settings.start + (k as f32 + 0.5) * dt);
                    settings.density
                        * (-settings.height_falloff * (q.y - settings.base_height)).exp()
                        * dt
                })
                .sum();
            let expected = (-depth_sum).exp();
            let got = image.pixels[i][0];
            assert!(
                (got - expected).abs() < 2e-3,
                "pixel ({x}, {y}): {got} vs {expected}"
            );
            checked += 1;
        }
    }
    assert!(checked > 20, "{checked} pixels checked");
}

#[test]
fn fog_hard_cases_stay_finite_and_in_range() {
    let renderer = test_renderer();
    for settings in [
        FogSettings {
            density: 0.0,
            ..Default::default()
        },
        FogSettings {
            density: 1e6,
            color: Vec3::splat(0.25),
            ..Default::default()
        },
        FogSettings {
            height_falloff: 0.0,
            ..Default::default()
        },
        FogSettings {
            height_falloff: 1e3,
            base_height: -1e9,
            ..Default::default()
        },
        FogSettings {
            start: 1e9,
            ..Default::default()
        },
        FogSettings {
            density: f32::NAN,
            height_falloff: f32::INFINITY,
            color: Vec3::splat(f32::NAN),
            ..Default::default()
        },
    ] {
        let (image, _, _) = fog_over_white(&renderer, settings);
        assert!(image.all_finite(), "{settings:?}");
        assert!(
            image
                .pixels
                .iter()
                .all(|p| (0.0..=1.0 + 1e-6).contains(&p[0])),
            "{settings:?}"
        );
    }
    // Infinitely dense fog: every surface pixel is the fog's colour.
    let (image, depth, _) = fog_over_white(
        &renderer,
        FogSettings {
            density: 1e6,
            color: Vec3::splat(0.25),
            ..Default::default()
        },
    );
    for (p, d) in image.pixels.iter().zip(&depth.pixels) {
        if d[0] > 0.0 {
            assert!((p[0] - 0.25).abs() < 1e-3, "{p:?}");
        }
    }
}

/// Fog and a Sky over it, in either order, run as one pass when nothing else
/// reads the inner one's image, with the image of the two passes (read
/// together with the inner image, they stay two).
#[test]
fn fog_and_sky_over_each_other_are_one_pass_with_the_image_of_two() {
    use spreadlight_render::environment::FOG_AND_SKY;
    let renderer = test_renderer();
    let g = gbuffer(&renderer);
    let lit = lit_image(
        &renderer,
        (0..SIZE.0 * SIZE.1)
            // Half-float values: what a pass between would have stored.
            .map(|i| [(i % 7) as f32 * 0.25, 0.5, (i % 5) as f32 * 0.125, 1.0])
            .collect::<Vec<_>>(),
    );
    let fog_settings = FogSettings {
        density: 0.2,
        ..Default::default()
    };
    for sky_over_fog in [true, false] {
        let (outer, inner_output) = if sky_over_fog {
            let fog = Fog::pass(
                &renderer,
                Some(1),
                g.clone(),
                lit.texture_ref(),
                fog_settings,
            );
            let sky = Sky::pass(
                &renderer,
                Some(2),
                g.clone(),
                fog.texture(),
                SkySettings::default(),
            );
            (sky, fog.output.clone())
        } else {
            let sky = Sky::pass(
                &renderer,
                Some(2),
                g.clone(),
                lit.texture_ref(),
                SkySettings::default(),
            );
            let fog = Fog::pass(&renderer, Some(1), g.clone(), sky.texture(), fog_settings);
            (fog, sky.output.clone())
        };
        let (one, images) =
            render_and_read(&renderer, outer.as_ref(), SIZE, &[&outer.output]).expect("renders");
        assert!(one.errors.is_empty(), "{:?}", one.errors);
        assert_eq!(one.counter(FOG_AND_SKY), 1);
        let names: Vec<&str> = one.passes.iter().map(|p| p.name.as_str()).collect();
        assert!(
            names.contains(&"Fog #1 and Sky #2") || names.contains(&"Sky #2 and Fog #1"),
            "{names:?}"
        );
        // The pass is both nodes' work.
        let merged = one
            .passes
            .iter()
            .find(|p| p.partner.is_some())
            .expect("merged");
        let mut owners = [merged.owner, merged.partner];
        owners.sort();
        assert_eq!(owners, [Some(1), Some(2)]);
        let (two, apart) = render_and_read(
            &renderer,
            outer.as_ref(),
            SIZE,
            &[&outer.output, &inner_output],
        )
        .expect("renders");
        assert_eq!(two.counter(FOG_AND_SKY), 0, "the inner image is read too");
        assert!(
            images[0].pixels == apart[0].pixels,
            "sky over fog {sky_over_fog}: one pass or two, the same image"
        );
        // Fog reached the surfaces and the sky the background.
        let sky_pixel = images[0].pixel(SIZE.0 / 2, 2);
        assert!(sky_pixel[1] != 0.5, "{sky_pixel:?}");
    }
}

/// Only a Fog and a Sky on the same G-buffer run as one: a Sky over a Sky,
/// or a Fog over a Sky of another G-buffer, stay two passes.
#[test]
fn only_fog_and_sky_of_one_gbuffer_run_as_one_pass() {
    use spreadlight_render::environment::FOG_AND_SKY;
    let renderer = test_renderer();
    let (g, other) = (gbuffer(&renderer), gbuffer(&renderer));
    let lit = lit_image(
        &renderer,
        vec![[0.5, 0.5, 0.5, 1.0]; (SIZE.0 * SIZE.1) as usize],
    );
    let sky = || SkySettings::default();
    let under = Sky::pass(&renderer, Some(1), g.clone(), lit.texture_ref(), sky());
    let sky_over_sky = Sky::pass(&renderer, Some(2), g.clone(), under.texture(), sky());
    let elsewhere = Sky::pass(&renderer, Some(3), other, lit.texture_ref(), sky());
    let fog_over_other = Fog::pass(
        &renderer,
        Some(4),
        g,
        elsewhere.texture(),
        FogSettings::default(),
    );
    for outer in [sky_over_sky, fog_over_other] {
        let (report, images) =
            render_and_read(&renderer, outer.as_ref(), SIZE, &[&outer.output]).expect("renders");
        assert!(report.errors.is_empty(), "{:?}", report.errors);
        assert_eq!(report.counter(FOG_AND_SKY), 0);
        let apart = report
            .passes
            .iter()
            .filter(|p| (p.kind == "Sky" || p.kind == "Fog") && p.partner.is_none())
            .count();
        assert_eq!(apart, 2, "{:?}", report.passes);
        assert!(images[0].all_finite());
    }
}
