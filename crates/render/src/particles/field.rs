//! A 3D vector field as a texture: a cube of `resolution`³ vectors, uploaded
//! once and sampled trilinearly by the simulation over the field's bounds.

use glam::Vec3;

use crate::error::RenderError;
use crate::renderer::Renderer;

/// An RGBA32F 3D texture holding the field (xyz, w unused).
#[derive(Debug)]
pub struct FieldTexture {
    pub texture: wgpu::Texture,
    pub view: wgpu::TextureView,
    pub resolution: u32,
}

impl FieldTexture {
    /// The field from `values`, x fastest then y then z. Non-finite values
    /// are kept: the simulation reads them as no force.
    pub fn new(renderer: &Renderer, resolution: u32, values: &[Vec3]) -> Result<Self, RenderError> {
        let n = resolution as usize;
        if resolution < 2 || values.len() != n * n * n {
            return Err(RenderError::Pass {
                pass: "particle field".to_owned(),
                message: format!(
                    "a field of resolution {resolution} needs {} vectors (at least 2 a side), got {}",
                    n * n * n,
                    values.len()
                ),
            });
        }
        let size = wgpu::Extent3d {
            width: resolution,
            height: resolution,
            depth_or_array_layers: resolution,
        };
        let texture = renderer
            .gpu
            .device
            .create_texture(&wgpu::TextureDescriptor {
                label: Some("particle field"),
                size,
                mip_level_count: 1,
                sample_count: 1,
                dimension: wgpu::TextureDimension::D3,
                format: wgpu::TextureFormat::Rgba32Float,
                usage: wgpu::TextureUsages::TEXTURE_BINDING | wgpu::TextureUsages::COPY_DST,
                view_formats: &[],
            });
        let texels: Vec<[f32; 4]> = values.iter().map(|v| [v.x, v.y, v.z, 0.0]).collect();
        renderer.gpu.queue.write_texture(
            texture.as_image_copy(),
            bytemuck::cast_slice(&texels),
            wgpu::TexelCopyBufferLayout {
                offset: 0,
                bytes_per_row: Some(resolution * 16),
                rows_per_image: Some(resolution),
            },
            size,
        );
        let view = texture.create_view(&Default::default());
        Ok(FieldTexture {
            texture,
            view,
            resolution,
        })
    }
}
