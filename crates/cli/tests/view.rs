//! `spreadlight view` on generated models (`spreadlight_gltf::models`),
//! against reference images in `tests/reference/view-*.png`: every channel
//! within 4/255 on 99% of pixels. These stay 8-bit where the workspace's
//! references are float (`tests/float_compare.rs`): `view` writes a tonemapped,
//! display-referred image, 0 to 1, and its PNG is what a user gets.
//! Bless after an intended change with
//! `SPREADLIGHT_BLESS=1 cargo test --workspace --test cli -- view::`, and look
//! at the images before committing them.

use std::path::{Path, PathBuf};
use std::process::{Command, Output};

use spreadlight_gltf::builder::{self, Doc, info, png};
use spreadlight_gltf::{models, skinned_models};

const SIZE: &str = "64x64";

fn root() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../..")
}

fn spreadlight(args: &[&str]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_spreadlight"))
        .args(args)
        .current_dir(root())
        .output()
        .expect("runs")
}

fn text(bytes: &[u8]) -> String {
    String::from_utf8_lossy(bytes).into_owned()
}

/// `view` of `model` (written as `name.gltf`) with `extra` arguments; the image.
fn view(dir: &Path, name: &str, model: &[u8], extra: &[&str]) -> (image::RgbaImage, String) {
    let path = dir.join(format!("{name}.gltf"));
    std::fs::write(&path, model).expect("write model");
    let out = dir.join(format!("{name}.png"));
    let mut args = vec![
        "view",
        path.to_str().expect("utf-8"),
        "-o",
        out.to_str().expect("utf-8"),
        "--size",
        SIZE,
    ];
    args.extend_from_slice(extra);
    let o = spreadlight(&args);
    let stderr = text(&o.stderr);
    assert_eq!(o.status.code(), Some(0), "{stderr}");
    (image::open(&out).expect("image").to_rgba8(), stderr)
}

fn matches_reference(name: &str, got: &image::RgbaImage) {
    let reference = root().join("tests/reference").join(format!("{name}.png"));
    if std::env::var_os("SPREADLIGHT_BLESS").is_some() {
        got.save(&reference).expect("bless");
        return;
    }
    let want = image::open(&reference)
        .unwrap_or_else(|e| panic!("{}: {e}; bless it", reference.display()))
        .to_rgba8();
    assert_eq!(want.dimensions(), got.dimensions(), "{name}: size");
    let matching = want
        .pixels()
        .zip(got.pixels())
        .filter(|(a, b)| {
            a.0.iter()
                .zip(b.0.iter())
                .all(|(x, y)| (i32::from(*x) - i32::from(*y)).abs() <= 4)
        })
        .count();
    let fraction = matching as f64 / want.pixels().len() as f64;
    let kept = std::env::temp_dir().join(format!("spreadlight-{name}.png"));
    got.save(&kept).expect("keep");
    assert!(
        fraction >= 0.99,
        "{name}: {:.1}% of pixels match (rendered: {})",
        fraction * 100.0,
        kept.display()
    );
}

#[test]
fn textured_normal_mapped_cube_is_lit_and_textured() {
    let dir = tempfile::tempdir().expect("tempdir");
    let (lit, _) = view(dir.path(), "cube", &models::textured_cube(), &[]);
    matches_reference("view-textured-cube", &lit);
    // Not a silhouette: the checker and the lighting give many distinct colours.
    let distinct: std::collections::HashSet<[u8; 4]> = lit.pixels().map(|p| p.0).collect();
    assert!(distinct.len() > 200, "{} colours", distinct.len());
    // The albedo channel shows the texture: both checker colours appear.
    let (albedo, _) = view(
        dir.path(),
        "cube",
        &models::textured_cube(),
        &["--channel", "Albedo"],
    );
    let near = |p: &image::Rgba<u8>, c: [u8; 3]| {
        p.0.iter()
            .zip(c)
            .all(|(a, b)| (i32::from(*a) - i32::from(b)).abs() < 12)
    };
    assert!(
        albedo.pixels().any(|p| near(p, [230, 120, 40])),
        "orange squares"
    );
    assert!(
        albedo.pixels().any(|p| near(p, [240, 240, 230])),
        "white squares"
    );
}

