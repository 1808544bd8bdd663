//! glTF BLEND materials through Transparency: a generated quad whose base
//! colour texture has two halves of different colour and alpha, with vertex
//! colours (COLOR_0, alpha too) running from left to right and a base
//! colour factor with alpha, composited over a green background. Every
//! inner pixel is checked against glTF's colour and coverage:
//! c = factor x texel x COLOR_0, a = the three alphas' product, and the
//! result background x (1 - a) + c x a. Turned away, the quad shows only
//! when its material is double-sided. A second frame binds the material
//! world's groups made in the first.

// The post tests' scene helpers, shared with the renderer's tests.
use crate::post_common;
// The glTF tests' quad view and layer.
use crate::common;

use std::sync::Arc;

use common::{QuadView, transparency_over};
use glam::{Mat4, Vec3};
use gltf_json as json;
use post_common::*;
use spreadlight_gltf::builder::{Doc, info, png, quad};
use spreadlight_gltf::{AlphaMode, load_gltf_slice};
use spreadlight_render::Renderer;
use spreadlight_render::frame_graph::FrameReport;
use spreadlight_render::gbuffer::GBuffer;
use spreadlight_render::mesh::MeshData;
use spreadlight_render::post::{Transparency, TransparencySettings};
use spreadlight_render::renderer::test_renderer;

const SIZE: (u32, u32) = (64, 64);
const DISTANCE: f32 = 3.0;
const FOV_Y: f32 = 0.8;
const VIEW: QuadView = QuadView {
    size: SIZE,
    distance: DISTANCE,
    fov_y: FOV_Y,
};
const BACKGROUND: [f32; 4] = [0.0, 1.0, 0.0, 1.0];
/// The texture's left and right halves (linear RGB, alpha); 0 and 255
/// decode exactly, and alpha is stored linear.
const HALVES: [[f32; 4]; 2] = [[1.0, 0.0, 1.0, 1.0], [1.0, 1.0, 1.0, 0.6]];
/// COLOR_0 at the quad's left (x = -1) and right (x = +1) edges.
const LEFT: [f32; 4] = [1.0, 0.5, 0.25, 1.0];
const RIGHT: [f32; 4] = [0.25, 0.5, 1.0, 0.5];
/// The material's base colour factor.
const FACTOR: [f32; 4] = [1.0, 1.0, 0.5, 0.8];

fn halves_png() -> Vec<u8> {
    let image = image::RgbaImage::from_fn(16, 16, |x, _| {
        let h = HALVES[usize::from(x >= 8)];
        image::Rgba(h.map(|c| (c * 255.0).round() as u8))
    });
    png(&image)
}

/// The quad x, y in [-1, 1] at z = 0, facing +Z. `tex_coord`: which UV set
/// maps the texture across the quad (the other is one point of its left half).
fn model(tex_coord: u32, double_sided: bool) -> Vec<u8> {
    let mut doc = Doc::new();
    let spanning = vec![[0.0, 1.0], [1.0, 1.0], [1.0, 0.0], [0.0, 0.0]];
    let constant = vec![[0.25, 0.5]; 4];
    let (uvs, uvs1) = if tex_coord == 1 {
        (constant, spanning)
    } else {
        (spanning, constant)
    };
    let quad = MeshData {
        uvs: Some(uvs),
        uvs1: Some(uvs1),
        colors: Some(vec![LEFT, RIGHT, RIGHT, LEFT]),
        ..quad()
    };
    let mesh = doc.mesh_data("Quad", &quad);
    let texture = doc.nearest_texture(&halves_png());
    let mut material = json::Material::default();
    material.pbr_metallic_roughness.base_color_factor = json::material::PbrBaseColorFactor(FACTOR);
    material.pbr_metallic_roughness.base_color_texture = Some(json::texture::Info {
        tex_coord,
        ..info(texture)
    });
    material.alpha_mode = json::validation::Checked::Valid(json::material::AlphaMode::Blend);
    material.double_sided = double_sided;
    let material = doc.material(material);
    doc.mesh_scene(mesh, material);
    doc.gltf_data_uri()
}

