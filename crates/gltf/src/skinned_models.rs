//! Generated skinned and morphed glTF models (nothing is downloaded): a flat
//! two-bone bar whose motion is known exactly (velocity tests), a tube on a
//! chain of joints with a morph target (reference images), and the
//! skinning benchmark's herd of tubes (`patches/assets/bench-skinning.gltf`).

use std::f32::consts::{FRAC_PI_2, TAU};

use glam::{Mat4, Quat, Vec3};
use gltf::json;
use json::accessor::{ComponentType, Type};
use json::validation::Checked::Valid;
use json::{Index, Node};

use super::builder::{Doc, bytes, primitive};

/// Rotation of the bar's second bone, radians per second (`two_bone_bar`).
pub const BAR_BEND_RATE: f32 = FRAC_PI_2;

/// A joint index accessor (VEC4 of UNSIGNED_SHORT).
pub fn joints(doc: &mut Doc, j: &[[u16; 4]]) -> Index<json::Accessor> {
    let view = doc.view(&bytes(j.as_flattened()));
    doc.accessor(Some(view), j.len(), ComponentType::U16, Type::Vec4)
}

/// Inverse bind matrices (MAT4 of FLOAT).
fn matrices(doc: &mut Doc, m: &[Mat4]) -> Index<json::Accessor> {
    let flat: Vec<f32> = m.iter().flat_map(|m| m.to_cols_array()).collect();
    let view = doc.view(&bytes(&flat));
    doc.accessor(Some(view), m.len(), ComponentType::F32, Type::Mat4)
}

/// Keyframe times (SCALAR of FLOAT, with the min and max glTF requires).
fn times(doc: &mut Doc, t: &[f32]) -> Index<json::Accessor> {
    let view = doc.view(&bytes(t));
    let a = doc.accessor(Some(view), t.len(), ComponentType::F32, Type::Scalar);
    let accessor = &mut doc.root.accessors[a.value()];
    accessor.min = Some(json::Value::from(vec![t[0]]));
    accessor.max = Some(json::Value::from(vec![t[t.len() - 1]]));
    a
}

fn scalars(doc: &mut Doc, v: &[f32]) -> Index<json::Accessor> {
    let view = doc.view(&bytes(v));
    doc.accessor(Some(view), v.len(), ComponentType::F32, Type::Scalar)
}

/// A linear channel of `node`'s `path` from `input` to `output`.
fn channel(
    samplers: &mut Vec<json::animation::Sampler>,
    channels: &mut Vec<json::animation::Channel>,
    node: Index<Node>,
    path: json::animation::Property,
    input: Index<json::Accessor>,
    output: Index<json::Accessor>,
) {
    channels.push(json::animation::Channel {
        sampler: Index::new(samplers.len() as u32),
        target: json::animation::Target {
            node,
            path: Valid(path),
            extensions: None,
            extras: Default::default(),
        },
        extensions: None,
        extras: Default::default(),
    });
    samplers.push(json::animation::Sampler {
        input,
        interpolation: Valid(json::animation::Interpolation::Linear),
        output,
        extensions: None,
        extras: Default::default(),
    });
}

fn animation(
    doc: &mut Doc,
    name: &str,
    samplers: Vec<json::animation::Sampler>,
    channels: Vec<json::animation::Channel>,
) {
    doc.root.push(json::Animation {
        channels,
        samplers,
        name: Some(name.into()),
        extensions: None,
        extras: Default::default(),
    });
}

fn skin(
    doc: &mut Doc,
    name: &str,
    joints: Vec<Index<Node>>,
    ibm: Index<json::Accessor>,
) -> Index<json::Skin> {
    doc.root.push(json::Skin {
        extensions: None,
        extras: Default::default(),
        inverse_bind_matrices: Some(ibm),
        skeleton: joints.first().copied(),
        joints,
        name: Some(name.into()),
    })
}

fn joint_node(name: String, translation: Vec3, children: Vec<Index<Node>>) -> Node {
    Node {
        name: Some(name),
        translation: Some(translation.into()),
        children: (!children.is_empty()).then_some(children),
        ..Default::default()
    }
}

