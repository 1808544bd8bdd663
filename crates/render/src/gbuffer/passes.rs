//! The G-buffer's three passes: visibility (hardware raster, or the compute
//! rasterizer in compute_raster.rs), surface and motion resolves (compute,
//! one dispatch per layer with that layer's permutation).

use crate::error::RenderError;
use crate::frame_graph::{FrameGraph, Lifetime, PassContext, TextureDesc};
use crate::renderer::Renderer;
use crate::shaders::ShaderKey;

use super::{GBuffer, RasterMode};

const VISIBILITY_FORMAT: wgpu::TextureFormat = wgpu::TextureFormat::Rg32Uint;
const HARDWARE_DEPTH_FORMAT: wgpu::TextureFormat = wgpu::TextureFormat::Depth32Float;
const DEPTH_FORMAT: wgpu::TextureFormat = wgpu::TextureFormat::R32Float;
const TARGET_FORMAT: wgpu::TextureFormat = wgpu::TextureFormat::Rgba16Float;
const SURFACE_FORMAT: wgpu::TextureFormat = wgpu::TextureFormat::Rgba32Uint;

pub(super) fn declare<'a>(g: &'a GBuffer, renderer: &'a Renderer, fg: &mut FrameGraph<'a>) {
    let t = &g.targets;
    let label = |what: &str| match g.owner {
        Some(node) => format!("MRE #{node}: {what}"),
        None => format!("MRE: {what}"),
    };
    let mut surface_reads: Vec<&str> = vec![&t.visibility];
    match (g.raster, &g.compute) {
        (RasterMode::Compute, Some(compute)) => {
            // The 64-bit buffer belongs to the G-buffer; this 1x1 token
            // carries the dependency through the frame graph.
            let token = TextureDesc::token();
            fg.add_pass(
                label("compute raster"),
                g.owner,
                &[],
                &[(&t.visibility, token)],
                move |cx| compute.record(g, renderer, cx),
            );
        }
        _ => {
            fg.add_pass(
                label("visibility"),
                g.owner,
                &[],
                &[
                    (
                        &t.visibility,
                        TextureDesc::attachment(VISIBILITY_FORMAT).size(g.size),
                    ),
                    (
                        &t.hardware_depth,
                        TextureDesc::attachment(HARDWARE_DEPTH_FORMAT).size(g.size),
                    ),
                ],
                move |cx| visibility(g, renderer, cx),
            );
            surface_reads.push(&t.hardware_depth);
        }
    }
    // The surface resolve also reads the layers' normal maps. Its depth is
    // Permanent: readers (lighting, GBufferView) come later in the frame.
    surface_reads.extend(
        g.layers
            .iter()
            .flat_map(|l| l.maps().chain(l.surface_textures()))
            .map(|n| n.name.as_str()),
    );
    let mut surface_writes = vec![
        (
            t.color.as_str(),
            TextureDesc::storage(TARGET_FORMAT).size(g.size),
        ),
        (
            t.normals.as_str(),
            TextureDesc::storage(TARGET_FORMAT).size(g.size),
        ),
        (
            t.depth.as_str(),
            TextureDesc::storage(DEPTH_FORMAT)
                .size(g.size)
                .lifetime(Lifetime::Permanent),
        ),
    ];
    if let Some(surface) = &t.surface {
        surface_writes.push((
            surface.as_str(),
            TextureDesc::storage(SURFACE_FORMAT).size(g.size),
        ));
    }
    fg.add_pass(
        label("resolve surface"),
        g.owner,
        &surface_reads,
        &surface_writes,
        move |cx| resolve(g, renderer, cx, false),
    );
    fg.add_pass(
        label("resolve motion"),
        g.owner,
        &[&t.visibility],
        &[(
            &t.velocity_uv,
            TextureDesc::storage(TARGET_FORMAT).size(g.size),
        )],
        move |cx| resolve(g, renderer, cx, true),
    );
}

