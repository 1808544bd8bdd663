//! Generated glTF models (made in code, so nothing is downloaded): what the
//! reference-image tests, `spreadlight view`'s tests and the generated
//! benchmark scenes load. Each returns a `.gltf` with its buffer as a data
//! URI and its images in buffer views.

use gltf::json;
use json::validation::Checked::Valid;

use super::builder::{Doc, info, light_node, mesh_node, png};
use spreadlight_render::mesh::primitives::{BoxParams, box_mesh};

/// A flat floor of two triangles, `size` across, facing up.
fn floor_mesh(doc: &mut Doc, size: glam::Vec2) -> json::Index<json::Mesh> {
    let floor = spreadlight_render::mesh::primitives::grid(
        spreadlight_render::mesh::primitives::GridParams {
            size,
            resolution_x: 1,
            resolution_y: 1,
        },
    );
    doc.mesh_data("Floor", &floor)
}

/// Texel size of the generated textures (one size class exactly, so they are not resampled).
pub const TEXTURE_SIZE: u32 = 64;

/// An 8 x 8 checkerboard of `a` and `b`.
pub fn checker(a: [u8; 4], b: [u8; 4]) -> image::RgbaImage {
    image::RgbaImage::from_fn(TEXTURE_SIZE, TEXTURE_SIZE, |x, y| {
        let cell = TEXTURE_SIZE / 8;
        image::Rgba(if (x / cell + y / cell).is_multiple_of(2) {
            a
        } else {
            b
        })
    })
}

/// A tangent-space normal map of ridges along v: normals lean along +u and
/// -u in alternating bands, flat between them.
pub fn ridges() -> image::RgbaImage {
    image::RgbaImage::from_fn(TEXTURE_SIZE, TEXTURE_SIZE, |x, _| {
        let band = (x * 8 / TEXTURE_SIZE) % 4;
        let lean: f32 = match band {
            0 => 0.6,
            2 => -0.6,
            _ => 0.0,
        };
        let n = glam::Vec3::new(lean, 0.0, 1.0).normalize();
        let encode = |c: f32| ((c * 0.5 + 0.5) * 255.0).round() as u8;
        image::Rgba([encode(n.x), encode(n.y), encode(n.z), 255])
    })
}

/// Metallic-roughness: roughness (G) rising with u, metalness (B) 1 in the top half.
pub fn metal_rough() -> image::RgbaImage {
    image::RgbaImage::from_fn(TEXTURE_SIZE, TEXTURE_SIZE, |x, y| {
        let rough = 40 + (x * 200 / TEXTURE_SIZE) as u8;
        let metal = if y < TEXTURE_SIZE / 2 { 255 } else { 0 };
        image::Rgba([0, rough, metal, 255])
    })
}

/// A unit cube whose material has a checker base colour texture, a ridged
/// normal map, a metallic-roughness texture and an emissive stripe, turned
/// so three faces show.
pub fn textured_cube() -> Vec<u8> {
    let mut doc = Doc::new();
    let textures: Vec<_> = [
        checker([230, 120, 40, 255], [240, 240, 230, 255]),
        ridges(),
        metal_rough(),
        image::RgbaImage::from_fn(TEXTURE_SIZE, TEXTURE_SIZE, |_, y| {
            let on = (TEXTURE_SIZE * 7 / 16..TEXTURE_SIZE * 9 / 16).contains(&y);
            image::Rgba(if on {
                [40, 160, 255, 255]
            } else {
                [0, 0, 0, 255]
            })
        }),
    ]
    .iter()
    .map(|image| {
        let image = doc.png_image(&png(image));
        doc.texture(image)
    })
    .collect();
    let mut material = json::Material {
        name: Some("Painted".into()),
        ..Default::default()
    };
    material.pbr_metallic_roughness.base_color_texture = Some(info(textures[0]));
    material.pbr_metallic_roughness.metallic_roughness_texture = Some(info(textures[2]));
    material.pbr_metallic_roughness.metallic_factor = json::material::StrengthFactor(1.0);
    material.pbr_metallic_roughness.roughness_factor = json::material::StrengthFactor(1.0);
    material.normal_texture = Some(json::material::NormalTexture {
        index: textures[1],
        scale: 1.0,
        tex_coord: 0,
        extensions: None,
        extras: Default::default(),
    });
    material.emissive_texture = Some(info(textures[3]));
    material.emissive_factor = json::material::EmissiveFactor([1.0, 1.0, 1.0]);
    let material = doc.material(material);
    let mesh = doc.mesh_data("Cube", &box_mesh(BoxParams::default()));
    doc.root.meshes[mesh.value()].primitives[0].material = Some(material);
    let node = doc.node(json::Node {
        mesh: Some(mesh),
        rotation: Some(json::scene::UnitQuaternion(
            glam::Quat::from_rotation_y(-0.6).to_array(),
        )),
        ..Default::default()
    });
    doc.scene(vec![node]);
    doc.gltf_data_uri()
}

