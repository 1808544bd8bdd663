//! Resolution choices for the expensive screen-space passes (SSAO/HBAO,
//! SSGI's gather, SSR's trace, DOF's blur): a quality setting an artist
//! trades against accuracy, measured by `spreadlight accuracy ao|reflection|post`.
//!
//! At [`Resolution::Half`] the pass runs its shader's `HALF` permutation:
//! one thread per 2x2 block, computing exactly what the full pass computes
//! for the block's top-left pixel (same camera, same full-size inputs) and
//! writing it to a half-size texture. [`upsample`] then fills the full-size
//! target with a depth- and normal-aware bilinear mix of the half texels
//! around each pixel, falling back to the texel of the nearest depth
//! (shaders/resolution/upsample.wgsl). Because each half texel stands at a
//! known full pixel, the upsample compares real depths and normals rather
//! than a downsampled guess, and a quarter of the pixels come out exactly
//! as at full resolution.
//!
//! [`Resolution::Full`] changes nothing: the same shaders and passes as
//! before the setting existed, so full-resolution images are bit-identical.

use crate::error::RenderError;
use crate::frame_graph::{Bindings, FrameGraph, PassContext, SizeRule, Tex, TextureDesc};
use crate::gbuffer::GBuffer;
use crate::report::PassName;
use crate::shaders::Permutation;

pub use crate::resolution_key::UpsampleKey;

/// The shader feature of a pass's half-resolution permutation.
pub const HALF_FEATURE: &str = "HALF";

/// At which resolution an effect's expensive pass runs.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
pub enum Resolution {
    /// Every pixel: the reference.
    #[default]
    Full,
    /// One pixel in four, upsampled with depth awareness: about a quarter
    /// of the pass's cost, with the error `spreadlight accuracy` reports.
    Half,
}

impl Resolution {
    /// The pin's option names, in order.
    pub const NAMES: [&'static str; 2] = ["Full", "Half"];
    /// Every resolution, in the order of [`Resolution::NAMES`].
    pub const ALL: [Resolution; 2] = [Resolution::Full, Resolution::Half];

    pub fn name(self) -> &'static str {
        match self {
            Resolution::Full => "Full",
            Resolution::Half => "Half",
        }
    }

    /// Parse a pin or command-line value (case-insensitive).
    pub fn parse(name: &str) -> Option<Self> {
        match name.to_ascii_lowercase().as_str() {
            "full" => Some(Resolution::Full),
            "half" => Some(Resolution::Half),
            _ => None,
        }
    }

    pub fn is_half(self) -> bool {
        self == Resolution::Half
    }

    /// The shader feature the expensive pass takes (none at full resolution).
    pub fn feature(self) -> Option<&'static str> {
        self.is_half().then_some(HALF_FEATURE)
    }

    /// The pixels the expensive pass writes for a full size of `full`.
    pub fn pixels(self, full: (u32, u32)) -> (u32, u32) {
        match self {
            Resolution::Full => full,
            Resolution::Half => (full.0.div_ceil(2).max(1), full.1.div_ceil(2).max(1)),
        }
    }

    /// The size rule of the expensive pass's target, for a G-buffer of
    /// `full` pixels: exactly `pixels` (a relative half would round odd
    /// sizes the other way).
    pub fn size_rule(self, full_rule: SizeRule, full: (u32, u32)) -> SizeRule {
        match self {
            Resolution::Full => full_rule,
            Resolution::Half => {
                let (width, height) = self.pixels(full);
                SizeRule::Absolute { width, height }
            }
        }
    }

    /// A suffix for pass names, so the frame report says which resolution ran.
    pub fn pass_suffix(self) -> &'static str {
        match self {
            Resolution::Full => "",
            Resolution::Half => " (half)",
        }
    }
}

impl std::fmt::Display for Resolution {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(self.name())
    }
}

/// The full-size target's format.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum UpsampleFormat {
    /// R32Float (AO's raw visibility).
    R32,
    /// RGBA16Float (radiance).
    Rgba16,
}

impl UpsampleFormat {
    pub fn texture_format(self) -> wgpu::TextureFormat {
        match self {
            UpsampleFormat::R32 => wgpu::TextureFormat::R32Float,
            UpsampleFormat::Rgba16 => wgpu::TextureFormat::Rgba16Float,
        }
    }

    /// A full-size target of this format for a G-buffer of `size`.
    pub fn full(self, size: SizeRule) -> TextureDesc {
        TextureDesc::storage(self.texture_format()).size(size)
    }
}

