//! `KHR_materials_volume` and `KHR_materials_transmission`'s map over files
//! written at test time: the values read, the absorption's numbers
//! (Beer-Lambert), the hard cases (zero thickness, an infinite or missing
//! attenuation distance, black attenuation, ior 1), and the transmission
//! map baked into the base colour's alpha texel by texel.

use super::builder::png;
use super::material_extensions_tests::{
    assert_close, assert_finite, cube_with, load_one, named, value,
};
use super::*;
use spreadlight_render::material::Feature;

/// `doc`'s one material gets the extension objects of `ext` (a format
/// string's output, naming textures the test added).
fn with_extensions(doc: &mut builder::Doc, ext: &str) {
    let others = value(ext).as_object().cloned().unwrap_or_default();
    for name in others.keys() {
        if !doc.root.extensions_used.contains(name) {
            doc.root.extensions_used.push(name.clone());
        }
    }
    doc.root.materials[0].extensions = Some(gltf_json::extensions::material::Material {
        others,
        ..Default::default()
    });
}

/// A texture of `pixels` (RGBA rows, `width` wide) added to `doc`.
fn texture(doc: &mut builder::Doc, width: u32, pixels: Vec<u8>) -> u32 {
    let height = pixels.len() as u32 / 4 / width;
    let image = image::RgbaImage::from_raw(width, height, pixels).expect("test pixels");
    let image = doc.png_image(&png(&image));
    doc.texture(image).value() as u32
}

#[test]
fn volume_values_are_read_and_absorb_by_beer_lambert() {
    let ext = r#"{"KHR_materials_transmission": {"transmissionFactor": 1},
        "KHR_materials_volume": {"thicknessFactor": 0.5, "attenuationColor": [0.5, 0.25, 1.0],
        "attenuationDistance": 2.0}}"#;
    let (m, warnings) = load_one(cube_with(named("Tinted"), ext));
    assert_eq!(m.thickness, 0.5);
    assert_eq!(m.attenuation_color, [0.5, 0.25, 1.0]);
    assert_eq!(m.attenuation_distance, 2.0);
    // c^(t/d): after the thickness (a quarter of the distance), and after
    // the distance itself (the attenuation colour, as the extension defines it).
    let t = m.transmittance(0.5);
    for (got, want) in t.iter().zip([0.5f32.powf(0.25), 0.25f32.powf(0.25), 1.0]) {
        assert_close(*got, want, 1e-6, "transmittance through the thickness");
    }
    for (got, want) in m.transmittance(2.0).iter().zip([0.5, 0.25, 1.0]) {
        assert_close(*got, want, 1e-6, "transmittance at the distance");
    }
    // Drawn: the Transmission feature carries ior, thickness and
    // σ = -ln(c) / d, so exp(-σ t) is the transmittance above.
    assert!(
        warnings.iter().all(|w| !w.contains("absorption")),
        "{warnings:?}"
    );
    let material = m.to_material();
    let p = material
        .params(Feature::Transmission)
        .expect("a Transmission feature");
    assert_eq!(p[0], [1.0, 1.5, 0.5, 0.0]);
    for (c, (sigma, want)) in p[1][..3].iter().zip(t).enumerate() {
        assert_close(
            (-sigma * 0.5).exp(),
            want,
            1e-6,
            &format!("exp(-σ t), channel {c}"),
        );
    }
}

