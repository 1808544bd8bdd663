//! The robustness sweep: for each class of malformed (or unusual but valid)
//! file the loader was read against, a test that it fails with an error
//! naming the file, the object and the problem, or that it loads as other
//! viewers show it. None of them may panic.

use gltf::json;
use json::accessor::{ComponentType, Type};
use json::mesh::Semantic;
use json::validation::Checked::Valid;
use json::validation::USize64;

use super::builder::{Doc, bytes, info, mesh_node, png_2x2};
use super::*;
use spreadlight_render::mesh::primitives::{BoxParams, box_mesh};

/// A cube (accessors: 0 POSITION, 1 NORMAL, 2 TEXCOORD_0, 3 indices; one
/// view each) on node 0.
fn cube_doc() -> Doc {
    let mut doc = Doc::new();
    let mesh = doc.mesh_data("Cube", &box_mesh(BoxParams::default()));
    let node = doc.node(mesh_node(Some(mesh), [0.0; 3], 1.0));
    doc.scene(vec![node]);
    doc
}

/// The cube with a base colour texture (texture 0 of image 0) on material 0.
fn textured_cube_doc() -> Doc {
    let mut doc = cube_doc();
    let png = doc.png_image(&png_2x2());
    let texture = doc.texture(png);
    let mut material = json::Material::default();
    material.pbr_metallic_roughness.base_color_texture = Some(info(texture));
    let material = doc.material(material);
    doc.root.meshes[0].primitives[0].material = Some(material);
    doc
}

fn edited(doc: Doc, edit: impl FnOnce(&mut json::Value)) -> Vec<u8> {
    let mut value: json::Value =
        json::deserialize::from_slice(&doc.gltf_data_uri()).expect("our own JSON");
    edit(&mut value);
    json::serialize::to_vec(&value).expect("serialize")
}

fn value(text: &str) -> json::Value {
    json::deserialize::from_str(text).expect("JSON")
}

fn error(bytes: &[u8]) -> String {
    match load_gltf_slice(bytes, None) {
        Ok(_) => panic!("the file loaded"),
        Err(e) => e.to_string(),
    }
}

fn assert_names(message: &str, parts: &[&str]) {
    assert!(message.starts_with("<memory>: "), "no file: {message}");
    for part in parts {
        assert!(message.contains(part), "`{part}` missing: {message}");
    }
}

#[test]
fn a_byte_stride_smaller_than_its_element_is_refused() {
    let mut doc = cube_doc();
    doc.root.buffer_views[0].byte_stride = Some(json::buffer::Stride(8));
    assert_names(
        &error(&doc.gltf_data_uri()),
        &[
            "accessor 0 (POSITION of mesh 0 `Cube`, primitive 0)",
            "byte stride of 8, less than one element (12 bytes)",
        ],
    );
}

#[test]
fn accessors_and_views_past_their_buffer_end_are_refused() {
    // An accessor offset that pushes its last element past its view.
    let mut doc = cube_doc();
    doc.root.accessors[1].byte_offset = Some(USize64(4));
    assert_names(
        &error(&doc.gltf_data_uri()),
        &[
            "accessor 1 (NORMAL of mesh 0 `Cube`, primitive 0)",
            "24 elements of 12 bytes from byte 4",
            "do not fit in buffer view 1",
        ],
    );
    // A view reaching past its buffer.
    let mut doc = cube_doc();
    doc.root.buffer_views[1].byte_length = USize64(1 << 20);
    assert_names(
        &error(&doc.gltf_data_uri()),
        &[
            "accessor 1 (NORMAL of mesh 0 `Cube`, primitive 0)",
            "buffer view 1",
            "lies outside buffer 0",
        ],
    );
    // A buffer declaring more bytes than its data has.
    let bytes = edited(cube_doc(), |v| {
        v["buffers"][0]["byteLength"] = value("100000")
    });
    assert_names(&error(&bytes), &["buffer 0", "declares 100000 bytes"]);
}

