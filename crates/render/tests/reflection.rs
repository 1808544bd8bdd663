//! Environment maps and `Reflection`: the prefiltered environment is
//! built once and reused, mirrors show what the CPU sky and the CPU ray
//! tracer say, roughness 1 is the irradiance's blur, a 1e6 sun pixel stays
//! inside the stated bound, passes run only when a material reflects, a
//! clear coat adds its own reflection over the dimmed base (against the
//! analytic value in a uniform environment, compiled only for a world with
//! a coat), an iridescent mirror reflects the sky times the thin film's
//! Fresnel, and no target ever holds NaN or infinity. SSR's tests are in
//! ssr.rs.

#[path = "reflection_probe/mod.rs"]
mod reflection_probe;
use crate::reflection_scene;

use std::sync::Arc;

use glam::Vec3;
use reflection_scene::*;
use spreadlight_reference::brdf::f_schlick;
use spreadlight_reference::iridescence::iridescence_fresnel;
use spreadlight_reference::reflection::CpuSky;
use spreadlight_render::Renderer;
use spreadlight_render::environment::{
    Environment, EnvironmentQuality, EnvironmentSource, EquirectImage, REFLECTION_BOTH_IN_ONE_PASS,
    Reflection, ReflectionMode, Sky, SkySettings,
};
use spreadlight_render::gbuffer::GBuffer;
use spreadlight_render::material::{Feature, Material, MaterialWorld};
use spreadlight_render::readback::{ImageF32, read_texture_layer, render_and_read};
use spreadlight_render::renderer::test_renderer;
use spreadlight_render::static_texture::StaticTexture;

/// The sun behind the camera and no glow: a smooth sky to compare against.
fn calm_sky() -> SkySettings {
    SkySettings {
        sun_direction: Vec3::new(0.0, -0.5, -1.0),
        glow: 0.0,
        ..Default::default()
    }
}

fn sky_environment(renderer: &Renderer, owner: Option<u32>, sky: SkySettings) -> Arc<Environment> {
    Environment::new(
        renderer,
        owner,
        EnvironmentSource::Sky(sky),
        EnvironmentQuality {
            cube_size: 64,
            samples: 32,
        },
    )
}

fn reflect(
    renderer: &Renderer,
    g: &Arc<GBuffer>,
    world: Vec<Material>,
    environment: Arc<Environment>,
    mode: ReflectionMode,
) -> (
    spreadlight_render::FrameReport,
    ImageF32,
    ImageF32,
    ImageF32,
) {
    let materials = MaterialWorld::new(renderer, world);
    let r = Reflection::new(renderer, None, g.clone(), materials, environment, mode);
    let (report, images) = render_and_read(
        renderer,
        r.as_ref(),
        SIZE,
        &[&r.specular, &r.diffuse, &g.targets.depth],
    )
    .expect("renders");
    assert!(report.errors.is_empty(), "{:?}", report.errors);
    let mut images = images.into_iter();
    let (s, d, z) = (
        images.next().expect("specular"),
        images.next().expect("diffuse"),
        images.next().expect("depth"),
    );
    (report, s, d, z)
}