/// The quad placed by `transform`, composited over the background, unlit
/// (ambient 1, no key light).
fn composite(model: &[u8], transform: Mat4) -> Vec<[f32; 4]> {
    let renderer = test_renderer();
    let (_, pass) = scene(&renderer, model, transform);
    render(&renderer, pass.as_ref(), &pass.output, SIZE)
        .1
        .pixels
}

/// [`composite`]'s recipe, and the G-buffer under it.
fn scene(renderer: &Renderer, model: &[u8], transform: Mat4) -> (Arc<GBuffer>, Arc<Transparency>) {
    let scene = load_gltf_slice(model, None).expect("loads");
    assert_eq!(scene.materials[0].alpha_mode, AlphaMode::Blend);
    assert!(scene.warnings.is_empty(), "{:?}", scene.warnings);
    let background = image(renderer, SIZE, |_, _| BACKGROUND);
    let settings = TransparencySettings {
        ambient: Vec3::ONE,
        light_color: Vec3::ZERO,
        ..Default::default()
    };
    transparency_over(
        renderer,
        &VIEW,
        &scene,
        transform,
        background.texture_ref(),
        settings,
    )
}

fn check(tex_coord: u32) {
    let pixels = composite(&model(tex_coord, false), Mat4::IDENTITY);
    let mut checked = [0; 2];
    for py in 0..SIZE.1 {
        for px in 0..SIZE.0 {
            let (x, y) = VIEW.hit(px, py);
            let got = pixels[(py * SIZE.0 + px) as usize];
            if x.abs() > 1.03 || y.abs() > 1.03 {
                assert_eq!(got[..3], BACKGROUND[..3], "pixel ({px}, {py}) off the quad");
                continue;
            }
            let t = (x + 1.0) / 2.0;
            // Well inside a half of the texture, and of the quad.
            if x.abs() > 0.95 || y.abs() > 0.95 || (t - 0.5).abs() < 0.04 {
                continue;
            }
            let half = usize::from(t >= 0.5);
            let vertex = |c: usize| LEFT[c] + (RIGHT[c] - LEFT[c]) * t;
            let base = |c: usize| FACTOR[c] * HALVES[half][c] * vertex(c);
            let alpha = base(3);
            for c in 0..3 {
                let want = BACKGROUND[c] * (1.0 - alpha) + base(c) * alpha;
                assert!(
                    (got[c] - want).abs() < 0.01,
                    "pixel ({px}, {py}), channel {c}: {} instead of {want} (half {half}, t {t}, alpha {alpha})",
                    got[c]
                );
            }
            checked[half] += 1;
        }
    }
    assert!(checked[0] > 600 && checked[1] > 600, "{checked:?}");
}

#[test]
fn blend_composites_factor_times_texture_times_color_0_with_their_alphas() {
    check(0);
}

#[test]
fn blend_reads_the_texture_through_its_second_uv_set() {
    check(1);
}

#[test]
fn blend_culls_back_faces_unless_double_sided() {
    let turned = Mat4::from_rotation_y(std::f32::consts::PI);
    let differing = |pixels: &[[f32; 4]]| {
        pixels
            .iter()
            .filter(|p| (0..3).any(|c| (p[c] - BACKGROUND[c]).abs() > 0.05))
            .count()
    };
    let one_sided = composite(&model(0, false), turned);
    assert_eq!(
        differing(&one_sided),
        0,
        "a one-sided quad's back is culled"
    );
    let double_sided = composite(&model(0, true), turned);
    assert!(
        differing(&double_sided) > 1500,
        "a double-sided quad's back shows: {} pixels",
        differing(&double_sided)
    );
}

#[test]
fn blend_binds_the_material_groups_it_made_before() {
    let renderer = test_renderer();
    let (g, pass) = scene(&renderer, &model(0, false), Mat4::IDENTITY);
    // The G-buffer's frame alone, twice: the groups its own passes make and reuse.
    render(&renderer, g.as_ref(), &g.targets.depth, SIZE);
    let (opaque, _) = render(&renderer, g.as_ref(), &g.targets.depth, SIZE);
    let mut first = None;
    for frame in 0..2 {
        let (report, out) = render(&renderer, pass.as_ref(), &pass.output, SIZE);
        if frame > 0 {
            // The accumulation binds the camera, the mesh arena, the
            // material world's buffers and its maps' arrays by name,
            // through the cache: the same resources are the same groups.
            let counter = |r: &FrameReport, name| r.counter(name);
            assert_eq!(
                counter(&report, "bind groups created"),
                counter(&opaque, "bind groups created"),
                "{:?}",
                report.counters
            );
            // Beyond the G-buffer's: the accumulation's groups 0 to 3, the
            // targets' clear's and the resolve's.
            assert_eq!(
                counter(&report, "bind groups reused") - counter(&opaque, "bind groups reused"),
                6,
                "{:?}",
                report.counters
            );
        }
        match &first {
            None => first = Some(out),
            Some(image) => assert!(image.pixels == out.pixels, "the same image"),
        }
    }
}