#[test]
fn sparse_indices_out_of_range_are_refused() {
    let mut doc = cube_doc();
    let indices = doc.view(&bytes(&[99u16, 0]));
    let values = doc.view(&bytes(&[0.25f32, 0.75]));
    doc.root.accessors[2].sparse = Some(json::accessor::sparse::Sparse {
        count: USize64(1),
        indices: json::accessor::sparse::Indices {
            buffer_view: indices,
            byte_offset: USize64(0),
            component_type: Valid(json::accessor::IndexComponentType(ComponentType::U16)),
            extensions: None,
            extras: Default::default(),
        },
        values: json::accessor::sparse::Values {
            buffer_view: values,
            byte_offset: USize64(0),
            extensions: None,
            extras: Default::default(),
        },
        extensions: None,
        extras: Default::default(),
    });
    assert_names(
        &error(&doc.gltf_data_uri()),
        &[
            "accessor 2 (TEXCOORD_0 of mesh 0 `Cube`, primitive 0)",
            "sparse index 0 is 99, but there are 24 elements",
        ],
    );
}

#[test]
fn textures_of_missing_images_or_samplers_are_refused() {
    let mut doc = textured_cube_doc();
    doc.root.textures[0].source = json::Index::new(5);
    assert_names(&error(&doc.gltf_data_uri()), &["textures[0].source"]);
    let mut doc = textured_cube_doc();
    doc.root.textures[0].sampler = Some(json::Index::new(3));
    assert_names(&error(&doc.gltf_data_uri()), &["textures[0].sampler"]);
    // An image that is not one.
    let mut doc = cube_doc();
    let png = doc.png_image(b"not a png at all");
    let texture = doc.texture(png);
    let material = doc.material(json::Material {
        emissive_texture: Some(info(texture)),
        ..Default::default()
    });
    doc.root.meshes[0].primitives[0].material = Some(material);
    assert_names(&error(&doc.gltf_data_uri()), &["image 0", "cannot decode"]);
}

