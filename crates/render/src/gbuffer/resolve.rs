//! The surface and motion resolves: the visibility buffer (or the hardware
//! raster's IDs and depth) into the MRE targets, one compute dispatch per
//! run of adjacent layers that one permutation serves.

use crate::error::RenderError;
use crate::frame_graph::{Bindings, PassContext, Tex};
use crate::renderer::Renderer;
use crate::shaders::{Reflection, ShaderKey};

use super::{GBuffer, RasterMode};

/// Statistic: resolve dispatches that wrote the surface and the motion
/// targets at once (the frame read both).
pub const SURFACE_AND_MOTION_DISPATCHES: &str = "surface and motion resolve dispatches";

/// Which targets a resolve dispatch writes.
#[derive(Clone, Copy, PartialEq, Eq)]
pub(super) enum Targets {
    /// Colour, normals, depth (and the surface target).
    Surface,
    /// Velocity and texture coordinates.
    Motion,
    /// Both, in one dispatch per run of layers alike in both.
    Both,
}

impl Targets {
    /// The compute pass's name, for captures.
    fn label(self) -> &'static str {
        match self {
            Targets::Surface => "resolve surface",
            Targets::Motion => "resolve motion",
            Targets::Both => "resolve surface and motion",
        }
    }

    /// The counter of dispatches of this kind.
    fn counter(self) -> &'static str {
        match self {
            Targets::Surface => "surface resolve dispatches",
            Targets::Motion => "motion resolve dispatches",
            Targets::Both => SURFACE_AND_MOTION_DISPATCHES,
        }
    }
}

/// What the surface resolve writes.
#[derive(Clone, Copy)]
pub(super) struct SurfaceOut {
    pub color: Tex,
    pub normals: Tex,
    pub depth: Tex,
    /// Where some layer has surface maps or a shader node material.
    pub surface: Option<Tex>,
}

/// What one layer's surface resolve reads beside the visibility.
#[derive(Clone, Default)]
pub(super) struct LayerReads {
    pub normal_map: Option<Tex>,
    pub color_map: Option<Tex>,
    /// A shader node material's texture inputs, in `@input` order.
    pub textures: Vec<Tex>,
}

/// What a resolve pass declared: it writes the surface targets, the motion
/// target, or both (one dispatch per run of layers).
#[derive(Clone)]
pub(super) struct ResolveIo {
    /// The hardware raster's ID texture, or the compute raster's ordering token.
    pub visibility: Tex,
    /// The hardware raster's depth (the surface resolve reads it).
    pub hardware_depth: Option<Tex>,
    pub surface: Option<SurfaceOut>,
    pub velocity_uv: Option<Tex>,
    /// Per layer (the surface resolve's reads).
    pub layers: Vec<LayerReads>,
}

impl ResolveIo {
    fn targets(&self) -> Targets {
        match (self.surface.is_some(), self.velocity_uv.is_some()) {
            (true, true) => Targets::Both,
            (false, _) => Targets::Motion,
            (true, false) => Targets::Surface,
        }
    }
}

