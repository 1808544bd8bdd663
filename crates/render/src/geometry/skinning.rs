//! GPU skinning and morph targets (shaders/geometry/skinning.wgsl): glTF
//! meshes deformed by their skins' joint matrices and their morph weights,
//! written into the mesh arena as new meshes that flow into DeferredBase
//! and shadow maps like any other.
//!
//! The per-vertex data that does not change with the pose (joint indices
//! and weights, morph deltas) is uploaded once per loaded scene into
//! buffers of its own ([`DeformSource`]): the arena's vertex layout stays
//! as it is. Per pose only the joint matrices and morph weights go up, and
//! one dispatch deforms every instance of the scene. Each output vertex
//! carries its position in the same instance's last output as its previous
//! position, so `Velocity: Geometry` (motion blur, TAA) sees the motion.

use std::sync::Arc;

use bytemuck::{Pod, Zeroable};
use wgpu::util::DeviceExt;

use super::{ArenaStreams, Work, dispatch_as};
use crate::error::RenderError;
use crate::mesh::deform::{Deform, DeformPose, MAX_INFLUENCES, UNSKINNED};
use crate::mesh_arena::{GpuMesh, MeshLayout};
use crate::renderer::Renderer;
use crate::shaders::Permutation;

pub use super::skinning_key::SkinningKey;

const PASS: &str = "skinning";
/// No influences: the job's mesh has no skin.
const NONE: u32 = u32::MAX;

/// Matches `Job` in shaders/geometry/skinning.wgsl.
#[repr(C)]
#[derive(Clone, Copy, Debug, Pod, Zeroable)]
struct GpuJob {
    src_vertex: u32,
    src_index: u32,
    dst_vertex: u32,
    dst_index: u32,
    vertex_count: u32,
    index_count: u32,
    previous_vertex: u32,
    has_previous: u32,
    influence_offset: u32,
    target_offset: u32,
    target_count: u32,
    palette_offset: u32,
    joint_count: u32,
    weight_offset: u32,
    first_thread: u32,
    spare: u32,
}

/// Matches `Influence` in the shader: 8 joints as 16-bit pairs, 8 weights.
#[repr(C)]
#[derive(Clone, Copy, Debug, Pod, Zeroable)]
struct GpuInfluence {
    joints: [u32; 4],
    weights: [f32; MAX_INFLUENCES],
}

/// Where one mesh's deformation data lies in the [`DeformSource`] buffers.
#[derive(Clone, Copy, Debug)]
struct Slot {
    influences: Option<u32>,
    targets: u32,
    target_count: u32,
    vertices: u32,
}

/// A scene's joint influences and morph deltas on the GPU, one slot per
/// mesh (same index as `GltfScene::meshes`).
pub struct DeformSource {
    influences: wgpu::Buffer,
    targets: wgpu::Buffer,
    slots: Vec<Slot>,
    /// What each pose writes, kept from pose to pose.
    pose: PoseBuffers,
}

/// The buffer a pose writes: the dispatch's counts, its jobs, joint
/// matrices and morph weights, each at an offset the device binds. It is
/// kept and written in place by one write, so a herd posed every frame
/// makes no buffer and stages one upload a pose, not four (wgpu stages
/// each `write_buffer` in a buffer of its own: four were 6% of
/// bench-skinning's main thread on the H200's host, session 30). The queue
/// orders a write after the dispatches submitted before it, so the last
/// pose's dispatch still reads the last pose.
#[derive(Default)]
struct PoseBuffers {
    buffer: Option<wgpu::Buffer>,
}

/// The parts of [`PoseBuffers`]' buffer, in binding order.
const POSE_PARTS: usize = 4;
/// A binding may not be empty: an empty part takes this many zero bytes
/// (a joint matrix, a job, sixteen weights).
const MIN_PART: usize = 64;

impl PoseBuffers {
    /// Writes `parts` into the kept buffer (made anew when too small, at
    /// twice the size, so a growing herd makes few) and returns each
    /// part's binding, in order.
    fn write<'a>(
        &'a mut self,
        renderer: &Renderer,
        parts: [&[u8]; POSE_PARTS],
    ) -> [wgpu::BindingResource<'a>; POSE_PARTS] {
        let limits = renderer.gpu.device.limits();
        let align = limits
            .min_uniform_buffer_offset_alignment
            .max(limits.min_storage_buffer_offset_alignment) as usize;
        let mut bytes = Vec::new();
        let ranges = parts.map(|part| {
            bytes.resize(bytes.len().next_multiple_of(align), 0);
            let start = bytes.len();
            bytes.extend_from_slice(part);
            bytes.resize(start + part.len().max(MIN_PART), 0);
            (start as u64, (bytes.len() - start) as u64)
        });
        let size = bytes.len() as u64;
        if self.buffer.as_ref().is_none_or(|b| b.size() < size) {
            self.buffer = Some(renderer.gpu.device.create_buffer(&wgpu::BufferDescriptor {
                label: Some("skinning pose"),
                size: size.next_power_of_two(),
                usage: wgpu::BufferUsages::UNIFORM
                    | wgpu::BufferUsages::STORAGE
                    | wgpu::BufferUsages::COPY_DST,
                mapped_at_creation: false,
            }));
        }
        let buffer = self.buffer.as_ref().expect("made above");
        renderer.gpu.queue.write_buffer(buffer, 0, &bytes);
        ranges.map(|(offset, size)| {
            wgpu::BindingResource::Buffer(wgpu::BufferBinding {
                buffer,
                offset,
                size: std::num::NonZeroU64::new(size),
            })
        })
    }
}

