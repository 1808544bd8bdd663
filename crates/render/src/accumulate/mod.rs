//! Sub-frames summed on the GPU: `spreadlight render --samples N` averages
//! N renders of each frame (motion blur, anti-aliasing). Reading every
//! sub-frame back to add them up on the CPU costs N copies of the frame
//! over the bus and N decodings; an [`Accumulator`] instead adds each
//! sub-frame into a sum of 32-bit floats where it was rendered
//! (`shaders/accumulate/add.wgsl`), and the frame is read back once
//! ([`Accumulator::start_read`]), divided by N on the CPU.
//!
//! The sum is exactly the CPU's f32 sum of the images a readback of each
//! sub-frame would give, added in order: the shader decodes the texels as
//! `readback.rs` does (halves by their bits, 8-bit values through the same
//! table) and float additions are correctly rounded on every Vulkan, Metal
//! and D3D12 device. The division is the CPU's, in f64, rounded once.
//! Against the average in f64 that the CPU made before (`Average` in the
//! CLI), only the sum's rounding to f32 differs: a few units in the last
//! place of a 32-bit float (docs/sequences.md).

pub(crate) mod key;

use std::sync::OnceLock;

use crate::context::GpuContext;
use crate::error::RenderError;
use crate::readback::{ImageF32, PendingImage, Pixels, Readback, readback_layout, srgb_to_linear};
use crate::renderer::Renderer;
use crate::shaders::{Permutation, PipelineRef};
use crate::texture_pool::TextureKey;

pub use key::AccumulateKey;

/// The shader's name for each texture format it decodes (`FORMAT_*` in add.wgsl).
fn format_code(format: wgpu::TextureFormat) -> Option<u32> {
    use wgpu::TextureFormat as F;
    Some(match format {
        F::Rgba16Float => 0,
        F::Rgba32Float => 1,
        F::Rgba8UnormSrgb => 2,
        F::Rgba8Unorm => 3,
        F::Depth32Float | F::R32Float => 4,
        F::Rg32Uint => 5,
        _ => return None,
    })
}

/// The linear value of each 8-bit value, as sRGB (0..256) and as unorm
/// (256..512), computed as the readback decodes them.
fn byte_values() -> &'static [f32; 512] {
    static TABLE: OnceLock<[f32; 512]> = OnceLock::new();
    TABLE.get_or_init(|| {
        let mut table = [0.0; 512];
        for v in 0..256 {
            let unorm = v as f32 / 255.0;
            table[v] = srgb_to_linear(unorm);
            table[256 + v] = unorm;
        }
        table
    })
}

/// The sum of the sub-frames of one image (one `Output`), on the GPU. Made
/// for a texture's size and format; each frame starts a new sum.
pub struct Accumulator {
    width: u32,
    height: u32,
    format: wgpu::TextureFormat,
    /// Bytes per padded row of the texel copy.
    row: u32,
    /// One sub-frame's texels, copied as a readback copies them.
    texels: wgpu::Buffer,
    byte_values: wgpu::Buffer,
    params: wgpu::Buffer,
    /// RGBA 32-bit floats, tightly packed, top row first.
    sum: wgpu::Buffer,
    /// Sub-frames in the sum.
    count: u32,
}

impl Accumulator {
    /// An accumulator for textures like `key`, or `None` when one cannot
    /// be made on this device (a format the readback does not decode, or a
    /// sum past the largest storage buffer: an image over 8.3 million pixels
    /// on a device of WebGPU's default limit): the caller then reads each
    /// sub-frame back as before.
    pub fn new(gpu: &GpuContext, key: &TextureKey) -> Option<Accumulator> {
        let code = format_code(key.format)?;
        let (_, row, texel_bytes) = readback_layout(gpu, key, "the sub-frame").ok()?;
        let sum_bytes = u64::from(key.width) * u64::from(key.height) * 16;
        let limits = gpu.device.limits();
        let largest = limits
            .max_storage_buffer_binding_size
            .min(limits.max_buffer_size);
        if sum_bytes > largest || texel_bytes > largest {
            return None;
        }
        let device = &gpu.device;
        let made = gpu.scoped(|| {
            let buffer = |label: &str, size: u64, usage: wgpu::BufferUsages| {
                device.create_buffer(&wgpu::BufferDescriptor {
                    label: Some(label),
                    size,
                    usage,
                    mapped_at_creation: false,
                })
            };
            use wgpu::BufferUsages as U;
            let texels = buffer("accumulate texels", texel_bytes, U::STORAGE | U::COPY_DST);
            let sum = buffer(
                "accumulate sum",
                sum_bytes,
                U::STORAGE | U::COPY_SRC | U::COPY_DST,
            );
            let params = buffer("accumulate params", 16, U::UNIFORM | U::COPY_DST);
            let values = buffer("accumulate byte values", 512 * 4, U::STORAGE | U::COPY_DST);
            let words = [key.width, key.height, row / 4, code];
            gpu.queue
                .write_buffer(&params, 0, bytemuck::cast_slice(&words));
            gpu.queue
                .write_buffer(&values, 0, bytemuck::cast_slice(byte_values()));
            (texels, sum, params, values)
        });
        let (texels, sum, params, byte_values) = made.ok()?;
        Some(Accumulator {
            width: key.width,
            height: key.height,
            format: key.format,
            row,
            texels,
            byte_values,
            params,
            sum,
            count: 0,
        })
    }

