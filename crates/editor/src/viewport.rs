//! The live viewports: a texture pin rendered by the shared renderer on the
//! device egui draws with, then shown as a native egui texture. No readback:
//! the frame graph's output is copied on the GPU into a texture egui samples.

use std::collections::HashMap;
use std::sync::Arc;

use spreadlight_render::shaders::Reflection;
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
struct Params {
    // The source texel the target's pixel (0, 0) starts at, and source
    // texels per target pixel: 1 for the viewports, more for thumbnails.
    origin: vec2<f32>,
    scale: vec2<f32>,
    // 0: colour (linear light, sRGB-encoded by the target's format);
    // 1: data (stored values shown as they are); 2: raw (a probe: unclamped).
    mode: u32,
    // Taps per axis across a target pixel's footprint (a box filter).
    taps: u32,
    pad: vec2<u32>,
}

@group(0) @binding(0) var src: texture_2d<f32>;
@group(0) @binding(1) var<uniform> params: Params;

@vertex
fn vs(@builtin(vertex_index) i: u32) -> @builtin(position) vec4<f32> {
    let uv = vec2<f32>(f32((i << 1u) & 2u), f32(i & 2u));
    return vec4<f32>(uv * 2.0 - 1.0, 0.0, 1.0);
}

fn srgb_to_linear(c: vec3<f32>) -> vec3<f32> {
    let low = c / 12.92;
    let high = pow((c + 0.055) / 1.055, vec3<f32>(2.4));
    return select(high, low, c <= vec3<f32>(0.04045));
}

@fragment
fn fs(@builtin(position) p: vec4<f32>) -> @location(0) vec4<f32> {
    let size = vec2<i32>(textureDimensions(src));
    let n = max(params.taps, 1u);
    let start = params.origin + floor(p.xy) * params.scale;
    var sum = vec4<f32>(0.0);
    for (var j = 0u; j < n; j++) {
        for (var i = 0u; i < n; i++) {
            let at = start + (vec2<f32>(f32(i), f32(j)) + 0.5) / f32(n) * params.scale;
            sum += textureLoad(src, clamp(vec2<i32>(at), vec2<i32>(0), size - 1), 0);
        }
    }
    let c = sum / f32(n * n);
    if params.mode == 2u {
        return c;
    }
    // Single-channel textures (depth-like data in R32Float) show in red.
    let v = clamp(c.rgb, vec3(0.0), vec3(1.0));
    if params.mode == 1u {
        // The target encodes what it is given: hand it the value whose
        // encoding is the stored value, so 0.5 shows as 128.
        return vec4<f32>(srgb_to_linear(v), 1.0);
    }
    return vec4<f32>(v, 1.0);
}
";

/// The format a probe (one texel read back unclamped) is blitted into.
const PROBE_FORMAT: wgpu::TextureFormat = wgpu::TextureFormat::Rgba32Float;

/// Whether a texture of `format` holds data shown as stored (a non-sRGB
/// 8- or 16-bit normalised format: a FileTexture with sRGB off, a normal
/// map, a mask), rather than linear light encoded for the display (sRGB
/// formats, float render targets, Tonemap's output). Data shows as image
/// viewers, vvvv and TouchDesigner show it: a stored 0.5 as grey 128.
pub fn shows_as_data(format: wgpu::TextureFormat) -> bool {
    use wgpu::TextureFormat as F;
    matches!(
        format,
        F::R8Unorm
            | F::Rg8Unorm
            | F::Rgba8Unorm
            | F::Bgra8Unorm
            | F::R16Unorm
            | F::Rg16Unorm
            | F::Rgba16Unorm
            | F::Rgb10a2Unorm
            | F::R8Snorm
            | F::Rg8Snorm
            | F::Rgba8Snorm
            | F::R16Snorm
            | F::Rg16Snorm
            | F::Rgba16Snorm
    )
}

/// How a blit maps its source onto its target.
#[derive(Clone, Copy, Debug)]
enum BlitMode {
    /// Every pixel of the target from the source's texels, whatever its size.
    Fit,
    /// One texel, unclamped, into a 1x1 float target.
    Probe(u32, u32),
}

/// Copies any float colour texture into the viewport's texture, whatever its
/// format (Rgba32Float is not filterable, so egui could not sample it
/// directly), and scales it down into thumbnails (a box filter).
pub struct Blitter {
    /// `BLIT_WGSL`'s variables, which each blit binds by name.
    reflection: Reflection,
    pipeline: wgpu::RenderPipeline,
    probe: wgpu::RenderPipeline,
}