/// A floor and a sphere-less box lit only by the file's own lights: a
/// warm point light and a cool spot light (`KHR_lights_punctual`), no
/// sun. Used to test that `view` lights a file with its lights alone.
pub fn punctual_lights_scene() -> Vec<u8> {
    let mut doc = Doc::new();
    let floor = floor_mesh(&mut doc, glam::Vec2::splat(6.0));
    let cube = doc.mesh_data("Block", &box_mesh(BoxParams::default()));
    let white = doc.material(json::Material {
        pbr_metallic_roughness: json::material::PbrMetallicRoughness {
            metallic_factor: json::material::StrengthFactor(0.0),
            roughness_factor: json::material::StrengthFactor(0.6),
            ..Default::default()
        },
        ..Default::default()
    });
    for mesh in [floor, cube] {
        doc.root.meshes[mesh.value()].primitives[0].material = Some(white);
    }
    let light =
        |kind, color: [f32; 3], intensity| json::extensions::scene::khr_lights_punctual::Light {
            color,
            extensions: None,
            extras: Default::default(),
            intensity,
            name: None,
            range: None,
            spot: None,
            type_: Valid(kind),
        };
    use json::extensions::scene::khr_lights_punctual::{Spot, Type};
    let point = light(Type::Point, [1.0, 0.6, 0.3], 40.0);
    let mut spot = light(Type::Spot, [0.3, 0.5, 1.0], 80.0);
    spot.spot = Some(Spot {
        inner_cone_angle: 0.3,
        outer_cone_angle: 0.5,
    });
    doc.punctual_lights(vec![point, spot]);
    let placed_light = |index: u32, translation: [f32; 3], rotation: glam::Quat| json::Node {
        translation: Some(translation),
        rotation: Some(json::scene::UnitQuaternion(rotation.to_array())),
        ..light_node(index)
    };
    let nodes = vec![
        doc.node(mesh_node(Some(floor), [0.0; 3], 1.0)),
        doc.node(mesh_node(Some(cube), [0.0, 0.5, 0.0], 1.0)),
        doc.node(placed_light(0, [-1.5, 1.5, 1.0], glam::Quat::IDENTITY)),
        // Spots shine along -Z: turned to look down at the block from the right.
        doc.node(placed_light(
            1,
            [2.0, 2.5, 0.0],
            glam::Quat::from_rotation_y(std::f32::consts::FRAC_PI_2)
                * glam::Quat::from_rotation_x(-0.9),
        )),
    ];
    doc.scene(nodes);
    doc.gltf_data_uri()
}

/// The materials benchmark (`patches/bench-gltf.ron`): `instances` spheres
/// on a grid, one glTF mesh per material (10 instances each), `materials`
/// materials, each with a base colour and a metallic-roughness texture of
/// their own out of `textures` (half 64², half 16² texels: two size
/// classes; small, so the committed files stay small). `textured: false` gives the same meshes and instances with one
/// untextured material: the baseline the textured scene is measured against.
pub fn bench_grid(instances: usize, materials: usize, textures: usize, textured: bool) -> Vec<u8> {
    let mut doc = Doc::new();
    let sphere = spreadlight_render::mesh::primitives::sphere(
        spreadlight_render::mesh::primitives::SphereParams {
            radius: 0.4,
            sectors: 16,
            stacks: 8,
        },
    );
    let mesh = doc.mesh_data("Sphere", &sphere);
    let template = doc.root.meshes[mesh.value()].primitives[0].clone();
    let textures: Vec<_> = (0..textures * usize::from(textured))
        .map(|t| {
            let size = if t % 2 == 0 { 64 } else { 16 };
            let hue = (t * 37 % 255) as u8;
            let image = image::RgbaImage::from_fn(size, size, |x, y| {
                let cell = size / 8;
                let on = (x / cell + y / cell).is_multiple_of(2);
                image::Rgba(if on {
                    [hue, 255 - hue, 128, 255]
                } else {
                    [230, 230, 230, 255]
                })
            });
            let image = doc.png_image(&png(&image));
            doc.texture(image)
        })
        .collect();
    let material_count = if textured { materials.max(1) } else { 1 };
    let material_ids: Vec<_> = (0..material_count)
        .map(|m| {
            let mut material = json::Material::default();
            material.pbr_metallic_roughness.metallic_factor = json::material::StrengthFactor(0.0);
            if let (Some(base), Some(rough)) = (
                textures.get((2 * m) % textures.len().max(1)),
                textures.get((2 * m + 1) % textures.len().max(1)),
            ) {
                material.pbr_metallic_roughness.base_color_texture = Some(info(*base));
                material.pbr_metallic_roughness.metallic_roughness_texture = Some(info(*rough));
            }
            doc.material(material)
        })
        .collect();
    // One mesh per material (glTF ties a primitive to its material); the
    // primitives share the sphere's accessors.
    let meshes: Vec<_> = (0..materials.max(1))
        .map(|m| {
            let mut primitive = template.clone();
            primitive.material = Some(material_ids[m % material_ids.len()]);
            doc.mesh(&format!("Sphere {m}"), vec![primitive])
        })
        .collect();
    let side = (instances as f32).sqrt().ceil() as usize;
    let nodes = (0..instances)
        .map(|i| {
            let (x, z) = ((i % side) as f32, (i / side) as f32);
            let at = [x - side as f32 * 0.5, 0.4, z - side as f32 * 0.5];
            doc.node(mesh_node(Some(meshes[i % meshes.len()]), at, 1.0))
        })
        .collect();
    doc.scene(nodes);
    doc.gltf_data_uri()
}

