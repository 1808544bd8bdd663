//! The G-buffer's three passes: visibility (raster), surface and motion
//! resolves (compute, one dispatch per layer with that layer's permutation).

use crate::error::RenderError;
use crate::frame_graph::{FrameGraph, PassContext, TextureDesc};
use crate::renderer::Renderer;
use crate::shaders::ShaderKey;

use super::GBuffer;

const VISIBILITY_FORMAT: wgpu::TextureFormat = wgpu::TextureFormat::Rg32Uint;
const DEPTH_FORMAT: wgpu::TextureFormat = wgpu::TextureFormat::Depth32Float;
const TARGET_FORMAT: wgpu::TextureFormat = wgpu::TextureFormat::Rgba16Float;

pub(super) fn declare<'a>(g: &'a GBuffer, renderer: &'a Renderer, fg: &mut FrameGraph<'a>) {
    let t = &g.targets;
    let label = |what: &str| match g.owner {
        Some(node) => format!("MRE #{node}: {what}"),
        None => format!("MRE: {what}"),
    };
    // The depth target is Permanent: readers (lighting, GBufferView, Output)
    // may come after the resolves, which must not recycle it.
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
                &t.depth,
                TextureDesc::attachment(DEPTH_FORMAT)
                    .size(g.size)
                    .lifetime(crate::frame_graph::Lifetime::Permanent),
            ),
        ],
        move |cx| visibility(g, renderer, cx),
    );
    // The surface resolve also reads the layers' normal maps.
    let mut surface_reads: Vec<&str> = vec![&t.visibility];
    surface_reads.extend(
        g.layers
            .iter()
            .filter_map(|l| l.normal_map.as_ref())
            .map(|n| n.name.as_str()),
    );
    fg.add_pass(
        label("resolve surface"),
        g.owner,
        &surface_reads,
        &[
            (&t.color, TextureDesc::storage(TARGET_FORMAT).size(g.size)),
            (&t.normals, TextureDesc::storage(TARGET_FORMAT).size(g.size)),
        ],
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
    let device = &cx.gpu.device;
    let key = ShaderKey::new("gbuffer/visibility.wgsl", []);
    let pipeline = cx
        .shaders
        .render_pipeline(device, &key, "rg32uint+depth32f", |module| {
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
                    cull_mode: Some(wgpu::Face::Back),
                    ..Default::default()
                },
                depth_stencil: Some(wgpu::DepthStencilState {
                    format: DEPTH_FORMAT,
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
        })?;
    let (vertices, indices, _) = renderer.meshes.buffers();
    let bind_group = device.create_bind_group(&wgpu::BindGroupDescriptor {
        label: Some("visibility"),
        layout: &pipeline.get_bind_group_layout(0),
        entries: &[
            wgpu::BindGroupEntry {
                binding: 0,
                resource: g.camera_buffer.as_entire_binding(),
            },
            wgpu::BindGroupEntry {
                binding: 1,
                resource: vertices.as_entire_binding(),
            },
            wgpu::BindGroupEntry {
                binding: 2,
                resource: indices.as_entire_binding(),
            },
            wgpu::BindGroupEntry {
                binding: 3,
                resource: g.instances.as_entire_binding(),
            },
        ],
    });
    let vis = cx.view(&g.targets.visibility)?;
    let depth = cx.view(&g.targets.depth)?;
    let timestamps = cx.render_timestamps();
    let mut pass = cx.encoder.begin_render_pass(&wgpu::RenderPassDescriptor {
        label: Some("visibility"),
        color_attachments: &[Some(wgpu::RenderPassColorAttachment {
            view: &vis,
            depth_slice: None,
            resolve_target: None,
            ops: wgpu::Operations {
                load: wgpu::LoadOp::Clear(wgpu::Color::TRANSPARENT),
                store: wgpu::StoreOp::Store,
            },
        })],
        depth_stencil_attachment: Some(wgpu::RenderPassDepthStencilAttachment {
            view: &depth,
            depth_ops: Some(wgpu::Operations {
                load: wgpu::LoadOp::Clear(0.0),
                store: wgpu::StoreOp::Store,
            }),
            stencil_ops: None,
        }),
        timestamp_writes: timestamps,
        occlusion_query_set: None,
        multiview_mask: None,
    });
    pass.set_pipeline(&pipeline);
    pass.set_bind_group(0, &bind_group, &[]);
    let mut draws = 0;
    for draw in g
        .draws
        .iter()
        .filter(|d| d.instance_count > 0 && d.index_count > 0)
    {
        pass.draw(
            0..draw.index_count,
            draw.first_instance..draw.first_instance + draw.instance_count,
        );
        draws += 1;
    }
    drop(pass);
    cx.draws += draws;
    Ok(())
}

fn resolve(
    g: &GBuffer,
    renderer: &Renderer,
    cx: &mut PassContext<'_>,
    motion: bool,
) -> Result<(), RenderError> {
    let device = cx.gpu.device.clone();
    let (vertices, indices, _) = renderer.meshes.buffers();
    let vis = cx.view(&g.targets.visibility)?;
    let outputs = if motion {
        vec![cx.view(&g.targets.velocity_uv)?]
    } else {
        vec![cx.view(&g.targets.color)?, cx.view(&g.targets.normals)?]
    };
    let (w, h) = {
        let t = cx.texture(&g.targets.visibility)?;
        (t.width(), t.height())
    };
    // With no layers, the first (background) dispatch still clears the targets.
    let layer_count = g.layers.len().max(1);
    let mut work = Vec::with_capacity(layer_count);
    for i in 0..layer_count {
        let layer = g.layers.get(i);
        let defines = match layer {
            Some(l) if motion => l.features.motion_defines(),
            Some(l) => l.features.surface_defines(),
            None if motion => vec!["MOTION"],
            None => vec![],
        };
        let key = ShaderKey::new("gbuffer/resolve.wgsl", defines);
        let pipeline = cx.shaders.compute_pipeline(&device, &key, "main")?;
        let layer_buffer = match g.layer_buffers.get(i) {
            Some(b) => b.clone(),
            None => background_layer(&device),
        };
        let mut entries = vec![
            wgpu::BindGroupEntry {
                binding: 0,
                resource: g.camera_buffer.as_entire_binding(),
            },
            wgpu::BindGroupEntry {
                binding: 1,
                resource: vertices.as_entire_binding(),
            },
            wgpu::BindGroupEntry {
                binding: 2,
                resource: indices.as_entire_binding(),
            },
            wgpu::BindGroupEntry {
                binding: 3,
                resource: g.instances.as_entire_binding(),
            },
            wgpu::BindGroupEntry {
                binding: 4,
                resource: wgpu::BindingResource::TextureView(&vis),
            },
            wgpu::BindGroupEntry {
                binding: 5,
                resource: layer_buffer.as_entire_binding(),
            },
        ];
        for (k, view) in outputs.iter().enumerate() {
            entries.push(wgpu::BindGroupEntry {
                binding: 6 + k as u32,
                resource: wgpu::BindingResource::TextureView(view),
            });
        }
        let group0 = device.create_bind_group(&wgpu::BindGroupDescriptor {
            label: Some("resolve"),
            layout: &pipeline.get_bind_group_layout(0),
            entries: &entries,
        });
        let group1 = match layer
            .and_then(|l| l.normal_map.as_ref())
            .filter(|_| !motion)
        {
            Some(normal_map) => {
                let normal_view = cx.view(&normal_map.name)?;
                let sampler = device.create_sampler(&wgpu::SamplerDescriptor {
                    address_mode_u: wgpu::AddressMode::Repeat,
                    address_mode_v: wgpu::AddressMode::Repeat,
                    mag_filter: wgpu::FilterMode::Linear,
                    min_filter: wgpu::FilterMode::Linear,
                    ..Default::default()
                });
                Some(device.create_bind_group(&wgpu::BindGroupDescriptor {
                    label: Some("resolve normal map"),
                    layout: &pipeline.get_bind_group_layout(1),
                    entries: &[
                        wgpu::BindGroupEntry {
                            binding: 0,
                            resource: wgpu::BindingResource::TextureView(&normal_view),
                        },
                        wgpu::BindGroupEntry {
                            binding: 1,
                            resource: wgpu::BindingResource::Sampler(&sampler),
                        },
                    ],
                }))
            }
            None => None,
        };
        work.push((pipeline, group0, group1));
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
    for (pipeline, group0, group1) in &work {
        pass.set_pipeline(pipeline);
        pass.set_bind_group(0, group0, &[]);
        if let Some(g1) = group1 {
            pass.set_bind_group(1, g1, &[]);
        }
        pass.dispatch_workgroups(w.div_ceil(8), h.div_ceil(8), 1);
    }
    Ok(())
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
