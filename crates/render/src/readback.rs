//! Reading textures back to the CPU: for `Output`, tests and the CLI.

use crate::context::GpuContext;
use crate::error::RenderError;
use crate::renderer::read_buffer;

/// A texture's pixels as linear RGBA floats, top row first.
#[derive(Clone, Debug, PartialEq)]
pub struct ImageF32 {
    pub width: u32,
    pub height: u32,
    pub pixels: Vec<[f32; 4]>,
}

impl ImageF32 {
    pub fn pixel(&self, x: u32, y: u32) -> [f32; 4] {
        self.pixels[(y * self.width + x) as usize]
    }

    /// Whether every channel of every pixel is finite: the stability promise.
    pub fn all_finite(&self) -> bool {
        self.pixels.iter().all(|p| p.iter().all(|c| c.is_finite()))
    }
}

/// Copy `texture` (mip 0) to the CPU. Supports the formats the renderer writes:
/// RGBA16F/32F, RGBA8 (sRGB decoded to linear), Depth32Float and R32Float (in R, G, B) and
/// RG32Uint (ids as floats in R, G).
pub fn read_texture(gpu: &GpuContext, texture: &wgpu::Texture) -> Result<ImageF32, RenderError> {
    read_texture_layer(gpu, texture, 0, 0)
}

/// [`read_texture`] of one array layer (a cube face) at one mip.
pub fn read_texture_layer(
    gpu: &GpuContext,
    texture: &wgpu::Texture,
    layer: u32,
    mip: u32,
) -> Result<ImageF32, RenderError> {
    let (width, height) = (
        (texture.width() >> mip).max(1),
        (texture.height() >> mip).max(1),
    );
    let format = texture.format();
    let key = crate::texture_pool::TextureKey {
        format,
        width,
        height,
        usage: texture.usage(),
    };
    let (bytes_per_pixel, row, size) = readback_layout(gpu, &key, "the texture")?;
    let aspect = if format == wgpu::TextureFormat::Depth32Float {
        wgpu::TextureAspect::DepthOnly
    } else {
        wgpu::TextureAspect::All
    };
    // In an error scope: whatever wgpu still refuses is this readback's error, not a panic.
    let buffer = gpu
        .scoped(|| {
            let buffer = gpu.device.create_buffer(&wgpu::BufferDescriptor {
                label: Some("readback"),
                size,
                usage: wgpu::BufferUsages::MAP_READ | wgpu::BufferUsages::COPY_DST,
                mapped_at_creation: false,
            });
            let mut encoder = gpu.device.create_command_encoder(&Default::default());
            encoder.copy_texture_to_buffer(
                wgpu::TexelCopyTextureInfo {
                    texture,
                    mip_level: mip,
                    origin: wgpu::Origin3d {
                        x: 0,
                        y: 0,
                        z: layer,
                    },
                    aspect,
                },
                wgpu::TexelCopyBufferInfo {
                    buffer: &buffer,
                    layout: wgpu::TexelCopyBufferLayout {
                        offset: 0,
                        bytes_per_row: Some(row),
                        rows_per_image: Some(height),
                    },
                },
                wgpu::Extent3d {
                    width,
                    height,
                    depth_or_array_layers: 1,
                },
            );
            (buffer, encoder.finish())
        })
        .map_err(RenderError::Readback)?;
    let (buffer, commands) = buffer;
    gpu.submit([commands]);
    let data = read_buffer(gpu, &buffer, size)?;
    let mut pixels = Vec::with_capacity((width * height) as usize);
    for y in 0..height {
        let start = (y * row) as usize;
        let line = &data[start..start + (width * bytes_per_pixel) as usize];
        for px in line.chunks_exact(bytes_per_pixel as usize) {
            pixels.push(decode(format, px));
        }
    }
    Ok(ImageF32 {
        width,
        height,
        pixels,
    })
}

