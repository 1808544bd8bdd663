//! The material extensions' maps, sampled: generated glTF quads whose
//! `KHR_materials_clearcoat` maps (its normal map too) and
//! `KHR_materials_specular` maps (through the G-buffer resolve into
//! CookTorrance, and through lit transparency's every shading path) and
//! `KHR_materials_volume` thickness map (through lit transparency) change
//! each pixel as the map says, checked
//! against the CPU references (spreadlight-reference's BRDF and coat,
//! spreadlight-gltf's Beer-Lambert `MaterialData::transmittance`) at every
//! inner pixel. A world without such a map compiles none of their code.
//! `KHR_materials_sheen`'s factors, through CookTorrance and lit
//! transparency (forward and in compute), against
//! `spreadlight_reference::sheen`.
//! And the core maps beyond the G-buffer: an EnvironmentProbe's faces show
//! a quad's checkered base colour texture, its sheen and its iridescent
//! film (against the CPU references, seen from the probe).
//! `KHR_materials_anisotropy`'s factors and map through the G-buffer's
//! anisotropy target into CookTorrance, against the CPU anisotropic lobe
//! (`spreadlight_reference::anisotropy`). And `KHR_materials_iridescence`:
//! the film's Fresnel at every inner pixel against `reference::iridescence`,
//! its factor and thickness maps (through the G-buffer's sheen and film
//! target, and through lit transparency's forward light pass), and
//! `KHR_materials_sheen`'s colour and roughness maps likewise. And
//! image-based anisotropy: Reflection mirrors an anisotropic quad's view
//! about the extension's bent normal
//! (`reference::anisotropy::anisotropic_bent_normal`), so an environment's
//! bright stripe shows where the CPU reference says.

// The post tests' scene helpers, shared with the renderer's tests.
use crate::post_common;
// The glTF tests' quad view and layer.
use crate::common;

use std::sync::Arc;

use common::{QuadView, transparency_over, world_and_layer};
use glam::{Mat4, Vec2, Vec3};
use gltf_json as json;
use post_common::*;
use spreadlight_gltf::builder::{Doc, png, quad};
use spreadlight_gltf::{GltfScene, load_gltf_slice};
use spreadlight_reference::anisotropy::{
    anisotropic_bent_normal, anisotropy_direction, anisotropy_tangent, cook_torrance_anisotropic,
};
use spreadlight_reference::brdf::{clearcoat, cook_torrance_f0};
use spreadlight_reference::iridescence::{Film, cook_torrance_iridescent};
use spreadlight_render::gbuffer::GBuffer;
use spreadlight_render::lighting::{
    CookTorrance, LightBuffer, LightLoop, PointLight, SunLight, Surfaces,
};
use spreadlight_render::post::transparency::TransparencyPass;
use spreadlight_render::post::{
    LitBy, Transparency, TransparencyKey, TransparencySettings, TransparencyShading,
    TransparentLights,
};
use spreadlight_render::readback::{ImageF32, render_and_read};
use spreadlight_render::renderer::test_renderer;
use spreadlight_render::{Renderer, SizeRule};

const SIZE: (u32, u32) = (48, 48);
const DISTANCE: f32 = 3.0;
const FOV_Y: f32 = 0.8;
const VIEW: QuadView = QuadView {
    size: SIZE,
    distance: DISTANCE,
    fov_y: FOV_Y,
};
const ALBEDO: [f32; 3] = [0.8, 0.7, 0.6];
const ROUGHNESS: f32 = 0.7;
/// From the camera's side and above, so the quad shows a highlight.
const SUN: SunLight = SunLight {
    direction: Vec3::new(-0.3, -0.4, -1.0),
    color: Vec3::ONE,
    illuminance: 3.0,
    shadow: None,
};

/// A 16 x 16 map, `left` on its left half (or top, with `rows`), `right` on the other.
fn halves(left: [u8; 4], right: [u8; 4], rows: bool) -> Vec<u8> {
    let image = image::RgbaImage::from_fn(16, 16, |x, y| {
        let second = if rows { y >= 8 } else { x >= 8 };
        image::Rgba(if second { right } else { left })
    });
    png(&image)
}

/// The quad x, y in [-1, 1] at z = 0, facing +Z, UVs spanning it (v down),
/// with one material: `material` (its factors) and `extensions` (JSON, `{0}`
/// .. the indices of `maps`' textures, each sampled NEAREST so halves stay sharp).
fn model(material: json::Material, extensions: &str, maps: &[Vec<u8>]) -> Vec<u8> {
    let mut doc = Doc::new();
    let mesh = doc.mesh_data("Quad", &quad());
    let sampler = doc.nearest_sampler();
    let mut extensions = extensions.to_owned();
    for (i, map) in maps.iter().enumerate() {
        let image = doc.png_image(map);
        let texture = doc.texture(image);
        doc.root.textures[texture.value()].sampler = Some(sampler);
        extensions = extensions.replace(&format!("{{{i}}}"), &texture.value().to_string());
    }
    let mut material = material;
    let others: json::extensions::material::Material =
        json::deserialize::from_str(&extensions).expect("the test's extension objects");
    for name in others.others.keys() {
        doc.root.extensions_used.push(name.clone());
    }
    material.extensions = Some(others);
    let material = doc.material(material);
    doc.mesh_scene(mesh, material);
    doc.gltf_data_uri()
}

/// An opaque dielectric of [`ALBEDO`] and [`ROUGHNESS`].
fn opaque_material() -> json::Material {
    let mut material = json::Material::default();
    let [r, g, b] = ALBEDO;
    material.pbr_metallic_roughness.base_color_factor =
        json::material::PbrBaseColorFactor([r, g, b, 1.0]);
    material.pbr_metallic_roughness.metallic_factor = json::material::StrengthFactor(0.0);
    material.pbr_metallic_roughness.roughness_factor = json::material::StrengthFactor(ROUGHNESS);
    material
}

/// Every pixel well inside the quad and inside a half of each map: its
/// pixel index, the point it sees, and which half of the columns (u) and
/// of the rows (v) it is in.
fn inner_pixels() -> impl Iterator<Item = (usize, Vec3, usize, usize)> {
    (0..SIZE.1).flat_map(|py| {
        (0..SIZE.0).filter_map(move |px| {
            let (x, y) = VIEW.hit(px, py);
            let (u, v) = ((x + 1.0) / 2.0, (1.0 - y) / 2.0);
            let inner = x.abs() < 0.95 && y.abs() < 0.95;
            let clear = (u - 0.5).abs() > 0.04 && (v - 0.5).abs() > 0.04;
            (inner && clear).then(|| {
                let at = (py * SIZE.0 + px) as usize;
                (
                    at,
                    Vec3::new(x, y, 0.0),
                    usize::from(u >= 0.5),
                    usize::from(v >= 0.5),
                )
            })
        })
    })
}

/// CookTorrance's diffuse and specular of `model` under [`SUN`] (a file
/// that loads without a warning).
fn lit(renderer: &Renderer, model: &[u8]) -> (ImageF32, ImageF32) {
    let scene = load_gltf_slice(model, None).expect("loads");
    assert!(scene.warnings.is_empty(), "{:?}", scene.warnings);
    lit_scene(renderer, &scene, "the file")
}

/// CookTorrance's diffuse and specular of a loaded `scene` under [`SUN`]:
/// the frame renders without an error and every value is finite (`what`
/// names the case in a failure).
fn lit_scene(renderer: &Renderer, scene: &GltfScene, what: &str) -> (ImageF32, ImageF32) {
    lit_scene_at(renderer, scene, Mat4::IDENTITY, what)
}

/// [`lit_scene`] with the quad placed by `transform`.
fn lit_scene_at(
    renderer: &Renderer,
    scene: &GltfScene,
    transform: Mat4,
    what: &str,
) -> (ImageF32, ImageF32) {
    let (world, layer) = world_and_layer(renderer, scene, transform, scene.materials[0].base_color);
    let g = GBuffer::new(
        renderer,
        None,
        vec![layer],
        VIEW.camera(),
        None,
        SizeRule::Relative(1.0),
    );
    let ct = CookTorrance::new(
        renderer,
        None,
        g,
        LightBuffer::suns(renderer, &[SUN]),
        LightLoop::Clustered,
        true,
        Surfaces::Materials(world),
    );
    let (report, images) =
        render_and_read(renderer, ct.as_ref(), SIZE, &[&ct.diffuse, &ct.specular])
            .expect("the frame renders");
    assert!(report.errors.is_empty(), "{what}: {:?}", report.errors);
    let [d, s]: [ImageF32; 2] = images.try_into().unwrap_or_else(|_| unreachable!());
    assert!(
        d.all_finite() && s.all_finite(),
        "{what}: no NaN or infinity"
    );
    (d, s)
}

/// How many compiled shaders have `feature` on (the feature-cost checks:
/// none without the material that calls for it).
fn compiled_with(renderer: &Renderer, feature: &str) -> usize {
    renderer
        .shaders()
        .compiled_keys()
        .filter(|k| k.features.contains(feature))
        .count()
}

/// Half-float targets (11 significant bits) against f32.
fn close(got: f32, want: f32) -> bool {
    (got - want).abs() <= 4e-3 * want + 1e-4
}

#[test]
fn clearcoat_maps_put_the_coat_where_they_say() {
    let renderer = test_renderer();
    // The coat on the right half only (clearcoatTexture's red 0 | 255);
    // its roughness 0.4 on the top half, 0.4 x 128/255 below
    // (clearcoatRoughnessTexture's green, linear).
    let coat_map = halves([0, 0, 0, 255], [255, 0, 0, 255], false);
    let rough_map = halves([0, 255, 0, 255], [0, 128, 0, 255], true);
    let ext = r#"{"KHR_materials_clearcoat": {"clearcoatFactor": 1.0, "clearcoatRoughnessFactor": 0.4,
        "clearcoatTexture": {"index": {0}}, "clearcoatRoughnessTexture": {"index": {1}}}}"#;
    // A plain file first: no extension map, none of their code compiled.
    let (plain_d, _) = lit(&renderer, &model(opaque_material(), "{}", &[]));
    assert_eq!(compiled_with(&renderer, "EXTENSION_MAPS"), 0);
    let (d, s) = lit(
        &renderer,
        &model(opaque_material(), ext, &[coat_map, rough_map]),
    );
    assert!(compiled_with(&renderer, "EXTENSION_MAPS") >= 1);
    let l = -SUN.direction.normalize();
    let radiance = SUN.color * SUN.illuminance;
    let eye = Vec3::Z * DISTANCE;
    let mut checked = [[0; 2]; 2];
    for (i, p, u, v) in inner_pixels() {
        let view = (eye - p).normalize();
        let factor = [0.0, 1.0][u];
        // The surface target keeps the coat's roughness in 10 bits.
        let roughness = ((0.4 * [1.0, 128.0 / 255.0][v]) * 1023.0f32).round() / 1023.0;
        let brdf = cook_torrance_f0(Vec3::Z, view, l, ALBEDO.into(), ROUGHNESS, 0.0, 0.04, true);
        let (dim, lobe) = clearcoat(Vec3::Z, view, l, factor, roughness);
        let want_d = brdf.diffuse * radiance * dim;
        let want_s = (brdf.specular * dim + Vec3::splat(factor * lobe)) * radiance;
        for c in 0..3 {
            assert!(
                close(d.pixels[i][c], want_d[c]) && close(s.pixels[i][c], want_s[c]),
                "pixel {i} (half u {u}, v {v}): diffuse {:?} specular {:?}, the reference says {want_d} {want_s}",
                d.pixels[i],
                s.pixels[i]
            );
        }
        // Uncoated, it is the plain file's; coated, the coat takes from the base.
        if u == 0 {
            assert!(close(d.pixels[i][0], plain_d.pixels[i][0]));
        } else {
            assert!(d.pixels[i][0] < plain_d.pixels[i][0]);
        }
        checked[u][v] += 1;
    }
    assert!(
        checked.iter().flatten().all(|&n| n > 150),
        "{checked:?} pixels per quarter"
    );
}