#[test]
fn a_scene_is_lit_by_its_own_punctual_lights() {
    let dir = tempfile::tempdir().expect("tempdir");
    let patch = dir.path().join("lights.ron");
    let (lit, _) = view(
        dir.path(),
        "lights",
        &models::punctual_lights_scene(),
        &["--save-patch", patch.to_str().expect("utf-8")],
    );
    matches_reference("view-punctual-lights", &lit);
    // The file's lights replace view's sun: point and spot buffers, no sun, no shadow map.
    let saved = std::fs::read_to_string(&patch).expect("saved patch");
    assert!(saved.contains("PointLightBuffer") && saved.contains("SpotLightBuffer"));
    assert!(!saved.contains("AddLight (Sun)") && !saved.contains("ShadowMap"));
    // The warm point light is left of the block, the blue spot right of it.
    let (w, h) = lit.dimensions();
    let sum = |x0: u32, x1: u32| {
        let mut s = [0i64; 3];
        for y in h / 2..h * 3 / 4 {
            for x in x0..x1 {
                let p = lit.get_pixel(x, y).0;
                for c in 0..3 {
                    s[c] += i64::from(p[c]);
                }
            }
        }
        s
    };
    let (left, right) = (sum(w / 4, w / 2), sum(w / 2, w * 3 / 4));
    assert!(left[0] > left[2], "warm on the left: {left:?}");
    assert!(right[2] > right[0], "blue on the right: {right:?}");
}

/// A one-sided white quad facing +Z on a node placed by `translation` and `scale`.
fn quad(translation: [f32; 3], scale: [f32; 3]) -> Vec<u8> {
    quad_with(translation, scale, 0.0, |_| None)
}

/// A quad facing +Z turned by `turn` radians about Y, with the material
/// `material` makes (given the builder, to add textures).
fn quad_with(
    translation: [f32; 3],
    scale: [f32; 3],
    turn: f32,
    material: impl FnOnce(&mut Doc) -> Option<gltf_json::Material>,
) -> Vec<u8> {
    let mut doc = Doc::new();
    let mesh = doc.mesh_data("Quad", &builder::quad());
    if let Some(m) = material(&mut doc) {
        let m = doc.material(m);
        doc.root.meshes[mesh.value()].primitives[0].material = Some(m);
    }
    let node = doc.node(gltf_json::Node {
        mesh: Some(mesh),
        translation: Some(translation),
        scale: Some(scale),
        rotation: Some(gltf_json::scene::UnitQuaternion(
            glam::Quat::from_rotation_y(turn).to_array(),
        )),
        ..Default::default()
    });
    doc.scene(vec![node]);
    doc.gltf_data_uri()
}

/// The share of pixels the model covers in the albedo view.
fn coverage(image: &image::RgbaImage) -> f64 {
    let covered = image.pixels().filter(|p| p.0[0] > 100).count();
    covered as f64 / (image.width() * image.height()) as f64
}

/// A file whose only primitive is refused (points: no triangles) has
/// nothing to show: `view` fails naming the file and why, and writes no
/// image (it used to write the sky alone and exit 0).
#[test]
fn a_file_whose_only_primitive_is_refused_fails_and_writes_nothing() {
    use gltf_json::mesh::{Mode, Semantic};
    use spreadlight_gltf::builder::{mesh_node, primitive};
    let dir = tempfile::tempdir().expect("tempdir");
    let mut doc = Doc::new();
    let points = doc.positions(&[[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0]]);
    let mesh = doc.mesh(
        "Dots",
        vec![primitive(
            &[(Semantic::Positions, points)],
            None,
            Mode::Points,
        )],
    );
    let node = doc.node(mesh_node(Some(mesh), [0.0; 3], 1.0));
    doc.scene(vec![node]);
    let model = dir.path().join("dots.gltf");
    std::fs::write(&model, doc.gltf_data_uri()).expect("write model");
    let out = dir.path().join("dots.png");
    let o = spreadlight(&[
        "view",
        model.to_str().expect("utf-8"),
        "-o",
        out.to_str().expect("utf-8"),
        "--size",
        SIZE,
    ]);
    let stderr = text(&o.stderr);
    assert_eq!(o.status.code(), Some(1), "{stderr}");
    assert!(
        stderr.contains("dots.gltf: nothing to show: no primitive of the file loaded as triangles"),
        "{stderr}"
    );
    // The warning that says which primitive was skipped, and why.
    assert!(
        stderr.contains("mesh 0 `Dots`, primitive 0") && stderr.contains("Points"),
        "{stderr}"
    );
    assert!(!out.exists(), "an image was written");
}