/// Whether a texture like `key` (`name` in messages) can be read back,
/// before anything is rendered or allocated: its format is one
/// [`read_texture`] decodes, it can be copied from, and its buffer fits the
/// adapter's largest. Returns (bytes per pixel, bytes per padded row,
/// buffer bytes).
pub fn readback_layout(
    gpu: &GpuContext,
    key: &crate::texture_pool::TextureKey,
    name: &str,
) -> Result<(u32, u32, u64), RenderError> {
    let format = key.format;
    let bytes_per_pixel: u32 = match format {
        wgpu::TextureFormat::Rgba16Float | wgpu::TextureFormat::Rg32Uint => 8,
        wgpu::TextureFormat::Rgba32Float => 16,
        wgpu::TextureFormat::Rgba8Unorm
        | wgpu::TextureFormat::Rgba8UnormSrgb
        | wgpu::TextureFormat::Depth32Float
        | wgpu::TextureFormat::R32Float => 4,
        other => {
            return Err(RenderError::Readback(format!(
                "reading back {other:?} ({name}) is not supported"
            )));
        }
    };
    if !key.usage.contains(wgpu::TextureUsages::COPY_SRC) {
        return Err(RenderError::Readback(format!(
            "{name} was made without COPY_SRC, so it cannot be copied out"
        )));
    }
    // In u64: a row of a wide texture does not fit u32's arithmetic.
    let row = (u64::from(key.width) * u64::from(bytes_per_pixel))
        .next_multiple_of(u64::from(wgpu::COPY_BYTES_PER_ROW_ALIGNMENT));
    let size = row * u64::from(key.height);
    let max = gpu.device.limits().max_buffer_size;
    let Ok(row) = u32::try_from(row) else {
        return Err(RenderError::TooLarge {
            what: format!("a row of the readback of {name} ({row} bytes)"),
            limit: "bytes_per_row (u32)",
            max: u64::from(u32::MAX),
        });
    };
    if size > max {
        return Err(RenderError::TooLarge {
            what: format!(
                "the readback of {name} ({}x{} {format:?}: a {size}-byte buffer)",
                key.width, key.height
            ),
            limit: "max_buffer_size",
            max,
        });
    }
    Ok((bytes_per_pixel, row, size))
}

fn decode(format: wgpu::TextureFormat, px: &[u8]) -> [f32; 4] {
    let f16 = |i: usize| half::f16::from_le_bytes([px[i], px[i + 1]]).to_f32();
    let f32_at = |i: usize| f32::from_le_bytes([px[i], px[i + 1], px[i + 2], px[i + 3]]);
    let u32_at = |i: usize| u32::from_le_bytes([px[i], px[i + 1], px[i + 2], px[i + 3]]);
    match format {
        wgpu::TextureFormat::Rgba16Float => [f16(0), f16(2), f16(4), f16(6)],
        wgpu::TextureFormat::Rgba32Float => [f32_at(0), f32_at(4), f32_at(8), f32_at(12)],
        wgpu::TextureFormat::Rg32Uint => [u32_at(0) as f32, u32_at(4) as f32, 0.0, 1.0],
        wgpu::TextureFormat::Depth32Float | wgpu::TextureFormat::R32Float => {
            let d = f32_at(0);
            [d, d, d, 1.0]
        }
        wgpu::TextureFormat::Rgba8UnormSrgb => {
            let c = |v: u8| srgb_to_linear(f32::from(v) / 255.0);
            [c(px[0]), c(px[1]), c(px[2]), f32::from(px[3]) / 255.0]
        }
        _ => [0, 1, 2, 3].map(|i| f32::from(px[i]) / 255.0),
    }
}

pub fn srgb_to_linear(c: f32) -> f32 {
    if c <= 0.04045 {
        c / 12.92
    } else {
        ((c + 0.055) / 1.055).powf(2.4)
    }
}

pub fn linear_to_srgb(c: f32) -> f32 {
    let c = c.clamp(0.0, 1.0);
    if c <= 0.003_130_8 {
        c * 12.92
    } else {
        1.055 * c.powf(1.0 / 2.4) - 0.055
    }
}

/// Build a frame from `recipe`, render the textures named `names` at
/// `size`, and read them back, in order. Passes that fail are in the
/// report's `errors` (the rest of the frame still renders); an impossible
/// graph or a failed readback is an `Err`.
pub fn render_and_read(
    renderer: &crate::renderer::Renderer,
    recipe: &dyn crate::recipe::Recipe,
    size: (u32, u32),
    names: &[&str],
) -> Result<(crate::frame_graph::FrameReport, Vec<ImageF32>), RenderError> {
    let mut graph = crate::frame_graph::FrameGraph::new(size);
    recipe.declare(renderer, &mut graph);
    for name in names {
        graph.request(name);
    }
    let (report, outputs) = graph.execute(renderer)?;
    let images = names
        .iter()
        .map(|name| {
            let texture = outputs
                .get(*name)
                .ok_or_else(|| RenderError::Readback(format!("the frame produced no `{name}`")))?;
            read_texture(&renderer.gpu, texture)
        })
        .collect::<Result<_, _>>()?;
    Ok((report, images))
}
