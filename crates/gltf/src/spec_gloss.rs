//! `KHR_materials_pbrSpecularGlossiness` converted to metallic-roughness on
//! load, the way the Khronos and Babylon.js converters do it: roughness is
//! 1 - glossiness; metallic is the root of the quadratic that makes a
//! metal-rough surface's perceived diffuse and specular brightness those of
//! the spec-gloss one; the base colour blends the colour the diffuse implies
//! (dielectric part) with the one the specular implies (metal part) by
//! metallic². With textures the conversion runs per texel (on the larger
//! image's grid, the other sampled nearest at the same relative place), so
//! a file's two maps become a base colour map and a metallic-roughness map.
//!
//! Its error: a spec-gloss surface has 3 + 3 + 1 free values per point, a
//! metal-rough one 3 + 1 + 1, so only surfaces that are physically either
//! (dielectric with f0 0.04, or metal with no diffuse) convert exactly; a
//! coloured dielectric specular or a grey specular over a coloured diffuse
//! comes back as the nearest blend. [`round_trip`] measures it (docs/gltf.md
//! gives the figures of the tests' sweep).

use std::sync::Arc;

use spreadlight_render::material::maps::MapImage;

/// glTF's f0 for dielectrics.
const DIELECTRIC_F0: f32 = 0.04;
const EPSILON: f32 = 1e-6;

/// A spec-gloss point: diffuse (rgba, linear), specular (rgb, linear), glossiness.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SpecGloss {
    pub diffuse: [f32; 4],
    pub specular: [f32; 3],
    pub glossiness: f32,
}

/// A metal-rough point: base colour (rgba, linear), metallic, roughness.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct MetalRough {
    pub base_color: [f32; 4],
    pub metallic: f32,
    pub roughness: f32,
}

fn perceived_brightness(c: [f32; 3]) -> f32 {
    (0.299 * c[0] * c[0] + 0.587 * c[1] * c[1] + 0.114 * c[2] * c[2]).sqrt()
}

/// The metallic whose metal-rough surface has the diffuse and specular
/// brightness given (0 for anything less specular than a dielectric).
fn solve_metallic(diffuse: f32, specular: f32, one_minus_specular_strength: f32) -> f32 {
    if specular < DIELECTRIC_F0 {
        return 0.0;
    }
    let a = DIELECTRIC_F0;
    let b = diffuse * one_minus_specular_strength / (1.0 - DIELECTRIC_F0) + specular
        - 2.0 * DIELECTRIC_F0;
    let c = DIELECTRIC_F0 - specular;
    let d = (b * b - 4.0 * a * c).max(0.0);
    ((-b + d.sqrt()) / (2.0 * a)).clamp(0.0, 1.0)
}

/// One point converted. Inputs outside 0..1 or not finite are clamped
/// first, so the result is always finite and in range.
pub fn convert(sg: SpecGloss) -> MetalRough {
    let unit = |v: f32| {
        if v.is_finite() {
            v.clamp(0.0, 1.0)
        } else {
            0.0
        }
    };
    let diffuse = [
        unit(sg.diffuse[0]),
        unit(sg.diffuse[1]),
        unit(sg.diffuse[2]),
    ];
    let specular = sg.specular.map(unit);
    let one_minus_specular_strength = 1.0 - specular.iter().fold(0.0f32, |a, &b| a.max(b));
    let metallic = solve_metallic(
        perceived_brightness(diffuse),
        perceived_brightness(specular),
        one_minus_specular_strength,
    );
    let from_diffuse = diffuse.map(|d| {
        d * (one_minus_specular_strength / (1.0 - DIELECTRIC_F0) / (1.0 - metallic).max(EPSILON))
    });
    let from_specular =
        specular.map(|s| (s - DIELECTRIC_F0 * (1.0 - metallic)) / metallic.max(EPSILON));
    let t = metallic * metallic;
    let [r, g, b] =
        [0, 1, 2].map(|i| unit(from_diffuse[i] + (from_specular[i] - from_diffuse[i]) * t));
    MetalRough {
        base_color: [r, g, b, unit(sg.diffuse[3])],
        metallic,
        roughness: 1.0 - unit(sg.glossiness),
    }
}