fn visibility(
    g: &GBuffer,
    renderer: &Renderer,
    cx: &mut PassContext<'_>,
) -> Result<(), RenderError> {
    let device = cx.gpu.device.clone();
    let (vertices, indices, _) = renderer.meshes.buffers();
    let extras = renderer.meshes.extras();
    // Culling back faces, and (for draws of double-sided materials) not.
    let mut plain: [Option<(wgpu::RenderPipeline, wgpu::BindGroup)>; 2] = [None, None];
    for sided in [false, true] {
        if g.draws.iter().any(|d| d.two_sided == sided) {
            let pipeline = visibility_pipeline(cx, false, sided)?;
            let group = device.create_bind_group(&wgpu::BindGroupDescriptor {
                label: Some("visibility"),
                layout: &pipeline.get_bind_group_layout(0),
                entries: &g.geometry_entries(&vertices, &indices),
            });
            plain[usize::from(sided)] = Some((pipeline, group));
        }
    }
    // Per layer with alpha-tested materials: the ALPHA_MASK pipeline and its world's groups.
    let mut masked = Vec::new();
    for (layer, range) in g.layers.iter().zip(&g.layer_ranges) {
        let Some(world) = layer.map_world().filter(|_| layer.alpha_masked()) else {
            continue;
        };
        for sided in [false, true] {
            let in_layer = |d: &&super::Draw| (range.0..range.1).contains(&d.first_instance);
            if !g
                .draws
                .iter()
                .filter(in_layer)
                .any(|d| d.two_sided == sided)
            {
                continue;
            }
            let pipeline = visibility_pipeline(cx, true, sided)?;
            let mut entries = g.geometry_entries(&vertices, &indices);
            entries.push(wgpu::BindGroupEntry {
                binding: 12,
                resource: extras.as_entire_binding(),
            });
            let group0 = device.create_bind_group(&wgpu::BindGroupDescriptor {
                label: Some("visibility, alpha mask"),
                layout: &pipeline.get_bind_group_layout(0),
                entries: &entries,
            });
            let group1 = world.world_bind_group(
                &device,
                &pipeline.get_bind_group_layout(1),
                "visibility: material world",
            );
            let group2 = device.create_bind_group(&wgpu::BindGroupDescriptor {
                label: Some("visibility: unused group"),
                layout: &pipeline.get_bind_group_layout(2),
                entries: &[],
            });
            let group3 = world.maps_bind_group(&device, &pipeline.get_bind_group_layout(3));
            masked.push((
                *range,
                sided,
                pipeline,
                [Some(group0), Some(group1), Some(group2), group3],
            ));
        }
    }
    let vis = cx.view(&g.targets.visibility)?;
    let depth = cx.view(&g.targets.hardware_depth)?;
    // Publishing a depth for particle collisions: the meshes in a first
    // pass, the depth copied, then the particles (procedural draws).
    let phases: &[Option<bool>] = match g.published_depth() {
        Some(_) => &[Some(false), Some(true)],
        None => &[None],
    };
    let mut draws = 0;
    for (k, phase) in phases.iter().enumerate() {
        if let (1, Some(name)) = (k, g.published_depth()) {
            super::published_depth::publish(
                renderer,
                cx,
                name,
                super::published_depth::DepthSource::Hardware(&depth),
                g.pixel_size(cx.output_size),
                g.camera.view_projection(),
            )?;
        }
        let (color_load, depth_load) = match k {
            0 => (
                wgpu::LoadOp::Clear(wgpu::Color::TRANSPARENT),
                wgpu::LoadOp::Clear(0.0),
            ),
            _ => (wgpu::LoadOp::Load, wgpu::LoadOp::Load),
        };
        let timestamps = cx.render_timestamps();
        let mut pass = cx.encoder.begin_render_pass(&wgpu::RenderPassDescriptor {
            label: Some("visibility"),
            color_attachments: &[Some(wgpu::RenderPassColorAttachment {
                view: &vis,
                depth_slice: None,
                resolve_target: None,
                ops: wgpu::Operations {
                    load: color_load,
                    store: wgpu::StoreOp::Store,
                },
            })],
            depth_stencil_attachment: Some(wgpu::RenderPassDepthStencilAttachment {
                view: &depth,
                depth_ops: Some(wgpu::Operations {
                    load: depth_load,
                    store: wgpu::StoreOp::Store,
                }),
                stencil_ops: None,
            }),
            timestamp_writes: timestamps,
            occlusion_query_set: None,
            multiview_mask: None,
        });
        for draw in g.draws.iter().filter(|d| {
            d.instance_count > 0
                && d.index_count > 0
                && phase.is_none_or(|procedural| d.procedural == procedural)
        }) {
            let mask = masked.iter().find(|((first, end), sided, _, _)| {
                (*first..*end).contains(&draw.first_instance) && *sided == draw.two_sided
            });
            match mask {
                Some((_, _, pipeline, groups)) => {
                    pass.set_pipeline(pipeline);
                    for (i, group) in groups.iter().enumerate() {
                        if let Some(group) = group {
                            pass.set_bind_group(i as u32, group, &[]);
                        }
                    }
                }
                None => {
                    let Some((pipeline, group)) = &plain[usize::from(draw.two_sided)] else {
                        continue;
                    };
                    pass.set_pipeline(pipeline);
                    pass.set_bind_group(0, group, &[]);
                }
            }
            pass.draw(
                0..draw.index_count,
                draw.first_instance..draw.first_instance + draw.instance_count,
            );
            draws += 1;
        }
    }
    cx.draws += draws;
    Ok(())
}

