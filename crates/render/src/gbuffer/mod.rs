//! The G-buffer: Emeshe's DeferredBase (layers of instanced meshes with
//! feature switches) and MRE (the targets they are written into).
//!
//! Layout, as Emeshe's MRE: `color` RGBA16F (albedo RGB, material id A),
//! `normals` RGBA16F (view-space normal RGB, object id A), `velocity_uv`
//! RGBA16F (velocity in UV units per frame RG, texture coordinates BA),
//! `depth` Depth32Float, reversed-Z.
//!
//! How: raster writes only depth and a visibility buffer (instance,
//! triangle) — 12 bytes a pixel — and compute resolves that into the MRE
//! targets (see DEVELOPERS.md: raster output is the H100's bottleneck). The
//! resolve is split in two passes, surface (color, normals) and motion
//! (velocity, UV), so a frame that reads no velocity culls the second.

pub(crate) mod compute_raster;
pub(crate) mod compute_raster_key;
mod instances;
mod layer;
mod passes;
mod published_depth;
pub(crate) mod published_depth_key;
mod resolve;
pub(crate) mod resolve_key;
mod surface_shader;
mod view;
pub(crate) mod view_key;
pub(crate) mod visibility_key;

use std::sync::Arc;

use glam::Mat4;

pub use layer::{
    DrawBatch, InstanceInput, Layer, LayerError, LayerFeatures, TRIPLANAR_SHARPNESS, VelocitySource,
};
pub use published_depth::{PublishedDepth, PublishedDepths};
pub use resolve::SURFACE_AND_MOTION_DISPATCHES;
pub use surface_shader::{SURFACE_MODULE, SurfaceBinding, SurfaceShader};
pub(crate) use surface_shader::{SplicedGroup, shader_node_group};
pub use view::{Channel, GBufferView};

pub(crate) use instances::{LayerMemo, pack_instances};

use crate::camera::{CameraInput, GpuCamera};
use crate::frame_graph::{FrameGraph, SizeRule};
use crate::recipe::{Recipe, next_recipe_id};
use crate::renderer::Renderer;

/// 224 bytes; matches `Instance` in shaders/lib/mesh.wgsl.
#[repr(C)]
#[derive(Clone, Copy, Debug, bytemuck::Pod, bytemuck::Zeroable)]
pub struct GpuInstance {
    pub model: [[f32; 4]; 4],
    pub previous_model: [[f32; 4]; 4],
    pub normal_matrix: [[f32; 4]; 4],
    pub color: [f32; 4],
    /// first index, base vertex, material id, object id
    pub info: [u32; 4],
}

/// Matches `Layer` in shaders/gbuffer/resolve.wgsl.
#[repr(C)]
#[derive(Clone, Copy, Debug, bytemuck::Pod, bytemuck::Zeroable)]
struct GpuLayer {
    first_instance: u32,
    end_instance: u32,
    write_background: u32,
    /// 1: add the vertices' geometry ids to the object id ("Instance from GeomFX").
    geometry_ids: u32,
    triplanar_sharpness: f32,
    pad: [u32; 3],
}

/// Runs of adjacent layers a resolve can serve in one dispatch: those whose
/// `alike` key is the same (None: the layer resolves alone). Instances are
/// packed layer after layer, so a run's instances are one range. Per run:
/// its first layer's index and its uniform.
fn runs<K: PartialEq>(
    layers: &[Arc<Layer>],
    ranges: &[(u32, u32)],
    alike: impl Fn(&Layer) -> Option<K>,
) -> Vec<(usize, GpuLayer)> {
    let mut runs: Vec<(usize, Option<K>, GpuLayer)> = Vec::new();
    for (i, (layer, &(first, end))) in layers.iter().zip(ranges).enumerate() {
        let key = alike(layer);
        if let Some((_, Some(run_key), run)) = runs.last_mut()
            && key.as_ref() == Some(&*run_key)
            && run.end_instance == first
        {
            run.end_instance = end;
            continue;
        }
        runs.push((
            i,
            key,
            GpuLayer {
                first_instance: first,
                end_instance: end,
                write_background: u32::from(i == 0),
                geometry_ids: u32::from(layer.features.adds_geometry_ids()),
                triplanar_sharpness: layer.features.triplanar_sharpness as f32,
                pad: [0; 3],
            },
        ));
    }
    runs.into_iter().map(|(i, _, gpu)| (i, gpu)).collect()
}

