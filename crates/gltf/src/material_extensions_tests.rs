//! `KHR_materials_*` over files written at test time: each extension's
//! values as the material world gets them, and the bad values a file can
//! hold (warned, naming the material; never NaN). The GPU side (what the
//! shaded pixels are) is crates/render/tests/surface_lighting.rs and
//! crates/gltf/tests/gltf_blend.rs.

use gltf_json as json;
use json::Value;

use super::builder::{Doc, png};
use super::spec_gloss::{MetalRough, SpecGloss, convert, round_trip};
use super::*;
use spreadlight_render::material::Feature;
use spreadlight_render::material::maps::MapSlot;
use spreadlight_render::mesh::primitives::{BoxParams, box_mesh};

pub(super) fn value(text: &str) -> Value {
    json::deserialize::from_str(text).expect("test JSON")
}

/// A cube whose one material is `material` with the extension objects of `extensions`.
pub(super) fn cube_with(mut material: json::Material, extensions: &str) -> Doc {
    let mut doc = Doc::new();
    let mesh = doc.mesh_data("Cube", &box_mesh(BoxParams::default()));
    let node = doc.node(super::builder::mesh_node(Some(mesh), [0.0; 3], 1.0));
    doc.scene(vec![node]);
    let others = value(extensions).as_object().cloned().unwrap_or_default();
    for name in others.keys() {
        doc.root.extensions_used.push(name.clone());
    }
    material.extensions = Some(json::extensions::material::Material {
        others,
        ..Default::default()
    });
    let material = doc.material(material);
    doc.root.meshes[0].primitives[0].material = Some(material);
    doc
}

pub(super) fn named(name: &str) -> json::Material {
    json::Material {
        name: Some(name.into()),
        ..Default::default()
    }
}

/// The file's one material, and the warnings of the load.
pub(super) fn load_one(doc: Doc) -> (MaterialData, Vec<String>) {
    let scene = load_gltf_slice(&doc.glb(), None).expect("the file loads");
    assert_eq!(scene.materials.len(), 1);
    (scene.materials[0].clone(), scene.warnings)
}

pub(super) fn params(m: &MaterialData, f: Feature) -> Option<[f32; 4]> {
    m.to_material().params(f).map(|p| p[0])
}

pub(super) fn assert_close(a: f32, b: f32, tolerance: f32, what: &str) {
    assert!((a - b).abs() <= tolerance, "{what}: {a} against {b}");
}

/// Every parameter of every feature of the material is finite.
pub(super) fn assert_finite(m: &MaterialData) {
    for (f, p) in m.to_material().features() {
        assert!(
            p.iter().flatten().all(|v| v.is_finite()),
            "{f}: {p:?} is not finite"
        );
    }
    assert!(m.base_color.iter().all(|c| c.is_finite()));
}