/// A flat bar in the XY plane facing +Z, from x = 0 to 2 and y = -0.1 to
/// 0.1, in 8 segments, on two joints: `Root` at the origin (vertices with
/// x < 1) and `Tip` at x = 1 (x > 1); the column at x = 1 is shared half
/// and half. Animation `Bend` turns `Tip` about +Z at [`BAR_BEND_RATE`]
/// from 0 to a right angle over 1 s; the part of the bar beyond x = 1.25
/// turns rigidly about (1, 0, 0).
pub fn two_bone_bar() -> Vec<u8> {
    two_bone_bar_doc().gltf_data_uri()
}

/// [`two_bone_bar`] before it is written, for tests that break it: its
/// mesh's one primitive reads JOINTS_0 and WEIGHTS_0, and skin 0 has
/// inverse bind matrices.
pub fn two_bone_bar_doc() -> Doc {
    let mut doc = Doc::new();
    let (mut positions, mut weights, mut joint_ids) = (Vec::new(), Vec::new(), Vec::new());
    for column in 0..=8 {
        let x = column as f32 * 0.25;
        for y in [-0.1f32, 0.1] {
            positions.push([x, y, 0.0]);
            let tip = if x < 1.0 {
                0.0
            } else if x > 1.0 {
                1.0
            } else {
                0.5
            };
            joint_ids.push([0u16, 1, 0, 0]);
            weights.push([1.0 - tip, tip, 0.0, 0.0]);
        }
    }
    let indices: Vec<u16> = (0..8u16)
        .flat_map(|c| {
            let (a, b, d, e) = (2 * c, 2 * c + 1, 2 * c + 2, 2 * c + 3);
            [a, d, b, b, d, e]
        })
        .collect();
    let normals = vec![[0.0f32, 0.0, 1.0]; positions.len()];
    let attributes = vec![
        (json::mesh::Semantic::Positions, doc.positions(&positions)),
        (json::mesh::Semantic::Normals, doc.floats(&normals)),
        (
            json::mesh::Semantic::Joints(0),
            joints(&mut doc, &joint_ids),
        ),
        (json::mesh::Semantic::Weights(0), doc.floats(&weights)),
    ];
    let indices = doc.indices(&indices);
    let mesh = doc.mesh(
        "Bar",
        vec![primitive(
            &attributes,
            Some(indices),
            json::mesh::Mode::Triangles,
        )],
    );
    let tip = doc.node(joint_node("Tip".into(), Vec3::X, vec![]));
    let root = doc.node(joint_node("Root".into(), Vec3::ZERO, vec![tip]));
    let ibm = matrices(
        &mut doc,
        &[Mat4::IDENTITY, Mat4::from_translation(-Vec3::X)],
    );
    let skin = skin(&mut doc, "Arm", vec![root, tip], ibm);
    let body = doc.node(Node {
        name: Some("Body".into()),
        mesh: Some(mesh),
        skin: Some(skin),
        ..Default::default()
    });
    doc.scene(vec![root, body]);
    let keys = [0.0f32, 0.5, 1.0];
    let input = times(&mut doc, &keys);
    let turns: Vec<[f32; 4]> = keys
        .iter()
        .map(|t| Quat::from_rotation_z(BAR_BEND_RATE * t).to_array())
        .collect();
    let output = doc.floats(&turns);
    let (mut samplers, mut channels) = (Vec::new(), Vec::new());
    use json::animation::Property;
    channel(
        &mut samplers,
        &mut channels,
        tip,
        Property::Rotation,
        input,
        output,
    );
    animation(&mut doc, "Bend", samplers, channels);
    doc
}

/// [`two_bone_bar`] with a COLOR_0 and a TEXCOORD_1 of its own at every
/// vertex, and those colours and UVs in vertex order: what a skinned mesh
/// must keep through its deformation.
pub fn coloured_two_bone_bar() -> (Vec<u8>, Vec<[f32; 4]>, Vec<[f32; 2]>) {
    let mut doc = two_bone_bar_doc();
    let count = 18;
    let colours: Vec<[f32; 4]> = (0..count)
        .map(|i| {
            let t = i as f32 / (count - 1) as f32;
            [t, 1.0 - t, 0.25, 1.0]
        })
        .collect();
    let uvs: Vec<[f32; 2]> = (0..count).map(|i| [i as f32 * 0.5, 2.0]).collect();
    let colour = doc.floats(&colours);
    let uv = doc.floats(&uvs);
    let attributes = &mut doc.root.meshes[0].primitives[0].attributes;
    attributes.insert(Valid(json::mesh::Semantic::Colors(0)), colour);
    attributes.insert(Valid(json::mesh::Semantic::TexCoords(1)), uv);
    (doc.gltf_data_uri(), colours, uvs)
}

