//! Lighting reads what the G-buffer resolved: a shader node material's
//! roughness, metallic, occlusion and emission (the surface target, see
//! shaders/lib/surface_target.wgsl) drive CookTorrance and CompositeLight,
//! with or without a material world, while pixels whose surface was not
//! written shade bit for bit as before, and G-buffers without a surface
//! target compile no surface-reading permutation.

use crate::floor_view;

use std::sync::Arc;

use floor_view::{SIZE, camera, floor_mesh, floor_points};
use glam::{Mat4, Vec3};
use spreadlight_reference::brdf::cook_torrance_f0;
use spreadlight_render::gbuffer::{DrawBatch, GBuffer, InstanceInput, Layer, SurfaceShader};
use spreadlight_render::lighting::{
    CompositeInputs, CompositeLight, CookTorrance, LightBuffer, LightLoop, PointLight, SunLight,
    Surfaces,
};
use spreadlight_render::material::{Feature, Material, MaterialWorld};
use spreadlight_render::mesh::primitives::{SphereParams, sphere};
use spreadlight_render::readback::{ImageF32, render_and_read};
use spreadlight_render::recipe::TextureRef;
use spreadlight_render::renderer::test_renderer;
use spreadlight_render::static_texture::StaticTexture;
use spreadlight_render::{Renderer, SizeRule};

const FLOOR_ALBEDO: [f32; 3] = [0.8, 0.7, 0.6];
const BALL_ALBEDO: [f32; 3] = [0.5, 0.6, 0.7];

/// A material whose `surface` function runs `body` on `out` (the layer's own surface).
fn material(name: &str, body: &str) -> Arc<SurfaceShader> {
    let text = format!(
        "#import spreadlight::surface::{{SurfaceInput, SurfaceOutput, surface_default}}\n\n\
         fn surface(in: SurfaceInput) -> SurfaceOutput {{\n    var out = surface_default(in);\n\
         {body}\n    return out;\n}}\n"
    );
    let key = text.bytes().fold(0xcbf2_9ce4_8422_2325u64, |h, b| {
        (h ^ u64::from(b)).wrapping_mul(0x100_0000_01b3)
    });
    Arc::new(SurfaceShader::new(
        format!("{name} (test)"),
        format!("tests/{name}.wgsl"),
        text,
        key,
        Vec::new(),
        Vec::new(),
        Vec::new(),
        1,
    ))
}

/// A 20x20 floor (material `floor`) and, with `ball`, a ball on it (material
/// `ball` when given one), each its own layer.
fn scene(
    renderer: &Renderer,
    floor: Option<Arc<SurfaceShader>>,
    ball: Option<Option<Arc<SurfaceShader>>>,
) -> Arc<GBuffer> {
    let instance = |t: Mat4, [r, g, b]: [f32; 3]| InstanceInput {
        transform: t,
        previous_transform: t,
        color: [r, g, b, 1.0],
        material_id: 0,
        object_id: 0,
    };
    let plane = floor_mesh(renderer);
    let layer = |mesh, t, albedo, surface| {
        let batches = vec![DrawBatch {
            mesh,
            instances: vec![instance(t, albedo)],
        }];
        Arc::new(Layer::plain(batches).with_surface(surface))
    };
    let mut layers = vec![layer(plane, Mat4::IDENTITY, FLOOR_ALBEDO, floor)];
    if let Some(surface) = ball {
        let mesh = renderer
            .meshes
            .upload(&renderer.gpu, &sphere(SphereParams::default()))
            .expect("upload");
        let t = Mat4::from_translation(Vec3::new(1.5, 0.5, 1.0));
        layers.push(layer(mesh, t, BALL_ALBEDO, surface));
    }
    GBuffer::new(
        renderer,
        None,
        layers,
        camera(),
        None,
        SizeRule::Relative(1.0),
    )
}

/// Render `names` of `recipe` and read them back; no pass may fail.
fn frame<const N: usize>(
    renderer: &Renderer,
    recipe: &dyn spreadlight_render::Recipe,
    names: [&str; N],
) -> [ImageF32; N] {
    let (report, images) =
        render_and_read(renderer, recipe, SIZE, &names).expect("the frame renders");
    assert!(report.errors.is_empty(), "{:?}", report.errors);
    images
        .try_into()
        .unwrap_or_else(|_| unreachable!("one image per name"))
}

