//! The `glTF` node's skinned and morphed instances: deformed on the GPU
//! (`render::geometry::skinning`) in one dispatch per file whenever the pose
//! changes, each new mesh carrying the last one's positions as previous
//! positions. Like GPU geometry nodes, a pose change asks for one more
//! evaluation next frame, which writes the same pose over itself so the
//! velocity settles to zero; after that an unchanged pose runs nothing.

use std::sync::Arc;

use glam::Mat4;
use rayon::prelude::*;
use spreadlight_gltf::deform::DeformPose;
use spreadlight_gltf::{GltfScene, MeshInstance};
use spreadlight_render::RenderError;
use spreadlight_render::Renderer;
use spreadlight_render::geometry::skinning::{DeformJob, DeformSource, deform};
use spreadlight_render::mesh_arena::GpuMesh;

/// Instances posed on the posing threads from this many.
const PARALLEL_INSTANCES: usize = 32;

/// One file's deformed instances and what they showed last.
pub(super) struct Deformer {
    source: DeformSource,
    /// Per instance of the scene: its last deformed mesh (`None` for rigid
    /// instances and before the first run).
    last: Vec<Option<Arc<GpuMesh>>>,
    /// Per instance: where its deformed mesh is drawn at the latest pose
    /// (a morph-only instance moves with its node without deforming anew).
    transforms: Vec<Mat4>,
    /// Per instance: the pose `last` shows (`None` for rigid instances).
    shown: Option<Vec<Option<DeformPose>>>,
    /// `last` was written over a different pose: its previous positions still move.
    moving: bool,
}

/// What one evaluation did.
pub(super) enum Ran {
    /// Nothing changed: the last meshes stand.
    Nothing,
    /// Deformed; `settle` asks for one more run next frame.
    Deformed { settle: bool },
}

impl Deformer {
    /// A deformer for `scene`, or `None` when no instance deforms.
    pub(super) fn new(
        renderer: &Renderer,
        scene: &GltfScene,
    ) -> Result<Option<Deformer>, RenderError> {
        if !scene.instances.iter().any(|i| scene.is_deformed(i)) {
            return Ok(None);
        }
        Ok(Some(Deformer {
            source: DeformSource::upload(renderer, &scene.deforms)?,
            last: vec![None; scene.instances.len()],
            transforms: vec![Mat4::IDENTITY; scene.instances.len()],
            shown: None,
            moving: false,
        }))
    }

    /// Deforms the scene's instances at the pose `world` (node world
    /// transforms) and `weights` (animated morph weights) when that differs
    /// from what is shown, or when the last run still moves.
    pub(super) fn pose(
        &mut self,
        renderer: &Renderer,
        scene: &GltfScene,
        uploaded: &[Arc<GpuMesh>],
        world: &[Mat4],
        weights: &[Option<Vec<f32>>],
    ) -> Result<Ran, RenderError> {
        let pose = |i: &MeshInstance| {
            scene
                .is_deformed(i)
                .then(|| scene.deform_pose(i, world, weights))
        };
        // A herd's joint matrices and posed bounds are made on the posing
        // threads (spreadlight_gltf::pool); a few instances stay on this one.
        let poses: Vec<Option<DeformPose>> = if scene.instances.len() >= PARALLEL_INSTANCES {
            spreadlight_gltf::pool::posing(|| {
                scene
                    .instances
                    .par_iter()
                    .with_min_len(PARALLEL_INSTANCES / 4)
                    .map(pose)
                    .collect()
            })
        } else {
            scene.instances.iter().map(pose).collect()
        };
        for (k, pose) in poses.iter().enumerate() {
            if let Some(pose) = pose {
                self.transforms[k] = pose.transform;
            }
        }
        let same = self.shown.as_deref().is_some_and(|shown| {
            shown.len() == poses.len()
                && shown.iter().zip(&poses).all(|(a, b)| match (a, b) {
                    (Some(a), Some(b)) => a.deforms_as(b),
                    (a, b) => a.is_none() && b.is_none(),
                })
        });
        if same && !self.moving {
            return Ok(Ran::Nothing);
        }
        let jobs: Vec<DeformJob<'_>> = poses
            .iter()
            .enumerate()
            .filter_map(|(k, pose)| {
                let instance = &scene.instances[k];
                Some(DeformJob {
                    rest: uploaded.get(instance.mesh)?,
                    mesh: instance.mesh,
                    pose: pose.as_ref()?,
                    previous: self.last[k].as_deref(),
                })
            })
            .collect();
        let mut made = deform(renderer, &mut self.source, &jobs)?.into_iter();
        for (k, pose) in poses.iter().enumerate() {
            if pose.is_some()
                && let Some(mesh) = made.next()
            {
                self.last[k] = Some(mesh);
            }
        }
        // A first run has nothing to move from; a new pose moved from the last.
        let settle = self.shown.is_some() && !same;
        self.shown = Some(poses);
        self.moving = settle;
        Ok(Ran::Deformed { settle })
    }

    /// Instance `k`'s deformed mesh and transform, when it deforms.
    pub(super) fn mesh(&self, k: usize) -> Option<(&Arc<GpuMesh>, Mat4)> {
        Some((self.last.get(k)?.as_ref()?, self.transforms[k]))
    }
}
