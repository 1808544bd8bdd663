//! glTF import tests over files written at test time (see `builder`).

use glam::{Mat4, Vec3};
use gltf_json as json;
use json::accessor::{ComponentType, Type};
use json::mesh::{Mode, Semantic};
use json::validation::Checked::Valid;
use json::validation::USize64;

use super::builder::{Doc, bytes, mesh_node, png_2x2, primitive};
use super::*;
use spreadlight_render::mesh::primitives::{BoxParams, box_mesh};

fn write(dir: &Path, name: &str, data: &[u8]) -> PathBuf {
    let path = dir.join(name);
    std::fs::write(&path, data).unwrap();
    path
}

/// A document with one cube mesh on one node in one scene.
fn cube_doc() -> Doc {
    let mut doc = Doc::new();
    let mesh = doc.mesh_data("Cube", &box_mesh(BoxParams::default()));
    let node = doc.node(mesh_node(Some(mesh), [0.0; 3], 1.0));
    doc.scene(vec![node]);
    doc
}

#[test]
fn cube_with_data_uri_buffer() {
    let dir = tempfile::tempdir().unwrap();
    let path = write(dir.path(), "cube.gltf", &cube_doc().gltf_data_uri());
    let scene = load_gltf(&path).unwrap();
    let cube = box_mesh(BoxParams::default());
    assert_eq!(scene.meshes.len(), 1);
    let m = &scene.meshes[0];
    assert_eq!(m.positions, cube.positions);
    assert_eq!(m.normals, cube.normals);
    assert_eq!(m.uvs, cube.uvs);
    assert_eq!(m.indices, cube.indices);
    // The file has no tangents: MikkTSpace makes the same ones the generator did.
    assert_eq!(m.tangents, cube.tangents);
    assert_eq!(m.validate(), Ok(()));
    assert_eq!(
        scene.instances,
        vec![MeshInstance {
            mesh: 0,
            transform: Mat4::IDENTITY,
            material: None,
            node: 0,
            skin: None,
            weights: Vec::new(),
            variant_materials: Vec::new(),
        }]
    );
    assert_eq!(scene.bounds, cube.bounds);
    assert!(scene.warnings.is_empty(), "{:?}", scene.warnings);
    assert!(scene.materials.is_empty());
}

#[test]
fn glb_with_embedded_buffer_and_png_texture() {
    let mut doc = cube_doc();
    let png = doc.view(&png_2x2());
    let image = doc.root.push(json::Image {
        buffer_view: Some(png),
        mime_type: Some(json::image::MimeType("image/png".into())),
        name: None,
        uri: None,
        extensions: None,
        extras: Default::default(),
    });
    let texture = doc.root.push(json::Texture {
        name: None,
        sampler: None,
        source: image,
        extensions: None,
        extras: Default::default(),
    });
    let info = json::texture::Info {
        index: texture,
        tex_coord: 0,
        extensions: None,
        extras: Default::default(),
    };
    let mut material = json::Material {
        name: Some("Painted".into()),
        alpha_mode: Valid(json::material::AlphaMode::Mask),
        alpha_cutoff: Some(json::material::AlphaCutoff(0.25)),
        double_sided: true,
        emissive_factor: json::material::EmissiveFactor([0.5, 0.0, 0.0]),
        ..Default::default()
    };
    material.pbr_metallic_roughness.base_color_factor =
        json::material::PbrBaseColorFactor([0.5, 0.5, 0.5, 1.0]);
    material.pbr_metallic_roughness.metallic_factor = json::material::StrengthFactor(0.0);
    material.pbr_metallic_roughness.roughness_factor = json::material::StrengthFactor(0.75);
    material.pbr_metallic_roughness.base_color_texture = Some(info.clone());
    material.emissive_texture = Some(info);
    let material = doc.root.push(material);
    doc.root.meshes[0].primitives[0].material = Some(material);

    let scene = load_gltf_slice(&doc.glb(), None).unwrap();
    assert_eq!(scene.meshes.len(), 1);
    assert_eq!(scene.instances[0].material, Some(0));
    let m = &scene.materials[0];
    assert_eq!(m.name.as_deref(), Some("Painted"));
    assert_eq!(m.base_color, [0.5, 0.5, 0.5, 1.0]);
    assert_eq!((m.metallic, m.roughness), (0.0, 0.75));
    assert_eq!(m.emissive, [0.5, 0.0, 0.0]);
    assert_eq!(m.alpha_mode, AlphaMode::Mask { cutoff: 0.25 });
    assert!(m.double_sided);
    let t = m.base_color_texture.as_ref().unwrap();
    assert_eq!((t.image.width, t.image.height, t.srgb), (2, 2, true));
    assert_eq!(&t.image.rgba8[..8], &[255, 0, 0, 255, 0, 255, 0, 255]);
    assert_eq!(t.image.rgba8.len(), 16);
    // One image for both slots, decoded once.
    let emissive = m.emissive_texture.as_ref().unwrap();
    assert!(std::sync::Arc::ptr_eq(&t.image, &emissive.image));
    assert!(!emissive.srgb || emissive.srgb == t.srgb);
    assert!(m.normal_texture.is_none() && m.occlusion_texture.is_none());
}