/// A quad like [`model`]'s (one UV set, no COLOR_0) whose material is
/// transmissive through a map (halves: red 0 | 255) and emits with a
/// strength: `KHR_materials_transmission` and
/// `KHR_materials_emissive_strength` as lit transparency draws them.
fn transmissive_model() -> Vec<u8> {
    let mut doc = Doc::new();
    let mesh = doc.mesh_data("Quad", &quad());
    let halves = image::RgbaImage::from_fn(16, 16, |x, _| {
        image::Rgba(if x >= 8 {
            [255, 0, 0, 255]
        } else {
            [0, 0, 0, 255]
        })
    });
    let texture = doc.nearest_texture(&png(&halves));
    let mut material = json::Material::default();
    material.pbr_metallic_roughness.base_color_factor =
        json::material::PbrBaseColorFactor([0.25, 0.25, 0.25, 1.0]);
    material.emissive_factor = json::material::EmissiveFactor([0.5, 0.25, 0.0]);
    let extensions = format!(
        r#"{{"KHR_materials_transmission": {{"transmissionFactor": 0.8,
            "transmissionTexture": {{"index": {}}}}},
          "KHR_materials_emissive_strength": {{"emissiveStrength": 2.0}}}}"#,
        texture.value()
    );
    let others: json::extensions::material::Material =
        json::deserialize::from_str(&extensions).expect("the test's extension objects");
    material.extensions = Some(others);
    for name in [
        "KHR_materials_transmission",
        "KHR_materials_emissive_strength",
    ] {
        doc.root.extensions_used.push(name.into());
    }
    let material = doc.material(material);
    doc.mesh_scene(mesh, material);
    doc.gltf_data_uri()
}

#[test]
fn transmission_maps_and_emissive_strength_reach_lit_transparency() {
    let renderer = test_renderer();
    let scene = load_gltf_slice(&transmissive_model(), None).expect("loads");
    let material = &scene.materials[0];
    assert_eq!(material.alpha_mode, AlphaMode::Blend);
    assert_eq!(material.emissive_strength, 2.0);
    let background = image(&renderer, SIZE, |_, _| BACKGROUND);
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
    // Unlit by lights (ambient 1): base 0.25 plus emission (0.5, 0.25, 0)
    // x strength 2. Left: no transmission, opaque. Right: transmission
    // 0.8 x 1, opacity 0.2 (baked alpha 51 / 255): the diffuse base scaled
    // by the opacity, the emission whole, and what shows through (0.8)
    // refracted (thin-walled: no shift) and tinted by the base colour, over
    // the green background.
    let (base, emission) = (0.25, [1.0, 0.5, 0.0]);
    let mut checked = [0; 2];
    for py in 0..SIZE.1 {
        for px in 0..SIZE.0 {
            let (x, y) = VIEW.hit(px, py);
            let t = (x + 1.0) / 2.0;
            if x.abs() > 0.95 || y.abs() > 0.95 || (t - 0.5).abs() < 0.04 {
                continue;
            }
            let half = usize::from(t >= 0.5);
            let alpha = [1.0, 0.2][half];
            let got = pixels[(py * SIZE.0 + px) as usize];
            for c in 0..3 {
                let want = base * alpha + emission[c] + (1.0 - alpha) * base * BACKGROUND[c];
                assert!(
                    got[c].is_finite() && (got[c] - want).abs() < 0.01,
                    "pixel ({px}, {py}), channel {c}: {} instead of {want} (half {half})",
                    got[c]
                );
            }
            checked[half] += 1;
        }
    }
    assert!(checked[0] > 600 && checked[1] > 600, "{checked:?}");
}
