//! The surface and motion resolves: the visibility buffer (or the hardware
//! raster's IDs and depth) into the MRE targets, one compute dispatch per
//! run of adjacent layers that one permutation serves.

use crate::error::RenderError;
use crate::frame_graph::PassContext;
use crate::renderer::Renderer;
use crate::shaders::{PipelineRef, ShaderKey};

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

pub(super) fn resolve(
    g: &GBuffer,
    renderer: &Renderer,
    cx: &mut PassContext<'_>,
    targets: Targets,
) -> Result<(), RenderError> {
    let motion = targets == Targets::Motion;
    let velocity_out = targets == Targets::Both;
    let device = cx.gpu.device.clone();
    let (vertices, indices, _) = renderer.meshes.buffers();
    let extras = renderer.meshes.extras();
    let compute = g
        .compute
        .as_ref()
        .filter(|_| g.raster == RasterMode::Compute);
    // What binding 4 is: the compute raster's buffer, or the hardware raster's texture.
    let (vis_view, vis_buffer) = match compute {
        Some(c) => {
            let buffer = c.visibility().ok_or_else(|| RenderError::Pass {
                pass: "resolve".to_owned(),
                message: "the compute raster has not run this frame".to_owned(),
            })?;
            (None, Some((buffer, c.first_triangle.clone())))
        }
        None => (Some(cx.view(&g.targets.visibility)?), None),
    };
    let hardware_depth = match (compute, motion) {
        (None, false) => Some(cx.view(&g.targets.hardware_depth)?),
        _ => None,
    };
    let outputs = if motion {
        vec![cx.view(&g.targets.velocity_uv)?]
    } else {
        vec![
            cx.view(&g.targets.color)?,
            cx.view(&g.targets.normals)?,
            cx.view(&g.targets.depth)?,
        ]
    };
    let velocity = match velocity_out {
        true => Some(cx.view(&g.targets.velocity_uv)?),
        false => None,
    };
    let surface = match (&g.targets.surface, motion) {
        (Some(name), false) => Some(cx.view(name)?),
        _ => None,
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
        if surface.is_some() {
            defines.push("SURFACE_OUT");
        }
        let vertex_extras = defines.contains(&"VERTEX_EXTRAS");
        let key = ShaderKey::new("gbuffer/resolve.wgsl", defines);
        // A shader node material: the resolve composed with its file.
        let custom = layer.and_then(|l| l.surface.as_ref()).filter(|_| !motion);
        let (pipeline, custom_used) = match custom {
            Some(s) => {
                let splice = crate::shaders::Splice {
                    key: s.key,
                    module: super::SURFACE_MODULE,
                    file_path: &s.file,
                    source: &s.text,
                };
                let (p, used) = cx
                    .shaders
                    .surface_pipeline(&device, &key, &splice, "main")
                    .map_err(|e| RenderError::Pass {
                        pass: format!("{}: resolve surface", s.label),
                        message: e.to_string(),
                    })?;
                (p, used)
            }
            None => (
                cx.shaders.compute_pipeline(&device, &key, "main")?,
                Vec::new(),
            ),
        };
        let layer_buffer = match layer_buffer {
            Some(b) => b.clone(),
            None => background_layer(&device),
        };
        let mut entries = g.geometry_entries(&vertices, &indices);
        if vertex_extras {
            entries.push(wgpu::BindGroupEntry {
                binding: 12,
                resource: extras.as_entire_binding(),
            });
        }
        entries.push(wgpu::BindGroupEntry {
            binding: 5,
            resource: layer_buffer.as_entire_binding(),
        });
        match (&vis_view, &vis_buffer) {
            (Some(view), _) => entries.push(wgpu::BindGroupEntry {
                binding: 4,
                resource: wgpu::BindingResource::TextureView(view),
            }),
            (None, Some((buffer, first_triangle))) => {
                entries.push(wgpu::BindGroupEntry {
                    binding: 4,
                    resource: buffer.as_entire_binding(),
                });
                entries.push(wgpu::BindGroupEntry {
                    binding: 10,
                    resource: first_triangle.as_entire_binding(),
                });
            }
            (None, None) => {}
        }
        if let Some(depth) = &hardware_depth {
            entries.push(wgpu::BindGroupEntry {
                binding: 9,
                resource: wgpu::BindingResource::TextureView(depth),
            });
        }
        for (k, view) in outputs.iter().enumerate() {
            entries.push(wgpu::BindGroupEntry {
                binding: 6 + k as u32,
                resource: wgpu::BindingResource::TextureView(view),
            });
        }
        if let Some(view) = &surface {
            entries.push(wgpu::BindGroupEntry {
                binding: 11,
                resource: wgpu::BindingResource::TextureView(view),
            });
        }
        if let Some(view) = &velocity {
            entries.push(wgpu::BindGroupEntry {
                binding: 13,
                resource: wgpu::BindingResource::TextureView(view),
            });
        }
        let pipeline_ref = PipelineRef::Compute(pipeline.clone());
        let group0 = cx
            .shaders
            .group(&device, &pipeline_ref, 0, "resolve", &entries);
        // Groups 1 and 3: the material world and its surface maps' arrays,
        // or group 1 alone: a shader node material's bindings.
        let (world_group, maps_group) = match (
            layer.and_then(|l| l.map_world()).filter(|_| !motion),
            custom,
        ) {
            (_, Some(s)) => (
                surface_group(
                    cx,
                    &pipeline,
                    s,
                    g.surface_buffers.get(i).and_then(Option::as_ref),
                    &custom_used,
                )?,
                None,
            ),
            (Some(world), None) => (
                Some(world.bind_group(cx, &key, &pipeline, false, g.targets.surface_targets())?),
                world.maps_bind_group(&device, &pipeline.get_bind_group_layout(3)),
            ),
            (None, None) => (None, None),
        };
        // Group 2: the layer's maps, bound where its permutation samples them.
        let group2 = match layer.filter(|l| !motion && l.maps().next().is_some()) {
            Some(l) => {
                let sampler = cx.sampler(crate::shaders::Sampling::LinearRepeat);
                let normal = l
                    .normal_map
                    .as_ref()
                    .filter(|_| l.features.normal_map)
                    .map(|m| cx.view(&m.name))
                    .transpose()?;
                let color = l.color_map.as_ref().map(|m| cx.view(&m.name)).transpose()?;
                let mut all = Vec::new();
                if let Some(v) = &normal {
                    all.push((0, wgpu::BindingResource::TextureView(v)));
                    all.push((1, wgpu::BindingResource::Sampler(&sampler)));
                }
                if let Some(v) = &color {
                    all.push((2, wgpu::BindingResource::TextureView(v)));
                    all.push((3, wgpu::BindingResource::Sampler(&sampler)));
                }
                Some(
                    cx.shaders
                        .bind_group(&device, &key, "main", &pipeline, 2, &all)?,
                )
            }
            None => None,
        };
        let mut groups = [world_group, group2, maps_group];
        // A derived layout has every group below the last used: fill the gaps empty.
        let last = groups.iter().rposition(Option::is_some).unwrap_or(0);
        for (i, group) in groups.iter_mut().enumerate().take(last) {
            if group.is_none() {
                *group = Some(cx.shaders.group(
                    &device,
                    &pipeline_ref,
                    i as u32 + 1,
                    "resolve: unused group",
                    &[],
                ));
            }
        }
        work.push((pipeline, group0, groups));
    }
    let pass = cx.compute_pass(targets.label());
    for (pipeline, group0, groups) in &work {
        pass.set_pipeline(pipeline);
        pass.set_bind_group(0, group0, &[]);
        for (i, group) in groups.iter().enumerate() {
            if let Some(group) = group {
                pass.set_bind_group(i as u32 + 1, group, &[]);
            }
        }
        pass.dispatch_workgroups(w.div_ceil(8), h.div_ceil(8), 1);
    }
    Ok(())
}

