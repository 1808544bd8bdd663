//! CPU-side checks of materials and their packing; the GPU side is in
//! crates/render/tests/material.rs.

use super::*;

#[test]
fn feature_ids_flags_and_names() {
    assert_eq!(Feature::CookTorrance.flag(), 1);
    assert_eq!(Feature::AmbientOcclusion.id(), 5);
    assert_eq!(Feature::from_id(2), Ok(Feature::FakeSss));
    assert_eq!(Feature::from_id(16), Ok(Feature::Custom(16)));
    assert_eq!(Feature::Custom(31).flag(), 1 << 31);
    assert_eq!(Feature::from_id(7), Ok(Feature::Clearcoat));
    assert_eq!(Feature::from_id(8), Ok(Feature::Unlit));
    assert_eq!(Feature::from_id(9), Ok(Feature::Transmission));
    assert_eq!(Feature::from_id(10), Ok(Feature::Sheen));
    assert_eq!(Feature::from_id(11), Ok(Feature::Iridescence));
    assert_eq!(Feature::from_id(12), Ok(Feature::Anisotropy));
    for bad in [-1, 6, 13, 15, 32, 1 << 40] {
        assert_eq!(
            Feature::from_id(bad),
            Err(FeatureError::UnknownFeature { id: bad })
        );
    }
    // In ascending id, each once; 6 (SurfaceMaps) is set through `set_maps`.
    let ids: Vec<u32> = Feature::BUILT_IN.iter().map(|f| f.id()).collect();
    assert_eq!(ids, [0, 1, 2, 3, 4, 5, 7, 8, 9, 10, 11, 12]);
    for f in Feature::BUILT_IN {
        // Transmission: refraction, then absorption.
        let count = if f == Feature::Transmission { 2 } else { 1 };
        assert_eq!(f.param_count(), Some(count));
        assert_eq!(Feature::from_id(i64::from(f.id())), Ok(f));
    }
    assert_eq!(Feature::FakeSss.name(), "FakeSSS");
}

#[test]
fn parameters_are_clamped_to_physical_ranges() {
    let m = Material::new()
        .with(Feature::CookTorrance, &[[1.5, -0.2, 0.04, 7.0]])
        .and_then(|m| m.with(Feature::Emission, &[[-1.0, 2.0, 0.5, -3.0]]))
        .and_then(|m| m.with(Feature::Custom(20), &[[-5.0, 1e6, 0.0, 1.0], [1.0; 4]]))
        .expect("finite parameters");
    assert_eq!(
        m.params(Feature::CookTorrance),
        Some(&[[1.0, 0.0, 0.04, 0.0]][..])
    );
    assert_eq!(
        m.params(Feature::Emission),
        Some(&[[0.0, 2.0, 0.5, 0.0]][..])
    );
    assert_eq!(
        m.params(Feature::Custom(20)).map(<[_]>::len),
        Some(2),
        "custom features keep any count and any finite value"
    );
    assert_eq!(m.params(Feature::Custom(20)).unwrap()[0][0], -5.0);
    assert_eq!(m.flags(), 0b11 | 1 << 20);
}

#[test]
fn setting_a_feature_again_replaces_it() {
    let mut m = Material::default_material();
    m.set(Feature::CookTorrance, &[[0.1, 1.0, 0.5, 0.0]])
        .expect("valid");
    assert_eq!(m.features().count(), 1);
    assert_eq!(m.params(Feature::CookTorrance).unwrap()[0][0], 0.1);
    m.remove(Feature::CookTorrance);
    assert_eq!(m.flags(), 0);
}

#[test]
fn non_finite_parameters_are_refused_naming_material_and_feature() {
    let err = Material::new()
        .with(Feature::Reflection, &[[f32::NAN, 0.0, 0.0, 0.0]])
        .expect_err("NaN");
    assert_eq!(
        err,
        FeatureError::NonFinite {
            feature: "Reflection".to_owned(),
            index: 0,
            component: 0
        }
    );
    let message = err.in_material(3).to_string();
    assert!(
        message.contains("material 3") && message.contains("Reflection"),
        "{message}"
    );
    let unused_inf = Material::new().with(Feature::MatCap, &[[1.0, f32::INFINITY, 0.0, 0.0]]);
    assert!(unused_inf.is_err(), "even unused components must be finite");
    let count = Material::new().with(Feature::Emission, &[]);
    assert!(matches!(
        count,
        Err(FeatureError::ParamCount {
            expected: 1,
            got: 0,
            ..
        })
    ));
}