#[test]
fn dispersion_reaches_the_transmission_feature_and_bad_values_are_warned() {
    let glass = |dispersion: &str| {
        let ext = format!(
            r#"{{"KHR_materials_transmission": {{"transmissionFactor": 1}},
            "KHR_materials_volume": {{"thicknessFactor": 0.5}},
            "KHR_materials_dispersion": {{"dispersion": {dispersion}}}}}"#
        );
        let (m, warnings) = load_one(cube_with(named("Flint"), &ext));
        let p = m
            .to_material()
            .params(Feature::Transmission)
            .expect("a Transmission feature")
            .to_vec();
        (m, warnings, p)
    };
    // An Abbe number of 20: dispersion 1, the second vec4's fourth.
    let (m, warnings, p) = glass("1.0");
    assert_eq!(m.dispersion, 1.0);
    assert_eq!(p[1][3], 1.0);
    assert!(
        warnings.iter().all(|w| !w.contains("dispersion")),
        "{warnings:?}"
    );
    // Large values are the extension's (no upper bound) and kept.
    assert_eq!(glass("40").2[1][3], 40.0);
    // Negative, not a number: warned naming the material, 0 (no dispersion).
    for bad in ["-2", "\"x\"", "1e39"] {
        let (m, warnings, p) = glass(bad);
        assert_eq!(m.dispersion, 0.0, "{bad}");
        assert_eq!(p[1][3], 0.0, "{bad}");
        assert!(
            warnings
                .iter()
                .any(|w| w.contains("material 0 `Flint`") && w.contains("dispersion")),
            "{bad}: {warnings:?}"
        );
        assert_finite(&m);
    }
    // A file may require it.
    let mut doc = cube_with(
        named("Flint"),
        r#"{"KHR_materials_dispersion": {"dispersion": 0.5}}"#,
    );
    doc.root.extensions_required = vec!["KHR_materials_dispersion".into()];
    let scene = load_gltf_slice(&doc.glb(), None).expect("dispersion is supported");
    assert_eq!(scene.materials[0].dispersion, 0.5);
}

#[test]
fn volume_hard_cases_stay_finite_and_in_range() {
    // No volume object values: thin-walled, infinite distance, no absorption.
    let (thin, warnings) = load_one(cube_with(named("Thin"), r#"{"KHR_materials_volume": {}}"#));
    assert!(warnings.is_empty(), "{warnings:?}");
    assert_eq!(thin.thickness, 0.0);
    assert_eq!(thin.attenuation_distance, f32::INFINITY);
    assert_eq!(thin.transmittance(1e30), [1.0; 3]);
    // Zero thickness: nothing absorbed, whatever the colour and distance.
    let (zero, _) = load_one(cube_with(
        named("Zero"),
        r#"{"KHR_materials_volume": {"thicknessFactor": 0, "attenuationColor": [0, 0, 0],
            "attenuationDistance": 0.001}}"#,
    ));
    assert_eq!(zero.transmittance(zero.thickness), [1.0; 3]);
    // A black channel absorbs everything along any path, and an infinite
    // path leaves nothing of a grey one: 0, not NaN.
    assert_eq!(zero.transmittance(1.0), [0.0; 3]);
    let grey = MaterialData {
        attenuation_color: [0.5; 3],
        attenuation_distance: 1e-30,
        ..MaterialData::default()
    };
    assert_eq!(grey.transmittance(f32::INFINITY), [0.0; 3]);
    assert_eq!(grey.transmittance(1e30), [0.0; 3]);
    assert_eq!(grey.transmittance(f32::NAN), [1.0; 3]);
    assert_eq!(grey.transmittance(-1.0), [1.0; 3]);
    // Bad values: warned, naming the material, and replaced.
    let (bad, warnings) = load_one(cube_with(
        named("Bad"),
        r#"{"KHR_materials_volume": {"thicknessFactor": -2, "attenuationDistance": 0,
            "attenuationColor": [2, -1, "x"]}}"#,
    ));
    assert_eq!(bad.thickness, 0.0);
    assert_eq!(bad.attenuation_distance, f32::INFINITY);
    assert_eq!(bad.attenuation_color, [1.0; 3]);
    for what in [
        "thicknessFactor is -2",
        "attenuationDistance is 0",
        "attenuationColor",
    ] {
        assert!(
            warnings
                .iter()
                .any(|w| w.contains("`Bad`") && w.contains(what)),
            "{what}: {warnings:?}"
        );
    }
    let (far, warnings) = load_one(cube_with(
        named("Far"),
        r#"{"KHR_materials_volume": {"attenuationDistance": -1e39, "thicknessFactor": 1e39}}"#,
    ));
    assert_eq!(far.attenuation_distance, f32::INFINITY);
    assert_eq!(far.thickness, 0.0);
    assert_eq!(warnings.len(), 2, "{warnings:?}");
    for m in [&thin, &zero, &bad, &far] {
        assert_finite(m);
        assert!(
            m.transmittance(m.thickness)
                .iter()
                .all(|t| (0.0..=1.0).contains(t))
        );
    }
}