/// What an upsample pass declared.
struct UpsampleIo {
    depth: Tex,
    normals: Tex,
    /// The half-size result.
    source: Tex,
    /// The full-size target.
    output: Tex,
    /// Depth of field: the full-size sharp image and the circle of
    /// confusion, so in-focus pixels keep their full-resolution detail.
    detail: Option<(Tex, Tex)>,
}

/// Record the depth-aware upsample of `io.source` into `io.output`.
fn upsample(
    cx: &mut PassContext<'_>,
    label: &str,
    gbuffer: &GBuffer,
    format: UpsampleFormat,
    io: &UpsampleIo,
) -> Result<(), RenderError> {
    // R32 is AO's; the detail is depth of field's, in RGBA16F.
    let key = match (format, io.detail) {
        (UpsampleFormat::R32, _) => UpsampleKey::R32,
        (UpsampleFormat::Rgba16, Some(_)) => UpsampleKey::Detail,
        (UpsampleFormat::Rgba16, None) => UpsampleKey::Rgba16,
    };
    let mut b = Bindings::new()
        .buffer("camera", gbuffer.camera_buffer())
        .texture("depth", io.depth)
        .texture("normals", io.normals)
        .texture("source", io.source)
        .texture("output", io.output);
    if let Some((image, coc)) = io.detail {
        b = b.texture("image", image).texture("coc", coc);
    }
    let size = gbuffer.pixel_size(cx.output_size);
    cx.dispatch_image(label, &key.key(), b, size)
}

/// Where a pass at `resolution` writes the estimate whose full-size target
/// is `full`: `full` itself, or at Half its half-size twin, which
/// [`declare_upsample`] turns into `full`.
pub fn written_target(full: &str, resolution: Resolution) -> String {
    if resolution.is_half() {
        format!("{full} half")
    } else {
        full.to_owned()
    }
}

/// A half-resolution estimate's way back to full size: the pass name, the
/// full-size target and its description, and the statistic that counts it.
pub struct UpsamplePass<'s, 'g> {
    pub name: PassName,
    pub owner: Option<u32>,
    pub gbuffer: &'g GBuffer,
    /// The half-size estimate (by convention [`written_target`] of `full`).
    pub half: &'s str,
    pub full: &'s str,
    pub desc: TextureDesc,
    pub format: UpsampleFormat,
    pub counter: &'static str,
    /// The dispatch's debug label.
    pub label: &'static str,
    /// Depth of field: the full-size sharp image and the circle of confusion
    /// (frame-graph names), so in-focus pixels keep their full-resolution detail.
    pub detail: Option<(&'s str, &'s str)>,
}

/// At Half, declare the depth-aware upsample of `half` into `full`
/// (nothing at Full, where the pass wrote `full` itself).
pub fn declare_upsample<'a>(
    fg: &mut FrameGraph<'a>,
    resolution: Resolution,
    u: UpsamplePass<'_, 'a>,
) {
    if !resolution.is_half() {
        return;
    }
    let g = &u.gbuffer.targets;
    let mut pass = fg.pass(u.name, u.owner);
    let io = UpsampleIo {
        source: pass.read(u.half),
        depth: pass.read(&g.depth),
        normals: pass.read(&g.normals),
        detail: u
            .detail
            .map(|(image, coc)| (pass.read(image), pass.read(coc))),
        output: pass.write(u.full, u.desc),
    };
    let (gbuffer, format, counter, label) = (u.gbuffer, u.format, u.counter, u.label);
    pass.run(move |cx| {
        cx.count(counter, 1);
        upsample(cx, label, gbuffer, format, &io)
    });
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn half_covers_odd_sizes_and_full_is_unchanged() {
        assert_eq!(Resolution::Half.pixels((1921, 1081)), (961, 541));
        assert_eq!(Resolution::Half.pixels((1, 1)), (1, 1));
        assert_eq!(Resolution::Full.pixels((7, 5)), (7, 5));
        assert_eq!(
            Resolution::Full.size_rule(SizeRule::Relative(1.0), (7, 5)),
            SizeRule::Relative(1.0)
        );
        assert_eq!(
            Resolution::Half.size_rule(SizeRule::Relative(1.0), (7, 5)),
            SizeRule::Absolute {
                width: 4,
                height: 3
            }
        );
    }

    #[test]
    fn names_round_trip() {
        for r in [Resolution::Full, Resolution::Half] {
            assert_eq!(Resolution::parse(r.name()), Some(r));
        }
        assert_eq!(Resolution::parse("HALF"), Some(Resolution::Half));
        assert_eq!(Resolution::parse("quarter"), None);
        assert_eq!(Resolution::default(), Resolution::Full);
    }
}