#[test]
fn unlit_materials_get_the_unlit_feature_and_lit_ones_do_not() {
    let (m, warnings) = load_one(cube_with(named("Cake"), r#"{"KHR_materials_unlit": {}}"#));
    assert!(m.unlit, "{m:?}");
    assert!(warnings.is_empty(), "{warnings:?}");
    assert_eq!(params(&m, Feature::Unlit), Some([1.0, 0.0, 0.0, 0.0]));
    let (lit, _) = load_one(cube_with(named("Plain"), "{}"));
    assert!(!lit.unlit);
    assert_eq!(params(&lit, Feature::Unlit), None);
    assert_eq!(lit.to_material().flags() & Feature::Unlit.flag(), 0);
}

#[test]
fn ior_sets_the_dielectric_f0() {
    let (water, warnings) = load_one(cube_with(
        named("Water"),
        r#"{"KHR_materials_ior": {"ior": 1.33}}"#,
    ));
    assert!(warnings.is_empty(), "{warnings:?}");
    assert_eq!(water.ior, 1.33);
    let expected = ((1.33f32 - 1.0) / (1.33 + 1.0)).powi(2);
    assert_close(water.reflectance(), expected, 1e-6, "f0 of water");
    let ct = params(&water, Feature::CookTorrance).expect("CookTorrance");
    assert_close(ct[2], expected, 1e-6, "CookTorrance reflectance");
    // glTF's default, 1.5, is the 0.04 every material had before.
    let (plain, _) = load_one(cube_with(named("Plain"), "{}"));
    assert_close(plain.reflectance(), 0.04, 1e-6, "default f0");
    // ior 0: the extension's "f0 = 1".
    let (mirror, warnings) = load_one(cube_with(
        named("Mirror"),
        r#"{"KHR_materials_ior": {"ior": 0}}"#,
    ));
    assert!(warnings.is_empty(), "{warnings:?}");
    assert_close(mirror.reflectance(), 1.0, 1e-6, "ior 0");
}

#[test]
fn out_of_range_ior_is_warned_by_material_and_keeps_the_default() {
    for bad in [r#"0.5"#, r#"-2"#, r#""glass""#, r#"1e39"#] {
        let ext = format!(r#"{{"KHR_materials_ior": {{"ior": {bad}}}}}"#);
        let (m, warnings) = load_one(cube_with(named("Odd"), &ext));
        assert_eq!(m.ior, 1.5, "{bad}");
        assert_close(m.reflectance(), 0.04, 1e-6, bad);
        assert!(
            warnings
                .iter()
                .any(|w| w.contains("material 0 `Odd`") && w.contains("ior")),
            "{bad}: {warnings:?}"
        );
        assert_finite(&m);
    }
}

#[test]
fn specular_scales_and_tints_the_dielectric_f0() {
    let ext = r#"{"KHR_materials_specular": {"specularFactor": 0.5, "specularColorFactor": [2.0, 1.0, 0.5]},
                 "KHR_materials_ior": {"ior": 2.0}}"#;
    let (m, warnings) = load_one(cube_with(named("Satin"), ext));
    assert!(warnings.is_empty(), "{warnings:?}");
    assert_eq!((m.specular, m.specular_color), (0.5, [2.0, 1.0, 0.5]));
    // f0(2.0) = 1/9; per channel min(f0 x colour, 1), then luminance x factor.
    let f0 = 1.0 / 9.0;
    let expected = (0.2126 * 2.0 * f0 + 0.7152 * f0 + 0.0722 * 0.5 * f0) * 0.5;
    assert_close(m.reflectance(), expected, 1e-6, "specular f0");
    // Specular 0: no dielectric reflection at normal incidence.
    let (matte, _) = load_one(cube_with(
        named("Matte"),
        r#"{"KHR_materials_specular": {"specularFactor": 0}}"#,
    ));
    assert_eq!(matte.reflectance(), 0.0);
    // Out of range and malformed: clamped or default, warned, finite.
    let ext = r#"{"KHR_materials_specular": {"specularFactor": 7, "specularColorFactor": [1, "red", 1]}}"#;
    let (bad, warnings) = load_one(cube_with(named("Bad"), ext));
    assert_eq!((bad.specular, bad.specular_color), (1.0, [1.0; 3]));
    assert!(
        warnings
            .iter()
            .any(|w| w.contains("`Bad`") && w.contains("specularFactor")),
        "{warnings:?}"
    );
    assert!(
        warnings
            .iter()
            .any(|w| w.contains("`Bad`") && w.contains("specularColorFactor")),
        "{warnings:?}"
    );
    assert_finite(&bad);
}

#[test]
fn clearcoat_becomes_the_clearcoat_feature() {
    let ext = r#"{"KHR_materials_clearcoat": {"clearcoatFactor": 0.8, "clearcoatRoughnessFactor": 0.25}}"#;
    let (m, warnings) = load_one(cube_with(named("Golf"), ext));
    assert!(warnings.is_empty(), "{warnings:?}");
    assert_eq!((m.clearcoat, m.clearcoat_roughness), (0.8, 0.25));
    assert_eq!(params(&m, Feature::Clearcoat), Some([0.8, 0.25, 0.0, 0.0]));
    // Factor 0 (the default): no coat, no feature, nothing compiled for it.
    let (none, _) = load_one(cube_with(
        named("Bare"),
        r#"{"KHR_materials_clearcoat": {}}"#,
    ));
    assert_eq!(params(&none, Feature::Clearcoat), None);
}

#[test]
fn clearcoat_bad_values_are_warned_and_its_normal_map_is_not() {
    let mut doc = cube_with(named("Coat"), "{}");
    let image = doc.png_image(&png(&image::RgbaImage::from_pixel(
        1,
        1,
        image::Rgba([255; 4]),
    )));
    let texture = doc.texture(image);
    let ext = format!(
        r#"{{"KHR_materials_clearcoat": {{"clearcoatFactor": 1.5, "clearcoatRoughnessFactor": -1,
            "clearcoatTexture": {{"index": {0}}}, "clearcoatNormalTexture": {{"index": {0}, "scale": "x"}}}}}}"#,
        texture.value()
    );
    doc.root.materials[0].extensions = Some(json::extensions::material::Material {
        others: value(&ext).as_object().cloned().unwrap_or_default(),
        ..Default::default()
    });
    doc.root
        .extensions_used
        .push("KHR_materials_clearcoat".into());
    let (m, warnings) = load_one(doc);
    assert_eq!(params(&m, Feature::Clearcoat), Some([1.0, 0.0, 0.0, 0.0]));
    assert!(
        !warnings.iter().any(|w| w.contains("not sampled")),
        "the coat's normal map is sampled: {warnings:?}"
    );
    // A scale that is not a number is warned and reads 1.
    assert_eq!(m.clearcoat_normal_scale, 1.0);
    assert!(m.clearcoat_normal_texture.is_some());
    for what in [
        "clearcoatFactor is 1.5",
        "clearcoatRoughnessFactor is -1",
        "scale is \"x\"",
    ] {
        assert!(
            warnings
                .iter()
                .any(|w| w.contains("material 0 `Coat`") && w.contains(what)),
            "{what}: {warnings:?}"
        );
    }
    // The coat's own map is sampled: no warning says otherwise.
    assert!(
        !warnings.iter().any(|w| w.contains("clearcoatTexture is")),
        "{warnings:?}"
    );
}