/// A frame that reads both outputs gets both from one pass ("both"); one
/// that reads only one runs only that one's entry point. The images are
/// the same either way.
#[test]
fn reflection_writes_what_the_frame_reads_both_in_one_pass() {
    let renderer = test_renderer();
    let g = gbuffer(&renderer);
    let environment = sky_environment(&renderer, None, calm_sky());
    let world = vec![reflective(0.5, 0.0), reflective(0.0, 1.0)];
    let r = Reflection::new(
        &renderer,
        None,
        g.clone(),
        MaterialWorld::new(&renderer, world),
        environment,
        ReflectionMode::Reflect,
    );
    let frame = |wanted: &[&str]| {
        let (report, images) =
            render_and_read(&renderer, r.as_ref(), SIZE, wanted).expect("renders");
        assert!(report.errors.is_empty(), "{:?}", report.errors);
        let passes = report
            .passes
            .iter()
            .filter(|p| p.kind == "Reflection")
            .count();
        (report, passes, images)
    };
    let (both, passes, images) = frame(&[&r.specular, &r.diffuse]);
    assert_eq!((both.counter(REFLECTION_BOTH_IN_ONE_PASS), passes), (1, 1));
    assert_eq!(both.counter("reflection shaded"), 1);
    let (alone, passes, specular) = frame(&[&r.specular]);
    assert_eq!((alone.counter(REFLECTION_BOTH_IN_ONE_PASS), passes), (0, 1));
    assert_eq!(alone.counter("reflection shaded"), 1);
    let (alone, passes, diffuse) = frame(&[&r.diffuse]);
    assert_eq!((alone.counter(REFLECTION_BOTH_IN_ONE_PASS), passes), (0, 1));
    assert_eq!(
        alone.counter("reflection shaded"),
        0,
        "no specular when only diffuse is read"
    );
    assert!(images[0].pixels == specular[0].pixels);
    assert!(images[1].pixels == diffuse[0].pixels);
    assert!(
        images[0].pixels.iter().any(|p| p[0] > 0.0) && images[1].pixels.iter().any(|p| p[0] > 0.0)
    );
}

#[test]
fn the_environment_is_prefiltered_once_and_reused_until_its_source_changes() {
    let renderer = test_renderer();
    let g = gbuffer(&renderer);
    let world = || vec![reflective(0.3, 0.0), reflective(0.0, 1.0)];
    let owner = Some(41);
    let (first, ..) = reflect(
        &renderer,
        &g,
        world(),
        sky_environment(&renderer, owner, calm_sky()),
        ReflectionMode::Reflect,
    );
    assert_eq!(first.counter("environment prefiltered"), 1);
    assert_eq!(first.counter("environment reused"), 0);
    // The node evaluated again with the same settings: a new recipe, the same maps.
    let (second, ..) = reflect(
        &renderer,
        &g,
        world(),
        sky_environment(&renderer, owner, calm_sky()),
        ReflectionMode::Reflect,
    );
    assert_eq!(second.counter("environment prefiltered"), 0);
    assert_eq!(second.counter("environment reused"), 1);
    let brighter = SkySettings {
        zenith: Vec3::new(0.5, 0.6, 0.9),
        ..calm_sky()
    };
    let (third, ..) = reflect(
        &renderer,
        &g,
        world(),
        sky_environment(&renderer, owner, brighter),
        ReflectionMode::Reflect,
    );
    assert_eq!(third.counter("environment prefiltered"), 1);
}

#[test]
fn a_mirror_floor_reflects_the_sky_the_cpu_sky_gives_times_fresnel() {
    let renderer = test_renderer();
    let g = gbuffer(&renderer);
    // Ball: rough dielectric; floor: a mirror of albedo 0.8 (F0 = 0.8).
    let (_, specular, diffuse, depth) = reflect(
        &renderer,
        &g,
        vec![reflective(0.5, 0.0), reflective(0.0, 1.0)],
        sky_environment(&renderer, None, calm_sky()),
        ReflectionMode::Reflect,
    );
    assert!(specular.all_finite() && diffuse.all_finite());
    let sky = CpuSky::from(&calm_sky());
    let mut checked = 0;
    for y in 0..SIZE.1 {
        for x in 0..SIZE.0 {
            let d = depth.pixel(x, y)[0];
            let got = Vec3::from_slice(&specular.pixel(x, y)[..3]);
            if d <= 0.0 {
                assert_eq!(got, Vec3::ZERO, "sky pixels reflect nothing");
                continue;
            }
            let p = world_position(&g, x, y, d);
            if p.y.abs() > 1e-3 || p.length() < 1.5 {
                continue; // the ball, or the floor next to it
            }
            let v = (EYE - p).normalize();
            let r = Vec3::new(-v.x, v.y, -v.z);
            let expected = sky.radiance(r) * f_schlick(Vec3::splat(0.8), v.y);
            let error = (got - expected).abs().max_element();
            assert!(
                error < 0.03 + 0.05 * expected.max_element(),
                "pixel ({x}, {y}): {got} vs {expected}"
            );
            checked += 1;
        }
    }
    assert!(checked > 100, "{checked} floor pixels checked");
}