#[test]
fn specular_maps_set_the_reflectance_per_pixel() {
    let renderer = test_renderer();
    // specularTexture's alpha: 64 | 255 (left | right); specularColorTexture:
    // white above, sRGB (255, 128, 0) below; ior 1.5 (f0 0.04), factors 1.
    let specular_map = halves([255, 255, 255, 64], [255, 255, 255, 255], false);
    let color_map = halves([255, 255, 255, 255], [255, 128, 0, 255], true);
    let ext = r#"{"KHR_materials_specular": {"specularTexture": {"index": {0}},
        "specularColorTexture": {"index": {1}}}}"#;
    let (_, s) = lit(
        &renderer,
        &model(opaque_material(), ext, &[specular_map, color_map]),
    );
    let l = -SUN.direction.normalize();
    let radiance = SUN.color * SUN.illuminance;
    let eye = Vec3::Z * DISTANCE;
    let srgb = |c: f32| ((c + 0.055) / 1.055).powf(2.4);
    let tints = [Vec3::ONE, Vec3::new(1.0, srgb(128.0 / 255.0), 0.0)];
    let mut checked = [[0; 2]; 2];
    for (i, p, u, v) in inner_pixels() {
        let view = (eye - p).normalize();
        // min(f0 x colour, 1) as one number (Rec. 709), x the specular map,
        // kept in 13 bits by the surface target.
        let f0 = 0.04 * tints[v];
        let grey = 0.2126 * f0.x + 0.7152 * f0.y + 0.0722 * f0.z;
        let reflectance = grey * [64.0 / 255.0, 1.0][u];
        let reflectance = (reflectance * 8191.0f32).round() / 8191.0;
        let want = cook_torrance_f0(
            Vec3::Z,
            view,
            l,
            ALBEDO.into(),
            ROUGHNESS,
            0.0,
            reflectance,
            true,
        )
        .specular
            * radiance;
        for c in 0..3 {
            assert!(
                close(s.pixels[i][c], want[c]),
                "pixel {i} (half u {u}, v {v}): specular {:?}, reflectance {reflectance} says {want}",
                s.pixels[i]
            );
        }
        checked[u][v] += 1;
    }
    assert!(
        checked.iter().flatten().all(|&n| n > 150),
        "{checked:?} pixels per quarter"
    );
}

#[test]
fn the_thickness_map_sets_how_much_a_transmissive_volume_absorbs() {
    let renderer = test_renderer();
    // All of it transmits (alpha 0), smooth, through a volume 0.5 deep
    // where thicknessTexture's green is 255 (right half) and 0 (left: thin
    // walled), absorbing to half after 0.25 (attenuation colour 0.5).
    let mut material = json::Material::default();
    material.pbr_metallic_roughness.roughness_factor = json::material::StrengthFactor(0.0);
    let thickness_map = halves([0, 0, 0, 255], [0, 255, 0, 255], false);
    let ext = r#"{"KHR_materials_transmission": {"transmissionFactor": 1.0},
        "KHR_materials_volume": {"thicknessFactor": 0.5, "thicknessTexture": {"index": {0}},
            "attenuationColor": [0.5, 0.5, 0.5], "attenuationDistance": 0.25}}"#;
    let scene = load_gltf_slice(&model(material, ext, &[thickness_map]), None).expect("loads");
    let data = &scene.materials[0];
    // Green behind: what shows through is green, absorbed.
    let background = image(&renderer, SIZE, |_, _| [0.0, 1.0, 0.0, 1.0]);
    let settings = TransparencySettings {
        ambient: Vec3::ONE,
        light_color: Vec3::ZERO,
        ..Default::default()
    };
    let (_, pass) = transparency_over(
        &renderer,
        &VIEW,
        &scene,
        Mat4::IDENTITY,
        background.texture_ref(),
        settings,
    );
    let pixels = render(&renderer, pass.as_ref(), &pass.output, SIZE)
        .1
        .pixels;
    let eye = Vec3::Z * DISTANCE;
    let mut checked = [0; 2];
    for (i, p, u, _) in inner_pixels() {
        // Snell into the slab (ior 1.5), the path across it: thickness / cos.
        let incident = (p - eye).normalize();
        let sin_t = incident.truncate().length() / 1.5;
        let path = [0.0, 0.5][u] / (1.0 - sin_t * sin_t).sqrt();
        let want = data.transmittance(path)[1];
        let got = pixels[i];
        assert!(
            (got[1] - want).abs() < 0.01 && got[0].abs() < 0.01 && got[2].abs() < 0.01,
            "pixel {i} (half {u}): {got:?}, Beer-Lambert over {path} says green {want}"
        );
        checked[u] += 1;
    }
    assert!(checked[0] > 300 && checked[1] > 300, "{checked:?}");
    // The thick half is clearly darker than the thin one: the map is read.
    let thick = data.transmittance(0.5)[1];
    assert!(thick < 0.3, "{thick}");
}

/// Hard cases under the maps: a specular colour factor of 1e30 (the
/// extension bounds it only below) caps f0 at 1, a coat of roughness 0 and
/// a thickness map under a factor of 1e30 stay finite (`lit` and `render`
/// check every pixel).
#[test]
fn extreme_factors_under_the_maps_stay_finite() {
    let renderer = test_renderer();
    let white = halves([255; 4], [255; 4], false);
    let ext = r#"{"KHR_materials_specular": {"specularColorFactor": [1e30, 1e30, 1e30],
            "specularTexture": {"index": {0}}, "specularColorTexture": {"index": {0}}},
        "KHR_materials_clearcoat": {"clearcoatFactor": 1.0, "clearcoatRoughnessFactor": 0.0,
            "clearcoatTexture": {"index": {0}}, "clearcoatRoughnessTexture": {"index": {0}}}}"#;
    // f0 1 reflects everything: a highlight, finite, and no diffuse left over it.
    let (d, s) = lit(
        &renderer,
        &model(opaque_material(), ext, std::slice::from_ref(&white)),
    );
    assert!(s.pixels.iter().any(|p| p[1] > 0.0));
    assert!(
        d.pixels.iter().all(|p| p[1] < 1e-3),
        "f0 1 leaves no diffuse"
    );
    let mut material = json::Material::default();
    material.pbr_metallic_roughness.roughness_factor = json::material::StrengthFactor(0.0);
    let ext = r#"{"KHR_materials_transmission": {"transmissionFactor": 1.0},
        "KHR_materials_volume": {"thicknessFactor": 1e30, "thicknessTexture": {"index": {0}},
            "attenuationColor": [0.5, 0.5, 0.5], "attenuationDistance": 0.25}}"#;
    let scene = load_gltf_slice(&model(material, ext, &[white]), None).expect("loads");
    let background = image(&renderer, SIZE, |_, _| [0.0, 1.0, 0.0, 1.0]);
    let (_, pass) = transparency_over(
        &renderer,
        &VIEW,
        &scene,
        Mat4::IDENTITY,
        background.texture_ref(),
        TransparencySettings::default(),
    );
    // Finite (checked by `render`): a thickness past 1e6 is no slab at all
    // (lit transparency's guard, as for an infinite factor), so what shows
    // through is the background, unabsorbed.
    let pixels = render(&renderer, pass.as_ref(), &pass.output, SIZE)
        .1
        .pixels;
    for (i, ..) in inner_pixels() {
        assert!(
            (pixels[i][1] - 1.0).abs() < 0.01,
            "pixel {i}: {:?}",
            pixels[i]
        );
    }
}

/// Lit transparency reads the specular map per fragment: a BLEND quad of
/// alpha 1 (what covers the background whole) whose specularTexture's
/// alpha is 64 | 255 (left | right), lit by [`SUN`] in a light pass, shows
/// the CPU BRDF's diffuse + specular with f0 0.04 x 64/255 on the left and
/// 0.04 on the right (sampled, not quantized).
#[test]
fn lit_transparency_reads_the_specular_map() {
    let renderer = test_renderer();
    let specular_map = halves([255, 255, 255, 64], [255, 255, 255, 255], false);
    let mut material = opaque_material();
    material.alpha_mode = json::validation::Checked::Valid(json::material::AlphaMode::Blend);
    let ext = r#"{"KHR_materials_specular": {"specularTexture": {"index": {0}}}}"#;
    let scene = load_gltf_slice(&model(material, ext, &[specular_map]), None).expect("loads");
    assert!(scene.warnings.is_empty(), "{:?}", scene.warnings);
    // The node's default shading and light loop.
    let defaults = TransparencySettings::default();
    let pass = blend_node(
        &renderer,
        &scene,
        defaults.shading,
        defaults.light_loop,
        LightBuffer::suns(&renderer, &[SUN]),
    );
    let pixels = render(&renderer, pass.as_ref(), &pass.output, SIZE)
        .1
        .pixels;
    let l = -SUN.direction.normalize();
    let radiance = SUN.color * SUN.illuminance;
    let eye = Vec3::Z * DISTANCE;
    let mut checked = [0; 2];
    for (i, p, u, _) in inner_pixels() {
        let view = (eye - p).normalize();
        let reflectance = 0.04 * [64.0 / 255.0, 1.0][u];
        let brdf = cook_torrance_f0(
            Vec3::Z,
            view,
            l,
            ALBEDO.into(),
            ROUGHNESS,
            0.0,
            reflectance,
            true,
        );
        let want = (brdf.diffuse + brdf.specular) * radiance;
        for c in 0..3 {
            // Half-float accumulation: about three decimal digits.
            assert!(
                (pixels[i][c] - want[c]).abs() <= 2e-3 + 1e-2 * want[c],
                "pixel {i} (half {u}): {:?}, f0 {reflectance} says {want}",
                pixels[i]
            );
        }
        checked[u] += 1;
    }
    assert!(checked[0] > 300 && checked[1] > 300, "{checked:?}");
}

/// An EnvironmentProbe in front of a generated glTF quad whose base colour
/// texture is a 4 x 4 checker of red and blue cells (sampled NEAREST) sees
/// the checker: the probe's -Z face shows, at each cell's centre, the
/// cell's colour, through the layer's surface maps (MATERIAL_MAPS on its
/// faces) as the G-buffer reads them. Without the maps it would be one
/// colour (the base colour factor's white).
#[test]
fn an_environment_probe_shows_a_gltf_quads_checker_base_colour() {
    use spreadlight_gltf::builder::info;
    use spreadlight_render::environment::probe::cube_direction;
    use spreadlight_render::environment::{
        Environment, EnvironmentQuality, EnvironmentSource, ProbeScene, ProbeSettings, Sky,
    };
    use spreadlight_render::readback::read_texture_layer;
    use spreadlight_render::static_texture::StaticTexture;
    const RED: [u8; 4] = [230, 40, 20, 255];
    const BLUE: [u8; 4] = [20, 40, 230, 255];
    let renderer = test_renderer();
    let checker = png(&image::RgbaImage::from_fn(16, 16, |x, y| {
        image::Rgba(if (x / 4 + y / 4) % 2 == 0 { RED } else { BLUE })
    }));
    let mut material = opaque_material();
    material.pbr_metallic_roughness.base_color_factor =
        json::material::PbrBaseColorFactor([1.0, 1.0, 1.0, 1.0]);
    // The first texture `model` makes: the checker.
    material.pbr_metallic_roughness.base_color_texture = Some(info(json::Index::new(0)));
    let scene = load_gltf_slice(&model(material, "{}", &[checker]), None).expect("loads");
    assert!(scene.warnings.is_empty(), "{:?}", scene.warnings);
    let (_, layer) = world_and_layer(
        &renderer,
        &scene,
        Mat4::IDENTITY,
        scene.materials[0].base_color,
    );
    // Before the quad (z = 0, facing +Z), looking at it through its -Z face.
    let position = Vec3::new(0.0, 0.0, 1.5);
    let probe = ProbeScene::new(
        vec![layer.clone()],
        ProbeSettings {
            position,
            ..Default::default()
        },
    )
    .expect("valid");
    let env = Environment::new(
        &renderer,
        None,
        EnvironmentSource::Probe(Arc::new(probe)),
        EnvironmentQuality {
            cube_size: 32,
            samples: 8,
        },
    );
    // Built for a Sky that shows it behind an empty G-buffer.
    let g = GBuffer::new(
        &renderer,
        None,
        Vec::new(),
        VIEW.camera(),
        None,
        SizeRule::Relative(1.0),
    );
    let black = vec![[0.0f32; 4]; (SIZE.0 * SIZE.1) as usize];
    let lit = StaticTexture::from_rgba32f(&renderer.gpu, SIZE.0, SIZE.1, &black, "lit");
    let sky = Sky::with_environment(
        &renderer,
        None,
        g,
        lit.texture_ref(),
        Default::default(),
        Some(env.clone()),
    );
    let (report, _) =
        render_and_read(&renderer, sky.as_ref(), SIZE, &[&sky.output]).expect("renders");
    assert!(report.errors.is_empty(), "{:?}", report.errors);
    assert_eq!(report.counter("environment probe rendered"), 1);
    let maps = env.maps().expect("built");
    let face = read_texture_layer(&renderer.gpu, &maps.base, 5, 0).expect("reads");
    assert!(face.all_finite());
    let n = face.width as f32;
    // Each cell's centre (u, v in the texture, the quad's x = 2u - 1, y = 1 - 2v).
    for row in 0..4 {
        for column in 0..4 {
            let (u, v) = ((column as f32 + 0.5) / 4.0, (row as f32 + 0.5) / 4.0);
            let p = Vec3::new(2.0 * u - 1.0, 1.0 - 2.0 * v, 0.0);
            // The -Z face's uv of the direction to it (`cube_direction(5, uv)` = (-u, -v, -1)).
            let d = (p - position) / (position.z - p.z);
            let face_uv = glam::Vec2::new(-d.x, -d.y);
            assert!((cube_direction(5, face_uv) - d).length() < 1e-5);
            let texel = |t: f32| ((t * 0.5 + 0.5) * n).floor().clamp(0.0, n - 1.0) as u32;
            let c = face.pixel(texel(face_uv.x), texel(face_uv.y));
            let red = (row + column) % 2 == 0;
            let (hot, cold) = if red { (c[0], c[2]) } else { (c[2], c[0]) };
            assert!(
                hot > 4.0 * cold,
                "cell ({column}, {row}) should be {}: {c:?}",
                if red { "red" } else { "blue" }
            );
        }
    }
    assert!(
        renderer
            .shaders()
            .compiled_keys()
            .any(|k| k.path() == "environment/environment_probe.wgsl"
                && k.features.contains("MATERIAL_MAPS")),
        "the surface maps' permutation"
    );
}