/// One instanced draw: a mesh and a range of the instance buffer.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) struct Draw {
    pub index_count: u32,
    pub first_instance: u32,
    pub instance_count: u32,
    /// Particles, drawn from their records (after the meshes, so the depth
    /// a G-buffer publishes for their collisions holds no particles).
    pub procedural: bool,
    /// Its instances' materials are double-sided: this draw keeps its back
    /// faces (a batch mixing sides is split in two draws, see [`pack_instances`]).
    pub two_sided: bool,
    /// The mesh's conservative bounds, before its instances' transforms;
    /// None for particles, whose triangles come from records that move on
    /// the GPU.
    pub bounds: Option<crate::mesh::Aabb>,
}

/// What every shader that pulls instanced meshes binds beside its view (the
/// G-buffer's, the compute rasterizer's, the shadow depth pass, transparency):
/// the mesh arena's vertices and indices and the instances, by the names
/// `shaders/lib/mesh_fetch.wgsl` gives them.
pub(crate) fn mesh_bindings<'b>(
    vertices: &'b wgpu::Buffer,
    indices: &'b wgpu::Buffer,
    instances: &'b wgpu::Buffer,
) -> crate::frame_graph::Bindings<'b> {
    crate::frame_graph::Bindings::new()
        .buffer("vertices", vertices)
        .buffer("indices", indices)
        .buffer("instances", instances)
}

/// How the visibility buffer is rasterized.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum RasterMode {
    /// The raster hardware: depth + an RG32Uint id target.
    Hardware,
    /// Compute shaders with 64-bit atomicMax into a buffer (where the adapter has 64-bit atomics).
    Compute,
}

/// Which raster a G-buffer should use.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum RasterChoice {
    /// Compute where the adapter supports it, else hardware.
    #[default]
    Auto,
    Hardware,
    Compute,
}

/// The frame-graph names of a G-buffer's targets.
#[derive(Clone, Debug)]
pub struct GBufferTargets {
    /// Hardware raster: the (instance + 1, triangle) texture. Compute raster:
    /// an ordering token (the 64-bit buffer itself belongs to the G-buffer).
    pub visibility: String,
    /// Hardware raster only: its Depth32Float attachment.
    pub hardware_depth: String,
    /// Reversed-Z depth as R32Float, written by the surface resolve.
    pub depth: String,
    pub color: String,
    pub normals: String,
    pub velocity_uv: String,
    /// Per pixel of surface-mapped materials and shader node materials:
    /// roughness, metallic, occlusion, emission and a written flag
    /// (Rgba32Uint, see shaders/lib/surface_target.wgsl), which lighting
    /// reads in place of the material's parameters. Only when some layer
    /// has surface maps or a shader node material.
    pub surface: Option<String>,
    /// Per pixel of Anisotropy materials (`KHR_materials_anisotropy`): the
    /// anisotropy direction (view space, unit, orthogonal to nothing yet:
    /// lighting makes it so against the shaded normal) in rgb and the
    /// strength (0..1) in a, Rgba16Float; other pixels are not written
    /// (lighting reads it only where the material has the feature). Only
    /// when some layer's maps world has such a material.
    pub anisotropy: Option<String>,
    /// Per pixel of glTF materials: the sheen colour and roughness and the
    /// thin film's factor and thickness as `KHR_materials_sheen`'s and
    /// `KHR_materials_iridescence`'s maps make them ([`SHEEN_FILM_FORMAT`],
    /// see shaders/lib/sheen_film.wgsl), which CookTorrance and Reflection
    /// read under SHEEN and IRIDESCENCE. Only when some layer's maps world
    /// has such a map (factors alone need none).
    pub sheen_film: Option<String>,
}

/// The sheen and film target's format (the material module's: its 1x1
/// stand-in has the same).
pub use crate::material::SHEEN_FILM_FORMAT;

impl GBufferTargets {
    /// What material lookups read at a pixel: the UV.
    pub fn surface_targets(&self) -> crate::material::SurfaceTargets<'_> {
        crate::material::SurfaceTargets {
            uv: &self.velocity_uv,
        }
    }

    /// The feature a lighting pass over this G-buffer compiles to read the
    /// surface target (`SURFACE_TARGET`): only when there is one, so passes
    /// over G-buffers without one compile what they always did.
    pub fn surface_feature(&self) -> Option<&'static str> {
        self.surface.as_ref().map(|_| "SURFACE_TARGET")
    }
}