/// A red cube sliding from x = -1 to x = 1 and back over 2 seconds (one
/// linear translation channel) on a still white floor, a point light riding
/// 1 above it (a child node): for posing at a time.
pub fn sliding_cube() -> Vec<u8> {
    use json::accessor::{ComponentType, Type};
    let mut doc = Doc::new();
    let cube = doc.mesh_data("Cube", &box_mesh(BoxParams::default()));
    let floor = floor_mesh(&mut doc, glam::Vec2::new(4.0, 2.0));
    let red = doc.material(json::Material {
        pbr_metallic_roughness: json::material::PbrMetallicRoughness {
            base_color_factor: json::material::PbrBaseColorFactor([0.9, 0.05, 0.05, 1.0]),
            ..Default::default()
        },
        ..Default::default()
    });
    doc.root.meshes[cube.value()].primitives[0].material = Some(red);
    let lamp = doc.node(json::Node {
        translation: Some([0.0, 2.0, 0.0]),
        ..light_node(0)
    });
    doc.punctual_lights(vec![json::extensions::scene::khr_lights_punctual::Light {
        color: [1.0, 0.9, 0.8],
        extensions: None,
        extras: Default::default(),
        intensity: 20.0,
        name: Some("Lamp".into()),
        range: None,
        spot: None,
        type_: Valid(json::extensions::scene::khr_lights_punctual::Type::Point),
    }]);
    let mut moving = mesh_node(Some(cube), [-1.0, 0.5, 0.0], 0.5);
    moving.children = Some(vec![lamp]);
    let moving = doc.node(moving);
    let still = doc.node(mesh_node(Some(floor), [0.0; 3], 1.0));
    doc.scene(vec![moving, still]);
    let times = [0.0f32, 1.0, 2.0];
    let input_view = doc.view(&super::builder::bytes(&times));
    let input = doc.accessor(Some(input_view), 3, ComponentType::F32, Type::Scalar);
    doc.root.accessors[input.value()].min = Some(json::Value::from(vec![0.0]));
    doc.root.accessors[input.value()].max = Some(json::Value::from(vec![2.0]));
    let output = doc.floats(&[[-1.0f32, 0.5, 0.0], [1.0, 0.5, 0.0], [-1.0, 0.5, 0.0]]);
    doc.root.push(json::Animation {
        channels: vec![json::animation::Channel {
            sampler: json::Index::new(0),
            target: json::animation::Target {
                node: moving,
                path: Valid(json::animation::Property::Translation),
                extensions: None,
                extras: Default::default(),
            },
            extensions: None,
            extras: Default::default(),
        }],
        samplers: vec![json::animation::Sampler {
            input,
            interpolation: Valid(json::animation::Interpolation::Linear),
            output,
            extensions: None,
            extras: Default::default(),
        }],
        name: Some("Slide".into()),
        extensions: None,
        extras: Default::default(),
    });
    doc.gltf_data_uri()
}

/// Half the side of [`textured_floor`]'s square.
pub const FLOOR_HALF: f32 = 20.0;
/// How many times [`textured_floor`]'s textures repeat across it.
pub const FLOOR_REPEAT: f32 = 8.0;

/// The material accuracy scene (`spreadlight accuracy gltf`): a floor
/// 2 x [`FLOOR_HALF`] square at y = 0 facing +Y, its textures repeating
/// [`FLOOR_REPEAT`] times (u along +x, v along +z, from the -x -z corner):
/// a fine checker base colour (4-texel cells, sRGB) and [`metal_rough`]
/// (roughness rising with u, metal in the top half), both 64². Seen at a
/// grazing angle its far part minifies the checker far past a texel per
/// pixel: where unfiltered maps alias.
pub fn textured_floor() -> Vec<u8> {
    let mut doc = Doc::new();
    let fine = image::RgbaImage::from_fn(TEXTURE_SIZE, TEXTURE_SIZE, |x, y| {
        image::Rgba(if (x / 4 + y / 4).is_multiple_of(2) {
            [220, 200, 160, 255]
        } else {
            [40, 60, 90, 255]
        })
    });
    let [base, rough] = [fine, metal_rough()].map(|image| {
        let image = doc.png_image(&png(&image));
        doc.texture(image)
    });
    let mut material = json::Material {
        name: Some("Floor".into()),
        ..Default::default()
    };
    material.pbr_metallic_roughness.base_color_texture = Some(info(base));
    material.pbr_metallic_roughness.metallic_roughness_texture = Some(info(rough));
    let material = doc.material(material);
    let (h, r) = (FLOOR_HALF, FLOOR_REPEAT);
    let corners = [[-h, h], [h, h], [h, -h], [-h, -h]];
    let mut floor = spreadlight_render::mesh::MeshData {
        positions: corners.iter().map(|&[x, z]| [x, 0.0, z]).collect(),
        normals: vec![[0.0, 1.0, 0.0]; 4],
        uvs: Some(
            corners
                .iter()
                .map(|&[x, z]| [(x + h) / (2.0 * h) * r, (z + h) / (2.0 * h) * r])
                .collect(),
        ),
        tangents: None,
        uvs1: None,
        colors: None,
        indices: vec![0, 1, 2, 0, 2, 3],
        bounds: spreadlight_render::mesh::Aabb::ZERO,
    };
    floor.recompute_bounds();
    let mesh = doc.mesh_data("Floor", &floor);
    doc.root.meshes[mesh.value()].primitives[0].material = Some(material);
    let node = doc.node(mesh_node(Some(mesh), [0.0; 3], 1.0));
    doc.scene(vec![node]);
    doc.gltf_data_uri()
}