#[test]
fn node_hierarchy_gives_world_transforms() {
    let mut doc = Doc::new();
    let mesh = doc.mesh_data("Cube", &box_mesh(BoxParams::default()));
    let child = doc.node(mesh_node(Some(mesh), [0.0, 1.0, 0.0], 1.0));
    let mut parent = mesh_node(Some(mesh), [1.0, 0.0, 0.0], 2.0);
    parent.children = Some(vec![child]);
    let parent = doc.node(parent);
    // Two scenes; the default is the second, which holds the hierarchy.
    let lone = doc.node(mesh_node(Some(mesh), [100.0, 0.0, 0.0], 1.0));
    doc.scene(vec![lone]);
    let default = doc.scene(vec![parent]);
    doc.root.scene = Some(default);

    let scene = load_gltf_slice(&doc.gltf_data_uri(), None).unwrap();
    assert_eq!(scene.meshes.len(), 1);
    assert_eq!(scene.instances.len(), 2);
    let parent_world = Mat4::from_translation(Vec3::X) * Mat4::from_scale(Vec3::splat(2.0));
    assert_eq!(scene.instances[0].transform, parent_world);
    let child_world = scene.instances[1].transform;
    assert!(child_world.abs_diff_eq(parent_world * Mat4::from_translation(Vec3::Y), 1e-6));
    assert_eq!(
        child_world.transform_point3(Vec3::ZERO),
        Vec3::new(1.0, 2.0, 0.0)
    );
    // Both cubes have size 2 in the world: x in [0, 2], y in [-1, 3].
    assert!((scene.bounds.min - Vec3::new(0.0, -1.0, -1.0)).length() < 1e-6);
    assert!((scene.bounds.max - Vec3::new(2.0, 3.0, 1.0)).length() < 1e-6);
}

#[test]
fn without_scenes_every_root_node_is_shown() {
    let mut doc = Doc::new();
    let mesh = doc.mesh_data("Cube", &box_mesh(BoxParams::default()));
    let child = doc.node(mesh_node(Some(mesh), [0.0, 5.0, 0.0], 1.0));
    let mut parent = mesh_node(None, [1.0, 0.0, 0.0], 1.0);
    parent.children = Some(vec![child]);
    doc.node(parent);
    doc.node(mesh_node(Some(mesh), [-3.0, 0.0, 0.0], 1.0));
    let scene = load_gltf_slice(&doc.gltf_data_uri(), None).unwrap();
    let origins: Vec<Vec3> = scene
        .instances
        .iter()
        .map(|i| i.transform.transform_point3(Vec3::ZERO))
        .collect();
    assert_eq!(
        origins,
        vec![Vec3::new(1.0, 5.0, 0.0), Vec3::new(-3.0, 0.0, 0.0)]
    );
}