#[test]
fn mirrored_nodes_turn_their_winding_around() {
    let dir = tempfile::tempdir().expect("tempdir");
    let args = ["--channel", "Albedo"];
    let (plain, _) = view(dir.path(), "plain", &quad([0.0; 3], [1.0; 3]), &args);
    let (mirrored, _) = view(
        dir.path(),
        "mirrored",
        &quad([0.0; 3], [-1.0, 1.0, 1.0]),
        &args,
    );
    assert!(coverage(&plain) > 0.2, "{}", coverage(&plain));
    // Culled as a back face, the mirrored quad would be missing.
    assert!(
        (coverage(&mirrored) - coverage(&plain)).abs() < 0.02,
        "{} vs {}",
        coverage(&mirrored),
        coverage(&plain)
    );
}

#[test]
fn extreme_coordinates_are_framed_and_shown() {
    let dir = tempfile::tempdir().expect("tempdir");
    for (name, s) in [("tiny", 1e-18f32), ("huge", 1e18)] {
        let model = quad([s, -s, 3.0 * s], [s; 3]);
        let (albedo, _) = view(dir.path(), name, &model, &["--channel", "Albedo"]);
        assert!(coverage(&albedo) > 0.2, "{name}: {}", coverage(&albedo));
        // Lit: finite, and the quad is not black.
        let (lit, stderr) = view(dir.path(), name, &model, &[]);
        // (lavapipe's own XDG_RUNTIME_DIR complaint is not ours)
        let ours = stderr
            .lines()
            .any(|l| l.contains("error") && !l.contains("XDG_RUNTIME_DIR"));
        assert!(!ours, "{name}: {stderr}");
        let centre = lit.get_pixel(lit.width() / 2, lit.height() / 2).0;
        assert!(centre[..3].iter().any(|c| *c > 40), "{name}: {centre:?}");
    }
}

#[test]
fn mask_materials_cut_out_below_their_cutoff() {
    let dir = tempfile::tempdir().expect("tempdir");
    let args = ["--channel", "Albedo"];
    // Alpha 0 on the left half of the texture, 1 on the right.
    let masked = quad_with([0.0; 3], [1.0; 3], 0.0, |doc| {
        let half = image::RgbaImage::from_fn(16, 16, |x, _| {
            image::Rgba([255, 255, 255, if x < 8 { 0 } else { 255 }])
        });
        let image = doc.png_image(&png(&half));
        let texture = doc.texture(image);
        let mut m = gltf_json::Material {
            alpha_mode: gltf_json::validation::Checked::Valid(gltf_json::material::AlphaMode::Mask),
            alpha_cutoff: Some(gltf_json::material::AlphaCutoff(0.5)),
            ..Default::default()
        };
        m.pbr_metallic_roughness.base_color_texture = Some(info(texture));
        Some(m)
    });
    let (plain, _) = view(dir.path(), "plain", &quad([0.0; 3], [1.0; 3]), &args);
    let (cut, _) = view(dir.path(), "masked", &masked, &args);
    let ratio = coverage(&cut) / coverage(&plain);
    assert!((0.35..0.65).contains(&ratio), "{ratio}");
}

#[test]
fn double_sided_materials_show_lit_back_faces() {
    let dir = tempfile::tempdir().expect("tempdir");
    let behind = |double_sided: bool| {
        // Turned away from the camera: the viewer sees its back.
        quad_with([0.0; 3], [1.0; 3], std::f32::consts::PI, move |_| {
            Some(gltf_json::Material {
                double_sided,
                ..Default::default()
            })
        })
    };
    let args = ["--channel", "Albedo"];
    let (one, _) = view(dir.path(), "one", &behind(false), &args);
    let (two, _) = view(dir.path(), "two", &behind(true), &args);
    assert!(coverage(&one) < 0.01, "{}", coverage(&one));
    assert!(coverage(&two) > 0.2, "{}", coverage(&two));
    // Its normals are flipped towards the viewer (view-space +Z: blue).
    let (normals, _) = view(dir.path(), "two", &behind(true), &["--channel", "Normals"]);
    let centre = normals
        .get_pixel(normals.width() / 2, normals.height() / 2)
        .0;
    assert!(centre[2] > 150, "{centre:?}");
}