#[test]
fn ior_one_gives_no_dielectric_reflection_and_stays_finite() {
    // ior 1: the surface does not reflect ((1 - 1) / (1 + 1))² = 0, with a
    // transmissive volume behind it.
    let ext = r#"{"KHR_materials_ior": {"ior": 1.0},
        "KHR_materials_transmission": {"transmissionFactor": 0.5},
        "KHR_materials_volume": {"thicknessFactor": 1, "attenuationDistance": 1}}"#;
    let (m, _) = load_one(cube_with(named("Air"), ext));
    assert_eq!(m.ior, 1.0);
    assert_eq!(m.reflectance(), 0.0);
    assert_eq!(
        m.transmittance(1.0),
        [1.0; 3],
        "white attenuation absorbs nothing"
    );
    assert_finite(&m);
}

#[test]
fn the_transmission_map_is_baked_into_the_base_colour_alpha() {
    let mut doc = cube_with(named("Window"), "{}");
    // Transmission map: red 0 (the frame) | 255 (the pane) | 128.
    let t = texture(
        &mut doc,
        3,
        vec![0, 0, 0, 255, 255, 0, 0, 255, 128, 0, 0, 255],
    );
    with_extensions(
        &mut doc,
        &format!(
            r#"{{"KHR_materials_transmission": {{"transmissionFactor": 0.8,
                "transmissionTexture": {{"index": {t}}}}}}}"#
        ),
    );
    let (m, warnings) = load_one(doc);
    assert_eq!(m.alpha_mode, AlphaMode::Blend);
    // The factor's alpha stays: the map carries the transmission.
    assert_eq!(m.base_color[3], 1.0);
    assert!(m.transmission_texture.is_some());
    let base = m
        .base_color_texture
        .as_ref()
        .expect("a baked base colour map");
    assert!(base.srgb);
    assert_eq!((base.image.width, base.image.height), (3, 1));
    let alpha: Vec<u8> = base.image.rgba8.chunks(4).map(|p| p[3]).collect();
    // 255 x (1 - 0.8 x red / 255): 255, 51, 255 x (1 - 0.8 x 128/255) = 152.6.
    assert_eq!(alpha, vec![255, 51, 153]);
    assert!(
        base.image
            .rgba8
            .chunks(4)
            .all(|p| p[..3] == [255, 255, 255])
    );
    assert!(
        warnings
            .iter()
            .any(|w| w.contains("`Window`") && w.contains("transmissionTexture")),
        "{warnings:?}"
    );
}

#[test]
fn the_transmission_map_keeps_the_base_colour_and_its_alpha() {
    let mut doc = cube_with(named("Stained"), "{}");
    // Base colour 2x1: red, half-transparent blue. Transmission 1x1: full.
    let base = texture(&mut doc, 2, vec![255, 0, 0, 255, 0, 0, 255, 128]);
    let t = texture(&mut doc, 1, vec![255, 255, 255, 255]);
    doc.root.materials[0]
        .pbr_metallic_roughness
        .base_color_texture = Some(builder::info(gltf_json::Index::new(base)));
    with_extensions(
        &mut doc,
        &format!(
            r#"{{"KHR_materials_transmission": {{"transmissionFactor": 0.5,
                "transmissionTexture": {{"index": {t}}}}}}}"#
        ),
    );
    let (m, _) = load_one(doc);
    let baked = m.base_color_texture.as_ref().expect("baked");
    assert_eq!((baked.image.width, baked.image.height), (2, 1));
    // Colours as stored; alpha x (1 - 0.5): 128 and 64.
    assert_eq!(baked.image.rgba8, vec![255, 0, 0, 128, 0, 0, 255, 64]);
}

