//! glTF's second UV set (TEXCOORD_1) and vertex colours (COLOR_0) through
//! the G-buffer, on both rasterizers: a generated quad whose base colour
//! texture is mapped by TEXCOORD_1 (TEXCOORD_0 is one constant point of
//! the texture, so a map read through the wrong set shows one colour) and
//! whose vertex colours run as a gradient from left to right. Each albedo
//! pixel is checked against the value predicted from the camera ray:
//! base colour factor x texel at TEXCOORD_1 x interpolated COLOR_0.

// The glTF tests' quad view and layer.
use crate::common;

use common::{QuadView, world_and_layer};
use glam::Mat4;
use gltf_json as json;
use spreadlight_gltf::builder::{Doc, QUAD_UVS, info, png, quad};
use spreadlight_gltf::load_gltf_slice;
use spreadlight_render::SizeRule;
use spreadlight_render::gbuffer::{GBuffer, RasterChoice, RasterMode};
use spreadlight_render::mesh::MeshData;
use spreadlight_render::readback::render_and_read;
use spreadlight_render::renderer::test_renderer;

const SIZE: (u32, u32) = (64, 64);
/// The camera: on +Z at this distance, looking at the quad's centre.
const DISTANCE: f32 = 3.0;
const FOV_Y: f32 = 0.8;
const VIEW: QuadView = QuadView {
    size: SIZE,
    distance: DISTANCE,
    fov_y: FOV_Y,
};
/// COLOR_0 at the quad's left (x = -1) and right (x = +1) edges.
const LEFT: [f32; 4] = [1.0, 0.5, 0.25, 1.0];
const RIGHT: [f32; 4] = [0.25, 0.5, 1.0, 1.0];
/// The texture's quadrants (top-left, top-right, bottom-left, bottom-right), linear.
const QUADRANTS: [[f32; 3]; 4] = [
    [1.0, 0.0, 0.0],
    [0.0, 1.0, 0.0],
    [0.0, 0.0, 1.0],
    [1.0, 1.0, 1.0],
];

/// 16 x 16 (a size class of its own, so it is uploaded unresized), one
/// colour per 8 x 8 quadrant; 0 and 255 decode to exactly 0 and 1 in sRGB.
fn quadrants_png() -> Vec<u8> {
    let image = image::RgbaImage::from_fn(16, 16, |x, y| {
        let q = QUADRANTS[(usize::from(y >= 8) * 2) + usize::from(x >= 8)];
        image::Rgba([
            (q[0] * 255.0) as u8,
            (q[1] * 255.0) as u8,
            (q[2] * 255.0) as u8,
            255,
        ])
    });
    png(&image)
}

/// The quad x, y in [-1, 1] at z = 0, facing +Z: TEXCOORD_0 constant in
/// the white quadrant, TEXCOORD_1 spanning the texture, COLOR_0 from LEFT
/// to RIGHT. `alpha`: COLOR_0's alpha from 0 (left) to 1 (right) and a
/// MASK material with cutoff 0.5.
fn model(with_colors: bool, alpha: bool) -> Vec<u8> {
    let mut doc = Doc::new();
    let (left, right) = if alpha {
        ([1.0, 1.0, 1.0, 0.0], [1.0; 4])
    } else {
        (LEFT, RIGHT)
    };
    let quad = MeshData {
        uvs: Some(vec![[0.75, 0.75]; 4]),
        uvs1: Some(QUAD_UVS.to_vec()),
        colors: with_colors.then(|| vec![left, right, right, left]),
        ..quad()
    };
    let mesh = doc.mesh_data("Quad", &quad);
    // NEAREST magnification: the quadrants stay sharp when magnified.
    let texture = doc.nearest_texture(&quadrants_png());
    let mut material = json::Material::default();
    material.pbr_metallic_roughness.base_color_texture = Some(json::texture::Info {
        tex_coord: 1,
        ..info(texture)
    });
    if alpha {
        material.alpha_mode = json::validation::Checked::Valid(json::material::AlphaMode::Mask);
        material.alpha_cutoff = Some(json::material::AlphaCutoff(0.5));
    }
    let material = doc.material(material);
    doc.mesh_scene(mesh, material);
    doc.gltf_data_uri()
}