#[test]
fn iridescence_becomes_the_iridescence_feature() {
    let ext = r#"{"KHR_materials_iridescence": {"iridescenceFactor": 0.75, "iridescenceIor": 1.5,
        "iridescenceThicknessMinimum": 200, "iridescenceThicknessMaximum": 800}}"#;
    let (m, warnings) = load_one(cube_with(named("Bubble"), ext));
    assert!(warnings.is_empty(), "{warnings:?}");
    assert_eq!(
        params(&m, Feature::Iridescence),
        Some([0.75, 1.5, 200.0, 800.0])
    );
    // The extension's defaults: ior 1.3, 100..400 nm; factor 0 is no film.
    let (defaults, _) = load_one(cube_with(
        named("Film"),
        r#"{"KHR_materials_iridescence": {"iridescenceFactor": 1}}"#,
    ));
    assert_eq!(
        params(&defaults, Feature::Iridescence),
        Some([1.0, 1.3, 100.0, 400.0])
    );
    let (none, _) = load_one(cube_with(
        named("Bare"),
        r#"{"KHR_materials_iridescence": {}}"#,
    ));
    assert_eq!(params(&none, Feature::Iridescence), None);
    // A file may require it.
    let mut doc = cube_with(named("Bubble"), ext);
    doc.root.extensions_required = vec!["KHR_materials_iridescence".into()];
    let scene = load_gltf_slice(&doc.glb(), None).expect("iridescence is supported");
    assert!(scene.warnings.is_empty(), "{:?}", scene.warnings);
}

#[test]
fn iridescence_bad_values_are_warned_by_material_and_its_maps_as_not_sampled() {
    let mut doc = cube_with(named("Oil"), "{}");
    let image = doc.png_image(&png(&image::RgbaImage::from_pixel(
        1,
        1,
        image::Rgba([255; 4]),
    )));
    let texture = doc.texture(image);
    let ext = format!(
        r#"{{"KHR_materials_iridescence": {{"iridescenceFactor": 1e39, "iridescenceIor": 0.5,
            "iridescenceThicknessMinimum": -5, "iridescenceThicknessMaximum": "thick",
            "iridescenceTexture": {{"index": {0}}}, "iridescenceThicknessTexture": {{"index": {0}}}}}}}"#,
        texture.value()
    );
    doc.root.materials[0].extensions = Some(json::extensions::material::Material {
        others: value(&ext).as_object().cloned().unwrap_or_default(),
        ..Default::default()
    });
    doc.root
        .extensions_used
        .push("KHR_materials_iridescence".into());
    let (m, warnings) = load_one(doc);
    assert_finite(&m);
    // 1e39 is no f32: infinite, not finite, so the default (0, no film)
    // stays; the ior 1.3; the minimum clamped to 0, the maximum 400.
    assert_eq!(
        (
            m.iridescence,
            m.iridescence_ior,
            m.iridescence_thickness_minimum,
            m.iridescence_thickness_maximum
        ),
        (0.0, 1.3, 0.0, 400.0)
    );
    for what in [
        "iridescenceFactor is ",
        "iridescenceIor is 0.5",
        "iridescenceThicknessMinimum is -5",
        "iridescenceThicknessMaximum is \"thick\"",
    ] {
        assert!(
            warnings
                .iter()
                .any(|w| w.contains("material 0 `Oil`") && w.contains(what)),
            "{what}: {warnings:?}"
        );
    }
    assert!(m.iridescence_texture.is_some() && m.iridescence_thickness_texture.is_some());
    // With a film, the maps are sampled: no warning, and the material's
    // iridescence slots carry them.
    let mut doc = cube_with(named("Oil"), "{}");
    let image = doc.png_image(&png(&image::RgbaImage::from_pixel(
        1,
        1,
        image::Rgba([255; 4]),
    )));
    let texture = doc.texture(image);
    let ext = format!(
        r#"{{"KHR_materials_iridescence": {{"iridescenceFactor": 2,
            "iridescenceTexture": {{"index": {0}}}, "iridescenceThicknessTexture": {{"index": {0}}}}}}}"#,
        texture.value()
    );
    doc.root.materials[0].extensions = Some(json::extensions::material::Material {
        others: value(&ext).as_object().cloned().unwrap_or_default(),
        ..Default::default()
    });
    doc.root
        .extensions_used
        .push("KHR_materials_iridescence".into());
    let (m, warnings) = load_one(doc);
    assert_eq!(
        params(&m, Feature::Iridescence),
        Some([1.0, 1.3, 100.0, 400.0])
    );
    assert!(
        warnings
            .iter()
            .any(|w| w.contains("material 0 `Oil`") && w.contains("iridescenceFactor is 2")),
        "{warnings:?}"
    );
    assert!(
        !warnings.iter().any(|w| w.contains("not sampled")),
        "{warnings:?}"
    );
    let material = m.to_material();
    let maps = material.maps().expect("surface maps");
    assert!(maps.map(MapSlot::Iridescence).is_some());
    assert!(maps.map(MapSlot::IridescenceThickness).is_some());
}

