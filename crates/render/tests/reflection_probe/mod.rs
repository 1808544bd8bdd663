//! `EnvironmentProbe` through Reflection: a mirror ball beside a red box
//! shows the box on its side, the probe renders again only when what it
//! sees changed (not when the camera moves), every N frames or once as
//! asked, a box volume corrects for parallax, and the hard cases (a probe
//! inside the box, a zero-size volume, no light direction) stay finite.

use std::sync::Arc;

use glam::{Mat4, Vec2, Vec3};
use spreadlight_render::environment::{
    Environment, EnvironmentQuality, EnvironmentSource, ProbeScene, ProbeSettings, ProbeUpdate,
    ProbeVolume, Reflection, ReflectionMode,
};
use spreadlight_render::gbuffer::{GBuffer, Layer};
use spreadlight_render::material::{Material, MaterialWorld};
use spreadlight_render::readback::{ImageF32, read_texture_layer, render_and_read};
use spreadlight_render::renderer::test_renderer;
use spreadlight_render::scenes::{MirrorBesideBox, mirror_beside_box};
use spreadlight_render::{FrameReport, Renderer, SizeRule};

use super::reflection_scene::{SIZE, camera, reflective, world_position};

const BALL: Vec3 = Vec3::new(0.0, 0.6, 0.0);
const RADIUS: f32 = 0.6;
const EYE: Vec3 = Vec3::new(0.0, 1.2, 4.0);
const QUALITY: EnvironmentQuality = EnvironmentQuality {
    cube_size: 32,
    samples: 16,
};

fn scene(renderer: &Renderer) -> MirrorBesideBox {
    mirror_beside_box(renderer, (BALL, RADIUS), Vec2::new(1.6, 0.0), 0.8, 8.0).expect("uploads")
}

fn probe(
    renderer: &Renderer,
    owner: Option<u32>,
    surroundings: &Arc<Layer>,
    settings: ProbeSettings,
) -> Arc<Environment> {
    let scene = ProbeScene::new(vec![surroundings.clone()], settings).expect("valid");
    Environment::new(renderer, owner, EnvironmentSource::Probe(Arc::new(scene)), QUALITY)
}

fn at_ball() -> ProbeSettings {
    ProbeSettings {
        position: BALL,
        ..Default::default()
    }
}

/// The mirror ball's reflection from `eye`: the report, the specular and the depth.
fn mirror(
    renderer: &Renderer,
    s: &MirrorBesideBox,
    eye: Vec3,
    environment: Arc<Environment>,
) -> (FrameReport, ImageF32, ImageF32, Arc<GBuffer>) {
    let g = GBuffer::new(
        renderer,
        None,
        vec![s.ball.clone(), s.surroundings.clone()],
        camera(eye, BALL),
        None,
        SizeRule::Relative(1.0),
    );
    let world = vec![reflective(0.0, 1.0), Material::default_material()];
    let r = Reflection::new(
        renderer,
        None,
        g.clone(),
        MaterialWorld::new(renderer, world),
        environment,
        ReflectionMode::Reflect,
    );
    let (report, images) = render_and_read(
        renderer,
        r.as_ref(),
        SIZE,
        &[&r.specular, &g.targets.depth],
    )
    .expect("renders");
    assert!(report.errors.is_empty(), "{:?}", report.errors);
    let mut images = images.into_iter();
    let specular = images.next().expect("specular");
    assert!(specular.all_finite(), "NaN or infinity in the reflection");
    (report, specular, images.next().expect("depth"), g)
}

/// The mean specular over the ball's pixels whose world x is beyond `side` (sign: which side).
fn ball_side(g: &GBuffer, specular: &ImageF32, depth: &ImageF32, side: f32) -> Vec3 {
    let (mut sum, mut n) = (Vec3::ZERO, 0);
    for y in 0..SIZE.1 {
        for x in 0..SIZE.0 {
            let d = depth.pixel(x, y)[0];
            if d <= 0.0 {
                continue;
            }
            let p = world_position(g, x, y, d);
            if ((p - BALL).length() - RADIUS).abs() > 0.05 || p.x * side.signum() < side.abs() {
                continue;
            }
            sum += Vec3::from_slice(&specular.pixel(x, y)[..3]);
            n += 1;
        }
    }
    assert!(n >= 8, "{n} ball pixels on side {side}");
    sum / n as f32
}

#[test]
fn a_mirror_sphere_beside_a_red_box_shows_the_box() {
    let renderer = test_renderer();
    let s = scene(&renderer);
    let (report, specular, depth, g) = mirror(
        &renderer,
        &s,
        EYE,
        probe(&renderer, None, &s.surroundings, at_ball()),
    );
    assert_eq!(report.counter("environment probe rendered"), 1);
    let right = ball_side(&g, &specular, &depth, 0.3);
    let left = ball_side(&g, &specular, &depth, -0.3);
    assert!(
        right.x > 2.0 * right.y && right.x > 2.0 * right.z,
        "the box's side is red: {right}"
    );
    assert!(left.x < 1.2 * left.z, "the other side is not: {left}");
}

