//! Textures uploaded from images (normal maps, file textures, material
//! textures). 8-bit textures get their whole mip chain on upload
//! ([`mips`]), so samplers with a mip filter never alias.

pub mod mips;

use crate::context::GpuContext;

/// What an uploaded texture can be used for: sampled, written once, and
/// copied from, because a node may hand it straight to a sink that reads
/// it back (`FileTexture` into `Output`: without COPY_SRC the readback was
/// a wgpu validation error, a panic).
pub const UPLOADED: wgpu::TextureUsages = wgpu::TextureUsages::TEXTURE_BINDING
    .union(wgpu::TextureUsages::COPY_DST)
    .union(wgpu::TextureUsages::COPY_SRC);

#[derive(Debug)]
pub struct GpuTexture {
    pub texture: wgpu::Texture,
    pub view: wgpu::TextureView,
}

impl GpuTexture {
    /// Upload 8-bit RGBA pixels (row-major, top row first). `srgb` for colour
    /// data, linear for data such as normal maps.
    pub fn from_rgba8(
        gpu: &GpuContext,
        width: u32,
        height: u32,
        rgba8: &[u8],
        srgb: bool,
        label: &str,
    ) -> Self {
        // Missing pixels (short data) are opaque white, as they always were.
        let mut data = rgba8.to_vec();
        data.resize((width.max(1) * height.max(1) * 4) as usize, 255);
        Self::upload_rgba8(gpu, (width, height), &[data], srgb, label)
    }

    /// Upload layers of 8-bit RGBA pixels of one size as a 2D texture array
    /// (spots' projected textures, material textures). Short layers are
    /// padded with opaque white; no layers make one white layer.
    pub fn array_from_rgba8(
        gpu: &GpuContext,
        width: u32,
        height: u32,
        layers: &[Vec<u8>],
        srgb: bool,
        label: &str,
    ) -> Self {
        let layer_bytes = (width.max(1) * height.max(1) * 4) as usize;
        let mut data = Vec::with_capacity(layer_bytes * layers.len().max(1));
        for layer in layers {
            let start = data.len();
            data.extend_from_slice(&layer[..layer.len().min(layer_bytes)]);
            data.resize(start + layer_bytes, 255);
        }
        if layers.is_empty() {
            data.resize(layer_bytes, 255);
        }
        let layers: Vec<Vec<u8>> = data.chunks(layer_bytes).map(<[u8]>::to_vec).collect();
        Self::upload_rgba8(gpu, (width, height), &layers, srgb, label)
    }

    /// Layers of 8-bit RGBA of one size (each exactly width x height x 4
    /// bytes) with their mip chains, box-filtered in linear light.
    pub fn upload_rgba8(
        gpu: &GpuContext,
        (width, height): (u32, u32),
        layers: &[Vec<u8>],
        srgb: bool,
        label: &str,
    ) -> Self {
        let (width, height) = (width.max(1), height.max(1));
        let chains: Vec<Vec<mips::Level>> = layers
            .iter()
            .map(|l| mips::chain(width, height, l, srgb))
            .collect();
        let levels = mips::level_count(width, height);
        let size = wgpu::Extent3d {
            width,
            height,
            depth_or_array_layers: layers.len().max(1) as u32,
        };
        let texture = gpu.device.create_texture(&wgpu::TextureDescriptor {
            label: Some(label),
            size,
            mip_level_count: levels,
            sample_count: 1,
            dimension: wgpu::TextureDimension::D2,
            format: rgba8_format(srgb),
            usage: UPLOADED,
            view_formats: &[],
        });
        for (layer, chain) in chains.iter().enumerate() {
            for (level, mip) in chain.iter().enumerate() {
                gpu.queue.write_texture(
                    wgpu::TexelCopyTextureInfo {
                        texture: &texture,
                        mip_level: level as u32,
                        origin: wgpu::Origin3d {
                            x: 0,
                            y: 0,
                            z: layer as u32,
                        },
                        aspect: wgpu::TextureAspect::All,
                    },
                    &mip.rgba8,
                    wgpu::TexelCopyBufferLayout {
                        offset: 0,
                        bytes_per_row: Some(mip.width * 4),
                        rows_per_image: Some(mip.height),
                    },
                    wgpu::Extent3d {
                        width: mip.width,
                        height: mip.height,
                        depth_or_array_layers: 1,
                    },
                );
            }
        }
        let view = texture.create_view(&wgpu::TextureViewDescriptor {
            dimension: Some(if size.depth_or_array_layers > 1 {
                wgpu::TextureViewDimension::D2Array
            } else {
                wgpu::TextureViewDimension::D2
            }),
            ..Default::default()
        });
        GpuTexture { texture, view }
    }