/// CookTorrance's diffuse and specular (checked finite).
fn shade(
    renderer: &Renderer,
    g: &Arc<GBuffer>,
    lights: Arc<LightBuffer>,
    surfaces: Surfaces,
) -> (ImageF32, ImageF32) {
    let ct = CookTorrance::new(
        renderer,
        None,
        g.clone(),
        lights,
        LightLoop::Clustered,
        true,
        surfaces,
    );
    let [d, s] = frame(renderer, ct.as_ref(), [&ct.diffuse, &ct.specular]);
    assert!(d.all_finite() && s.all_finite(), "no NaN or infinity");
    (d, s)
}

/// CompositeLight over CookTorrance (pins roughness 0.5, metallic 0) under `lights`.
fn composite(
    renderer: &Renderer,
    g: &Arc<GBuffer>,
    lights: Arc<LightBuffer>,
    ambient: f32,
    world: Option<Arc<MaterialWorld>>,
    gi: Option<TextureRef>,
) -> ImageF32 {
    let ct = CookTorrance::new(
        renderer,
        None,
        g.clone(),
        lights,
        LightLoop::Naive,
        false,
        Surfaces::PerMaterialId(vec![(0.5, 0.0)]),
    );
    let c = CompositeLight::new(
        renderer,
        None,
        g.clone(),
        CompositeInputs {
            components: vec![ct.components()],
            ambient: [ambient; 3],
            materials: world,
            occlusion: None,
            gi,
            reflection: None,
        },
    )
    .expect("valid");
    let [image] = frame(renderer, c.as_ref(), [&c.output]);
    assert!(image.all_finite(), "no NaN or infinity");
    image
}

fn no_lights(renderer: &Renderer) -> Arc<LightBuffer> {
    LightBuffer::points(renderer, &[])
}

fn point_light(renderer: &Renderer) -> Arc<LightBuffer> {
    LightBuffer::points(
        renderer,
        &[PointLight {
            shadow: None,
            position: Vec3::new(0.0, 2.0, -2.0),
            color: Vec3::ONE,
            intensity: 40.0,
            range: 30.0,
        }],
    )
}

const SUN: SunLight = SunLight {
    direction: Vec3::new(-0.3, -1.0, -0.2),
    color: Vec3::ONE,
    illuminance: 3.0,
    shadow: None,
};

/// The largest value of the red channel, and how many pixels reach half of it.
fn peak_and_spread(image: &ImageF32) -> (f32, usize) {
    let peak = image.pixels.iter().map(|p| p[0]).fold(0.0, f32::max);
    let spread = image.pixels.iter().filter(|p| p[0] >= 0.5 * peak).count();
    (peak, spread)
}

#[test]
fn roughness_a_material_writes_sharpens_or_widens_the_highlight() {
    let renderer = test_renderer();
    let specular_of = |floor| {
        let g = scene(&renderer, floor, None);
        // The node's pins say roughness 0.5: the material's value wins where it wrote one.
        shade(
            &renderer,
            &g,
            point_light(&renderer),
            Surfaces::PerMaterialId(vec![(0.5, 0.0)]),
        )
        .1
    };
    let smooth = specular_of(Some(material("smooth", "out.roughness = 0.1;")));
    let rough = specular_of(Some(material("rough", "out.roughness = 0.9;")));
    let (smooth_peak, smooth_spread) = peak_and_spread(&smooth);
    let (rough_peak, rough_spread) = peak_and_spread(&rough);
    assert!(
        smooth_peak > 20.0 * rough_peak,
        "a sharp highlight is brighter: peak {smooth_peak} at roughness 0.1, {rough_peak} at 0.9"
    );
    assert!(
        smooth_spread * 10 < rough_spread,
        "and smaller: {smooth_spread} pixels above half the peak at 0.1, {rough_spread} at 0.9"
    );
    // A material that writes what the pins say shades as the pins do.
    let pins = specular_of(None);
    let same = specular_of(Some(material("half", "out.roughness = 0.5;")));
    for (a, b) in same.pixels.iter().zip(&pins.pixels) {
        assert!(
            (a[0] - b[0]).abs() <= 1e-3 * b[0].abs() + 1e-6,
            "{a:?} vs {b:?}"
        );
    }
}

