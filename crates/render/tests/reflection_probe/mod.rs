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
const EYE: Vec3 = Vec3::new(0.0, 1.0, 2.4);
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
    Environment::new(
        renderer,
        owner,
        EnvironmentSource::Probe(Arc::new(scene)),
        QUALITY,
    )
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
    let (report, images) =
        render_and_read(renderer, r.as_ref(), SIZE, &[&r.specular, &g.targets.depth])
            .expect("renders");
    assert!(report.errors.is_empty(), "{:?}", report.errors);
    let mut images = images.into_iter();
    let specular = images.next().expect("specular");
    assert!(specular.all_finite(), "NaN or infinity in the reflection");
    (report, specular, images.next().expect("depth"), g)
}

/// The ball's pixels, each with its specular and the world direction it
/// reflects (from the ball's centre, where the probe is).
fn ball_pixels(g: &GBuffer, specular: &ImageF32, depth: &ImageF32) -> Vec<(Vec3, Vec3)> {
    let mut pixels = Vec::new();
    for y in 0..SIZE.1 {
        for x in 0..SIZE.0 {
            let d = depth.pixel(x, y)[0];
            if d <= 0.0 {
                continue;
            }
            let p = world_position(g, x, y, d);
            if ((p - BALL).length() - RADIUS).abs() > 0.05 {
                continue;
            }
            let n = (p - BALL).normalize();
            let v = (g.camera.view.inverse().w_axis.truncate() - p).normalize();
            let r = 2.0 * n.dot(v) * n - v;
            pixels.push((Vec3::from_slice(&specular.pixel(x, y)[..3]), r));
        }
    }
    pixels
}

fn red(c: Vec3) -> bool {
    c.x > 2.0 * c.y && c.x > 2.0 * c.z
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
    // The box's centre seen from the ball's (its near face spans about 0.3 rad either side).
    let towards_box = (Vec3::new(1.6, 0.402, 0.0) - BALL).normalize();
    let pixels = ball_pixels(&g, &specular, &depth);
    let on_box: Vec<Vec3> = pixels
        .iter()
        .filter(|(_, r)| r.angle_between(towards_box) < 0.2)
        .map(|(c, _)| *c)
        .collect();
    assert!(on_box.len() >= 3, "{} pixels reflect the box", on_box.len());
    let mean = on_box.iter().sum::<Vec3>() / on_box.len() as f32;
    assert!(
        red(mean),
        "where the ball reflects the box it is red: {mean}"
    );
    // Away from the box (reflecting towards -x), nothing is red.
    let away: Vec<Vec3> = pixels
        .iter()
        .filter(|(_, r)| r.x < -0.3)
        .map(|(c, _)| *c)
        .collect();
    assert!(
        away.len() >= 8 && !away.iter().any(|c| red(*c)),
        "the other side is not red"
    );
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
    assert_eq!(
        frame(&s, moved_eye, at_ball(), owner),
        (0, 1),
        "a moved camera"
    );
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
    let counts: Vec<_> = (0..5).map(|_| frame(&s, EYE, every, Some(502)).0).collect();
    assert_eq!(counts, [1, 0, 0, 1, 0]);
    // Once: a moved box does not render it again.
    let once = ProbeSettings {
        update: ProbeUpdate::Once,
        ..at_ball()
    };
    assert_eq!(frame(&s, EYE, once, Some(503)), (1, 0));
    assert_eq!(frame(&moved, EYE, once, Some(503)), (0, 1));
}

/// A closed room of six walls of different colours, walls at x, z = ±5, floor at 0, ceiling at 4.
fn room(renderer: &Renderer) -> Arc<Layer> {
    use spreadlight_render::gbuffer::{DrawBatch, InstanceInput};
    let mesh = renderer
        .meshes
        .upload(
            &renderer.gpu,
            &spreadlight_render::mesh::primitives::box_mesh(Default::default()),
        )
        .expect("uploads");
    let wall = |center: Vec3, size: Vec3, color: [f32; 4]| {
        let t = Mat4::from_translation(center) * Mat4::from_scale(size);
        InstanceInput {
            transform: t,
            previous_transform: t,
            color,
            material_id: 1,
            object_id: 1,
        }
    };
    let mut layer = Layer::plain(vec![DrawBatch {
        mesh,
        instances: vec![
            wall(
                Vec3::new(5.0, 2.0, 0.0),
                Vec3::new(0.02, 4.0, 10.0),
                [0.9, 0.1, 0.1, 1.0],
            ),
            wall(
                Vec3::new(-5.0, 2.0, 0.0),
                Vec3::new(0.02, 4.0, 10.0),
                [0.1, 0.9, 0.1, 1.0],
            ),
            wall(
                Vec3::new(0.0, 2.0, 5.0),
                Vec3::new(10.0, 4.0, 0.02),
                [0.1, 0.1, 0.9, 1.0],
            ),
            wall(
                Vec3::new(0.0, 2.0, -5.0),
                Vec3::new(10.0, 4.0, 0.02),
                [0.9, 0.9, 0.1, 1.0],
            ),
            wall(
                Vec3::new(0.0, 0.0, 0.0),
                Vec3::new(10.0, 0.02, 10.0),
                [0.5, 0.5, 0.5, 1.0],
            ),
            wall(
                Vec3::new(0.0, 4.0, 0.0),
                Vec3::new(10.0, 0.02, 10.0),
                [0.1, 0.9, 0.9, 1.0],
            ),
        ],
    }]);
    layer.features.ids = true;
    Arc::new(layer)
}