/// The -Z face (level 0) of an EnvironmentProbe 1.5 in front of the quad
/// of `file`, lit by the point `light` alone (no sun, no ambient, a black
/// background), and where the probe is.
fn probe_face(renderer: &Renderer, file: &[u8], light: PointLight) -> (ImageF32, Vec3) {
    use spreadlight_render::environment::{
        Environment, EnvironmentQuality, EnvironmentSource, ProbeLighting, ProbeLights, ProbeScene,
        ProbeSettings, Sky,
    };
    use spreadlight_render::readback::read_texture_layer;
    use spreadlight_render::static_texture::StaticTexture;
    let scene = load_gltf_slice(file, None).expect("loads");
    assert!(scene.warnings.is_empty(), "{:?}", scene.warnings);
    let (_, layer) = world_and_layer(
        renderer,
        &scene,
        Mat4::IDENTITY,
        scene.materials[0].base_color,
    );
    let position = Vec3::new(0.0, 0.0, 1.5);
    let probe = ProbeScene::new(
        vec![layer],
        ProbeSettings {
            position,
            lighting: ProbeLighting {
                sun_direction: Vec3::NEG_Y,
                sun_color: Vec3::ZERO,
                ambient: Vec3::ZERO,
                background: Vec3::ZERO,
            },
            ..Default::default()
        },
    )
    .expect("valid")
    .with_lights(
        vec![ProbeLights {
            lights: LightBuffer::points(renderer, &[light]),
            shadows: None,
        }],
        8,
    )
    .expect("a point buffer");
    let env = Environment::new(
        renderer,
        None,
        EnvironmentSource::Probe(Arc::new(probe)),
        EnvironmentQuality {
            cube_size: 32,
            samples: 8,
        },
    );
    let g = GBuffer::new(
        renderer,
        None,
        Vec::new(),
        VIEW.camera(),
        None,
        SizeRule::Relative(1.0),
    );
    let black = vec![[0.0f32; 4]; (SIZE.0 * SIZE.1) as usize];
    let lit = StaticTexture::from_rgba32f(&renderer.gpu, SIZE.0, SIZE.1, &black, "lit");
    let sky = Sky::with_environment(
        renderer,
        None,
        g,
        lit.texture_ref(),
        Default::default(),
        Some(env.clone()),
    );
    let (report, _) =
        render_and_read(renderer, sky.as_ref(), SIZE, &[&sky.output]).expect("renders");
    assert!(report.errors.is_empty(), "{:?}", report.errors);
    let maps = env.maps().expect("built");
    let face = read_texture_layer(&renderer.gpu, &maps.base, 5, 0).expect("reads");
    assert!(face.all_finite(), "no NaN or infinity on the face");
    (face, position)
}

/// How many compiled probe-face shaders have `feature` on.
fn probe_permutations(renderer: &Renderer, feature: &str) -> usize {
    renderer
        .shaders()
        .compiled_keys()
        .filter(|k| {
            k.path() == "environment/environment_probe.wgsl" && k.features.contains(feature)
        })
        .count()
}

/// An EnvironmentProbe's faces draw the sheen and the iridescent film of
/// what they see: a probe in front of the quad, lit by a point light, at
/// chosen texels of its -Z face (a 5 x 5 grid over the quad): the plain
/// quad and one with a sheen, a plain copper metal and one with an oil
/// film, each within 2% + 2e-3 of the CPU reference (the half-float face)
/// seen from the probe; the lobed quads differ from the plain ones in the
/// direction the reference's difference says, wherever it says they differ
/// by more than 1% (the sheen dims the diffuse and adds its pink lobe, the
/// film recolours the metal's Fresnel). The plain file compiles none of the lobes; a quad
/// with a coat and anisotropy too draws finite.
#[test]
fn an_environment_probe_sees_the_sheen_and_the_iridescent_film() {
    use spreadlight_render::environment::probe::cube_direction;
    let renderer = test_renderer();
    let light = PointLight {
        position: Vec3::new(0.5, 0.4, 1.2),
        color: Vec3::ONE,
        intensity: 3.0,
        range: 8.0,
        shadow: None,
    };
    let (plain, position) = probe_face(&renderer, &model(opaque_material(), "{}", &[]), light);
    for lobe in ["CLEARCOAT", "SHEEN", "ANISOTROPY", "IRIDESCENCE"] {
        assert_eq!(
            probe_permutations(&renderer, lobe),
            0,
            "{lobe} for a plain file"
        );
    }
    let (sheened, _) = probe_face(&renderer, &model(opaque_material(), SHEEN_EXT, &[]), light);
    assert_eq!(probe_permutations(&renderer, "SHEEN"), 1);
    // The film over a copper-coloured metal (all specular: the film's F is all it shows).
    let copper = [0.95, 0.64, 0.54];
    let metal = || {
        let mut material = metal_material(0.4);
        let [r, g, b] = copper;
        material.pbr_metallic_roughness.base_color_factor =
            json::material::PbrBaseColorFactor([r, g, b, 1.0]);
        material
    };
    let (plain_metal, _) = probe_face(&renderer, &model(metal(), "{}", &[]), light);
    let film = r#"{"KHR_materials_iridescence": {"iridescenceFactor": 0.6, "iridescenceIor": 1.5,
        "iridescenceThicknessMaximum": 700}}"#;
    let (filmed, _) = probe_face(&renderer, &model(metal(), film, &[]), light);
    assert_eq!(probe_permutations(&renderer, "IRIDESCENCE"), 1);
    let n = plain.width as f32;
    let mut differing = [0; 2];
    for row in 0..5 {
        for column in 0..5 {
            // A texel over the quad (|x|, |y| < 0.9 on it) and the point it sees.
            let texel = |k: i32| ((k as f32 * 0.14 + 0.5) * n).floor() as u32;
            let (tx, ty) = (texel(column - 2), texel(row - 2));
            let uv = glam::Vec2::new(
                (tx as f32 + 0.5) / n * 2.0 - 1.0,
                (ty as f32 + 0.5) / n * 2.0 - 1.0,
            );
            let d = cube_direction(5, uv);
            let p = position + d * (position.z / -d.z);
            assert!(p.x.abs() < 0.9 && p.y.abs() < 0.9, "{p}");
            let view = (position - p).normalize();
            let to = light.position - p;
            let radiance = light.color
                * light.intensity
                * spreadlight_reference::lights::point_attenuation(to.length(), light.range);
            let l = to.normalize();
            let base =
                cook_torrance_f0(Vec3::Z, view, l, ALBEDO.into(), ROUGHNESS, 0.0, 0.04, true);
            let want_plain = (base.diffuse + base.specular) * radiance;
            let (scaling, lobe) = spreadlight_reference::sheen::sheen(
                Vec3::Z,
                view,
                l,
                SHEEN_COLOR.into(),
                SHEEN_ROUGHNESS,
            );
            let want_sheen = ((base.diffuse + base.specular) * scaling + lobe) * radiance;
            let oil = cook_torrance_iridescent(
                Vec3::Z,
                view,
                l,
                copper.into(),
                0.4,
                1.0,
                0.04,
                Film::new(0.6, 1.5, 700.0),
                true,
            );
            let want_film = (oil.diffuse + oil.specular) * radiance;
            let bare = cook_torrance_f0(Vec3::Z, view, l, copper.into(), 0.4, 1.0, 0.04, true);
            let want_metal = (bare.diffuse + bare.specular) * radiance;
            let at = |image: &ImageF32| image.pixel(tx, ty);
            for (k, (got, want)) in [
                (at(&plain), want_plain),
                (at(&sheened), want_sheen),
                (at(&plain_metal), want_metal),
                (at(&filmed), want_film),
            ]
            .into_iter()
            .enumerate()
            {
                for c in 0..3 {
                    assert!(
                        (got[c] - want[c]).abs() <= 2e-3 + 2e-2 * want[c],
                        "texel ({tx}, {ty}), image {k}: {got:?}, the reference says {want}"
                    );
                }
            }
            for (i, (image, want, bare, want_bare)) in [
                (&sheened, want_sheen, &plain, want_plain),
                (&filmed, want_film, &plain_metal, want_metal),
            ]
            .into_iter()
            .enumerate()
            {
                for c in 0..3 {
                    let said = want[c] - want_bare[c];
                    if said.abs() > 1e-2 * want_bare[c] + 2e-3 {
                        let got = at(image)[c] - at(bare)[c];
                        assert!(
                            got.signum() == said.signum(),
                            "texel ({tx}, {ty}), channel {c}: the lobe moved it by {got}, the reference by {said}"
                        );
                        differing[i] += 1;
                    }
                }
            }
        }
    }
    assert!(
        differing[0] >= 25 && differing[1] >= 15,
        "texel channels the lobes change: {differing:?}"
    );
    // Every lobe at once, a coat and anisotropy too: compiled and finite.
    let all = r#"{"KHR_materials_sheen": {"sheenColorFactor": [0.9, 0.5, 0.7], "sheenRoughnessFactor": 0.6},
        "KHR_materials_iridescence": {"iridescenceFactor": 1.0},
        "KHR_materials_clearcoat": {"clearcoatFactor": 1.0, "clearcoatRoughnessFactor": 0.1},
        "KHR_materials_anisotropy": {"anisotropyStrength": 1.0}}"#;
    probe_face(&renderer, &model(metal_material(0.0), all, &[]), light);
    for lobe in ["CLEARCOAT", "ANISOTROPY"] {
        assert_eq!(probe_permutations(&renderer, lobe), 1, "{lobe}");
    }
}

/// The coat's unit normal that a clearcoatNormalTexture texel (rgb) gives
/// on the quad: glTF's tangent frame there (MikkTSpace's, as the importer
/// makes it) is +x along u and +y up the image (v runs down the quad); x
/// and y scaled by `scale`.
fn coat_normal(texel: [u8; 3], scale: f32) -> Vec3 {
    let [x, y, z] = texel.map(|c| c as f32 / 255.0 * 2.0 - 1.0);
    Vec3::new(x * scale, y * scale, z).normalize()
}

/// `n` (z > 0) as the surface target keeps it: octahedral, 1022 steps an
/// axis (shaders/lib/surface_target.wgsl's pack_coat_normal). The camera
/// looks down -z from +z, so view space is world space turned by nothing.
fn kept_normal(n: Vec3) -> Vec3 {
    let e = n.truncate() / (n.x.abs() + n.y.abs() + n.z.abs());
    let q = ((e * 0.5 + Vec2::splat(0.5)) * 1022.0).round() / 1022.0 * 2.0 - Vec2::ONE;
    Vec3::new(q.x, q.y, 1.0 - q.x.abs() - q.y.abs()).normalize()
}

/// A coat over the whole quad (factor 1, roughness 0.4), its normal map
/// flat on the left and tilted along +u on the right (scale 0.8).
const FLAT: [u8; 3] = [128, 128, 255];
const TILTED: [u8; 3] = [200, 128, 220];
const COAT_NORMAL_EXT: &str = r#"{"KHR_materials_clearcoat": {"clearcoatFactor": 1.0,
    "clearcoatRoughnessFactor": 0.4, "clearcoatNormalTexture": {"index": {0}, "scale": 0.8}}}"#;

fn coat_normal_map() -> Vec<u8> {
    let [a, b, c] = FLAT;
    let [d, e, f] = TILTED;
    halves([a, b, c, 255], [d, e, f, 255], false)
}