#[test]
fn metallic_a_material_writes_scales_the_diffuse_term_as_the_brdf_says() {
    let renderer = test_renderer();
    let l = -SUN.direction.normalize();
    let radiance = SUN.color * SUN.illuminance;
    let points = floor_points();
    let albedo = Vec3::from(FLOOR_ALBEDO);
    for (metallic, world) in [
        (0.0, None),
        (0.5, None),
        (1.0, None),
        // A material world says rough and non-metallic: the resolved surface wins.
        (
            1.0,
            Some(MaterialWorld::new(
                &renderer,
                vec![
                    Material::new()
                        .with(Feature::CookTorrance, &[[0.9, 0.0, 0.04, 0.0]])
                        .expect("valid"),
                ],
            )),
        ),
    ] {
        let body = format!("out.roughness = 0.4;\n    out.metallic = {metallic:.1};");
        let g = scene(&renderer, Some(material("metal", &body)), None);
        let surfaces = match world {
            Some(w) => Surfaces::Materials(w),
            None => Surfaces::PerMaterialId(vec![(0.9, 0.0)]),
        };
        let (diffuse, _) = shade(
            &renderer,
            &g,
            LightBuffer::suns(&renderer, &[SUN]),
            surfaces,
        );
        let mut checked = 0;
        for (pixel, seen) in diffuse.pixels.iter().zip(&points) {
            let Some((_, v)) = seen else { continue };
            let brdf = cook_torrance_f0(Vec3::Y, *v, l, albedo, 0.4, metallic, 0.04, true);
            let expected = brdf.diffuse * radiance;
            for c in 0..3 {
                assert!(
                    (pixel[c] - expected[c]).abs() <= 1e-2 * expected[c] + 1e-4,
                    "metallic {metallic}: diffuse {pixel:?}, the BRDF says {expected}"
                );
            }
            if metallic == 1.0 {
                assert_eq!(pixel[..3], [0.0; 3], "a metal takes no diffuse light");
            }
            checked += 1;
        }
        assert!(
            checked > (SIZE.0 * SIZE.1 / 2) as usize,
            "{checked} floor pixels"
        );
    }
}

#[test]
fn occlusion_a_material_writes_darkens_ambient_and_indirect_light() {
    let renderer = test_renderer();
    let gi = StaticTexture::from_rgba32f(
        &renderer.gpu,
        SIZE.0,
        SIZE.1,
        &vec![[0.5f32, 0.5, 0.5, 1.0]; (SIZE.0 * SIZE.1) as usize],
        "gi",
    );
    let points = floor_points();
    for (occlusion, metallic) in [(1.0, 0.0), (0.5, 0.0), (0.0, 0.0), (1.0, 1.0), (0.5, 1.0)] {
        let body = format!("out.occlusion = {occlusion:.1};\n    out.metallic = {metallic:.1};");
        let g = scene(&renderer, Some(material("ao", &body)), None);
        // Ambient 1 alone (no material world at all), then with indirect light 0.5.
        let ambient = composite(&renderer, &g, no_lights(&renderer), 1.0, None, None);
        let both = composite(
            &renderer,
            &g,
            no_lights(&renderer),
            1.0,
            None,
            Some(gi.texture_ref()),
        );
        for ((a, b), seen) in ambient.pixels.iter().zip(&both.pixels).zip(&points) {
            if seen.is_none() {
                continue;
            }
            for c in 0..3 {
                let albedo = FLOOR_ALBEDO[c];
                let want_ambient = albedo * occlusion;
                let want_both = want_ambient + 0.5 * albedo * (1.0 - metallic) * occlusion;
                // Albedo and the output are half floats: 11 significant bits.
                let close = |got: f32, want: f32| (got - want).abs() <= 2e-3 * want.max(0.5);
                assert!(
                    close(a[c], want_ambient),
                    "ambient {a:?}, want {want_ambient}"
                );
                assert!(close(b[c], want_both), "with GI {b:?}, want {want_both}");
            }
            if occlusion == 0.0 {
                assert_eq!(a[..3], [0.0; 3], "occlusion 0 removes the ambient term");
                assert_eq!(b[..3], [0.0; 3], "and indirect light");
            }
        }
    }
}