/// What a metal-rough point shades as, in spec-gloss terms: glTF's
/// diffuse colour (base x (1 - 0.04), none for metals) and f0.
pub fn round_trip(mr: MetalRough) -> ([f32; 3], [f32; 3]) {
    let m = mr.metallic;
    let diffuse = [0, 1, 2].map(|i| mr.base_color[i] * (1.0 - DIELECTRIC_F0) * (1.0 - m));
    let specular = [0, 1, 2].map(|i| DIELECTRIC_F0 + (mr.base_color[i] - DIELECTRIC_F0) * m);
    (diffuse, specular)
}

fn srgb_to_linear(c: u8) -> f32 {
    let c = f32::from(c) / 255.0;
    if c <= 0.04045 {
        c / 12.92
    } else {
        ((c + 0.055) / 1.055).powf(2.4)
    }
}

fn linear_to_srgb(c: f32) -> u8 {
    let c = c.clamp(0.0, 1.0);
    let s = if c <= 0.003_130_8 {
        c * 12.92
    } else {
        1.055 * c.powf(1.0 / 2.4) - 0.055
    };
    (s * 255.0 + 0.5) as u8
}

/// The texel of `image` nearest to relative place (u, v) in 0..1.
pub(super) fn nearest(image: &MapImage, u: f32, v: f32) -> [u8; 4] {
    let x = ((u * image.width as f32) as u32).min(image.width.saturating_sub(1));
    let y = ((v * image.height as f32) as u32).min(image.height.saturating_sub(1));
    let at = (y as usize * image.width as usize + x as usize) * 4;
    match image.rgba8.get(at..at + 4) {
        Some(t) => [t[0], t[1], t[2], t[3]],
        None => [255; 4],
    }
}

/// The two maps of a spec-gloss material, converted texel by texel: a base
/// colour map (sRGB, alpha = diffuse alpha) and a metallic-roughness map
/// (roughness in green, metallic in blue). `factors` scale the maps (glTF:
/// factor x texel); a missing map reads as white. The grid is the larger
/// map's.
pub fn convert_maps(
    factors: SpecGloss,
    diffuse: Option<&MapImage>,
    specular_glossiness: Option<&MapImage>,
) -> (Arc<MapImage>, Arc<MapImage>) {
    let size = |m: Option<&MapImage>| m.map_or((1, 1), |m| (m.width.max(1), m.height.max(1)));
    let (dw, dh) = size(diffuse);
    let (sw, sh) = size(specular_glossiness);
    let (width, height) = (dw.max(sw), dh.max(sh));
    let texels = width as usize * height as usize;
    let mut base = Vec::with_capacity(texels * 4);
    let mut metal_rough = Vec::with_capacity(texels * 4);
    for y in 0..height {
        for x in 0..width {
            let u = (x as f32 + 0.5) / width as f32;
            let v = (y as f32 + 0.5) / height as f32;
            let d = diffuse.map_or([255; 4], |m| nearest(m, u, v));
            let s = specular_glossiness.map_or([255; 4], |m| nearest(m, u, v));
            let point = SpecGloss {
                diffuse: [
                    factors.diffuse[0] * srgb_to_linear(d[0]),
                    factors.diffuse[1] * srgb_to_linear(d[1]),
                    factors.diffuse[2] * srgb_to_linear(d[2]),
                    factors.diffuse[3] * f32::from(d[3]) / 255.0,
                ],
                // The specular colour is sRGB-encoded, glossiness (alpha) linear.
                specular: [0, 1, 2].map(|i| factors.specular[i] * srgb_to_linear(s[i])),
                glossiness: factors.glossiness * f32::from(s[3]) / 255.0,
            };
            let mr = convert(point);
            base.extend([
                linear_to_srgb(mr.base_color[0]),
                linear_to_srgb(mr.base_color[1]),
                linear_to_srgb(mr.base_color[2]),
                (mr.base_color[3].clamp(0.0, 1.0) * 255.0 + 0.5) as u8,
            ]);
            let unorm = |v: f32| (v.clamp(0.0, 1.0) * 255.0 + 0.5) as u8;
            metal_rough.extend([0, unorm(mr.roughness), unorm(mr.metallic), 255]);
        }
    }
    let image = |rgba8| {
        Arc::new(MapImage {
            width,
            height,
            rgba8,
        })
    };
    (image(base), image(metal_rough))
}