/// A skinned tube: what [`tube`] makes.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct TubeSpec {
    /// Along +X from the origin.
    pub length: f32,
    pub radius: f32,
    /// Rings of vertices along the tube, and vertices around each ring.
    pub rings: usize,
    pub sides: usize,
    /// Joints in a chain along the tube (at least 1).
    pub joints: usize,
    /// Joint influences per vertex: 4 (JOINTS_0 only) or 8 (and JOINTS_1).
    pub influences: usize,
    /// Copies of the rig on a grid around the origin (x spaced by `length`
    /// * 1.2, z by half that), each with its own skeleton, out of phase.
    pub copies: usize,
}

/// Tubes swaying on chains of joints (each joint turns about Z by up to
/// 1.2 rad / joints and about Y by half that, period 2 s), with a morph target that swells the far half
/// (its weight |sin(pi t)|: 1 at 0.5 s and 1.5 s, 0 at whole seconds). The mesh is
/// shared by every copy; each copy has its own skin and joints.
pub fn tube(spec: TubeSpec) -> Vec<u8> {
    let mut doc = Doc::new();
    let joints_n = spec.joints.max(1);
    let (rings, sides) = (spec.rings.max(2), spec.sides.max(3));
    let segment = spec.length / joints_n as f32;
    let (mut positions, mut normals, mut uvs) = (Vec::new(), Vec::new(), Vec::new());
    let (mut sets, mut bulge) = (vec![Vec::new(), Vec::new()], Vec::new());
    for r in 0..rings {
        let u = r as f32 / (rings - 1) as f32;
        let x = u * spec.length;
        let influences = tube_influences(x / segment, joints_n, spec.influences);
        for s in 0..=sides {
            let a = s as f32 / sides as f32 * TAU;
            let radial = Vec3::new(0.0, a.cos(), a.sin());
            positions.push((Vec3::X * x + radial * spec.radius).to_array());
            normals.push(radial.to_array());
            uvs.push([u, s as f32 / sides as f32]);
            // The far half swells to twice the radius at the end.
            let swell = ((u - 0.5) * 2.0).max(0.0);
            bulge.push((radial * spec.radius * swell).to_array());
            for (k, set) in sets.iter_mut().enumerate() {
                set.push(influences[k]);
            }
        }
    }
    let row = (sides + 1) as u16;
    let indices: Vec<u16> = (0..rings as u16 - 1)
        .flat_map(|r| {
            (0..sides as u16).flat_map(move |s| {
                let (a, b) = (r * row + s, (r + 1) * row + s);
                [a, b, a + 1, a + 1, b, b + 1]
            })
        })
        .collect();
    use json::mesh::Semantic as S;
    let mut attributes = vec![
        (S::Positions, doc.positions(&positions)),
        (S::Normals, doc.floats(&normals)),
        (S::TexCoords(0), doc.floats(&uvs)),
    ];
    let set_count = if spec.influences > 4 { 2 } else { 1 };
    for (k, set) in sets.iter().take(set_count).enumerate() {
        let ids: Vec<[u16; 4]> = set.iter().map(|(j, _)| *j).collect();
        let w: Vec<[f32; 4]> = set.iter().map(|(_, w)| *w).collect();
        attributes.push((S::Joints(k as u32), joints(&mut doc, &ids)));
        attributes.push((S::Weights(k as u32), doc.floats(&w)));
    }
    let indices = doc.indices(&indices);
    let mut prim = primitive(&attributes, Some(indices), json::mesh::Mode::Triangles);
    prim.targets = Some(vec![json::mesh::MorphTarget {
        positions: Some(doc.positions(&bulge)),
        normals: None,
        tangents: None,
    }]);
    let mesh = doc.mesh("Tube", vec![prim]);
    doc.root.meshes[mesh.value()].weights = Some(vec![0.0]);
    let ibm: Vec<Mat4> = (0..joints_n)
        .map(|j| Mat4::from_translation(-Vec3::X * segment * j as f32))
        .collect();
    let ibm = matrices(&mut doc, &ibm);

    // One period, 9 keys: every copy samples its own phase of the same sway.
    let keys: Vec<f32> = (0..=8).map(|k| k as f32 * 0.25).collect();
    let input = times(&mut doc, &keys);
    let phases = spec.copies.clamp(1, 8);
    let sways: Vec<Index<json::Accessor>> = (0..phases)
        .map(|p| {
            let turns: Vec<[f32; 4]> = keys
                .iter()
                .map(|t| {
                    let a = (t / 2.0 + p as f32 / phases as f32) * TAU;
                    // Split over the chain: the whole tube bends up to 1.2 rad.
                    let bend = 1.2 / joints_n as f32;
                    (Quat::from_rotation_z(bend * a.sin())
                        * Quat::from_rotation_y(0.5 * bend * a.cos()))
                    .to_array()
                })
                .collect();
            doc.floats(&turns)
        })
        .collect();
    let swell: Vec<f32> = keys.iter().map(|t| (t * 0.5 * TAU).sin().abs()).collect();
    let swell = scalars(&mut doc, &swell);

    let side = (spec.copies.max(1) as f32).sqrt().ceil() as usize;
    let spacing = spec.length * 1.2;
    let (mut samplers, mut channels, mut roots) = (Vec::new(), Vec::new(), Vec::new());
    use json::animation::Property;
    for copy in 0..spec.copies.max(1) {
        // Centred on the origin (the tube runs along +X from its root).
        let middle = (side - 1) as f32 * 0.5;
        let at = Vec3::new(
            ((copy % side) as f32 - middle) * spacing - spec.length * 0.5,
            0.0,
            ((copy / side) as f32 - middle) * spacing * 0.5,
        );
        // The chain, tip first so each joint's child exists when it is made.
        let mut chain = Vec::new();
        let mut child: Option<Index<Node>> = None;
        for j in (0..joints_n).rev() {
            let offset = if j == 0 { at } else { Vec3::X * segment };
            let node = doc.node(joint_node(
                format!("Joint {copy}.{j}"),
                offset,
                child.into_iter().collect(),
            ));
            chain.push(node);
            child = Some(node);
        }
        chain.reverse();
        for &joint in &chain[1..] {
            let sway = sways[copy % phases];
            channel(
                &mut samplers,
                &mut channels,
                joint,
                Property::Rotation,
                input,
                sway,
            );
        }
        let skin = skin(&mut doc, &format!("Rig {copy}"), chain.clone(), ibm);
        let body = doc.node(Node {
            name: Some(format!("Tube {copy}")),
            mesh: Some(mesh),
            skin: Some(skin),
            ..Default::default()
        });
        channel(
            &mut samplers,
            &mut channels,
            body,
            Property::MorphTargetWeights,
            input,
            swell,
        );
        roots.push(chain[0]);
        roots.push(body);
    }
    doc.scene(roots);
    animation(&mut doc, "Sway", samplers, channels);
    doc.gltf_data_uri()
}

