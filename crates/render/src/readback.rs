//! Reading textures back to the CPU: for `Output`, tests and the CLI.

use half::slice::HalfFloatSliceExt;

use crate::context::GpuContext;
use crate::error::RenderError;

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

    /// This image stretched to `size` with bilinear filtering, as a GPU
    /// sampler with clamp-to-edge addressing reads a texture drawn over a
    /// target of `size` (texel centres at half-integers): what `Output`
    /// hands on when its texture is not at the output size (a 1x1
    /// luminance, a half-resolution buffer), so every host gets an image of
    /// the size it asked for. The same size returns a copy.
    pub fn resized(&self, size: (u32, u32)) -> ImageF32 {
        let (width, height) = (size.0.max(1), size.1.max(1));
        if (width, height) == (self.width, self.height) || self.pixels.is_empty() {
            return ImageF32 {
                width,
                height,
                pixels: if self.pixels.is_empty() {
                    vec![[0.0; 4]; (width * height) as usize]
                } else {
                    self.pixels.clone()
                },
            };
        }
        // Where destination texel `i` of `to` samples a source of `from`
        // texels: the two neighbours and the weight of the second.
        let taps = |i: u32, from: u32, to: u32| {
            let at =
                ((i as f32 + 0.5) * from as f32 / to as f32 - 0.5).clamp(0.0, (from - 1) as f32);
            let first = at.floor() as u32;
            (first, (first + 1).min(from - 1), at - first as f32)
        };
        let xs: Vec<_> = (0..width).map(|x| taps(x, self.width, width)).collect();
        let mut pixels = Vec::with_capacity((width * height) as usize);
        for y in 0..height {
            let (y0, y1, ty) = taps(y, self.height, height);
            for &(x0, x1, tx) in &xs {
                let lerp = |a: [f32; 4], b: [f32; 4], t: f32| {
                    [0, 1, 2, 3].map(|c| a[c] + (b[c] - a[c]) * t)
                };
                let top = lerp(self.pixel(x0, y0), self.pixel(x1, y0), tx);
                let bottom = lerp(self.pixel(x0, y1), self.pixel(x1, y1), tx);
                pixels.push(lerp(top, bottom, ty));
            }
        }
        ImageF32 {
            width,
            height,
            pixels,
        }
    }
}

/// A texture's RGBA half floats as it held them, top row first: what a
/// `Rgba16Float` target reads back as before anything decodes it, so a
/// host that writes halves (a half-float EXR) or maps them through a table
/// (8-bit PNG) skips the round trip through 32-bit floats.
#[derive(Clone, Debug, PartialEq)]
pub struct ImageF16 {
    pub width: u32,
    pub height: u32,
    /// `width * height * 4` halves: R, G, B, A of each pixel.
    pub values: Vec<half::f16>,
}

impl ImageF16 {
    /// The same image as 32-bit floats: each half widened exactly, what
    /// [`read_texture`] returns for the texture.
    pub fn to_f32(&self) -> ImageF32 {
        let mut floats = vec![0.0f32; self.values.len()];
        // A slice at a time: F16C where the CPU has it (the values are those of `to_f32`).
        self.values.convert_to_f32_slice(&mut floats);
        ImageF32 {
            width: self.width,
            height: self.height,
            pixels: floats
                .chunks_exact(4)
                .map(|p| [p[0], p[1], p[2], p[3]])
                .collect(),
        }
    }
}

/// An image read back: half floats when the texture held them, else
/// decoded to 32-bit floats ([`PendingImage::wait_pixels`]).
#[derive(Clone, Debug, PartialEq)]
pub enum Pixels {
    Half(ImageF16),
    Float(ImageF32),
}

impl Pixels {
    pub fn size(&self) -> (u32, u32) {
        match self {
            Pixels::Half(image) => (image.width, image.height),
            Pixels::Float(image) => (image.width, image.height),
        }
    }

