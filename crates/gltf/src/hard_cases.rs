//! The loader's hard cases and bad files, one test per class of the issue
//! (the rest are in `tests.rs`: data URIs, images in buffer views,
//! strips and fans, errors naming file and object, corrupted GLBs).

use gltf::json;
use json::accessor::{ComponentType, Type};
use json::mesh::{Mode, Semantic};
use json::validation::Checked::Valid;
use json::validation::USize64;

use super::builder::{Doc, bytes, info, mesh_node, png_2x2, primitive};
use super::*;
use spreadlight_render::mesh::primitives::{BoxParams, box_mesh};

fn cube_doc() -> Doc {
    let mut doc = Doc::new();
    let mesh = doc.mesh_data("Cube", &box_mesh(BoxParams::default()));
    let node = doc.node(mesh_node(Some(mesh), [0.0; 3], 1.0));
    doc.scene(vec![node]);
    doc
}

/// `doc` as JSON, changed by `edit` (for extension objects gltf-json has no builder for).
fn edited(doc: Doc, edit: impl FnOnce(&mut json::Value)) -> Vec<u8> {
    let mut value: json::Value =
        json::deserialize::from_slice(&doc.gltf_data_uri()).expect("our own JSON");
    edit(&mut value);
    json::serialize::to_vec(&value).expect("serialize")
}

fn value(text: &str) -> json::Value {
    json::deserialize::from_str(text).expect("JSON")
}

fn load(bytes: &[u8]) -> Result<GltfScene, GltfError> {
    load_gltf_slice(bytes, None)
}

#[test]
fn accessors_of_count_zero_load_as_nothing_to_draw() {
    let mut doc = cube_doc();
    let p = doc.positions(&[]);
    doc.root.accessors[p.value()].min = Some(json::Value::from(vec![0.0, 0.0, 0.0]));
    doc.root.accessors[p.value()].max = Some(json::Value::from(vec![0.0, 0.0, 0.0]));
    let empty = doc.mesh(
        "Empty",
        vec![primitive(
            &[(Semantic::Positions, p)],
            None,
            Mode::Triangles,
        )],
    );
    let node = doc.node(mesh_node(Some(empty), [0.0; 3], 1.0));
    doc.root.scenes[0].nodes.push(node);
    let scene = load(&doc.gltf_data_uri()).unwrap();
    assert_eq!(scene.meshes.len(), 1, "the cube only");
    assert_eq!(scene.instances.len(), 1);
    assert_eq!(
        scene.warnings,
        vec!["mesh 1 `Empty`, primitive 0: it has no triangles; skipped".to_owned()]
    );
}