/// The visibility pipeline: culling back faces unless `two_sided` (a draw
/// of a double-sided material), with `alpha_mask` testing MASK materials.
fn visibility_pipeline(
    cx: &mut PassContext<'_>,
    alpha_mask: bool,
    two_sided: bool,
) -> Result<wgpu::RenderPipeline, RenderError> {
    let device = cx.gpu.device.clone();
    let key = ShaderKey::new(
        "gbuffer/visibility.wgsl",
        alpha_mask.then_some("ALPHA_MASK"),
    );
    // Double-sided materials: every face is drawn (the resolve flips their back faces' normals).
    let variant = if two_sided {
        "rg32uint+depth32f, two-sided"
    } else {
        "rg32uint+depth32f"
    };
    cx.shaders
        .render_pipeline(&device, &key, variant, |module| {
            device.create_render_pipeline(&wgpu::RenderPipelineDescriptor {
                label: Some("visibility"),
                layout: None,
                vertex: wgpu::VertexState {
                    module,
                    entry_point: Some("vs"),
                    compilation_options: Default::default(),
                    buffers: &[],
                },
                primitive: wgpu::PrimitiveState {
                    topology: wgpu::PrimitiveTopology::TriangleList,
                    front_face: wgpu::FrontFace::Ccw,
                    cull_mode: (!two_sided).then_some(wgpu::Face::Back),
                    ..Default::default()
                },
                depth_stencil: Some(wgpu::DepthStencilState {
                    format: HARDWARE_DEPTH_FORMAT,
                    depth_write_enabled: Some(true),
                    depth_compare: Some(wgpu::CompareFunction::Greater),
                    stencil: Default::default(),
                    bias: Default::default(),
                }),
                multisample: Default::default(),
                fragment: Some(wgpu::FragmentState {
                    module,
                    entry_point: Some("fs"),
                    compilation_options: Default::default(),
                    targets: &[Some(wgpu::ColorTargetState {
                        format: VISIBILITY_FORMAT,
                        blend: None,
                        write_mask: wgpu::ColorWrites::ALL,
                    })],
                }),
                multiview_mask: None,
                cache: None,
            })
        })
}

fn resolve(
    g: &GBuffer,
    renderer: &Renderer,
    cx: &mut PassContext<'_>,
    motion: bool,
) -> Result<(), RenderError> {
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
        let runs = if motion {
            &g.motion_runs
        } else {
            &g.surface_runs
        };
        runs.iter().map(|(i, b)| (Some(*i), Some(b))).collect()
    };
    cx.count(
        if motion {
            "motion resolve dispatches"
        } else {
            "surface resolve dispatches"
        },
        dispatches.len() as u64,
    );
    let mut work = Vec::with_capacity(dispatches.len());
    for (index, layer_buffer) in dispatches {
        let i = index.unwrap_or(0);
        let layer = index.and_then(|i| g.layers.get(i));
        let mut defines = match layer {
            Some(l) if motion => l.features.motion_defines(),
            Some(l) => l.surface_defines(),
            None if motion => vec!["MOTION"],
            None => vec![],
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
        let group0 = device.create_bind_group(&wgpu::BindGroupDescriptor {
            label: Some("resolve"),
            layout: &pipeline.get_bind_group_layout(0),
            entries: &entries,
        });
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
                let sampler = cx
                    .shaders
                    .sampler(&device, crate::shaders::Sampling::LinearRepeat);
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
                *group = Some(device.create_bind_group(&wgpu::BindGroupDescriptor {
                    label: Some("resolve: unused group"),
                    layout: &pipeline.get_bind_group_layout(i as u32 + 1),
                    entries: &[],
                }));
            }
        }
        work.push((pipeline, group0, groups));
    }
    let timestamps = cx.compute_timestamps();
    let mut pass = cx.encoder.begin_compute_pass(&wgpu::ComputePassDescriptor {
        label: Some(if motion {
            "resolve motion"
        } else {
            "resolve surface"
        }),
        timestamp_writes: timestamps,
    });
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
    let device = cx.gpu.device.clone();
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
            samplers.push((*repeat, cx.shaders.sampler(&device, sampling)));
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
    Ok(Some(device.create_bind_group(&wgpu::BindGroupDescriptor {
        label: Some("resolve: shader node material"),
        layout: &pipeline.get_bind_group_layout(1),
        entries: &entries,
    })))
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