impl std::fmt::Debug for DeformSource {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(f, "DeformSource({} meshes)", self.slots.len())
    }
}

fn error(message: String) -> RenderError {
    RenderError::Pass {
        pass: PASS.to_owned(),
        message,
    }
}

fn storage(renderer: &Renderer, label: &str, bytes: &[u8]) -> wgpu::Buffer {
    // A binding may not be empty: at least one 16-byte element.
    let mut contents = bytes.to_vec();
    contents.resize(contents.len().max(64), 0);
    renderer
        .gpu
        .device
        .create_buffer_init(&wgpu::util::BufferInitDescriptor {
            label: Some(label),
            contents: &contents,
            usage: wgpu::BufferUsages::STORAGE,
        })
}

impl DeformSource {
    /// Uploads `deforms` (one per mesh of a scene; rigid meshes take no room).
    pub fn upload(renderer: &Renderer, deforms: &[Deform]) -> Result<DeformSource, RenderError> {
        let mut influences: Vec<GpuInfluence> = Vec::new();
        let mut targets: Vec<[f32; 4]> = Vec::new();
        let mut slots = Vec::with_capacity(deforms.len());
        let too_many = || error("the scene's skins and morph targets exceed 2^32 elements".into());
        for deform in deforms {
            let vertices = deform.influences.as_ref().map_or_else(
                || {
                    deform.targets.first().map_or(0, |t| {
                        t.positions.len().max(t.normals.len()).max(t.tangents.len())
                    })
                },
                |i| i.joints.len(),
            );
            let influence_offset = match &deform.influences {
                None => None,
                Some(i) => {
                    let at = u32::try_from(influences.len()).map_err(|_| too_many())?;
                    influences.extend(i.joints.iter().zip(&i.weights).map(|(j, w)| {
                        let id = |k: usize| {
                            if j[k] == UNSKINNED {
                                0xFFFF
                            } else {
                                j[k] & 0xFFFF
                            }
                        };
                        GpuInfluence {
                            joints: std::array::from_fn(|p| id(2 * p) | (id(2 * p + 1) << 16)),
                            weights: *w,
                        }
                    }));
                    Some(at)
                }
            };
            let target_offset = u32::try_from(targets.len()).map_err(|_| too_many())?;
            for target in &deform.targets {
                let delta = |list: &[[f32; 3]], v: usize| {
                    let d = list.get(v).copied().unwrap_or([0.0; 3]);
                    [d[0], d[1], d[2], 0.0]
                };
                for v in 0..vertices {
                    targets.push(delta(&target.positions, v));
                    targets.push(delta(&target.normals, v));
                    targets.push(delta(&target.tangents, v));
                }
            }
            slots.push(Slot {
                influences: influence_offset,
                targets: target_offset,
                target_count: u32::try_from(deform.targets.len()).map_err(|_| too_many())?,
                vertices: u32::try_from(vertices).map_err(|_| too_many())?,
            });
        }
        u32::try_from(targets.len()).map_err(|_| too_many())?;
        Ok(DeformSource {
            influences: storage(
                renderer,
                "skin influences",
                bytemuck::cast_slice(&influences),
            ),
            targets: storage(renderer, "morph targets", bytemuck::cast_slice(&targets)),
            slots,
            pose: PoseBuffers::default(),
        })
    }
}

/// One instance to deform: its rest mesh (uploaded from `GltfScene::meshes[mesh]`),
/// its pose, and its last output (the source of previous positions).
pub struct DeformJob<'a> {
    pub rest: &'a GpuMesh,
    /// Index of the mesh in the scene (and in its [`DeformSource`]).
    pub mesh: usize,
    pub pose: &'a DeformPose,
    pub previous: Option<&'a GpuMesh>,
}

