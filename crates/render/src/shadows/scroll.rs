//! Scrolling a sun cascade's map as the camera moves. A cascade's box is
//! snapped to its texel grid (views.rs), so a camera moving across the light
//! moves the box by whole texels: the map it had, shifted by those texels,
//! is the new map but for the strips the move uncovers. The kept part is
//! shifted into place (through a scratch layer: a layer cannot be moved
//! within itself where the two places overlap) and only the strips are
//! rasterized, clipped to them.
//! VSM's moments shift the same way; they are filtered again only where
//! their filter reaches a new strip or the map's border (where it clamps).

use crate::error::RenderError;
use crate::frame_graph::{Bindings, PassContext};
use crate::shaders::Permutation;
use crate::texture_pool::ViewSpec;

use super::scroll_key::ShadowScrollKey;

/// A rectangle of a map layer's texels (x right, y down).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(super) struct Rect {
    pub x: u32,
    pub y: u32,
    pub w: u32,
    pub h: u32,
}

impl Rect {
    /// The whole layer.
    pub fn full(resolution: u32) -> Rect {
        Rect {
            x: 0,
            y: 0,
            w: resolution,
            h: resolution,
        }
    }

    pub fn texels(&self) -> u64 {
        u64::from(self.w) * u64::from(self.h)
    }

    /// Grown by `by` texels on every side, within a map of `resolution`.
    pub fn grown(&self, by: u32, resolution: u32) -> Rect {
        let (x, y) = (self.x.saturating_sub(by), self.y.saturating_sub(by));
        let right = (self.x + self.w).saturating_add(by).min(resolution);
        let bottom = (self.y + self.h).saturating_add(by).min(resolution);
        Rect {
            x,
            y,
            w: right - x,
            h: bottom - y,
        }
    }

    pub fn is_empty(&self) -> bool {
        self.w == 0 || self.h == 0
    }

    /// Moved by `shift` texels (right, down) with the map it lies in, as
    /// [`shift_layer`] moves it, and cut to the map of `resolution`.
    pub fn shifted(self, (sx, sy): (i32, i32), resolution: u32) -> Rect {
        let r = i64::from(resolution);
        let x0 = (i64::from(self.x) + i64::from(sx)).clamp(0, r);
        let y0 = (i64::from(self.y) + i64::from(sy)).clamp(0, r);
        let x1 = (i64::from(self.x + self.w) + i64::from(sx)).clamp(0, r);
        let y1 = (i64::from(self.y + self.h) + i64::from(sy)).clamp(0, r);
        Rect {
            x: x0 as u32,
            y: y0 as u32,
            w: (x1 - x0) as u32,
            h: (y1 - y0) as u32,
        }
    }

    /// The smallest rectangle holding both (an empty one holds nothing).
    pub fn union(self, other: Rect) -> Rect {
        if self.is_empty() {
            return other;
        }
        if other.is_empty() {
            return self;
        }
        let (x, y) = (self.x.min(other.x), self.y.min(other.y));
        let right = (self.x + self.w).max(other.x + other.w);
        let bottom = (self.y + self.h).max(other.y + other.h);
        Rect {
            x,
            y,
            w: right - x,
            h: bottom - y,
        }
    }

    /// As the region uniform the resolve and moments shaders read
    /// (`Info.region`): origin and size.
    pub fn to_gpu(self) -> [u32; 4] {
        [self.x, self.y, self.w, self.h]
    }
}

/// The texels a map of `resolution` moved by `shift` (texels right, down)
/// no longer holds: a strip of columns the full height, and a strip of rows
/// across the rest (at most two rectangles, not overlapping).
pub(super) fn uncovered(resolution: u32, (sx, sy): (i32, i32)) -> Vec<Rect> {
    let (ax, ay) = (
        sx.unsigned_abs().min(resolution),
        sy.unsigned_abs().min(resolution),
    );
    let mut strips = Vec::new();
    if ax > 0 {
        strips.push(Rect {
            x: if sx > 0 { 0 } else { resolution - ax },
            y: 0,
            w: ax,
            h: resolution,
        });
    }
    if ay > 0 && ax < resolution {
        strips.push(Rect {
            x: if sx > 0 { ax } else { 0 },
            y: if sy > 0 { 0 } else { resolution - ay },
            w: resolution - ax,
            h: ay,
        });
    }
    strips
}

/// Where VSM's moments must be filtered again after a shift that uncovered
/// `strips`: wherever a `blur`-texel filter reaches a strip, and a band of
/// `blur` texels along each border (the filter clamps at the border, which
/// lies elsewhere in the world after the shift).
pub(super) fn moments_regions(resolution: u32, strips: &[Rect], blur: u32) -> Vec<Rect> {
    let mut regions: Vec<Rect> = strips.iter().map(|s| s.grown(blur, resolution)).collect();
    let b = blur.min(resolution);
    if b > 0 {
        regions.extend([
            Rect {
                x: 0,
                y: 0,
                w: resolution,
                h: b,
            },
            Rect {
                x: 0,
                y: resolution - b,
                w: resolution,
                h: b,
            },
            Rect {
                x: 0,
                y: 0,
                w: b,
                h: resolution,
            },
            Rect {
                x: resolution - b,
                y: 0,
                w: b,
                h: resolution,
            },
        ]);
    }
    regions
}