/// The CPU reference of the coated quad at `p` under [`SUN`]: diffuse and
/// specular (per channel), with the coat's normal `coat_n` and the base's
/// reflectance `reflectance`.
fn coated_reference(p: Vec3, coat_n: Vec3, coat_roughness: f32, reflectance: f32) -> (Vec3, Vec3) {
    let l = -SUN.direction.normalize();
    let radiance = SUN.color * SUN.illuminance;
    let view = (Vec3::Z * DISTANCE - p).normalize();
    let brdf = cook_torrance_f0(
        Vec3::Z,
        view,
        l,
        ALBEDO.into(),
        ROUGHNESS,
        0.0,
        reflectance,
        true,
    );
    let (dim, lobe) = clearcoat(coat_n, view, l, 1.0, coat_roughness);
    (
        brdf.diffuse * radiance * dim,
        (brdf.specular * dim + Vec3::splat(lobe)) * radiance,
    )
}

/// The coat's own normal: a glTF with a clearcoatNormalTexture loads with
/// no warning, and CookTorrance shades the coat lobe (and the Fresnel it
/// dims the base by) on the map's normal, the base on the quad's: each
/// inner pixel is the CPU BRDF's with the coat on the normal the surface
/// target keeps (8-bit coat roughness, the reflectance's 9-bit square root,
/// the normal in 2 x 10 bits), within 0.8% + 2e-4 (half-float targets);
/// the tilted half's coat differs from a flat coat's there by far more.
#[test]
fn the_clearcoat_normal_map_bends_the_coat_alone() {
    let renderer = test_renderer();
    let (d, s) = lit(
        &renderer,
        &model(opaque_material(), COAT_NORMAL_EXT, &[coat_normal_map()]),
    );
    assert!(compiled_with(&renderer, "EXTENSION_MAPS") >= 1);
    let kept = |x: f32, steps: f32| (x * steps).round() / steps;
    let coat_roughness = kept(0.4, 255.0);
    let reflectance = kept(0.04f32.sqrt(), 511.0).powi(2);
    let near = |got: f32, want: f32| (got - want).abs() <= 8e-3 * want + 2e-4;
    let mut checked = [0; 2];
    let mut bent = 0;
    for (i, p, u, _) in inner_pixels() {
        let coat_n = kept_normal(coat_normal([FLAT, TILTED][u], 0.8));
        let (want_d, want_s) = coated_reference(p, coat_n, coat_roughness, reflectance);
        for c in 0..3 {
            assert!(
                near(d.pixels[i][c], want_d[c]) && near(s.pixels[i][c], want_s[c]),
                "pixel {i} (half {u}): diffuse {:?} specular {:?}, the reference says {want_d} {want_s} (coat normal {coat_n})",
                d.pixels[i],
                s.pixels[i]
            );
        }
        // Where the map tilts the coat, a flat coat would look otherwise.
        let (_, flat_s) = coated_reference(p, Vec3::Z, coat_roughness, reflectance);
        if u == 1 && (s.pixels[i][0] - flat_s.x).abs() > 0.1 * flat_s.x {
            bent += 1;
        }
        checked[u] += 1;
    }
    assert!(checked[0] > 300 && checked[1] > 300, "{checked:?}");
    assert!(
        bent * 2 > checked[1],
        "{bent} of {} pixels bent",
        checked[1]
    );
}

/// A BLEND quad of alpha 1 lit by `lights`, shaded as `shading`.
fn lit_blend(
    renderer: &Renderer,
    ext: &str,
    maps: &[Vec<u8>],
    lights: Arc<LightBuffer>,
    light_loop: LightLoop,
    shading: TransparencyShading,
) -> Vec<[f32; 4]> {
    let mut material = opaque_material();
    material.alpha_mode = json::validation::Checked::Valid(json::material::AlphaMode::Blend);
    let scene = load_gltf_slice(&model(material, ext, maps), None).expect("loads");
    assert!(scene.warnings.is_empty(), "{:?}", scene.warnings);
    let g = GBuffer::new(
        renderer,
        None,
        vec![],
        VIEW.camera(),
        None,
        SizeRule::Relative(1.0),
    );
    let background = image(renderer, SIZE, |_, _| [0.0, 0.0, 0.0, 1.0]);
    let settings = TransparencySettings {
        ambient: Vec3::ZERO,
        light_color: Vec3::ZERO,
        energy_compensation: true,
        light_loop,
        shading,
        ..Default::default()
    };
    let (_, layer) = world_and_layer(
        renderer,
        &scene,
        Mat4::IDENTITY,
        scene.materials[0].base_color,
    );
    let pass = Transparency::lit(
        renderer,
        None,
        background.texture_ref(),
        g,
        vec![layer],
        settings,
        LitBy {
            lights: vec![TransparentLights {
                lights,
                shadows: None,
            }],
            ..Default::default()
        },
    );
    assert_eq!(
        pass.shades_in_compute(),
        shading != TransparencyShading::Forward
    );
    // `render` asserts every pixel finite.
    render(renderer, pass.as_ref(), &pass.output, SIZE).1.pixels
}

/// How many compiled shaders have CLEARCOAT on.
fn coat_permutations(renderer: &Renderer) -> usize {
    renderer
        .shaders()
        .compiled_keys()
        .filter(|k| k.path() == "post/transparency.wgsl" && k.features.contains("CLEARCOAT"))
        .count()
}

/// Lit transparency draws the coat, on its normal map's normal, in every
/// shading path: forward and compute under [`SUN`] match the CPU BRDF's
/// (diffuse + specular) x dim + the coat's lobe at every inner pixel
/// (within 1% + 2e-3: the half-float accumulation); a clustered point
/// light shaded in tiles matches its forward picture, and the tilted
/// half differs from a flat coat's. A layer without a coat compiles none
/// of it.
#[test]
fn lit_transparency_draws_the_coat_on_its_normal_map() {
    let renderer = test_renderer();
    let suns = || LightBuffer::suns(&renderer, &[SUN]);
    let forward = TransparencyShading::Forward;
    // Uncoated first: no coat code compiled.
    lit_blend(&renderer, "{}", &[], suns(), LightLoop::Naive, forward);
    assert_eq!(coat_permutations(&renderer), 0);
    for shading in [forward, TransparencyShading::Compute] {
        let pixels = lit_blend(
            &renderer,
            COAT_NORMAL_EXT,
            &[coat_normal_map()],
            suns(),
            LightLoop::Naive,
            shading,
        );
        let mut checked = [0; 2];
        for (i, p, u, _) in inner_pixels() {
            let coat_n = coat_normal([FLAT, TILTED][u], 0.8);
            let (d, s) = coated_reference(p, coat_n, 0.4, 0.04);
            let want = d + s;
            for c in 0..3 {
                assert!(
                    (pixels[i][c] - want[c]).abs() <= 2e-3 + 1e-2 * want[c],
                    "{shading:?}: pixel {i} (half {u}): {:?}, the reference says {want}",
                    pixels[i]
                );
            }
            checked[u] += 1;
        }
        assert!(checked[0] > 300 && checked[1] > 300, "{checked:?}");
    }
    assert!(coat_permutations(&renderer) >= 2);
    // A point light in front of the tilted half, its lists walked in tiles.
    let point = || {
        LightBuffer::points(
            &renderer,
            &[PointLight {
                position: Vec3::new(0.6, 0.2, 1.0),
                color: Vec3::ONE,
                intensity: 4.0,
                range: 10.0,
                shadow: None,
            }],
        )
    };
    let clustered = LightLoop::Clustered;
    let ahead = lit_blend(
        &renderer,
        COAT_NORMAL_EXT,
        &[coat_normal_map()],
        point(),
        clustered,
        forward,
    );
    let tiled = lit_blend(
        &renderer,
        COAT_NORMAL_EXT,
        &[coat_normal_map()],
        point(),
        clustered,
        TransparencyShading::Tiled,
    );
    let flat_ext = COAT_NORMAL_EXT.replace(
        r#", "clearcoatNormalTexture": {"index": {0}, "scale": 0.8}"#,
        "",
    );
    assert!(!flat_ext.contains("Normal"), "{flat_ext}");
    let flat = lit_blend(
        &renderer,
        &flat_ext,
        &[],
        point(),
        clustered,
        TransparencyShading::Tiled,
    );
    // Per half: how far the tiled picture is from the flat coat's, and the flat coat's light.
    let mut apart = [0.0f32; 2];
    let mut light = [0.0f32; 2];
    for (i, _, u, _) in inner_pixels() {
        for c in 0..3 {
            assert!(
                (tiled[i][c] - ahead[i][c]).abs() <= 2e-3 + 1e-2 * ahead[i][c],
                "pixel {i}: tiled {:?}, forward {:?}",
                tiled[i],
                ahead[i]
            );
            apart[u] += (tiled[i][c] - flat[i][c]).abs();
            light[u] += flat[i][c];
        }
    }
    // The flat texels leave the coat as it was; the tilted ones move its highlight.
    assert!(
        apart[1] > 10.0 * apart[0] && apart[1] > 0.01 * light[1],
        "the map moves the tiled coat: {apart:?} apart over {light:?}"
    );
}

/// Hard cases of the coat's normal map: texels of (almost) zero length
/// (128, 128, 128: the quad's frame times 1/255) on the left and pointing
/// into the surface (128, 128, 0) on the right, under a coat of factor 0
/// and 1 and roughness 0, opaque and blended, forward and in compute:
/// every pixel finite (`lit` and `render` check). Factor 0 drops the maps
/// (the plain file's picture); factor 1 with the coat facing away from
/// the viewer reflects all at N.V = 0 (Schlick), so nothing of the base
/// shows through it there.
#[test]
fn degenerate_clearcoat_normals_stay_finite() {
    let renderer = test_renderer();
    let map = halves([128, 128, 128, 255], [128, 128, 0, 255], false);
    let (plain_d, _) = lit(&renderer, &model(opaque_material(), "{}", &[]));
    for factor in [0.0, 1.0] {
        let ext = format!(
            r#"{{"KHR_materials_clearcoat": {{"clearcoatFactor": {factor:.1},
                "clearcoatRoughnessFactor": 0.0, "clearcoatNormalTexture": {{"index": {{0}}}}}}}}"#
        );
        let (d, _) = lit(
            &renderer,
            &model(opaque_material(), &ext, std::slice::from_ref(&map)),
        );
        for (i, _, u, _) in inner_pixels() {
            let (got, plain) = (d.pixels[i][0], plain_d.pixels[i][0]);
            if factor == 0.0 {
                assert!(close(got, plain), "pixel {i}: {got} against {plain}");
            } else if u == 1 {
                assert!(got < 0.01 * plain, "pixel {i}: {got} shows through");
            }
        }
        for shading in [TransparencyShading::Forward, TransparencyShading::Compute] {
            lit_blend(
                &renderer,
                &ext,
                std::slice::from_ref(&map),
                LightBuffer::suns(&renderer, &[SUN]),
                LightLoop::Naive,
                shading,
            );
        }
    }
}

/// A metal of [`ALBEDO`] and roughness `roughness`: its highlight is all
/// specular, where anisotropy shows.
fn metal_material(roughness: f32) -> json::Material {
    let mut material = opaque_material();
    material.pbr_metallic_roughness.metallic_factor = json::material::StrengthFactor(1.0);
    material.pbr_metallic_roughness.roughness_factor = json::material::StrengthFactor(roughness);
    material
}

/// CookTorrance's diffuse and specular of `model` under [`SUN`], the quad
/// placed by `transform`.
fn lit_at(renderer: &Renderer, model: &[u8], transform: Mat4) -> (ImageF32, ImageF32) {
    let scene = load_gltf_slice(model, None).expect("loads");
    lit_scene_at(renderer, &scene, transform, "the file")
}

/// The CPU reference of the anisotropic metal quad at `p` under [`SUN`]:
/// diffuse and specular, the direction `direction` in the quad's tangent
/// frame (+x along u, +y up the image: see [`coat_normal`]).
fn anisotropic_reference(
    p: Vec3,
    roughness: f32,
    direction: [f32; 2],
    strength: f32,
) -> (Vec3, Vec3) {
    let l = -SUN.direction.normalize();
    let radiance = SUN.color * SUN.illuminance;
    let view = (Vec3::Z * DISTANCE - p).normalize();
    let brdf = match anisotropy_tangent(Vec3::Z, Vec3::X, Vec3::Y, direction) {
        Some(t) => cook_torrance_anisotropic(
            Vec3::Z,
            view,
            l,
            t,
            ALBEDO.into(),
            roughness,
            1.0,
            0.04,
            strength,
            true,
        ),
        None => cook_torrance_f0(Vec3::Z, view, l, ALBEDO.into(), roughness, 1.0, 0.04, true),
    };
    (brdf.diffuse * radiance, brdf.specular * radiance)
}

