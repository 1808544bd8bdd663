//! `KHR_materials_transmission`'s map, drawn the way transmission is drawn
//! today (BLEND, opacity = alpha x (1 - transmission)): per texel, through
//! the base colour map's alpha, which the G-buffer resolve and the
//! Transparency pass already sample. So a window whose transmission map is
//! black at the frame and white in the pane is opaque at the frame and
//! clear in the pane, as the file says, with no new G-buffer slot.

use std::sync::Arc;

use spreadlight_render::material::maps::MapImage;

use super::spec_gloss::nearest;

/// The base colour map with its alpha times `1 - factor x transmission.r`
/// per texel (the extension: transmission = factor x red). A missing base
/// map reads as opaque white. The grid is the larger map's, the other
/// sampled nearest (as the spec-gloss conversion does); colour channels are
/// copied as stored (sRGB), alpha is linear in every format.
pub fn bake_opacity(
    base: Option<&MapImage>,
    transmission: &MapImage,
    factor: f32,
) -> Arc<MapImage> {
    let factor = if factor.is_finite() {
        factor.clamp(0.0, 1.0)
    } else {
        0.0
    };
    let size = |m: &MapImage| (m.width.max(1), m.height.max(1));
    let (tw, th) = size(transmission);
    let (bw, bh) = base.map_or((1, 1), size);
    let (width, height) = (tw.max(bw), th.max(bh));
    let mut rgba8 = Vec::with_capacity(width as usize * height as usize * 4);
    for y in 0..height {
        for x in 0..width {
            let u = (x as f32 + 0.5) / width as f32;
            let v = (y as f32 + 0.5) / height as f32;
            let [r, g, b, a] = base.map_or([255; 4], |m| nearest(m, u, v));
            let t = factor * f32::from(nearest(transmission, u, v)[0]) / 255.0;
            let alpha = f32::from(a) / 255.0 * (1.0 - t);
            rgba8.extend([r, g, b, (alpha.clamp(0.0, 1.0) * 255.0 + 0.5) as u8]);
        }
    }
    Arc::new(MapImage {
        width,
        height,
        rgba8,
    })
}