#[test]
fn missing_normals_are_made_flat() {
    let mut doc = Doc::new();
    let p = doc.positions(&[
        [0.0, 0.0, 0.0],
        [1.0, 0.0, 0.0],
        [1.0, 1.0, 0.0],
        [0.0, 1.0, 0.0],
    ]);
    let uv = doc.floats(&[[0.0, 1.0], [1.0, 1.0], [1.0, 0.0], [0.0, 0.0]]);
    let i = doc.indices(&[0, 1, 2, 0, 2, 3]);
    let mesh = doc.mesh(
        "Quad",
        vec![primitive(
            &[(Semantic::Positions, p), (Semantic::TexCoords(0), uv)],
            Some(i),
            Mode::Triangles,
        )],
    );
    let node = doc.node(mesh_node(Some(mesh), [0.0; 3], 1.0));
    doc.scene(vec![node]);
    let scene = load_gltf_slice(&doc.gltf_data_uri(), None).unwrap();
    let m = &scene.meshes[0];
    assert_eq!(
        m.vertex_count(),
        6,
        "flat shading gives each triangle its own corners"
    );
    assert!(m.normals.iter().all(|&n| n == [0.0, 0.0, 1.0]));
    let tangents = m.tangents.as_ref().unwrap();
    assert!(
        tangents
            .iter()
            .all(|t| (Vec3::new(t[0], t[1], t[2]) - Vec3::X).length() < 1e-5)
    );
    assert_eq!(m.validate(), Ok(()));
}

#[test]
fn strips_and_fans_become_lists_and_points_are_skipped() {
    let mut doc = Doc::new();
    let p = doc.positions(&[
        [0.0, 0.0, 0.0],
        [1.0, 0.0, 0.0],
        [0.0, 1.0, 0.0],
        [1.0, 1.0, 0.0],
    ]);
    let n = doc.floats(&[[0.0, 0.0, 1.0f32]; 4]);
    let attrs = [(Semantic::Positions, p), (Semantic::Normals, n)];
    let mesh = doc.mesh(
        "Mixed",
        vec![
            primitive(&attrs, None, Mode::TriangleStrip),
            primitive(&attrs, None, Mode::Points),
            primitive(&attrs, None, Mode::TriangleFan),
            primitive(&attrs, None, Mode::Lines),
        ],
    );
    let node = doc.node(mesh_node(Some(mesh), [0.0; 3], 1.0));
    doc.scene(vec![node]);
    let scene = load_gltf_slice(&doc.gltf_data_uri(), None).unwrap();
    assert_eq!(scene.meshes.len(), 2);
    // Strip 0 1 2 3: triangles (0 1 2), (1 3 2), both counter-clockwise about +Z.
    assert_eq!(scene.meshes[0].indices, vec![0, 1, 2, 1, 3, 2]);
    // Fan 0 1 2 3: triangles (1 2 0), (2 3 0).
    assert_eq!(scene.meshes[1].indices, vec![1, 2, 0, 2, 3, 0]);
    assert_eq!(scene.instances.len(), 2);
    assert_eq!(scene.instances[1].mesh, 1);
    assert_eq!(scene.warnings.len(), 2, "{:?}", scene.warnings);
    assert!(scene.warnings[0].contains("mesh 0 `Mixed`, primitive 1"));
    assert!(scene.warnings[0].contains("Points"));
    assert!(scene.warnings[1].contains("Lines"));
    // No UVs in the file: none in the mesh, and so no tangents.
    assert!(scene.meshes[0].uvs.is_none() && scene.meshes[0].tangents.is_none());
}