/// `KHR_materials_anisotropy`'s factors and map, through the G-buffer's
/// anisotropy target into CookTorrance: a metal quad (roughness 0.3,
/// strength 0.8, rotation 0.5 rad) whose anisotropyTexture points along
/// the tangent at full strength on the left half and along the bitangent
/// at half strength on the right; every inner pixel against the CPU
/// anisotropic lobe (`spreadlight_reference::anisotropy`) within 1% +
/// 2e-4 (half-float targets: the direction in 11-bit components), and
/// the two halves' highlights differ from the isotropic picture. A plain
/// file compiles no ANISOTROPY code; the file requires the extension and
/// loads without a warning.
#[test]
fn the_anisotropy_map_and_factors_stretch_the_highlight() {
    let renderer = test_renderer();
    let roughness = 0.3;
    let (_, iso_s) = lit(&renderer, &model(metal_material(roughness), "{}", &[]));
    assert_eq!(compiled_with(&renderer, "ANISOTROPY"), 0);
    let map = halves([255, 128, 255, 255], [128, 255, 128, 255], false);
    let ext = r#"{"KHR_materials_anisotropy": {"anisotropyStrength": 0.8, "anisotropyRotation": 0.5,
        "anisotropyTexture": {"index": {0}}}}"#;
    let file = model(metal_material(roughness), ext, &[map]);
    let text = String::from_utf8_lossy(&file).into_owned();
    let required = text.replacen(
        "\"extensionsUsed\"",
        "\"extensionsRequired\":[\"KHR_materials_anisotropy\"],\"extensionsUsed\"",
        1,
    );
    assert_ne!(required, text, "the file names the extensions it uses");
    let scene = load_gltf_slice(required.as_bytes(), None).expect("a file requiring it loads");
    assert!(scene.warnings.is_empty(), "{:?}", scene.warnings);
    let (d, s) = lit(&renderer, required.as_bytes());
    assert!(
        compiled_with(&renderer, "ANISOTROPY") >= 2,
        "the resolve's and the light loop's"
    );
    let near = |got: f32, want: f32| (got - want).abs() <= 1e-2 * want + 2e-4;
    let texels = [[255u8, 128, 255], [128, 255, 128]];
    let mut checked = [0; 2];
    let mut stretched = [0; 2];
    for (i, p, u, _) in inner_pixels() {
        let [r, g, b] = texels[u].map(|c| c as f32 / 255.0);
        let direction = anisotropy_direction(0.5, Some([r, g]));
        let (want_d, want_s) = anisotropic_reference(p, roughness, direction, 0.8 * b);
        for c in 0..3 {
            assert!(
                near(d.pixels[i][c], want_d[c]) && near(s.pixels[i][c], want_s[c]),
                "pixel {i} (half {u}): diffuse {:?} specular {:?}, the reference says {want_d} {want_s}",
                d.pixels[i],
                s.pixels[i]
            );
        }
        if (s.pixels[i][0] - iso_s.pixels[i][0]).abs() > 0.05 * iso_s.pixels[i][0] {
            stretched[u] += 1;
        }
        checked[u] += 1;
    }
    assert!(checked[0] > 300 && checked[1] > 300, "{checked:?}");
    assert!(
        stretched[0] * 2 > checked[0] && stretched[1] * 4 > checked[1],
        "{stretched:?} of {checked:?} pixels differ from the isotropic lobe"
    );
}

/// The factors alone (no map): strength 1 turned a quarter turn, so the
/// highlight stretches along the quad's bitangent; every inner pixel
/// against the CPU lobe, as above.
#[test]
fn anisotropy_factors_alone_turn_the_highlight() {
    let renderer = test_renderer();
    let roughness = 0.4;
    let ext = r#"{"KHR_materials_anisotropy": {"anisotropyStrength": 1.0, "anisotropyRotation": 1.5707964}}"#;
    let (d, s) = lit(&renderer, &model(metal_material(roughness), ext, &[]));
    let near = |got: f32, want: f32| (got - want).abs() <= 1e-2 * want + 2e-4;
    let direction = anisotropy_direction(std::f32::consts::FRAC_PI_2, None);
    let mut checked = 0;
    for (i, p, _, _) in inner_pixels() {
        let (want_d, want_s) = anisotropic_reference(p, roughness, direction, 1.0);
        for c in 0..3 {
            assert!(
                near(d.pixels[i][c], want_d[c]) && near(s.pixels[i][c], want_s[c]),
                "pixel {i}: diffuse {:?} specular {:?}, the reference says {want_d} {want_s}",
                d.pixels[i],
                s.pixels[i]
            );
        }
        checked += 1;
    }
    assert!(checked > 1000, "{checked}");
}

/// Hard cases: strength 1 over roughness 0 on a quad turned 80 degrees
/// about y, so its tangent runs almost along the view; out-of-range and
/// malformed factors (strength 5, a rotation that is no number) warned by
/// material index and clamped or defaulted; a map whose left half has
/// almost no direction (rg 128/255: 1/255 along the diagonal, which is
/// made a unit direction) and a right half of strength 0. Every pixel
/// finite (`lit_at` checks); the half of strength 0 is the isotropic lobe's.
#[test]
fn degenerate_anisotropy_stays_finite() {
    let renderer = test_renderer();
    let ext = r#"{"KHR_materials_anisotropy": {"anisotropyStrength": 5.0, "anisotropyRotation": "turned",
        "anisotropyTexture": {"index": {0}}}}"#;
    let map = halves([128, 128, 255, 255], [255, 128, 0, 255], false);
    let file = model(metal_material(0.0), ext, std::slice::from_ref(&map));
    let scene = load_gltf_slice(&file, None).expect("loads");
    let warned = |key: &str| {
        scene
            .warnings
            .iter()
            .any(|w| w.contains("material 0") && w.contains(key))
    };
    assert!(warned("anisotropyStrength is 5"), "{:?}", scene.warnings);
    assert!(warned("anisotropyRotation"), "{:?}", scene.warnings);
    assert_eq!(scene.materials[0].anisotropy_strength, 1.0);
    assert_eq!(scene.materials[0].anisotropy_rotation, 0.0);
    let turned = Mat4::from_rotation_y(80f32.to_radians());
    lit_at(&renderer, &file, turned);
    // Facing the camera: no strength is the isotropic lobe.
    let (_, s) = lit_at(&renderer, &file, Mat4::IDENTITY);
    let (_, iso_s) = lit(&renderer, &model(metal_material(0.0), "{}", &[]));
    for (i, _, _, _) in inner_pixels().filter(|&(_, _, u, _)| u == 1) {
        assert!(
            close(s.pixels[i][0], iso_s.pixels[i][0]),
            "pixel {i}: {:?} against {:?}",
            s.pixels[i],
            iso_s.pixels[i]
        );
    }
    // Strength 1, roughness 0, grazing: the factor alone, the quad edge-on.
    let ext = r#"{"KHR_materials_anisotropy": {"anisotropyStrength": 1.0}}"#;
    lit_at(
        &renderer,
        &model(metal_material(0.0), ext, &[]),
        Mat4::from_rotation_y(89f32.to_radians()),
    );
}

/// `scene`'s first layer as a lit transparent layer over black, lit by
/// `lights` (walked by `light_loop`) alone and shaded as `shading` says:
/// the node and its picture.
fn lit_blend_scene(
    renderer: &Renderer,
    scene: &spreadlight_gltf::GltfScene,
    shading: TransparencyShading,
    light_loop: LightLoop,
    lights: Arc<LightBuffer>,
) -> (Arc<Transparency>, ImageF32) {
    let pass = blend_node(renderer, scene, shading, light_loop, lights);
    let out = render(renderer, pass.as_ref(), &pass.output, SIZE).1;
    (pass, out)
}

/// The node of [`lit_blend_scene`], not rendered.
fn blend_node(
    renderer: &Renderer,
    scene: &spreadlight_gltf::GltfScene,
    shading: TransparencyShading,
    light_loop: LightLoop,
    lights: Arc<LightBuffer>,
) -> Arc<Transparency> {
    let g = GBuffer::new(
        renderer,
        None,
        vec![],
        VIEW.camera(),
        None,
        SizeRule::Relative(1.0),
    );
    let background = image(renderer, SIZE, |_, _| [0.0, 0.0, 0.0, 1.0]);
    let settings = TransparencySettings {
        ambient: Vec3::ZERO,
        light_color: Vec3::ZERO,
        energy_compensation: true,
        light_loop,
        shading,
        ..Default::default()
    };
    let (_, layer) = world_and_layer(
        renderer,
        scene,
        Mat4::IDENTITY,
        scene.materials[0].base_color,
    );
    Transparency::lit(
        renderer,
        None,
        background.texture_ref(),
        g,
        vec![layer],
        settings,
        LitBy {
            lights: vec![TransparentLights {
                lights,
                shadows: None,
            }],
            ..Default::default()
        },
    )
}

/// A BLEND version of `material`.
fn blended(material: json::Material) -> json::Material {
    let mut material = material;
    material.alpha_mode = json::validation::Checked::Valid(json::material::AlphaMode::Blend);
    material
}

/// The largest difference between two pictures, relative to 1 or the value
/// where larger (the transparency tests' measure of forward against compute).
fn largest_difference(a: &ImageF32, b: &ImageF32) -> (f32, String) {
    let mut worst = (0.0, String::new());
    for (i, (s, t)) in a.pixels.iter().zip(&b.pixels).enumerate() {
        for (u, v) in s.iter().zip(t) {
            let d = (u - v).abs() / u.abs().max(1.0);
            if d > worst.0 {
                worst = (d, format!("pixel {i}: {s:?} against {t:?}"));
            }
        }
    }
    worst
}

/// How close compute shading comes to the forward light passes: the
/// tolerance of crates/render/tests/transparency.rs (`COMPUTE_TOLERANCE`:
/// the records' 16-bit packing and the forward path's half-float sums).
const COMPUTE_TOLERANCE: f32 = 4e-3;

/// Lit transparency draws the anisotropic lobe: a BLEND metal quad of
/// alpha 1 (the map and factors of
/// [`the_anisotropy_map_and_factors_stretch_the_highlight`]) under [`SUN`],
/// every inner pixel against the CPU lobe's diffuse + specular within 1% +
/// 2e-3 (the half-float accumulation), shaded forward and in compute (the
/// fragment records keep each fragment's direction and strength), the two
/// within the forward-against-compute tolerance of each other.
#[test]
fn lit_transparency_draws_the_anisotropic_lobe() {
    let renderer = test_renderer();
    let roughness = 0.3;
    let map = halves([255, 128, 255, 255], [128, 255, 128, 255], false);
    let ext = r#"{"KHR_materials_anisotropy": {"anisotropyStrength": 0.8, "anisotropyRotation": 0.5,
        "anisotropyTexture": {"index": {0}}}}"#;
    let scene = load_gltf_slice(
        &model(blended(metal_material(roughness)), ext, &[map]),
        None,
    )
    .expect("loads");
    assert!(scene.warnings.is_empty(), "{:?}", scene.warnings);
    let texels = [[255u8, 128, 255], [128, 255, 128]];
    let mut forward = None;
    for shading in [TransparencyShading::Forward, TransparencyShading::Compute] {
        let (pass, out) = lit_blend_scene(
            &renderer,
            &scene,
            shading,
            LightLoop::Naive,
            LightBuffer::suns(&renderer, &[SUN]),
        );
        assert_eq!(
            pass.shades_in_compute(),
            shading == TransparencyShading::Compute
        );
        let pixels = &out.pixels;
        let mut checked = [0; 2];
        for (i, p, u, _) in inner_pixels() {
            let [r, g, b] = texels[u].map(|c| c as f32 / 255.0);
            let direction = anisotropy_direction(0.5, Some([r, g]));
            let (d, s) = anisotropic_reference(p, roughness, direction, 0.8 * b);
            let want = d + s;
            for c in 0..3 {
                assert!(
                    (pixels[i][c] - want[c]).abs() <= 2e-3 + 1e-2 * want[c],
                    "{shading:?}: pixel {i} (half {u}): {:?}, the reference says {want}",
                    pixels[i]
                );
            }
            checked[u] += 1;
        }
        assert!(checked[0] > 300 && checked[1] > 300, "{checked:?}");
        match &forward {
            None => forward = Some(out),
            Some(forward) => {
                let (d, worst) = largest_difference(forward, &out);
                assert!(d <= COMPUTE_TOLERANCE, "{d} from forward {worst}");
            }
        }
    }
    assert!(
        renderer
            .shaders()
            .compiled_keys()
            .any(|k| k.path() == "post/transparency.wgsl" && k.features.contains("ANISOTROPY")),
        "the light pass compiled the lobe"
    );
}