    /// Whether `texture` is one this accumulator adds (its size and format).
    pub fn fits(&self, texture: &wgpu::Texture) -> bool {
        (texture.width(), texture.height(), texture.format())
            == (self.width, self.height, self.format)
    }

    /// The size of the images summed.
    pub fn size(&self) -> (u32, u32) {
        (self.width, self.height)
    }

    /// Sub-frames added since the sum began.
    pub fn count(&self) -> u32 {
        self.count
    }

    /// Forget the sum (a frame that failed half way): the next
    /// [`Accumulator::add`] begins a new one.
    pub fn restart(&mut self) {
        self.count = 0;
    }

    /// Add `texture` (mip 0, layer 0) into the sum, behind the work queued
    /// on the GPU so far; the first add of a frame starts from zero.
    pub fn add(&mut self, renderer: &Renderer, texture: &wgpu::Texture) -> Result<(), RenderError> {
        if !self.fits(texture) {
            return Err(RenderError::Readback(format!(
                "a sub-frame of {}x{} {:?} cannot be added to a sum of {}x{} {:?}",
                texture.width(),
                texture.height(),
                texture.format(),
                self.width,
                self.height,
                self.format
            )));
        }
        let gpu = &renderer.gpu;
        let device = &gpu.device;
        let key = AccumulateKey.key();
        let (pipeline, groups) = {
            let mut shaders = renderer.shaders();
            let pipeline = shaders.compute_pipeline(device, &key, "add")?;
            let groups = shaders.named_groups(
                device,
                &key,
                &["add"],
                &PipelineRef::Compute(pipeline.clone()),
                &[
                    ("params", self.params.as_entire_binding()),
                    ("texels", self.texels.as_entire_binding()),
                    ("byte_values", self.byte_values.as_entire_binding()),
                    ("sum", self.sum.as_entire_binding()),
                ],
                &[],
            )?;
            (pipeline, groups)
        };
        let aspect = if self.format == wgpu::TextureFormat::Depth32Float {
            wgpu::TextureAspect::DepthOnly
        } else {
            wgpu::TextureAspect::All
        };
        let commands = gpu
            .scoped(|| {
                let mut encoder = device.create_command_encoder(&wgpu::CommandEncoderDescriptor {
                    label: Some("accumulate"),
                });
                if self.count == 0 {
                    encoder.clear_buffer(&self.sum, 0, None);
                }
                encoder.copy_texture_to_buffer(
                    wgpu::TexelCopyTextureInfo {
                        texture,
                        mip_level: 0,
                        origin: wgpu::Origin3d::ZERO,
                        aspect,
                    },
                    wgpu::TexelCopyBufferInfo {
                        buffer: &self.texels,
                        layout: wgpu::TexelCopyBufferLayout {
                            offset: 0,
                            bytes_per_row: Some(self.row),
                            rows_per_image: Some(self.height),
                        },
                    },
                    wgpu::Extent3d {
                        width: self.width,
                        height: self.height,
                        depth_or_array_layers: 1,
                    },
                );
                {
                    let mut pass = encoder.begin_compute_pass(&wgpu::ComputePassDescriptor {
                        label: Some("accumulate add"),
                        timestamp_writes: None,
                    });
                    pass.set_pipeline(&pipeline);
                    for (i, group) in groups.iter().enumerate() {
                        pass.set_bind_group(i as u32, group, &[]);
                    }
                    pass.dispatch_workgroups(self.width.div_ceil(8), self.height.div_ceil(8), 1);
                }
                encoder.finish()
            })
            .map_err(|message| RenderError::Validation {
                pass: "accumulate".to_owned(),
                message,
            })?;
        gpu.submit([commands]);
        self.count += 1;
        Ok(())
    }