/// A grey floor and a red block lit as a photometric export lights them (a
/// 50,000 lux sun, as Blender writes a sun of strength 50,000 in lux), seen
/// by the file's own camera `Shot`: straight at the block's front face from
/// 2.5 m with a 0.3 rad field of view, so the face fills the picture. What
/// `view` must show from that camera, exposed down (`view`'s tests).
pub fn photometric_camera_scene() -> Vec<u8> {
    use json::extensions::scene::khr_lights_punctual::{Light, Type};
    let mut doc = Doc::new();
    let floor = floor_mesh(&mut doc, glam::Vec2::splat(6.0));
    let block = doc.mesh_data("Block", &box_mesh(BoxParams::default()));
    let matte = |color: [f32; 4]| json::Material {
        pbr_metallic_roughness: json::material::PbrMetallicRoughness {
            base_color_factor: json::material::PbrBaseColorFactor(color),
            metallic_factor: json::material::StrengthFactor(0.0),
            roughness_factor: json::material::StrengthFactor(0.8),
            ..Default::default()
        },
        ..Default::default()
    };
    let grey = doc.material(matte([0.4, 0.4, 0.4, 1.0]));
    let red = doc.material(matte([0.15, 0.015, 0.015, 1.0]));
    doc.root.meshes[floor.value()].primitives[0].material = Some(grey);
    doc.root.meshes[block.value()].primitives[0].material = Some(red);
    doc.punctual_lights(vec![Light {
        color: [1.0, 1.0, 1.0],
        extensions: None,
        extras: Default::default(),
        intensity: 50_000.0,
        name: Some("Sun".into()),
        range: None,
        spot: None,
        type_: Valid(Type::Directional),
    }]);
    let camera = doc.root.push(json::Camera {
        name: Some("Shot".into()),
        orthographic: None,
        perspective: Some(json::camera::Perspective {
            aspect_ratio: None,
            yfov: 0.3,
            zfar: Some(100.0),
            znear: 0.05,
            extensions: None,
            extras: Default::default(),
        }),
        type_: Valid(json::camera::Type::Perspective),
        extensions: None,
        extras: Default::default(),
    });
    // The sun shines down and into the block's front face (lights shine along -Z).
    let sun = glam::Quat::from_rotation_arc(
        glam::Vec3::NEG_Z,
        glam::Vec3::new(0.0, -0.5, -1.0).normalize(),
    );
    let nodes = vec![
        doc.node(mesh_node(Some(floor), [0.0; 3], 1.0)),
        doc.node(mesh_node(Some(block), [0.0, 0.5, 0.0], 1.0)),
        doc.node(json::Node {
            rotation: Some(json::scene::UnitQuaternion(sun.to_array())),
            ..light_node(0)
        }),
        // Cameras look along -Z: from +Z straight at the block.
        doc.node(json::Node {
            camera: Some(camera),
            translation: Some([0.0, 0.5, 3.0]),
            ..Default::default()
        }),
    ];
    doc.scene(nodes);
    doc.gltf_data_uri()
}

