//! What deforms an instance at a pose: the joint matrices of its skin and
//! the weights of its morph targets, with conservative bounds of the
//! result, ready for the GPU pass (`render::geometry::skinning`).
//!
//! Skinned instances are deformed into world space (glTF: the skinned
//! node's own transform does not apply, its joints place it) and drawn with
//! the identity; morph-only instances stay in their mesh's space and are
//! drawn with their node's world transform.

use glam::{Mat4, Vec3};

use super::morph::morph_extent;
use super::skin::skin_point;
use super::{GltfScene, MeshInstance};
use spreadlight_render::mesh::Aabb;
pub use spreadlight_render::mesh::deform::{Deform, DeformPose};

impl GltfScene {
    /// Whether `instance` is deformed (skinned or morphed) rather than rigid.
    pub fn is_deformed(&self, instance: &MeshInstance) -> bool {
        instance.skin.is_some()
            || self
                .deforms
                .get(instance.mesh)
                .is_some_and(|d| !d.targets.is_empty())
    }

    /// Per glTF node, its morph weights as `animation` sets them at `time`
    /// (looping), or `None` where no channel animates them.
    pub fn morph_weights(&self, animation: Option<usize>, time: f32) -> Vec<Option<Vec<f32>>> {
        let mut out = vec![None; self.graph.rest.len()];
        if let Some(a) = animation.and_then(|a| self.animations.get(a)) {
            let time = a.looped(time);
            for c in &a.weights {
                if let Some(slot) = out.get_mut(c.node) {
                    *slot = Some(c.sample(time));
                }
            }
        }
        out
    }

    /// `instance` deformed at a pose: `world` from [`GltfScene::node_worlds`],
    /// `weights` from [`GltfScene::morph_weights`] of the same pose.
    pub fn deform_pose(
        &self,
        instance: &MeshInstance,
        world: &[Mat4],
        weights: &[Option<Vec<f32>>],
    ) -> DeformPose {
        let node_world = world
            .get(instance.node)
            .copied()
            .unwrap_or(instance.transform);
        let empty = Deform::default();
        let deform = self.deforms.get(instance.mesh).unwrap_or(&empty);
        let rest = self
            .meshes
            .get(instance.mesh)
            .map_or(Aabb::ZERO, |m| m.bounds);
        let mut morph = match weights.get(instance.node) {
            Some(Some(animated)) => animated.clone(),
            _ => instance.weights.clone(),
        };
        morph.resize(deform.targets.len(), 0.0);
        // A non-finite weight would poison every vertex it touches.
        for w in &mut morph {
            if !w.is_finite() {
                *w = 0.0;
            }
        }
        let grow = morph_extent(&deform.targets, &morph);
        let skin = instance.skin.and_then(|s| self.skins.get(s));
        match (skin, &deform.influences) {
            (Some(skin), Some(influences)) => {
                let palette = skin.palette(world, node_world);
                DeformPose {
                    bounds: influences.posed_bounds(&palette, grow),
                    palette,
                    weights: morph,
                    transform: Mat4::IDENTITY,
                }
            }
            _ => DeformPose {
                palette: Vec::new(),
                weights: morph,
                bounds: Aabb {
                    min: rest.min - grow,
                    max: rest.max + grow,
                },
                transform: node_world,
            },
        }
    }

    /// World bounds of every instance at a pose (deformed instances by
    /// their posed bounds), [`Aabb::ZERO`] when there are none.
    pub fn bounds_at(&self, world: &[Mat4], weights: &[Option<Vec<f32>>]) -> Aabb {
        self.instances
            .iter()
            .filter_map(|i| {
                let mesh = self.meshes.get(i.mesh)?;
                Some(if self.is_deformed(i) {
                    let pose = self.deform_pose(i, world, weights);
                    pose.bounds.transformed(pose.transform)
                } else {
                    let at = world.get(i.node).copied().unwrap_or(i.transform);
                    mesh.bounds.transformed(at)
                })
            })
            .filter(|b| b.is_finite())
            .reduce(Aabb::union)
            .unwrap_or(Aabb::ZERO)
    }

    /// The CPU reference of the GPU pass: mesh `mesh`'s positions deformed
    /// by `pose` (morph targets, then the skin).
    pub fn deformed_positions(&self, mesh: usize, pose: &DeformPose) -> Vec<Vec3> {
        let (Some(data), Some(deform)) = (self.meshes.get(mesh), self.deforms.get(mesh)) else {
            return Vec::new();
        };
        data.positions
            .iter()
            .enumerate()
            .map(|(v, p)| {
                let mut p = Vec3::from(*p);
                for (t, w) in deform.targets.iter().zip(&pose.weights) {
                    if let Some(d) = t.positions.get(v) {
                        p += Vec3::from(*d) * *w;
                    }
                }
                match &deform.influences {
                    Some(i) if !pose.palette.is_empty() => {
                        skin_point(&pose.palette, &i.joints[v], &i.weights[v], p)
                    }
                    _ => p,
                }
            })
            .collect()
    }
}
