//! Skins: each vertex's joint influences (JOINTS_n / WEIGHTS_n, every set
//! the file has, the 8 strongest kept), each skin's joints and inverse bind
//! matrices, and the joint matrices of a pose. The deformation itself runs
//! on the GPU (`render::geometry::skinning`); [`skin_point`] is its CPU
//! reference.
//!
//! What the loader does with skins the spec does not allow:
//! - weights that do not sum to 1 are normalized (one warning per primitive);
//! - negative or non-finite weights count as 0 (warned);
//! - a vertex with no weight at all follows the mesh's node (warned);
//! - a joint index beyond the skin's joints, or fewer inverse bind matrices
//!   than joints, refuses the file with an error naming the node, skin and
//!   primitive.

use glam::{Mat4, Vec3};
use gltf::Semantic;

use super::{GltfError, Importer};
use spreadlight_render::mesh::Aabb;
pub use spreadlight_render::mesh::deform::{
    Influences, MAX_INFLUENCES, MAX_JOINTS, UNSKINNED, skin_point,
};

/// A glTF skin: its joints (glTF node indices) and the matrix that takes
/// the mesh into each joint's space at bind time.
#[derive(Debug, Clone, PartialEq)]
pub struct Skin {
    /// "skin 0 `Armature`": how messages name it.
    pub name: String,
    pub joints: Vec<usize>,
    /// One per joint (identity when the file gives none).
    pub inverse_bind: Vec<Mat4>,
}

impl Skin {
    /// The joint matrices at a pose (`world`: every node's world transform),
    /// then `mesh_world` (the skinned node's own transform, for vertices
    /// without weights). Skinned vertices land in world space.
    pub fn palette(&self, world: &[Mat4], mesh_world: Mat4) -> Vec<Mat4> {
        self.joints
            .iter()
            .zip(&self.inverse_bind)
            .map(|(&j, ibm)| world.get(j).copied().unwrap_or(Mat4::IDENTITY) * *ibm)
            .chain([mesh_world])
            .collect()
    }
}

/// One JOINTS_n/WEIGHTS_n pair as read: per file vertex, four of each.
type InfluenceSet = (Vec<[u32; 4]>, Vec<[f32; 4]>);

/// Counts of vertices whose weights were repaired, for one warning each.
#[derive(Default)]
struct Repairs {
    unnormalized: usize,
    unweighted: usize,
    bad: usize,
    dropped: usize,
}