/// Points near the quad, in front of it: a point light's highlight moves
/// across the quad, so the lobes' shapes show; clustered, so Tiled shares
/// their lists.
fn near_points() -> [PointLight; 2] {
    [
        PointLight {
            position: Vec3::new(0.6, 0.7, 1.2),
            color: Vec3::new(1.0, 0.9, 0.8),
            intensity: 4.0,
            range: 6.0,
            shadow: None,
        },
        PointLight {
            position: Vec3::new(-0.8, -0.3, 0.9),
            color: Vec3::new(0.4, 0.6, 1.0),
            intensity: 2.0,
            range: 4.0,
            shadow: None,
        },
    ]
}

/// Compute and Tiled shading draw the sheen, the anisotropic lobe and both
/// together on BLEND quads as the forward light passes do (within the
/// forward-against-compute tolerance), under two clustered point lights;
/// each lobe changes the picture, Auto shades such layers in compute, and
/// the shade passes compile SHEEN and ANISOTROPY only for a node whose
/// layers have them (a plain quad's compile neither).
#[test]
fn compute_transparency_draws_the_sheen_and_anisotropy_as_forward_does() {
    let renderer = test_renderer();
    let points = near_points();
    let lights = || LightBuffer::points(&renderer, &points);
    let map = halves([255, 128, 255, 255], [128, 255, 128, 255], false);
    let aniso = r#""KHR_materials_anisotropy": {"anisotropyStrength": 0.8, "anisotropyRotation": 0.5,
        "anisotropyTexture": {"index": {0}}}"#;
    let sheen = r#""KHR_materials_sheen": {"sheenColorFactor": [0.9, 0.5, 0.7], "sheenRoughnessFactor": 0.6}"#;
    let material = || blended(metal_material(0.3));
    let plain = load_gltf_slice(&model(material(), "{}", &[]), None).expect("loads");
    let (plain_pass, plain_out) = lit_blend_scene(
        &renderer,
        &plain,
        TransparencyShading::Compute,
        LightLoop::Clustered,
        lights(),
    );
    assert!(plain_pass.shades_in_compute());
    let shade_keys = |pass: &Transparency| -> Vec<TransparencyKey> {
        pass.keys()
            .into_iter()
            .filter(|k| {
                matches!(
                    k.pass,
                    TransparencyPass::Shade(_) | TransparencyPass::ShadeTiled(_)
                )
            })
            .collect()
    };
    let plain_keys = shade_keys(&plain_pass);
    assert!(!plain_keys.is_empty());
    assert!(plain_keys.iter().all(|k| !k.sheen && !k.anisotropy));
    for (what, ext, maps, has_sheen, has_aniso) in [
        ("sheen", format!("{{{sheen}}}"), vec![], true, false),
        (
            "anisotropy",
            format!("{{{aniso}}}"),
            vec![map.clone()],
            false,
            true,
        ),
        (
            "both",
            format!("{{{sheen}, {aniso}}}"),
            vec![map.clone()],
            true,
            true,
        ),
    ] {
        let scene = load_gltf_slice(&model(material(), &ext, &maps), None).expect("loads");
        assert!(scene.warnings.is_empty(), "{what}: {:?}", scene.warnings);
        let (forward_pass, forward) = lit_blend_scene(
            &renderer,
            &scene,
            TransparencyShading::Forward,
            LightLoop::Clustered,
            lights(),
        );
        assert!(!forward_pass.shades_in_compute());
        let (changed, _) = largest_difference(&plain_out, &forward);
        assert!(
            changed > 0.01,
            "{what}: the lobe changes the picture by {changed}"
        );
        // Auto is Compute on every adapter: such a layer no longer sends it forward.
        let auto = blend_node(
            &renderer,
            &scene,
            TransparencyShading::Auto,
            LightLoop::Clustered,
            lights(),
        );
        assert!(auto.shades_in_compute(), "{what}: Auto shades in compute");
        for shading in [TransparencyShading::Compute, TransparencyShading::Tiled] {
            let (pass, out) =
                lit_blend_scene(&renderer, &scene, shading, LightLoop::Clustered, lights());
            assert!(
                pass.shades_in_compute(),
                "{what}: {shading:?} shades in compute"
            );
            let keys = shade_keys(&pass);
            assert!(!keys.is_empty(), "{what}: {shading:?}");
            assert!(
                keys.iter()
                    .all(|k| k.sheen == has_sheen && k.anisotropy == has_aniso),
                "{what}: {shading:?}: {keys:?}"
            );
            let (d, worst) = largest_difference(&forward, &out);
            assert!(
                d <= COMPUTE_TOLERANCE,
                "{what}: {shading:?} is {d} from forward {worst}"
            );
        }
    }
}

/// `KHR_materials_iridescence` through CookTorrance: a soap film (ior 1.3,
/// 400 nm, factor 1) over the dielectric quad and an oil film (ior 1.5,
/// 700 nm, factor 0.6) over a copper-coloured metal match the CPU BRDF with
/// the film's Fresnel (`cook_torrance_iridescent`, a port of the Khronos
/// sample viewer's thin film) at every inner pixel, diffuse and specular
/// (half-float targets: 4e-3 relative); the film changes the highlight's
/// colour (green over red where Schlick's F is grey). No IRIDESCENCE code
/// compiled for a file without a film.
#[test]
fn an_iridescent_film_colours_the_specular_as_the_reference_says() {
    let renderer = test_renderer();
    let (_, plain_s) = lit(&renderer, &model(opaque_material(), "{}", &[]));
    assert_eq!(compiled_with(&renderer, "IRIDESCENCE"), 0);
    let l = -SUN.direction.normalize();
    let radiance = SUN.color * SUN.illuminance;
    let eye = Vec3::Z * DISTANCE;
    let copper = [0.95, 0.64, 0.54];
    for (albedo, metallic, ext, film) in [
        (
            ALBEDO,
            0.0,
            r#"{"KHR_materials_iridescence": {"iridescenceFactor": 1.0}}"#,
            Film::new(1.0, 1.3, 400.0),
        ),
        (
            copper,
            1.0,
            r#"{"KHR_materials_iridescence": {"iridescenceFactor": 0.6, "iridescenceIor": 1.5,
                "iridescenceThicknessMaximum": 700}}"#,
            Film::new(0.6, 1.5, 700.0),
        ),
    ] {
        let mut material = opaque_material();
        let [r, g, b] = albedo;
        material.pbr_metallic_roughness.base_color_factor =
            json::material::PbrBaseColorFactor([r, g, b, 1.0]);
        material.pbr_metallic_roughness.metallic_factor = json::material::StrengthFactor(metallic);
        let (d, s) = lit(&renderer, &model(material, ext, &[]));
        assert!(compiled_with(&renderer, "IRIDESCENCE") >= 1);
        let mut checked = 0;
        for (i, p, _, _) in inner_pixels() {
            let view = (eye - p).normalize();
            let want = cook_torrance_iridescent(
                Vec3::Z,
                view,
                l,
                albedo.into(),
                ROUGHNESS,
                metallic,
                0.04,
                film,
                true,
            );
            let (want_d, want_s) = (want.diffuse * radiance, want.specular * radiance);
            for c in 0..3 {
                assert!(
                    close(d.pixels[i][c], want_d[c]) && close(s.pixels[i][c], want_s[c]),
                    "pixel {i} (metallic {metallic}): diffuse {:?} specular {:?}, the reference says {want_d} {want_s}",
                    d.pixels[i],
                    s.pixels[i]
                );
            }
            checked += 1;
        }
        assert!(checked > 1000, "{checked} pixels");
    }
    // The soap film's highlight is green at near-normal view (its F at 400
    // nm: 0.007, 0.038, 0.016), where the bare dielectric's is grey.
    let (_, soap_s) = lit(
        &renderer,
        &model(
            opaque_material(),
            r#"{"KHR_materials_iridescence": {"iridescenceFactor": 1.0}}"#,
            &[],
        ),
    );
    let centre = (SIZE.1 / 2 * SIZE.0 + SIZE.0 / 2) as usize;
    let [r, g, _, _] = soap_s.pixels[centre];
    let [pr, pg, _, _] = plain_s.pixels[centre];
    assert!(
        g > 2.0 * r && (pg - pr).abs() < 1e-3 * pg,
        "soap {r} {g}, plain {pr} {pg}"
    );
}

/// Hard films stay finite: a factor of 1e30 (warned, 1), an ior below 1
/// (warned, 1.3), a thickness of 1e30 nm, a minimum above the maximum, a
/// grazing metal film; every pixel finite (`lit` asserts it) and each bad
/// value warned naming the material.
#[test]
fn hard_iridescence_values_stay_finite_and_are_warned() {
    let renderer = test_renderer();
    for ext in [
        r#"{"KHR_materials_iridescence": {"iridescenceFactor": 1e30, "iridescenceIor": 0.2}}"#,
        r#"{"KHR_materials_iridescence": {"iridescenceFactor": 1, "iridescenceThicknessMaximum": 1e30}}"#,
        r#"{"KHR_materials_iridescence": {"iridescenceFactor": 1, "iridescenceThicknessMinimum": 900,
            "iridescenceThicknessMaximum": 0}}"#,
        r#"{"KHR_materials_iridescence": {"iridescenceFactor": 1, "iridescenceIor": 1e30}}"#,
    ] {
        let file = model(opaque_material(), ext, &[]);
        let scene = load_gltf_slice(&file, None).expect("loads");
        let quiet = ext.contains("1e30}") && !ext.contains("Factor\": 1e30");
        assert!(
            quiet
                || scene.warnings.iter().all(|w| w.contains("material 0"))
                    && !scene.warnings.is_empty(),
            "{ext}: {:?}",
            scene.warnings
        );
        lit_scene(&renderer, &scene, ext);
    }
}

const SHEEN_COLOR: [f32; 3] = [0.9, 0.5, 0.7];
const SHEEN_ROUGHNESS: f32 = 0.6;
const SHEEN_EXT: &str = r#"{"KHR_materials_sheen": {"sheenColorFactor": [0.9, 0.5, 0.7],
    "sheenRoughnessFactor": 0.6}}"#;

/// What the CPU references say a pixel seeing `p` on the quad under [`SUN`]
/// gets with `sheen` (colour, roughness) over the opaque material:
/// diffuse and specular radiance (the sheen's lobe is specular).
fn sheened_reference(p: Vec3, sheen: ([f32; 3], f32)) -> (Vec3, Vec3) {
    let l = -SUN.direction.normalize();
    let radiance = SUN.color * SUN.illuminance;
    let view = (Vec3::Z * DISTANCE - p).normalize();
    let brdf = cook_torrance_f0(Vec3::Z, view, l, ALBEDO.into(), ROUGHNESS, 0.0, 0.04, true);
    let (scaling, lobe) =
        spreadlight_reference::sheen::sheen(Vec3::Z, view, l, sheen.0.into(), sheen.1);
    (
        brdf.diffuse * scaling * radiance,
        (brdf.specular * scaling + lobe) * radiance,
    )
}

/// KHR_materials_sheen's factors through CookTorrance (SHEEN): every inner
/// pixel's diffuse (dimmed by the sheen's albedo scaling) and specular
/// (with the Charlie lobe) against `spreadlight_reference::sheen`; a file
/// without a sheen compiles none of its code; extreme factors stay finite.
#[test]
fn the_sheen_factors_light_the_quad_as_the_reference_says() {
    let renderer = test_renderer();
    let (plain_d, plain_s) = lit(&renderer, &model(opaque_material(), "{}", &[]));
    assert_eq!(
        compiled_with(&renderer, "SHEEN"),
        0,
        "no sheen, no SHEEN code"
    );
    let (d, s) = lit(&renderer, &model(opaque_material(), SHEEN_EXT, &[]));
    assert!(compiled_with(&renderer, "SHEEN") >= 1);
    let mut checked = 0;
    for (i, p, _, _) in inner_pixels() {
        let (want_d, want_s) = sheened_reference(p, (SHEEN_COLOR, SHEEN_ROUGHNESS));
        for c in 0..3 {
            assert!(
                close(d.pixels[i][c], want_d[c]) && close(s.pixels[i][c], want_s[c]),
                "pixel {i}: diffuse {:?} specular {:?}, the reference says {want_d} {want_s}",
                d.pixels[i],
                s.pixels[i]
            );
        }
        // The sheen takes from the base's diffuse and adds its lobe,
        // tinted by its colour (red over green), to the base's grey specular.
        assert!(d.pixels[i][0] < plain_d.pixels[i][0]);
        assert!((plain_s.pixels[i][0] - plain_s.pixels[i][1]).abs() < 1e-3 * plain_s.pixels[i][0]);
        assert!(s.pixels[i][0] > s.pixels[i][1]);
        checked += 1;
    }
    assert!(checked > 600, "{checked} pixels checked");
    // Out of range and degenerate: a colour of 1e30 (clamped to 1 by the
    // loader, warned) at roughness 0, the narrowest lobe: finite (`lit` asserts it).
    let wild = r#"{"KHR_materials_sheen": {"sheenColorFactor": [1e30, 1e30, 1e30], "sheenRoughnessFactor": 0}}"#;
    let scene = load_gltf_slice(&model(opaque_material(), wild, &[]), None).expect("loads");
    assert_eq!(scene.warnings.len(), 1, "{:?}", scene.warnings);
    assert!(
        scene.warnings[0].contains("material 0"),
        "{:?}",
        scene.warnings
    );
    // What the loader made of it (white, roughness 0) draws finite (`lit`
    // asserts every pixel finite) and within the reference.
    let clamped = model(
        opaque_material(),
        r#"{"KHR_materials_sheen": {"sheenColorFactor": [1, 1, 1], "sheenRoughnessFactor": 0}}"#,
        &[],
    );
    let (d, s) = lit(&renderer, &clamped);
    for (i, p, _, _) in inner_pixels() {
        let (want_d, want_s) = sheened_reference(p, ([1.0; 3], 0.0));
        assert!(close(d.pixels[i][1], want_d[1]) && close(s.pixels[i][1], want_s[1]));
    }
}