/// Image-based iridescence: a metal mirror floor (albedo 0.8) under a
/// soap film (ior 1.3, 400 nm, factor 1) reflects the CPU sky times the
/// film's Fresnel at N.V (`reference::iridescence`; the split sum at
/// roughness 0 is F x (A + B), A + B = 1), not Schlick's: the film's blue
/// falls to 0.5 at grazing views where Schlick's F stays 0.8 and more.
/// Reflection compiles IRIDESCENCE only for a world with a film.
#[test]
fn an_iridescent_mirror_reflects_the_sky_times_the_films_fresnel() {
    let renderer = test_renderer();
    let g = gbuffer(&renderer);
    let film = |m: Material| {
        m.with(Feature::Iridescence, &[[1.0, 1.3, 400.0, 400.0]])
            .expect("valid")
    };
    let (_, specular, _, depth) = reflect(
        &renderer,
        &g,
        vec![reflective(0.5, 0.0), film(reflective(0.0, 1.0))],
        sky_environment(&renderer, None, calm_sky()),
        ReflectionMode::Reflect,
    );
    assert!(specular.all_finite());
    assert!(
        renderer.shaders().compiled_keys().any(
            |k| k.path() == "environment/reflection.wgsl" && k.features.contains("IRIDESCENCE")
        )
    );
    let sky = CpuSky::from(&calm_sky());
    let (mut checked, mut coloured) = (0, 0);
    for y in 0..SIZE.1 {
        for x in 0..SIZE.0 {
            let d = depth.pixel(x, y)[0];
            if d <= 0.0 {
                continue;
            }
            let got = Vec3::from_slice(&specular.pixel(x, y)[..3]);
            let p = world_position(&g, x, y, d);
            if p.y.abs() > 1e-3 || p.length() < 1.5 {
                continue; // the ball, or the floor next to it
            }
            let v = (EYE - p).normalize();
            let r = Vec3::new(-v.x, v.y, -v.z);
            let fresnel = iridescence_fresnel(0.04, Vec3::splat(0.8), 1.0, v.y, 1.3, 400.0);
            let expected = sky.radiance(r) * fresnel;
            let tolerance = 0.03 + 0.05 * expected.max_element();
            let error = (got - expected).abs().max_element();
            assert!(error < tolerance, "pixel ({x}, {y}): {got} vs {expected}");
            let schlick = sky.radiance(r) * f_schlick(Vec3::splat(0.8), v.y);
            if (schlick - expected).abs().max_element() > 2.0 * tolerance {
                coloured += 1;
            }
            checked += 1;
        }
    }
    assert!(checked > 100, "{checked} floor pixels checked");
    assert!(
        coloured * 4 > checked,
        "{coloured} of {checked} pixels tell the film from Schlick's F"
    );
}

fn cube_level(renderer: &Renderer, texture: &wgpu::Texture, mip: u32) -> Vec<ImageF32> {
    (0..6)
        .map(|face| read_texture_layer(&renderer.gpu, texture, face, mip).expect("reads"))
        .collect()
}

/// Build `environment` alone and return its maps.
fn build(
    renderer: &Renderer,
    environment: &Arc<Environment>,
) -> Arc<spreadlight_render::environment::EnvironmentMaps> {
    let mut graph = spreadlight_render::FrameGraph::new(SIZE);
    spreadlight_render::Recipe::declare(environment.as_ref(), renderer, &mut graph);
    graph.request(environment.token());
    let (report, _) = graph.execute(renderer).expect("runs");
    assert!(report.errors.is_empty(), "{:?}", report.errors);
    environment.maps().expect("built")
}