impl Importer<'_> {
    /// The skins of the file, in file order.
    pub(super) fn skins(&mut self, document: &gltf::Document) -> Result<Vec<Skin>, GltfError> {
        let mut out = Vec::new();
        for skin in document.skins() {
            let name = match skin.name() {
                Some(n) => format!("skin {} `{n}`", skin.index()),
                None => format!("skin {}", skin.index()),
            };
            let error = |reason: String| GltfError::Skin {
                path: self.path.to_owned(),
                skin: name.clone(),
                reason,
            };
            let joints: Vec<usize> = skin.joints().map(|n| n.index()).collect();
            if joints.len() > MAX_JOINTS {
                return Err(error(format!(
                    "it has {} joints; at most {MAX_JOINTS} are supported",
                    joints.len()
                )));
            }
            let inverse_bind = match skin.inverse_bind_matrices() {
                None => vec![Mat4::IDENTITY; joints.len()],
                Some(accessor) => {
                    let read = self.buffers.read_mat4(&accessor).map_err(|reason| {
                        GltfError::Accessor {
                            path: self.path.to_owned(),
                            index: accessor.index(),
                            usage: format!("inverse bind matrices of {name}"),
                            reason,
                        }
                    })?;
                    if read.len() < joints.len() {
                        return Err(error(format!(
                            "it has {} joints but {} inverse bind matrices (accessor {})",
                            joints.len(),
                            read.len(),
                            accessor.index()
                        )));
                    }
                    if let Some(k) = read.iter().position(|m| !m.iter().all(|x| x.is_finite())) {
                        return Err(error(format!(
                            "inverse bind matrix {k} is not finite (accessor {})",
                            accessor.index()
                        )));
                    }
                    read.iter()
                        .take(joints.len())
                        .map(Mat4::from_cols_array)
                        .collect()
                }
            };
            out.push(Skin {
                name,
                joints,
                inverse_bind,
            });
        }
        Ok(out)
    }

    /// The primitive's joint influences, or `None` when it has no
    /// JOINTS_0/WEIGHTS_0. `origin` maps output vertices to the file's
    /// (when the loader unwelded them); `positions` are the output's.
    pub(super) fn influences(
        &mut self,
        name: &str,
        primitive: &gltf::Primitive,
        vertices: usize,
        origin: Option<&[u32]>,
        positions: &[[f32; 3]],
    ) -> Result<Option<Influences>, GltfError> {
        let mut sets: Vec<InfluenceSet> = Vec::new();
        for set in 0u32.. {
            let joints = primitive.get(&Semantic::Joints(set));
            let weights = primitive.get(&Semantic::Weights(set));
            let (joints, weights) = match (joints, weights) {
                (Some(j), Some(w)) => (j, w),
                (None, None) => break,
                (j, _) => {
                    let (has, lacks) = if j.is_some() {
                        ("JOINTS", "WEIGHTS")
                    } else {
                        ("WEIGHTS", "JOINTS")
                    };
                    self.warn(format!(
                        "{name}: it has {has}_{set} but no {lacks}_{set}; that set is ignored"
                    ));
                    break;
                }
            };
            let j = self.buffers.read_joints(&joints).map_err(|reason| {
                self.accessor_error(&joints, &format!("JOINTS_{set}"), name, reason)
            })?;
            let w = self.buffers.read_floats::<4>(&weights).map_err(|reason| {
                self.accessor_error(&weights, &format!("WEIGHTS_{set}"), name, reason)
            })?;
            for (count, what) in [(j.len(), "JOINTS"), (w.len(), "WEIGHTS")] {
                if count != vertices {
                    return Err(GltfError::Primitive {
                        path: self.path.to_owned(),
                        primitive: name.to_owned(),
                        reason: format!(
                            "{what}_{set} has {count} elements but POSITION has {vertices}"
                        ),
                    });
                }
            }
            sets.push((j, w));
        }
        if sets.is_empty() {
            return Ok(None);
        }
        let mut repairs = Repairs::default();
        let per_file_vertex: Vec<([u32; MAX_INFLUENCES], [f32; MAX_INFLUENCES])> = (0..vertices)
            .map(|v| vertex_influences(&sets, v, &mut repairs))
            .collect();
        let mut influences = Influences::default();
        let mut bounds: std::collections::BTreeMap<u32, Aabb> = Default::default();
        for (out, position) in positions.iter().enumerate() {
            let from = origin.map_or(out, |o| o[out] as usize);
            let Some(&(joints, weights)) = per_file_vertex.get(from) else {
                continue;
            };
            for (j, w) in joints.iter().zip(&weights) {
                if *w == 0.0 {
                    continue;
                }
                if *j != UNSKINNED && influences.max_joint.is_none_or(|(m, _)| *j > m) {
                    influences.max_joint = Some((*j, from));
                }
                let p = Aabb {
                    min: Vec3::from(*position),
                    max: Vec3::from(*position),
                };
                bounds
                    .entry(*j)
                    .and_modify(|b| *b = b.union(p))
                    .or_insert(p);
            }
            influences.joints.push(joints);
            influences.weights.push(weights);
        }
        influences.joint_bounds = bounds.into_iter().collect();
        let warnings = [
            (
                repairs.unnormalized,
                "weights do not sum to 1; they are normalized",
            ),
            (
                repairs.unweighted,
                "no joint weight; they follow the mesh's node",
            ),
            (
                repairs.bad,
                "negative or non-finite weights; those count as 0",
            ),
            (
                repairs.dropped,
                "more than 8 joint influences; the weakest are dropped",
            ),
        ];
        for (count, what) in warnings {
            if count > 0 {
                self.warn(format!("{name}: {count} vertices have {what}"));
            }
        }
        Ok(Some(influences))
    }
}

/// Vertex `v`'s strongest influences over every set, normalized.
fn vertex_influences(
    sets: &[InfluenceSet],
    v: usize,
    repairs: &mut Repairs,
) -> ([u32; MAX_INFLUENCES], [f32; MAX_INFLUENCES]) {
    let mut all: Vec<(u32, f32)> = Vec::with_capacity(4 * sets.len());
    let mut bad = false;
    for (joints, weights) in sets {
        for k in 0..4 {
            let w = weights[v][k];
            if !w.is_finite() || w < 0.0 {
                bad = true;
            } else if w > 0.0 {
                all.push((joints[v][k], w));
            }
        }
    }
    repairs.bad += usize::from(bad);
    // Strongest first; equal weights keep the file's order.
    all.sort_by(|a, b| b.1.total_cmp(&a.1));
    if all.len() > MAX_INFLUENCES {
        repairs.dropped += 1;
        all.truncate(MAX_INFLUENCES);
    }
    let sum: f32 = all.iter().map(|(_, w)| w).sum();
    let mut joints = [0u32; MAX_INFLUENCES];
    let mut weights = [0f32; MAX_INFLUENCES];
    if !(sum > 0.0 && sum.is_finite()) {
        repairs.unweighted += 1;
        joints[0] = UNSKINNED;
        weights[0] = 1.0;
        return (joints, weights);
    }
    // glTF allows rounding: a sum within 2e-3 of 1 is taken as meant to be 1.
    if (sum - 1.0).abs() > 2e-3 {
        repairs.unnormalized += 1;
    }
    for (k, (j, w)) in all.into_iter().enumerate() {
        joints[k] = j;
        weights[k] = w / sum;
    }
    (joints, weights)
}