#[test]
fn transmission_is_blended_with_opacity_one_minus_transmission() {
    let mut material = named("Glass");
    material.pbr_metallic_roughness.base_color_factor =
        json::material::PbrBaseColorFactor([0.9, 0.95, 1.0, 0.8]);
    let ext = r#"{"KHR_materials_transmission": {"transmissionFactor": 0.75}}"#;
    let (m, warnings) = load_one(cube_with(material, ext));
    assert_eq!(m.transmission, 0.75);
    assert_eq!(m.alpha_mode, AlphaMode::Blend);
    assert_close(m.base_color[3], 0.8 * 0.25, 1e-6, "opacity");
    assert!(
        warnings
            .iter()
            .any(|w| w.contains("`Glass`") && w.contains("BLEND")),
        "{warnings:?}"
    );
    // No transmission: opaque as the core material says.
    let (opaque, _) = load_one(cube_with(
        named("Solid"),
        r#"{"KHR_materials_transmission": {"transmissionFactor": 0}}"#,
    ));
    assert_eq!(opaque.alpha_mode, AlphaMode::Opaque);
    assert_eq!(opaque.base_color[3], 1.0);
}

#[test]
fn spec_gloss_factors_convert_to_metal_rough() {
    // A dielectric (f0 0.04): exact, base colour = diffuse.
    let ext = r#"{"KHR_materials_pbrSpecularGlossiness": {"diffuseFactor": [0.5, 0.25, 0.1, 0.5],
        "specularFactor": [0.04, 0.04, 0.04], "glossinessFactor": 0.8}}"#;
    let (m, warnings) = load_one(cube_with(named("Plastic"), ext));
    assert!(warnings.is_empty(), "{warnings:?}");
    assert!(m.from_spec_gloss);
    assert_close(m.metallic, 0.0, 1e-4, "metallic");
    assert_close(m.roughness, 0.2, 1e-6, "roughness");
    for (got, want) in m.base_color.iter().zip([0.5, 0.25, 0.1, 0.5]) {
        assert_close(*got, want, 1e-4, "dielectric base colour");
    }
    // A metal (no diffuse): metallic 1, base colour = specular.
    let ext = r#"{"KHR_materials_pbrSpecularGlossiness": {"diffuseFactor": [0, 0, 0, 1],
        "specularFactor": [0.95, 0.64, 0.54], "glossinessFactor": 1}}"#;
    let (gold, _) = load_one(cube_with(named("Copper"), ext));
    assert_close(gold.metallic, 1.0, 1e-4, "metallic");
    assert_eq!(gold.roughness, 0.0);
    for (got, want) in gold.base_color.iter().zip([0.95, 0.64, 0.54]) {
        assert_close(*got, want, 1e-4, "metal base colour");
    }
}