    /// As 32-bit floats (halves widened exactly).
    pub fn into_f32(self) -> ImageF32 {
        match self {
            Pixels::Half(image) => image.to_f32(),
            Pixels::Float(image) => image,
        }
    }
}

/// What [`PendingImage::wait_pixels`] hands back: the pixels, and where the
/// wait went (`render --json`'s per-stage times).
pub struct Readback {
    pub pixels: Pixels,
    /// Blocked until the GPU had made the copy and the buffer was mapped.
    pub waited: std::time::Duration,
    /// Taking the rows out of the mapped buffer (and decoding them).
    pub copied: std::time::Duration,
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
    start_read_texture_layer(gpu, texture, layer, mip)?.wait()
}

/// Start copying `texture` (mip 0) to the CPU and return at once: the copy
/// is submitted behind the work already queued, and [`PendingImage::wait`]
/// takes the pixels when the GPU has got there. What lets a host keep
/// several frames in flight (`spreadlight render` sequences): the renderer
/// goes on with the next frame while this one is copied, and the wait and
/// the decoding run on another thread.
pub fn start_read_texture(
    gpu: &GpuContext,
    texture: &wgpu::Texture,
) -> Result<PendingImage, RenderError> {
    start_read_texture_layer(gpu, texture, 0, 0)
}

/// [`start_read_texture`] of one array layer (a cube face) at one mip.
pub fn start_read_texture_layer(
    gpu: &GpuContext,
    texture: &wgpu::Texture,
    layer: u32,
    mip: u32,
) -> Result<PendingImage, RenderError> {
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
    let submission = gpu.submit([commands]);
    Ok(PendingImage {
        device: gpu.device.clone(),
        buffer,
        submission,
        format,
        width,
        height,
        row,
        bytes_per_pixel,
        size,
    })
}

/// A texture's copy on its way to the CPU ([`start_read_texture`]). It
/// can be sent to another thread and waited for there; dropped unwaited,
/// the copy is simply thrown away.
pub struct PendingImage {
    device: wgpu::Device,
    buffer: wgpu::Buffer,
    submission: wgpu::SubmissionIndex,
    format: wgpu::TextureFormat,
    width: u32,
    height: u32,
    /// Bytes per padded row of the buffer.
    row: u32,
    bytes_per_pixel: u32,
    size: u64,
}

impl PendingImage {
    /// A copy of tightly packed RGBA 32-bit floats on its way into
    /// `buffer` (mappable for reading) by `submission`: how the
    /// accumulator (`accumulate/`) hands on its sum.
    pub(crate) fn of_floats(
        device: wgpu::Device,
        buffer: wgpu::Buffer,
        submission: wgpu::SubmissionIndex,
        (width, height): (u32, u32),
    ) -> Self {
        PendingImage {
            device,
            buffer,
            submission,
            format: wgpu::TextureFormat::Rgba32Float,
            width,
            height,
            row: width * 16,
            bytes_per_pixel: 16,
            size: u64::from(width) * u64::from(height) * 16,
        }
    }

    /// The size of the texture being copied.
    pub fn size(&self) -> (u32, u32) {
        (self.width, self.height)
    }

    /// Block until the GPU has made the copy (waiting for its own
    /// submission, not for frames queued after it), then decode it as
    /// [`read_texture`] does.
    pub fn wait(self) -> Result<ImageF32, RenderError> {
        Ok(self.wait_pixels()?.pixels.into_f32())
    }