/// Deforms every job in one dispatch (counted and timed as skinning in
/// [`super::GeometryStats`]) and returns the new meshes, in job order.
pub fn deform(
    renderer: &Renderer,
    source: &mut DeformSource,
    jobs: &[DeformJob<'_>],
) -> Result<Vec<Arc<GpuMesh>>, RenderError> {
    if jobs.is_empty() {
        return Ok(Vec::new());
    }
    let mut outputs = Vec::with_capacity(jobs.len());
    let mut gpu_jobs = Vec::with_capacity(jobs.len());
    let mut palette: Vec<[f32; 16]> = Vec::new();
    let mut weights: Vec<f32> = Vec::new();
    let mut threads: u32 = 0;
    for (k, job) in jobs.iter().enumerate() {
        let slot = source.slots.get(job.mesh).copied().ok_or_else(|| {
            error(format!(
                "job {k}: mesh {} has no deformation data",
                job.mesh
            ))
        })?;
        let rest = job.rest;
        let (vertex_count, index_count) = (rest.vertices.len() as u32, rest.indices.len() as u32);
        if slot.vertices != vertex_count && (slot.influences.is_some() || slot.target_count > 0) {
            return Err(error(format!(
                "job {k}: the mesh has {vertex_count} vertices but its skin or morph targets {}",
                slot.vertices
            )));
        }
        let mut output = renderer.meshes.allocate(
            &renderer.gpu,
            vertex_count,
            index_count,
            MeshLayout {
                bounds: job.pose.bounds,
                has_uvs: rest.has_uvs,
                has_tangents: rest.has_tangents,
            },
        )?;
        // The kernel copies the rest vertex's extras: the colours and second
        // UV set stay, so the G-buffer reads them as it would the rest mesh's.
        if let Some(mesh) = Arc::get_mut(&mut output) {
            mesh.has_uvs1 = rest.has_uvs1;
            mesh.has_colors = rest.has_colors;
        }
        let previous = job
            .previous
            .filter(|p| p.vertices.len() == output.vertices.len());
        let skinned = slot.influences.filter(|_| !job.pose.palette.is_empty());
        let palette_offset = palette.len() as u32;
        if skinned.is_some() {
            // A matrix that overflowed would spread NaN over the mesh: identity instead.
            palette.extend(job.pose.palette.iter().map(|m| {
                if m.is_finite() {
                    m.to_cols_array()
                } else {
                    glam::Mat4::IDENTITY.to_cols_array()
                }
            }));
        }
        let weight_offset = weights.len() as u32;
        let mut morph = job.pose.weights.clone();
        morph.resize(slot.target_count as usize, 0.0);
        weights.extend(morph.iter().map(|w| if w.is_finite() { *w } else { 0.0 }));
        gpu_jobs.push(GpuJob {
            src_vertex: rest.vertices.start,
            src_index: rest.indices.start,
            dst_vertex: output.vertices.start,
            dst_index: output.indices.start,
            vertex_count,
            index_count,
            previous_vertex: previous.map_or(0, |p| p.vertices.start),
            has_previous: u32::from(previous.is_some()),
            influence_offset: skinned.unwrap_or(NONE),
            target_offset: slot.targets,
            target_count: slot.target_count,
            palette_offset,
            joint_count: (job.pose.palette.len() as u32).saturating_sub(1),
            weight_offset,
            first_thread: threads,
            spare: 0,
        });
        threads = threads
            .checked_add(vertex_count.max(index_count))
            .ok_or_else(|| error("more than 2^32 vertices to deform at once".into()))?;
        outputs.push(output);
    }
    // After every allocation: one may have grown the arena.
    let arena = ArenaStreams::of(renderer);
    let [work, jobs_buffer, palette, weights] = source.pose.write(
        renderer,
        [
            bytemuck::cast_slice(&[gpu_jobs.len() as u32, threads, 0, 0]),
            bytemuck::cast_slice(&gpu_jobs),
            bytemuck::cast_slice(&palette),
            bytemuck::cast_slice(&weights),
        ],
    );
    dispatch_as(
        renderer,
        &SkinningKey.key(),
        arena.bindings([
            ("work", work),
            ("jobs", jobs_buffer),
            ("palette", palette),
            ("influences", source.influences.as_entire_binding()),
            ("targets", source.targets.as_entire_binding()),
            ("morph_weights", weights),
        ]),
        threads,
        Work::Skinning,
    )?;
    Ok(outputs)
}

/// The layout the shader sees (shaders/layout.rs).
#[cfg(test)]
mod wgsl_layout {
    use super::*;

    #[test]
    fn gpu_job_matches_job_in_the_shader() {
        crate::assert_wgsl_layout!(
            GpuJob,
            crate::geometry::skinning_key::SkinningKey,
            [],
            "Job",
            [
                src_vertex,
                src_index,
                dst_vertex,
                dst_index,
                vertex_count,
                index_count,
                previous_vertex,
                has_previous,
                influence_offset,
                target_offset,
                target_count,
                palette_offset,
                joint_count,
                weight_offset,
                first_thread,
                spare
            ]
        );
    }

    #[test]
    fn gpu_influence_matches_influence_in_the_shader() {
        crate::assert_wgsl_layout!(
            GpuInfluence,
            crate::geometry::skinning_key::SkinningKey,
            [],
            "Influence",
            [joints, weights]
        );
    }
}