#[test]
fn sparse_and_normalised_accessors() {
    let mut doc = Doc::new();
    let p = doc.positions(&[[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0]]);
    // Replace vertex 2 with (0, 2, 0) through a sparse substitution.
    let sparse_indices = doc.view(&bytes(&[2u16, 0]));
    let sparse_values = doc.view(&bytes(&[0.0f32, 2.0, 0.0]));
    doc.root.accessors[p.value()].sparse = Some(json::accessor::sparse::Sparse {
        count: USize64(1),
        indices: json::accessor::sparse::Indices {
            buffer_view: sparse_indices,
            byte_offset: USize64(0),
            component_type: Valid(json::accessor::IndexComponentType(ComponentType::U16)),
            extensions: None,
            extras: Default::default(),
        },
        values: json::accessor::sparse::Values {
            buffer_view: sparse_values,
            byte_offset: USize64(0),
            extensions: None,
            extras: Default::default(),
        },
        extensions: None,
        extras: Default::default(),
    });
    doc.root.accessors[p.value()].max = Some(json::Value::from(vec![1.0, 2.0, 0.0]));
    // UVs as normalised unsigned bytes.
    let uv_view = doc.view(&[0u8, 255, 255, 255, 0, 0, 0, 0]);
    let uv = doc.accessor(Some(uv_view), 3, ComponentType::U8, Type::Vec2);
    doc.root.accessors[uv.value()].normalized = true;
    let mesh = doc.mesh(
        "Tri",
        vec![primitive(
            &[(Semantic::Positions, p), (Semantic::TexCoords(0), uv)],
            None,
            Mode::Triangles,
        )],
    );
    let node = doc.node(mesh_node(Some(mesh), [0.0; 3], 1.0));
    doc.scene(vec![node]);
    let scene = load_gltf_slice(&doc.gltf_data_uri(), None).unwrap();
    let m = &scene.meshes[0];
    assert_eq!(m.positions[2], [0.0, 2.0, 0.0]);
    assert_eq!(
        m.uvs.as_ref().unwrap()[..3],
        [[0.0, 1.0], [1.0, 1.0], [0.0, 0.0]]
    );
}

#[test]
fn required_extension_is_refused_by_name() {
    let mut doc = cube_doc();
    doc.root.extensions_used = vec!["KHR_draco_mesh_compression".into()];
    doc.root.extensions_required = vec!["KHR_draco_mesh_compression".into()];
    let dir = tempfile::tempdir().unwrap();
    let path = write(dir.path(), "draco.gltf", &doc.gltf_data_uri());
    let err = load_gltf(&path).unwrap_err();
    assert!(
        matches!(&err, GltfError::UnsupportedExtension { extension, .. } if extension == "KHR_draco_mesh_compression")
    );
    let message = err.to_string();
    assert!(message.contains("draco.gltf"), "{message}");
    assert!(
        message.contains("`KHR_draco_mesh_compression`"),
        "{message}"
    );
}

#[test]
fn missing_bin_is_named() {
    let dir = tempfile::tempdir().unwrap();
    // The URI is percent-encoded; the file it names is `cube data.bin`.
    let path = cube_doc().gltf_external(dir.path(), "cube.gltf", "cube%20data.bin", None);
    let err = load_gltf(&path).unwrap_err();
    let message = err.to_string();
    assert!(matches!(err, GltfError::MissingFile { .. }), "{message}");
    assert!(message.contains("cube.gltf"), "{message}");
    assert!(message.contains("buffer 0"), "{message}");
    assert!(message.contains("cube data.bin"), "{message}");

    let path = cube_doc().gltf_external(
        dir.path(),
        "cube.gltf",
        "cube%20data.bin",
        Some("cube data.bin"),
    );
    assert_eq!(load_gltf(&path).unwrap().meshes.len(), 1);
}