#[test]
fn the_clearcoat_and_specular_maps_are_read_and_become_surface_maps() {
    let mut doc = cube_with(named("Maps"), "{}");
    let t = texture(&mut doc, 1, vec![200, 100, 50, 25]);
    with_extensions(
        &mut doc,
        &format!(
            r#"{{"KHR_materials_clearcoat": {{"clearcoatFactor": 1, "clearcoatTexture": {{"index": {t}}},
                "clearcoatRoughnessTexture": {{"index": {t}}}, "clearcoatNormalTexture": {{"index": {t}, "scale": 0.5}}}},
              "KHR_materials_specular": {{"specularTexture": {{"index": {t}}},
                "specularColorTexture": {{"index": {t}}}}},
              "KHR_materials_volume": {{"thicknessFactor": 0.1, "thicknessTexture": {{"index": {t}}}}}}}"#
        ),
    );
    let (m, warnings) = load_one(doc);
    for (name, map, srgb) in [
        ("clearcoat", &m.clearcoat_texture, false),
        ("clearcoat roughness", &m.clearcoat_roughness_texture, false),
        ("clearcoat normal", &m.clearcoat_normal_texture, false),
        ("specular", &m.specular_texture, false),
        ("specular colour", &m.specular_color_texture, true),
        ("thickness", &m.thickness_texture, false),
    ] {
        let map = map.as_ref().unwrap_or_else(|| panic!("{name} map"));
        assert_eq!(map.image.rgba8, vec![200, 100, 50, 25], "{name}");
        assert_eq!(map.srgb, srgb, "{name}");
    }
    // The coat's normal map is sampled too: nothing says otherwise.
    assert!(
        !warnings
            .iter()
            .any(|w| w.contains("not sampled") || w.contains("clearcoat")),
        "{warnings:?}"
    );
    assert_eq!(m.clearcoat_normal_scale, 0.5);
    // They become the material's surface maps, in their slots; the
    // thickness map only for a material that transmits (this one does not).
    let material = m.to_material();
    let maps = material.maps().expect("surface maps");
    use spreadlight_render::material::maps::MapSlot;
    for slot in [
        MapSlot::Clearcoat,
        MapSlot::ClearcoatRoughness,
        MapSlot::ClearcoatNormal,
        MapSlot::Specular,
        MapSlot::SpecularColor,
    ] {
        assert!(maps.map(slot).is_some(), "{slot:?}");
    }
    assert_eq!(maps.clearcoat_normal_scale, 0.5);
    assert!(maps.map(MapSlot::Thickness).is_none());
    assert!(maps.has_extension_maps());
    // White specular colour, ior 1.5, factor 1: glTF's f0.
    assert_eq!(maps.specular.f0_color, [0.04; 3]);
    assert_eq!(maps.specular.factor, 1.0);
}