#[test]
fn roughness_one_is_the_irradiance_blur() {
    let renderer = test_renderer();
    let environment = Environment::new(
        &renderer,
        None,
        EnvironmentSource::Sky(calm_sky()),
        EnvironmentQuality {
            cube_size: 64,
            samples: 256,
        },
    );
    let maps = build(&renderer, &environment);
    let last = maps.levels() - 1;
    let rough = cube_level(&renderer, &maps.prefiltered, last);
    let irradiance = cube_level(&renderer, &maps.irradiance, 0);
    // With N = V, GGX at roughness 1 sends reflected directions uniformly
    // over the sphere: the N.L-weighted average is E / pi, the irradiance output.
    // Compared face by face, as means (the levels differ in size).
    let mean = |image: &ImageF32| {
        image
            .pixels
            .iter()
            .fold(Vec3::ZERO, |acc, p| acc + Vec3::from_slice(&p[..3]))
            / image.pixels.len() as f32
    };
    for face in 0..6 {
        let (r, i) = (mean(&rough[face]), mean(&irradiance[face]));
        assert!(
            ((r - i).abs()).max_element() < 0.08 * i.max_element() + 0.01,
            "face {face}: roughness 1 {r} vs irradiance {i}"
        );
    }
}

#[test]
fn a_1e6_sun_pixel_stays_finite_and_inside_the_stated_bound() {
    let renderer = test_renderer();
    let (w, h) = (128u32, 64u32);
    let mut pixels = vec![[1.0f32, 1.0, 1.0, 1.0]; (w * h) as usize];
    pixels[(20 * w + 40) as usize] = [1e6, 1e6, 1e6, 1.0];
    // Bad texels too: NaN and infinity are read as 0 and 65000.
    pixels[(40 * w + 90) as usize] = [f32::NAN, f32::NAN, f32::NAN, 1.0];
    pixels[(50 * w + 10) as usize] = [f32::INFINITY, 0.0, 0.0, 1.0];
    let image = Arc::new(EquirectImage {
        width: w,
        height: h,
        pixels,
    });
    let environment = Environment::new(
        &renderer,
        None,
        EnvironmentSource::Equirect(image),
        EnvironmentQuality {
            cube_size: 32,
            samples: 64,
        },
    );
    let maps = build(&renderer, &environment);
    // The stated bound (docs/reflection.md): the sun texel is clamped to
    // 65000 on upload; its energy is then 65000 x its solid angle, and the
    // roughest level (the cosine-weighted average E / pi) holds at most the
    // background plus that energy / pi, doubled for the mip filtering's spread.
    let theta = (20.5 / h as f32) * std::f32::consts::PI;
    let solid_angle =
        (std::f32::consts::TAU / w as f32) * (std::f32::consts::PI / h as f32) * theta.sin();
    let bound = 1.0 + 2.0 * 65000.0 * solid_angle / std::f32::consts::PI;
    for level in 0..maps.levels() {
        let faces = cube_level(&renderer, &maps.prefiltered, level);
        let max = faces
            .iter()
            .flat_map(|f| f.pixels.iter().map(|p| p[0].max(p[1]).max(p[2])))
            .fold(0.0f32, f32::max);
        assert!(faces.iter().all(ImageF32::all_finite), "level {level}");
        assert!(max <= 65000.0, "level {level}: {max}");
        if level == maps.levels() - 1 {
            assert!(max <= bound, "roughest level {max} > bound {bound}");
            assert!(max > 1.0, "the sun's energy is still there: {max}");
        }
    }
    let irradiance = cube_level(&renderer, &maps.irradiance, 0);
    assert!(irradiance.iter().all(ImageF32::all_finite));
    let max = irradiance
        .iter()
        .flat_map(|f| f.pixels.iter().map(|p| p[0]))
        .fold(0.0f32, f32::max);
    assert!(max <= bound, "irradiance {max} > bound {bound}");
}