    /// Start copying the sum to the CPU, behind every add queued, and
    /// return at once; the next add begins a new sum (the copy is queued
    /// before it, so it is not disturbed).
    pub fn start_read(&mut self, gpu: &GpuContext) -> Result<PendingSum, RenderError> {
        let count = self.count;
        self.count = 0;
        if count == 0 {
            return Err(RenderError::Readback(
                "no sub-frame was added to the sum".to_owned(),
            ));
        }
        let size = self.sum.size();
        let device = &gpu.device;
        let (buffer, commands) = gpu
            .scoped(|| {
                let buffer = device.create_buffer(&wgpu::BufferDescriptor {
                    label: Some("accumulate readback"),
                    size,
                    usage: wgpu::BufferUsages::MAP_READ | wgpu::BufferUsages::COPY_DST,
                    mapped_at_creation: false,
                });
                let mut encoder = device.create_command_encoder(&Default::default());
                encoder.copy_buffer_to_buffer(&self.sum, 0, &buffer, 0, size);
                (buffer, encoder.finish())
            })
            .map_err(RenderError::Readback)?;
        let submission = gpu.submit([commands]);
        Ok(PendingSum {
            image: PendingImage::of_floats(
                device.clone(),
                buffer,
                submission,
                (self.width, self.height),
            ),
            count,
        })
    }
}

/// The sums of several images by name (each `Output`'s), made when a name
/// first adds and made anew when its texture changes size between frames.
#[derive(Default)]
pub struct Sums {
    sums: std::collections::BTreeMap<String, Accumulator>,
}

impl Sums {
    /// Add `texture` into the sum named `name`. Ok(false): the device
    /// cannot hold such a sum (see [`Accumulator::new`]); the caller reads
    /// the texture back instead.
    pub fn add(
        &mut self,
        name: &str,
        renderer: &Renderer,
        texture: &wgpu::Texture,
    ) -> Result<bool, RenderError> {
        match self
            .sums
            .get(name)
            .map(|sum| (sum.fits(texture), sum.count()))
        {
            Some((true, _)) => {}
            Some((false, count)) if count > 0 => {
                return Err(RenderError::Readback(
                    "its texture changed size or format between sub-frames".to_owned(),
                ));
            }
            _ => {
                let key = TextureKey {
                    format: texture.format(),
                    width: texture.width(),
                    height: texture.height(),
                    usage: texture.usage(),
                };
                match Accumulator::new(&renderer.gpu, &key) {
                    Some(sum) => {
                        self.sums.insert(name.to_owned(), sum);
                    }
                    None => {
                        self.sums.remove(name);
                        return Ok(false);
                    }
                }
            }
        }
        match self.sums.get_mut(name) {
            Some(sum) => sum.add(renderer, texture).map(|()| true),
            None => Ok(false),
        }
    }

    /// Images added into the sum named `name` since it began (0 for a name that has none).
    pub fn count(&self, name: &str) -> u32 {
        self.sums.get(name).map_or(0, Accumulator::count)
    }

    /// The size of the images the sum named `name` adds.
    pub fn size(&self, name: &str) -> Option<(u32, u32)> {
        self.sums.get(name).map(Accumulator::size)
    }

    /// Forget every sum begun (a frame that failed half way).
    pub fn restart(&mut self) {
        self.sums.values_mut().for_each(Accumulator::restart);
    }

    /// The sum named `name`, its copy to the CPU started, the next add
    /// beginning a new one; `None` when nothing was added to it.
    pub fn start_read(
        &mut self,
        name: &str,
        gpu: &GpuContext,
    ) -> Option<Result<PendingSum, RenderError>> {
        let sum = self.sums.get_mut(name).filter(|sum| sum.count() > 0)?;
        Some(sum.start_read(gpu))
    }
}

/// A frame's sum on its way to the CPU ([`Accumulator::start_read`]): it
/// can be waited for on another thread.
pub struct PendingSum {
    image: PendingImage,
    count: u32,
}

impl PendingSum {
    /// Sub-frames in the sum.
    pub fn count(&self) -> u32 {
        self.count
    }

    /// The size of the image.
    pub fn size(&self) -> (u32, u32) {
        self.image.size()
    }

    /// Wait for the copy and return the average: each float of the sum
    /// divided by the count, in f64, rounded to f32 once.
    pub fn wait(self) -> Result<ImageF32, RenderError> {
        Ok(self.wait_readback()?.pixels.into_f32())
    }

    /// [`PendingSum::wait`] with the time it took (the division counts as
    /// taking the rows out).
    pub fn wait_readback(self) -> Result<Readback, RenderError> {
        let n = f64::from(self.count.max(1));
        let read = self.image.wait_pixels()?;
        let started = std::time::Instant::now();
        let mut image = read.pixels.into_f32();
        for p in &mut image.pixels {
            *p = p.map(|v| (f64::from(v) / n) as f32);
        }
        Ok(Readback {
            pixels: Pixels::Float(image),
            waited: read.waited,
            copied: read.copied + started.elapsed(),
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn byte_values_are_the_readback_decoding() {
        let table = byte_values();
        assert_eq!(table[0], 0.0);
        assert_eq!(table[255], 1.0);
        assert_eq!(table[256 + 255], 1.0);
        assert_eq!(table[128], srgb_to_linear(128.0 / 255.0));
        assert_eq!(table[256 + 51], 0.2);
        assert_eq!(format_code(wgpu::TextureFormat::Bgra8Unorm), None);
    }
}