/// Move `layer` of `texture` by `shift` texels (right, down), through
/// `scratch` (one layer as large, of the same format, storage and sampled):
/// the kept part lands where the new view sees it; the uncovered strips
/// keep stale texels until they are drawn. Two dispatches of
/// `shadows/scroll.wgsl` (`moments`: the two-channel moments), reading
/// `uniform` (the shift and the layer's size, [`shift_uniform`]).
pub(super) fn shift_layer(
    cx: &mut PassContext<'_>,
    uniform: &wgpu::Buffer,
    (texture, scratch): (&wgpu::Texture, &wgpu::Texture),
    layer: u32,
    resolution: u32,
    moments: bool,
) -> Result<(), RenderError> {
    let key = ShadowScrollKey { moments }.key();
    let groups = (resolution.div_ceil(8), resolution.div_ceil(8), 1);
    let layer_view = cx.view_of(texture, ViewSpec::layer(layer));
    let scratch_view = cx.view_of(scratch, ViewSpec::layer(0));
    for (entry, source, target) in [
        ("to_scratch", &layer_view, &scratch_view),
        ("back", &scratch_view, &layer_view),
    ] {
        let b = Bindings::new()
            .buffer("shift", uniform)
            .view("source", source.clone())
            .view("destination", target.clone());
        cx.dispatch_shader("shadow scroll", &key, entry, b, groups)?;
    }
    Ok(())
}

/// What [`shift_layer`]'s shader reads: the shift (texels right, down) and
/// the layer's size (`Shift` in shadows/scroll.wgsl).
pub(super) fn shift_uniform((sx, sy): (i32, i32), resolution: u32) -> [u32; 4] {
    [sx as u32, sy as u32, resolution, resolution]
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_rectangle_moves_with_its_map_and_is_cut_to_it() {
        let r = Rect {
            x: 10,
            y: 20,
            w: 8,
            h: 6,
        };
        assert_eq!(
            r.shifted((3, -5), 64),
            Rect {
                x: 13,
                y: 15,
                w: 8,
                h: 6
            }
        );
        // Past the left edge, and past the bottom: cut.
        assert_eq!(
            r.shifted((-14, 40), 64),
            Rect {
                x: 0,
                y: 60,
                w: 4,
                h: 4
            }
        );
        assert!(r.shifted((100, 0), 64).is_empty());
    }

    #[test]
    fn two_rectangles_union_and_an_empty_one_adds_nothing() {
        let a = Rect {
            x: 2,
            y: 3,
            w: 4,
            h: 5,
        };
        let b = Rect {
            x: 10,
            y: 1,
            w: 2,
            h: 2,
        };
        assert_eq!(
            a.union(b),
            Rect {
                x: 2,
                y: 1,
                w: 10,
                h: 7
            }
        );
        let none = Rect {
            x: 50,
            y: 50,
            w: 0,
            h: 0,
        };
        assert_eq!(a.union(none), a);
        assert_eq!(none.union(b), b);
    }

    /// Every texel of the map is either kept (its old place, moved, is
    /// inside the map) or in exactly one uncovered strip.
    #[test]
    fn the_uncovered_strips_are_exactly_the_texels_a_shift_does_not_keep() {
        let res = 16;
        for shift in [
            (3, 0),
            (-3, 0),
            (0, 5),
            (0, -5),
            (2, -7),
            (-4, 4),
            (15, 15),
            (16, 0),
        ] {
            let strips = uncovered(res, shift);
            for y in 0..res {
                for x in 0..res {
                    let (ox, oy) = (x as i32 - shift.0, y as i32 - shift.1);
                    let kept = (0..res as i32).contains(&ox) && (0..res as i32).contains(&oy);
                    let inside = strips
                        .iter()
                        .filter(|s| (s.x..s.x + s.w).contains(&x) && (s.y..s.y + s.h).contains(&y))
                        .count();
                    assert_eq!(inside, usize::from(!kept), "{shift:?} at ({x}, {y})");
                }
            }
        }
        assert!(uncovered(res, (0, 0)).is_empty());
    }

    #[test]
    fn moments_are_filtered_again_near_new_strips_and_borders_only() {
        let strips = uncovered(64, (4, 0));
        let regions = moments_regions(64, &strips, 2);
        assert_eq!(
            regions[0],
            Rect {
                x: 0,
                y: 0,
                w: 6,
                h: 64
            }
        );
        let covered = |x: u32, y: u32| {
            regions
                .iter()
                .any(|r| (r.x..r.x + r.w).contains(&x) && (r.y..r.y + r.h).contains(&y))
        };
        assert!(covered(5, 30) && covered(62, 30) && covered(30, 1) && covered(30, 63));
        assert!(!covered(30, 30) && !covered(6, 30) && !covered(61, 2));
        // No blur: the strips alone.
        assert_eq!(moments_regions(64, &strips, 0), strips);
    }
}
