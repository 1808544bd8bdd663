//! Weighted blended transparency: alpha 0 leaves the opaque image exactly,
//! alpha 1 covers it, alpha 0.5 front and back faces reveal a quarter of it;
//! the opaque depth hides what is behind; 100 overlapping layers, and
//! layers at the near and far planes, neither overflow nor make NaN. Lit
//! forward+: point and sun lights on a glass pane match the CPU BRDF
//! reference at chosen pixels, naive and clustered alike; zero normals,
//! zero roughness and a light at the surface stay finite; light passes run
//! only for connected light buffers, with only their type compiled in.
//! A clear coat on a BLEND surface reflects a uniform environment over its
//! dimmed base as the analytic value says. Transmission: a glass slab over a ramp shifts what is behind by what
//! Snell's law says (the CPU reference, `spreadlight_reference::
//! refraction`), ior 1 shows it unshifted, the volume absorbs by
//! exp(-σ path); a dispersive material (KHR_materials_dispersion) bends
//! red, green and blue by their own ior as the CPU reference does (fringes
//! on the predicted side of a white/black edge), dispersion 0 bit for bit
//! as before; ior 0 or NaN, an infinite thickness, grazing angles and
//! rays leaving the screen stay finite and clamp. Rough glass blurs through
//! the opaque image's mip chain (built only when a layer refracts) as the
//! taps do; rays leaving the screen see the Environment where there is one.
//! Shading: the lights shaded in compute over each pixel's recorded
//! fragments give the forward path's picture (within 4e-3) on the froxel
//! scene, the CPU reference's on the pane, and the forward one with a
//! colour and a normal map; hard cases stay finite, and a pixel with more
//! layers than slots counts the missed fragments and lights them as the
//! recorded ones.

use crate::post_common;

use std::sync::Arc;

use glam::{Mat4, Vec3};
use post_common::*;
use spreadlight_reference::brdf::{cook_torrance_f0, specular_albedo};
use spreadlight_reference::lights::point_attenuation;
use spreadlight_render::Renderer;
use spreadlight_render::environment::{
    Environment, EnvironmentQuality, EnvironmentSource, EquirectImage,
};
use spreadlight_render::gbuffer::{DrawBatch, GBuffer, InstanceInput, Layer, LayerFeatures};
use spreadlight_render::lighting::{LightBuffer, LightLoop, PointLight, SunLight};
use spreadlight_render::mesh::MeshData;
use spreadlight_render::mesh::primitives::{SphereParams, plane, sphere};
use spreadlight_render::post::transparency::compute::{FRAGMENT_SLOTS, SHADED, SLOTS};
use spreadlight_render::post::transparency::{
    ASSIGNED, DRAWN, LIGHT_PASSES, MIP_CHAINS, MatCapKey, REFRACTING, RefractionBlur,
    RefractionKey, SKIPPED, TransmissionSettings, TransparencyPass,
};
use spreadlight_render::post::{
    LitBy, Transparency, TransparencySettings, TransparencyShading, TransparentLights,
};
use spreadlight_render::readback::ImageF32;
use spreadlight_render::renderer::test_renderer;
use spreadlight_render::shaders::Permutation;
use spreadlight_render::static_texture::StaticTexture;
use spreadlight_render::texture::GpuTexture;

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
    Arc::new(Layer::plain(vec![DrawBatch { mesh, instances }]))
}

/// Unlit: ambient 1, no key light, so a layer shows exactly its colour.
fn unlit() -> TransparencySettings {
    TransparencySettings {
        ambient: Vec3::ONE,
        light_color: Vec3::ZERO,
        ..Default::default()
    }
}

/// An opaque ball (radius 0.5 at the origin, seen from z = 8), and a green "lit" image.
fn ball_under_green(renderer: &Renderer) -> (Arc<GBuffer>, Arc<StaticTexture>) {
    let opaque = balls(renderer, &[Ball::still(Vec3::ZERO, 0.5)]);
    let g = gbuffer(
        renderer,
        opaque,
        look(Vec3::new(0.0, 0.0, 8.0), Vec3::ZERO, 0.6, 1.0),
        None,
    );
    (g, image(renderer, SIZE, |_, _| GREEN))
}