/// In a closed box room with the room as the probe's volume, parallax
/// correction makes the mirror's reflection (nearly) independent of where
/// in the room the probe stands; without it an offset probe shows the
/// walls from the wrong place.
#[test]
fn a_box_volume_corrects_an_offset_probe_for_parallax() {
    let renderer = test_renderer();
    let walls = room(&renderer);
    let s = MirrorBesideBox {
        ball: scene(&renderer).ball,
        surroundings: walls.clone(),
    };
    let volume = ProbeVolume::Box {
        center: Vec3::new(0.0, 2.0, 0.0),
        size: Vec3::new(10.0, 4.0, 10.0),
    };
    let image = |position: Vec3, volume: ProbeVolume| {
        let settings = ProbeSettings {
            position,
            volume,
            ..Default::default()
        };
        mirror(&renderer, &s, EYE, probe(&renderer, None, &walls, settings)).1
    };
    let rmse = |a: &ImageF32, b: &ImageF32| {
        let sum: f32 = a
            .pixels
            .iter()
            .zip(&b.pixels)
            .map(|(a, b)| (Vec3::from_slice(&a[..3]) - Vec3::from_slice(&b[..3])).length_squared())
            .sum();
        (sum / a.pixels.len() as f32).sqrt()
    };
    let reference = image(BALL, volume);
    let offset = Vec3::new(-2.5, 2.5, 1.5);
    let corrected = rmse(&image(offset, volume), &reference);
    let uncorrected_image = image(offset, ProbeVolume::Infinite);
    let uncorrected = rmse(&uncorrected_image, &reference);
    assert!(
        corrected < 0.4 * uncorrected,
        "parallax-corrected error {corrected} vs uncorrected {uncorrected}"
    );
    // A zero-size volume is no volume: exactly the uncorrected image.
    let flat = image(
        offset,
        ProbeVolume::Box {
            center: Vec3::ZERO,
            size: Vec3::new(3.0, 0.0, 3.0),
        },
    );
    assert_eq!(rmse(&flat, &uncorrected_image), 0.0);
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

fn blue(c: Vec3) -> bool {
    c.z > 2.0 * c.x && c.z > 2.0 * c.y
}

/// The probe's faces take the layer's Color Texture: the box made white and
/// textured blue (by its UVs, then by the triplanar projection) shows blue
/// where the mirror reflects it, where a white box would show white. A
/// texture changed under the same layer is a new content key: rendered again.
#[test]
fn a_mirror_sphere_beside_a_textured_box_shows_the_textures_colour() {
    use spreadlight_render::static_texture::StaticTexture;
    use spreadlight_render::texture::GpuTexture;
    let renderer = test_renderer();
    let s = scene(&renderer);
    // Linear 8-bit (filterable, as a file's texture is).
    let texture = |rgb: [u8; 3]| {
        let texels: Vec<u8> = (0..16)
            .flat_map(|_| [rgb[0], rgb[1], rgb[2], 255])
            .collect();
        StaticTexture::new(GpuTexture::from_rgba8(
            &renderer.gpu,
            4,
            4,
            &texels,
            false,
            "probe test texture",
        ))
        .texture_ref()
    };
    // The box white (the texture alone colours it), the floor as it was.
    let mut white = Layer::clone(&s.surroundings);
    for batch in &mut white.batches {
        for instance in &mut batch.instances {
            if instance.color == spreadlight_render::scenes::RED_BOX {
                instance.color = [1.0; 4];
            }
        }
    }
    let towards_box = (Vec3::new(1.6, 0.402, 0.0) - BALL).normalize();
    let box_colour = |surroundings: Layer, owner: Option<u32>| {
        let surroundings = Arc::new(surroundings);
        let (report, specular, depth, g) = mirror(
            &renderer,
            &MirrorBesideBox {
                ball: s.ball.clone(),
                surroundings: surroundings.clone(),
            },
            EYE,
            probe(&renderer, owner, &surroundings, at_ball()),
        );
        let on_box: Vec<Vec3> = ball_pixels(&g, &specular, &depth)
            .into_iter()
            .filter(|(_, r)| r.angle_between(towards_box) < 0.2)
            .map(|(c, _)| c)
            .collect();
        assert!(on_box.len() >= 3, "{} pixels reflect the box", on_box.len());
        (
            on_box.iter().sum::<Vec3>() / on_box.len() as f32,
            report.counter("environment probe rendered"),
        )
    };
    let (plain, _) = box_colour(white.clone(), None);
    assert!(!blue(plain), "an untextured white box is not blue: {plain}");
    for triplanar in [false, true] {
        let mut textured = white.clone();
        textured.features.texcoords = !triplanar;
        textured.features.triplanar = triplanar;
        let textured = textured
            .with_color_map(Some(texture([13, 26, 230])))
            .expect("UVs or triplanar");
        let (mean, _) = box_colour(textured, None);
        assert!(
            blue(mean),
            "triplanar {triplanar}: the textured box is blue in the mirror: {mean}"
        );
    }
    // Another texture on the same layer, same node: the probe sees the change.
    let mut layer = white.clone();
    layer.features.texcoords = true;
    let (_, first) = box_colour(
        layer
            .clone()
            .with_color_map(Some(texture([13, 26, 230])))
            .expect("UVs"),
        Some(7),
    );
    let (green, again) = box_colour(
        layer
            .with_color_map(Some(texture([13, 230, 26])))
            .expect("UVs"),
        Some(7),
    );
    assert_eq!(
        (first, again),
        (1, 1),
        "a new texture renders the faces again"
    );
    assert!(
        green.y > 2.0 * green.x && green.y > 2.0 * green.z,
        "{green}"
    );
}

/// The probe above the floor, looking down its -Y face: floor point (x, 0,
/// z) is at u = x / h, v = -z / h of that face (`cube_direction`).
const ABOVE: Vec3 = Vec3::new(0.0, 1.5, 0.0);
/// From +x and above at 45°: the box (x 1.2..2.0, 0.8 high) shadows the
/// floor over x 0.4..1.2, |z| < 0.4.
const SUN_DIRECTION: Vec3 = Vec3::new(-1.0, -1.0, 0.0);
const FLOOR_ALBEDO: f32 = 0.5;

/// The probe above the floor, lit by [`SUN_DIRECTION`] (sun 2, ambient 0.25 grey).
fn above() -> ProbeSettings {
    ProbeSettings {
        position: ABOVE,
        lighting: spreadlight_render::environment::ProbeLighting {
            sun_direction: SUN_DIRECTION,
            sun_color: Vec3::splat(2.0),
            ambient: Vec3::splat(0.25),
            ..Default::default()
        },
        ..Default::default()
    }
}

/// What the probe's base cube shows of floor point (x, 0, z) (its -Y face, level 0).
fn floor_seen(renderer: &Renderer, env: &Environment, x: f32, z: f32) -> Vec3 {
    let maps = env.maps().expect("the probe was built");
    let face = read_texture_layer(&renderer.gpu, &maps.base, 3, 0).expect("reads");
    let (u, v) = (x / ABOVE.y, -z / ABOVE.y);
    let n = face.width as f32;
    let texel = |t: f32| ((t * 0.5 + 0.5) * n).floor().clamp(0.0, n - 1.0) as u32;
    Vec3::from_slice(&face.pixel(texel(u), texel(v))[..3])
}

/// A ShadowMap (Sun)'s maps for [`SUN_DIRECTION`], slice 0, one cascade 8
/// deep, 1024 texels a side, cast by `casters`.
fn sun_shadow(
    renderer: &Renderer,
    casters: Vec<Arc<Layer>>,
    eye: Vec3,
) -> Arc<spreadlight_render::shadows::ShadowMaps> {
    use spreadlight_render::shadows::{Cascades, ShadowLights, ShadowMaps, ShadowSettings};
    let lights = ShadowLights::Sun {
        lights: vec![(0, SUN_DIRECTION)],
        cascades: Cascades {
            count: 1,
            split_lambda: 0.5,
            distance: 8.0,
            step: 0.0,
        },
    };
    // Fine enough that the filter and the biases (a few texels) keep the
    // shadow's edge within 0.3 of where the box puts it.
    let settings = ShadowSettings {
        resolution: 1024,
        ..Default::default()
    };
    ShadowMaps::new(
        renderer,
        None,
        &lights,
        casters,
        &camera(eye, BALL),
        settings,
    )
    .expect("valid shadow maps")
}

fn shadowed_probe(
    renderer: &Renderer,
    owner: Option<u32>,
    surroundings: &Arc<Layer>,
    shadow: Option<Arc<spreadlight_render::shadows::ShadowMaps>>,
) -> Arc<Environment> {
    use spreadlight_render::environment::ProbeShadow;
    let scene = ProbeScene::new(vec![surroundings.clone()], above())
        .and_then(|s| s.with_sun_shadow(shadow.map(|maps| ProbeShadow { maps, slice: 0 })))
        .expect("valid");
    Environment::new(
        renderer,
        owner,
        EnvironmentSource::Probe(Arc::new(scene)),
        QUALITY,
    )
}

/// With the scene's sun shadow maps, the floor the probe sees in the box's
/// shadow is lit by the ambient alone: albedo x 0.25 where the lit floor
/// beside it is albedo x (0.25 + 2 cos 45°), 0.150 of it. Without them both
/// are lit. The shadow's casters are part of the probe's content key (a
/// moved caster renders it again), its cascades are not (a moved camera
/// reuses the cube).
#[test]
fn a_probe_sees_the_suns_shadow_beside_a_box() {
    let renderer = test_renderer();
    let s = scene(&renderer);
    let lit = FLOOR_ALBEDO * (0.25 + 2.0 * std::f32::consts::FRAC_1_SQRT_2);
    let dark = FLOOR_ALBEDO * 0.25;
    // In the shadow (x 0.4..1.2), away from its edges; beside it; behind the box.
    let (shadowed, beside, behind) = ((1.0, 0.0), (-0.8, 0.0), (1.0, 1.0));
    // Unshadowed: all three lit alike.
    let env = shadowed_probe(&renderer, None, &s.surroundings, None);
    mirror(&renderer, &s, EYE, env.clone());
    for (x, z) in [shadowed, beside, behind] {
        let c = floor_seen(&renderer, &env, x, z);
        assert!(
            (c.x - lit).abs() < 0.03 * lit,
            "({x}, {z}) unshadowed: {c}, want {lit}"
        );
    }
    let shadows = sun_shadow(&renderer, vec![s.surroundings.clone()], EYE);
    let env = shadowed_probe(&renderer, None, &s.surroundings, Some(shadows));
    let (report, ..) = mirror(&renderer, &s, EYE, env.clone());
    assert!(report.errors.is_empty(), "{:?}", report.errors);
    let in_shadow = floor_seen(&renderer, &env, shadowed.0, shadowed.1);
    for (x, z) in [beside, behind] {
        let c = floor_seen(&renderer, &env, x, z);
        assert!(
            (c.x - lit).abs() < 0.03 * lit,
            "({x}, {z}) in the sun: {c}, want {lit}"
        );
        // Darker than the lit side by the ambient's share of the light.
        let ratio = in_shadow.x / c.x;
        assert!(
            (ratio - dark / lit).abs() < 0.02,
            "shadowed / lit = {ratio}, want {}",
            dark / lit
        );
    }
    assert!(
        (in_shadow.x - dark).abs() < 0.03 * dark,
        "{in_shadow}, want {dark}"
    );
    assert!(
        renderer
            .shaders()
            .compiled_keys()
            .any(|k| k.path() == "environment/environment_probe.wgsl"
                && k.features.contains("SHADOWS")),
        "the shadowed faces' permutation"
    );

    // Re-rendered when what it sees changed, and the shadow is part of that.
    let frame = |surroundings: &Arc<Layer>, casters: Vec<Arc<Layer>>, eye: Vec3| {
        let shadows = sun_shadow(&renderer, casters, eye);
        let env = shadowed_probe(&renderer, Some(601), surroundings, Some(shadows));
        let (report, ..) = mirror(&renderer, &s, eye, env);
        (
            report.counter("environment probe rendered"),
            report.counter("environment probe reused"),
        )
    };
    let again = |layer: &Arc<Layer>| Arc::new((**layer).clone());
    let casters = || vec![again(&s.surroundings), again(&s.ball)];
    assert_eq!(
        frame(&again(&s.surroundings), casters(), EYE),
        (1, 0),
        "first"
    );
    assert_eq!(
        frame(&again(&s.surroundings), casters(), EYE),
        (0, 1),
        "still"
    );
    let moved_eye = Vec3::new(2.0, 2.0, 3.0);
    assert_eq!(
        frame(&again(&s.surroundings), casters(), moved_eye),
        (0, 1),
        "a moved camera moves the cascades, not what the probe sees"
    );
    // A caster the probe does not draw (the ball) moves: its shadow does.
    let mut ball = Layer::clone(&s.ball);
    ball.batches[0].instances[0].transform =
        Mat4::from_translation(Vec3::new(-1.0, 0.6, 0.0)) * Mat4::from_scale(Vec3::splat(RADIUS));
    let moved = vec![again(&s.surroundings), Arc::new(ball)];
    assert_eq!(
        frame(&again(&s.surroundings), moved, EYE),
        (1, 0),
        "a moved caster"
    );

    // Bad input: a slice the maps lack, or maps of another light type, named.
    use spreadlight_render::environment::{ProbeError, ProbeShadow};
    use spreadlight_render::shadows::{ShadowLights, ShadowMaps, ShadowSettings};
    let refused = |maps: Arc<ShadowMaps>, slice: u32| {
        ProbeScene::new(vec![s.surroundings.clone()], above())
            .and_then(|p| p.with_sun_shadow(Some(ProbeShadow { maps, slice })))
            .map(|_| ())
            .expect_err("refused")
    };
    let sun = sun_shadow(&renderer, vec![s.surroundings.clone()], EYE);
    assert_eq!(
        refused(sun, 3),
        ProbeError::ShadowSlice { slice: 3, count: 1 }
    );
    let spot = ShadowMaps::new(
        &renderer,
        None,
        &ShadowLights::Spot(vec![(0, Mat4::IDENTITY, Mat4::IDENTITY)]),
        vec![s.surroundings.clone()],
        &camera(EYE, BALL),
        ShadowSettings::default(),
    )
    .expect("valid spot maps");
    let e = refused(spot, 0);
    assert!(e.to_string().contains("ShadowMap (Sun)"), "{e}");
}

/// The layer's Normal Map reaches the probe's faces as it reaches the
/// G-buffer: a triplanar normal map of one texel (218, 128, 218) tilts the
/// floor's normal towards +x by the whiteout blend (N = normalize(t.x,
/// |t.z|, t.y), t = texel x 2 - 1), towards the sun: the floor the probe
/// sees is lit by N.L of the tilted normal, brighter than the flat floor.
#[test]
fn a_normal_mapped_floor_differs_from_the_flat_one_as_its_normal_says() {
    use spreadlight_render::static_texture::StaticTexture;
    use spreadlight_render::texture::GpuTexture;
    let renderer = test_renderer();
    let s = scene(&renderer);
    let texel = [218u8, 128, 218];
    let texels: Vec<u8> = (0..16)
        .flat_map(|_| [texel[0], texel[1], texel[2], 255])
        .collect();
    let normal_map = StaticTexture::new(GpuTexture::from_rgba8(
        &renderer.gpu,
        4,
        4,
        &texels,
        false,
        "probe normal map",
    ))
    .texture_ref();
    let mut mapped = Layer::clone(&s.surroundings);
    mapped.features.triplanar = true;
    mapped.features.normal_map = true;
    mapped.normal_map = Some(normal_map);
    let mapped = Arc::new(mapped);
    let seen = |surroundings: &Arc<Layer>| {
        let env = shadowed_probe(&renderer, None, surroundings, None);
        let shown = MirrorBesideBox {
            ball: s.ball.clone(),
            surroundings: surroundings.clone(),
        };
        let (report, ..) = mirror(&renderer, &shown, EYE, env.clone());
        assert!(report.errors.is_empty(), "{:?}", report.errors);
        floor_seen(&renderer, &env, -0.8, 0.0)
    };
    let flat = seen(&s.surroundings);
    let bumped = seen(&mapped);
    let t = Vec3::from(texel.map(|c| f32::from(c) / 255.0)) * 2.0 - Vec3::ONE;
    let n = Vec3::new(t.x, t.z.abs(), t.y).normalize();
    let l = -SUN_DIRECTION.normalize();
    let want = FLOOR_ALBEDO * (0.25 + 2.0 * n.dot(l).max(0.0));
    let want_flat = FLOOR_ALBEDO * (0.25 + 2.0 * Vec3::Y.dot(l));
    assert!(
        (flat.x - want_flat).abs() < 0.03 * want_flat,
        "flat: {flat}, want {want_flat}"
    );
    assert!(
        (bumped.x - want).abs() < 0.03 * want,
        "mapped: {bumped}, want {want}"
    );
    assert!(bumped.x > 1.2 * flat.x, "{bumped} against {flat}");
    assert!(
        renderer
            .shaders()
            .compiled_keys()
            .any(|k| k.path() == "environment/environment_probe.wgsl"
                && k.features.contains("NORMAL_MAP")),
        "the normal-mapped faces' permutation"
    );
}

/// A red point light beside the probe, above the floor.
const LAMP: Vec3 = Vec3::new(-0.6, 0.6, 0.4);

fn red_lamp(position: Vec3) -> spreadlight_render::lighting::PointLight {
    spreadlight_render::lighting::PointLight {
        position,
        color: Vec3::new(1.0, 0.05, 0.05),
        intensity: 3.0,
        range: 3.0,
        shadow: None,
    }
}

/// [`above`]'s probe lit by `lights` too (at most `max_lights` of each buffer).
fn lit_probe(
    renderer: &Renderer,
    owner: Option<u32>,
    surroundings: &Arc<Layer>,
    lights: Vec<spreadlight_render::environment::ProbeLights>,
    max_lights: u32,
) -> Arc<Environment> {
    let scene = ProbeScene::new(vec![surroundings.clone()], above())
        .and_then(|s| s.with_lights(lights, max_lights))
        .expect("valid");
    Environment::new(
        renderer,
        owner,
        EnvironmentSource::Probe(Arc::new(scene)),
        QUALITY,
    )
}

fn point_buffer(
    renderer: &Renderer,
    lights: &[spreadlight_render::lighting::PointLight],
) -> Vec<spreadlight_render::environment::ProbeLights> {
    vec![spreadlight_render::environment::ProbeLights {
        lights: spreadlight_render::lighting::LightBuffer::points(renderer, lights),
        shadows: None,
    }]
}

/// The -Y face's texel (level 0) that holds floor point (x, 0, z): its
/// colour, and the floor point at the texel's centre (where the raster
/// shaded it).
fn floor_texel(renderer: &Renderer, env: &Environment, x: f32, z: f32) -> (Vec3, Vec3) {
    use spreadlight_render::environment::probe::cube_direction;
    let maps = env.maps().expect("the probe was built");
    let face = read_texture_layer(&renderer.gpu, &maps.base, 3, 0).expect("reads");
    let n = face.width as f32;
    let texel = |t: f32| ((t * 0.5 + 0.5) * n).floor().clamp(0.0, n - 1.0);
    let (i, j) = (texel(x / ABOVE.y), texel(-z / ABOVE.y));
    let centre = |k: f32| (k + 0.5) / n * 2.0 - 1.0;
    // The face's direction has y = -1: ABOVE.y along it reaches the floor.
    let d = cube_direction(3, Vec2::new(centre(i), centre(j)));
    let colour = Vec3::from_slice(&face.pixel(i as u32, j as u32)[..3]);
    (colour, ABOVE + d * ABOVE.y)
}

/// What the probe sees of floor point `p` (the CPU reference): the base
/// pass's albedo x (ambient + sun N.L), plus each point light's
/// Cook-Torrance light (spreadlight-reference's BRDF and falloff) for the
/// probe's rough dielectric, seen from the probe.
fn floor_reference(p: Vec3, lights: &[spreadlight_render::lighting::PointLight]) -> Vec3 {
    use spreadlight_reference::brdf::cook_torrance_f0;
    use spreadlight_reference::lights::point_attenuation;
    use spreadlight_render::environment::probe::{SURFACE_METALLIC, SURFACE_ROUGHNESS};
    let albedo = Vec3::splat(FLOOR_ALBEDO);
    let sun = Vec3::Y.dot(-SUN_DIRECTION.normalize()).max(0.0);
    let mut c = albedo * (0.25 + 2.0 * sun);
    let v = (ABOVE - p).normalize();
    for light in lights {
        let to = light.position - p;
        let b = cook_torrance_f0(
            Vec3::Y,
            v,
            to.normalize(),
            albedo,
            SURFACE_ROUGHNESS,
            SURFACE_METALLIC,
            0.04,
            true,
        );
        c += (b.diffuse + b.specular)
            * light.color
            * light.intensity
            * point_attenuation(to.length(), light.range);
    }
    c
}

fn close(got: Vec3, want: Vec3) -> bool {
    (got - want)
        .abs()
        .cmple(want.abs() * 0.02 + Vec3::splat(3e-3))
        .all()
}

/// A red point light beside the probe reddens the floor the probe sees, by
/// the light CookTorrance would give it: the CPU reference at chosen
/// texels, each channel within 2%. Green and blue (the lamp's are 0.05 of
/// its red) barely change. A moved light renders the probe again, the
/// same light in a new buffer does not.
#[test]
fn a_red_point_light_beside_the_probe_reddens_what_it_shows() {
    let renderer = test_renderer();
    let s = scene(&renderer);
    let unlit = lit_probe(&renderer, None, &s.surroundings, Vec::new(), 64);
    mirror(&renderer, &s, EYE, unlit.clone());
    let lamps = [red_lamp(LAMP)];
    let lit = lit_probe(
        &renderer,
        None,
        &s.surroundings,
        point_buffer(&renderer, &lamps),
        64,
    );
    let (report, ..) = mirror(&renderer, &s, EYE, lit.clone());
    assert!(report.errors.is_empty(), "{:?}", report.errors);
    for (x, z) in [(-0.8, 0.0), (-0.3, 0.6), (0.4, -0.3), (-1.0, 0.9)] {
        let (before, _) = floor_texel(&renderer, &unlit, x, z);
        let (after, p) = floor_texel(&renderer, &lit, x, z);
        let want = floor_reference(p, &lamps);
        assert!(
            close(after, want),
            "({x}, {z}) at {p}: {after}, want {want}"
        );
        assert!(
            close(before, floor_reference(p, &[])),
            "({x}, {z}) unlit: {before}"
        );
        assert!(
            after.x > before.x + 0.05 && after.x > after.y + 0.05,
            "({x}, {z}) reddened: {before} -> {after}"
        );
    }
    assert!(
        renderer
            .shaders()
            .compiled_keys()
            .any(|k| k.path() == "environment/environment_probe.wgsl"
                && k.features.contains("LIGHT_PASS")),
        "the light pass's permutation"
    );

    // Rendered again only when the lights change.
    let frame = |lamp: Vec3| {
        let env = lit_probe(
            &renderer,
            Some(701),
            &s.surroundings,
            point_buffer(&renderer, &[red_lamp(lamp)]),
            64,
        );
        let (report, ..) = mirror(&renderer, &s, EYE, env);
        (
            report.counter("environment probe rendered"),
            report.counter("environment probe reused"),
        )
    };
    assert_eq!(frame(LAMP), (1, 0), "first");
    assert_eq!(frame(LAMP), (0, 1), "the same light, a new buffer");
    let moved = LAMP + Vec3::new(0.3, 0.0, 0.0);
    assert_eq!(frame(moved), (1, 0), "a moved light");
    assert_eq!(frame(moved), (0, 1), "still again");
}

/// A red spot shining down beside the probe reddens the floor inside its
/// cone and leaves the floor outside it as the unlit probe shows it.
#[test]
fn a_spot_light_reddens_the_floor_inside_its_cone_only() {
    use spreadlight_render::lighting::{LightBuffer, SpotLight};
    let renderer = test_renderer();
    let s = scene(&renderer);
    let unlit = lit_probe(&renderer, None, &s.surroundings, Vec::new(), 64);
    mirror(&renderer, &s, EYE, unlit.clone());
    let spot = SpotLight::cone(Vec3::new(-0.6, 1.0, -0.5), Vec3::NEG_Y, 3.0, 0.2, 0.3)
        .with_light(Vec3::new(1.0, 0.05, 0.05), 3.0);
    let lights = vec![spreadlight_render::environment::ProbeLights {
        lights: LightBuffer::spots(&renderer, &[spot], None).expect("a valid spot"),
        shadows: None,
    }];
    let lit = lit_probe(&renderer, None, &s.surroundings, lights, 64);
    let (report, ..) = mirror(&renderer, &s, EYE, lit.clone());
    assert!(report.errors.is_empty(), "{:?}", report.errors);
    let (under_before, _) = floor_texel(&renderer, &unlit, -0.6, -0.5);
    let (under, _) = floor_texel(&renderer, &lit, -0.6, -0.5);
    assert!(
        under.x > under_before.x + 0.2 && under.x > 1.3 * under.y,
        "under the spot: {under_before} -> {under}"
    );
    let (outside_before, _) = floor_texel(&renderer, &unlit, 0.5, 0.6);
    let (outside, _) = floor_texel(&renderer, &lit, 0.5, 0.6);
    assert!(
        (outside - outside_before).abs().max_element() < 1e-3,
        "outside the cone: {outside_before} -> {outside}"
    );
    assert!(
        renderer
            .shaders()
            .compiled_keys()
            .any(|k| k.path() == "environment/environment_probe.wgsl"
                && k.features.contains("LIGHT_SPOT")),
        "the spot pass's permutation"
    );
}

/// Hard cases: a light at the probe's very centre lights every face
/// finitely; a light of range 0, and Max Lights 0, add exactly nothing; a
/// sun buffer is refused, naming the probe's own sun.
#[test]
fn probe_lights_at_its_centre_or_without_range_stay_finite() {
    use spreadlight_render::environment::{ProbeError, ProbeLights};
    use spreadlight_render::lighting::{LightBuffer, SunLight};
    let renderer = test_renderer();
    let s = scene(&renderer);
    let unlit = lit_probe(&renderer, None, &s.surroundings, Vec::new(), 64);
    mirror(&renderer, &s, EYE, unlit.clone());
    let centre = lit_probe(
        &renderer,
        None,
        &s.surroundings,
        point_buffer(&renderer, &[red_lamp(ABOVE)]),
        64,
    );
    mirror(&renderer, &s, EYE, centre.clone());
    let maps = centre.maps().expect("built");
    for face in 0..6 {
        let image = read_texture_layer(&renderer.gpu, &maps.base, face, 0).expect("reads");
        assert!(image.all_finite(), "face {face}: NaN or infinity");
    }
    let no_range = spreadlight_render::lighting::PointLight {
        range: 0.0,
        ..red_lamp(LAMP)
    };
    let none = [
        lit_probe(
            &renderer,
            None,
            &s.surroundings,
            point_buffer(&renderer, &[no_range]),
            64,
        ),
        lit_probe(
            &renderer,
            None,
            &s.surroundings,
            point_buffer(&renderer, &[red_lamp(LAMP)]),
            0,
        ),
    ];
    for env in none {
        mirror(&renderer, &s, EYE, env.clone());
        for (x, z) in [(-0.8, 0.0), (-0.3, 0.6)] {
            assert_eq!(
                floor_texel(&renderer, &env, x, z).0,
                floor_texel(&renderer, &unlit, x, z).0,
                "({x}, {z})"
            );
        }
    }
    let suns = vec![ProbeLights {
        lights: LightBuffer::suns(
            &renderer,
            &[SunLight {
                direction: SUN_DIRECTION,
                color: Vec3::ONE,
                illuminance: 1.0,
                shadow: None,
            }],
        ),
        shadows: None,
    }];
    let e = ProbeScene::new(vec![s.surroundings.clone()], above())
        .and_then(|p| p.with_lights(suns, 64))
        .map(|_| ())
        .expect_err("refused");
    assert_eq!(e, ProbeError::SunBuffer { index: 0 });
}

/// A point light's shadow map reaches the probe's light pass: a light on
/// the box's far side (+x) leaves the floor behind the box, as the probe
/// sees it, as unlit as without the light, and the floor beside the box lit
/// as without the shadow maps.
#[test]
fn a_point_lights_shadow_darkens_what_the_probe_sees_behind_the_box() {
    use spreadlight_render::environment::ProbeLights;
    use spreadlight_render::lighting::{LightBuffer, PointLight};
    use spreadlight_render::shadows::{ShadowLights, ShadowMaps, ShadowSettings};
    let renderer = test_renderer();
    let s = scene(&renderer);
    let at = Vec3::new(2.8, 0.6, 0.0);
    let light = PointLight {
        position: at,
        color: Vec3::ONE,
        intensity: 40.0,
        range: 4.0,
        shadow: Some(0),
    };
    let maps = ShadowMaps::new(
        &renderer,
        None,
        &ShadowLights::Point(vec![(0, at, 4.0)]),
        vec![s.surroundings.clone()],
        &camera(EYE, BALL),
        ShadowSettings::default(),
    )
    .expect("valid point shadow maps");
    let probe_of = |shadows: Option<Arc<ShadowMaps>>| {
        let lights = vec![ProbeLights {
            lights: LightBuffer::points(&renderer, &[light]),
            shadows,
        }];
        let env = lit_probe(&renderer, None, &s.surroundings, lights, 64);
        let (report, ..) = mirror(&renderer, &s, EYE, env.clone());
        assert!(report.errors.is_empty(), "{:?}", report.errors);
        env
    };
    let unlit = lit_probe(&renderer, None, &s.surroundings, Vec::new(), 64);
    mirror(&renderer, &s, EYE, unlit.clone());
    let unshadowed = probe_of(None);
    let shadowed = probe_of(Some(maps));
    // Behind the box from the light; beside it, in the light's view.
    let (behind, beside) = ((0.8, 0.0), (0.8, 1.2));
    let seen = |env: &Environment, (x, z): (f32, f32)| floor_texel(&renderer, env, x, z).0;
    let dark = seen(&unlit, behind);
    let light_behind = seen(&unshadowed, behind).x - dark.x;
    assert!(
        light_behind > 0.1,
        "the light reaches the floor unshadowed: {light_behind}"
    );
    let in_shadow = seen(&shadowed, behind);
    assert!(
        (in_shadow.x - dark.x).abs() < 0.05 * light_behind,
        "behind the box: {in_shadow}, unlit {dark}"
    );
    let lit = seen(&unshadowed, beside);
    let still_lit = seen(&shadowed, beside);
    assert!(
        (still_lit - lit).abs().max_element() < 0.03 * lit.x,
        "beside the box: {still_lit}, unshadowed {lit}"
    );
    assert!(
        renderer.shaders().compiled_keys().any(|k| {
            k.path() == "environment/environment_probe.wgsl"
                && k.features.contains("LIGHT_PASS")
                && k.features.contains("SHADOWS")
        }),
        "the shadowed light pass's permutation"
    );
}