#[test]
fn a_probe_renders_again_only_when_what_it_sees_changed() {
    let renderer = test_renderer();
    let s = scene(&renderer);
    let owner = Some(501);
    // The node evaluated again: new recipes, layers equal but not the same Arcs.
    let again = |layer: &Arc<Layer>| Arc::new((**layer).clone());
    let frame = |s: &MirrorBesideBox, eye: Vec3, settings: ProbeSettings, owner| {
        let env = probe(&renderer, owner, &again(&s.surroundings), settings);
        let (report, ..) = mirror(&renderer, s, eye, env);
        (
            report.counter("environment probe rendered"),
            report.counter("environment probe reused"),
        )
    };
    assert_eq!(frame(&s, EYE, at_ball(), owner), (1, 0), "first frame");
    assert_eq!(frame(&s, EYE, at_ball(), owner), (0, 1), "still scene");
    let moved_eye = Vec3::new(2.0, 2.0, 3.0);
    assert_eq!(frame(&s, moved_eye, at_ball(), owner), (0, 1), "a moved camera");
    let mut moved = Layer::clone(&s.surroundings);
    moved.batches[0].instances[0].transform =
        Mat4::from_translation(Vec3::new(1.7, 0.4, 0.2)) * Mat4::from_scale(Vec3::splat(0.8));
    let moved = MirrorBesideBox {
        ball: s.ball.clone(),
        surroundings: Arc::new(moved),
    };
    assert_eq!(frame(&moved, EYE, at_ball(), owner), (1, 0), "a moved box");
    assert_eq!(frame(&moved, EYE, at_ball(), owner), (0, 1), "still again");

    // Every 3 frames: the first, then every third, changed or not.
    let every = ProbeSettings {
        update: ProbeUpdate::EveryNFrames(3),
        ..at_ball()
    };
    let counts: Vec<_> = (0..5)
        .map(|_| frame(&s, EYE, every, Some(502)).0)
        .collect();
    assert_eq!(counts, [1, 0, 0, 1, 0]);
    // Once: a moved box does not render it again.
    let once = ProbeSettings {
        update: ProbeUpdate::Once,
        ..at_ball()
    };
    assert_eq!(frame(&s, EYE, once, Some(503)), (1, 0));
    assert_eq!(frame(&moved, EYE, once, Some(503)), (0, 1));
}

/// A probe away from the ball sees the box from the wrong place; a box
/// volume around the scene moves the reflection back towards what a probe
/// at the ball sees.
#[test]
fn a_box_volume_corrects_an_offset_probe_for_parallax() {
    let renderer = test_renderer();
    let s = scene(&renderer);
    let reference = mirror(&renderer, &s, EYE, probe(&renderer, None, &s.surroundings, at_ball())).1;
    let offset = Vec3::new(-1.0, 0.6, 0.5);
    let error = |volume: ProbeVolume| {
        let settings = ProbeSettings {
            position: offset,
            volume,
            ..Default::default()
        };
        let image = mirror(&renderer, &s, EYE, probe(&renderer, None, &s.surroundings, settings)).1;
        let sum: f32 = image
            .pixels
            .iter()
            .zip(&reference.pixels)
            .map(|(a, b)| (Vec3::from_slice(&a[..3]) - Vec3::from_slice(&b[..3])).length_squared())
            .sum();
        (sum / image.pixels.len() as f32).sqrt()
    };
    let uncorrected = error(ProbeVolume::Infinite);
    let corrected = error(ProbeVolume::Box {
        center: Vec3::new(0.4, 1.0, 0.0),
        size: Vec3::new(3.2, 2.0, 3.0),
    });
    assert!(
        corrected < 0.8 * uncorrected,
        "parallax-corrected error {corrected} vs uncorrected {uncorrected}"
    );
    // A zero-size volume is no volume: exactly the uncorrected image.
    let flat = error(ProbeVolume::Box {
        center: Vec3::ZERO,
        size: Vec3::new(3.0, 0.0, 3.0),
    });
    assert_eq!(flat, uncorrected);
}

#[test]
fn a_probe_inside_the_box_sees_its_inside_and_stays_finite() {
    let renderer = test_renderer();
    let s = scene(&renderer);
    let mut inside = ProbeSettings {
        position: Vec3::new(1.6, 0.4, 0.0),
        ..Default::default()
    };
    // No light direction at all: the sun falls back to straight down, not NaN.
    inside.lighting.sun_direction = Vec3::ZERO;
    let env = probe(&renderer, None, &s.surroundings, inside);
    let (report, ..) = mirror(&renderer, &s, EYE, env.clone());
    assert_eq!(report.counter("environment probe rendered"), 1);
    let maps = env.maps().expect("built");
    for face in 0..6 {
        let image = read_texture_layer(&renderer.gpu, &maps.base, face, 0).expect("reads");
        assert!(image.all_finite(), "face {face}");
        let mean = image
            .pixels
            .iter()
            .fold(Vec3::ZERO, |a, p| a + Vec3::from_slice(&p[..3]))
            / image.pixels.len() as f32;
        assert!(
            mean.x > 3.0 * mean.y && mean.x > 0.0,
            "face {face} sees the red inside: {mean}"
        );
    }
}

/// Nothing of a probe runs in a frame without one.
#[test]
fn a_frame_without_a_probe_has_no_probe_pass() {
    let renderer = test_renderer();
    let s = scene(&renderer);
    let sky = Environment::new(
        &renderer,
        None,
        EnvironmentSource::Sky(Default::default()),
        QUALITY,
    );
    let (report, ..) = mirror(&renderer, &s, EYE, sky);
    assert!(report.passes.iter().all(|p| p.kind != "EnvironmentProbe"));
    assert_eq!(report.counter("environment probe rendered"), 0);
    let (report, ..) = mirror(
        &renderer,
        &s,
        EYE,
        probe(&renderer, None, &s.surroundings, at_ball()),
    );
    assert!(report.passes.iter().any(|p| p.kind == "EnvironmentProbe"));
}