#[test]
fn time_poses_an_animated_model() {
    let dir = tempfile::tempdir().expect("tempdir");
    let model = models::sliding_cube();
    // Where the cube is: its red pixels in the albedo view.
    let centroid = |time: &str| {
        let (image, _) = view(
            dir.path(),
            "slide",
            &model,
            &["--channel", "Albedo", "--time", time],
        );
        let (mut sum, mut n) = (0.0f64, 0.0f64);
        for (x, _, p) in image.enumerate_pixels() {
            if p.0[0] > 150 && p.0[1] < 80 {
                sum += f64::from(x);
                n += 1.0;
            }
        }
        assert!(n > 10.0, "the cube is in view at {time} s");
        sum / n
    };
    let (start, middle) = (centroid("0"), centroid("1"));
    assert!(
        middle > start + 8.0,
        "the cube slid right: {start} -> {middle}"
    );
}

#[test]
fn blend_materials_go_through_transparency() {
    let dir = tempfile::tempdir().expect("tempdir");
    let red = |mode| {
        move |_: &mut Doc| {
            let mut m = gltf_json::Material {
                alpha_mode: gltf_json::validation::Checked::Valid(mode),
                ..Default::default()
            };
            m.pbr_metallic_roughness.base_color_factor =
                gltf_json::material::PbrBaseColorFactor([1.0, 0.0, 0.0, 0.5]);
            m.pbr_metallic_roughness.metallic_factor = gltf_json::material::StrengthFactor(0.0);
            Some(m)
        }
    };
    use gltf_json::material::AlphaMode;
    let patch = dir.path().join("blend.ron");
    let blend = quad_with([0.0; 3], [1.0; 3], 0.0, red(AlphaMode::Blend));
    let opaque = quad_with([0.0; 3], [1.0; 3], 0.0, red(AlphaMode::Opaque));
    let (glass, _) = view(
        dir.path(),
        "glass",
        &blend,
        &["--save-patch", patch.to_str().expect("utf-8")],
    );
    let (solid, _) = view(dir.path(), "solid", &opaque, &[]);
    assert!(
        std::fs::read_to_string(&patch)
            .expect("patch")
            .contains("Transparency")
    );
    // Not in the G-buffer: the albedo view is empty.
    let (albedo, _) = view(dir.path(), "glass", &blend, &["--channel", "Albedo"]);
    assert!(coverage(&albedo) < 0.01, "{}", coverage(&albedo));
    // Over the sky, half red: redder than the sky, less than the opaque quad.
    let centre = |i: &image::RgbaImage| i.get_pixel(i.width() / 2, i.height() / 2).0;
    let (g, s) = (centre(&glass), centre(&solid));
    let redness = |p: [u8; 4]| i32::from(p[0]) - i32::from(p[2]);
    assert!(redness(g) > 0, "glass {g:?}");
    assert!(redness(s) > redness(g), "solid {s:?} vs glass {g:?}");
}

/// A tube on six joints (8 influences a vertex) whose far half swells by a
/// morph target: `--time` poses both. The two times bend it differently and
/// swell it differently, against a reference each.
#[test]
fn a_skinned_and_morphed_model_is_posed_at_two_times() {
    let dir = tempfile::tempdir().expect("tempdir");
    let model = skinned_models::swaying_tube();
    let (rest, _) = view(dir.path(), "tube", &model, &["--time", "0"]);
    let (posed, _) = view(dir.path(), "tube", &model, &["--time", "0.5"]);
    matches_reference("view-skinned-time-0", &rest);
    matches_reference("view-skinned-time-0.5", &posed);
    let differing = rest
        .pixels()
        .zip(posed.pixels())
        .filter(|(a, b)| a.0.iter().zip(b.0).any(|(x, y)| x.abs_diff(y) > 24))
        .count();
    assert!(
        differing > rest.pixels().len() / 20,
        "the pose changes the picture: {differing} pixels differ"
    );
    // Lit, not a silhouette.
    let distinct: std::collections::HashSet<[u8; 4]> = posed.pixels().map(|p| p.0).collect();
    assert!(distinct.len() > 100, "{} colours", distinct.len());
}