/// A BLEND quad with a sheen through lit transparency, shaded in compute
/// under Auto (the fragment records keep the sheen): every inner pixel's
/// colour against the same reference as the opaque surface.
#[test]
fn lit_transparency_draws_the_sheen() {
    let renderer = test_renderer();
    let scene =
        load_gltf_slice(&model(blended(opaque_material()), SHEEN_EXT, &[]), None).expect("loads");
    assert!(scene.warnings.is_empty(), "{:?}", scene.warnings);
    let (pass, out) = lit_blend_scene(
        &renderer,
        &scene,
        TransparencyShading::Auto,
        LightLoop::Auto,
        LightBuffer::suns(&renderer, &[SUN]),
    );
    assert!(pass.shades_in_compute(), "a sheen layer shades in compute");
    let pixels = out.pixels;
    assert!(
        compiled_with(&renderer, "SHEEN") >= 2,
        "the record's and the shade's"
    );
    let mut checked = 0;
    for (i, p, _, _) in inner_pixels() {
        let (want_d, want_s) = sheened_reference(p, (SHEEN_COLOR, SHEEN_ROUGHNESS));
        let want = want_d + want_s;
        for c in 0..3 {
            // Half-float accumulation: about three decimal digits.
            assert!(
                (pixels[i][c] - want[c]).abs() <= 2e-3 + 1e-2 * want[c],
                "pixel {i}: {:?}, the reference says {want}",
                pixels[i]
            );
        }
        checked += 1;
    }
    assert!(checked > 600, "{checked} pixels checked");
}

/// The stripe environment of [`anisotropic_reflection_follows_the_bent_normal`]:
/// radiance 4 where 0.1 < d.x < 0.2 (a band of directions towards +x),
/// 0.25 elsewhere.
fn stripe_radiance(d: Vec3) -> f32 {
    if d.x > STRIPE[0] && d.x < STRIPE[1] {
        4.0
    } else {
        0.25
    }
}

/// The band's edges in d.x.
const STRIPE: [f32; 2] = [0.1, 0.2];

/// Reflection's specular of `model` (its materials given the Reflection
/// feature) in an environment of [`stripe_radiance`], and whether the
/// frame compiled Reflection's ANISOTROPY.
fn reflected_stripe(renderer: &Renderer, model: &[u8]) -> (ImageF32, bool) {
    use common::world_and_layer_of;
    use spreadlight_render::environment::{
        Environment, EnvironmentQuality, EnvironmentSource, EquirectImage, Reflection,
        ReflectionMode,
    };
    use spreadlight_render::material::Feature;
    // Fine enough (0.006 rad a texel) that the band's edges lie where
    // `stripe_radiance` puts them, within the cube's texel.
    let (width, height) = (1024u32, 512u32);
    // Texel (x, y)'s direction: the inverse of `reference::reflection::equirect_uv`.
    let pixels = (0..height)
        .flat_map(|y| {
            (0..width).map(move |x| {
                let phi = ((x as f32 + 0.5) / width as f32 - 0.5) * std::f32::consts::TAU;
                let theta = (y as f32 + 0.5) / height as f32 * std::f32::consts::PI;
                let d = Vec3::new(
                    theta.sin() * phi.sin(),
                    theta.cos(),
                    -theta.sin() * phi.cos(),
                );
                let l = stripe_radiance(d);
                [l, l, l, 1.0]
            })
        })
        .collect();
    let environment = Environment::new(
        renderer,
        None,
        EnvironmentSource::Equirect(Arc::new(EquirectImage {
            width,
            height,
            pixels,
        })),
        EnvironmentQuality {
            cube_size: 128,
            samples: 8,
        },
    );
    let scene = load_gltf_slice(model, None).expect("loads");
    assert!(scene.warnings.is_empty(), "{:?}", scene.warnings);
    let reflective = |m: spreadlight_render::material::Material| {
        m.with(Feature::Reflection, &[[1.0, 0.0, 0.0, 0.0]])
            .expect("valid")
    };
    let (world, layer) = world_and_layer_of(
        renderer,
        &scene,
        Mat4::IDENTITY,
        scene.materials[0].base_color,
        reflective,
    );
    let g = GBuffer::new(
        renderer,
        None,
        vec![layer],
        VIEW.camera(),
        None,
        SizeRule::Relative(1.0),
    );
    let r = Reflection::new(
        renderer,
        None,
        g,
        world,
        environment,
        ReflectionMode::Reflect,
    );
    let (report, images) =
        render_and_read(renderer, r.as_ref(), SIZE, &[&r.specular]).expect("renders");
    assert!(report.errors.is_empty(), "{:?}", report.errors);
    let image = images.into_iter().next().expect("specular");
    assert!(image.all_finite(), "no NaN or infinity");
    let anisotropic = renderer
        .shaders()
        .compiled_keys()
        .any(|k| k.path() == "environment/reflection.wgsl" && k.features.contains("ANISOTROPY"));
    (image, anisotropic)
}

/// Image-based anisotropy: a mirror metal quad (roughness 0) whose
/// anisotropyTexture points along the tangent (+x) at strength 1 on the
/// left half and along the bitangent (+y) at strength 0.5 on the right, in
/// an environment with a bright band of directions towards +x
/// ([`stripe_radiance`]). Reflection reads the environment along the
/// reflection about the bent normal (the view projected onto the plane of
/// the normal and the direction, mixed with the normal by
/// (1 - strength (1 - roughness))^4): along the tangent the reflection
/// keeps the view's x where a mirror flips it, so the band, which the plain
/// mirror shows on the right half only, shows on the left half too; along
/// the bitangent the x flip stays and the band stays on the right. Every
/// inner pixel whose reflected direction lies clear of the band's edges
/// (0.025 in d.x: two cube texels of the 128 cube) against the CPU's band radiance along
/// that direction times Schlick's Fresnel of the albedo at N.V (the split
/// sum at roughness 0) within 0.03 + 5%, as the mirror floor test. The
/// plain file compiles no ANISOTROPY in Reflection.
#[test]
fn anisotropic_reflection_follows_the_bent_normal() {
    let renderer = test_renderer();
    let (plain, compiled) = reflected_stripe(&renderer, &model(metal_material(0.0), "{}", &[]));
    assert!(!compiled, "no anisotropy, no ANISOTROPY in Reflection");
    let map = halves([255, 128, 255, 255], [128, 255, 128, 255], false);
    let ext = r#"{"KHR_materials_anisotropy": {"anisotropyStrength": 1.0,
        "anisotropyTexture": {"index": {0}}}}"#;
    let (image, compiled) = reflected_stripe(&renderer, &model(metal_material(0.0), ext, &[map]));
    assert!(compiled, "Reflection's ANISOTROPY");
    let texels = [[255u8, 128, 255], [128, 255, 128]];
    let eye = Vec3::Z * DISTANCE;
    let fresnel = |n_dot_v: f32| {
        Vec3::from(ALBEDO) + (Vec3::ONE - Vec3::from(ALBEDO)) * (1.0 - n_dot_v).powi(5)
    };
    let (mut checked, mut band, mut plain_band) = ([0; 2], [0; 2], [0; 2]);
    for (i, p, u, _) in inner_pixels() {
        let [r, g, b] = texels[u].map(|c| c as f32 / 255.0);
        let v = (eye - p).normalize();
        let t = anisotropy_tangent(
            Vec3::Z,
            Vec3::X,
            Vec3::Y,
            anisotropy_direction(0.0, Some([r, g])),
        )
        .expect("a direction");
        let bent = anisotropic_bent_normal(Vec3::Z, v, t, 0.0, b);
        let reflected = (2.0 * v.dot(bent) * bent - v).normalize();
        let mirrored = Vec3::new(-v.x, -v.y, v.z);
        let clear = |d: Vec3| STRIPE.iter().all(|edge| (d.x - edge).abs() > 0.025);
        if clear(mirrored) && stripe_radiance(mirrored) > 1.0 {
            plain_band[u] += 1;
            assert!(
                plain.pixels[i][0] > 1.0,
                "pixel {i}: the mirror shows the band"
            );
        }
        if u == 0 {
            assert!(
                plain.pixels[i][0] < 1.0,
                "pixel {i}: the mirror shows no band on the left"
            );
        }
        if !clear(reflected) {
            continue;
        }
        let want = stripe_radiance(reflected) * fresnel(v.z);
        let got = image.pixels[i];
        for c in 0..3 {
            assert!(
                (got[c] - want[c]).abs() < 0.03 + 0.05 * want[c],
                "pixel {i} (half {u}): {got:?}, the reference says {want} (along {reflected})"
            );
        }
        checked[u] += 1;
        band[u] += usize::from(stripe_radiance(reflected) > 1.0);
    }
    assert!(checked[0] > 250 && checked[1] > 250, "{checked:?}");
    assert!(plain_band[1] > 40, "{plain_band:?}");
    assert!(
        band[0] > 40 && band[1] > 40,
        "the band on both halves: {band:?}"
    );
}

/// KHR_materials_sheen's maps through the G-buffer's sheen and film
/// target into CookTorrance (SHEEN): a sheenColorTexture whose left half is
/// white and right half magenta (no green) and a sheenRoughnessTexture whose
/// top half has alpha 1 and bottom half 128/255; every inner pixel of each
/// quadrant against `spreadlight_reference::sheen` with the factors times
/// that quadrant's texels. A file whose sheen has factors alone writes no
/// such target; no warning says a map is not sampled.
#[test]
fn the_sheen_maps_colour_each_half_as_the_reference_says() {
    let renderer = test_renderer();
    let (_, factors_s) = lit(&renderer, &model(opaque_material(), SHEEN_EXT, &[]));
    assert_eq!(
        compiled_with(&renderer, "SHEEN_FILM"),
        0,
        "factors alone: no sheen and film target"
    );
    let written = |renderer: &Renderer| {
        renderer
            .last_report()
            .counters
            .get("G-buffer sheen and film targets written")
            .copied()
    };
    assert_eq!(written(&renderer), None, "stats show no target");
    let ext = r#"{"KHR_materials_sheen": {"sheenColorFactor": [0.9, 0.5, 0.7],
        "sheenRoughnessFactor": 0.6, "sheenColorTexture": {"index": {0}},
        "sheenRoughnessTexture": {"index": {1}}}}"#;
    let colour = halves([255, 255, 255, 255], [255, 0, 255, 255], false);
    let roughness = halves([0, 0, 0, 255], [0, 0, 0, 128], true);
    let (d, s) = lit(
        &renderer,
        &model(opaque_material(), ext, &[colour, roughness]),
    );
    assert!(
        compiled_with(&renderer, "SHEEN_FILM") >= 1,
        "the resolve wrote the target"
    );
    assert_eq!(written(&renderer), Some(1), "stats show the target");
    let mut checked = [0; 4];
    for (i, p, column, row) in inner_pixels() {
        let green = [SHEEN_COLOR[1], 0.0][column];
        let colour = [SHEEN_COLOR[0], green, SHEEN_COLOR[2]];
        let roughness = SHEEN_ROUGHNESS * [1.0, 128.0 / 255.0][row];
        let (want_d, want_s) = sheened_reference(p, (colour, roughness));
        for c in 0..3 {
            assert!(
                close(d.pixels[i][c], want_d[c]) && close(s.pixels[i][c], want_s[c]),
                "pixel {i} (column {column}, row {row}): diffuse {:?} specular {:?}, the reference says {want_d} {want_s}",
                d.pixels[i],
                s.pixels[i]
            );
        }
        checked[column + 2 * row] += 1;
    }
    assert!(
        checked.iter().all(|&n| n > 150),
        "{checked:?} pixels per quadrant"
    );
    // The map changes what the factors alone draw: the right half's sheen
    // has no green (less green specular), the left half's is the factors'.
    let at = |px: u32, py: u32| (py * SIZE.0 + px) as usize;
    let (left, right) = (at(SIZE.0 / 4, SIZE.1 / 4), at(3 * SIZE.0 / 4, SIZE.1 / 4));
    assert!(s.pixels[right][1] < factors_s.pixels[right][1]);
    assert!(close(s.pixels[left][1], factors_s.pixels[left][1]));
}