#[test]
fn packing_follows_emeshes_three_buffers() {
    let a = Material::default_material()
        .with(Feature::Emission, &[[1.0, 0.5, 0.25, 2.0]])
        .expect("valid");
    let b = Material::new();
    let c = Material::new()
        .with(
            Feature::Custom(17),
            &[[1.0, 2.0, 3.0, 4.0], [5.0, 6.0, 7.0, 8.0]],
        )
        .and_then(|m| m.with(Feature::AmbientOcclusion, &[[0.5, 0.0, 0.0, 0.0]]))
        .expect("valid");
    let packed = PackedMaterials::pack(&[a, b, c]);
    let meta = |flags, address, size| GpuMaterialMeta {
        flags,
        address,
        size,
        pad: 0,
    };
    assert_eq!(
        packed.meta,
        [
            meta(0b11, 0, 2),
            meta(0, 2, 0),
            meta(1 << 5 | 1 << 17, 2, 2)
        ]
    );
    let entry = |feature, offset, count| GpuFeatureOffset {
        maps: [0; 4],
        feature,
        offset,
        count,
        texture: 0,
    };
    // Ascending feature id within a material: AO (5) before custom 17.
    assert_eq!(
        packed.offsets,
        [
            entry(0, 0, 1),
            entry(1, 1, 1),
            entry(5, 2, 1),
            entry(17, 3, 2)
        ]
    );
    assert_eq!(packed.data.len(), 5);
    assert_eq!(packed.data[1], [1.0, 0.5, 0.25, 2.0]);
    assert_eq!(packed.data[4], [5.0, 6.0, 7.0, 8.0]);
}

#[test]
fn a_feature_texture_packs_as_its_layer_plus_one_and_only_with_its_feature() {
    let mut m = Material::default_material();
    assert!(!m.has_textures());
    m.set_texture(Feature::CookTorrance, Some(0));
    // A texture for a feature the material lacks is kept but not packed.
    m.set_texture(Feature::Emission, Some(3));
    assert_eq!(m.texture(Feature::CookTorrance), Some(0));
    assert_eq!(m.texture(Feature::Emission), None);
    let packed = PackedMaterials::pack(std::slice::from_ref(&m));
    assert_eq!(packed.offsets.len(), 1);
    assert_eq!(packed.offsets[0].texture, 1);
    m.set(Feature::Emission, &[[1.0, 1.0, 1.0, 1.0]])
        .expect("valid");
    let packed = PackedMaterials::pack(std::slice::from_ref(&m));
    assert_eq!(
        packed.offsets.iter().map(|o| o.texture).collect::<Vec<_>>(),
        [1, 4]
    );
    m.set_texture(Feature::CookTorrance, None);
    m.remove(Feature::Emission);
    assert!(!m.has_textures());
}

#[test]
fn every_parameter_of_a_built_in_feature_can_have_its_own_layer() {
    let mut m = Material::default_material()
        .with(Feature::Emission, &[[1.0, 0.5, 0.25, 2.0]])
        .expect("valid");
    assert_eq!(m.component_maps(Feature::CookTorrance), [0; 4]);
    // The feature's Texture ID: component k by channel k of its layer.
    m.set_texture(Feature::CookTorrance, Some(2));
    assert_eq!(
        m.component_maps(Feature::CookTorrance),
        [3, 3 | 1 << 24, 3 | 2 << 24, 3 | 3 << 24]
    );
    // Metallic (parameter 1) alone by layer 5's red channel: the others keep the Texture ID.
    m.set_param_texture(Feature::CookTorrance, 1, Some(5));
    assert_eq!(m.param_texture(Feature::CookTorrance, 1), Some(5));
    assert_eq!(
        m.component_maps(Feature::CookTorrance),
        [3, 6, 3 | 2 << 24, 3 | 3 << 24]
    );
    // Emission's colour by a layer's rgb, its strength (parameter 1) by another's red.
    m.set_param_texture(Feature::Emission, 0, Some(0));
    m.set_param_texture(Feature::Emission, 1, Some(7));
    assert_eq!(
        m.component_maps(Feature::Emission),
        [1, 1 | 1 << 24, 1 | 2 << 24, 8]
    );
    assert!(m.has_textures());
    let packed = PackedMaterials::pack(std::slice::from_ref(&m));
    assert_eq!(packed.offsets[1].maps, [1, 1 | 1 << 24, 1 | 2 << 24, 8]);
    assert_eq!(packed.offsets[1].texture, 0, "no Texture ID of its own");
    // A parameter map alone makes the material textured; removing the feature drops it.
    m.set_texture(Feature::CookTorrance, None);
    m.set_param_texture(Feature::CookTorrance, 1, None);
    m.remove(Feature::Emission);
    assert!(!m.has_textures());
    assert_eq!(m.component_maps(Feature::Emission), [0; 4]);
    // MatCap's Texture ID is its image, never a scale.
    let mut matcap = Material::new()
        .with(Feature::MatCap, &[[1.0, 0.0, 0.0, 0.0]])
        .expect("valid");
    matcap.set_texture(Feature::MatCap, Some(0));
    assert_eq!(matcap.component_maps(Feature::MatCap), [0; 4]);
}