#[test]
fn a_photometric_file_is_seen_from_its_camera_and_exposed_down() {
    let dir = tempfile::tempdir().expect("tempdir");
    let patch = dir.path().join("shot.ron");
    let model = models::photometric_camera_scene();
    let (lit, stderr) = view(
        dir.path(),
        "shot",
        &model,
        &["--save-patch", patch.to_str().expect("utf-8")],
    );
    assert!(stderr.contains("viewed from camera `Shot`"), "{stderr}");
    assert!(
        stderr.contains("50000 lux") && stderr.contains("exposed by"),
        "{stderr}"
    );
    let saved = std::fs::read_to_string(&patch).expect("saved patch");
    assert!(saved.contains("Exposure"), "Tonemap is given the exposure");
    // From the file's camera the block's red face fills the picture (a
    // framing camera would show the whole floor, the block small in it).
    let (albedo, _) = view(dir.path(), "shot", &model, &["--channel", "Albedo"]);
    let red = albedo
        .pixels()
        .filter(|p| p.0[0] > 2 * p.0[1].max(10) && p.0[0] > 2 * p.0[2].max(10))
        .count();
    let total = albedo.pixels().len();
    assert!(
        red * 10 >= total * 9,
        "{red} of {total} pixels show the block"
    );
    // Exposed down, the face lit by a 50,000 lux sun is a mid red, not
    // burnt white: not one pixel saturates, and the red stays far above
    // green (without the exposure every channel clips at 255).
    let mut reds: Vec<u8> = lit.pixels().map(|p| p.0[0]).collect();
    reds.sort_unstable();
    let median = reds[reds.len() / 2];
    assert!((60..236).contains(&median), "median red {median}");
    assert!(
        lit.pixels().all(|p| p.0[1] < 200),
        "no channel burns: {:?}",
        lit.pixels().map(|p| p.0[1]).max()
    );
}

#[test]
fn material_extensions_show_as_their_materials_say() {
    let dir = tempfile::tempdir().expect("tempdir");
    let (lit, stderr) = view(
        dir.path(),
        "extensions",
        &models::material_extensions_row(),
        &[],
    );
    // Transmission is blended (its warning says so); nothing else is ignored.
    assert!(
        stderr.contains("`Transmission`") && stderr.contains("BLEND"),
        "{stderr}"
    );
    assert!(!stderr.contains("not supported"), "{stderr}");
    matches_reference("view-material-extensions", &lit);
}

#[test]
fn sheen_shows_on_the_velvet_row() {
    let dir = tempfile::tempdir().expect("tempdir");
    let (lit, stderr) = view(dir.path(), "sheen", &models::sheen_row(), &[]);
    assert!(!stderr.contains("not supported"), "{stderr}");
    matches_reference("view-sheen", &lit);
}

/// A file shaped like Khronos' DepthOfFieldExample (Blender's export): a
/// large floor, blocks at several depths along the view, a camera of the
/// file's own looking down the row, and point lights of thousands of
/// candela above it, no sun. `view` must show it from that camera, exposed
/// for those lights: the floor a mid grey, not the white, burnt-out floor
/// a framing camera at exposure 1 gave.
fn depth_of_field_shaped_scene() -> Vec<u8> {
    use gltf_json::extensions::scene::khr_lights_punctual::{Light, Type};
    use gltf_json::validation::Checked::Valid;
    use spreadlight_gltf::builder::{light_node, mesh_node};
    use spreadlight_render::mesh::primitives::{BoxParams, GridParams, box_mesh, grid};
    let mut doc = Doc::new();
    let floor = doc.mesh_data(
        "Floor",
        &grid(GridParams {
            size: glam::Vec2::splat(16.0),
            resolution_x: 1,
            resolution_y: 1,
        }),
    );
    let block = doc.mesh_data("Block", &box_mesh(BoxParams::default()));
    let matte = |color: [f32; 4]| gltf_json::Material {
        pbr_metallic_roughness: gltf_json::material::PbrMetallicRoughness {
            base_color_factor: gltf_json::material::PbrBaseColorFactor(color),
            metallic_factor: gltf_json::material::StrengthFactor(0.0),
            roughness_factor: gltf_json::material::StrengthFactor(0.6),
            ..Default::default()
        },
        ..Default::default()
    };
    let grey = doc.material(matte([0.5, 0.5, 0.5, 1.0]));
    let orange = doc.material(matte([0.6, 0.25, 0.05, 1.0]));
    doc.root.meshes[floor.value()].primitives[0].material = Some(grey);
    doc.root.meshes[block.value()].primitives[0].material = Some(orange);
    let point = |name: &str, intensity: f32| Light {
        color: [1.0, 0.95, 0.9],
        extensions: None,
        extras: Default::default(),
        intensity,
        name: Some(name.into()),
        range: None,
        spot: None,
        type_: Valid(Type::Point),
    };
    doc.punctual_lights(vec![
        point("Lamp", 3000.0),
        point("Lamp.001", 6000.0),
        point("Lamp.002", 4500.0),
    ]);
    let camera = doc.root.push(gltf_json::Camera {
        name: Some("DOF Camera".into()),
        orthographic: None,
        perspective: Some(gltf_json::camera::Perspective {
            aspect_ratio: Some(1.0),
            yfov: 0.6,
            zfar: Some(100.0),
            znear: 0.1,
            extensions: None,
            extras: Default::default(),
        }),
        type_: Valid(gltf_json::camera::Type::Perspective),
        extensions: None,
        extras: Default::default(),
    });
    let mut nodes = vec![doc.node(mesh_node(Some(floor), [0.0; 3], 1.0))];
    for (i, z) in [1.0f32, -1.0, -3.0, -5.0, -7.0].into_iter().enumerate() {
        let x = if i % 2 == 0 { -0.8 } else { 0.8 };
        nodes.push(doc.node(mesh_node(Some(block), [x, 0.5, z], 1.0)));
    }
    for (light, position) in [[-2.0, 3.0, 0.0], [2.0, 3.0, -3.0], [0.0, 3.5, -6.0]]
        .into_iter()
        .enumerate()
    {
        nodes.push(doc.node(gltf_json::Node {
            translation: Some(position),
            ..light_node(light as u32)
        }));
    }
    // Cameras look along -Z: from in front of the row, pitched down at it.
    let pitch = glam::Quat::from_rotation_x(-0.3);
    nodes.push(doc.node(gltf_json::Node {
        camera: Some(camera),
        translation: Some([0.0, 1.8, 5.0]),
        rotation: Some(gltf_json::scene::UnitQuaternion(pitch.to_array())),
        ..Default::default()
    }));
    doc.scene(nodes);
    doc.gltf_data_uri()
}

