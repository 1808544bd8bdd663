//! The live viewports: a texture pin rendered by the shared renderer on the
//! device egui draws with, then shown as a native egui texture. No readback:
//! the frame graph's output is copied on the GPU into a texture egui samples.

use std::sync::Arc;

use spreadlight_render::{FrameGraph, GpuContext, Renderer, TextureRef};
use thiserror::Error;

#[derive(Debug, Error, Clone, PartialEq)]
pub enum ViewportError {
    #[error("nothing to show: link a texture into the Output node, or pick a texture pin")]
    NoTexture,
    #[error("{0} feeds no Output, so it is not evaluated")]
    NotEvaluated(String),
    #[error("rendering failed: {0}")]
    Render(String),
    #[error("the frame produced no `{0}`")]
    Missing(String),
    #[error("a {0:?} texture cannot be shown (depth and integer textures have no colour)")]
    Format(wgpu::TextureFormat),
}

/// The format the viewport's texture is written in: the frame graph's
/// linear values, sRGB-encoded by the hardware on write.
pub const VIEW_FORMAT: wgpu::TextureFormat = wgpu::TextureFormat::Rgba8UnormSrgb;
/// The format egui reads it through. egui treats what it samples as
/// gamma-encoded (`tex_gamma` in egui-wgpu's shader), so it must get the
/// encoded bytes: through an sRGB view it got linear values back and showed
/// them as if encoded (a linear grey of 0.305, sRGB 150, shown as 78).
pub const EGUI_VIEW_FORMAT: wgpu::TextureFormat = wgpu::TextureFormat::Rgba8Unorm;

const BLIT_WGSL: &str = r"
@group(0) @binding(0) var src: texture_2d<f32>;

@vertex
fn vs(@builtin(vertex_index) i: u32) -> @builtin(position) vec4<f32> {
    let uv = vec2<f32>(f32((i << 1u) & 2u), f32(i & 2u));
    return vec4<f32>(uv * 2.0 - 1.0, 0.0, 1.0);
}

@fragment
fn fs(@builtin(position) p: vec4<f32>) -> @location(0) vec4<f32> {
    let size = vec2<i32>(textureDimensions(src));
    let c = textureLoad(src, min(vec2<i32>(p.xy), size - 1), 0);
    // Single-channel textures (depth-like data in R32Float) show as grey.
    return vec4<f32>(clamp(c.rgb, vec3(0.0), vec3(1.0)), 1.0);
}
";

/// Copies any float colour texture into the viewport's texture, whatever its
/// format (Rgba32Float is not filterable, so egui could not sample it directly).
pub struct Blitter {
    layout: wgpu::BindGroupLayout,
    pipeline: wgpu::RenderPipeline,
}

impl Blitter {
    pub fn new(device: &wgpu::Device) -> Self {
        let shader = device.create_shader_module(wgpu::ShaderModuleDescriptor {
            label: Some("viewport blit"),
            source: wgpu::ShaderSource::Wgsl(BLIT_WGSL.into()),
        });
        let layout = device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
            label: Some("viewport blit"),
            entries: &[wgpu::BindGroupLayoutEntry {
                binding: 0,
                visibility: wgpu::ShaderStages::FRAGMENT,
                ty: wgpu::BindingType::Texture {
                    sample_type: wgpu::TextureSampleType::Float { filterable: false },
                    view_dimension: wgpu::TextureViewDimension::D2,
                    multisampled: false,
                },
                count: None,
            }],
        });
        let pipeline_layout = device.create_pipeline_layout(&wgpu::PipelineLayoutDescriptor {
            label: Some("viewport blit"),
            bind_group_layouts: &[Some(&layout)],
            immediate_size: 0,
        });
        let pipeline = device.create_render_pipeline(&wgpu::RenderPipelineDescriptor {
            label: Some("viewport blit"),
            layout: Some(&pipeline_layout),
            vertex: wgpu::VertexState {
                module: &shader,
                entry_point: Some("vs"),
                compilation_options: Default::default(),
                buffers: &[],
            },
            fragment: Some(wgpu::FragmentState {
                module: &shader,
                entry_point: Some("fs"),
                compilation_options: Default::default(),
                targets: &[Some(VIEW_FORMAT.into())],
            }),
            primitive: wgpu::PrimitiveState::default(),
            depth_stencil: None,
            multisample: wgpu::MultisampleState::default(),
            multiview_mask: None,
            cache: None,
        });
        Blitter { layout, pipeline }
    }

    fn blit(
        &self,
        gpu: &GpuContext,
        src: &wgpu::Texture,
        dst: &wgpu::TextureView,
    ) -> Result<(), ViewportError> {
        let showable = matches!(
            src.format().sample_type(None, None),
            Some(wgpu::TextureSampleType::Float { .. })
        );
        if !showable || src.format().is_depth_stencil_format() {
            return Err(ViewportError::Format(src.format()));
        }
        // In an error scope: what wgpu refuses is this viewport's error, not a panic.
        let commands = gpu
            .scoped(|| {
                // Its first layer and level as a plain 2D view, whatever it is (an
                // image file's texture array, a mip chain): what the blit samples.
                let view = src.create_view(&wgpu::TextureViewDescriptor {
                    dimension: Some(wgpu::TextureViewDimension::D2),
                    base_mip_level: 0,
                    mip_level_count: Some(1),
                    base_array_layer: 0,
                    array_layer_count: Some(1),
                    ..Default::default()
                });
                let bind = gpu.device.create_bind_group(&wgpu::BindGroupDescriptor {
                    label: Some("viewport blit"),
                    layout: &self.layout,
                    entries: &[wgpu::BindGroupEntry {
                        binding: 0,
                        resource: wgpu::BindingResource::TextureView(&view),
                    }],
                });
                let mut encoder = gpu.device.create_command_encoder(&Default::default());
                {
                    let mut pass = encoder.begin_render_pass(&wgpu::RenderPassDescriptor {
                        label: Some("viewport blit"),
                        color_attachments: &[Some(wgpu::RenderPassColorAttachment {
                            view: dst,
                            depth_slice: None,
                            resolve_target: None,
                            ops: wgpu::Operations {
                                load: wgpu::LoadOp::Clear(wgpu::Color::BLACK),
                                store: wgpu::StoreOp::Store,
                            },
                        })],
                        depth_stencil_attachment: None,
                        timestamp_writes: None,
                        occlusion_query_set: None,
                        multiview_mask: None,
                    });
                    pass.set_pipeline(&self.pipeline);
                    pass.set_bind_group(0, &bind, &[]);
                    pass.draw(0..3, 0..1);
                }
                encoder.finish()
            })
            .map_err(ViewportError::Render)?;
        // Through the renderer's gate like its own frames: a window's surface
        // may be configured on the UI thread meanwhile (`GpuContext::submit`).
        gpu.submit([commands]);
        Ok(())
    }
}