#[test]
fn emission_a_material_writes_shows_where_no_light_reaches() {
    let renderer = test_renderer();
    let glow = material("glow", "out.emission = vec3<f32>(0.25, 1.5, 3.0);");
    let g = scene(&renderer, None, Some(Some(glow)));
    let dark = composite(&renderer, &g, no_lights(&renderer), 0.0, None, None);
    // The ball glows its colour; the floor, without a material, stays black.
    let glowing: Vec<usize> = (0..dark.pixels.len())
        .filter(|&i| dark.pixels[i][2] > 0.0)
        .collect();
    assert!(glowing.len() > 20, "{} glowing pixels", glowing.len());
    for &i in &glowing {
        let p = dark.pixels[i];
        for (c, want) in [0.25f32, 1.5, 3.0].into_iter().enumerate() {
            // RGB9E5 keeps 9 bits below the largest channel's exponent.
            assert!((p[c] - want).abs() <= 3.0 / 256.0, "{p:?}");
        }
    }
    assert!(
        dark.pixels
            .iter()
            .enumerate()
            .all(|(i, p)| glowing.contains(&i) || p[..3] == [0.0; 3]),
        "nothing else emits"
    );
    // With a world whose material emits, the floor glows as the world says
    // and the ball as its surface function says.
    let world = MaterialWorld::new(
        &renderer,
        vec![
            Material::default_material()
                .with(Feature::Emission, &[[1.0, 1.0, 1.0, 5.0]])
                .expect("valid"),
        ],
    );
    let both = composite(&renderer, &g, no_lights(&renderer), 0.0, Some(world), None);
    let floor = floor_points();
    for (i, p) in both.pixels.iter().enumerate() {
        if glowing.contains(&i) {
            assert_eq!(
                p, &dark.pixels[i],
                "the resolved emission replaces the world's"
            );
        } else if floor[i].is_some() {
            assert!((p[0] - 5.0).abs() < 1e-3, "{p:?}");
        }
    }
}

#[test]
fn extreme_surface_values_reach_no_target_as_nan_or_infinity() {
    let renderer = test_renderer();
    // `in.uv` is 0 without texture coordinates: divisions by it make NaN and
    // infinities at run time, where no compiler can fold them away.
    let bodies = [
        "let zero = in.uv.x;\n    out.roughness = zero / zero;\n    out.metallic = 1.0 / zero;\n    \
         out.occlusion = -1.0 / zero;\n    out.emission = vec3<f32>(1.0 / zero, zero / zero, -1.0 / zero);",
        "out.roughness = 0.0;\n    out.metallic = 1.0;\n    out.emission = vec3<f32>(1e30);",
        "out.roughness = -5.0;\n    out.metallic = -5.0;\n    out.occlusion = 7.0;\n    \
         out.emission = vec3<f32>(-1e30, 65500.0, 3e38);",
    ];
    for body in bodies {
        let g = scene(&renderer, Some(material("extreme", body)), Some(None));
        for lights in [point_light(&renderer), LightBuffer::suns(&renderer, &[SUN])] {
            shade(
                &renderer,
                &g,
                lights.clone(),
                Surfaces::PerMaterialId(vec![(0.5, 0.0)]),
            );
            let lit = composite(&renderer, &g, lights, 1.0, None, None);
            assert!(
                lit.pixels
                    .iter()
                    .all(|p| p[..3].iter().all(|c| (0.0..=65000.0).contains(c))),
                "{body}: composite stays within half-float range"
            );
        }
    }
}