#[test]
fn spec_gloss_round_trip_error_over_a_sweep() {
    // The conversion's error, as docs/gltf.md states it: physical inputs
    // (dielectric f0 0.04 or metal without diffuse) come back within 1e-4;
    // any energy-conserving combination (diffuse + specular <= 1) within
    // 0.25 per channel of diffuse colour or f0 (0.231 at diffuse 0.5 with
    // specular 0.5: a half metal); the median of the sweep is 0.04.
    let steps = [0.0, 0.1, 0.25, 0.5, 0.75, 1.0];
    let mut physical: f32 = 0.0;
    let mut any: f32 = 0.0;
    for &d in &steps {
        for &s in steps.iter().filter(|&&s| d + s <= 1.0) {
            for &hue in &[0.5f32, 1.0] {
                let diffuse = [d, d * hue, d * hue * hue, 1.0];
                let specular = [s, s * hue, s * hue];
                let mr = convert(SpecGloss {
                    diffuse,
                    specular,
                    glossiness: 0.5,
                });
                assert!(
                    mr.base_color
                        .iter()
                        .all(|c| c.is_finite() && (0.0..=1.0).contains(c))
                );
                assert!((0.0..=1.0).contains(&mr.metallic));
                let (d2, s2) = round_trip(mr);
                let err = (0..3)
                    .map(|i| {
                        (d2[i] - diffuse[i] * (1.0 - 0.04))
                            .abs()
                            .max((s2[i] - specular[i]).abs())
                    })
                    .fold(0.0, f32::max);
                any = any.max(err);
            }
        }
        // Dielectric.
        let mr = convert(SpecGloss {
            diffuse: [d, d * 0.5, d * 0.25, 1.0],
            specular: [0.04; 3],
            glossiness: 0.5,
        });
        let (d2, s2) = round_trip(mr);
        for ((got_d, got_s), want_d) in d2.iter().zip(s2).zip([d, d * 0.5, d * 0.25]) {
            physical = physical.max((got_d - want_d * 0.96).abs());
            physical = physical.max((got_s - 0.04).abs());
        }
    }
    // Metals.
    for &s in &steps[1..] {
        let specular = [s, s * 0.8, s * 0.6];
        let mr = convert(SpecGloss {
            diffuse: [0.0, 0.0, 0.0, 1.0],
            specular,
            glossiness: 1.0,
        });
        if specular.iter().all(|&c| c >= 0.04) {
            let (_, s2) = round_trip(mr);
            for (got, want) in s2.iter().zip(specular) {
                physical = physical.max((got - want).abs());
            }
        }
    }
    assert!(physical < 1e-4, "physical inputs: {physical}");
    // The sweep's worst (a half metal, coloured speculars): docs/gltf.md quotes it.
    assert!(any < 0.25, "any input: {any}");
    assert!(
        any > 0.2,
        "the sweep reaches the documented worst case: {any}"
    );
    eprintln!("spec-gloss round trip: physical {physical:e}, worst {any}");
}

#[test]
fn spec_gloss_maps_convert_per_texel() {
    let mut doc = cube_with(named("Painted"), "{}");
    // Diffuse: mid grey | black. Spec-gloss: f0 0.04 with gloss 1 | gold with gloss 0.5 (alpha 128).
    let diffuse = image::RgbaImage::from_raw(2, 1, vec![188, 188, 188, 255, 0, 0, 0, 255]).unwrap();
    let sg = image::RgbaImage::from_raw(2, 1, vec![56, 56, 56, 255, 250, 210, 100, 128]).unwrap();
    let d = doc.png_image(&png(&diffuse));
    let d = doc.texture(d);
    let s = doc.png_image(&png(&sg));
    let s = doc.texture(s);
    let ext = format!(
        r#"{{"KHR_materials_pbrSpecularGlossiness": {{"diffuseTexture": {{"index": {}}},
            "specularGlossinessTexture": {{"index": {}}}}}}}"#,
        d.value(),
        s.value()
    );
    doc.root.materials[0].extensions = Some(json::extensions::material::Material {
        others: value(&ext).as_object().cloned().unwrap_or_default(),
        ..Default::default()
    });
    let (m, warnings) = load_one(doc);
    assert!(warnings.is_empty(), "{warnings:?}");
    let base = m
        .base_color_texture
        .as_ref()
        .expect("converted base colour map");
    let mr = m
        .metallic_roughness_texture
        .as_ref()
        .expect("converted metal-rough map");
    assert!(base.srgb && !mr.srgb);
    assert_eq!((base.image.width, base.image.height), (2, 1));
    assert_eq!(m.base_color, [1.0; 4]);
    // Left texel: dielectric, the diffuse kept (sRGB 188), roughness 0.
    assert_eq!(&mr.image.rgba8[0..4], &[0, 0, 0, 255]);
    assert!(
        (i32::from(base.image.rgba8[0]) - 188).abs() <= 1,
        "{:?}",
        &base.image.rgba8[0..4]
    );
    // Right texel: a metal, roughness 1 - 128/255, base colour its specular colour.
    assert!(
        mr.image.rgba8[6] > 250,
        "metallic {:?}",
        &mr.image.rgba8[4..8]
    );
    assert!((i32::from(mr.image.rgba8[5]) - 127).abs() <= 1);
    for (got, want) in base.image.rgba8[4..7].iter().zip([250, 210, 100]) {
        assert!(
            (i32::from(*got) - want).abs() <= 2,
            "{:?}",
            &base.image.rgba8[4..8]
        );
    }
    // A map index that does not exist: warned, drawn without it.
    let ext = r#"{"KHR_materials_pbrSpecularGlossiness": {"diffuseTexture": {"index": 9}}}"#;
    let (m, warnings) = load_one(cube_with(named("Lost"), ext));
    assert!(m.base_color_texture.is_none());
    assert!(
        warnings
            .iter()
            .any(|w| w.contains("`Lost`") && w.contains("diffuseTexture")),
        "{warnings:?}"
    );
}

