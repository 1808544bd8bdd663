//! What deforms a mesh: joint influences (skins) and morph targets, as the
//! glTF importer (`spreadlight-gltf`) reads them and the GPU pass
//! (`geometry::skinning`) consumes them, with the CPU reference of the
//! blend ([`skin_point`]) and conservative bounds of a pose.
//!
//! Pure data here, below both: the importer depends on the renderer, never
//! the other way round.

use glam::{Mat4, Vec3};

use super::Aabb;

/// Influences kept per vertex: two sets of JOINTS/WEIGHTS.
pub const MAX_INFLUENCES: usize = 8;

/// The joint index of a vertex without weights: the palette's last matrix,
/// the mesh node's world transform.
pub const UNSKINNED: u32 = u32::MAX;

/// Joints a skin may have: joint indices go to the GPU as 16 bits, and
/// 0xFFFF stands for [`UNSKINNED`].
pub const MAX_JOINTS: usize = 0xFFFF;

/// Per vertex, up to [`MAX_INFLUENCES`] joints (indices into the skin's
/// joints; [`UNSKINNED`] for vertices without weights) and their weights,
/// which sum to 1. Unused slots have weight 0.
#[derive(Debug, Clone, PartialEq, Default)]
pub struct Influences {
    pub joints: Vec<[u32; MAX_INFLUENCES]>,
    pub weights: Vec<[f32; MAX_INFLUENCES]>,
    /// The largest joint index in use and a vertex using it (for messages).
    pub max_joint: Option<(u32, usize)>,
    /// Rest-pose bounds of the vertices each joint moves: a posed vertex is
    /// a convex blend of its joints' transforms, so the union of these boxes
    /// transformed by their joints bounds the posed mesh.
    pub joint_bounds: Vec<(u32, Aabb)>,
}

/// `point` skinned by `palette` (joint matrices, the mesh node's last) with
/// one vertex's influences: what the GPU pass computes.
pub fn skin_point(
    palette: &[Mat4],
    joints: &[u32; MAX_INFLUENCES],
    weights: &[f32; MAX_INFLUENCES],
    point: Vec3,
) -> Vec3 {
    let mut blended = Mat4::ZERO;
    for (j, w) in joints.iter().zip(weights) {
        if *w != 0.0 {
            blended += palette_matrix(palette, *j) * *w;
        }
    }
    blended.transform_point3(point)
}

fn palette_matrix(palette: &[Mat4], joint: u32) -> Mat4 {
    let last = palette.len().saturating_sub(1);
    let at = if joint == UNSKINNED {
        last
    } else {
        (joint as usize).min(last)
    };
    palette.get(at).copied().unwrap_or(Mat4::IDENTITY)
}

impl Influences {
    /// Bounds of the mesh posed by `palette`, its rest positions grown by
    /// `morph` (the most the morph targets move a vertex, per axis).
    pub fn posed_bounds(&self, palette: &[Mat4], morph: Vec3) -> Aabb {
        self.joint_bounds
            .iter()
            .map(|(j, b)| {
                let grown = Aabb {
                    min: b.min - morph,
                    max: b.max + morph,
                };
                grown.transformed(palette_matrix(palette, *j))
            })
            .reduce(Aabb::union)
            .unwrap_or(Aabb::ZERO)
    }
}

/// One morph target of a primitive: deltas per vertex (an absent attribute
/// is empty: it does not move).
#[derive(Debug, Clone, PartialEq, Default)]
pub struct MorphTarget {
    pub positions: Vec<[f32; 3]>,
    pub normals: Vec<[f32; 3]>,
    pub tangents: Vec<[f32; 3]>,
    /// The largest position delta per axis (absolute): weight w moves no
    /// vertex further than w times this, which bounds the morphed mesh.
    pub extent: Vec3,
}

/// How far `weights` move any vertex of a primitive with `targets`, per axis.
pub fn morph_extent(targets: &[MorphTarget], weights: &[f32]) -> Vec3 {
    targets
        .iter()
        .zip(weights)
        .map(|(t, w)| t.extent * w.abs())
        .sum()
}

/// What deforms one primitive's vertices (empty for rigid meshes).
#[derive(Debug, Clone, PartialEq, Default)]
pub struct Deform {
    /// Joint influences (JOINTS_n/WEIGHTS_n), when it has them.
    pub influences: Option<Influences>,
    pub targets: Vec<MorphTarget>,
}

impl Deform {
    pub fn is_empty(&self) -> bool {
        self.influences.is_none() && self.targets.is_empty()
    }
}

/// One instance's deformation at one pose: what the GPU pass takes.
#[derive(Debug, Clone, PartialEq)]
pub struct DeformPose {
    /// Joint matrices, then the skinned node's world transform (vertices
    /// without weights follow it); empty for an instance without a skin.
    pub palette: Vec<Mat4>,
    /// One weight per morph target of the mesh.
    pub weights: Vec<f32>,
    /// Bounds of the deformed mesh in its own space (conservative).
    pub bounds: Aabb,
    /// What places the deformed mesh: identity for skinned (world space),
    /// the node's world transform for morph-only instances.
    pub transform: Mat4,
}

impl DeformPose {
    /// Whether `other` deforms the mesh as this pose does: the same joint
    /// matrices and morph weights, bit for bit (a pose sampled again at an
    /// unchanged time need not run again; `==` would call NaN unequal).
    pub fn deforms_as(&self, other: &DeformPose) -> bool {
        let bits = |m: &Mat4| m.to_cols_array().map(f32::to_bits);
        self.palette.len() == other.palette.len()
            && self.weights.len() == other.weights.len()
            && self
                .palette
                .iter()
                .zip(&other.palette)
                .all(|(a, b)| bits(a) == bits(b))
            && self
                .weights
                .iter()
                .zip(&other.weights)
                .all(|(a, b)| a.to_bits() == b.to_bits())
    }
}