#[test]
fn pixels_without_a_resolved_surface_shade_bit_for_bit_as_before() {
    let renderer = test_renderer();
    // The floor has no material in either; the ball has one in the first
    // G-buffer only, which therefore has a surface target.
    let shiny = material(
        "shiny",
        "out.roughness = 0.15;\n    out.metallic = 1.0;\n    out.occlusion = 0.3;\n    out.emission = vec3<f32>(2.0);",
    );
    let with = scene(&renderer, None, Some(Some(shiny)));
    let without = scene(&renderer, None, Some(None));
    let ball = composite(&renderer, &with, no_lights(&renderer), 0.0, None, None);
    let on_ball = |i: usize| ball.pixels[i][0] > 0.0;
    assert!((0..ball.pixels.len()).any(on_ball));
    let world = || {
        Some(MaterialWorld::new(
            &renderer,
            vec![
                Material::default_material()
                    .with(Feature::Emission, &[[0.1, 0.2, 0.3, 1.0]])
                    .expect("valid"),
            ],
        ))
    };
    for lights in [point_light(&renderer), LightBuffer::suns(&renderer, &[SUN])] {
        let mut compared = 0;
        let a = shade(
            &renderer,
            &with,
            lights.clone(),
            Surfaces::PerMaterialId(vec![(0.3, 0.2)]),
        );
        let b = shade(
            &renderer,
            &without,
            lights.clone(),
            Surfaces::PerMaterialId(vec![(0.3, 0.2)]),
        );
        let c = composite(&renderer, &with, lights.clone(), 0.2, world(), None);
        let d = composite(&renderer, &without, lights.clone(), 0.2, world(), None);
        for i in (0..ball.pixels.len()).filter(|&i| !on_ball(i)) {
            assert_eq!(a.0.pixels[i], b.0.pixels[i], "diffuse at pixel {i}");
            assert_eq!(a.1.pixels[i], b.1.pixels[i], "specular at pixel {i}");
            assert_eq!(c.pixels[i], d.pixels[i], "composite at pixel {i}");
            compared += 1;
        }
        assert!(compared > (SIZE.0 * SIZE.1 / 2) as usize);
        // And the ball is lit differently: the material's values are read.
        assert!((0..ball.pixels.len()).any(|i| on_ball(i) && a.1.pixels[i] != b.1.pixels[i]));
    }
}

#[test]
fn only_gbuffers_with_a_surface_target_compile_the_permutations_that_read_it() {
    let reads_surface = |renderer: &Renderer| {
        renderer
            .shaders()
            .compiled_keys()
            .filter(|k| k.features.contains("SURFACE_TARGET"))
            .map(|k| k.path())
            .collect::<std::collections::BTreeSet<_>>()
    };
    let renderer = test_renderer();
    let plain = scene(&renderer, None, Some(None));
    shade(
        &renderer,
        &plain,
        point_light(&renderer),
        Surfaces::PerMaterialId(vec![(0.5, 0.0)]),
    );
    composite(&renderer, &plain, point_light(&renderer), 0.1, None, None);
    assert!(plain.targets.surface.is_none());
    assert!(
        reads_surface(&renderer).is_empty(),
        "{:?}",
        reads_surface(&renderer)
    );
    let textured = scene(&renderer, None, Some(Some(material("any", ""))));
    assert!(textured.targets.surface.is_some());
    composite(
        &renderer,
        &textured,
        point_light(&renderer),
        0.1,
        None,
        None,
    );
    assert_eq!(
        reads_surface(&renderer).into_iter().collect::<Vec<_>>(),
        ["lighting/composite.wgsl", "lighting/cook_torrance.wgsl"]
    );
}