/// One sphere per glTF material extension the loader reads, in a row
/// along x, for docs/gltf.md's picture and `view`'s test of them: plain
/// metal-rough, clearcoat, unlit, ior 1.8 with a tinted specular, spec-gloss
/// (a converted gold), transmission (drawn blended).
pub fn material_extensions_row() -> Vec<u8> {
    let mut doc = Doc::new();
    let sphere = doc.mesh_data(
        "Sphere",
        &spreadlight_render::mesh::primitives::sphere(
            spreadlight_render::mesh::primitives::SphereParams {
                radius: 0.45,
                sectors: 32,
                stacks: 16,
            },
        ),
    );
    let base = |color: [f32; 4], roughness: f32| json::Material {
        pbr_metallic_roughness: json::material::PbrMetallicRoughness {
            base_color_factor: json::material::PbrBaseColorFactor(color),
            metallic_factor: json::material::StrengthFactor(0.0),
            roughness_factor: json::material::StrengthFactor(roughness),
            ..Default::default()
        },
        ..Default::default()
    };
    let red = [0.6, 0.08, 0.05, 1.0];
    let variants: [(&str, json::Material, &str); 6] = [
        ("Plain", base(red, 0.6), "{}"),
        (
            "Clearcoat",
            base(red, 0.6),
            r#"{"KHR_materials_clearcoat": {"clearcoatFactor": 1.0, "clearcoatRoughnessFactor": 0.05}}"#,
        ),
        ("Unlit", base(red, 0.6), r#"{"KHR_materials_unlit": {}}"#),
        (
            "Specular",
            base(red, 0.6),
            r#"{"KHR_materials_ior": {"ior": 1.8}, "KHR_materials_specular": {"specularColorFactor": [1.0, 0.8, 0.4]}}"#,
        ),
        (
            "SpecGloss",
            base(red, 0.6),
            r#"{"KHR_materials_pbrSpecularGlossiness": {"diffuseFactor": [0, 0, 0, 1], "specularFactor": [1.0, 0.77, 0.34], "glossinessFactor": 0.7}}"#,
        ),
        (
            "Transmission",
            base([0.8, 0.9, 1.0, 1.0], 0.1),
            r#"{"KHR_materials_transmission": {"transmissionFactor": 0.7}}"#,
        ),
    ];
    let mut nodes = Vec::new();
    for (i, (name, mut material, extensions)) in variants.into_iter().enumerate() {
        material.name = Some(name.into());
        let others = json::deserialize::from_str::<json::Value>(extensions)
            .ok()
            .and_then(|v| v.as_object().cloned())
            .unwrap_or_default();
        for extension in others.keys() {
            if !doc.root.extensions_used.contains(extension) {
                doc.root.extensions_used.push(extension.clone());
            }
        }
        material.extensions = Some(json::extensions::material::Material {
            others,
            ..Default::default()
        });
        let material = doc.material(material);
        let mut mesh = doc.root.meshes[sphere.value()].clone();
        mesh.primitives[0].material = Some(material);
        mesh.name = Some(name.into());
        let mesh = doc.root.push(mesh);
        nodes.push(doc.node(mesh_node(Some(mesh), [i as f32 - 2.5, 0.0, 0.0], 1.0)));
    }
    doc.scene(nodes);
    doc.gltf_data_uri()
}

/// Velvet: four spheres of one dark blue cloth, left to right without a
/// sheen, then `KHR_materials_sheen` white at roughness 0.3, pink at 0.5
/// and white at 0.9 (the factors only), for docs/gltf.md's picture and the
/// view test's reference image (`patches/assets/gltf-sheen.gltf`).
pub fn sheen_row() -> Vec<u8> {
    velvet_row(true, false)
}

/// [`sheen_row`] whose sheens are mapped
/// (`patches/assets/gltf-sheen-maps.gltf`): one texture, bands of white at
/// full roughness and of a rose colour at half roughness, as both the
/// sheenColorTexture (rgb) and the sheenRoughnessTexture (alpha): the cost
/// of the G-buffer's sheen and film target (`spreadlight bench`, docs/gltf.md).
pub fn sheen_row_with_maps() -> Vec<u8> {
    velvet_row(true, true)
}

/// [`sheen_row`] without its sheens (`patches/assets/gltf-sheen-off.gltf`):
/// the baseline of the sheen's cost (`spreadlight bench`, docs/gltf.md).
pub fn sheen_row_without_sheen() -> Vec<u8> {
    velvet_row(false, false)
}

fn velvet_row(with_sheen: bool, maps: bool) -> Vec<u8> {
    let mut doc = Doc::new();
    let sphere = doc.mesh_data(
        "Sphere",
        &spreadlight_render::mesh::primitives::sphere(
            spreadlight_render::mesh::primitives::SphereParams {
                radius: 0.45,
                sectors: 32,
                stacks: 16,
            },
        ),
    );
    if with_sheen {
        doc.root
            .extensions_used
            .push("KHR_materials_sheen".to_owned());
    }
    // Eight bands across u: white at alpha 1, rose at alpha 1/2.
    let map = maps.then(|| {
        let bands = image::RgbaImage::from_fn(TEXTURE_SIZE, TEXTURE_SIZE, |x, _| {
            image::Rgba(if (x / 8) % 2 == 0 {
                [255, 255, 255, 255]
            } else {
                [255, 140, 170, 128]
            })
        });
        let image = doc.png_image(&png(&bands));
        doc.texture(image).value()
    });
    let textures = map.map_or(String::new(), |t| {
        format!(
            r#", "sheenColorTexture": {{"index": {t}}}, "sheenRoughnessTexture": {{"index": {t}}}"#
        )
    });
    // A material's name and its sheen (colour, roughness), if any.
    type Sheen = Option<([f32; 3], f32)>;
    let sheens: [(&str, Sheen); 4] = [
        ("Cloth", None),
        ("Satin", Some(([1.0, 1.0, 1.0], 0.3))),
        ("Pink velvet", Some(([1.0, 0.45, 0.6], 0.5))),
        ("Velvet", Some(([1.0, 1.0, 1.0], 0.9))),
    ];
    let mut nodes = Vec::new();
    for (i, (name, sheen)) in sheens.into_iter().enumerate() {
        let others = sheen
            .filter(|_| with_sheen)
            .map(|([r, g, b], roughness)| {
                json::deserialize::from_str::<json::Value>(&format!(
                    r#"{{"KHR_materials_sheen": {{"sheenColorFactor": [{r}, {g}, {b}], "sheenRoughnessFactor": {roughness}{textures}}}}}"#
                ))
                .ok()
                .and_then(|v| v.as_object().cloned())
                .unwrap_or_default()
            })
            .unwrap_or_default();
        let material = doc.material(json::Material {
            name: Some(name.into()),
            pbr_metallic_roughness: json::material::PbrMetallicRoughness {
                base_color_factor: json::material::PbrBaseColorFactor([0.05, 0.07, 0.25, 1.0]),
                metallic_factor: json::material::StrengthFactor(0.0),
                roughness_factor: json::material::StrengthFactor(0.8),
                ..Default::default()
            },
            extensions: Some(json::extensions::material::Material {
                others,
                ..Default::default()
            }),
            ..Default::default()
        });
        let mut mesh = doc.root.meshes[sphere.value()].clone();
        mesh.primitives[0].material = Some(material);
        mesh.name = Some(name.into());
        let mesh = doc.root.push(mesh);
        nodes.push(doc.node(mesh_node(Some(mesh), [i as f32 - 1.5, 0.0, 0.0], 1.0)));
    }
    doc.scene(nodes);
    doc.gltf_data_uri()
}

/// A window: an orange box seen through a pane whose
/// `KHR_materials_transmission` map is a frame (red 0: opaque) around four
/// panes (red 255: transmission 0.9), for docs/gltf.md's picture of the
/// map baked into the base colour's alpha.
pub fn transmission_window() -> Vec<u8> {
    let mut doc = Doc::new();
    let cube = doc.mesh_data("Box", &box_mesh(BoxParams::default()));
    let orange = doc.material(json::Material {
        name: Some("Orange".into()),
        pbr_metallic_roughness: json::material::PbrMetallicRoughness {
            base_color_factor: json::material::PbrBaseColorFactor([0.9, 0.35, 0.05, 1.0]),
            metallic_factor: json::material::StrengthFactor(0.0),
            roughness_factor: json::material::StrengthFactor(0.5),
            ..Default::default()
        },
        ..Default::default()
    });
    doc.root.meshes[cube.value()].primitives[0].material = Some(orange);
    let pane = floor_mesh(&mut doc, glam::Vec2::splat(2.0));
    // An 8-texel frame and cross (red 0) around four panes (red 255).
    let map = image::RgbaImage::from_fn(TEXTURE_SIZE, TEXTURE_SIZE, |x, y| {
        let bar = |c: u32| !(8..56).contains(&c) || (28..36).contains(&c);
        image::Rgba(if bar(x) || bar(y) {
            [0, 0, 0, 255]
        } else {
            [255, 0, 0, 255]
        })
    });
    let image = doc.png_image(&png(&map));
    let texture = doc.texture(image);
    let others = json::deserialize::from_str::<json::Value>(&format!(
        r#"{{"KHR_materials_transmission": {{"transmissionFactor": 0.9,
            "transmissionTexture": {{"index": {}}}}}}}"#,
        texture.value()
    ))
    .ok()
    .and_then(|v| v.as_object().cloned())
    .unwrap_or_default();
    doc.root
        .extensions_used
        .push("KHR_materials_transmission".into());
    let glass = doc.material(json::Material {
        name: Some("Window".into()),
        pbr_metallic_roughness: json::material::PbrMetallicRoughness {
            base_color_factor: json::material::PbrBaseColorFactor([0.85, 0.9, 1.0, 1.0]),
            metallic_factor: json::material::StrengthFactor(0.0),
            roughness_factor: json::material::StrengthFactor(0.3),
            ..Default::default()
        },
        double_sided: true,
        extensions: Some(json::extensions::material::Material {
            others,
            ..Default::default()
        }),
        ..Default::default()
    });
    doc.root.meshes[pane.value()].primitives[0].material = Some(glass);
    let behind = doc.node(mesh_node(Some(cube), [0.0, 0.0, -1.5], 1.0));
    // The grid lies in y = 0 facing +y: stood up to face the camera (+z).
    let window = doc.node(json::Node {
        mesh: Some(pane),
        rotation: Some(json::scene::UnitQuaternion([
            std::f32::consts::FRAC_1_SQRT_2,
            0.0,
            0.0,
            std::f32::consts::FRAC_1_SQRT_2,
        ])),
        ..Default::default()
    });
    doc.scene(vec![behind, window]);
    doc.gltf_data_uri()
}