#[test]
fn the_supported_material_extensions_may_be_required() {
    let mut doc = cube_with(
        named("Coat"),
        r#"{"KHR_materials_clearcoat": {"clearcoatFactor": 1}}"#,
    );
    doc.root.extensions_required = vec![
        "KHR_materials_clearcoat".into(),
        "KHR_materials_unlit".into(),
        "KHR_materials_pbrSpecularGlossiness".into(),
    ];
    // glTF: what a file requires it also lists as used.
    doc.root.extensions_used = doc.root.extensions_required.clone();
    let scene = load_gltf_slice(&doc.glb(), None).expect("supported extensions are accepted");
    assert!(scene.warnings.is_empty(), "{:?}", scene.warnings);
    // Volume is read: a file may require it.
    let mut doc = cube_with(named("Thick"), "{}");
    doc.root.extensions_required = vec!["KHR_materials_volume".into()];
    doc.root.extensions_used = doc.root.extensions_required.clone();
    load_gltf_slice(&doc.glb(), None).expect("volume is supported");
    // Sheen is read: a file that requires it loads.
    let mut doc = cube_with(
        named("Velvet"),
        r#"{"KHR_materials_sheen": {"sheenColorFactor": [0.5, 0.2, 0.8]}}"#,
    );
    doc.root.extensions_required = vec!["KHR_materials_sheen".into()];
    let scene = load_gltf_slice(&doc.glb(), None).expect("sheen is supported");
    assert!(scene.warnings.is_empty(), "{:?}", scene.warnings);
    // One that is not read is refused by name.
    let mut doc = cube_with(named("Leaf"), "{}");
    doc.root.extensions_required = vec!["KHR_materials_diffuse_transmission".into()];
    doc.root.extensions_used = doc.root.extensions_required.clone();
    let err = load_gltf_slice(&doc.glb(), None).expect_err("refused");
    assert!(
        err.to_string()
            .contains("KHR_materials_diffuse_transmission"),
        "{err}"
    );
}

#[test]
fn sheen_factors_become_the_sheen_feature_and_bad_ones_are_warned() {
    let (m, warnings) = load_one(cube_with(
        named("Velvet"),
        r#"{"KHR_materials_sheen": {"sheenColorFactor": [0.5, 0.2, 0.8], "sheenRoughnessFactor": 0.3}}"#,
    ));
    assert!(warnings.is_empty(), "{warnings:?}");
    assert_eq!(params(&m, Feature::Sheen), Some([0.5, 0.2, 0.8, 0.3]));
    // No extension, or a black sheen (the extension's default): no feature.
    let (plain, _) = load_one(cube_with(named("Plain"), "{}"));
    assert_eq!(params(&plain, Feature::Sheen), None);
    let (black, _) = load_one(cube_with(
        named("Black"),
        r#"{"KHR_materials_sheen": {"sheenRoughnessFactor": 0.5}}"#,
    ));
    assert_eq!(params(&black, Feature::Sheen), None);
    // Out of range: clamped; not numbers: the default; maps: warned, not
    // sampled. Each warning names the material.
    let (wild, warnings) = load_one(cube_with(
        named("Wild"),
        r#"{"KHR_materials_sheen": {"sheenColorFactor": [2.0, -1.0, 0.5],
            "sheenRoughnessFactor": 1.5, "sheenRoughnessTexture": {"index": 0}}}"#,
    ));
    assert_eq!(params(&wild, Feature::Sheen), Some([1.0, 0.0, 0.5, 1.0]));
    assert_finite(&wild);
    assert_eq!(warnings.len(), 3, "{warnings:?}");
    assert!(
        warnings.iter().all(|w| w.contains("material 0 `Wild`")),
        "{warnings:?}"
    );
    let (nan, warnings) = load_one(cube_with(
        named("Nan"),
        r#"{"KHR_materials_sheen": {"sheenColorFactor": "red", "sheenRoughnessFactor": "x"}}"#,
    ));
    assert_eq!(params(&nan, Feature::Sheen), None);
    assert_finite(&nan);
    assert_eq!(warnings.len(), 2, "{warnings:?}");
}

#[test]
fn no_extension_value_makes_a_material_non_finite() {
    let ext = r#"{"KHR_materials_ior": {"ior": 1e39},
        "KHR_materials_specular": {"specularFactor": 1e39, "specularColorFactor": [1e39, 1e39, 1e39]},
        "KHR_materials_clearcoat": {"clearcoatFactor": 1e39, "clearcoatRoughnessFactor": "x"},
        "KHR_materials_transmission": {"transmissionFactor": -1e39},
        "KHR_materials_emissive_strength": {"emissiveStrength": 1e30}}"#;
    let (m, warnings) = load_one(cube_with(named("Wild"), ext));
    assert_finite(&m);
    assert!((0.0..=1.0).contains(&m.reflectance()));
    assert!(!warnings.is_empty());
    let sg = convert(SpecGloss {
        diffuse: [f32::NAN, f32::INFINITY, -1.0, 2.0],
        specular: [f32::NAN; 3],
        glossiness: f32::INFINITY,
    });
    let MetalRough {
        base_color,
        metallic,
        roughness,
    } = sg;
    assert!(
        base_color
            .iter()
            .chain([&metallic, &roughness])
            .all(|v| v.is_finite())
    );
}