/// The strongest `count` (4 or 8) joints of a vertex at `s` joint segments
/// along the chain, in two sets of four: weights fall off with distance
/// from each joint's segment middle and sum to 1.
fn tube_influences(s: f32, joints: usize, count: usize) -> [([u16; 4], [f32; 4]); 2] {
    let mut near: Vec<(usize, f32)> = (0..joints)
        .map(|j| {
            let d = s - (j as f32 + 0.5);
            (j, (-d * d * 1.5).exp())
        })
        .collect();
    near.sort_by(|a, b| b.1.total_cmp(&a.1));
    near.truncate(count.clamp(1, 8));
    let sum: f32 = near.iter().map(|(_, w)| w).sum();
    let mut out = [([0u16; 4], [0f32; 4]); 2];
    for (k, (j, w)) in near.into_iter().enumerate() {
        out[k / 4].0[k % 4] = j as u16;
        out[k / 4].1[k % 4] = w / sum;
    }
    out
}

/// The figure the reference images show: one tube of 6 joints and 8
/// influences per vertex (both JOINTS sets), with its morph target.
pub fn swaying_tube() -> Vec<u8> {
    tube(TubeSpec {
        length: 2.4,
        radius: 0.18,
        rings: 25,
        sides: 12,
        joints: 6,
        influences: 8,
        copies: 1,
    })
}

/// The skinning benchmark (`patches/bench-skinning.ron`): 100 copies of a
/// 20-joint tube of 3,232 vertices, 4 influences each.
pub fn bench_herd() -> Vec<u8> {
    tube(TubeSpec {
        length: 4.0,
        radius: 0.25,
        rings: 202,
        sides: 15,
        joints: 20,
        influences: 4,
        copies: 100,
    })
}