    /// [`PendingImage::wait`], with a `Rgba16Float` texture's halves left
    /// as they are (the same values, not yet widened), and the time the
    /// wait and the copy took.
    pub fn wait_pixels(self) -> Result<Readback, RenderError> {
        let started = std::time::Instant::now();
        let slice = self.buffer.slice(0..self.size);
        let (tx, rx) = std::sync::mpsc::channel();
        slice.map_async(wgpu::MapMode::Read, move |r| {
            let _ = tx.send(r);
        });
        self.device
            .poll(wgpu::PollType::Wait {
                submission_index: Some(self.submission.clone()),
                timeout: None,
            })
            .map_err(|e| RenderError::Readback(e.to_string()))?;
        // Another thread's poll may be the one that runs the callback: wait for it either way.
        rx.recv()
            .map_err(|e| RenderError::Readback(e.to_string()))?
            .map_err(|e| RenderError::Readback(e.to_string()))?;
        let mapped = std::time::Instant::now();
        let pixels = {
            let data = slice
                .get_mapped_range()
                .map_err(|e| RenderError::Readback(e.to_string()))?;
            let size = (self.width, self.height);
            if self.format == wgpu::TextureFormat::Rgba16Float {
                Pixels::Half(ImageF16 {
                    width: self.width,
                    height: self.height,
                    values: halves(&data, size, self.row),
                })
            } else {
                Pixels::Float(ImageF32 {
                    width: self.width,
                    height: self.height,
                    pixels: decode_rows(self.format, &data, size, self.row, self.bytes_per_pixel),
                })
            }
        };
        self.buffer.unmap();
        Ok(Readback {
            pixels,
            waited: mapped - started,
            copied: mapped.elapsed(),
        })
    }
}

/// The halves of a buffer of padded `Rgba16Float` rows, top row first.
fn halves(data: &[u8], (width, height): (u32, u32), row: u32) -> Vec<half::f16> {
    let line = width as usize * 4;
    let mut values = Vec::with_capacity(line * height as usize);
    for y in 0..height as usize {
        let start = y * row as usize;
        values.extend(
            data[start..start + line * 2]
                .chunks_exact(2)
                .map(|b| half::f16::from_le_bytes([b[0], b[1]])),
        );
    }
    values
}

/// The pixels of a buffer of padded rows, top row first.
fn decode_rows(
    format: wgpu::TextureFormat,
    data: &[u8],
    (width, height): (u32, u32),
    row: u32,
    bytes_per_pixel: u32,
) -> Vec<[f32; 4]> {
    let mut pixels = Vec::with_capacity(width as usize * height as usize);
    for y in 0..height as usize {
        let start = y * row as usize;
        let line = &data[start..start + width as usize * bytes_per_pixel as usize];
        for px in line.chunks_exact(bytes_per_pixel as usize) {
            pixels.push(decode(format, px));
        }
    }
    pixels
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

#[cfg(test)]
mod tests {
    use super::*;

    fn image(width: u32, height: u32, values: &[f32]) -> ImageF32 {
        ImageF32 {
            width,
            height,
            pixels: values.iter().map(|&v| [v, v, v, 1.0]).collect(),
        }
    }

    fn reds(image: &ImageF32) -> Vec<f32> {
        image.pixels.iter().map(|p| p[0]).collect()
    }

    #[test]
    fn stretching_samples_texel_centres_with_clamped_edges() {
        // 2 texels over 4: centres at 0.5, 1.5, 2.5, 3.5 of the target fall at
        // -0.25 (clamped to 0), 0.25, 0.75 and 1.25 (clamped to 1) source texels.
        let wide = image(2, 1, &[0.0, 1.0]).resized((4, 1));
        assert_eq!((wide.width, wide.height), (4, 1));
        assert_eq!(reds(&wide), [0.0, 0.25, 0.75, 1.0]);
        // One texel is a constant of any size.
        let flat = image(1, 1, &[0.3]).resized((3, 2));
        assert_eq!(reds(&flat), [0.3; 6]);
        // 4 texels over 2 (a shrink): each target texel lands between two sources.
        let narrow = image(4, 1, &[0.0, 1.0, 3.0, 7.0]).resized((2, 1));
        assert_eq!(reds(&narrow), [0.5, 5.0]);
        // Vertical too: 1x2 over 1x4.
        let tall = image(1, 2, &[2.0, 6.0]).resized((1, 4));
        assert_eq!(reds(&tall), [2.0, 3.0, 5.0, 6.0]);
        let same = image(2, 1, &[0.0, 1.0]);
        assert_eq!(same.resized((2, 1)), same);
    }
}