#[test]
fn errors_name_the_file_and_the_problem() {
    let dir = tempfile::tempdir().unwrap();

    let err = load_gltf(&dir.path().join("nope.glb")).unwrap_err();
    assert!(matches!(err, GltfError::Read { .. }));
    assert!(err.to_string().contains("nope.glb"));

    let path = write(
        dir.path(),
        "broken.gltf",
        b"{ \"asset\": { \"version\": \"2.0\" ",
    );
    let err = load_gltf(&path).unwrap_err();
    let message = err.to_string();
    assert!(matches!(err, GltfError::Json { .. }), "{message}");
    assert!(
        message.contains("broken.gltf") && message.contains("line 1"),
        "{message}"
    );

    // A primitive without positions fails glTF validation, which names the path.
    let mut doc = cube_doc();
    doc.root.meshes[0].primitives[0]
        .attributes
        .remove(&Valid(Semantic::Positions));
    let err = load_gltf_slice(&doc.gltf_data_uri(), None).unwrap_err();
    let message = err.to_string();
    assert!(matches!(err, GltfError::Invalid { .. }), "{message}");
    assert!(message.contains("POSITION"), "{message}");

    // An accessor reading past its buffer view.
    let mut doc = cube_doc();
    doc.root.accessors[1].count = USize64(10_000);
    let err = load_gltf_slice(&doc.gltf_data_uri(), None).unwrap_err();
    let message = err.to_string();
    assert!(
        matches!(err, GltfError::Accessor { index: 1, .. }),
        "{message}"
    );
    assert!(
        message.contains("<memory>: accessor 1 (NORMAL of mesh 0 `Cube`, primitive 0)"),
        "{message}"
    );
    assert!(message.contains("do not fit"), "{message}");

    // An index past the vertices.
    let mut doc = Doc::new();
    let p = doc.positions(&[[0.0; 3], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0]]);
    let i = doc.indices(&[0, 1, 7]);
    let mesh = doc.mesh(
        "Bad",
        vec![primitive(
            &[(Semantic::Positions, p)],
            Some(i),
            Mode::Triangles,
        )],
    );
    let node = doc.node(mesh_node(Some(mesh), [0.0; 3], 1.0));
    doc.scene(vec![node]);
    let message = load_gltf_slice(&doc.gltf_data_uri(), None)
        .unwrap_err()
        .to_string();
    assert!(
        message.contains("mesh 0 `Bad`, primitive 0: index 2 is 7"),
        "{message}"
    );

    // External files need a directory when loading from memory.
    let mut doc = cube_doc();
    doc.root.buffers[0].uri = Some("cube.bin".into());
    let bytes = json::serialize::to_vec(&doc.root).unwrap();
    let message = load_gltf_slice(&bytes, None).unwrap_err().to_string();
    assert!(
        message.contains("buffer 0") && message.contains("from memory"),
        "{message}"
    );
}

#[test]
fn truncated_glb_is_an_error() {
    let glb = cube_doc().glb();
    let dir = tempfile::tempdir().unwrap();
    let path = write(dir.path(), "cut.glb", &glb[..glb.len() / 2]);
    let err = load_gltf(&path).unwrap_err();
    let message = err.to_string();
    assert!(matches!(err, GltfError::Glb { .. }), "{message}");
    assert!(
        message.contains("cut.glb") && message.contains("truncated"),
        "{message}"
    );
}