#[test]
fn a_depth_of_field_shaped_file_is_seen_from_its_camera_and_its_floor_is_not_burnt() {
    let dir = tempfile::tempdir().expect("tempdir");
    let model = depth_of_field_shaped_scene();
    let (lit, stderr) = view(dir.path(), "dof", &model, &[]);
    assert!(
        stderr.contains("viewed from camera `DOF Camera`"),
        "{stderr}"
    );
    assert!(stderr.contains("exposed by"), "{stderr}");
    // The floor fills the lower half of the picture, between the blocks.
    let floor: Vec<[u8; 4]> = lit
        .enumerate_pixels()
        .filter(|(_, y, _)| *y >= lit.height() * 3 / 4)
        .map(|(_, _, p)| p.0)
        .filter(|p| (i32::from(p[0]) - i32::from(p[2])).abs() < 40)
        .collect();
    assert!(floor.len() > 100, "{} floor pixels", floor.len());
    let burnt = floor
        .iter()
        .filter(|p| p[..3].iter().all(|c| *c >= 250))
        .count();
    assert!(
        burnt * 50 < floor.len(),
        "{burnt} of {} floor pixels are white",
        floor.len()
    );
    let mut grey: Vec<u8> = floor.iter().map(|p| p[1]).collect();
    grey.sort_unstable();
    let median = grey[grey.len() / 2];
    assert!(
        (25..240).contains(&median),
        "the floor's median green {median}: neither black nor burnt"
    );
}

#[test]
fn variant_shows_a_material_variant_and_an_unknown_one_is_a_warning() {
    let dir = tempfile::tempdir().expect("tempdir");
    let model = models::material_variants();
    // Pixels of the body's colour in the albedo view: red (the default
    // mapping) or blue (Ocean), whichever the material says.
    let counts = |variant: &str| {
        let (image, stderr) = view(
            dir.path(),
            "variants",
            &model,
            &["--channel", "Albedo", "--variant", variant],
        );
        let (mut red, mut blue) = (0, 0);
        for p in image.pixels() {
            let [r, _, b, _] = p.0.map(i32::from);
            red += i32::from(r > b + 100);
            blue += i32::from(b > r + 100);
        }
        (red, blue, stderr)
    };
    let (red, blue, _) = counts("Ocean");
    assert!(blue > 50 && red == 0, "Ocean: {blue} blue, {red} red");
    let (red, blue, stderr) = counts("Desert");
    assert!(red > 50 && blue == 0, "Desert: {red} red, {blue} blue");
    assert!(
        stderr.contains("variants.gltf: warning: material variant `Desert`")
            && stderr.contains("`Forest`, `Ocean`"),
        "{stderr}"
    );
}