/// An MRE: its layers uploaded, ready to declare its passes. Nodes pass it on
/// as a resource; the sink that reaches it decides which of its targets are needed.
pub struct GBuffer {
    id: u64,
    owner: Option<u32>,
    pub size: SizeRule,
    pub camera: CameraInput,
    previous_view_projection: Option<Mat4>,
    pub targets: GBufferTargets,
    layers: Vec<Arc<Layer>>,
    draws: Vec<Draw>,
    /// Per layer: its instance range in the instance buffer.
    layer_ranges: Vec<(u32, u32)>,
    instances: wgpu::Buffer,
    camera_buffer: wgpu::Buffer,
    /// The resolves' dispatches: runs of adjacent layers the same
    /// permutation serves, as (the run's first layer, the run's instance
    /// range as a layer uniform). One dispatch serves a run: each is a pass
    /// over every pixel, most of which belong to other layers.
    surface_runs: Vec<(usize, wgpu::Buffer)>,
    motion_runs: Vec<(usize, wgpu::Buffer)>,
    /// The runs of both in one dispatch: layers alike in both.
    fused_runs: Vec<(usize, wgpu::Buffer)>,
    /// Per layer with a shader node material that has pins: its uniform block.
    surface_buffers: Vec<Option<wgpu::Buffer>>,
    pub raster: RasterMode,
    compute: Option<compute_raster::ComputeRaster>,
    /// The name its depth (before particles) is published under for next
    /// frame's particle collisions ([`PublishedDepths`]).
    publish_depth: Option<String>,
    /// Layers packed anew and layers whose packing was kept (see [`LayerMemo`]).
    packed: (u64, u64),
}

impl std::fmt::Debug for GBuffer {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(
            f,
            "GBuffer({}, {} layers)",
            self.targets.color,
            self.layers.len()
        )
    }
}

impl GBuffer {
    /// Upload the layers' instances. `owner` is the node that made it, for error reports.
    pub fn new(
        renderer: &Renderer,
        owner: Option<u32>,
        layers: Vec<Arc<Layer>>,
        camera: CameraInput,
        previous_view_projection: Option<Mat4>,
        size: SizeRule,
    ) -> Arc<Self> {
        Self::with_raster(
            renderer,
            owner,
            layers,
            camera,
            previous_view_projection,
            size,
            RasterChoice::Auto,
        )
    }