    /// 8-bit RGBA pixels as a texture of one level: for pictures that change
    /// every frame (video), where the mip chain [`GpuTexture::from_rgba8`]
    /// computes on the CPU would cost more than the frame. A queue write: nothing waits.
    pub fn frame_rgba8(
        gpu: &GpuContext,
        (width, height): (u32, u32),
        rgba8: &[u8],
        srgb: bool,
        label: &str,
    ) -> Self {
        Self::upload(gpu, rgba8_format(srgb), 4, width, height, rgba8, label)
    }

    /// Upload linear RGBA 32-bit float pixels (HDR images, test frames).
    pub fn from_rgba32f(
        gpu: &GpuContext,
        width: u32,
        height: u32,
        pixels: &[[f32; 4]],
        label: &str,
    ) -> Self {
        let bytes: &[u8] = bytemuck::cast_slice(pixels);
        Self::upload(
            gpu,
            wgpu::TextureFormat::Rgba32Float,
            16,
            width,
            height,
            bytes,
            label,
        )
    }

    /// A sampled texture filled with `bytes`; short data is padded, long data cut, to the size.
    fn upload(
        gpu: &GpuContext,
        format: wgpu::TextureFormat,
        bytes_per_pixel: u32,
        width: u32,
        height: u32,
        bytes: &[u8],
        label: &str,
    ) -> Self {
        Self::upload_layers(
            gpu,
            format,
            bytes_per_pixel,
            (width, height, 1),
            bytes,
            label,
        )
    }

    /// `upload` for (width, height, layers): one layer is a plain 2D texture.
    fn upload_layers(
        gpu: &GpuContext,
        format: wgpu::TextureFormat,
        bytes_per_pixel: u32,
        (width, height, layers): (u32, u32, u32),
        bytes: &[u8],
        label: &str,
    ) -> Self {
        let size = wgpu::Extent3d {
            width: width.max(1),
            height: height.max(1),
            depth_or_array_layers: layers.max(1),
        };
        let texture = gpu.device.create_texture(&wgpu::TextureDescriptor {
            label: Some(label),
            size,
            mip_level_count: 1,
            sample_count: 1,
            dimension: wgpu::TextureDimension::D2,
            format,
            usage: UPLOADED,
            view_formats: &[],
        });
        let mut data = bytes.to_vec();
        data.resize(
            (size.width * size.height * size.depth_or_array_layers * bytes_per_pixel) as usize,
            0,
        );
        gpu.queue.write_texture(
            wgpu::TexelCopyTextureInfo {
                texture: &texture,
                mip_level: 0,
                origin: wgpu::Origin3d::ZERO,
                aspect: wgpu::TextureAspect::All,
            },
            &data,
            wgpu::TexelCopyBufferLayout {
                offset: 0,
                bytes_per_row: Some(size.width * bytes_per_pixel),
                rows_per_image: Some(size.height),
            },
            size,
        );
        // A one-layer texture views as D2; several as an array.
        let view = texture.create_view(&wgpu::TextureViewDescriptor {
            dimension: Some(if size.depth_or_array_layers > 1 {
                wgpu::TextureViewDimension::D2Array
            } else {
                wgpu::TextureViewDimension::D2
            }),
            ..Default::default()
        });
        GpuTexture { texture, view }
    }
}

/// 8-bit RGBA, with the sRGB transfer for colour or linear for data.
fn rgba8_format(srgb: bool) -> wgpu::TextureFormat {
    if srgb {
        wgpu::TextureFormat::Rgba8UnormSrgb
    } else {
        wgpu::TextureFormat::Rgba8Unorm
    }
}