#[test]
fn without_a_reflective_material_no_environment_is_built_and_reflection_only_clears() {
    let renderer = test_renderer();
    let g = gbuffer(&renderer);
    let plain = Material::default_material();
    let materials = MaterialWorld::new(&renderer, vec![plain.clone(), plain.clone()]);
    let r = Reflection::new(
        &renderer,
        None,
        g.clone(),
        materials,
        sky_environment(&renderer, Some(77), calm_sky()),
        ReflectionMode::Reflect,
    );
    let (report, images) =
        render_and_read(&renderer, r.as_ref(), SIZE, &[&r.specular]).expect("renders");
    assert!(report.errors.is_empty(), "{:?}", report.errors);
    assert_eq!(report.counter("reflection skipped"), 1);
    assert_eq!(report.counter("reflection shaded"), 0);
    assert_eq!(report.counter("environment prefiltered"), 0);
    assert!(!report.passes.iter().any(|p| p.name.contains("Environment")));
    assert!(images[0].pixels.iter().all(|p| p[..3] == [0.0; 3]));

    // The environment's diffuse light does not need a reflective material:
    // asked for, it lights every surface (and builds the environment).
    let (report, specular, diffuse, depth) = reflect(
        &renderer,
        &g,
        vec![plain.clone(), plain],
        sky_environment(&renderer, Some(78), calm_sky()),
        ReflectionMode::Reflect,
    );
    assert_eq!(report.counter("reflection skipped"), 1);
    assert!(specular.pixels.iter().all(|p| p[..3] == [0.0; 3]));
    for (p, d) in diffuse.pixels.iter().zip(&depth.pixels) {
        if d[0] > 0.0 {
            assert!(p[0] > 0.0 && p[1] > 0.0 && p[2] > 0.0, "{p:?}");
        } else {
            assert_eq!(p[..3], [0.0; 3]);
        }
    }

    // Wired but not requested: the reflection pass is culled.
    let materials = MaterialWorld::new(&renderer, vec![reflective(0.2, 1.0)]);
    let environment = sky_environment(&renderer, None, calm_sky());
    let r = Reflection::new(
        &renderer,
        None,
        g.clone(),
        materials,
        environment,
        ReflectionMode::Reflect,
    );
    let mut graph = spreadlight_render::FrameGraph::new(SIZE);
    spreadlight_render::Recipe::declare(r.as_ref(), &renderer, &mut graph);
    graph.request(&g.targets.color);
    let (report, _) = graph.execute(&renderer).expect("runs");
    assert!(report.errors.is_empty(), "{:?}", report.errors);
    assert!(
        !report
            .passes
            .iter()
            .any(|p| p.kind == "Reflection" || p.kind == "Environment")
    );
    assert!(report.culled.iter().any(|p| p.contains("Reflection")));
}

#[test]
fn reflection_and_refraction_stay_finite_from_every_side() {
    let renderer = test_renderer();
    let environment = sky_environment(&renderer, Some(5), SkySettings::default());
    // Above; below the floor looking up (its normal faces away); grazing; inside the ball.
    for (eye, target) in [
        (EYE, Vec3::ZERO),
        (Vec3::new(0.5, -2.0, 3.0), Vec3::new(0.0, 0.5, 0.0)),
        (Vec3::new(0.0, 0.02, 6.0), Vec3::new(0.0, 0.0, 0.0)),
        (Vec3::new(0.0, 0.6, 0.0), Vec3::new(1.0, 0.6, 0.0)),
    ] {
        let g = gbuffer_from(&renderer, eye, target);
        for mode in [
            ReflectionMode::Reflect,
            ReflectionMode::Refract { ior: 1.5 },
            ReflectionMode::Refract { ior: f32::NAN },
            ReflectionMode::Refract { ior: 0.2 },
        ] {
            for (ball, floor) in [(0.0, 1.0), (1.0, 0.0)] {
                let (_, s, d, _) = reflect(
                    &renderer,
                    &g,
                    vec![reflective(ball, 1.0), reflective(floor, 0.0)],
                    environment.clone(),
                    mode,
                );
                assert!(s.all_finite() && d.all_finite(), "{eye} {mode:?}");
                assert!(
                    s.pixels
                        .iter()
                        .chain(&d.pixels)
                        .all(|p| p[..3].iter().all(|c| *c >= 0.0 && *c <= 65000.0))
                );
            }
        }
    }
}

