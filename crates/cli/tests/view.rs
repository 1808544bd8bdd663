//! `spreadlight view` on generated models (`render::mesh::gltf_import::models`),
//! against reference images in `tests/reference/` with the tolerance of the
//! workspace's reference tests: every channel within 4/255 on 99% of pixels.
//! Bless after an intended change with
//! `SPREADLIGHT_BLESS=1 cargo test -p spreadlight-cli --test view`, and look
//! at the images before committing them.

use std::path::{Path, PathBuf};
use std::process::{Command, Output};

use spreadlight_render::mesh::gltf_import::models;

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
    assert!(albedo.pixels().any(|p| near(p, [230, 120, 40])), "orange squares");
    assert!(albedo.pixels().any(|p| near(p, [240, 240, 230])), "white squares");
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