#[test]
fn reflection_takes_roughness_and_metallic_from_the_resolved_surface() {
    use spreadlight_render::environment::{
        Environment, EnvironmentQuality, EnvironmentSource, Reflection, ReflectionMode, SkySettings,
    };
    let renderer = test_renderer();
    let environment = Environment::new(
        &renderer,
        None,
        EnvironmentSource::Sky(SkySettings::default()),
        EnvironmentQuality {
            cube_size: 32,
            samples: 16,
        },
    );
    let reflective = |roughness: f32, metallic: f32| {
        MaterialWorld::new(
            &renderer,
            vec![
                Material::new()
                    .with(Feature::CookTorrance, &[[roughness, metallic, 0.04, 0.0]])
                    .and_then(|m| m.with(Feature::Reflection, &[[1.0, 0.0, 0.0, 0.0]]))
                    .expect("valid"),
            ],
        )
    };
    let specular = |g: &Arc<GBuffer>, world: Arc<MaterialWorld>| {
        let r = Reflection::new(
            &renderer,
            None,
            g.clone(),
            world,
            environment.clone(),
            ReflectionMode::Reflect,
        );
        let [image] = frame(&renderer, r.as_ref(), [&r.specular]);
        assert!(image.all_finite());
        image
    };
    // The world says rough and dielectric; the floor's material says a mirror metal.
    let mirror = scene(
        &renderer,
        Some(material(
            "mirror",
            "out.roughness = 0.0;\n    out.metallic = 1.0;",
        )),
        None,
    );
    let plain = scene(&renderer, None, None);
    let resolved = specular(&mirror, reflective(0.9, 0.0));
    let as_mirror = specular(&plain, reflective(0.0, 1.0));
    let as_world = specular(&plain, reflective(0.9, 0.0));
    let mut differs = 0;
    for ((a, b), c) in resolved
        .pixels
        .iter()
        .zip(&as_mirror.pixels)
        .zip(&as_world.pixels)
    {
        for k in 0..3 {
            assert!(
                (a[k] - b[k]).abs() <= 2e-3 * b[k].max(1.0),
                "{a:?} vs {b:?}"
            );
        }
        differs += usize::from((a[0] - c[0]).abs() > 0.05);
    }
    assert!(
        differs > (SIZE.0 * SIZE.1 / 4) as usize,
        "a rough dielectric reflects otherwise ({differs} pixels differ)"
    );
}

/// A material's `uv` is the layer's texture coordinates whenever the layer
/// has them (docs/shader-nodes.md), with no colour or normal map besides;
/// and read with the velocity (the surface and motion resolves in one
/// dispatch) the G-buffer is the one each resolve writes alone.
#[test]
fn a_material_reads_the_layers_texture_coordinates_without_maps() {
    use spreadlight_render::gbuffer::{LayerFeatures, SURFACE_AND_MOTION_DISPATCHES};
    let renderer = test_renderer();
    let uv_albedo = material("uv", "    out.albedo = vec3<f32>(in.uv, 0.25);");
    let t = Mat4::IDENTITY;
    let batches = vec![DrawBatch {
        mesh: floor_mesh(&renderer),
        instances: vec![InstanceInput {
            transform: t,
            previous_transform: t,
            color: [1.0; 4],
            material_id: 0,
            object_id: 0,
        }],
    }];
    let features = LayerFeatures {
        texcoords: true,
        ..LayerFeatures::default()
    };
    let layer = Layer::new(None, batches, features, None)
        .expect("a plain layer")
        .with_surface(Some(uv_albedo));
    let g = GBuffer::new(
        &renderer,
        None,
        vec![Arc::new(layer)],
        camera(),
        None,
        SizeRule::Relative(1.0),
    );
    let [alone] = frame(&renderer, g.as_ref(), [&g.targets.color]);
    let (report, both) = render_and_read(
        &renderer,
        g.as_ref(),
        SIZE,
        &[&g.targets.color, &g.targets.velocity_uv],
    )
    .expect("the frame renders");
    assert!(report.errors.is_empty(), "{:?}", report.errors);
    assert_eq!(report.counter(SURFACE_AND_MOTION_DISPATCHES), 1);
    assert!(
        alone.pixels == both[0].pixels,
        "one dispatch or two: the same colours"
    );
    // The floor's colour is its UV: it spans the texture across the view,
    // and the motion target's texture coordinates (BA) are the same UVs.
    let (mut lo, mut hi) = (f32::MAX, f32::MIN);
    for (c, v) in alone.pixels.iter().zip(&both[1].pixels) {
        if c[2] == 0.25 {
            lo = lo.min(c[0]);
            hi = hi.max(c[0]);
            assert!(
                (c[0] - v[2]).abs() < 1e-3 && (c[1] - v[3]).abs() < 1e-3,
                "{c:?} {v:?}"
            );
        }
    }
    assert!(hi - lo > 0.2, "u spans {lo}..{hi} across the floor");
}