/// The ball under the green image, with `spheres` over it.
fn composite(
    spheres: &[(Vec3, f32, [f32; 4])],
    settings: TransparencySettings,
) -> (ImageF32, u64, u64) {
    let renderer = test_renderer();
    let (g, lit) = ball_under_green(&renderer);
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

/// Particles drawn from their records through a layer, as `Particles` into
/// `DeferredBase` into `Transparency`'s Layer pin: `count` sprites of half
/// size 0.5 all at `at`, in `color` (alpha in w).
fn particles(renderer: &Renderer, at: Vec3, count: u32, color: [f32; 4]) -> Arc<Layer> {
    use spreadlight_render::particles::{DrawShape, ParticleSettings, ParticleSystem, draw};
    let mut system = ParticleSystem::new(renderer, count, 1).expect("system");
    let settings = ParticleSettings {
        emitter: Mat4::from_translation(at),
        rate: 1e6,
        lifetime: 10.0,
        velocity: Vec3::ZERO,
        gravity: Vec3::ZERO,
        ..Default::default()
    };
    system.step(renderer, &settings, 1.0 / 60.0).expect("step");
    let mesh = draw(renderer, &system, DrawShape::Sprites, 0.5, false, 100.0).expect("draw");
    Arc::new(Layer::plain(vec![DrawBatch {
        mesh,
        instances: vec![InstanceInput {
            transform: Mat4::IDENTITY,
            previous_transform: Mat4::IDENTITY,
            color,
            material_id: 0,
            object_id: 0,
        }],
    }]))
}

/// The paper's weight (shaders/post/transparency.wgsl) at view distance `d`.
fn weight(d: f32, alpha: f32) -> f32 {
    let w = 10.0 / (1e-5 + (d / 5.0).powi(2) + (d / 200.0).powi(6));
    alpha * w.clamp(1e-2, 3e3) / 3e3
}

#[test]
fn alpha_blended_particles_blend_unsorted_through_transparency() {
    let renderer = test_renderer();
    let fov = 0.6f32;
    let opaque = balls(&renderer, &[Ball::still(Vec3::ZERO, 0.5)]);
    let g = gbuffer(
        &renderer,
        opaque,
        look(Vec3::new(0.0, 0.0, 8.0), Vec3::ZERO, fov, 1.0),
        None,
    );
    let lit = image(&renderer, SIZE, |_, _| GREEN);
    let red = [1.0, 0.0, 0.0, 0.5];
    let blue = [0.0, 0.0, 1.0, 0.5];
    // Four red particles 6 m from the eye and four blue ones 5 m from it,
    // in both orders: weighted blended OIT needs no sorting.
    let run = |layers: Vec<Arc<Layer>>| {
        let pass = Transparency::new(
            &renderer,
            None,
            lit.texture_ref(),
            g.clone(),
            layers,
            unlit(),
        );
        let (report, out) = render(&renderer, pass.as_ref(), &pass.output, SIZE);
        assert_eq!(report.counter(DRAWN), 2);
        out
    };
    let a = particles(&renderer, Vec3::new(0.0, 0.0, 2.0), 4, red);
    let b = particles(&renderer, Vec3::new(0.0, 0.0, 3.0), 4, blue);
    let forwards = run(vec![a.clone(), b.clone()]);
    let backwards = run(vec![b, a]);
    for (p, q) in forwards.pixels.iter().zip(&backwards.pixels) {
        assert!(
            p.iter().zip(q).all(|(s, t)| (s - t).abs() < 1e-3),
            "{p:?} vs {q:?}"
        );
    }
    // Eight layers of alpha 0.5 reveal 1/256 of the green; the rest is the
    // weighted average of red and blue.
    let (wr, wb) = (4.0 * weight(6.0, 0.5), 4.0 * weight(5.0, 0.5));
    let revealed = 0.5f32.powi(8);
    let expected = [
        wr / (wr + wb) * (1.0 - revealed),
        revealed,
        wb / (wr + wb) * (1.0 - revealed),
    ];
    let c = at(&forwards, 24, 24);
    for k in 0..3 {
        assert!(
            (c[k] - expected[k]).abs() < 0.02,
            "{c:?}, expected {expected:?}"
        );
    }
    // Coverage: the blue sprites (the larger on screen) cover a square of
    // 2 x 0.5 m at 5 m; everything else is the green image exactly.
    let half_pixels = 0.5 / (5.0 * (fov / 2.0).tan()) * SIZE.0 as f32 / 2.0;
    let expected_covered = (2.0 * half_pixels).powi(2);
    let covered = forwards
        .pixels
        .iter()
        .filter(|p| p[..3] != GREEN[..3])
        .count() as f32;
    assert!(
        (covered - expected_covered).abs() < 0.15 * expected_covered,
        "{covered} pixels covered, expected about {expected_covered}"
    );
    assert_eq!(at(&forwards, 1, 1)[..3], GREEN[..3]);
}

#[test]
fn a_re_made_transparency_binds_the_groups_it_made_before() {
    let renderer = test_renderer();
    let (g, lit) = ball_under_green(&renderer);
    let layers = vec![glass(
        &renderer,
        &[(Vec3::new(0.0, 0.0, 2.0), 1.0, [1.0, 0.0, 0.0, 0.5])],
    )];
    // The opaque frame alone, twice: the groups its own passes reuse.
    render(&renderer, g.as_ref(), &g.targets.color, SIZE);
    let opaque_reused = render(&renderer, g.as_ref(), &g.targets.color, SIZE)
        .0
        .counter("bind groups reused");
    let mut first = None;
    for frame in 0..3 {
        // The node makes its recipe again each frame from the same inputs.
        let pass = Transparency::new(
            &renderer,
            Some(70),
            lit.texture_ref(),
            g.clone(),
            layers.clone(),
            unlit(),
        );
        let (report, out) = render(&renderer, pass.as_ref(), &pass.output, SIZE);
        assert!(report.errors.is_empty(), "{:?}", report.errors);
        assert_eq!(report.counter(DRAWN), 1);
        if frame > 0 {
            // The accumulation's group binds the same camera, meshes, kept
            // instances and parameters: reused, not made again.
            assert_eq!(
                report.counter("bind groups created"),
                0,
                "frame {frame}: {:?}",
                report.counters
            );
            // Beyond the opaque frame's: the targets' clear's, the
            // accumulation's and the resolve's.
            assert_eq!(
                report.counter("bind groups reused") - opaque_reused,
                3,
                "frame {frame}: {:?}",
                report.counters
            );
        }
        // The pooled targets come back holding last frame's sums: the same
        // image shows the clear ran before the accumulation.
        match &first {
            None => first = Some(out),
            Some(image) => assert!(image.pixels == out.pixels, "frame {frame}: the same image"),
        }
    }
}

// Lit transparency.

const EYE: Vec3 = Vec3::new(0.0, 0.0, 8.0);
const FOV: f32 = 0.6;
/// The glass pane's plane (z) and albedo; roughness and metallic are the settings'.
const PANE_Z: f32 = 3.0;
const ALBEDO: Vec3 = Vec3::new(0.8, 0.6, 0.4);
const ROUGHNESS: f32 = 0.4;
const METALLIC: f32 = 0.3;

/// A 4 x 4 pane at z = PANE_Z facing the eye, opaque (alpha 1) so a pixel
/// shows its lit colour alone; `mesh` replaces the plane (its normals, say).
fn pane(renderer: &Renderer, mesh: Option<MeshData>, alpha: f32) -> Arc<Layer> {
    pane_of(renderer, mesh, ALBEDO.extend(alpha))
}

/// `pane` in `color` (alpha in w).
fn pane_of(renderer: &Renderer, mesh: Option<MeshData>, color: glam::Vec4) -> Arc<Layer> {
    let mesh = renderer
        .meshes
        .upload(&renderer.gpu, &mesh.unwrap_or_else(plane))
        .expect("upload");
    let t = Mat4::from_translation(Vec3::new(0.0, 0.0, PANE_Z))
        * Mat4::from_rotation_x(std::f32::consts::FRAC_PI_2)
        * Mat4::from_scale(Vec3::splat(4.0));
    Arc::new(Layer::plain(vec![DrawBatch {
        mesh,
        instances: vec![InstanceInput {
            transform: t,
            previous_transform: t,
            color: color.to_array(),
            material_id: 0,
            object_id: 0,
        }],
    }]))
}

/// No ambient, no key light: only the light buffers light the pane.
/// Drawn forward (what these tests were written for); `computed` shades in compute.
fn dark(light_loop: LightLoop) -> TransparencySettings {
    TransparencySettings {
        ambient: Vec3::ZERO,
        roughness: ROUGHNESS,
        metallic: METALLIC,
        light_loop,
        shading: TransparencyShading::Forward,
        ..Default::default()
    }
}

/// `settings` with the lights shaded in compute.
fn computed(settings: TransparencySettings) -> TransparencySettings {
    TransparencySettings {
        shading: TransparencyShading::Compute,
        ..settings
    }
}

/// The largest difference between `a` and `b`, relative to 1 or the value
/// where that is larger, over every channel of every pixel; and where it
/// is, with both pixels, for the failure's message.
fn largest_difference(a: &ImageF32, b: &ImageF32) -> (f32, String) {
    let mut worst = (0.0, String::new());
    for (i, (s, t)) in a.pixels.iter().zip(&b.pixels).enumerate() {
        for (u, v) in s.iter().zip(t) {
            let d = (u - v).abs() / u.abs().max(1.0);
            if d > worst.0 {
                let (x, y) = (i as u32 % SIZE.0, i as u32 / SIZE.0);
                worst = (d, format!("at ({x}, {y}): {s:?} against {t:?}"));
            }
        }
    }
    worst
}

/// How close compute shading comes to the forward path, relative to 1 or
/// the value where larger. The records hold roughness, metallic, alpha and
/// coverage to 1/65535 and the normal to about 5e-5 radians, and compute
/// sums the light in f32. The forward path blends each light into the
/// half-float accumulation, rounding each of a pixel's adds by up to 2^-11
/// (and far layers, whose weights are half-float subnormals, coarser):
/// over the froxel scene's seven layers a pixel this much apart is the
/// forward path's rounding (the compute path is the exact one there; on a
/// single pane both match the CPU reference).
const COMPUTE_TOLERANCE: f32 = 4e-3;

/// The pane lit by `lights` over a black image; the frame's report and image.
fn lit_pane(
    renderer: &Renderer,
    layer: Arc<Layer>,
    settings: TransparencySettings,
    lights: Vec<Arc<LightBuffer>>,
) -> (
    spreadlight_render::report::FrameReport,
    ImageF32,
    Arc<Transparency>,
) {
    lit_pane_by(renderer, layer, settings, lights, None)
}

/// `lit_pane`, with an environment.
fn lit_pane_by(
    renderer: &Renderer,
    layer: Arc<Layer>,
    settings: TransparencySettings,
    lights: Vec<Arc<LightBuffer>>,
    environment: Option<Arc<Environment>>,
) -> (
    spreadlight_render::report::FrameReport,
    ImageF32,
    Arc<Transparency>,
) {
    let lights = lights
        .into_iter()
        .map(|lights| TransparentLights {
            lights,
            shadows: None,
        })
        .collect();
    lit_pane_with(
        renderer,
        layer,
        settings,
        LitBy {
            lights,
            environment,
            ..Default::default()
        },
    )
}

/// The pane lit as `by` says over a black image.
fn lit_pane_with(
    renderer: &Renderer,
    layer: Arc<Layer>,
    settings: TransparencySettings,
    by: LitBy,
) -> (
    spreadlight_render::report::FrameReport,
    ImageF32,
    Arc<Transparency>,
) {
    let opaque = balls(renderer, &[Ball::still(Vec3::ZERO, 0.5)]);
    let g = gbuffer(renderer, opaque, look(EYE, Vec3::ZERO, FOV, 1.0), None);
    let black = image(renderer, SIZE, |_, _| [0.0, 0.0, 0.0, 1.0]);
    let pass = Transparency::lit(
        renderer,
        None,
        black.texture_ref(),
        g,
        vec![layer],
        settings,
        by,
    );
    let (report, out) = render(renderer, pass.as_ref(), &pass.output, SIZE);
    (report, out, pass)
}

/// Where the ray through pixel (x, y)'s centre meets the pane.
fn pane_point(x: u32, y: u32) -> Vec3 {
    let half = (FOV / 2.0).tan();
    let ndc_x = (x as f32 + 0.5) / SIZE.0 as f32 * 2.0 - 1.0;
    let ndc_y = 1.0 - (y as f32 + 0.5) / SIZE.1 as f32 * 2.0;
    let direction = Vec3::new(ndc_x * half, ndc_y * half, -1.0);
    EYE + direction * ((EYE.z - PANE_Z) / 1.0)
}

/// What the CPU reference says the pane shows at pixel (x, y) under `points` and `suns`.
fn reference(x: u32, y: u32, points: &[PointLight], suns: &[SunLight]) -> Vec3 {
    let p = pane_point(x, y);
    let n = Vec3::Z;
    let v = (EYE - p).normalize();
    let brdf = |l: Vec3| {
        let b = cook_torrance_f0(n, v, l, ALBEDO, ROUGHNESS, METALLIC, 0.04, true);
        b.diffuse + b.specular
    };
    let mut sum = Vec3::ZERO;
    for light in points {
        let to = light.position - p;
        sum += brdf(to.normalize())
            * light.color
            * light.intensity
            * point_attenuation(to.length(), light.range);
    }
    for sun in suns {
        sum += brdf(-sun.direction.normalize()) * sun.color * sun.illuminance;
    }
    sum
}

fn point(position: Vec3, color: Vec3, intensity: f32, range: f32) -> PointLight {
    PointLight {
        position,
        color,
        intensity,
        range,
        shadow: None,
    }
}

/// Two points lighting the glass pane from in front, of different colours and reaches.
fn glass_points() -> [PointLight; 2] {
    [
        point(Vec3::new(1.0, 1.5, 4.5), Vec3::new(1.0, 0.9, 0.8), 6.0, 6.0),
        point(
            Vec3::new(-1.5, -1.0, 4.0),
            Vec3::new(0.3, 0.5, 1.0),
            4.0,
            4.0,
        ),
    ]
}

/// A warm sun from above and behind the camera.
const GLASS_SUN: SunLight = SunLight {
    direction: Vec3::new(0.4, -0.3, -1.0),
    color: Vec3::new(1.0, 0.95, 0.9),
    illuminance: 0.8,
    shadow: None,
};

/// A buffer of `points` and one of `suns`: a light pass each.
fn light_buffers(
    renderer: &Renderer,
    points: &[PointLight],
    suns: &[SunLight],
) -> Vec<Arc<LightBuffer>> {
    vec![
        LightBuffer::points(renderer, points),
        LightBuffer::suns(renderer, suns),
    ]
}

/// Compares the pane's colour with the reference at a spread of pixels.
fn assert_matches_reference(out: &ImageF32, points: &[PointLight], suns: &[SunLight], what: &str) {
    let mut lit = 0;
    for (x, y) in [(24, 24), (10, 12), (36, 30), (20, 40), (40, 8), (5, 5)] {
        let want = reference(x, y, points, suns);
        let got = Vec3::from_slice(&at(out, x, y)[..3]);
        // Half-float accumulation: about three decimal digits.
        let tolerance = 2e-3 + 1e-2 * want.max_element();
        assert!(
            (got - want).abs().max_element() <= tolerance,
            "{what}: pixel ({x}, {y}) is {got}, the reference says {want}"
        );
        lit += usize::from(want.max_element() > 0.05);
    }
    assert!(lit >= 3, "{what}: the chosen pixels are lit");
}

#[test]
fn point_and_sun_lights_on_glass_match_the_cpu_brdf_naive_and_clustered() {
    let renderer = test_renderer();
    let [near, far] = glass_points();
    let points = [
        near,
        far,
        // Out of reach of the pane: lights nothing.
        point(Vec3::new(0.0, 0.0, 12.0), Vec3::ONE, 100.0, 2.0),
    ];
    let suns = [GLASS_SUN];
    let buffers = || light_buffers(&renderer, &points, &suns);
    let mut images = Vec::new();
    for light_loop in [LightLoop::Naive, LightLoop::Clustered] {
        let (report, out, pass) = lit_pane(
            &renderer,
            pane(&renderer, None, 1.0),
            dark(light_loop),
            buffers(),
        );
        assert_matches_reference(&out, &points, &suns, &format!("{light_loop:?}"));
        // A light pass per buffer; only the point buffer is clustered (suns have no range).
        assert_eq!(report.counter(LIGHT_PASSES), 2);
        let clustered = u64::from(light_loop == LightLoop::Clustered);
        assert_eq!(report.counter(ASSIGNED), clustered);
        // The base pass and one light pass per buffer: no spot code anywhere.
        let keys = pass.keys();
        assert_eq!(keys.len(), 3);
        assert!(
            keys.iter()
                .all(|k| !k.key().features.contains("LIGHT_SPOT"))
        );
        images.push(out);
    }
    // The two walks visit the same lights in another order: the same picture.
    for (a, b) in images[0].pixels.iter().zip(&images[1].pixels) {
        assert!(
            a.iter()
                .zip(b)
                .all(|(s, t)| (s - t).abs() <= 1e-3 * s.abs().max(1.0)),
            "{a:?} vs {b:?}"
        );
    }
}

#[test]
fn compute_shading_matches_the_cpu_brdf_and_records_every_fragment() {
    let renderer = test_renderer();
    let (points, suns) = (glass_points(), [GLASS_SUN]);
    let buffers = || light_buffers(&renderer, &points, &suns);
    for light_loop in [LightLoop::Naive, LightLoop::Clustered] {
        let what = format!("{light_loop:?} in compute");
        let (report, out, pass) = lit_pane(
            &renderer,
            pane(&renderer, None, 1.0),
            computed(dark(light_loop)),
            buffers(),
        );
        assert!(pass.shades_in_compute());
        assert_matches_reference(&out, &points, &suns, &what);
        // No layer is drawn again: one compute pass per light buffer.
        assert_eq!(report.counter(LIGHT_PASSES), 0, "{what}");
        assert_eq!(report.counter(SHADED), 2, "{what}");
        assert_eq!(report.counter(FRAGMENT_SLOTS), u64::from(SLOTS), "{what}");
        assert_eq!(
            report.counter(ASSIGNED),
            u64::from(light_loop == LightLoop::Clustered)
        );
        // The recording base pass, a shade per buffer and the shaded resolve.
        let keys = pass.keys();
        assert_eq!(keys.len(), 4, "{what}: {keys:?}");
        assert!(
            keys.iter()
                .any(|k| matches!(k.pass, TransparencyPass::Base { records: true, .. }))
        );
        assert!(keys.contains(&spreadlight_render::post::TransparencyKey::SHADED_RESOLVE));
        assert_eq!(pass.missed_fragments(&renderer).expect("read back"), 0);
        let (_, forward, forward_pass) = lit_pane(
            &renderer,
            pane(&renderer, None, 1.0),
            dark(light_loop),
            buffers(),
        );
        assert!(!forward_pass.shades_in_compute());
        let (d, worst) = largest_difference(&forward, &out);
        assert!(
            d <= COMPUTE_TOLERANCE,
            "{what}: {d} from the forward path {worst}"
        );
    }
    // Without a light buffer there is nothing to shade: the forward keys, no records.
    let (report, _, pass) = lit_pane(
        &renderer,
        pane(&renderer, None, 1.0),
        computed(unlit()),
        vec![],
    );
    assert!(!pass.shades_in_compute());
    assert_eq!(report.counter(SHADED), 0);
    assert_eq!(report.counter(FRAGMENT_SLOTS), 0);
}

#[test]
fn compute_shading_matches_forward_with_a_colour_and_a_normal_map() {
    let renderer = test_renderer();
    // A checker of two colours and a normal map tilting alternate texels
    // four ways: the lit colour changes from texel to texel.
    let checker: Vec<u8> = (0..16)
        .flat_map(|i| {
            if (i % 4 + i / 4) % 2 == 0 {
                [230u8, 128, 50, 255]
            } else {
                [80, 200, 230, 255]
            }
        })
        .collect();
    let colours = StaticTexture::new(GpuTexture::from_rgba8(
        &renderer.gpu,
        4,
        4,
        &checker,
        false,
        "checker",
    ));
    let tilts: Vec<u8> = (0..16)
        .flat_map(|i| match i % 4 {
            0 => [200u8, 128, 220, 255],
            1 => [60, 128, 220, 255],
            2 => [128, 200, 220, 255],
            _ => [128, 128, 255, 255],
        })
        .collect();
    let normals = StaticTexture::new(GpuTexture::from_rgba8(
        &renderer.gpu,
        4,
        4,
        &tilts,
        false,
        "tilting normal map",
    ));
    let mapped = || {
        let plain = pane(&renderer, None, 0.7);
        let features = LayerFeatures {
            texcoords: true,
            normal_map: true,
            ..Default::default()
        };
        let mut layer = Layer::new(
            None,
            plain.batches.clone(),
            features,
            Some(normals.texture_ref()),
        )
        .expect("the plane has UVs and tangents");
        layer.color_map = Some(colours.texture_ref());
        Arc::new(layer)
    };
    let points = [
        point(Vec3::new(1.0, 1.5, 4.5), Vec3::new(1.0, 0.9, 0.8), 6.0, 6.0),
        point(
            Vec3::new(-1.0, -0.5, 3.6),
            Vec3::new(0.3, 0.5, 1.0),
            3.0,
            3.0,
        ),
    ];
    let lights = || vec![LightBuffer::points(&renderer, &points)];
    let (_, forward, _) = lit_pane(&renderer, mapped(), dark(LightLoop::Clustered), lights());
    let (_, out, pass) = lit_pane(
        &renderer,
        mapped(),
        computed(dark(LightLoop::Clustered)),
        lights(),
    );
    assert!(pass.shades_in_compute());
    let (d, worst) = largest_difference(&forward, &out);
    assert!(d <= COMPUTE_TOLERANCE, "{d} from the forward path {worst}");
    // The maps show: the lit pane is not one colour.
    let (lo, hi) = (at(&out, 20, 24), at(&out, 28, 24));
    assert!(lo[..3] != hi[..3], "{lo:?} {hi:?}");
}

#[test]
fn more_layers_than_slots_are_counted_and_lit_as_the_recorded_ones() {
    let renderer = test_renderer();
    // Twenty panes a hair apart, under one light far enough to light them
    // all alike: twelve fragments a pixel find no slot.
    let layers = 20;
    let panes = || {
        let mesh = renderer
            .meshes
            .upload(&renderer.gpu, &plane())
            .expect("upload");
        let instances = (0..layers)
            .map(|i| {
                let t = Mat4::from_translation(Vec3::new(0.0, 0.0, PANE_Z + i as f32 * 1e-3))
                    * Mat4::from_rotation_x(std::f32::consts::FRAC_PI_2)
                    * Mat4::from_scale(Vec3::splat(4.0));
                InstanceInput {
                    transform: t,
                    previous_transform: t,
                    color: ALBEDO.extend(0.3).to_array(),
                    material_id: 0,
                    object_id: 0,
                }
            })
            .collect();
        Arc::new(Layer::plain(vec![DrawBatch { mesh, instances }]))
    };
    let points = [point(Vec3::new(0.5, 0.5, 40.0), Vec3::ONE, 5e3, 100.0)];
    let lights = || vec![LightBuffer::points(&renderer, &points)];
    let (_, forward, _) = lit_pane(&renderer, panes(), dark(LightLoop::Naive), lights());
    let (_, out, pass) = lit_pane(
        &renderer,
        panes(),
        computed(dark(LightLoop::Naive)),
        lights(),
    );
    let missed = pass.missed_fragments(&renderer).expect("read back");
    let covered = out.pixels.iter().filter(|p| p[..3] != [0.0; 3]).count() as u32;
    assert!(covered > 100, "the panes cover the middle: {covered}");
    assert_eq!(
        missed,
        covered * (layers - SLOTS),
        "every covered pixel misses twelve"
    );
    // Alike layers: the missed ones lit as the recorded ones is the picture.
    let (d, worst) = largest_difference(&forward, &out);
    assert!(d <= 1e-2, "{d} from the forward path {worst}");
    // Hard cases through the records: a light at the surface, a perfect
    // mirror, zero normals, and lights past half-float range stay finite.
    let on = pane_point(24, 24);
    let wild = [
        point(on, Vec3::ONE, 1e6, 1.0),
        point(on + Vec3::Z * 1e-7, Vec3::ONE, 1e30, 1e-20),
        point(Vec3::new(0.5, 0.5, 3.2), Vec3::ONE, 1e38, 1e30),
    ];
    let mirror = TransparencySettings {
        roughness: 0.0,
        metallic: 1.0,
        ..computed(dark(LightLoop::Naive))
    };
    let mut flat = plane();
    flat.normals.iter_mut().for_each(|n| *n = [0.0; 3]);
    for (what, layer, settings) in [
        ("mirror", pane(&renderer, None, 0.5), mirror),
        ("overfull", panes(), mirror),
        (
            "zero normals",
            pane(&renderer, Some(flat), 1.0),
            computed(dark(LightLoop::Clustered)),
        ),
    ] {
        let (_, out, _) = lit_pane(
            &renderer,
            layer,
            settings,
            vec![LightBuffer::points(&renderer, &wild)],
        );
        // `render` asserts every pixel finite; and nothing past half-float range.
        let (lo, hi) = range(&out);
        assert!(lo >= 0.0 && hi <= 65000.0, "{what}: {lo}..{hi}");
        assert!(hi > 1.0, "{what}: the lights light the pane");
    }
}

#[test]
fn light_at_the_surface_zero_roughness_and_zero_normals_stay_finite() {
    let renderer = test_renderer();
    // A light on the pane at the centre pixel's point, and one a hair off
    // it; a sun straight down the mirror direction of a perfect mirror.
    let on = pane_point(24, 24);
    let points = [
        point(on, Vec3::ONE, 1e6, 1.0),
        point(on + Vec3::Z * 1e-7, Vec3::ONE, 1e30, 1e-20),
        point(Vec3::new(0.5, 0.5, 3.2), Vec3::ONE, 1e38, 1e30),
    ];
    let suns = [SunLight {
        direction: Vec3::NEG_Z,
        color: Vec3::ONE,
        illuminance: 1e30,
        shadow: None,
    }];
    let mirror = TransparencySettings {
        roughness: 0.0,
        metallic: 1.0,
        ..dark(LightLoop::Naive)
    };
    // Zero-length normals: the plane with every normal zeroed.
    let mut flat = plane();
    flat.normals.iter_mut().for_each(|n| *n = [0.0; 3]);
    for (what, layer, settings) in [
        ("mirror", pane(&renderer, None, 1.0), mirror),
        ("half-covering mirror", pane(&renderer, None, 0.5), mirror),
        (
            "zero normals",
            pane(&renderer, Some(flat), 1.0),
            dark(LightLoop::Clustered),
        ),
    ] {
        let (_, out, _) = lit_pane(
            &renderer,
            layer,
            settings,
            vec![
                LightBuffer::points(&renderer, &points),
                LightBuffer::suns(&renderer, &suns),
            ],
        );
        // `render` asserts every pixel finite; and nothing past half-float range.
        let (lo, hi) = range(&out);
        assert!(lo >= 0.0 && hi <= 65000.0, "{what}: {lo}..{hi}");
        assert!(hi > 1.0, "{what}: the lights light the pane");
    }
}

#[test]
fn no_light_buffer_no_light_pass_and_the_old_look() {
    let renderer = test_renderer();
    // Unlit settings as before: every light pass is absent, the key light
    // and ambient give today's colour (ambient 1: the albedo).
    let (report, out, pass) = lit_pane(&renderer, pane(&renderer, None, 1.0), unlit(), vec![]);
    assert_eq!(report.counter(LIGHT_PASSES), 0);
    assert_eq!(report.counter(ASSIGNED), 0);
    assert!(pass.keys().iter().all(|k| k.pass
        == TransparencyPass::Base {
            environment: false,
            matcap: MatCapKey::Off,
            marks: false,
            transmission: RefractionKey::Off,
            records: false,
        }));
    // Nothing transmits: no refraction code, the opaque image unbound, no mip chain.
    assert_eq!(report.counter(REFRACTING), 0);
    assert_eq!(report.counter(MIP_CHAINS), 0);
    let c = Vec3::from_slice(&at(&out, 24, 24)[..3]);
    assert!((c - ALBEDO).abs().max_element() < 5e-3, "{c}");
    // An empty light buffer is no light pass either.
    let (report, _, _) = lit_pane(
        &renderer,
        pane(&renderer, None, 1.0),
        unlit(),
        vec![LightBuffer::points(&renderer, &[])],
    );
    assert_eq!(report.counter(LIGHT_PASSES), 0);
    // Nothing transparent: a copy, no light pass, no assignment, whatever is connected.
    let (g, black) = ball_under_green(&renderer);
    let pass = Transparency::lit(
        &renderer,
        None,
        black.texture_ref(),
        g,
        vec![],
        dark(LightLoop::Clustered),
        LitBy {
            lights: vec![TransparentLights {
                lights: LightBuffer::points(&renderer, &[point(Vec3::Z, Vec3::ONE, 1.0, 5.0)]),
                shadows: None,
            }],
            ..Default::default()
        },
    );
    let (report, _) = render(&renderer, pass.as_ref(), &pass.output, SIZE);
    assert_eq!(
        (
            report.counter(SKIPPED),
            report.counter(LIGHT_PASSES),
            report.counter(ASSIGNED)
        ),
        (1, 0, 0)
    );
}

#[test]
fn a_uniform_environment_reflects_off_white_metal_glass_as_its_specular_albedo() {
    // Radiance 0.5 from every direction: the prefiltered reflection is 0.5
    // at every roughness, so white metal (F0 = 1, no diffuse) shows 0.5
    // times its directional albedo, which the split-sum table holds (A + B)
    // and the CPU reference fits.
    let renderer = test_renderer();
    let radiance = 0.5;
    let image = Arc::new(EquirectImage {
        width: 16,
        height: 8,
        pixels: vec![[radiance, radiance, radiance, 1.0]; 16 * 8],
    });
    let environment = Environment::new(
        &renderer,
        None,
        EnvironmentSource::Equirect(image),
        EnvironmentQuality {
            cube_size: 16,
            samples: 64,
        },
    );
    // No light buffer: the built-in key light would be on; off, so the
    // environment alone lights the pane.
    let settings = TransparencySettings {
        metallic: 1.0,
        light_color: Vec3::ZERO,
        ..dark(LightLoop::Auto)
    };
    let white = pane_of(&renderer, None, glam::Vec4::ONE);
    let (_, out, pass) = lit_pane_by(&renderer, white, settings, vec![], Some(environment));
    assert_eq!(
        pass.keys()
            .iter()
            .filter(|k| k.key().features.contains("ENVIRONMENT"))
            .count(),
        1,
        "the base pass reads the environment"
    );
    for (x, y) in [(24, 24), (12, 30), (40, 10)] {
        let p = pane_point(x, y);
        let n_dot_v = (EYE - p).normalize().z;
        let want = radiance * specular_albedo(n_dot_v, ROUGHNESS);
        let got = at(&out, x, y);
        for c in &got[..3] {
            assert!(
                (c - want).abs() < 0.04 * want,
                "pixel ({x}, {y}): {got:?}, the reference says {want}"
            );
        }
    }
}

/// A clear coat on a BLEND surface reflects the environment too (the base
/// pass's `coated_environment`, as Reflection for opaque ones). Radiance L
/// from every direction: the irradiance is L and the prefiltered reflection
/// L at every roughness, and at roughness 0 the split sum is Schlick's
/// S(f0, N.V). A pane turned 1.2 rad (N.V about 0.36, where the coat's
/// Fresnel is 0.14), albedo 0.5, not metal, reflectance 0, with a mirror
/// coat of factor c, shows L [(0.5 + S(0, N.V)) (1 - c S(0.04, N.V)) +
/// c S(0.04, N.V)]: diffuse and base reflection dimmed by what the coat
/// reflects, and the coat's lobe.
#[test]
fn a_coated_blend_surface_reflects_the_environment_over_its_dimmed_base() {
    use spreadlight_reference::refraction::hit_plane;
    use spreadlight_render::material::{Feature, Material, MaterialWorld};
    let renderer = test_renderer();
    let radiance = 1.0;
    let image = Arc::new(EquirectImage {
        width: 16,
        height: 8,
        pixels: vec![[radiance, radiance, radiance, 1.0]; 16 * 8],
    });
    let environment = Environment::new(
        &renderer,
        None,
        EnvironmentSource::Equirect(image),
        EnvironmentQuality {
            cube_size: 16,
            samples: 64,
        },
    );
    let albedo = 0.5;
    let tilt = 1.2;
    let (_, n) = glass_pane(&renderer, tilt);
    let schlick = |f0: f32, n_dot_v: f32| f0 + (1.0 - f0) * (1.0 - n_dot_v).powi(5);
    for coat in [0.0, 1.0, 0.5] {
        let mut material = Material::new()
            .with(Feature::CookTorrance, &[[0.0, 0.0, 0.0, 0.0]])
            .and_then(|m| m.with(Feature::Reflection, &[[1.0, 0.0, 0.0, 0.0]]))
            .expect("valid");
        if coat > 0.0 {
            material = material
                .with(Feature::Clearcoat, &[[coat, 0.0, 0.0, 0.0]])
                .expect("valid");
        }
        let world = MaterialWorld::new(&renderer, vec![material]);
        // The turned pane, opaque grey (alpha 1: its own colour alone).
        let (glass, _) = glass_pane(&renderer, tilt);
        let batch = &glass.batches[0];
        let instance = InstanceInput {
            color: [albedo, albedo, albedo, 1.0],
            ..batch.instances[0]
        };
        let layer = Arc::new(Layer::plain(vec![DrawBatch {
            mesh: batch.mesh.clone(),
            instances: vec![instance],
        }]));
        let settings = TransparencySettings {
            light_color: Vec3::ZERO,
            ..dark(LightLoop::Auto)
        };
        let by = LitBy {
            environment: Some(environment.clone()),
            materials: Some(world),
            ..Default::default()
        };
        let (_, out, pass) = lit_pane_with(&renderer, layer, settings, by);
        assert_eq!(
            pass.keys()
                .iter()
                .any(|k| k.key().features.contains("CLEARCOAT")),
            coat > 0.0,
            "the base pass compiles the coat only for a coated world"
        );
        let mut checked = 0;
        for x in 0..SIZE.0 {
            let y = 24;
            let d = pixel_ray(x, y);
            let Some(p) = hit_plane(EYE, d, Vec3::new(0.0, 0.0, PANE_Z), n) else {
                continue;
            };
            let across = n.cross(Vec3::Y).normalize();
            if (p - Vec3::new(0.0, 0.0, PANE_Z)).dot(across).abs() > 1.8 {
                continue;
            }
            let n_dot_v = (EYE - p).normalize().dot(n);
            let lobe = coat * schlick(0.04, n_dot_v);
            let want = radiance * ((albedo + schlick(0.0, n_dot_v)) * (1.0 - lobe) + lobe);
            let got = at(&out, x, y);
            for c in &got[..3] {
                assert!(
                    (c - want).abs() < 0.02 * want,
                    "coat {coat}, pixel ({x}, {y}), N.V {n_dot_v}: {got:?}, analytic {want}"
                );
            }
            checked += 1;
        }
        assert!(checked > 8, "{checked} pane pixels checked");
    }
}

/// MatCap is a material feature, so a transparent layer whose material has
/// it gets it in its base pass as CompositeLight gives opaque surfaces: the
/// pane faces the eye, its view-space normal is +z everywhere, and the
/// built-in matcap there (the CPU twin's value) is added (Add) or tinted by
/// the albedo (Multiply), times strength. Without a MatCap material no
/// MATCAP permutation is compiled.
#[test]
fn matcap_materials_shade_transparent_layers_as_the_cpu_matcap_says() {
    use spreadlight_reference::matcap::{default_matcap, matcap_uv};
    use spreadlight_render::material::{
        Feature, MatCapMapping, MatCapMode, Material, MaterialWorld, matcap_params,
    };
    let renderer = test_renderer();
    let image = default_matcap(matcap_uv(Vec3::Z, Vec3::NEG_Z, false));
    let matcap_keys = |pass: &Transparency| {
        pass.keys()
            .iter()
            .filter(|k| k.key().features.contains("MATCAP"))
            .count()
    };
    let plain = MaterialWorld::new(&renderer, vec![Material::new()]);
    let (_, out, pass) = lit_pane_with(
        &renderer,
        pane(&renderer, None, 1.0),
        unlit(),
        LitBy {
            materials: Some(plain),
            ..Default::default()
        },
    );
    assert_eq!(matcap_keys(&pass), 0, "no MatCap material, no matcap code");
    let c = Vec3::from_slice(&at(&out, 24, 24)[..3]);
    assert!((c - ALBEDO).abs().max_element() < 5e-3, "{c}");
    for (mode, strength, want) in [
        (MatCapMode::Add, 1.0, ALBEDO + image),
        (MatCapMode::Add, 0.5, ALBEDO + image * 0.5),
        (MatCapMode::Multiply, 1.0, ALBEDO + image * ALBEDO),
    ] {
        let material = Material::new()
            .with(
                Feature::MatCap,
                &[matcap_params(strength, mode, MatCapMapping::Normal)],
            )
            .expect("valid");
        let world = MaterialWorld::new(&renderer, vec![material]);
        let (_, out, pass) = lit_pane_with(
            &renderer,
            pane(&renderer, None, 1.0),
            unlit(),
            LitBy {
                materials: Some(world),
                ..Default::default()
            },
        );
        assert_eq!(matcap_keys(&pass), 1, "the base pass reads the matcap");
        assert!(out.all_finite());
        for (x, y) in [(24, 24), (14, 30), (34, 16)] {
            let c = Vec3::from_slice(&at(&out, x, y)[..3]);
            assert!(
                (c - want).abs().max_element() < 5e-3,
                "{mode:?} {strength} at ({x}, {y}): {c}, the matcap says {want}"
            );
        }
    }
}

/// A floor at y = -1.5 from the eye (z = 8) to z = -80: one layer through
/// every depth slice of the forward grid.
fn floor(renderer: &Renderer, alpha: f32) -> Arc<Layer> {
    let mesh = renderer
        .meshes
        .upload(&renderer.gpu, &plane())
        .expect("upload");
    let t = Mat4::from_translation(Vec3::new(0.0, -1.5, -36.0))
        * Mat4::from_scale(Vec3::new(40.0, 1.0, 88.0));
    Arc::new(Layer::plain(vec![DrawBatch {
        mesh,
        instances: vec![InstanceInput {
            transform: t,
            previous_transform: t,
            color: ALBEDO.extend(alpha).to_array(),
            material_id: 0,
            object_id: 0,
        }],
    }]))
}

/// Where the ray through the pixel-grid point (x, y) (edges included, not
/// centres) is `depth` in front of the eye (view-space z).
fn on_ray(x: f32, y: f32, depth: f32) -> Vec3 {
    let half = (FOV / 2.0).tan();
    let ndc_x = x / SIZE.0 as f32 * 2.0 - 1.0;
    let ndc_y = 1.0 - y / SIZE.1 as f32 * 2.0;
    EYE + Vec3::new(ndc_x * half * depth, ndc_y * half * depth, -depth)
}

#[test]
fn froxel_lists_shade_as_every_light_does_near_far_across_slices_and_tile_edges() {
    let renderer = test_renderer();
    // Glass in front of all opaque geometry (depth 1), beside the ball and
    // far behind it (depth 38), and a floor through every slice.
    let layers = || {
        vec![
            glass(
                &renderer,
                &[
                    (Vec3::new(0.25, -0.2, 7.0), 0.3, [0.9, 0.8, 0.7, 0.5]),
                    (Vec3::new(0.9, 0.4, 1.0), 0.5, [0.6, 0.9, 0.8, 0.6]),
                    (Vec3::new(-6.0, 5.0, -30.0), 6.0, [0.7, 0.7, 1.0, 0.5]),
                ],
            ),
            floor(&renderer, 0.5),
        ]
    };
    // Lights strewn through the volume (a fixed sequence), with ranges from
    // half a unit to six; and small lights on the 32-pixel tile edges (the
    // column and row at pixel 32) where they meet the floor and the near glass.
    let mut state = 0x2545_f491_u32;
    let mut next = move || {
        state = state.wrapping_mul(1_664_525).wrapping_add(1_013_904_223);
        (state >> 8) as f32 / (1u32 << 24) as f32
    };
    let mut points: Vec<PointLight> = (0..60)
        .map(|_| {
            let position = Vec3::new(
                -4.0 + 8.0 * next(),
                -2.0 + 4.0 * next(),
                -40.0 + 47.5 * next(),
            );
            let color = Vec3::new(next(), next(), next());
            point(position, color, 40.0 + 400.0 * next(), 0.5 + 5.5 * next())
        })
        .collect();
    for depth in [5.0, 20.0] {
        let mut p = on_ray(32.0, 40.0, depth);
        p.y = -1.4;
        points.push(point(p, Vec3::ONE, 3.0, 0.6));
    }
    // The floor meets the row y = 32 at depth 1.5 / (tan(FOV / 2) / 3).
    let row = 1.5 / ((FOV / 2.0).tan() / 3.0);
    points.push(point(
        on_ray(20.0, 32.0, row) + Vec3::Y * 0.1,
        Vec3::ONE,
        3.0,
        0.8,
    ));
    // On the tile corner (32, 32), just before the near glass.
    points.push(point(on_ray(32.0, 32.0, 0.6), Vec3::ONE, 20.0, 0.5));
    // Before the far glass, and over the floor far off (depth 26).
    points.push(point(Vec3::new(-4.5, 3.5, -22.0), Vec3::ONE, 400.0, 6.0));
    let mut far = on_ray(4.5, 28.5, 26.0);
    far.y = -1.0;
    points.push(point(far, Vec3::ONE, 300.0, 3.0));
    let black = image(&renderer, SIZE, |_, _| [0.0, 0.0, 0.0, 1.0]);
    let opaque = balls(&renderer, &[Ball::still(Vec3::ZERO, 0.5)]);
    let g = gbuffer(&renderer, opaque, look(EYE, Vec3::ZERO, FOV, 1.0), None);
    let shade = |light_loop, shading, points: &[PointLight]| {
        let by = LitBy {
            lights: vec![TransparentLights {
                lights: LightBuffer::points(&renderer, points),
                shadows: None,
            }],
            ..Default::default()
        };
        let pass = Transparency::lit(
            &renderer,
            None,
            black.texture_ref(),
            g.clone(),
            layers(),
            TransparencySettings {
                shading,
                ..dark(light_loop)
            },
            by,
        );
        // `render` asserts every pixel finite.
        let (report, out) = render(&renderer, pass.as_ref(), &pass.output, SIZE);
        (report, out)
    };
    let forward = TransparencyShading::Forward;
    let same = |a: &ImageF32, b: &ImageF32, what: &str| {
        for (i, (s, t)) in a.pixels.iter().zip(&b.pixels).enumerate() {
            let (x, y) = (i as u32 % SIZE.0, i as u32 / SIZE.0);
            assert!(
                s.iter()
                    .zip(t)
                    .all(|(s, t)| (s - t).abs() <= 1e-3 * s.abs().max(1.0)),
                "{what}: pixel ({x}, {y}) every light {s:?}, froxel lists {t:?}"
            );
        }
    };
    let (_, naive) = shade(LightLoop::Naive, forward, &points);
    let (report, clustered) = shade(LightLoop::Clustered, forward, &points);
    assert_eq!(report.counter(ASSIGNED), 1);
    same(&naive, &clustered, "60 strewn lights and 4 on tile edges");
    // The lights reach the near glass, the floor near and far, and the far glass.
    let probes = [(37, 35), (10, 44), (4, 28), (12, 14)];
    for (x, y) in probes {
        let c = at(&naive, x, y);
        assert!(c[..3].iter().any(|c| *c > 0.05), "({x}, {y}) is lit: {c:?}");
    }
    let lit = naive
        .pixels
        .iter()
        .filter(|p| p[..3].iter().any(|c| *c > 0.02))
        .count();
    assert!(
        lit * 3 > naive.pixels.len(),
        "a third of the pixels are lit: {lit}"
    );
    // Zero lights: no light pass, the same as naive's unlit picture.
    let (report, none) = shade(LightLoop::Clustered, forward, &[]);
    assert_eq!(report.counter(LIGHT_PASSES), 0);
    let (_, none_naive) = shade(LightLoop::Naive, forward, &[]);
    same(&none_naive, &none, "no lights");
    // Shaded in compute over the recorded fragments, walking the same lists
    // or every light: the forward picture within the records' precision.
    let mut per_pixel = None;
    for (light_loop, reference, shading) in [
        (
            LightLoop::Clustered,
            &clustered,
            TransparencyShading::Compute,
        ),
        (LightLoop::Naive, &naive, TransparencyShading::Compute),
        (LightLoop::Clustered, &clustered, TransparencyShading::Tiled),
    ] {
        let what = format!("{light_loop:?} {shading:?}");
        let (report, out) = shade(light_loop, shading, &points);
        assert_eq!(report.counter(SHADED), 1);
        assert_eq!(report.counter(LIGHT_PASSES), 0);
        let (d, worst) = largest_difference(reference, &out);
        // Most pixels agree to the output's own half-float precision.
        let loose = reference
            .pixels
            .iter()
            .zip(&out.pixels)
            .filter(|(s, t)| {
                s.iter()
                    .zip(t.iter())
                    .any(|(u, v)| (u - v).abs() / u.abs().max(1.0) > 2e-3)
            })
            .count();
        assert!(
            loose * 50 <= out.pixels.len(),
            "{what}: {loose} pixels differ by more than 2e-3"
        );
        assert!(d <= COMPUTE_TOLERANCE, "{what}: {d} from forward {worst}");
        match shading {
            // The tiles share the lights each fragment walks alone in Compute, in the same order.
            TransparencyShading::Tiled => {
                let alone = per_pixel.as_ref().expect("Compute ran first");
                let (d, worst) = largest_difference(alone, &out);
                assert!(d <= 1e-5, "{what}: {d} from Compute {worst}");
            }
            _ if light_loop == LightLoop::Clustered => per_pixel = Some(out),
            _ => {}
        }
    }
}

/// The refraction scene: an opaque wall at z = 0 facing the eye, 40 wide.
fn wall(renderer: &Renderer) -> Arc<GBuffer> {
    let mesh = renderer
        .meshes
        .upload(&renderer.gpu, &plane())
        .expect("upload");
    let t =
        Mat4::from_rotation_x(std::f32::consts::FRAC_PI_2) * Mat4::from_scale(Vec3::splat(40.0));
    let layer = Arc::new(Layer::plain(vec![DrawBatch {
        mesh,
        instances: vec![InstanceInput {
            transform: t,
            previous_transform: t,
            color: [1.0; 4],
            material_id: 0,
            object_id: 0,
        }],
    }]));
    gbuffer(renderer, layer, look(EYE, Vec3::ZERO, FOV, 1.0), None)
}

/// The glass: a 4 x 4 pane at z = PANE_Z turned `tilt` radians about y,
/// white and fully transmissive (alpha 0: all of it shows through).
fn glass_pane(renderer: &Renderer, tilt: f32) -> (Arc<Layer>, Vec3) {
    let mesh = renderer
        .meshes
        .upload(&renderer.gpu, &plane())
        .expect("upload");
    let turn = Mat4::from_rotation_y(tilt);
    let t = Mat4::from_translation(Vec3::new(0.0, 0.0, PANE_Z))
        * turn
        * Mat4::from_rotation_x(std::f32::consts::FRAC_PI_2)
        * Mat4::from_scale(Vec3::splat(4.0));
    let layer = Arc::new(Layer::plain(vec![DrawBatch {
        mesh,
        instances: vec![InstanceInput {
            transform: t,
            previous_transform: t,
            color: [1.0, 1.0, 1.0, 0.0],
            material_id: 0,
            object_id: 0,
        }],
    }]));
    (layer, turn.transform_vector3(Vec3::Z))
}

/// A ramp: each pixel holds its own uv in red and green, so what a pixel
/// shows says where it sampled (linear filtering of a ramp is the ramp).
fn uv_ramp(x: u32, y: u32) -> [f32; 4] {
    [
        (x as f32 + 0.5) / SIZE.0 as f32,
        (y as f32 + 0.5) / SIZE.1 as f32,
        0.0,
        1.0,
    ]
}

/// Unlit glass that refracts as `t` says (roughness 0: no blur).
fn glass_settings(t: TransmissionSettings) -> TransparencySettings {
    TransparencySettings {
        roughness: 0.0,
        transmission: t,
        ..unlit()
    }
}

/// The glass pane tilted `tilt` over the wall with `lit` as the opaque image.
fn refract_through(
    renderer: &Renderer,
    tilt: f32,
    settings: TransparencySettings,
    materials: Option<Arc<spreadlight_render::material::MaterialWorld>>,
    lit: fn(u32, u32) -> [f32; 4],
) -> (
    spreadlight_render::report::FrameReport,
    ImageF32,
    Arc<Transparency>,
    Vec3,
) {
    let by = LitBy {
        materials,
        ..Default::default()
    };
    refract_by(renderer, tilt, settings, by, lit)
}

/// [`refract_through`] lit (and refracting) by what `by` brings.
fn refract_by(
    renderer: &Renderer,
    tilt: f32,
    settings: TransparencySettings,
    by: LitBy,
    lit: fn(u32, u32) -> [f32; 4],
) -> (
    spreadlight_render::report::FrameReport,
    ImageF32,
    Arc<Transparency>,
    Vec3,
) {
    let (layer, normal) = glass_pane(renderer, tilt);
    let lit = image(renderer, SIZE, lit);
    let pass = Transparency::lit(
        renderer,
        None,
        lit.texture_ref(),
        wall(renderer),
        vec![layer],
        settings,
        by,
    );
    let (report, out) = render(renderer, pass.as_ref(), &pass.output, SIZE);
    (report, out, pass, normal)
}

/// The ray through pixel (x, y)'s centre: from the eye, unit.
fn pixel_ray(x: u32, y: u32) -> Vec3 {
    let half = (FOV / 2.0).tan();
    let ndc_x = (x as f32 + 0.5) / SIZE.0 as f32 * 2.0 - 1.0;
    let ndc_y = 1.0 - (y as f32 + 0.5) / SIZE.1 as f32 * 2.0;
    Vec3::new(ndc_x * half, ndc_y * half, -1.0).normalize()
}

/// The uv on screen of world point `p`.
fn screen_uv(p: Vec3) -> glam::Vec2 {
    let camera = look(EYE, Vec3::ZERO, FOV, 1.0);
    let clip = camera.projection * camera.view * p.extend(1.0);
    let ndc = clip.truncate().truncate() / clip.w;
    glam::Vec2::new(ndc.x * 0.5 + 0.5, 0.5 - ndc.y * 0.5)
}

/// Where, by the CPU reference, the eye sees the wall through the pane
/// (normal `n`) at pixel (x, y) with `ior` and `thickness`: the wall's uv
/// and the path inside the glass. `None` off the pane.
fn snell_uv(x: u32, y: u32, n: Vec3, ior: f32, thickness: f32) -> Option<(glam::Vec2, f32)> {
    use spreadlight_reference::refraction::{hit_plane, through_slab};
    let d = pixel_ray(x, y);
    let entry = hit_plane(EYE, d, Vec3::new(0.0, 0.0, PANE_Z), n)?;
    let local = entry - Vec3::new(0.0, 0.0, PANE_Z);
    // On the pane: 2 either side of its centre, along its two in-plane axes.
    let across = n.cross(Vec3::Y).normalize();
    if local.dot(across).abs() > 1.8 || local.y.abs() > 1.8 {
        return None;
    }
    let (back, path) = through_slab(entry, d, n, ior, thickness, Vec3::ZERO, Vec3::Z)?;
    Some((screen_uv(back), path))
}

/// Pixels on the pane across its width (the tilt bends rays along x).
const REFRACTED_PIXELS: [(u32, u32); 4] = [(14, 24), (20, 20), (26, 28), (32, 24)];

#[test]
fn a_glass_slab_shifts_what_is_behind_by_snells_law_and_ior_one_does_not() {
    let renderer = test_renderer();
    let tilt = 0.6;
    let texel = 1.0 / SIZE.0 as f32;
    for (ior, thickness) in [(1.5, 2.0), (1.33, 1.5), (1.0, 1.5)] {
        let t = TransmissionSettings {
            factor: 1.0,
            ior,
            thickness,
            ..Default::default()
        };
        let (report, out, pass, n) =
            refract_through(&renderer, tilt, glass_settings(t), None, uv_ramp);
        assert_eq!(report.counter(REFRACTING), 1);
        assert!(
            pass.keys()
                .iter()
                .any(|k| k.key().features.contains("TRANSMISSION"))
        );
        for (x, y) in REFRACTED_PIXELS {
            let (want, _) = snell_uv(x, y, n, ior, thickness).expect("the pixel sees the pane");
            let got = glam::Vec2::from_slice(&at(&out, x, y)[..2]);
            assert!(
                (got - want).abs().max_element() < 0.3 * texel,
                "ior {ior}, thickness {thickness} at ({x}, {y}): sampled {got}, Snell says {want}"
            );
            let own = glam::Vec2::from_slice(&uv_ramp(x, y)[..2]);
            if ior == 1.0 {
                // No bend: the wall straight behind, unshifted.
                assert!(
                    (got - own).abs().max_element() < 0.3 * texel,
                    "ior 1 at ({x}, {y}): {got} vs {own}"
                );
            } else {
                assert!(
                    (want - own).x.abs() > 1.5 * texel,
                    "a shift worth testing at ({x}, {y})"
                );
            }
        }
    }
}

#[test]
fn the_volume_absorbs_by_beer_lambert_over_the_path_inside() {
    let renderer = test_renderer();
    let color = Vec3::new(0.5, 0.25, 1.0);
    let (ior, thickness) = (1.5, 1.0);
    let t = TransmissionSettings {
        factor: 1.0,
        ior,
        thickness,
        attenuation_color: color,
        attenuation_distance: 2.0,
        ..Default::default()
    };
    let (_, out, _, n) = refract_through(&renderer, 0.6, glass_settings(t), None, |_, _| [1.0; 4]);
    for (x, y) in REFRACTED_PIXELS {
        let (_, path) = snell_uv(x, y, n, ior, thickness).expect("on the pane");
        // σ = -ln(c) / d: exp(-σ path) = c^(path / d).
        let sigma = Vec3::new(-color.x.ln(), -color.y.ln(), -color.z.ln()) / 2.0;
        let want = spreadlight_reference::refraction::beer_lambert(sigma, path);
        let got = Vec3::from_slice(&at(&out, x, y)[..3]);
        assert!(
            (got - want).abs().max_element() < 3e-3,
            "({x}, {y}): {got}, Beer-Lambert over {path} says {want}"
        );
        assert!(
            want.x < 0.75 && path > thickness,
            "absorbed along a slanted path"
        );
    }
}

/// A grey ramp: every channel holds the pixel's u, so each channel of what
/// a pixel shows says where that channel sampled.
fn grey_ramp(x: u32, _: u32) -> [f32; 4] {
    let u = (x as f32 + 0.5) / SIZE.0 as f32;
    [u, u, u, 1.0]
}

/// The column of [`white_then_black`]'s first black texel.
const EDGE: u32 = 24;

/// White left of column EDGE, black from it on.
fn white_then_black(x: u32, _: u32) -> [f32; 4] {
    if x < EDGE {
        [1.0; 4]
    } else {
        [0.0, 0.0, 0.0, 1.0]
    }
}

#[test]
fn dispersion_bends_red_green_and_blue_by_their_own_ior_and_zero_is_todays_image() {
    use spreadlight_render::material::{Feature, Material, MaterialWorld, transmission_params};
    let renderer = test_renderer();
    let texel = 1.0 / SIZE.0 as f32;
    let (tilt, ior, thickness) = (0.6, 1.5, 2.0);
    let glass = |dispersion: f32| {
        let params = transmission_params(1.0, ior, thickness, [1.0; 3], f32::INFINITY, dispersion);
        let material = Material::new()
            .with(Feature::Transmission, &params)
            .expect("valid");
        Some(MaterialWorld::new(&renderer, vec![material]))
    };
    let node = glass_settings(TransmissionSettings::default());
    // Dispersion 20 (an Abbe number of 1, far beyond flint's 30ish, so
    // the spread is pixels wide): KHR_materials_dispersion's spread is
    // (ior - 1) x 20 / 20 = 0.5 about the green's 1.5.
    let iors = [1.25, 1.5, 1.75];
    let (_, out, _, n) = refract_through(&renderer, tilt, node, glass(20.0), grey_ramp);
    for (x, y) in REFRACTED_PIXELS {
        let got = at(&out, x, y);
        let want = iors.map(|ior| snell_uv(x, y, n, ior, thickness).expect("on the pane").0.x);
        for c in 0..3 {
            assert!(
                (got[c] - want[c]).abs() < 0.3 * texel,
                "({x}, {y}) channel {c} (ior {}): sampled u {}, Snell says {}",
                iors[c],
                got[c],
                want[c]
            );
        }
        assert!(
            want[0] - want[2] > 1.5 * texel,
            "a spread worth testing at ({x}, {y}): {want:?}"
        );
    }
    // Over a white/black edge: the fringes the CPU predicts. Bilinear
    // filtering of the edge gives a sample at texel coordinate t (u x width
    // - 0.5) white below EDGE - 1 and black above EDGE; channels whose
    // sample is clear of that band by 0.3 texel (the tolerance above) are
    // checked.
    let (_, out, _, n) = refract_through(&renderer, tilt, node, glass(20.0), white_then_black);
    let (mut checked, mut fringes) = (0, 0);
    for y in [20, 24, 28] {
        for x in 0..SIZE.0 {
            let Some(want) = iors
                .iter()
                .map(|&ior| snell_uv(x, y, n, ior, thickness))
                .collect::<Option<Vec<_>>>()
            else {
                continue;
            };
            let got = at(&out, x, y);
            let mut seen = [None; 3];
            for c in 0..3 {
                let t = want[c].0.x * SIZE.0 as f32 - 0.5;
                let expected = if t <= EDGE as f32 - 1.3 {
                    1.0
                } else if t >= EDGE as f32 + 0.3 {
                    0.0
                } else {
                    continue;
                };
                assert!(
                    (got[c] - expected).abs() < 0.02,
                    "({x}, {y}) channel {c}: {} instead of {expected} (sampled at texel {t})",
                    got[c]
                );
                seen[c] = Some(expected);
                checked += 1;
            }
            // A fringe: red (the least bent) already on the black side
            // while blue (the most) still sees white; never the other way.
            if seen[0] == Some(0.0) && seen[2] == Some(1.0) {
                fringes += 1;
            }
            assert!(
                !(seen[0] == Some(1.0) && seen[2] == Some(0.0)),
                "({x}, {y}): {got:?}"
            );
        }
    }
    assert!(
        fringes >= 3 && checked > 200,
        "{fringes} fringes, {checked} checked"
    );
    // Dispersion 0 takes the walk it always did: the node's own glass
    // (no material world) with the same ior and thickness, bit for bit, and
    // every channel alike.
    let (_, zero, _, _) = refract_through(&renderer, tilt, node, glass(0.0), grey_ramp);
    let same = TransmissionSettings {
        factor: 1.0,
        ior,
        thickness,
        ..Default::default()
    };
    let (_, today, _, _) = refract_through(&renderer, tilt, glass_settings(same), None, grey_ramp);
    assert_eq!(
        zero.pixels, today.pixels,
        "dispersion 0 against the node's glass"
    );
    for (x, y) in REFRACTED_PIXELS {
        let got = at(&zero, x, y);
        assert!(got[0] == got[1] && got[1] == got[2], "({x}, {y}): {got:?}");
        let want = snell_uv(x, y, n, ior, thickness).expect("on the pane").0.x;
        assert!(
            (got[1] - want).abs() < 0.3 * texel,
            "({x}, {y}): {got:?} vs {want}"
        );
    }
}

#[test]
fn refraction_hard_cases_stay_finite_and_clamp_to_the_screen() {
    use spreadlight_render::material::{Feature, Material, MaterialWorld};
    let renderer = test_renderer();
    let texel = 1.0 / SIZE.0 as f32;
    let straight = |out: &ImageF32, what: &str| {
        for (x, y) in REFRACTED_PIXELS {
            let got = glam::Vec2::from_slice(&at(out, x, y)[..2]);
            let own = glam::Vec2::from_slice(&uv_ramp(x, y)[..2]);
            assert!(
                (got - own).abs().max_element() < 0.3 * texel,
                "{what} at ({x}, {y}): {got} vs {own}"
            );
        }
    };
    // An ior of 0, NaN or below 0 bends nothing; an infinite thickness is thin-walled.
    for (ior, thickness) in [
        (0.0, 1.0),
        (f32::NAN, 1.0),
        (-1.0, 1.0),
        (1.5, f32::INFINITY),
    ] {
        let t = TransmissionSettings {
            factor: 1.0,
            ior,
            thickness,
            attenuation_distance: f32::NAN,
            ..Default::default()
        };
        let (_, out, _, _) = refract_through(&renderer, 0.6, glass_settings(t), None, uv_ramp);
        straight(&out, &format!("ior {ior}, thickness {thickness}"));
    }
    // Through a material world the shader sees ior 0 itself (kept, not
    // sanitized to 1 on the CPU): it bends nothing either.
    let material = Material::new()
        .with(Feature::Transmission, &[[1.0, 0.0, 1.0, 0.0], [0.0; 4]])
        .expect("valid");
    let world = MaterialWorld::new(&renderer, vec![material]);
    let (report, out, _, _) = refract_through(
        &renderer,
        0.6,
        glass_settings(TransmissionSettings::default()),
        Some(world),
        uv_ramp,
    );
    assert_eq!(
        report.counter(REFRACTING),
        1,
        "the world's Transmission turns it on"
    );
    straight(&out, "a material's ior 0");
    // A slab a thousand units deep, steeply tilted, bends the rays off
    // screen (the CPU reference says where): they sample the screen's edge.
    let deep = TransmissionSettings {
        factor: 1.0,
        thickness: 1e3,
        ..Default::default()
    };
    let (_, out, _, n) = refract_through(&renderer, 1.2, glass_settings(deep), None, uv_ramp);
    let mut clamped = 0;
    for (x, y) in REFRACTED_PIXELS {
        // On the pane (by a thin slab's reference), and where the deep one's exit projects.
        if snell_uv(x, y, n, 1.5, 0.0).is_none() {
            continue;
        }
        let d = pixel_ray(x, y);
        let entry =
            spreadlight_reference::refraction::hit_plane(EYE, d, Vec3::new(0.0, 0.0, PANE_Z), n)
                .expect("on the pane");
        let (exit, _) = spreadlight_reference::refraction::slab_exit(entry, d, n, 1.5, 1e3);
        let want = screen_uv(exit);
        assert!(
            want.x < 0.0 || want.x > 1.0,
            "({x}, {y}) leaves the screen: {want}"
        );
        let u = at(&out, x, y)[0];
        let edge = if want.x < 0.0 {
            0.5 * texel
        } else {
            1.0 - 0.5 * texel
        };
        assert!(
            (u - edge).abs() < 0.1 * texel,
            "({x}, {y}): u {u}, not the edge {edge}"
        );
        clamped += 1;
    }
    assert!(clamped >= 2, "{clamped} pixels on the steep pane");
    for (tilt, t) in [
        (
            1.55,
            TransmissionSettings {
                factor: 1.0,
                thickness: 5.0,
                ..Default::default()
            },
        ),
        (
            0.6,
            TransmissionSettings {
                factor: 1.0,
                thickness: 1.0,
                attenuation_color: Vec3::ZERO,
                attenuation_distance: 1e-30,
                ..Default::default()
            },
        ),
    ] {
        let (_, out, _, _) = refract_through(&renderer, tilt, glass_settings(t), None, uv_ramp);
        let (lo, hi) = range(&out);
        assert!(lo >= 0.0 && hi <= 1.0 + 1e-3, "tilt {tilt}: {lo}..{hi}");
    }
}

/// Columns a pixel wide, alternately black and white (red): any blur over
/// two pixels or more is 0.5.
fn stripes(x: u32, _: u32) -> [f32; 4] {
    [(x % 2) as f32, 0.0, 0.0, 1.0]
}

/// The red channel's spread (max - min) over the refracted pixels.
fn spread(out: &ImageF32) -> f32 {
    let reds: Vec<f32> = REFRACTED_PIXELS
        .iter()
        .map(|&(x, y)| at(out, x, y)[0])
        .collect();
    let (lo, hi) = reds
        .iter()
        .fold((f32::MAX, f32::MIN), |(lo, hi), &r| (lo.min(r), hi.max(r)));
    hi - lo
}

#[test]
fn rough_glass_blurs_by_one_read_of_a_mip_chain_built_only_when_it_refracts() {
    let renderer = test_renderer();
    let texel = 1.0 / SIZE.0 as f32;
    let (ior, thickness) = (1.5, 2.0);
    let rough = |blur, taps, roughness| TransparencySettings {
        roughness,
        ..glass_settings(TransmissionSettings {
            factor: 1.0,
            ior,
            thickness,
            taps,
            blur,
            ..Default::default()
        })
    };
    // Auto is the chain: built once (one refracting layer), read with
    // REFRACTION_MIPS. Roughness 1 is a disc 4.8 pixels wide, levels 2 to 3;
    // a blur of a ramp is the ramp, so the chain's levels line up with the
    // image when the uv still lands where Snell's law says.
    let (report, out, pass, n) = refract_through(
        &renderer,
        0.6,
        rough(RefractionBlur::Auto, 8, 1.0),
        None,
        uv_ramp,
    );
    assert_eq!(report.counter(MIP_CHAINS), 1);
    assert!(pass.keys().iter().any(|k| {
        let features = &k.key().features;
        features.contains("TRANSMISSION") && features.contains("REFRACTION_MIPS")
    }));
    for (x, y) in REFRACTED_PIXELS {
        let (want, _) = snell_uv(x, y, n, ior, thickness).expect("on the pane");
        let got = glam::Vec2::from_slice(&at(&out, x, y)[..2]);
        assert!(
            (got - want).abs().max_element() < 0.5 * texel,
            "({x}, {y}): the chain gave {got}, Snell says {want}"
        );
    }
    // Stripes a pixel wide: smooth glass reads level 0 (the stripes, so the
    // pixels differ), rough glass a level where they are grey.
    let (_, sharp, _, _) = refract_through(
        &renderer,
        0.6,
        rough(RefractionBlur::Mips, 8, 0.0),
        None,
        stripes,
    );
    let (_, blurred, _, _) = refract_through(
        &renderer,
        0.6,
        rough(RefractionBlur::Mips, 8, 1.0),
        None,
        stripes,
    );
    assert!(spread(&sharp) > 0.3, "smooth glass shows the stripes");
    for (x, y) in REFRACTED_PIXELS {
        let r = at(&blurred, x, y)[0];
        assert!(
            (r - 0.5).abs() < 0.02,
            "({x}, {y}): {r}, not the stripes' grey"
        );
    }
    // Taps: no chain, the image read by hand over the disc, the same grey.
    let (report, taps, pass, _) = refract_through(
        &renderer,
        0.6,
        rough(RefractionBlur::Taps, 32, 1.0),
        None,
        stripes,
    );
    assert_eq!(report.counter(MIP_CHAINS), 0);
    assert!(
        pass.keys()
            .iter()
            .all(|k| !k.key().features.contains("REFRACTION_MIPS"))
    );
    for (x, y) in REFRACTED_PIXELS {
        let r = at(&taps, x, y)[0];
        assert!((r - 0.5).abs() < 0.1, "({x}, {y}): {r} through 32 taps");
    }
    // Hard cases through the chain stay finite and in range.
    for t in [
        TransmissionSettings {
            factor: 1.0,
            ior: f32::NAN,
            thickness: f32::INFINITY,
            blur: RefractionBlur::Mips,
            ..Default::default()
        },
        TransmissionSettings {
            factor: 1.0,
            thickness: 1e3,
            blur: RefractionBlur::Mips,
            ..Default::default()
        },
    ] {
        let settings = TransparencySettings {
            roughness: 1.0,
            ..glass_settings(t)
        };
        let (_, out, _, _) = refract_through(&renderer, 1.2, settings, None, uv_ramp);
        let (lo, hi) = range(&out);
        assert!(lo >= 0.0 && hi <= 1.0 + 1e-3, "{t:?}: {lo}..{hi}");
    }
}

#[test]
fn a_ray_leaving_the_screen_sees_the_environment_faded_in_at_the_border() {
    use spreadlight_render::material::{Feature, Material, MaterialWorld};
    let renderer = test_renderer();
    let texel = 1.0 / SIZE.0 as f32;
    let sky = [0.2, 0.4, 0.8];
    let environment = Environment::new(
        &renderer,
        None,
        EnvironmentSource::Equirect(Arc::new(EquirectImage {
            width: 16,
            height: 8,
            pixels: vec![[sky[0], sky[1], sky[2], 1.0]; 16 * 8],
        })),
        EnvironmentQuality {
            cube_size: 16,
            samples: 64,
        },
    );
    // The glass's own look off: metal (no irradiance diffuse) whose material
    // has no Reflection feature (no reflection), so what shows is what it
    // refracts. The material's Transmission: all of it, ior 1.5, a slab
    // `thickness` deep.
    let glass = |thickness: f32| {
        let material = Material::new()
            .with(
                Feature::Transmission,
                &[[1.0, 1.5, thickness, 0.0], [0.0; 4]],
            )
            .expect("valid");
        LitBy {
            materials: Some(MaterialWorld::new(&renderer, vec![material])),
            environment: Some(environment.clone()),
            ..Default::default()
        }
    };
    let settings = |blur| TransparencySettings {
        metallic: 1.0,
        ..glass_settings(TransmissionSettings {
            blur,
            ..Default::default()
        })
    };
    for blur in [RefractionBlur::Mips, RefractionBlur::Taps] {
        // A slab a thousand deep, steeply tilted: its rays leave the screen
        // (by the CPU reference), and there it shows the sky, not the edge.
        let (_, out, _, n) = refract_by(&renderer, 1.2, settings(blur), glass(1e3), uv_ramp);
        let mut off = 0;
        for (x, y) in REFRACTED_PIXELS {
            if snell_uv(x, y, n, 1.5, 0.0).is_none() {
                continue;
            }
            let d = pixel_ray(x, y);
            let entry = spreadlight_reference::refraction::hit_plane(
                EYE,
                d,
                Vec3::new(0.0, 0.0, PANE_Z),
                n,
            )
            .expect("on the pane");
            let (exit, _) = spreadlight_reference::refraction::slab_exit(entry, d, n, 1.5, 1e3);
            let want = screen_uv(exit);
            // Past the shader's fade band (5% of the screen beyond the border).
            let outside = (-want).max(want - glam::Vec2::ONE).max_element();
            assert!(
                outside > 0.05,
                "({x}, {y}) lands {want}, well off the screen"
            );
            let got = at(&out, x, y);
            for c in 0..3 {
                assert!(
                    got[c].is_finite() && (got[c] - sky[c]).abs() < 0.02 * sky[c].max(0.1),
                    "{blur:?} ({x}, {y}): {got:?}, not the sky {sky:?}"
                );
            }
            off += 1;
        }
        assert!(off >= 2, "{off} pixels leave the screen");
        // A thin slab lands well inside the screen: the image, untouched by the sky.
        let (_, out, _, n) = refract_by(&renderer, 0.6, settings(blur), glass(2.0), uv_ramp);
        for (x, y) in REFRACTED_PIXELS {
            let (want, _) = snell_uv(x, y, n, 1.5, 2.0).expect("on the pane");
            assert!(want.min_element() > 0.1 && want.max_element() < 0.9);
            let got = at(&out, x, y);
            assert!(
                (glam::Vec2::from_slice(&got[..2]) - want)
                    .abs()
                    .max_element()
                    < 0.3 * texel
                    && got[2].abs() < 1e-3,
                "{blur:?} ({x}, {y}): {got:?}, Snell says {want}"
            );
        }
    }
}