#[test]
fn the_window_asset_is_what_the_generator_makes_and_bakes_its_frame() {
    // patches/assets/gltf-transmission-window.gltf (docs/gltf.md's picture)
    // is the committed output of the generator.
    let path = std::path::Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("../../patches/assets/gltf-transmission-window.gltf");
    let made = super::models::transmission_window();
    if std::env::var_os("SPREADLIGHT_BLESS").is_some() {
        std::fs::write(&path, &made).expect("bless the asset");
    }
    let committed = std::fs::read(&path).expect("the committed asset");
    assert!(
        committed == made,
        "{} is stale: regenerate with SPREADLIGHT_BLESS=1",
        path.display()
    );
    let scene = load_gltf_slice(&made, None).expect("loads");
    let window = scene
        .materials
        .iter()
        .find(|m| m.name.as_deref() == Some("Window"))
        .expect("the window");
    let map = window.base_color_texture.as_ref().expect("the baked map");
    let alpha = |x: usize, y: usize| map.image.rgba8[(y * map.image.width as usize + x) * 4 + 3];
    // The frame is opaque; a pane lets 0.9 through: 255 x 0.1 = 25.5.
    assert_eq!(alpha(0, 0), 255);
    assert_eq!(alpha(32, 10), 255);
    assert_eq!(alpha(16, 16), 26);
}

#[test]
fn the_refraction_asset_is_what_the_generator_makes_and_refracts() {
    // patches/assets/gltf-refraction.gltf (docs/gltf.md's picture of
    // refracted transmission) is the committed output of the generator.
    let path = std::path::Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("../../patches/assets/gltf-refraction.gltf");
    let made = super::models::refraction_block();
    if std::env::var_os("SPREADLIGHT_BLESS").is_some() {
        std::fs::write(&path, &made).expect("bless the asset");
    }
    let committed = std::fs::read(&path).expect("the committed asset");
    assert!(
        committed == made,
        "{} is stale: regenerate with SPREADLIGHT_BLESS=1",
        path.display()
    );
    let scene = load_gltf_slice(&made, None).expect("loads");
    let glass = scene
        .materials
        .iter()
        .find(|m| m.name.as_deref() == Some("Glass"))
        .expect("the glass");
    // Fully transmissive: opacity 0, all of what shows through refracted
    // with the file's ior, thickness and absorption.
    assert_eq!(glass.alpha_mode, AlphaMode::Blend);
    assert_eq!(glass.base_color[3], 0.0);
    let material = glass.to_material();
    let p = material
        .params(Feature::Transmission)
        .expect("a Transmission feature");
    assert_eq!(p[0], [1.0, 1.5, 0.5, 0.0]);
    for (sigma, c) in p[1][..3].iter().zip([0.6f32, 0.85, 1.0]) {
        assert_close(*sigma, -c.ln() / 0.8, 1e-6, "σ = -ln(c) / d");
    }
}

#[test]
fn the_dispersion_asset_is_what_the_generator_makes_and_disperses() {
    // patches/assets/gltf-dispersion.gltf (docs/gltf.md's picture of
    // dispersion, and its bench scene) is the committed output of the
    // generator: the refraction block's scene with dispersion 20.
    let path = std::path::Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("../../patches/assets/gltf-dispersion.gltf");
    let made = super::models::dispersion_block();
    if std::env::var_os("SPREADLIGHT_BLESS").is_some() {
        std::fs::write(&path, &made).expect("bless the asset");
    }
    let committed = std::fs::read(&path).expect("the committed asset");
    assert!(
        committed == made,
        "{} is stale: regenerate with SPREADLIGHT_BLESS=1",
        path.display()
    );
    let scene = load_gltf_slice(&made, None).expect("loads");
    let plain = load_gltf_slice(&super::models::refraction_block(), None).expect("loads");
    let glass = |s: &GltfScene| {
        s.materials
            .iter()
            .find(|m| m.name.as_deref() == Some("Glass"))
            .expect("the glass")
            .to_material()
            .params(Feature::Transmission)
            .expect("a Transmission feature")
            .to_vec()
    };
    let (dispersive, refracting) = (glass(&scene), glass(&plain));
    assert_eq!(dispersive[1][3], 20.0);
    assert_eq!(refracting[1][3], 0.0);
    // Otherwise the same glass.
    assert_eq!(dispersive[0], refracting[0]);
    assert_eq!(dispersive[1][..3], refracting[1][..3]);
}