#[test]
fn the_sheen_asset_is_what_the_generator_makes_and_loads_clean() {
    // patches/assets/gltf-sheen.gltf (docs/gltf.md's picture, `spreadlight
    // view` of it) is the committed output of the generator.
    let path = std::path::Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("../../patches/assets/gltf-sheen.gltf");
    let made = super::models::sheen_row();
    // Its baseline without the sheens, for `spreadlight bench` (docs/gltf.md).
    let off_path = path.with_file_name("gltf-sheen-off.gltf");
    let off = super::models::sheen_row_without_sheen();
    // Its mapped twin, the cost of the sheen and film target.
    let maps_path = path.with_file_name("gltf-sheen-maps.gltf");
    let mapped = super::models::sheen_row_with_maps();
    if std::env::var_os("SPREADLIGHT_BLESS").is_some() {
        std::fs::write(&path, &made).unwrap();
        std::fs::write(&off_path, &off).unwrap();
        std::fs::write(&maps_path, &mapped).unwrap();
    }
    let committed = std::fs::read(&maps_path).expect("patches/assets/gltf-sheen-maps.gltf");
    assert!(
        committed == mapped,
        "regenerate it with SPREADLIGHT_BLESS=1"
    );
    let scene = load_gltf_slice(&mapped, None).expect("loads");
    assert!(scene.warnings.is_empty(), "{:?}", scene.warnings);
    let with_maps: Vec<bool> = scene
        .materials
        .iter()
        .map(|m| m.sheen_color_texture.is_some() && m.sheen_roughness_texture.is_some())
        .collect();
    assert_eq!(with_maps, [false, true, true, true]);
    let committed = std::fs::read(&path).expect("patches/assets/gltf-sheen.gltf");
    assert!(committed == made, "regenerate it with SPREADLIGHT_BLESS=1");
    let committed = std::fs::read(&off_path).expect("patches/assets/gltf-sheen-off.gltf");
    assert!(committed == off, "regenerate it with SPREADLIGHT_BLESS=1");
    let plain = load_gltf_slice(&off, None).expect("loads");
    assert!(
        plain
            .materials
            .iter()
            .all(|m| params(m, Feature::Sheen).is_none())
    );
    let scene = load_gltf_slice(&made, None).expect("loads");
    assert!(scene.warnings.is_empty(), "{:?}", scene.warnings);
    let sheens: Vec<_> = scene
        .materials
        .iter()
        .map(|m| params(m, Feature::Sheen))
        .collect();
    assert_eq!(sheens[0], None);
    assert_eq!(sheens[1], Some([1.0, 1.0, 1.0, 0.3]));
    assert_eq!(sheens[3], Some([1.0, 1.0, 1.0, 0.9]));
}

#[test]
fn the_extensions_row_asset_is_what_the_generator_makes_and_loads_clean() {
    // patches/assets/gltf-material-extensions.gltf (docs/gltf.md's picture,
    // `spreadlight view` of it) is the committed output of the generator.
    let path = std::path::Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("../../patches/assets/gltf-material-extensions.gltf");
    let made = super::models::material_extensions_row();
    if std::env::var_os("SPREADLIGHT_BLESS").is_some() {
        std::fs::write(&path, &made).unwrap();
    }
    let committed = std::fs::read(&path).unwrap();
    assert!(
        committed == made,
        "{} is stale: regenerate with SPREADLIGHT_BLESS=1",
        path.display()
    );
    let scene = load_gltf_slice(&made, None).unwrap();
    let by_name = |name: &str| {
        scene
            .materials
            .iter()
            .find(|m| m.name.as_deref() == Some(name))
            .unwrap_or_else(|| panic!("{name}"))
    };
    assert!(by_name("Unlit").unlit);
    assert_eq!(by_name("Clearcoat").clearcoat, 1.0);
    assert!(by_name("Specular").reflectance() > 0.06);
    assert!(by_name("SpecGloss").from_spec_gloss && by_name("SpecGloss").metallic > 0.99);
    assert_eq!(by_name("Transmission").alpha_mode, AlphaMode::Blend);
    // The one warning: transmission drawn as blending.
    assert_eq!(scene.warnings.len(), 1, "{:?}", scene.warnings);
}