/// One viewport's texture, registered with egui.
#[derive(Clone)]
pub struct ViewTarget {
    pub texture: wgpu::Texture,
    pub id: egui::TextureId,
}

/// Render `texture` at `size` with the shared renderer and copy it into
/// `target` (made or resized as needed). Returns the frame's report for the
/// GPU times.
pub fn render_into(
    render_state: &egui_wgpu::RenderState,
    renderer: &Arc<Renderer>,
    blitter: &Blitter,
    texture: &TextureRef,
    size: (u32, u32),
    target: &mut Option<ViewTarget>,
) -> Result<spreadlight_render::FrameReport, ViewportError> {
    let size = (size.0.max(1), size.1.max(1));
    renderer.set_output_size(size);
    let mut graph = FrameGraph::new(size);
    texture.recipe.declare(renderer, &mut graph);
    graph.request(&texture.name);
    let (report, outputs) = graph
        .execute(renderer)
        .map_err(|e| ViewportError::Render(e.to_string()))?;
    let src = outputs
        .get(&texture.name)
        .ok_or_else(|| ViewportError::Missing(texture.name.clone()))?;
    let device = &render_state.device;
    let src_size = (src.width(), src.height());
    let fits = target
        .as_ref()
        .is_some_and(|t| (t.texture.width(), t.texture.height()) == src_size);
    if !fits {
        let new = device.create_texture(&wgpu::TextureDescriptor {
            label: Some("viewport"),
            size: wgpu::Extent3d {
                width: src_size.0,
                height: src_size.1,
                depth_or_array_layers: 1,
            },
            mip_level_count: 1,
            sample_count: 1,
            dimension: wgpu::TextureDimension::D2,
            format: VIEW_FORMAT,
            usage: wgpu::TextureUsages::RENDER_ATTACHMENT
                | wgpu::TextureUsages::TEXTURE_BINDING
                | wgpu::TextureUsages::COPY_SRC,
            view_formats: &[EGUI_VIEW_FORMAT],
        });
        let view = new.create_view(&wgpu::TextureViewDescriptor {
            format: Some(EGUI_VIEW_FORMAT),
            ..Default::default()
        });
        let mut egui_renderer = render_state.renderer.write();
        let id = match target.take() {
            Some(old) => {
                egui_renderer.update_egui_texture_from_wgpu_texture(
                    device,
                    &view,
                    wgpu::FilterMode::Linear,
                    old.id,
                );
                old.id
            }
            None => egui_renderer.register_native_texture(device, &view, wgpu::FilterMode::Linear),
        };
        *target = Some(ViewTarget { texture: new, id });
    }
    let Some(t) = target.as_ref() else {
        return Err(ViewportError::NoTexture);
    };
    let dst = t.texture.create_view(&Default::default());
    blitter.blit(&renderer.gpu, src, &dst)?;
    Ok(report)
}