/// glTF material extensions as the lit floor shows them. The floor's
/// material 0 is `material`; each pixel against the CPU BRDF at the floor
/// point it sees.
fn shade_floor_material(renderer: &Renderer, material: Material) -> (ImageF32, ImageF32) {
    let g = scene(renderer, None, None);
    let world = MaterialWorld::new(renderer, vec![material]);
    shade(
        renderer,
        &g,
        LightBuffer::suns(renderer, &[SUN]),
        Surfaces::Materials(world),
    )
}

#[test]
fn clearcoat_adds_its_lobe_and_dims_the_base_as_the_reference_does() {
    use spreadlight_reference::brdf::clearcoat;
    let renderer = test_renderer();
    let l = -SUN.direction.normalize();
    let radiance = SUN.color * SUN.illuminance;
    let albedo = Vec3::from(FLOOR_ALBEDO);
    let points = floor_points();
    let base = Material::new()
        .with(Feature::CookTorrance, &[[0.7, 0.0, 0.04, 0.0]])
        .expect("valid");
    let compiled = |renderer: &Renderer| {
        renderer
            .shaders()
            .compiled_keys()
            .filter(|k| k.features.contains("CLEARCOAT"))
            .count()
    };
    // No coat anywhere: the coat's code is never compiled.
    let (plain_d, plain_s) = shade_floor_material(&renderer, base.clone());
    assert_eq!(
        compiled(&renderer),
        0,
        "no Clearcoat material, no CLEARCOAT permutation"
    );
    for (factor, coat_roughness) in [(1.0, 0.1), (0.5, 0.4)] {
        let coated = base
            .clone()
            .with(Feature::Clearcoat, &[[factor, coat_roughness, 0.0, 0.0]])
            .expect("valid");
        let (d, s) = shade_floor_material(&renderer, coated);
        let mut checked = 0;
        for (i, seen) in points.iter().enumerate() {
            let Some((_, v)) = seen else { continue };
            let brdf = cook_torrance_f0(Vec3::Y, *v, l, albedo, 0.7, 0.0, 0.04, true);
            let (dim, lobe) = clearcoat(Vec3::Y, *v, l, factor, coat_roughness);
            let want_d = brdf.diffuse * radiance * dim;
            let want_s = (brdf.specular * dim + Vec3::splat(factor * lobe)) * radiance;
            for c in 0..3 {
                // Half-float targets (11 significant bits) and f32 against f32.
                let close = |got: f32, want: f32| (got - want).abs() <= 4e-3 * want + 1e-4;
                assert!(
                    close(d.pixels[i][c], want_d[c]),
                    "coat {factor}/{coat_roughness}: diffuse {:?}, the reference says {want_d}",
                    d.pixels[i]
                );
                assert!(
                    close(s.pixels[i][c], want_s[c]),
                    "coat {factor}/{coat_roughness}: specular {:?}, the reference says {want_s}",
                    s.pixels[i]
                );
            }
            // The coat takes light from the base: every lit pixel's diffuse is darker.
            if plain_d.pixels[i][0] > 1e-3 {
                assert!(d.pixels[i][0] < plain_d.pixels[i][0]);
            }
            checked += 1;
        }
        assert!(
            checked > (SIZE.0 * SIZE.1 / 3) as usize,
            "{checked} floor pixels"
        );
        // The coat changes the specular image, not only the diffuse one.
        let sum = |image: &ImageF32| image.pixels.iter().map(|p| f64::from(p[1])).sum::<f64>();
        assert!(
            (sum(&s) - sum(&plain_s)).abs() > 0.01 * sum(&plain_s),
            "{} vs {}",
            sum(&s),
            sum(&plain_s)
        );
    }
    assert!(compiled(&renderer) >= 1);
}