#[test]
fn surface_maps_pack_in_id_order_with_their_places() {
    use maps::{MapImage, MapRef, SurfaceMaps};
    let image = Arc::new(MapImage {
        width: 300,
        height: 20,
        rgba8: vec![255; 300 * 20 * 4],
    });
    let mut surface = SurfaceMaps::default();
    surface.set_map(MapSlot::MetallicRoughness, Some(MapRef::new(image)));
    let mut m = Material::default_material()
        .with(Feature::AmbientOcclusion, &[[1.0, 0.0, 0.0, 0.0]])
        .and_then(|m| m.with(Feature::Custom(16), &[[2.0; 4]]))
        .expect("finite");
    m.set_maps(Some(Arc::new(surface)));
    assert_eq!(m.flags(), 1 | 1 << 5 | 1 << FEATURE_SURFACE_MAPS | 1 << 16);
    let mut layout = MapLayout::new();
    let map = m.maps().unwrap().map(MapSlot::MetallicRoughness).unwrap();
    layout.place(map, MapSlot::MetallicRoughness, 256);
    let packed = PackedMaterials::pack_with(&[m], Some(&layout));
    let ids: Vec<u32> = packed.offsets.iter().map(|o| o.feature).collect();
    assert_eq!(
        ids,
        vec![0, 5, FEATURE_SURFACE_MAPS, 16],
        "ascending, as the shader finds them"
    );
    let maps = packed.offsets[2];
    assert_eq!(maps.count as usize, maps::PARAM_COUNT);
    // The 300-texel map is in the 512 class (index 3), linear: array 6, layer 0.
    let slot = packed.data[(maps.offset + 1 + 2 * MapSlot::MetallicRoughness as u32) as usize];
    assert_eq!(slot[0], (6 * 65536 + 1) as f32);
    assert_eq!(packed.data[(packed.offsets[3].offset) as usize], [2.0; 4]);
}

#[test]
fn worlds_with_the_same_maps_share_their_upload() {
    use maps::{MapImage, MapRef, SurfaceMaps};
    let renderer = crate::renderer::test_renderer();
    let image = Arc::new(MapImage {
        width: 16,
        height: 16,
        rgba8: vec![200; 16 * 16 * 4],
    });
    let material = |roughness: f32| {
        let mut surface = SurfaceMaps::default();
        surface.set_map(MapSlot::BaseColor, Some(MapRef::new(image.clone())));
        let mut m = Material::new()
            .with(Feature::CookTorrance, &[[roughness, 0.0, 0.04, 0.0]])
            .expect("finite");
        m.set_maps(Some(Arc::new(surface)));
        m
    };
    let a = MaterialWorld::new(&renderer, vec![material(0.2)]);
    // A changed factor, the same image: no new upload.
    let b = MaterialWorld::new(&renderer, vec![material(0.7)]);
    let (ta, tb) = (
        &a.world_maps().unwrap().textures,
        &b.world_maps().unwrap().textures,
    );
    assert!(Arc::ptr_eq(ta, tb));
    // Another image: a new upload.
    let other = Arc::new(MapImage {
        width: 16,
        height: 16,
        rgba8: vec![10; 16 * 16 * 4],
    });
    let mut surface = SurfaceMaps::default();
    surface.set_map(MapSlot::BaseColor, Some(MapRef::new(other)));
    let mut m = Material::default_material();
    m.set_maps(Some(Arc::new(surface)));
    let c = MaterialWorld::new(&renderer, vec![m]);
    assert!(!Arc::ptr_eq(ta, &c.world_maps().unwrap().textures));
}