#[test]
fn sparse_accessors_without_min_max_or_buffer_view() {
    let mut doc = cube_doc();
    let uvs = doc.accessor(None, 24, ComponentType::F32, Type::Vec2);
    let indices = doc.view(&bytes(&[3u8, 0, 0, 0]));
    let values = doc.view(&bytes(&[0.25f32, 0.75]));
    doc.root.accessors[uvs.value()].sparse = Some(json::accessor::sparse::Sparse {
        count: USize64(1),
        indices: json::accessor::sparse::Indices {
            buffer_view: indices,
            byte_offset: USize64(0),
            component_type: Valid(json::accessor::IndexComponentType(ComponentType::U8)),
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
    let prim = &mut doc.root.meshes[0].primitives[0];
    prim.attributes.insert(Valid(Semantic::TexCoords(0)), uvs);
    let scene = load(&doc.gltf_data_uri()).unwrap();
    let loaded = scene.meshes[0].uvs.as_ref().unwrap();
    assert_eq!(loaded[3], [0.25, 0.75]);
    assert_eq!(loaded[2], [0.0, 0.0]);
    // POSITION is the one accessor glTF requires bounds on: refused, by name.
    let mut doc = cube_doc();
    doc.root.accessors[0].min = None;
    let err = load(&doc.gltf_data_uri()).unwrap_err().to_string();
    assert!(
        err.contains("<memory>") && err.contains("POSITION") && err.contains(".min"),
        "{err}"
    );
}

#[test]
fn asset_version_other_than_2_is_refused() {
    let bytes = edited(cube_doc(), |v| v["asset"]["version"] = "3.0".into());
    let err = load(&bytes).unwrap_err().to_string();
    assert_eq!(
        err,
        "<memory>: invalid glTF: asset.version is `3.0`: only glTF 2.x can be read"
    );
    let bytes = edited(cube_doc(), |v| v["asset"]["version"] = "2.1".into());
    assert!(load(&bytes).is_ok(), "a later 2.x loads");
}

#[test]
fn hierarchies_that_are_not_a_forest_are_refused_by_node() {
    // A node that is its own child.
    let mut doc = cube_doc();
    doc.root.nodes[0].children = Some(vec![json::Index::new(0)]);
    let err = load(&doc.gltf_data_uri()).unwrap_err().to_string();
    assert_eq!(err, "<memory>: invalid glTF: node 0 is its own child");
    // Two nodes that are each other's child.
    let mut doc = cube_doc();
    let other = doc.node(mesh_node(None, [0.0; 3], 1.0));
    doc.root.nodes[0].children = Some(vec![other]);
    doc.root.nodes[other.value()].children = Some(vec![json::Index::new(0)]);
    let err = load(&doc.gltf_data_uri()).unwrap_err().to_string();
    assert!(err.contains("each other's ancestors"), "{err}");
    assert!(err.contains("0 -> 1 -> 0"), "{err}");
    // A node with two parents.
    let mut doc = cube_doc();
    let a = doc.node(mesh_node(None, [0.0; 3], 1.0));
    let b = doc.node(mesh_node(None, [0.0; 3], 1.0));
    doc.root.nodes[a.value()].children = Some(vec![json::Index::new(0)]);
    doc.root.nodes[b.value()].children = Some(vec![json::Index::new(0)]);
    doc.root.scenes[0].nodes = vec![a, b];
    let err = load(&doc.gltf_data_uri()).unwrap_err().to_string();
    assert_eq!(
        err,
        "<memory>: invalid glTF: node 0 is a child of nodes 1 and 2; a node has at most one parent"
    );
}

#[test]
fn extreme_coordinates_keep_finite_bounds() {
    for scale in [1e-18f32, 1e18] {
        let mut doc = Doc::new();
        let mesh = doc.mesh_data("Cube", &box_mesh(BoxParams::default()));
        let node = doc.node(mesh_node(Some(mesh), [scale; 3], scale));
        doc.scene(vec![node]);
        let scene = load(&doc.gltf_data_uri()).unwrap();
        let size = scene.bounds.size();
        assert!(size.is_finite() && size.x > 0.0, "{scale}: {size}");
        assert!((size.x / scale - 1.0).abs() < 1e-5, "{scale}: {size}");
        assert!((scene.bounds.center().x / scale - 1.0).abs() < 1e-5);
    }
}

#[test]
fn mirrored_nodes_keep_their_transform() {
    let mut doc = Doc::new();
    let mesh = doc.mesh_data("Cube", &box_mesh(BoxParams::default()));
    let node = doc.node(json::Node {
        mesh: Some(mesh),
        scale: Some([-1.0, 1.0, 1.0]),
        ..Default::default()
    });
    doc.scene(vec![node]);
    let scene = load(&doc.gltf_data_uri()).unwrap();
    // The winding is turned around where it is drawn (visibility and the
    // compute raster test the determinant); the loader keeps the mirror.
    assert!(scene.instances[0].transform.determinant() < 0.0);
    assert_eq!(
        scene.meshes[0].indices,
        box_mesh(BoxParams::default()).indices
    );
}

#[test]
fn non_indexed_triangles_load_in_vertex_order() {
    let mut doc = Doc::new();
    let p = doc.positions(&[[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0]]);
    let mesh = doc.mesh(
        "Tri",
        vec![primitive(
            &[(Semantic::Positions, p)],
            None,
            Mode::Triangles,
        )],
    );
    let node = doc.node(mesh_node(Some(mesh), [0.0; 3], 1.0));
    doc.scene(vec![node]);
    let scene = load(&doc.gltf_data_uri()).unwrap();
    assert_eq!(scene.meshes[0].indices, vec![0, 1, 2]);
}

#[test]
fn interleaved_buffers_are_read_by_stride() {
    let mut doc = Doc::new();
    // position xyz, normal xyz per vertex: 24 bytes apart.
    let interleaved: Vec<f32> = [
        [0.0, 0.0, 0.0, 0.0, 0.0, 1.0],
        [1.0, 0.0, 0.0, 0.0, 0.0, 1.0],
        [0.0, 1.0, 0.0, 0.0, 0.0, 1.0],
    ]
    .concat();
    let view = doc.view(&bytes(&interleaved));
    doc.root.buffer_views[view.value()].byte_stride = Some(json::buffer::Stride(24));
    let p = doc.accessor(Some(view), 3, ComponentType::F32, Type::Vec3);
    doc.root.accessors[p.value()].min = Some(json::Value::from(vec![0.0, 0.0, 0.0]));
    doc.root.accessors[p.value()].max = Some(json::Value::from(vec![1.0, 1.0, 0.0]));
    let n = doc.accessor(Some(view), 3, ComponentType::F32, Type::Vec3);
    doc.root.accessors[n.value()].byte_offset = Some(USize64(12));
    let mesh = doc.mesh(
        "Interleaved",
        vec![primitive(
            &[(Semantic::Positions, p), (Semantic::Normals, n)],
            None,
            Mode::Triangles,
        )],
    );
    let node = doc.node(mesh_node(Some(mesh), [0.0; 3], 1.0));
    doc.scene(vec![node]);
    let scene = load(&doc.gltf_data_uri()).unwrap();
    let m = &scene.meshes[0];
    assert_eq!(
        m.positions,
        vec![[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0]]
    );
    assert_eq!(m.normals, vec![[0.0, 0.0, 1.0]; 3]);
}

#[test]
fn supported_required_extensions_load_and_unknown_optional_ones_warn_once() {
    let mut doc = cube_doc();
    let png = doc.png_image(&png_2x2());
    let texture = doc.texture(png);
    let mut material = json::Material::default();
    material.pbr_metallic_roughness.base_color_texture = Some(info(texture));
    material.emissive_factor = json::material::EmissiveFactor([1.0, 0.5, 0.0]);
    let material = doc.material(material);
    doc.root.meshes[0].primitives[0].material = Some(material);
    let bytes = edited(doc, |v| {
        v["extensionsUsed"] = json::Value::from(vec![
            "KHR_texture_transform",
            "KHR_materials_emissive_strength",
            "EXT_made_up",
        ]);
        v["extensionsRequired"] = json::Value::from(vec!["KHR_texture_transform"]);
        let m = &mut v["materials"][0];
        m["pbrMetallicRoughness"]["baseColorTexture"]["extensions"] = value(
            r#"{"KHR_texture_transform": {"offset": [0.5, 0.0], "rotation": 1.5, "scale": [2.0, 3.0]},
                "EXT_made_up": {"a": 1}}"#,
        );
        m["extensions"] = value(
            r#"{"KHR_materials_emissive_strength": {"emissiveStrength": 4.0}, "EXT_made_up": {}}"#,
        );
    });
    let scene = load(&bytes).unwrap();
    let m = &scene.materials[0];
    assert_eq!(m.emissive_strength, 4.0);
    let t = m.base_color_texture.as_ref().unwrap();
    assert_eq!(t.transform.offset, [0.5, 0.0]);
    assert_eq!((t.transform.rotation, t.transform.scale), (1.5, [2.0, 3.0]));
    assert_eq!(
        scene.warnings,
        vec!["extension `EXT_made_up` is not supported; what it adds is ignored".to_owned()]
    );
    // The material world's view: CookTorrance, Emission x strength, maps.
    let material = m.to_material();
    let emission = material
        .params(spreadlight_render::material::Feature::Emission)
        .unwrap();
    assert_eq!(emission, &[[1.0, 0.5, 0.0, 4.0]]);
    let maps = material.maps().unwrap();
    assert!(
        maps.map(spreadlight_render::material::maps::MapSlot::BaseColor)
            .is_some()
    );
}

#[test]
fn untrusted_counts_are_not_allocated() {
    // Four billion elements in a 288-byte view: refused before reading.
    let mut doc = cube_doc();
    doc.root.accessors[0].count = USize64(u32::MAX as u64);
    let err = load(&doc.gltf_data_uri()).unwrap_err().to_string();
    assert!(
        err.contains("accessor 0") && err.contains("do not fit"),
        "{err}"
    );
    // Four billion zeros without a buffer view (sparse, one value): refused too.
    let mut doc = cube_doc();
    let uvs = doc.accessor(None, u32::MAX as usize, ComponentType::F32, Type::Vec2);
    let indices = doc.view(&bytes(&[3u32]));
    let values = doc.view(&bytes(&[0.25f32, 0.75]));
    doc.root.accessors[uvs.value()].sparse = Some(json::accessor::sparse::Sparse {
        count: USize64(1),
        indices: json::accessor::sparse::Indices {
            buffer_view: indices,
            byte_offset: USize64(0),
            component_type: Valid(json::accessor::IndexComponentType(ComponentType::U32)),
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
    let prim = &mut doc.root.meshes[0].primitives[0];
    prim.attributes.insert(Valid(Semantic::TexCoords(0)), uvs);
    let err = load(&doc.gltf_data_uri()).unwrap_err().to_string();
    assert!(err.contains("without a buffer view"), "{err}");
}

#[test]
fn many_instances_of_one_mesh_share_it() {
    let mut doc = Doc::new();
    let mesh = doc.mesh_data("Cube", &box_mesh(BoxParams::default()));
    let nodes: Vec<_> = (0..2000)
        .map(|i| doc.node(mesh_node(Some(mesh), [i as f32, 0.0, 0.0], 1.0)))
        .collect();
    doc.scene(nodes);
    let scene = load(&doc.gltf_data_uri()).unwrap();
    assert_eq!(scene.meshes.len(), 1, "one mesh, uploaded once");
    assert_eq!(scene.instances.len(), 2000);
    assert!(scene.instances.iter().all(|i| i.mesh == 0));
}

#[test]
fn the_benchmark_models_are_what_the_generator_makes() {
    // patches/assets/bench-gltf-*.gltf are committed outputs of `bench_grid`.
    let root = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("../../patches/assets");
    for (file, textured) in [
        ("bench-gltf-textured.gltf", true),
        ("bench-gltf-plain.gltf", false),
    ] {
        let made = super::models::bench_grid(1000, 100, 200, textured);
        let path = root.join(file);
        if std::env::var_os("SPREADLIGHT_BLESS").is_some() {
            std::fs::write(&path, &made).unwrap();
        }
        let committed = std::fs::read(&path).unwrap();
        assert!(
            committed == made,
            "{file} is stale: regenerate with SPREADLIGHT_BLESS=1"
        );
        let scene = load(&made).unwrap();
        assert_eq!(scene.instances.len(), 1000);
        let textured_materials = scene
            .materials
            .iter()
            .filter(|m| m.base_color_texture.is_some());
        assert_eq!(textured_materials.count(), if textured { 100 } else { 0 });
    }
}

/// `cube_doc` with `attribute` added to its primitive from `data` as
/// `count` elements of `type_` in `component` (normalised when asked).
fn with_attribute(
    semantic: Semantic,
    data: &[u8],
    count: usize,
    component: ComponentType,
    type_: Type,
    normalized: bool,
) -> Doc {
    let mut doc = cube_doc();
    let view = doc.view(data);
    let a = doc.accessor(Some(view), count, component, type_);
    doc.root.accessors[a.value()].normalized = normalized;
    doc.root.meshes[0].primitives[0]
        .attributes
        .insert(Valid(semantic), a);
    doc
}

#[test]
fn color_0_and_texcoord_1_load_from_every_allowed_format() {
    let n = box_mesh(BoxParams::default()).positions.len();
    // VEC3 float colours get alpha 1.
    let rgb: Vec<f32> = (0..n)
        .flat_map(|i| [i as f32 / n as f32, 0.5, 1.0])
        .collect();
    let doc = with_attribute(
        Semantic::Colors(0),
        &bytes(&rgb),
        n,
        ComponentType::F32,
        Type::Vec3,
        false,
    );
    let m = &load(&doc.gltf_data_uri()).unwrap().meshes[0];
    let colors = m.colors.as_ref().unwrap();
    assert_eq!(colors[3], [3.0 / n as f32, 0.5, 1.0, 1.0]);
    // Normalised unsigned bytes and shorts (VEC4) are divided by their maximum.
    let rgba8: Vec<u8> = (0..n).flat_map(|_| [255u8, 51, 0, 102]).collect();
    let doc = with_attribute(
        Semantic::Colors(0),
        &rgba8,
        n,
        ComponentType::U8,
        Type::Vec4,
        true,
    );
    let m = &load(&doc.gltf_data_uri()).unwrap().meshes[0];
    assert_eq!(m.colors.as_ref().unwrap()[0], [1.0, 0.2, 0.0, 0.4]);
    let rgba16: Vec<u16> = (0..n).flat_map(|_| [0u16, 65535, 13107, 65535]).collect();
    let doc = with_attribute(
        Semantic::Colors(0),
        &bytes(&rgba16),
        n,
        ComponentType::U16,
        Type::Vec4,
        true,
    );
    let m = &load(&doc.gltf_data_uri()).unwrap().meshes[0];
    assert_eq!(m.colors.as_ref().unwrap()[n - 1], [0.0, 1.0, 0.2, 1.0]);
    // TEXCOORD_1 as normalised unsigned shorts.
    let uv16: Vec<u16> = (0..n).flat_map(|_| [65535u16, 0]).collect();
    let doc = with_attribute(
        Semantic::TexCoords(1),
        &bytes(&uv16),
        n,
        ComponentType::U16,
        Type::Vec2,
        true,
    );
    let scene = load(&doc.gltf_data_uri()).unwrap();
    assert_eq!(scene.meshes[0].uvs1.as_ref().unwrap()[5], [1.0, 0.0]);
    assert!(scene.warnings.is_empty(), "{:?}", scene.warnings);
}

#[test]
fn a_vertex_stream_of_the_wrong_length_is_refused_naming_the_primitive() {
    let doc = with_attribute(
        Semantic::Colors(0),
        &bytes(&[1.0f32; 12]),
        3,
        ComponentType::F32,
        Type::Vec4,
        false,
    );
    let err = load(&doc.gltf_data_uri()).unwrap_err().to_string();
    assert!(
        err.starts_with("<memory>") && err.contains("mesh 0 `Cube`, primitive 0"),
        "{err}"
    );
    assert!(err.contains("colors stream has 3 entries"), "{err}");
    // Colours outside 0..1 are data, not an error: clamped on upload.
    let doc = with_attribute(
        Semantic::Colors(0),
        &bytes(&vec![
            2.0f32;
            4 * box_mesh(BoxParams::default()).positions.len()
        ]),
        box_mesh(BoxParams::default()).positions.len(),
        ComponentType::F32,
        Type::Vec4,
        false,
    );
    assert!(load(&doc.gltf_data_uri()).is_ok());
}

#[test]
fn vertex_colours_of_a_primitive_without_normals_follow_its_flat_corners() {
    let mut doc = Doc::new();
    let positions = doc.positions(&[[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0]]);
    let colors = doc.floats(&[
        [1.0, 0.0, 0.0, 1.0],
        [0.0, 1.0, 0.0, 1.0],
        [0.0, 0.0, 1.0, 1.0],
    ]);
    let uv1 = doc.floats(&[[0.0, 0.0], [1.0, 0.0], [0.0, 1.0]]);
    let indices = doc.indices(&[2, 0, 1]);
    let mesh = doc.mesh(
        "Tri",
        vec![primitive(
            &[
                (Semantic::Positions, positions),
                (Semantic::Colors(0), colors),
                (Semantic::TexCoords(1), uv1),
            ],
            Some(indices),
            Mode::Triangles,
        )],
    );
    let node = doc.node(mesh_node(Some(mesh), [0.0; 3], 1.0));
    doc.scene(vec![node]);
    let m = &load(&doc.gltf_data_uri()).unwrap().meshes[0];
    // Flat shading gave each corner its own vertex, in index order (2, 0, 1).
    assert_eq!(m.positions[0], [0.0, 1.0, 0.0]);
    assert_eq!(m.colors.as_ref().unwrap()[0], [0.0, 0.0, 1.0, 1.0]);
    assert_eq!(m.uvs1.as_ref().unwrap()[1], [0.0, 0.0]);
    assert_eq!(m.normals[0], [0.0, 0.0, 1.0]);
}

#[test]
fn texture_sets_the_mesh_lacks_warn_once_and_fall_back_to_texcoord_0() {
    let mut doc = cube_doc();
    let png = doc.png_image(&png_2x2());
    let texture = doc.texture(png);
    let mut material = json::Material::default();
    material.pbr_metallic_roughness.base_color_texture = Some(json::texture::Info {
        tex_coord: 1,
        ..info(texture)
    });
    material.emissive_texture = Some(json::texture::Info {
        tex_coord: 3,
        ..info(texture)
    });
    let material = doc.material(material);
    doc.root.meshes[0].primitives[0].material = Some(material);
    let scene = load(&doc.gltf_data_uri()).unwrap();
    let m = &scene.materials[0];
    assert_eq!(m.base_color_texture.as_ref().unwrap().tex_coord, 1);
    assert_eq!(m.emissive_texture.as_ref().unwrap().tex_coord, 0);
    assert_eq!(
        scene.warnings,
        vec![
            "mesh 0 `Cube`, primitive 0: its material maps a texture with TEXCOORD_1, which it lacks; TEXCOORD_0 stands in".to_owned(),
            "material 0, emissive texture uses TEXCOORD_3; meshes carry TEXCOORD_0 and TEXCOORD_1, so it is mapped with TEXCOORD_0".to_owned(),
        ]
    );
}
