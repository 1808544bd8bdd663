//! `KHR_materials_anisotropy` over files written at test time: its factors
//! and map as the material world gets them (the Anisotropy feature, the
//! anisotropy map slot), bad values warned naming the material, a file
//! that requires it loading, and the brushed-metal example's asset. What
//! the shaded pixels are: crates/gltf/tests/gltf_extension_maps.rs.

use super::builder::png;
use super::material_extensions_tests::{assert_finite, cube_with, load_one, named, params};
use super::*;
use spreadlight_render::material::Feature;
use spreadlight_render::material::maps::MapSlot;

#[test]
fn anisotropy_factors_and_map_make_the_anisotropy_feature() {
    let mut doc = cube_with(named("Brushed"), "{}");
    let image = doc.png_image(&png(&super::models::circular_brush(8)));
    let texture = doc.texture(image);
    let ext = format!(
        r#"{{"anisotropyStrength": 0.6, "anisotropyRotation": 1.25, "anisotropyTexture": {{"index": {}}}}}"#,
        texture.value()
    );
    doc.root
        .extensions_used
        .push("KHR_materials_anisotropy".into());
    doc.root.extensions_required = vec!["KHR_materials_anisotropy".into()];
    let material = &mut doc.root.materials[0];
    let mut others = material.extensions.clone().unwrap_or_default().others;
    others.insert("KHR_materials_anisotropy".into(), json_value(&ext));
    material.extensions = Some(gltf::json::extensions::material::Material {
        others,
        ..Default::default()
    });
    let (m, warnings) = load_one(doc);
    assert!(warnings.is_empty(), "{warnings:?}");
    assert_eq!((m.anisotropy_strength, m.anisotropy_rotation), (0.6, 1.25));
    assert_eq!(params(&m, Feature::Anisotropy), Some([0.6, 1.25, 0.0, 0.0]));
    let material = m.to_material();
    let maps = material.maps().expect("surface maps");
    let map = maps.map(MapSlot::Anisotropy).expect("the anisotropy map");
    assert_eq!((map.image.width, map.image.height), (8, 8));
    assert!(maps.has_extension_maps(), "it packs the long layout");
    // Strength 0 (the default): no feature, and the map is left out.
    let (m, _) = load_one(cube_with(
        named("Round"),
        r#"{"KHR_materials_anisotropy": {"anisotropyRotation": 2.0}}"#,
    ));
    assert_eq!(params(&m, Feature::Anisotropy), None);
}

fn json_value(text: &str) -> gltf::json::Value {
    gltf::json::deserialize::from_str(text).expect("test JSON")
}

#[test]
fn bad_anisotropy_values_are_warned_by_material_and_stay_finite() {
    let ext = r#"{"KHR_materials_anisotropy": {"anisotropyStrength": -3.0, "anisotropyRotation": 1e39,
        "anisotropyTexture": {"index": 7}}}"#;
    let (m, warnings) = load_one(cube_with(named("Scratched"), ext));
    assert_finite(&m);
    let said = |what: &str| {
        warnings
            .iter()
            .any(|w| w.contains("material 0 `Scratched`") && w.contains(what))
    };
    assert!(said("anisotropyStrength is -3"), "{warnings:?}");
    // 1e39 is no f32: not a finite number, the default used.
    assert!(said("anisotropyRotation"), "{warnings:?}");
    assert!(said("anisotropyTexture names no texture"), "{warnings:?}");
    assert_eq!((m.anisotropy_strength, m.anisotropy_rotation), (0.0, 0.0));
    assert!(m.anisotropy_texture.is_none());
    // Above 1: clamped to 1.
    let (m, warnings) = load_one(cube_with(
        named("Hard"),
        r#"{"KHR_materials_anisotropy": {"anisotropyStrength": 4.0}}"#,
    ));
    assert_eq!(m.anisotropy_strength, 1.0);
    assert_eq!(warnings.len(), 1, "{warnings:?}");
}

#[test]
fn the_brushed_metal_asset_is_what_the_generator_makes_and_loads_clean() {
    // patches/assets/brushed-metal.gltf (patches/brushed-metal.ron, the
    // picture in docs/materials.md) and its isotropic twin
    // brushed-metal-plain.gltf (the benchmark's comparison) are the
    // committed output of the generator.
    let path = std::path::Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("../../patches/assets/brushed-metal.gltf");
    let made = super::models::brushed_metal_row();
    let plain_path = path.with_file_name("brushed-metal-plain.gltf");
    let plain = super::models::plain_metal_row();
    for (path, made) in [(&path, &made), (&plain_path, &plain)] {
        if std::env::var_os("SPREADLIGHT_BLESS").is_some() {
            std::fs::write(path, made).expect("bless the asset");
        }
        let committed = std::fs::read(path).expect("the committed asset");
        assert!(
            &committed == made,
            "{} is stale: regenerate with SPREADLIGHT_BLESS=1",
            path.display()
        );
    }
    // The benchmark's twin: the same discs, none anisotropic.
    let twin = load_gltf_slice(&plain, None).expect("loads");
    assert!(
        twin.materials
            .iter()
            .all(|m| m.to_material().params(Feature::Anisotropy).is_none())
    );
    let scene = load_gltf_slice(&made, None).expect("loads");
    assert!(scene.warnings.is_empty(), "{:?}", scene.warnings);
    let strengths: Vec<f32> = scene
        .materials
        .iter()
        .map(|m| m.anisotropy_strength)
        .collect();
    assert_eq!(strengths, super::models::BRUSHED_STRENGTHS);
    assert!(
        scene
            .materials
            .iter()
            .all(|m| m.anisotropy_texture.is_some())
    );
    // The map's direction runs around its centre: at the middle of the
    // right edge it points up the image (g high), at the top along -u.
    let brush = super::models::circular_brush(64);
    let right = brush.get_pixel(63, 32).0;
    let top = brush.get_pixel(32, 0).0;
    assert!(
        right[1] > 250 && (right[0] as i32 - 128).abs() < 8,
        "{right:?}"
    );
    assert!(top[0] < 5 && (top[1] as i32 - 128).abs() < 8, "{top:?}");
}