#[test]
fn material_variants_map_each_primitive_and_an_unknown_one_lists_the_files() {
    let made = super::models::material_variants();
    // patches/assets/gltf-variants.gltf (docs/gltf.md's picture, `spreadlight
    // view --variant` of it) is the committed output of the generator.
    let path = std::path::Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("../../patches/assets/gltf-variants.gltf");
    if std::env::var_os("SPREADLIGHT_BLESS").is_some() {
        std::fs::write(&path, &made).expect("bless the asset");
    }
    assert!(
        std::fs::read(&path).expect("the committed asset") == made,
        "{} is stale: regenerate with SPREADLIGHT_BLESS=1",
        path.display()
    );
    let scene = load_gltf_slice(&made, None).expect("loads");
    assert!(scene.warnings.is_empty(), "{:?}", scene.warnings);
    assert_eq!(scene.variants, ["Forest", "Ocean"]);
    let shown = |scene: &GltfScene, variant: Option<usize>| -> Vec<String> {
        scene
            .instances
            .iter()
            .map(|i| {
                let m = i.material_in(variant).expect("a material");
                scene.materials[m].name.clone().unwrap_or_default()
            })
            .collect()
    };
    // Body, then lid: the lid has no Forest mapping and keeps its default.
    assert_eq!(shown(&scene, None), ["Red", "White"]);
    for (choice, want) in [
        ("", ["Red", "White"]),
        ("Forest", ["Green", "White"]),
        ("0", ["Green", "White"]),
        ("Ocean", ["Blue", "Black"]),
        (" 1 ", ["Blue", "Black"]),
    ] {
        let variant = scene.variant(choice).expect("known");
        assert_eq!(shown(&scene, variant), want, "`{choice}`");
    }
    // The material colour each variant gives the body.
    let body =
        |v: Option<usize>| scene.materials[scene.instances[0].material_in(v).unwrap()].base_color;
    assert_eq!(body(Some(1)), [0.05, 0.05, 0.8, 1.0]);
    for unknown in ["Desert", "2", "-1"] {
        let e = scene.variant(unknown).expect_err("unknown");
        let text = e.to_string();
        assert!(
            text.contains(&format!("`{unknown}`")) && text.contains("`Forest`, `Ocean`"),
            "{text}"
        );
    }
    // A file may require the extension; one without variants names none.
    let mut json: Value = json::deserialize::from_slice(&made).expect("JSON");
    json["extensionsRequired"] = value(r#"["KHR_materials_variants"]"#);
    load_gltf_slice(&json::serialize::to_vec(&json).expect("JSON"), None).expect("required");
    let plain = load_gltf_slice(&super::models::textured_cube(), None).expect("loads");
    assert!(plain.variants.is_empty());
    assert!(
        plain
            .instances
            .iter()
            .all(|i| i.variant_materials.is_empty())
    );
    let e = plain.variant("Forest").expect_err("no variants");
    assert!(
        e.to_string().contains("no KHR_materials_variants variants"),
        "{e}"
    );
}

#[test]
fn malformed_variant_mappings_are_warned_by_primitive_and_left_out() {
    let mut json: Value =
        json::deserialize::from_slice(&super::models::material_variants()).expect("JSON");
    // The body: a material the file lacks, a variant it lacks beside one it
    // has, no material, and variant 1 mapped twice; the lid: no mappings.
    json["meshes"][0]["primitives"][0]["extensions"]["KHR_materials_variants"]["mappings"] = value(
        r#"[{"material": 99, "variants": [0]}, {"material": 1, "variants": [5, 0]},
            {"variants": [1]}, {"material": 2, "variants": [1]}, {"material": 3, "variants": [1]}]"#,
    );
    json["meshes"][1]["primitives"][0]["extensions"]["KHR_materials_variants"] = value("{}");
    json["extensions"]["KHR_materials_variants"]["variants"][1] = value("{}");
    let scene =
        load_gltf_slice(&json::serialize::to_vec(&json).expect("JSON"), None).expect("loads");
    let w = &scene.warnings;
    let said = |text: &str| {
        assert!(w.iter().any(|m| m.contains(text)), "`{text}` in {w:?}");
    };
    said(
        "mesh 0 `Body` primitive 0: KHR_materials_variants mappings[0] names material 99, the file has 5; ignored",
    );
    said("mappings[1] names variant 5, the file has 2; ignored");
    said("mappings[2] has no material index; ignored");
    said("mappings[4] maps variant 1 again; its first mapping is kept");
    said("mesh 1 `Lid` primitive 0: KHR_materials_variants has no `mappings` array; ignored");
    said("variants[1] has no name: `variant 1` used");
    assert_eq!(scene.variants, ["Forest", "variant 1"]);
    let body = &scene.instances[0];
    assert_eq!(body.variant_materials, [Some(1), Some(2)]);
    assert_eq!(scene.instances[1].variant_materials, [None, None]);
    assert_eq!(scene.instances[1].material_in(Some(1)), Some(3));
}