pub(super) fn resolve(
    g: &GBuffer,
    renderer: &Renderer,
    cx: &mut PassContext<'_>,
    io: &ResolveIo,
) -> Result<(), RenderError> {
    let targets = io.targets();
    let motion = targets == Targets::Motion;
    let device = cx.gpu.device.clone();
    let (vertices, indices, _) = renderer.meshes.buffers();
    let extras = renderer.meshes.extras();
    let compute = g
        .compute
        .as_ref()
        .filter(|_| g.raster == RasterMode::Compute);
    // The compute raster's 64-bit buffer, or the hardware raster's IDs.
    let visibility = match compute {
        Some(c) => Some((
            c.visibility().ok_or_else(|| RenderError::Pass {
                pass: "resolve".to_owned(),
                message: "the compute raster has not run this frame".to_owned(),
            })?,
            &c.first_triangle,
        )),
        None => None,
    };
    let (w, h) = g.pixel_size(cx.output_size);
    // Per dispatch: its layer and its layer uniform. With no layers, one
    // (background) dispatch still clears the targets; otherwise one per run
    // of adjacent layers the same permutation serves.
    let dispatches: Vec<(Option<usize>, Option<&wgpu::Buffer>)> = if g.layers.is_empty() {
        vec![(None, None)]
    } else {
        let runs = match targets {
            Targets::Surface => &g.surface_runs,
            Targets::Motion => &g.motion_runs,
            Targets::Both => &g.fused_runs,
        };
        runs.iter().map(|(i, b)| (Some(*i), Some(b))).collect()
    };
    cx.count(targets.counter(), dispatches.len() as u64);
    let mut work = Vec::with_capacity(dispatches.len());
    for (index, layer_buffer) in dispatches {
        let i = index.unwrap_or(0);
        let layer = index.and_then(|i| g.layers.get(i));
        let reads = index.and_then(|i| io.layers.get(i)).filter(|_| !motion);
        let mut defines = match (layer, targets) {
            (Some(l), Targets::Motion) => l.features.motion_defines(),
            (Some(l), Targets::Surface) => l.surface_defines(),
            (Some(l), Targets::Both) => l.fused_defines(),
            (None, Targets::Motion) => vec!["MOTION"],
            (None, Targets::Surface) => vec![],
            (None, Targets::Both) => vec!["VELOCITY_OUT"],
        };
        if compute.is_some() {
            defines.push("COMPUTE_RASTER");
        }
        let surface_out = io.surface.and_then(|s| s.surface);
        if surface_out.is_some() {
            defines.push("SURFACE_OUT");
        }
        let key = ShaderKey::new("gbuffer/resolve.wgsl", defines);
        let layer_buffer = match layer_buffer {
            Some(b) => b.clone(),
            None => background_layer(&device),
        };
        let mut b = Bindings::new()
            .buffer("camera", g.camera_buffer())
            .buffer("vertices", &vertices)
            .buffer("indices", &indices)
            .buffer("instances", &g.instances)
            .buffer("extras", &extras)
            .buffer("layer", &layer_buffer)
            .texture_opt("hardware_depth", io.hardware_depth.filter(|_| !motion))
            .texture_opt("out_surface", surface_out)
            .texture_opt("out_velocity_uv", io.velocity_uv);
        b = match visibility.as_ref() {
            Some((buffer, first_triangle)) => b
                .buffer("visibility", buffer)
                .buffer("first_triangle", first_triangle),
            None => b.texture("visibility", io.visibility),
        };
        if let Some(out) = io.surface {
            b = b
                .texture("out_color", out.color)
                .texture("out_normal", out.normals)
                .texture("out_depth", out.depth);
        }
        // The layer's maps, where its permutation samples them.
        if let Some(reads) = reads {
            let sampling = crate::shaders::Sampling::LinearRepeat;
            if let Some(map) = reads.normal_map {
                b = b
                    .texture("normal_map", map)
                    .sampler("normal_sampler", sampling);
            }
            if let Some(map) = reads.color_map {
                b = b
                    .texture("color_map", map)
                    .sampler("color_sampler", sampling);
            }
        }
        // A shader node material: the resolve composed with its file, whose
        // group 1 its own file lays out; else the material world and its
        // surface maps' arrays.
        let custom = layer.and_then(|l| l.surface.as_ref()).filter(|_| !motion);
        let groups = match custom {
            Some(s) => {
                let splice = crate::shaders::Splice {
                    key: s.key,
                    module: super::SURFACE_MODULE,
                    file_path: &s.file,
                    source: &s.text,
                };
                let label = format!("{}: resolve surface", s.label);
                let (pipeline, reflection) = cx
                    .shaders
                    .surface_pipeline(&device, &key, &splice, "main")
                    .map_err(|e| RenderError::Pass {
                        pass: label.clone(),
                        message: e.to_string(),
                    })?;
                let params = g.surface_buffers.get(i).and_then(Option::as_ref);
                let textures = reads.map_or(&[][..], |r| r.textures.as_slice());
                let spliced = SplicedGroup {
                    group: 1,
                    label: &label,
                    reflection: &reflection,
                };
                if let Some(group) =
                    shader_node_group(cx, &pipeline, s, params, textures, &spliced)?
                {
                    b = b.group(1, group);
                }
                // spreadlight::materials: the layer's world in group 3, its
                // texture array read after the material's own inputs.
                if s.reads_materials {
                    let world =
                        layer
                            .and_then(|l| l.library_world())
                            .ok_or_else(|| RenderError::Pass {
                                pass: label.clone(),
                                message: "it reads the material world (spreadlight::materials), \
                                      but its DeferredBase has no Material World connected"
                                    .to_owned(),
                            })?;
                    let array = layer
                        .and_then(|l| l.library_textures())
                        .and_then(|_| textures.get(s.textures.len()).copied());
                    b = b.extend(world.library_bindings(array));
                }
                let groups = cx.bind_groups_reflected(&label, &reflection, &pipeline, b)?;
                (pipeline, groups)
            }
            None => {
                if let Some(world) = layer.and_then(|l| l.map_world()).filter(|_| !motion) {
                    b = b.extend(world.bindings(None));
                    if let Some(maps) = world.maps_bindings() {
                        b = b.extend(maps);
                    }
                }
                let pipeline = cx.shaders.compute_pipeline(&device, &key, "main")?;
                let groups = cx.bind_groups(&key, "main", &pipeline, b)?;
                (pipeline, groups)
            }
        };
        work.push(groups);
    }
    let pass = cx.compute_pass(targets.label());
    for (pipeline, groups) in &work {
        pass.set_pipeline(pipeline);
        for (i, group) in groups.iter().enumerate() {
            pass.set_bind_group(i as u32, group, &[]);
        }
        pass.dispatch_workgroups(w.div_ceil(8), h.div_ceil(8), 1);
    }
    Ok(())
}