    /// As [`GBuffer::new`], choosing the rasterizer. `Compute` on an adapter
    /// without 64-bit atomics falls back to `Hardware`.
    pub fn with_raster(
        renderer: &Renderer,
        owner: Option<u32>,
        layers: Vec<Arc<Layer>>,
        camera: CameraInput,
        previous_view_projection: Option<Mat4>,
        size: SizeRule,
        choice: RasterChoice,
    ) -> Arc<Self> {
        let id = next_recipe_id();
        let prefix = format!("mre{id}");
        // A node's layers that did not change since its last recipe keep
        // their packing (one ball moving among a thousand still spheres).
        let kept = owner.map(|node| {
            instances::pack_instances_kept(
                &layers,
                &renderer.state::<LayerMemo<instances::PackedLayer>>(u64::from(node)),
                &renderer.state::<instances::Placement>(u64::from(node)),
            )
        });
        // A storage binding cannot be empty: one zeroed instance then.
        let empty: [GpuInstance; 1] = [bytemuck::Zeroable::zeroed()];
        // Kept under the MRE node across its recipes, so the bind groups of
        // every pass that reads the camera are reused from frame to frame;
        // a layer lying where it lay last frame is not compared again.
        let (instances, draws, layer_ranges, instance_count, packed) = match kept {
            Some(kept) => {
                let (mut parts, mut unchanged) = (kept.parts(), kept.unchanged.clone());
                if kept.count == 0 {
                    (parts, unchanged) = (vec![bytemuck::cast_slice(&empty)], vec![false]);
                }
                let buffer = renderer.kept_init_parts(
                    owner,
                    "mre instances",
                    &parts,
                    &unchanged,
                    wgpu::BufferUsages::STORAGE,
                );
                let count = (kept.count as usize).max(1);
                (buffer, kept.draws, kept.ranges, count, kept.made)
            }
            None => {
                let (gpu_instances, draws, ranges) = pack_instances(&layers);
                let buffer = renderer.kept_storage(owner, "mre instances", &gpu_instances);
                // As the buffer holds: one zeroed instance when there are none.
                let count = gpu_instances.len().max(1);
                (buffer, draws, ranges, count, layers.len() as u64)
            }
        };
        let packed = (packed, layers.len() as u64 - packed);
        let camera_buffer = renderer.kept_buffer(
            owner,
            "mre camera",
            std::mem::size_of::<GpuCamera>() as u64,
            wgpu::BufferUsages::UNIFORM | wgpu::BufferUsages::COPY_DST,
        );
        let kept =
            |label: &'static str, runs: Vec<(usize, GpuLayer)>| -> Vec<(usize, wgpu::Buffer)> {
                runs.into_iter()
                    .enumerate()
                    .map(|(k, (layer, gpu))| {
                        let buffer = renderer.kept_init_at(
                            owner,
                            label,
                            k as u32,
                            bytemuck::bytes_of(&gpu),
                            wgpu::BufferUsages::UNIFORM,
                        );
                        (layer, buffer)
                    })
                    .collect()
            };
        // A layer with maps, a material world or a shader material binds
        // its own: it resolves alone (alone too with the motion resolve).
        let surface_runs = kept(
            "mre surface run",
            runs(&layers, &layer_ranges, |l| {
                l.resolves_with_others().then(|| {
                    let f = &l.features;
                    (
                        l.surface_key(),
                        f.adds_geometry_ids(),
                        f.triplanar_sharpness,
                    )
                })
            }),
        );
        let motion_runs = kept(
            "mre motion run",
            runs(&layers, &layer_ranges, |l| {
                Some((l.features.motion_key(), l.features.adds_geometry_ids()))
            }),
        );
        let fused_runs = kept(
            "mre fused run",
            runs(&layers, &layer_ranges, |l| {
                l.resolves_with_others().then(|| {
                    let f = &l.features;
                    (l.fused_key(), f.adds_geometry_ids(), f.triplanar_sharpness)
                })
            }),
        );
        let surface_buffers = layers
            .iter()
            .enumerate()
            .map(|(i, l)| {
                let s = l.surface.as_ref().filter(|s| !s.params.is_empty())?;
                Some(renderer.kept_init_at(
                    owner,
                    "mre material pins",
                    i as u32,
                    &s.params,
                    wgpu::BufferUsages::UNIFORM,
                ))
            })
            .collect();
        let raster = match choice {
            RasterChoice::Hardware => RasterMode::Hardware,
            // Alpha tests discard per pixel, which the raster hardware does.
            _ if layers.iter().any(|l| l.alpha_masked()) => RasterMode::Hardware,
            _ if !renderer.gpu.has_compute_raster() => RasterMode::Hardware,
            _ => RasterMode::Compute,
        };
        let compute = (raster == RasterMode::Compute).then(|| {
            compute_raster::ComputeRaster::new(
                renderer,
                owner,
                compute_raster::RasterLabels::G_BUFFER,
                compute_raster::Words::Visibility64,
                &draws,
                instance_count,
            )
        });
        Arc::new(GBuffer {
            id,
            owner,
            size,
            camera,
            previous_view_projection,
            targets: GBufferTargets {
                visibility: format!("{prefix}/visibility"),
                hardware_depth: format!("{prefix}/hardware_depth"),
                depth: format!("{prefix}/depth"),
                color: format!("{prefix}/color"),
                normals: format!("{prefix}/normals"),
                velocity_uv: format!("{prefix}/velocity_uv"),
                surface: layers
                    .iter()
                    .any(|l| l.map_world().is_some() || l.surface.is_some())
                    .then(|| format!("{prefix}/surface")),
                anisotropy: layers
                    .iter()
                    .any(|l| l.map_world().is_some_and(|w| w.has_anisotropy()))
                    .then(|| format!("{prefix}/anisotropy")),
                sheen_film: layers
                    .iter()
                    .any(|l| l.map_world().is_some_and(|w| w.has_sheen_film_maps()))
                    .then(|| format!("{prefix}/sheen_film")),
            },
            layers,
            draws,
            layer_ranges,
            instances,
            camera_buffer,
            surface_runs,
            motion_runs,
            fused_runs,
            surface_buffers,
            raster,
            compute,
            publish_depth: None,
            packed,
        })
    }

    /// As [`GBuffer::with_raster`], publishing its depth (meshes only, not
    /// particles) under `name` each frame it renders, for the next frame's
    /// particle depth collisions ([`PublishedDepths`]).
    #[allow(clippy::too_many_arguments)]
    pub fn publishing_depth(
        renderer: &Renderer,
        owner: Option<u32>,
        layers: Vec<Arc<Layer>>,
        camera: CameraInput,
        previous_view_projection: Option<Mat4>,
        size: SizeRule,
        choice: RasterChoice,
        name: String,
    ) -> Arc<Self> {
        let mut g = Self::with_raster(
            renderer,
            owner,
            layers,
            camera,
            previous_view_projection,
            size,
            choice,
        );
        if let Some(g) = Arc::get_mut(&mut g) {
            g.publish_depth = Some(name).filter(|n| !n.is_empty());
        }
        g
    }

    /// The name its depth is published under, if any.
    pub fn published_depth(&self) -> Option<&str> {
        self.publish_depth.as_deref()
    }

    /// The G-buffer's size in pixels for a frame of `output` size.
    pub fn pixel_size(&self, output: (u32, u32)) -> (u32, u32) {
        self.size.pixels(output)
    }

    /// What every G-buffer shader binds: the camera, the mesh arena's
    /// vertices and indices, and the instances.
    fn geometry_bindings<'b>(
        &'b self,
        vertices: &'b wgpu::Buffer,
        indices: &'b wgpu::Buffer,
    ) -> crate::frame_graph::Bindings<'b> {
        mesh_bindings(vertices, indices, &self.instances).buffer("camera", &self.camera_buffer)
    }

    pub fn owner(&self) -> Option<u32> {
        self.owner
    }

    /// Last frame's view-projection, as the node that made this G-buffer saw it
    /// (None: no last frame, or not told).
    pub fn previous_view_projection(&self) -> Option<Mat4> {
        self.previous_view_projection
    }

    pub fn camera_buffer(&self) -> &wgpu::Buffer {
        &self.camera_buffer
    }

    /// True when nothing moves this frame: the camera and every instance are
    /// where they were last frame and no layer takes velocity from deforming
    /// geometry, so the velocity target is zero everywhere (post passes skip on it).
    pub fn is_still(&self) -> bool {
        let camera = self
            .previous_view_projection
            .is_none_or(|p| p == self.camera.view_projection());
        camera
            && self.layers.iter().all(|l| match l.features.velocity {
                VelocitySource::Off => true,
                VelocitySource::Geometry => false,
                VelocitySource::Transforms => l
                    .batches
                    .iter()
                    .flat_map(|b| &b.instances)
                    .all(|i| i.transform == i.previous_transform),
            })
    }

    /// Whether some draw keeps its back faces (a double-sided material);
    /// the other draws are still culled.
    pub fn two_sided(&self) -> bool {
        self.draws.iter().any(|d| d.two_sided)
    }

    /// How many draws keep their back faces.
    pub fn two_sided_draws(&self) -> usize {
        self.draws.iter().filter(|d| d.two_sided).count()
    }

    pub fn instance_count(&self) -> u32 {
        self.layer_ranges.last().map_or(0, |r| r.1)
    }
}

