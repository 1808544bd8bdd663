//! glTF materials on the CPU: what the G-buffer resolve
//! (`shaders/gbuffer/resolve.wgsl` with `shaders/lib/material_maps.wgsl`)
//! computes at a surface point, with every map point-sampled (the nearest
//! texel of the full-size image, no mips). Factors times maps as glTF
//! says: base colour = factor x texture x COLOR_0, roughness = factor x
//! green, metallic = factor x blue; each map on its UV set (`texCoord`),
//! through its `KHR_texture_transform` and wrap modes; colour maps decoded
//! from sRGB. `spreadlight accuracy gltf` shades these with the CPU
//! Cook-Torrance (`spreadlight_reference::material::shade_sun`) as the
//! reference of the GPU's image. It stays beside the imported material's
//! types, which the pure reference crate does not know.

use glam::{Vec3, Vec4};
use spreadlight_reference::material::SurfaceSample;

use spreadlight_render::material::maps::Wrap;
use spreadlight_render::readback::srgb_to_linear;

use crate::{MaterialData, TextureData};

fn wrap(t: f32, mode: Wrap) -> f32 {
    match mode {
        Wrap::Repeat => t - t.floor(),
        Wrap::Clamp => t.clamp(0.0, 1.0),
        // 1 - |t mod 2 - 1|: the shader's map_wrap.
        Wrap::Mirror => 1.0 - (t - 2.0 * (t * 0.5).floor() - 1.0).abs(),
    }
}

/// The texel of `texture` nearest to the point with UV sets `uvs` (0 and
/// 1), as linear RGBA: the transform applied, wrapped, then the texel
/// whose square holds it (as a nearest sampler at mip 0 picks).
pub fn point_sample(texture: &TextureData, uvs: [[f32; 2]; 2]) -> Vec4 {
    let uv = uvs[usize::from(texture.tex_coord == 1)];
    let [u, v] = texture.transform.apply(uv);
    let image = &texture.image;
    let (w, h) = (image.width.max(1), image.height.max(1));
    let texel = |t: f32, mode: Wrap, n: u32| ((wrap(t, mode) * n as f32).floor() as u32).min(n - 1);
    let (x, y) = (texel(u, texture.wrap[0], w), texel(v, texture.wrap[1], h));
    let at = ((y * w + x) * 4) as usize;
    let byte = |k: usize| f32::from(image.rgba8.get(at + k).copied().unwrap_or(255)) / 255.0;
    let decode = |c: f32| if texture.srgb { srgb_to_linear(c) } else { c };
    Vec4::new(decode(byte(0)), decode(byte(1)), decode(byte(2)), byte(3))
}

/// `material` at a point with UV sets `uvs` and vertex colour `color`
/// (white without COLOR_0).
pub fn sample_material(material: &MaterialData, uvs: [[f32; 2]; 2], color: Vec4) -> SurfaceSample {
    let map = |t: &Option<TextureData>| t.as_ref().map_or(Vec4::ONE, |t| point_sample(t, uvs));
    let base = Vec4::from(material.base_color) * map(&material.base_color_texture) * color;
    let mr = map(&material.metallic_roughness_texture);
    SurfaceSample {
        albedo: base.truncate().max(Vec3::ZERO),
        alpha: base.w,
        roughness: (material.roughness * mr.y).clamp(0.0, 1.0),
        metallic: (material.metallic * mr.z).clamp(0.0, 1.0),
    }
}

#[cfg(test)]
mod tests {
    use std::sync::Arc;

    use super::*;
    use spreadlight_render::material::maps::{MapImage, UvTransform};

    fn texture(srgb: bool, tex_coord: u32) -> TextureData {
        // 2 x 2: 0, 64 / 128, 255 in every channel.
        let values = [0u8, 64, 128, 255];
        TextureData {
            image: Arc::new(MapImage {
                width: 2,
                height: 2,
                rgba8: values.iter().flat_map(|&v| [v, v, v, 255]).collect(),
            }),
            srgb,
            tex_coord,
            transform: UvTransform::default(),
            wrap: [Wrap::Repeat; 2],
            nearest: true,
        }
    }

    #[test]
    fn the_nearest_texel_of_the_named_uv_set_wrapped() {
        let t = texture(false, 0);
        let at = |uv: [f32; 2]| point_sample(&t, [uv, [0.0; 2]]).x;
        assert_eq!(at([0.25, 0.25]), 0.0);
        assert_eq!(at([0.75, 0.25]), 64.0 / 255.0);
        assert_eq!(at([0.25, 0.75]), 128.0 / 255.0);
        // Repeat: 1.75 is 0.75; -0.25 is 0.75.
        assert_eq!(at([1.75, -0.25]), 1.0);
        let second = texture(false, 1);
        assert_eq!(point_sample(&second, [[0.25; 2], [0.75; 2]]).x, 1.0);
        let mut clamped = texture(false, 0);
        clamped.wrap = [Wrap::Clamp; 2];
        assert_eq!(
            point_sample(&clamped, [[5.0, -3.0], [0.0; 2]]).x,
            64.0 / 255.0
        );
        let mut mirrored = texture(false, 0);
        mirrored.wrap = [Wrap::Mirror; 2];
        // 1.25 mirrors to 0.75.
        assert_eq!(
            point_sample(&mirrored, [[1.25, 0.25], [0.0; 2]]).x,
            64.0 / 255.0
        );
    }

    #[test]
    fn colour_maps_decode_srgb_and_factors_multiply() {
        let t = texture(true, 0);
        let s = point_sample(&t, [[0.75, 0.25], [0.0; 2]]);
        assert!((s.x - srgb_to_linear(64.0 / 255.0)).abs() < 1e-6);
        let material = MaterialData {
            base_color: [0.5, 1.0, 1.0, 1.0],
            base_color_texture: Some(texture(true, 0)),
            metallic_roughness_texture: Some(texture(false, 0)),
            roughness: 0.5,
            metallic: 1.0,
            ..Default::default()
        };
        let m = sample_material(
            &material,
            [[0.25, 0.75], [0.0; 2]],
            Vec4::new(1.0, 0.5, 1.0, 0.25),
        );
        let texel = srgb_to_linear(128.0 / 255.0);
        assert!((m.albedo - Vec3::new(0.5 * texel, 0.5 * texel, texel)).length() < 1e-6);
        assert_eq!(m.alpha, 0.25);
        assert!((m.roughness - 0.5 * 128.0 / 255.0).abs() < 1e-6);
        assert!((m.metallic - 128.0 / 255.0).abs() < 1e-6);
    }
}