/// The albedo target (linear RGB) and which raster made it.
fn albedo(model: &[u8], choice: RasterChoice) -> (Vec<[f32; 4]>, RasterMode) {
    let renderer = test_renderer();
    let scene = load_gltf_slice(model, None).expect("loads");
    assert!(
        !scene.warnings.iter().any(|w| w.contains("TEXCOORD")),
        "{:?}",
        scene.warnings
    );
    let g = GBuffer::with_raster(
        &renderer,
        Some(2),
        vec![world_and_layer(&renderer, &scene, Mat4::IDENTITY, [1.0; 4]).1],
        VIEW.camera(),
        None,
        SizeRule::Relative(1.0),
        choice,
    );
    let (report, images) =
        render_and_read(&renderer, g.as_ref(), SIZE, &[&g.targets.color]).expect("renders");
    assert!(report.errors.is_empty(), "{:?}", report.errors);
    (images[0].pixels.clone(), g.raster)
}

/// Pixels well inside one quadrant of the texture (a texel and more from
/// every edge), with their (x, y) on the quad and their quadrant.
fn inner_pixels() -> impl Iterator<Item = (u32, u32, f32, usize)> {
    (0..SIZE.1).flat_map(|py| {
        (0..SIZE.0).filter_map(move |px| {
            let (x, y) = VIEW.hit(px, py);
            let (u, v) = ((x + 1.0) / 2.0, (1.0 - y) / 2.0);
            let away = |t: f32| (0.07..0.43).contains(&t) || (0.57..0.93).contains(&t);
            (away(u) && away(v)).then(|| {
                let quadrant = usize::from(v >= 0.5) * 2 + usize::from(u >= 0.5);
                (px, py, u, quadrant)
            })
        })
    })
}

fn check(choice: RasterChoice, expected: RasterMode) {
    let (pixels, raster) = albedo(&model(true, false), choice);
    assert_eq!(raster, expected);
    let mut checked = 0;
    for (px, py, t, quadrant) in inner_pixels() {
        let got = pixels[(py * SIZE.0 + px) as usize];
        for c in 0..3 {
            let color = LEFT[c] + (RIGHT[c] - LEFT[c]) * t;
            let want = QUADRANTS[quadrant][c] * color;
            assert!(
                (got[c] - want).abs() < 0.01,
                "pixel ({px}, {py}), channel {c}: {} instead of {want} (quadrant {quadrant}, t {t})",
                got[c]
            );
        }
        checked += 1;
    }
    assert!(checked > 1000, "{checked} pixels checked");
}

#[test]
fn texcoord_1_maps_the_texture_and_color_0_multiplies_it_compute_raster() {
    check(RasterChoice::Compute, RasterMode::Compute);
}

#[test]
fn texcoord_1_maps_the_texture_and_color_0_multiplies_it_hardware_raster() {
    check(RasterChoice::Hardware, RasterMode::Hardware);
}

#[test]
fn without_color_0_the_texture_is_unscaled() {
    let (pixels, _) = albedo(&model(false, false), RasterChoice::Auto);
    for (px, py, _, quadrant) in inner_pixels() {
        let got = pixels[(py * SIZE.0 + px) as usize];
        for c in 0..3 {
            assert!(
                (got[c] - QUADRANTS[quadrant][c]).abs() < 0.01,
                "pixel ({px}, {py}): {got:?} instead of {:?}",
                QUADRANTS[quadrant]
            );
        }
    }
}

#[test]
fn color_0_alpha_takes_part_in_the_alpha_test() {
    // Alpha from 0 (left edge) to 1 (right edge), cutoff 0.5: the left half is cut.
    let (pixels, raster) = albedo(&model(true, true), RasterChoice::Auto);
    assert_eq!(
        raster,
        RasterMode::Hardware,
        "alpha tests use the raster hardware"
    );
    let mut seen = [0usize; 2];
    for (px, py, t, _) in inner_pixels() {
        let covered = pixels[(py * SIZE.0 + px) as usize][..3]
            .iter()
            .any(|c| *c > 0.0);
        if (t - 0.5).abs() > 0.05 {
            assert_eq!(covered, t > 0.5, "pixel ({px}, {py}) at t {t}");
            seen[usize::from(covered)] += 1;
        }
    }
    assert!(seen[0] > 300 && seen[1] > 300, "{seen:?}");
}

#[test]
fn the_streams_load_as_written() {
    let scene = load_gltf_slice(&model(true, false), None).expect("loads");
    let mesh = &scene.meshes[0];
    assert_eq!(
        mesh.uvs1.as_deref(),
        Some(&[[0.0, 1.0], [1.0, 1.0], [1.0, 0.0], [0.0, 0.0]][..])
    );
    assert_eq!(
        mesh.colors.as_deref(),
        Some(&[LEFT, RIGHT, RIGHT, LEFT][..])
    );
    let texture = scene.materials[0]
        .base_color_texture
        .as_ref()
        .expect("a base colour texture");
    assert_eq!(texture.tex_coord, 1);
}