/// Group 1 of a resolve composed with a shader node material: its pins'
/// uniform block, texture inputs and samplers, those the permutation uses.
fn surface_group(
    cx: &mut PassContext<'_>,
    pipeline: &wgpu::ComputePipeline,
    surface: &super::SurfaceShader,
    params: Option<&wgpu::Buffer>,
    used: &[(u32, u32)],
) -> Result<Option<wgpu::BindGroup>, RenderError> {
    use super::SurfaceBinding;
    // A derived layout has groups up to the last one used: none past 0, no group 1.
    if !used.iter().any(|(group, _)| *group >= 1) {
        return Ok(None);
    }
    let mut views = Vec::new();
    for (_, binding) in &surface.bindings {
        if let SurfaceBinding::Texture(t) = binding {
            let texture = surface.textures.get(*t).ok_or_else(|| RenderError::Pass {
                pass: format!("{}: resolve surface", surface.label),
                message: format!("texture input {t} is not connected"),
            })?;
            views.push((*t, cx.view(&texture.name)?));
        }
    }
    let mut samplers = Vec::new();
    for (_, binding) in &surface.bindings {
        if let SurfaceBinding::Sampler { repeat } = binding {
            let sampling = if *repeat {
                crate::shaders::Sampling::LinearRepeat
            } else {
                crate::shaders::Sampling::LinearClamp
            };
            samplers.push((*repeat, cx.sampler(sampling)));
        }
    }
    let mut entries = Vec::new();
    for (binding, role) in &surface.bindings {
        if !used.contains(&(1, *binding)) {
            continue;
        }
        let resource = match role {
            SurfaceBinding::Uniform => match params {
                Some(buffer) => buffer.as_entire_binding(),
                None => continue,
            },
            SurfaceBinding::Texture(t) => match views.iter().find(|(i, _)| i == t) {
                Some((_, view)) => wgpu::BindingResource::TextureView(view),
                None => continue,
            },
            SurfaceBinding::Sampler { repeat } => {
                match samplers.iter().find(|(r, _)| r == repeat) {
                    Some((_, sampler)) => wgpu::BindingResource::Sampler(sampler),
                    None => continue,
                }
            }
        };
        entries.push(wgpu::BindGroupEntry {
            binding: *binding,
            resource,
        });
    }
    Ok(Some(cx.gpu.device.create_bind_group(
        &wgpu::BindGroupDescriptor {
            label: Some("resolve: shader node material"),
            layout: &pipeline.get_bind_group_layout(1),
            entries: &entries,
        },
    )))
}

/// The layer record of a G-buffer with no layers: covers nothing, clears everything.
fn background_layer(device: &wgpu::Device) -> wgpu::Buffer {
    use wgpu::util::DeviceExt;
    device.create_buffer_init(&wgpu::util::BufferInitDescriptor {
        label: Some("mre background layer"),
        contents: bytemuck::cast_slice(&[0u32, 0, 1, 0]),
        usage: wgpu::BufferUsages::UNIFORM,
    })
}