/// KHR_materials_iridescence's maps through the sheen and film target into
/// CookTorrance (IRIDESCENCE): an iridescenceTexture whose left half is red
/// 1 and right half 128/255 (the factor) and an iridescenceThicknessTexture
/// whose top half is green 0 (the minimum, 250 nm) and bottom half 1 (the
/// maximum, 650 nm); every inner pixel of each quadrant against
/// `cook_torrance_iridescent` with that film. A film of a minimum above its
/// maximum and an extreme thickness stay finite under maps.
#[test]
fn the_iridescence_maps_set_the_film_per_half_as_the_reference_says() {
    let renderer = test_renderer();
    let ext = r#"{"KHR_materials_iridescence": {"iridescenceFactor": 1.0,
        "iridescenceThicknessMinimum": 250, "iridescenceThicknessMaximum": 650,
        "iridescenceTexture": {"index": {0}}, "iridescenceThicknessTexture": {"index": {1}}}}"#;
    let factor = halves([255, 0, 0, 255], [128, 0, 0, 255], false);
    let thickness = halves([0, 0, 0, 255], [0, 255, 0, 255], true);
    let (d, s) = lit(
        &renderer,
        &model(opaque_material(), ext, &[factor.clone(), thickness.clone()]),
    );
    assert!(
        compiled_with(&renderer, "SHEEN_FILM") >= 1,
        "the resolve wrote the target"
    );
    let l = -SUN.direction.normalize();
    let radiance = SUN.color * SUN.illuminance;
    let eye = Vec3::Z * DISTANCE;
    let mut checked = [0; 4];
    for (i, p, column, row) in inner_pixels() {
        let film = Film::new([1.0, 128.0 / 255.0][column], 1.3, [250.0, 650.0][row]);
        let view = (eye - p).normalize();
        let want = cook_torrance_iridescent(
            Vec3::Z,
            view,
            l,
            ALBEDO.into(),
            ROUGHNESS,
            0.0,
            0.04,
            film,
            true,
        );
        let (want_d, want_s) = (want.diffuse * radiance, want.specular * radiance);
        for c in 0..3 {
            assert!(
                close(d.pixels[i][c], want_d[c]) && close(s.pixels[i][c], want_s[c]),
                "pixel {i} (column {column}, row {row}): diffuse {:?} specular {:?}, the reference says {want_d} {want_s}",
                d.pixels[i],
                s.pixels[i]
            );
        }
        checked[column + 2 * row] += 1;
    }
    assert!(
        checked.iter().all(|&n| n > 150),
        "{checked:?} pixels per quadrant"
    );
    // The two thicknesses colour the highlight differently.
    let at = |px: u32, py: u32| (py * SIZE.0 + px) as usize;
    let (top, bottom) = (at(SIZE.0 / 4, SIZE.1 / 4), at(SIZE.0 / 4, 3 * SIZE.1 / 4));
    let hue = |p: [f32; 4]| p[1] / p[0].max(1e-6);
    assert!((hue(s.pixels[top]) - hue(s.pixels[bottom])).abs() > 0.05);
    // Hard films under maps: a minimum above the maximum (warned, kept),
    // a thickness of 1e30 nm; every pixel finite (`render_and_read` below).
    for hard in [
        r#"{"KHR_materials_iridescence": {"iridescenceFactor": 1, "iridescenceThicknessMinimum": 900,
            "iridescenceThicknessMaximum": 0, "iridescenceTexture": {"index": {0}},
            "iridescenceThicknessTexture": {"index": {1}}}}"#,
        r#"{"KHR_materials_iridescence": {"iridescenceFactor": 1, "iridescenceThicknessMaximum": 1e30,
            "iridescenceThicknessTexture": {"index": {1}}, "iridescenceTexture": {"index": {0}}}}"#,
    ] {
        let file = model(
            opaque_material(),
            hard,
            &[factor.clone(), thickness.clone()],
        );
        let scene = load_gltf_slice(&file, None).expect("loads");
        lit_scene(&renderer, &scene, hard);
    }
}

/// A BLEND quad with a thin film through lit transparency's forward light
/// pass (compiled under SHEEN, the switch of its extension lobes; a node
/// with an iridescent layer shades forward under Auto), its factor and thickness from maps in four quadrants as in
/// `the_iridescence_maps_set_the_film_per_half_as_the_reference_says`:
/// every inner pixel's colour against `cook_torrance_iridescent`, as the
/// opaque surface's. A soap bubble is such a layer.
#[test]
fn lit_transparency_draws_the_film() {
    let renderer = test_renderer();
    let mut material = opaque_material();
    material.alpha_mode = json::validation::Checked::Valid(json::material::AlphaMode::Blend);
    let ext = r#"{"KHR_materials_iridescence": {"iridescenceFactor": 1.0,
        "iridescenceThicknessMinimum": 250, "iridescenceThicknessMaximum": 650,
        "iridescenceTexture": {"index": {0}}, "iridescenceThicknessTexture": {"index": {1}}}}"#;
    let factor = halves([255, 0, 0, 255], [128, 0, 0, 255], false);
    let thickness = halves([0, 0, 0, 255], [0, 255, 0, 255], true);
    let scene = load_gltf_slice(&model(material, ext, &[factor, thickness]), None).expect("loads");
    assert!(scene.warnings.is_empty(), "{:?}", scene.warnings);
    // The node's default shading and light loop.
    let defaults = TransparencySettings::default();
    let pass = blend_node(
        &renderer,
        &scene,
        defaults.shading,
        defaults.light_loop,
        LightBuffer::suns(&renderer, &[SUN]),
    );
    assert!(
        !pass.shades_in_compute(),
        "an iridescent layer shades forward"
    );
    let pixels = render(&renderer, pass.as_ref(), &pass.output, SIZE)
        .1
        .pixels;
    assert!(
        renderer
            .shaders()
            .compiled_keys()
            .any(|k| k.path() == "post/transparency.wgsl" && k.features.contains("SHEEN")),
        "the light pass compiled the film (under SHEEN)"
    );
    let l = -SUN.direction.normalize();
    let radiance = SUN.color * SUN.illuminance;
    let eye = Vec3::Z * DISTANCE;
    let mut checked = [0; 4];
    for (i, p, column, row) in inner_pixels() {
        let film = Film::new([1.0, 128.0 / 255.0][column], 1.3, [250.0, 650.0][row]);
        let view = (eye - p).normalize();
        let brdf = cook_torrance_iridescent(
            Vec3::Z,
            view,
            l,
            ALBEDO.into(),
            ROUGHNESS,
            0.0,
            0.04,
            film,
            true,
        );
        let want = (brdf.diffuse + brdf.specular) * radiance;
        for c in 0..3 {
            // Half-float accumulation: about three decimal digits.
            assert!(
                (pixels[i][c] - want[c]).abs() <= 2e-3 + 1e-2 * want[c],
                "pixel {i} (column {column}, row {row}): {:?}, the reference says {want}",
                pixels[i]
            );
        }
        checked[column + 2 * row] += 1;
    }
    assert!(
        checked.iter().all(|&n| n > 150),
        "{checked:?} pixels per quadrant"
    );
}

/// Reflection's sheen term (SHEEN) under a uniform environment of `model`'s
/// quad, its material made reflective: the specular and diffuse outputs.
fn reflected(renderer: &Renderer, model: &[u8]) -> (ImageF32, ImageF32) {
    use spreadlight_render::environment::{
        Environment, EnvironmentQuality, EnvironmentSource, EquirectImage, Reflection,
        ReflectionMode,
    };
    use spreadlight_render::material::Feature;
    let scene = load_gltf_slice(model, None).expect("loads");
    assert!(scene.warnings.is_empty(), "{:?}", scene.warnings);
    let (world, layer) = common::world_and_layer_of(
        renderer,
        &scene,
        Mat4::IDENTITY,
        scene.materials[0].base_color,
        |m| {
            m.with(Feature::Reflection, &[[1.0, 0.0, 0.0, 0.0]])
                .expect("valid")
        },
    );
    let g = GBuffer::new(
        renderer,
        None,
        vec![layer],
        VIEW.camera(),
        None,
        SizeRule::Relative(1.0),
    );
    let image = Arc::new(EquirectImage {
        width: 16,
        height: 8,
        pixels: vec![[0.5, 0.5, 0.5, 1.0]; 16 * 8],
    });
    let environment = Environment::new(
        renderer,
        None,
        EnvironmentSource::Equirect(image),
        EnvironmentQuality {
            cube_size: 16,
            samples: 16,
        },
    );
    let r = Reflection::new(
        renderer,
        None,
        g,
        world,
        environment,
        ReflectionMode::Reflect,
    );
    let (report, images) =
        render_and_read(renderer, r.as_ref(), SIZE, &[&r.specular, &r.diffuse]).expect("renders");
    assert!(report.errors.is_empty(), "{:?}", report.errors);
    let [s, d]: [ImageF32; 2] = images.try_into().unwrap_or_else(|_| unreachable!());
    assert!(s.all_finite() && d.all_finite(), "no NaN or infinity");
    (s, d)
}

/// Reflection reads the sheen and film target too: the quad of
/// `the_sheen_maps_colour_each_half_as_the_reference_says`, reflective
/// under a uniform environment, gives each quadrant's pixels what a quad
/// whose sheen factors are that quadrant's colour and roughness gives
/// (the sheen's environment light and the base's dimming, specular and
/// diffuse; unorm16 in the target), and the quadrants differ.
#[test]
fn reflection_lights_the_sheen_maps_per_pixel() {
    let renderer = test_renderer();
    let ext = r#"{"KHR_materials_sheen": {"sheenColorFactor": [0.9, 0.5, 0.7],
        "sheenRoughnessFactor": 0.6, "sheenColorTexture": {"index": {0}},
        "sheenRoughnessTexture": {"index": {1}}}}"#;
    let colour = halves([255, 255, 255, 255], [255, 0, 255, 255], false);
    let roughness = halves([0, 0, 0, 255], [0, 0, 0, 128], true);
    let (s, d) = reflected(
        &renderer,
        &model(opaque_material(), ext, &[colour, roughness]),
    );
    assert!(
        compiled_with(&renderer, "SHEEN_FILM") >= 1,
        "the resolve wrote the target"
    );
    let mut quadrants = Vec::new();
    for row in 0..2 {
        for column in 0..2 {
            let green = [SHEEN_COLOR[1], 0.0][column];
            let roughness = SHEEN_ROUGHNESS * [1.0, 128.0 / 255.0][row];
            let factors = format!(
                r#"{{"KHR_materials_sheen": {{"sheenColorFactor": [0.9, {green}, 0.7],
                    "sheenRoughnessFactor": {roughness}}}}}"#
            );
            quadrants.push(reflected(
                &renderer,
                &model(opaque_material(), &factors, &[]),
            ));
        }
    }
    let mut checked = [0; 4];
    for (i, _, column, row) in inner_pixels() {
        let (want_s, want_d) = &quadrants[column + 2 * row];
        for c in 0..3 {
            assert!(
                close(s.pixels[i][c], want_s.pixels[i][c])
                    && close(d.pixels[i][c], want_d.pixels[i][c]),
                "pixel {i} (column {column}, row {row}): specular {:?} diffuse {:?}, its factors give {:?} {:?}",
                s.pixels[i],
                d.pixels[i],
                want_s.pixels[i],
                want_d.pixels[i]
            );
        }
        checked[column + 2 * row] += 1;
    }
    assert!(
        checked.iter().all(|&n| n > 150),
        "{checked:?} pixels per quadrant"
    );
    // The map matters: its magenta half reflects less green than the
    // factors' colour alone would there.
    let right = (SIZE.1 / 4 * SIZE.0 + 3 * SIZE.0 / 4) as usize;
    assert!(s.pixels[right][1] < quadrants[0].0.pixels[right][1]);
}