/// A file using most of what the importer reads: a textured cube, and a
/// child node with a triangle strip whose positions are sparse and whose
/// UVs are normalised bytes.
fn rich_glb() -> Vec<u8> {
    let mut doc = cube_doc();
    let png = doc.view(&png_2x2());
    let image = doc.root.push(json::Image {
        buffer_view: Some(png),
        mime_type: Some(json::image::MimeType("image/png".into())),
        name: None,
        uri: None,
        extensions: None,
        extras: Default::default(),
    });
    let texture = doc.root.push(json::Texture {
        name: None,
        sampler: None,
        source: image,
        extensions: None,
        extras: Default::default(),
    });
    let mut material = json::Material::default();
    material.pbr_metallic_roughness.base_color_texture = Some(json::texture::Info {
        index: texture,
        tex_coord: 0,
        extensions: None,
        extras: Default::default(),
    });
    let material = doc.root.push(material);
    doc.root.meshes[0].primitives[0].material = Some(material);

    let p = doc.positions(&[
        [0.0, 0.0, 0.0],
        [1.0, 0.0, 0.0],
        [0.0, 1.0, 0.0],
        [1.0, 1.0, 0.0],
    ]);
    let sparse_indices = doc.view(&bytes(&[2u16, 0]));
    let sparse_values = doc.view(&bytes(&[0.0f32, 2.0, 0.0]));
    doc.root.accessors[p.value()].sparse = Some(json::accessor::sparse::Sparse {
        count: USize64(1),
        indices: json::accessor::sparse::Indices {
            buffer_view: sparse_indices,
            byte_offset: USize64(0),
            component_type: Valid(json::accessor::IndexComponentType(ComponentType::U16)),
            extensions: None,
            extras: Default::default(),
        },
        values: json::accessor::sparse::Values {
            buffer_view: sparse_values,
            byte_offset: USize64(0),
            extensions: None,
            extras: Default::default(),
        },
        extensions: None,
        extras: Default::default(),
    });
    let uv_view = doc.view(&[0u8, 255, 255, 255, 0, 0, 255, 0]);
    let uv = doc.accessor(Some(uv_view), 4, ComponentType::U8, Type::Vec2);
    doc.root.accessors[uv.value()].normalized = true;
    let attributes = [(Semantic::Positions, p), (Semantic::TexCoords(0), uv)];
    let strip = doc.mesh(
        "Strip",
        vec![primitive(&attributes, None, Mode::TriangleStrip)],
    );
    let child = doc.node(mesh_node(Some(strip), [1.0, 2.0, 3.0], 2.0));
    doc.root.nodes[0].children = Some(vec![child]);
    doc.glb()
}

/// Every prefix of a valid .glb, the file with bytes overwritten at every
/// offset, and the file with each number in its JSON replaced by edge
/// values: each loads or fails, and none panics (in a debug build, so
/// arithmetic overflow would panic too).
#[test]
fn corrupted_glb_never_panics() {
    let glb = rich_glb();
    let scene = load_gltf_slice(&glb, None).unwrap();
    assert_eq!((scene.meshes.len(), scene.instances.len()), (2, 2));

    for cut in 0..glb.len() {
        assert!(
            load_gltf_slice(&glb[..cut], None).is_err(),
            "prefix of {cut} bytes"
        );
    }
    // Digits and quotes change numbers and structure in the JSON; 0xff and
    // 0x7f make large or negative lengths in binary fields.
    for at in 0..glb.len() {
        for byte in [b'9', b'0', b'"', 0x00, 0x7f, 0xff] {
            let mut bad = glb.clone();
            bad[at] = byte;
            let _ = load_gltf_slice(&bad, None);
        }
    }

    let json_len = u32::from_le_bytes([glb[12], glb[13], glb[14], glb[15]]) as usize;
    let (json, bin) = (&glb[20..20 + json_len], &glb[20 + json_len..]);
    let is_number = |b: u8| b.is_ascii_digit() || b"-.e".contains(&b);
    let mut at = 0;
    while at < json.len() {
        if !json[at].is_ascii_digit() {
            at += 1;
            continue;
        }
        let end = at + json[at..].iter().take_while(|&&b| is_number(b)).count();
        for value in [
            "0",
            "1",
            "3",
            "-1",
            "255",
            "65536",
            "4294967295",
            "18446744073709551615",
            "1e40",
        ] {
            let mut bad = json[..at].to_vec();
            bad.extend_from_slice(value.as_bytes());
            bad.extend_from_slice(&json[end..]);
            bad.resize(bad.len().next_multiple_of(4), b' ');
            let mut file = b"glTF".to_vec();
            file.extend(2u32.to_le_bytes());
            file.extend(((20 + bad.len() + bin.len()) as u32).to_le_bytes());
            file.extend((bad.len() as u32).to_le_bytes());
            file.extend_from_slice(b"JSON");
            file.extend(bad);
            file.extend_from_slice(bin);
            let _ = load_gltf_slice(&file, None);
        }
        at = end;
    }
}