/// Where a spliced shader node file's own bindings go.
pub(crate) struct SplicedGroup<'a> {
    /// 1 for a material in the resolve, 2 for a light shader in CookTorrance.
    pub group: u32,
    /// The pass, for errors.
    pub label: &'a str,
    pub reflection: &'a Reflection,
}

/// The group of a built-in pass composed with a shader node file (a
/// material in the resolve, a light shader in CookTorrance): its pins'
/// uniform block, texture inputs and samplers, numbered as the user's file
/// numbers them, those the permutation uses. None where it uses no such group.
pub(crate) fn shader_node_group(
    cx: &mut PassContext<'_>,
    pipeline: &wgpu::ComputePipeline,
    surface: &super::SurfaceShader,
    params: Option<&wgpu::Buffer>,
    textures: &[Tex],
    spliced: &SplicedGroup<'_>,
) -> Result<Option<wgpu::BindGroup>, RenderError> {
    use super::SurfaceBinding;
    let (group, reflection) = (spliced.group, spliced.reflection);
    // A derived layout has groups up to the last one used: none past the last.
    if reflection.last_group().is_none_or(|last| last < group) {
        return Ok(None);
    }
    let mut resources = Vec::new();
    for (binding, role) in &surface.bindings {
        if !reflection.used().any(|u| u == (group, *binding)) {
            continue;
        }
        let resource = match role {
            SurfaceBinding::Uniform => match params {
                Some(buffer) => Bound::Buffer(buffer.clone()),
                None => continue,
            },
            SurfaceBinding::Texture(t) => {
                let tex = textures.get(*t).ok_or_else(|| RenderError::Pass {
                    pass: spliced.label.to_owned(),
                    message: format!("texture input {t} is not connected"),
                })?;
                Bound::View(cx.view(*tex)?)
            }
            SurfaceBinding::Sampler { repeat } => Bound::Sampler(cx.sampler(if *repeat {
                crate::shaders::Sampling::LinearRepeat
            } else {
                crate::shaders::Sampling::LinearClamp
            })),
        };
        resources.push((*binding, resource));
    }
    let entries: Vec<wgpu::BindGroupEntry<'_>> = resources
        .iter()
        .map(|(binding, bound)| wgpu::BindGroupEntry {
            binding: *binding,
            resource: match bound {
                Bound::Buffer(b) => b.as_entire_binding(),
                Bound::View(v) => wgpu::BindingResource::TextureView(v),
                Bound::Sampler(s) => wgpu::BindingResource::Sampler(s),
            },
        })
        .collect();
    Ok(Some(cx.gpu.device.create_bind_group(
        &wgpu::BindGroupDescriptor {
            label: Some(spliced.label),
            layout: &pipeline.get_bind_group_layout(group),
            entries: &entries,
        },
    )))
}

/// A resource of a shader node material's group, resolved.
enum Bound {
    Buffer(wgpu::Buffer),
    View(wgpu::TextureView),
    Sampler(wgpu::Sampler),
}

/// The layer record of a G-buffer with no layers: covers nothing, clears everything.
fn background_layer(device: &wgpu::Device) -> wgpu::Buffer {
    use wgpu::util::DeviceExt;
    device.create_buffer_init(&wgpu::util::BufferInitDescriptor {
        label: Some("mre background layer"),
        // No instances; writes the background. (Layer in resolve.wgsl: 8 words.)
        contents: bytemuck::cast_slice(&[0u32, 0, 1, 0, 0, 0, 0, 0]),
        usage: wgpu::BufferUsages::UNIFORM,
    })
}