#[test]
fn refraction_shows_the_environment_behind_the_surface() {
    let renderer = test_renderer();
    // Looking straight down at the floor: reflection sees the zenith, refraction the ground below.
    let g = gbuffer_from(
        &renderer,
        Vec3::new(3.0, 3.0, 0.01),
        Vec3::new(3.0, 0.0, 0.0),
    );
    let sky = SkySettings {
        zenith: Vec3::new(0.0, 0.0, 1.0),
        horizon: Vec3::ONE,
        ground: Vec3::new(0.0, 1.0, 0.0),
        sun_color: Vec3::ZERO,
        glow: 0.0,
        ..Default::default()
    };
    let environment = sky_environment(&renderer, None, sky);
    let world = || vec![reflective(0.0, 0.0), reflective(0.0, 0.0)];
    let (_, reflected, ..) = reflect(
        &renderer,
        &g,
        world(),
        environment.clone(),
        ReflectionMode::Reflect,
    );
    let (_, refracted, ..) = reflect(
        &renderer,
        &g,
        world(),
        environment,
        ReflectionMode::Refract { ior: 1.33 },
    );
    let (r, t) = (
        reflected.pixel(SIZE.0 / 2, SIZE.1 / 2),
        refracted.pixel(SIZE.0 / 2, SIZE.1 / 2),
    );
    assert!(r[2] > r[1], "reflection: the blue zenith {r:?}");
    assert!(
        t[1] > t[2] && t[1] > 0.5,
        "refraction: the green ground, most light through {t:?}"
    );
}

#[test]
fn the_sky_node_draws_an_environment_where_depth_is_empty() {
    let renderer = test_renderer();
    let g = gbuffer(&renderer);
    let lit = StaticTexture::from_rgba32f(
        &renderer.gpu,
        SIZE.0,
        SIZE.1,
        &vec![[1.0, 0.0, 1.0, 1.0]; (SIZE.0 * SIZE.1) as usize],
        "lit",
    );
    let procedural = Sky::pass(&renderer, None, g.clone(), lit.texture_ref(), calm_sky());
    let environment = sky_environment(&renderer, None, calm_sky());
    let baked = Sky::with_environment(
        &renderer,
        None,
        g.clone(),
        lit.texture_ref(),
        SkySettings::default(),
        Some(environment),
    );
    let read = |pass: &Arc<spreadlight_render::environment::ImagePass>| {
        let (report, images) =
            render_and_read(&renderer, pass.as_ref(), SIZE, &[&pass.output]).expect("renders");
        assert!(report.errors.is_empty(), "{:?}", report.errors);
        images.into_iter().next().expect("image")
    };
    let (a, b) = (read(&procedural), read(&baked));
    assert!(b.all_finite());
    for (p, q) in a.pixels.iter().zip(&b.pixels) {
        for c in 0..3 {
            assert!((p[c] - q[c]).abs() < 0.03 + 0.03 * p[c], "{p:?} vs {q:?}");
        }
    }
}

// ---- SSR ----