/// A glass block before a checkered wall: `KHR_materials_transmission` 1
/// with `KHR_materials_ior` 1.5 and `KHR_materials_volume` (thickness 0.5,
/// a pale blue absorption over 0.8), turned so the wall's lines bend
/// through it; docs/gltf.md's picture of refracted transmission.
pub fn refraction_block() -> Vec<u8> {
    glass_block(None)
}

/// [`refraction_block`]'s glass with `KHR_materials_dispersion` 20 (an Abbe
/// number of 1, exaggerated: dense flint glass is about 30; so the fringes
/// are pixels wide at a picture's size), the checkered wall's edges fringed
/// in colour;
/// docs/gltf.md's picture of dispersion and the scene its cost is measured
/// on (against `refraction_block`, the same scene without it).
pub fn dispersion_block() -> Vec<u8> {
    glass_block(Some(20.0))
}

/// The wall and the turned glass block, with `dispersion` where given.
fn glass_block(dispersion: Option<f32>) -> Vec<u8> {
    let mut doc = Doc::new();
    let wall = floor_mesh(&mut doc, glam::Vec2::splat(4.0));
    let image = doc.png_image(&png(&checker([230, 220, 200, 255], [30, 40, 60, 255])));
    let texture = doc.texture(image);
    let mut paper = json::Material {
        name: Some("Wall".into()),
        ..Default::default()
    };
    paper.pbr_metallic_roughness.base_color_texture = Some(info(texture));
    paper.pbr_metallic_roughness.metallic_factor = json::material::StrengthFactor(0.0);
    let paper = doc.material(paper);
    doc.root.meshes[wall.value()].primitives[0].material = Some(paper);
    let block = doc.mesh_data("Block", &box_mesh(BoxParams::default()));
    let others = json::deserialize::from_str::<json::Value>(
        r#"{"KHR_materials_transmission": {"transmissionFactor": 1.0},
            "KHR_materials_ior": {"ior": 1.5},
            "KHR_materials_volume": {"thicknessFactor": 0.5,
                "attenuationColor": [0.6, 0.85, 1.0], "attenuationDistance": 0.8}}"#,
    )
    .ok()
    .and_then(|v| v.as_object().cloned())
    .unwrap_or_default();
    let mut others = others;
    if let Some(d) = dispersion {
        others.insert(
            "KHR_materials_dispersion".into(),
            json::deserialize::from_str(&format!(r#"{{"dispersion": {d}}}"#)).unwrap_or_default(),
        );
    }
    for name in others.keys() {
        doc.root.extensions_used.push(name.clone());
    }
    let glass = doc.material(json::Material {
        name: Some("Glass".into()),
        pbr_metallic_roughness: json::material::PbrMetallicRoughness {
            metallic_factor: json::material::StrengthFactor(0.0),
            roughness_factor: json::material::StrengthFactor(0.05),
            ..Default::default()
        },
        extensions: Some(json::extensions::material::Material {
            others,
            ..Default::default()
        }),
        ..Default::default()
    });
    doc.root.meshes[block.value()].primitives[0].material = Some(glass);
    // The grid lies in y = 0 facing +y: stood up to face the camera (+z).
    let (s, c) = (
        std::f32::consts::FRAC_1_SQRT_2,
        std::f32::consts::FRAC_1_SQRT_2,
    );
    let wall = doc.node(json::Node {
        mesh: Some(wall),
        rotation: Some(json::scene::UnitQuaternion([s, 0.0, 0.0, c])),
        translation: Some([0.0, 0.0, -1.0]),
        ..Default::default()
    });
    // Turned 0.6 rad about y.
    let half = 0.3f32;
    let block = doc.node(json::Node {
        mesh: Some(block),
        rotation: Some(json::scene::UnitQuaternion([
            0.0,
            half.sin(),
            0.0,
            half.cos(),
        ])),
        translation: Some([0.0, 0.0, 0.2]),
        ..Default::default()
    });
    doc.scene(vec![wall, block]);
    doc.gltf_data_uri()
}

/// The strengths of [`brushed_metal_row`]'s discs, left to right.
pub const BRUSHED_STRENGTHS: [f32; 4] = [0.0, 0.3, 0.6, 1.0];

/// A circularly brushed anisotropy map (`KHR_materials_anisotropy`'s
/// anisotropyTexture): at each texel the direction runs around the map's
/// centre (rg, in the tangent frame: x along u, y up the image), at full
/// strength (b); the centre texel, which has no such direction, along u.
pub fn circular_brush(size: u32) -> image::RgbaImage {
    image::RgbaImage::from_fn(size, size, |x, y| {
        let half = size as f32 / 2.0;
        let px = (x as f32 + 0.5 - half) / half;
        let py = (half - y as f32 - 0.5) / half;
        let (dx, dy) = match glam::Vec2::new(-py, px).try_normalize() {
            Some(d) => (d.x, d.y),
            None => (1.0, 0.0),
        };
        let channel = |c: f32| ((c * 0.5 + 0.5) * 255.0).round() as u8;
        image::Rgba([channel(dx), channel(dy), 255, 255])
    })
}

/// Brushed metal: four discs (flat cylinders, a cap facing +Z) in a row
/// along x, a silvery metal of roughness 0.35 with
/// `KHR_materials_anisotropy` strengths [`BRUSHED_STRENGTHS`] over a
/// [`circular_brush`] map, for `patches/brushed-metal.ron` and the picture
/// in docs/materials.md.
pub fn brushed_metal_row() -> Vec<u8> {
    metal_disc_row(BRUSHED_STRENGTHS)
}

/// [`brushed_metal_row`] with every strength 0: the same discs, maps and
/// materials, which the importer makes isotropic (no Anisotropy feature,
/// no map): what `spreadlight bench` compares the example against.
pub fn plain_metal_row() -> Vec<u8> {
    metal_disc_row([0.0; 4])
}

fn metal_disc_row(strengths: [f32; 4]) -> Vec<u8> {
    use spreadlight_render::mesh::primitives::{CylinderParams, cylinder};
    let mut doc = Doc::new();
    let disc = doc.mesh_data(
        "Disc",
        &cylinder(CylinderParams {
            radius: 0.8,
            height: 0.1,
            sectors: 48,
            caps: true,
        }),
    );
    let brush = doc.png_image(&png(&circular_brush(64)));
    let brush = doc.texture(brush);
    doc.root
        .extensions_used
        .push("KHR_materials_anisotropy".into());
    // The cylinder's top cap (+Y) turned to face the camera on +Z.
    let facing = glam::Quat::from_rotation_x(std::f32::consts::FRAC_PI_2);
    let mut nodes = Vec::new();
    for (i, strength) in strengths.into_iter().enumerate() {
        let extension = format!(
            r#"{{"KHR_materials_anisotropy": {{"anisotropyStrength": {strength}, "anisotropyTexture": {{"index": {}}}}}}}"#,
            brush.value()
        );
        let others = json::deserialize::from_str::<json::Value>(&extension)
            .ok()
            .and_then(|v| v.as_object().cloned())
            .unwrap_or_default();
        let material = doc.material(json::Material {
            name: Some(format!("Brushed {strength}")),
            pbr_metallic_roughness: json::material::PbrMetallicRoughness {
                base_color_factor: json::material::PbrBaseColorFactor([0.92, 0.92, 0.95, 1.0]),
                metallic_factor: json::material::StrengthFactor(1.0),
                roughness_factor: json::material::StrengthFactor(0.35),
                ..Default::default()
            },
            extensions: Some(json::extensions::material::Material {
                others,
                ..Default::default()
            }),
            ..Default::default()
        });
        let mut mesh = doc.root.meshes[disc.value()].clone();
        mesh.primitives[0].material = Some(material);
        mesh.name = Some(format!("Disc {i}"));
        let mesh = doc.root.push(mesh);
        let mut node = mesh_node(Some(mesh), [i as f32 * 1.8 - 2.7, 0.0, 0.0], 1.0);
        node.rotation = Some(json::scene::UnitQuaternion(facing.to_array()));
        nodes.push(doc.node(node));
    }
    doc.scene(nodes);
    doc.gltf_data_uri()
}

/// `KHR_materials_variants`: a box "Body" and a smaller box "Lid" on it.
/// Materials: Red (0, the body's default), Green (1), Blue (2), White (3,
/// the lid's default), Black (4). Variants: "Forest" (body Green, the lid
/// unmapped: White) and "Ocean" (body Blue, lid Black). For the loader's,
/// the glTF node's and `spreadlight view --variant`'s tests.
pub fn material_variants() -> Vec<u8> {
    let mut doc = Doc::new();
    let colours: [(&str, [f32; 4]); 5] = [
        ("Red", [0.8, 0.05, 0.05, 1.0]),
        ("Green", [0.05, 0.8, 0.05, 1.0]),
        ("Blue", [0.05, 0.05, 0.8, 1.0]),
        ("White", [0.9, 0.9, 0.9, 1.0]),
        ("Black", [0.02, 0.02, 0.02, 1.0]),
    ];
    let materials: Vec<_> = colours
        .iter()
        .map(|&(name, colour)| {
            doc.material(json::Material {
                name: Some(name.into()),
                pbr_metallic_roughness: json::material::PbrMetallicRoughness {
                    base_color_factor: json::material::PbrBaseColorFactor(colour),
                    metallic_factor: json::material::StrengthFactor(0.0),
                    roughness_factor: json::material::StrengthFactor(0.5),
                    ..Default::default()
                },
                ..Default::default()
            })
        })
        .collect();
    let body = doc.mesh_data("Body", &box_mesh(BoxParams::default()));
    let lid = doc.mesh_data("Lid", &box_mesh(BoxParams::default()));
    let mapped = |default: usize, mappings: &str| {
        let others = json::deserialize::from_str::<json::Value>(&format!(
            r#"{{"KHR_materials_variants": {{"mappings": {mappings}}}}}"#
        ))
        .ok()
        .and_then(|v| v.as_object().cloned())
        .unwrap_or_default();
        (
            Some(materials[default]),
            Some(json::extensions::mesh::Primitive { others }),
        )
    };
    let body_primitive = &mut doc.root.meshes[body.value()].primitives[0];
    (body_primitive.material, body_primitive.extensions) = mapped(
        0,
        r#"[{"material": 1, "variants": [0]}, {"material": 2, "variants": [1]}]"#,
    );
    let lid_primitive = &mut doc.root.meshes[lid.value()].primitives[0];
    (lid_primitive.material, lid_primitive.extensions) =
        mapped(3, r#"[{"material": 4, "variants": [1]}]"#);
    let variants = json::deserialize::from_str::<json::Value>(
        r#"{"variants": [{"name": "Forest"}, {"name": "Ocean"}]}"#,
    )
    .unwrap_or_default();
    doc.root
        .extensions
        .get_or_insert_with(Default::default)
        .others
        .insert("KHR_materials_variants".into(), variants);
    doc.root
        .extensions_used
        .push("KHR_materials_variants".into());
    let body = doc.node(mesh_node(Some(body), [0.0; 3], 1.0));
    let lid = doc.node(mesh_node(Some(lid), [0.0, 0.75, 0.0], 0.5));
    doc.scene(vec![body, lid]);
    doc.gltf_data_uri()
}