impl Recipe for GBuffer {
    fn declare<'a>(&'a self, renderer: &'a Renderer, fg: &mut FrameGraph<'a>) {
        if !fg.include(self.id) {
            return;
        }
        let key = fg.resolve(
            &crate::frame_graph::TextureDesc::storage(wgpu::TextureFormat::Rgba16Float)
                .size(self.size),
        );
        let camera = self
            .camera
            .to_gpu(self.previous_view_projection, (key.width, key.height));
        // Written only where it changed: a still camera writes nothing.
        renderer.write_kept(
            self.owner,
            "mre camera",
            &self.camera_buffer,
            bytemuck::bytes_of(&camera),
        );
        for map in self.layers.iter().flat_map(|l| l.maps()) {
            map.recipe.declare(renderer, fg);
        }
        for layer in &self.layers {
            for texture in layer.surface_textures() {
                texture.recipe.declare(renderer, fg);
            }
            if let Some(compiled) = layer.surface.as_ref().map(|s| s.take_compiled())
                && compiled > 0
            {
                fg.count("shader node permutations compiled", compiled);
            }
        }
        for (name, n) in [
            ("instance layers packed", self.packed.0),
            ("instance layers kept", self.packed.1),
        ] {
            if n > 0 {
                fg.count(name, n);
            }
        }
        passes::declare(self, renderer, fg);
    }
}

/// The layout the shader sees (shaders/layout.rs).
#[cfg(test)]
mod wgsl_layout {
    use super::*;

    #[test]
    fn gpu_instance_matches_instance_in_the_shader() {
        crate::assert_wgsl_layout!(
            GpuInstance,
            crate::gbuffer::resolve_key::ResolveKey,
            [],
            "Instance",
            [model, previous_model, normal_matrix, color, info]
        );
    }

    #[test]
    fn gpu_layer_matches_layer_in_the_shader() {
        crate::assert_wgsl_layout!(
            GpuLayer,
            crate::gbuffer::resolve_key::ResolveKey,
            [],
            "Layer",
            [
                first_instance,
                end_instance,
                write_background,
                geometry_ids,
                triplanar_sharpness,
                pad
            ]
        );
    }
}