/// The clear coat in image-based reflection. Radiance L from every
/// direction: the prefiltered environment is L along every direction at
/// every roughness, and at roughness 0 the split sum is Schlick's Fresnel
/// S(f0, N.V) = f0 + (1 - f0)(1 - N.V)^5. So a floor whose base (f0 0: not
/// metal, reflectance 0) and coat (factor c) are both mirrors reflects
/// L [S(0, N.V) (1 - c S(0.04, N.V)) + c S(0.04, N.V)]: the base dimmed by
/// what the coat reflects, and the coat's own lobe. The diffuse output
/// (irradiance E / pi = L, within the irradiance cube's 3%) is dimmed by
/// what the coat reflects too, to the uncoated floor's times
/// 1 - c S(0.04, N.V), as the light walk dims the base's diffuse, also in a
/// world where nothing has the Reflection feature (the diffuse-only pass);
/// the uncoated ball's stays as it was. Without a coat the CLEARCOAT
/// permutation is not compiled.
#[test]
fn the_clear_coat_reflects_the_environment_over_the_dimmed_base() {
    let renderer = test_renderer();
    let g = gbuffer(&renderer);
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
    let floor = |coat: f32| {
        let m = Material::new()
            .with(Feature::CookTorrance, &[[0.0, 0.0, 0.0, 0.0]])
            .expect("valid");
        let m = if coat >= 0.0 {
            m.with(Feature::Reflection, &[[1.0, 0.0, 0.0, 0.0]])
                .expect("valid")
        } else {
            m
        };
        let coat = coat.abs();
        if coat > 0.0 {
            m.with(Feature::Clearcoat, &[[coat, 0.0, 0.0, 0.0]])
                .expect("valid")
        } else {
            m
        }
    };
    let coat_keys = |renderer: &Renderer| {
        renderer
            .shaders()
            .compiled_keys()
            .filter(|k| k.features.contains("CLEARCOAT"))
            .count()
    };
    let schlick = |f0: f32, n_dot_v: f32| f0 + (1.0 - f0) * (1.0 - n_dot_v).powi(5);
    // A negative coat: that coat on a floor without the Reflection feature,
    // in a world where nothing reflects (only the diffuse light is drawn).
    let mut uncoated: Option<ImageF32> = None;
    for coat in [0.0, 1.0, 0.5, -1.0] {
        let ball = if coat < 0.0 {
            Material::default_material()
        } else {
            reflective(0.5, 0.0)
        };
        let (report, specular, diffuse, depth) = reflect(
            &renderer,
            &g,
            vec![ball, floor(coat)],
            environment.clone(),
            ReflectionMode::Reflect,
        );
        assert!(specular.all_finite() && diffuse.all_finite());
        let (reflects, coat) = (coat >= 0.0, coat.abs());
        assert_eq!(report.counter("reflection skipped"), u64::from(!reflects));
        if coat == 0.0 {
            assert_eq!(coat_keys(&renderer), 0, "no coat, no CLEARCOAT");
        }
        let (mut checked, mut largest_lobe) = (0, 0.0f32);
        for y in 0..SIZE.1 {
            for x in 0..SIZE.0 {
                let d = depth.pixel(x, y)[0];
                if d <= 0.0 {
                    continue;
                }
                let p = world_position(&g, x, y, d);
                let light = diffuse.pixel(x, y);
                // The environment's irradiance / pi without a coat.
                let bare = uncoated.as_ref().map_or(light, |u| u.pixel(x, y));
                for c in &bare[..3] {
                    assert!(
                        (c - radiance).abs() < 0.03 * radiance,
                        "({x}, {y}): {bare:?}"
                    );
                }
                if p.y > 0.05 {
                    // The ball, uncoated: as it was.
                    for c in 0..3 {
                        assert!(
                            (light[c] - bare[c]).abs() < 2e-3,
                            "ball ({x}, {y}): {light:?}"
                        );
                    }
                }
                if p.y.abs() > 1e-3 || p.length() < 1.5 {
                    continue; // the ball, or the floor next to it
                }
                let n_dot_v = (EYE - p).normalize().y;
                let lobe = coat * schlick(0.04, n_dot_v);
                for c in 0..3 {
                    let dimmed = bare[c] * (1.0 - lobe);
                    assert!(
                        (light[c] - dimmed).abs() < 2e-3,
                        "coat {coat}, pixel ({x}, {y}), N.V {n_dot_v}: diffuse {light:?}, {bare:?} dimmed {dimmed}"
                    );
                }
                let want = if reflects {
                    radiance * (schlick(0.0, n_dot_v) * (1.0 - lobe) + lobe)
                } else {
                    0.0
                };
                let got = specular.pixel(x, y);
                for c in &got[..3] {
                    assert!(
                        (c - want).abs() < 0.01 + 0.05 * want,
                        "coat {coat}, pixel ({x}, {y}), N.V {n_dot_v}: {got:?}, analytic {want}"
                    );
                }
                largest_lobe = largest_lobe.max(radiance * lobe);
                checked += 1;
            }
        }
        assert!(checked > 100, "{checked} floor pixels checked");
        if coat > 0.0 {
            assert!(coat_keys(&renderer) > 0, "a coat compiles CLEARCOAT");
            assert!(largest_lobe > 0.05, "a lobe worth testing: {largest_lobe}");
        }
        uncoated.get_or_insert(diffuse);
    }
}