#[test]
fn a_texture_without_source_is_drawn_without_it() {
    // Valid glTF: an extension (KTX2, WebP) would supply the image.
    let bytes = edited(textured_cube_doc(), |v| {
        v["textures"][0]
            .as_object_mut()
            .expect("a texture")
            .remove("source");
        v["textures"][0]["extensions"] = value(r#"{"EXT_texture_webp": {"source": 0}}"#);
        v["extensionsUsed"] = value(r#"["EXT_texture_webp"]"#);
    });
    let scene = load_gltf_slice(&bytes, None).expect("loads");
    assert!(scene.materials[0].base_color_texture.is_none());
    assert_eq!(
        scene.warnings,
        vec![
            "extension `EXT_texture_webp` is not supported; what it adds is ignored".to_owned(),
            "material 0, base colour texture: texture 0 has no image this loader reads (no `source`); drawn without it".to_owned(),
        ]
    );
}

#[test]
fn a_texture_transform_tex_coord_override_picks_the_uv_set() {
    let mut doc = textured_cube_doc();
    let material = &mut doc.root.materials[0];
    material.emissive_texture = material.pbr_metallic_roughness.base_color_texture.clone();
    // The base colour texture says set 1, its transform overrides with 0:
    // the cube (which has no TEXCOORD_1) is not warned about. The emissive
    // texture's override asks for set 4: mapped with set 0, warned once.
    let bytes = edited(doc, |v| {
        v["extensionsUsed"] = value(r#"["KHR_texture_transform"]"#);
        let m = &mut v["materials"][0];
        m["pbrMetallicRoughness"]["baseColorTexture"]["texCoord"] = value("1");
        m["pbrMetallicRoughness"]["baseColorTexture"]["extensions"] =
            value(r#"{"KHR_texture_transform": {"offset": [0.5, 0.0], "texCoord": 0}}"#);
        m["emissiveTexture"]["extensions"] = value(r#"{"KHR_texture_transform": {"texCoord": 4}}"#);
    });
    let scene = load_gltf_slice(&bytes, None).expect("loads");
    let m = &scene.materials[0];
    let base = m.base_color_texture.as_ref().expect("base colour");
    assert_eq!((base.tex_coord, base.transform.offset), (0, [0.5, 0.0]));
    assert_eq!(m.emissive_texture.as_ref().expect("emissive").tex_coord, 0);
    assert_eq!(
        scene.warnings,
        vec!["material 0, emissive texture uses TEXCOORD_4; meshes carry TEXCOORD_0 and TEXCOORD_1, so it is mapped with TEXCOORD_0".to_owned()]
    );
    // The other way round: texCoord 0 overridden with 1 on a mesh without
    // TEXCOORD_1 is warned about (set 0 stands in).
    let mut doc = textured_cube_doc();
    doc.root.materials[0].emissive_texture = None;
    let bytes = edited(doc, |v| {
        v["extensionsUsed"] = value(r#"["KHR_texture_transform"]"#);
        v["materials"][0]["pbrMetallicRoughness"]["baseColorTexture"]["extensions"] =
            value(r#"{"KHR_texture_transform": {"texCoord": 1}}"#);
    });
    let scene = load_gltf_slice(&bytes, None).expect("loads");
    assert_eq!(
        scene.materials[0]
            .base_color_texture
            .as_ref()
            .expect("base colour")
            .tex_coord,
        1
    );
    assert_eq!(
        scene.warnings,
        vec!["mesh 0 `Cube`, primitive 0: its material maps a texture with TEXCOORD_1, which it lacks; TEXCOORD_0 stands in".to_owned()]
    );
}

#[test]
fn cameras_with_zero_aspect_near_or_magnification_give_finite_projections() {
    let bytes = edited(cube_doc(), |v| {
        v["cameras"] = value(
            r#"[
                {"type": "perspective", "perspective": {"aspectRatio": 0.0, "yfov": 0.0, "znear": 0.0, "zfar": 0.0}},
                {"type": "orthographic", "orthographic": {"xmag": 0.0, "ymag": 0.0, "znear": 0.0, "zfar": 0.0}},
                {"type": "perspective", "perspective": {"yfov": 1.0, "znear": 1e38}}
            ]"#,
        );
        v["nodes"][0]["camera"] = value("0");
        v["nodes"].as_array_mut().expect("nodes").extend([
            value(r#"{"camera": 1, "translation": [0, 0, 5]}"#),
            value(r#"{"camera": 2, "scale": [0, 0, 0]}"#),
        ]);
        v["scenes"][0]["nodes"] = value("[0, 1, 2]");
    });
    let scene = load_gltf_slice(&bytes, None).expect("loads");
    assert_eq!(scene.cameras.len(), 3);
    for camera in &scene.cameras {
        let projection = camera.projection_for(16.0 / 9.0);
        // Finite, and a point before the camera lands in front of it.
        let clip = projection * glam::Vec4::new(0.0, 0.0, -2.0, 1.0);
        assert!(
            projection.is_finite() && clip.is_finite() && clip.w > 0.0,
            "{}: {projection}",
            camera.name
        );
        assert!(camera.view.is_finite(), "{}: {}", camera.name, camera.view);
    }
    assert_eq!(scene.cameras[0].aspect_ratio, None, "aspect 0 is none");
}

#[test]
fn a_camera_without_its_projection_object_is_refused() {
    let bytes = edited(cube_doc(), |v| {
        v["cameras"] = value(
            r#"[{"name": "Eye", "type": "perspective", "orthographic": {"xmag": 1, "ymag": 1, "znear": 0, "zfar": 10}}]"#,
        );
        v["nodes"][0]["camera"] = value("0");
    });
    assert_names(
        &error(&bytes),
        &[
            "cameras[0] `Eye`",
            "its type is perspective but it has no `perspective` object",
        ],
    );
}

#[test]
fn a_skin_with_no_joints_is_refused_where_weights_use_it() {
    let mut doc = cube_doc();
    let joints = doc.view(&bytes(&[[0u8; 4]; 24]));
    let joints = doc.accessor(Some(joints), 24, ComponentType::U8, Type::Vec4);
    let weights = doc.floats(&[[1.0f32, 0.0, 0.0, 0.0]; 24]);
    let prim = &mut doc.root.meshes[0].primitives[0];
    prim.attributes.insert(Valid(Semantic::Joints(0)), joints);
    prim.attributes.insert(Valid(Semantic::Weights(0)), weights);
    let bytes = edited(doc, |v| {
        v["skins"] = value(r#"[{"name": "Empty", "joints": []}]"#);
        v["nodes"][0]["skin"] = value("0");
    });
    match load_gltf_slice(&bytes, None) {
        // Refused by validation (joints must not be empty) or by the skin check.
        Err(e) => {
            let message = e.to_string();
            assert!(message.starts_with("<memory>: "), "{message}");
            assert!(
                message.contains("skins[0].joints")
                    || (message.contains("skin 0 `Empty`")
                        && message.contains("uses joint 0, but the skin has 0 joints")),
                "{message}"
            );
        }
        Ok(_) => panic!("a skin without joints loaded"),
    }
    // Without weights on the mesh the empty skin is ignored, with a warning.
    let bytes = edited(cube_doc(), |v| {
        v["skins"] = value(r#"[{"name": "Empty", "joints": []}]"#);
        v["nodes"][0]["skin"] = value("0");
    });
    let scene = load_gltf_slice(&bytes, None).expect("loads");
    assert_eq!(scene.instances.len(), 1);
    assert!(
        scene
            .warnings
            .iter()
            .any(|w| w.contains("the skin is ignored")),
        "{:?}",
        scene.warnings
    );
}

#[test]
fn a_node_light_without_the_files_lights_is_refused() {
    let bytes = edited(cube_doc(), |v| {
        v["extensionsUsed"] = value(r#"["KHR_lights_punctual"]"#);
        v["nodes"][0]["extensions"] = value(r#"{"KHR_lights_punctual": {"light": 3}}"#);
    });
    assert_names(&error(&bytes), &["nodes[0]", "light"]);
}

#[test]
fn lights_of_extreme_range_and_intensity_stay_finite() {
    let bytes = edited(cube_doc(), |v| {
        v["extensionsUsed"] = value(r#"["KHR_lights_punctual"]"#);
        v["extensions"] = value(
            r#"{"KHR_lights_punctual": {"lights": [
                {"type": "spot", "range": 3e38, "intensity": 3e38, "spot": {"innerConeAngle": 2.0, "outerConeAngle": 0.0}},
                {"type": "spot", "intensity": 3e38, "spot": {}},
                {"type": "point", "range": 3e38, "intensity": -5}
            ]}}"#,
        );
        v["nodes"].as_array_mut().expect("nodes").extend([
            value(r#"{"extensions": {"KHR_lights_punctual": {"light": 0}}}"#),
            value(r#"{"extensions": {"KHR_lights_punctual": {"light": 1}}}"#),
            value(r#"{"extensions": {"KHR_lights_punctual": {"light": 2}}}"#),
        ]);
        v["scenes"][0]["nodes"] = value("[0, 1, 2, 3]");
    });
    let scene = load_gltf_slice(&bytes, None).expect("loads");
    assert_eq!(scene.lights.spots.len(), 2);
    for (name, spot) in &scene.lights.spots {
        assert!(
            spot.projection.is_finite() && spot.view.is_finite(),
            "{name}: {spot:?}"
        );
    }
    let (_, point) = &scene.lights.points[0];
    assert!(
        point.range.is_finite() && point.intensity == 0.0,
        "{point:?}"
    );
}