impl Blitter {
    pub fn new(device: &wgpu::Device) -> Self {
        let shader = device.create_shader_module(wgpu::ShaderModuleDescriptor {
            label: Some("viewport blit"),
            source: wgpu::ShaderSource::Wgsl(BLIT_WGSL.into()),
        });
        // Bound by variable name (render's reflection), its layout derived
        // by wgpu: no binding number is written twice.
        let reflection = Reflection::of_wgsl(BLIT_WGSL, "fs")
            .expect("the viewport blit's own shader parses and has `fs`");
        let pipeline = |format: wgpu::TextureFormat| {
            device.create_render_pipeline(&wgpu::RenderPipelineDescriptor {
                label: Some("viewport blit"),
                layout: None,
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
                    targets: &[Some(format.into())],
                }),
                primitive: wgpu::PrimitiveState::default(),
                depth_stencil: None,
                multisample: wgpu::MultisampleState::default(),
                multiview_mask: None,
                cache: None,
            })
        };
        Blitter {
            pipeline: pipeline(VIEW_FORMAT),
            probe: pipeline(PROBE_FORMAT),
            reflection,
        }
    }

    /// Whether the blit can show `format`: float-sampled colour, not depth.
    fn check(format: wgpu::TextureFormat) -> Result<(), ViewportError> {
        let showable = matches!(
            format.sample_type(None, None),
            Some(wgpu::TextureSampleType::Float { .. })
        );
        if !showable || format.is_depth_stencil_format() {
            return Err(ViewportError::Format(format));
        }
        Ok(())
    }

    fn blit(
        &self,
        gpu: &GpuContext,
        src: &wgpu::Texture,
        dst: &wgpu::Texture,
        how: BlitMode,
    ) -> Result<(), ViewportError> {
        let commands = self.encode(gpu, src, dst, how)?;
        // Through the renderer's gate like its own frames: a window's surface
        // may be configured on the UI thread meanwhile (`GpuContext::submit`).
        gpu.submit([commands]);
        Ok(())
    }

    /// The commands of a blit, to submit with others: each submission may
    /// wait for the UI's next frame at the gate, so a frame's thumbnails
    /// go in one.
    fn encode(
        &self,
        gpu: &GpuContext,
        src: &wgpu::Texture,
        dst: &wgpu::Texture,
        how: BlitMode,
    ) -> Result<wgpu::CommandBuffer, ViewportError> {
        use wgpu::util::DeviceExt;
        Self::check(src.format())?;
        let (dst_w, dst_h) = (dst.width().max(1), dst.height().max(1));
        let (origin, scale, mode, taps, pipeline) = match how {
            BlitMode::Fit => {
                let scale = [
                    src.width() as f32 / dst_w as f32,
                    src.height() as f32 / dst_h as f32,
                ];
                // Up to 4x4 taps a pixel: enough that a thumbnail of a
                // noisy frame does not shimmer, cheap at thumbnail sizes.
                let taps = scale[0].max(scale[1]).ceil().clamp(1.0, 4.0) as u32;
                let mode = u32::from(shows_as_data(src.format()));
                ([0.0, 0.0], scale, mode, taps, &self.pipeline)
            }
            BlitMode::Probe(x, y) => ([x as f32, y as f32], [1.0, 1.0], 2, 1, &self.probe),
        };
        let mut params = [0u8; 32];
        for (k, v) in origin.iter().chain(&scale).enumerate() {
            params[k * 4..k * 4 + 4].copy_from_slice(&v.to_le_bytes());
        }
        params[16..20].copy_from_slice(&mode.to_le_bytes());
        params[20..24].copy_from_slice(&taps.to_le_bytes());
        // In an error scope: what wgpu refuses is this viewport's error, not a panic.
        gpu.scoped(|| {
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
            let dst = dst.create_view(&Default::default());
            let buffer = gpu
                .device
                .create_buffer_init(&wgpu::util::BufferInitDescriptor {
                    label: Some("viewport blit params"),
                    contents: &params,
                    usage: wgpu::BufferUsages::UNIFORM,
                });
            let entries = self.reflection.entries(
                0,
                &[
                    ("src", wgpu::BindingResource::TextureView(&view)),
                    ("params", buffer.as_entire_binding()),
                ],
            )?;
            let bind = gpu.device.create_bind_group(&wgpu::BindGroupDescriptor {
                label: Some("viewport blit"),
                layout: &pipeline.get_bind_group_layout(0),
                entries: &entries,
            });
            let mut encoder = gpu.device.create_command_encoder(&Default::default());
            {
                let mut pass = encoder.begin_render_pass(&wgpu::RenderPassDescriptor {
                    label: Some("viewport blit"),
                    color_attachments: &[Some(wgpu::RenderPassColorAttachment {
                        view: &dst,
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
                pass.set_pipeline(pipeline);
                pass.set_bind_group(0, &bind, &[]);
                pass.draw(0..3, 0..1);
            }
            Ok(encoder.finish())
        })
        .and_then(|made| made)
        .map_err(ViewportError::Render)
    }

    /// The value of texel (x, y) of `src` as the shaders read it (linear,
    /// unclamped): what a preview shows under the pointer. Waits for the GPU.
    pub fn probe(
        &self,
        gpu: &GpuContext,
        src: &wgpu::Texture,
        (x, y): (u32, u32),
    ) -> Result<[f32; 4], ViewportError> {
        let texel = gpu.device.create_texture(&wgpu::TextureDescriptor {
            label: Some("preview probe"),
            size: wgpu::Extent3d {
                width: 1,
                height: 1,
                depth_or_array_layers: 1,
            },
            mip_level_count: 1,
            sample_count: 1,
            dimension: wgpu::TextureDimension::D2,
            format: PROBE_FORMAT,
            usage: wgpu::TextureUsages::RENDER_ATTACHMENT | wgpu::TextureUsages::COPY_SRC,
            view_formats: &[],
        });
        self.blit(gpu, src, &texel, BlitMode::Probe(x, y))?;
        spreadlight_render::readback::read_texture(gpu, &texel)
            .map(|image| image.pixel(0, 0))
            .map_err(|e| ViewportError::Render(e.to_string()))
    }
}

/// One viewport's texture, registered with egui.
#[derive(Clone)]
pub struct ViewTarget {
    pub texture: wgpu::Texture,
    pub id: egui::TextureId,
}

/// Render `textures` at `size` with the shared renderer, in one frame graph
/// (a recipe two of them share runs once), and watch `watched`
/// ([`FrameGraph::watch`]: handed back when the frame makes them anyway,
/// without changing the frame). Returns the frame's report and the
/// textures by name.
pub fn render_frame(
    renderer: &Arc<Renderer>,
    textures: &[&TextureRef],
    watched: &[&TextureRef],
    size: (u32, u32),
) -> Result<RenderedFrame, ViewportError> {
    render_frame_then(renderer, textures, watched, size, |_| Vec::new())
}

/// [`render_frame`], with `then`'s commands (the blits of what the frame
/// hands back into egui's textures) in the frame's own submission
/// ([`FrameGraph::execute_then`]): every submission of the worker's may wait
/// at the gate for a UI frame, so a frame and its blits wait once.
pub fn render_frame_then(
    renderer: &Arc<Renderer>,
    textures: &[&TextureRef],
    watched: &[&TextureRef],
    size: (u32, u32),
    then: impl FnOnce(&HashMap<String, wgpu::Texture>) -> Vec<wgpu::CommandBuffer>,
) -> Result<RenderedFrame, ViewportError> {
    let size = (size.0.max(1), size.1.max(1));
    renderer.set_output_size(size);
    let mut graph = FrameGraph::new(size);
    for texture in textures {
        texture.recipe.declare(renderer, &mut graph);
        graph.request(&texture.name);
    }
    for texture in watched {
        texture.recipe.declare(renderer, &mut graph);
        graph.watch(&texture.name);
    }
    graph
        .execute_then(renderer, then)
        .map_err(|e| ViewportError::Render(e.to_string()))
}

/// A rendered frame: its report and its requested textures by name.
pub type RenderedFrame = (
    spreadlight_render::FrameReport,
    HashMap<String, wgpu::Texture>,
);

/// Render `texture` at `size` with the shared renderer and copy it into
/// `target` (made or resized as needed), in the frame's own submission.
/// Returns the frame's report for the GPU times.
pub fn render_into(
    render_state: &egui_wgpu::RenderState,
    renderer: &Arc<Renderer>,
    blitter: &Blitter,
    texture: &TextureRef,
    size: (u32, u32),
    target: &mut Option<ViewTarget>,
) -> Result<spreadlight_render::FrameReport, ViewportError> {
    let mut shown = Err(ViewportError::Missing(texture.name.clone()));
    let (report, _) = render_frame_then(renderer, &[texture], &[], size, |outputs| {
        let mut batch = Vec::new();
        if let Some(src) = outputs.get(&texture.name) {
            shown = show_in_batch(
                render_state,
                renderer,
                blitter,
                src,
                (src.width(), src.height()),
                target,
                &mut batch,
            );
        }
        batch
    })?;
    shown.map(|()| report)
}

/// Copy `src` into `target` at `size` in pixels (made, or remade at another
/// size, and registered with egui as needed): one blit, scaled down when
/// `size` is smaller (a thumbnail), its commands added to `batch` for the
/// caller to submit (with the frame that made `src`: [`render_frame_then`]).
pub fn show_in_batch(
    render_state: &egui_wgpu::RenderState,
    renderer: &Renderer,
    blitter: &Blitter,
    src: &wgpu::Texture,
    size: (u32, u32),
    target: &mut Option<ViewTarget>,
    batch: &mut Vec<wgpu::CommandBuffer>,
) -> Result<(), ViewportError> {
    Blitter::check(src.format())?;
    let size = (size.0.max(1), size.1.max(1));
    let device = &render_state.device;
    let fits = target
        .as_ref()
        .is_some_and(|t| (t.texture.width(), t.texture.height()) == size);
    if !fits {
        let new = device.create_texture(&wgpu::TextureDescriptor {
            label: Some("viewport"),
            size: wgpu::Extent3d {
                width: size.0,
                height: size.1,
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
    batch.push(blitter.encode(&renderer.gpu, src, &t.texture, BlitMode::Fit)?);
    Ok(())
}