#[test]
fn ior_and_specular_reach_direct_light_through_the_reflectance() {
    let renderer = test_renderer();
    let l = -SUN.direction.normalize();
    let radiance = SUN.color * SUN.illuminance;
    let albedo = Vec3::from(FLOOR_ALBEDO);
    let points = floor_points();
    // glTF's KHR_materials_ior and _specular arrive as CookTorrance's
    // reflectance (spreadlight-gltf's `MaterialData::reflectance`, tested
    // there): water's ior (f0 0.020), and a tinted (Rec. 709 luminance of
    // (1, 0.5, 0.25)), halved specular over ior 1.8.
    let water = ((1.33f32 - 1.0) / (1.33 + 1.0)).powi(2);
    let tinted =
        ((1.8f32 - 1.0) / (1.8 + 1.0)).powi(2) * (0.2126 + 0.7152 * 0.5 + 0.0722 * 0.25) * 0.5;
    for (ior, f0) in [(1.33, water), (1.8, tinted)] {
        let material = Material::new()
            .with(Feature::CookTorrance, &[[0.5, 0.0, f0, 0.0]])
            .expect("valid");
        let (_, s) = shade_floor_material(&renderer, material);
        for (i, seen) in points.iter().enumerate() {
            let Some((_, v)) = seen else { continue };
            let want =
                cook_torrance_f0(Vec3::Y, *v, l, albedo, 0.5, 0.0, f0, true).specular * radiance;
            for c in 0..3 {
                assert!(
                    (s.pixels[i][c] - want[c]).abs() <= 4e-3 * want[c] + 1e-4,
                    "ior {ior}: specular {:?}, f0 {f0} says {want}",
                    s.pixels[i]
                );
            }
        }
    }
}

#[test]
fn unlit_materials_show_their_albedo_whatever_the_light() {
    let renderer = test_renderer();
    let points = floor_points();
    let g = scene(&renderer, None, None);
    let unlit = Material::default_material()
        .with(Feature::Unlit, &[[1.0, 0.0, 0.0, 0.0]])
        .expect("valid");
    let half = Material::default_material()
        .with(Feature::Unlit, &[[0.5, 0.0, 0.0, 0.0]])
        .expect("valid");
    // Unlit shares the emission permutation (no material here emits).
    let compiled = |renderer: &Renderer| {
        renderer
            .shaders()
            .compiled_keys()
            .filter(|k| k.features.contains("EMISSION"))
            .count()
    };
    let lit = composite(
        &renderer,
        &g,
        point_light(&renderer),
        0.3,
        Some(MaterialWorld::new(
            &renderer,
            vec![Material::default_material()],
        )),
        None,
    );
    assert_eq!(compiled(&renderer), 0, "no Unlit material, no unlit code");
    for light in [no_lights(&renderer), point_light(&renderer)] {
        let image = composite(
            &renderer,
            &g,
            light,
            0.3,
            Some(MaterialWorld::new(&renderer, vec![unlit.clone()])),
            None,
        );
        for (pixel, seen) in image.pixels.iter().zip(&points) {
            if seen.is_none() {
                continue;
            }
            for c in 0..3 {
                assert!(
                    (pixel[c] - FLOOR_ALBEDO[c]).abs() <= 4e-3,
                    "unlit: {pixel:?}, albedo {FLOOR_ALBEDO:?}"
                );
            }
        }
    }
    // Strength 0.5: halfway between the lit colour and the albedo.
    let mixed = composite(
        &renderer,
        &g,
        point_light(&renderer),
        0.3,
        Some(MaterialWorld::new(&renderer, vec![half])),
        None,
    );
    for ((m, l), seen) in mixed.pixels.iter().zip(&lit.pixels).zip(&points) {
        if seen.is_none() {
            continue;
        }
        for c in 0..3 {
            let want = 0.5 * l[c] + 0.5 * FLOOR_ALBEDO[c];
            assert!(
                (m[c] - want).abs() <= 2e-3 * want.max(0.5),
                "{m:?} vs {want}"
            );
        }
    }
    assert!(compiled(&renderer) >= 1);
}
