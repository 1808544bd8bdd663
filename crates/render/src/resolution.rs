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
//! AO and SSGI keep the rest of their chain at half size too (the temporal
//! blend and both depth-aware blur passes, each half texel reading the full
//! G-buffer at its own pixel and tapping every second full pixel), and
//! upsample once at the end, where the upsample also does what their last
//! blur pass did at full size (AO's grey RGBA output and `COMBINE`, SSGI's
//! ambient): see [`UpsampleKey`]'s `Ao`, `AoCombine` and `Ambient`.
//!
//! [`Resolution::Full`] changes nothing: the same shaders and passes as
//! before the setting existed, so full-resolution images are bit-identical.
//!
//! [`Resolution::Auto`] (the pins' default) is Half for frames of at least
//! [`AUTO_HALF_FROM_PIXELS`] pixels and Full below; each effect resolves it
//! when it declares its passes ([`Resolution::resolve`]), and
//! [`AUTO_VAR`] forces what it resolves to.

use crate::error::RenderError;
use crate::frame_graph::{Bindings, FrameGraph, PassContext, SizeRule, Tex, TextureDesc};
use crate::gbuffer::GBuffer;
use crate::renderer::Renderer;
use crate::report::PassName;
use crate::shaders::Permutation;

pub use crate::resolution_key::UpsampleKey;

use std::sync::atomic::{AtomicU8, Ordering};

/// The shader feature of a pass's half-resolution permutation.
pub const HALF_FEATURE: &str = "HALF";

/// The frame size (pixels of the G-buffer) from which [`Resolution::Auto`]
/// is Half. 1920x1080: on the H200 the half chain saves most at 1080p and
/// above, where the AO/SSGI family is about 1.0 ms of post.ron's 2.4, and
/// its error (docs/indirect-light.md#half-resolution) is smallest relative
/// to a pixel's size; below it the passes are cheap and a small image shows
/// the half grid's softening more.
pub const AUTO_HALF_FROM_PIXELS: u64 = 1920 * 1080;

/// The environment variable that forces what [`Resolution::Auto`] resolves
/// to: `full`, `half`, or `size` (the rule, [`AUTO_HALF_FROM_PIXELS`]).
pub const AUTO_VAR: &str = "SPREADLIGHT_RESOLUTION_AUTO";

/// Statistic: effects whose Resolution Auto resolved to Half this frame.
pub const AUTO_HALF: &str = "Resolution Auto ran at Half";
/// Statistic: effects whose Resolution Auto resolved to Full this frame.
pub const AUTO_FULL: &str = "Resolution Auto ran at Full";

/// At which resolution an effect's expensive pass runs.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
pub enum Resolution {
    /// Half at [`AUTO_HALF_FROM_PIXELS`] pixels and above, Full below
    /// ([`Resolution::resolve`]; [`AUTO_VAR`] forces it).
    #[default]
    Auto,
    /// Every pixel: the reference.
    Full,
    /// One pixel in four, upsampled with depth awareness: about a quarter
    /// of the pass's cost, with the error `spreadlight accuracy` reports.
    Half,
}

impl Resolution {
    /// The pin's option names, in order.
    pub const NAMES: [&'static str; 3] = ["Auto", "Full", "Half"];
    /// Every resolution, in the order of [`Resolution::NAMES`].
    pub const ALL: [Resolution; 3] = [Resolution::Auto, Resolution::Full, Resolution::Half];
    /// The two an effect runs at (what [`Resolution::resolve`] returns).
    pub const RESOLVED: [Resolution; 2] = [Resolution::Full, Resolution::Half];

    pub fn name(self) -> &'static str {
        match self {
            Resolution::Auto => "Auto",
            Resolution::Full => "Full",
            Resolution::Half => "Half",
        }
    }

    /// Parse a pin or command-line value (case-insensitive).
    pub fn parse(name: &str) -> Option<Self> {
        match name.to_ascii_lowercase().as_str() {
            "auto" => Some(Resolution::Auto),
            "full" => Some(Resolution::Full),
            "half" => Some(Resolution::Half),
            _ => None,
        }
    }

    /// What an effect runs at for a G-buffer of `pixels`: Full or Half as
    /// set, and Auto as `renderer`'s [`AutoChoice`] says (by default the
    /// size rule).
    pub fn resolve(self, renderer: &Renderer, pixels: (u32, u32)) -> Resolution {
        match self {
            Resolution::Auto => auto_choice(renderer).resolve(pixels),
            set => set,
        }
    }

    /// [`Resolution::resolve`] for an effect declaring its passes into
    /// `fg`, counting what Auto resolved to ([`AUTO_HALF`], [`AUTO_FULL`]),
    /// so `stats` and `bench --json` say it.
    pub fn resolve_in(
        self,
        renderer: &Renderer,
        fg: &mut FrameGraph<'_>,
        pixels: (u32, u32),
    ) -> Resolution {
        let resolved = self.resolve(renderer, pixels);
        if self == Resolution::Auto {
            fg.count(
                if resolved.is_half() {
                    AUTO_HALF
                } else {
                    AUTO_FULL
                },
                1,
            );
        }
        resolved
    }

    /// Half, as set or resolved (Auto is neither until [`Resolution::resolve`]).
    pub fn is_half(self) -> bool {
        self == Resolution::Half
    }

    /// The shader feature the expensive pass takes (none at full resolution).
    pub fn feature(self) -> Option<&'static str> {
        self.is_half().then_some(HALF_FEATURE)
    }

    /// The pixels the expensive pass writes for a full size of `full`
    /// (Auto, which an effect resolves first, counts as Full).
    pub fn pixels(self, full: (u32, u32)) -> (u32, u32) {
        match self {
            Resolution::Full | Resolution::Auto => full,
            Resolution::Half => (full.0.div_ceil(2).max(1), full.1.div_ceil(2).max(1)),
        }
    }

    /// The size rule of the expensive pass's target, for a G-buffer of
    /// `full` pixels: exactly `pixels` (a relative half would round odd
    /// sizes the other way).
    pub fn size_rule(self, full_rule: SizeRule, full: (u32, u32)) -> SizeRule {
        match self {
            Resolution::Full | Resolution::Auto => full_rule,
            Resolution::Half => {
                let (width, height) = self.pixels(full);
                SizeRule::Absolute { width, height }
            }
        }
    }

    /// A suffix for pass names, so the frame report says which resolution ran.
    pub fn pass_suffix(self) -> &'static str {
        match self {
            Resolution::Full | Resolution::Auto => "",
            Resolution::Half => " (half)",
        }
    }
}

/// What [`Resolution::Auto`] resolves to on a renderer.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum AutoChoice {
    /// Half from [`AUTO_HALF_FROM_PIXELS`] on, Full below.
    #[default]
    Size,
    /// Always Full (to measure against the rule).
    Full,
    /// Always Half.
    Half,
}

impl AutoChoice {
    pub fn name(self) -> &'static str {
        match self {
            AutoChoice::Size => "size",
            AutoChoice::Full => "full",
            AutoChoice::Half => "half",
        }
    }

    pub fn parse(name: &str) -> Option<Self> {
        match name.to_ascii_lowercase().as_str() {
            "size" => Some(AutoChoice::Size),
            "full" => Some(AutoChoice::Full),
            "half" => Some(AutoChoice::Half),
            _ => None,
        }
    }

    /// What [`AUTO_VAR`] asks for; unset, the size rule. A value it does not
    /// know is an error naming the variable and the value.
    pub fn from_env() -> Result<Self, String> {
        crate::setting::from_env(AUTO_VAR, Self::parse, "`full`, `half` or `size`")
    }

    /// Auto's resolution for a G-buffer of `pixels`.
    pub fn resolve(self, pixels: (u32, u32)) -> Resolution {
        match self {
            AutoChoice::Full => Resolution::Full,
            AutoChoice::Half => Resolution::Half,
            AutoChoice::Size => {
                if u64::from(pixels.0) * u64::from(pixels.1) >= AUTO_HALF_FROM_PIXELS {
                    Resolution::Half
                } else {
                    Resolution::Full
                }
            }
        }
    }
}

/// What Auto resolves to on `renderer` ([`AUTO_VAR`] until set).
pub fn auto_choice(renderer: &Renderer) -> AutoChoice {
    renderer.setting(0, || {
        AutoChoice::from_env().unwrap_or_else(|e| {
            // Not fatal: the frame renders either way; the rule stands.
            eprintln!("warning: {e}; Auto follows the frame size");
            AutoChoice::default()
        })
    })
}

/// Make Auto resolve as `choice` on `renderer` from the next frame on.
pub fn set_auto_choice(renderer: &Renderer, choice: AutoChoice) {
    renderer.set_setting(0, choice);
}

/// A recipe's resolution as it resolved when it last declared its passes,
/// for the methods that run later (a pass's closure) or have no frame size.
#[derive(Debug, Default)]
pub struct ResolvedCell(AtomicU8);

impl ResolvedCell {
    pub fn set(&self, resolution: Resolution) {
        self.0
            .store(u8::from(resolution.is_half()), Ordering::Relaxed);
    }

    /// Full until first set.
    pub fn get(&self) -> Resolution {
        if self.0.load(Ordering::Relaxed) == 1 {
            Resolution::Half
        } else {
            Resolution::Full
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
    /// What the permutation reads besides, by variable: depth of field's
    /// sharp image and circle of confusion, or a half chain's finish's
    /// combined AO or ambient light.
    extra: [Option<(&'static str, Tex)>; 2],
}

/// Record the depth-aware upsample of `io.source` into `io.output` with
/// permutation `key`.
fn upsample(
    cx: &mut PassContext<'_>,
    label: &str,
    gbuffer: &GBuffer,
    key: UpsampleKey,
    io: &UpsampleIo,
) -> Result<(), RenderError> {
    let mut b = Bindings::new()
        .buffer("camera", gbuffer.camera_buffer())
        .texture("depth", io.depth)
        .texture("normals", io.normals)
        .texture("source", io.source)
        .texture("output", io.output);
    for (var, tex) in io.extra.into_iter().flatten() {
        b = b.texture(var, tex);
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

/// The upsample's permutation for a target of `format`, with or without
/// depth of field's detail.
fn upsample_key(format: UpsampleFormat, detail: bool) -> UpsampleKey {
    match (format, detail) {
        (UpsampleFormat::R32, _) => UpsampleKey::R32,
        (UpsampleFormat::Rgba16, true) => UpsampleKey::Detail,
        (UpsampleFormat::Rgba16, false) => UpsampleKey::Rgba16,
    }
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
    let (source, depth, normals) = (
        pass.read(u.half),
        pass.read(&g.depth),
        pass.read(&g.normals),
    );
    let detail = u
        .detail
        .map(|(image, coc)| (pass.read(image), pass.read(coc)));
    let io = UpsampleIo {
        source,
        depth,
        normals,
        extra: [
            detail.map(|(image, _)| ("image", image)),
            detail.map(|(_, coc)| ("coc", coc)),
        ],
        output: pass.write(u.full, u.desc),
    };
    // R32 is AO's; the detail is depth of field's, in RGBA16F.
    let key = upsample_key(u.format, u.detail.is_some());
    // Announced, so a first frame finds its pipeline made on a thread
    // (frame_graph/gather.rs); SSR's and DOF's half paths come through here.
    pass.will_dispatch(&key.key(), "main");
    let (gbuffer, counter, label) = (u.gbuffer, u.counter, u.label);
    pass.run(move |cx| {
        cx.count(counter, 1);
        upsample(cx, label, gbuffer, key, &io)
    });
}

/// What the upsample at the end of a half chain does besides upsampling:
/// what the effect's last full-resolution pass did.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Finish<'s> {
    /// AO: the half R32 visibility into the grey RGBA16F output, times
    /// another AO (frame-graph name) when given.
    Ao { combine: Option<&'s str> },
    /// SSGI: the half (bounce, escaped share) into the full RGBA16F output,
    /// with the ambient light (frame-graph name) times the escaped share
    /// added when given.
    Light { ambient: Option<&'s str> },
}

impl Finish<'_> {
    /// The upsample's permutation.
    pub fn key(self) -> UpsampleKey {
        match self {
            Finish::Ao { combine: None } => UpsampleKey::Ao,
            Finish::Ao { combine: Some(_) } => UpsampleKey::AoCombine,
            Finish::Light { ambient: None } => UpsampleKey::Rgba16,
            Finish::Light { ambient: Some(_) } => UpsampleKey::Ambient,
        }
    }
}

/// The last pass of a half chain (AO, SSGI): the depth-aware upsample of
/// `half` into `full`, doing what [`Finish`] says.
pub struct FinishPass<'s, 'g> {
    pub name: PassName,
    pub owner: Option<u32>,
    pub gbuffer: &'g GBuffer,
    /// The half-size result of the chain.
    pub half: &'s str,
    /// The effect's full-size output.
    pub full: &'s str,
    pub desc: TextureDesc,
    pub finish: Finish<'s>,
    /// The statistic that counts it.
    pub counter: &'static str,
    /// The dispatch's debug label.
    pub label: &'static str,
}

/// Declare the last pass of a half chain ([`FinishPass`]).
pub fn declare_finish<'a>(fg: &mut FrameGraph<'a>, u: FinishPass<'_, 'a>) {
    let g = &u.gbuffer.targets;
    let key = u.finish.key();
    let mut pass = fg.pass(u.name, u.owner);
    let (source, depth, normals) = (
        pass.read(u.half),
        pass.read(&g.depth),
        pass.read(&g.normals),
    );
    let extra = match u.finish {
        Finish::Ao { combine } => combine.map(|c| ("combine", pass.read(c))),
        Finish::Light { ambient } => ambient.map(|a| ("ambient", pass.read(a))),
    };
    let io = UpsampleIo {
        source,
        depth,
        normals,
        extra: [extra, None],
        output: pass.write(u.full, u.desc),
    };
    pass.will_dispatch(&key.key(), "main");
    let (gbuffer, counter, label) = (u.gbuffer, u.counter, u.label);
    pass.run(move |cx| {
        cx.count(counter, 1);
        upsample(cx, label, gbuffer, key, &io)
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
        for r in Resolution::ALL {
            assert_eq!(Resolution::parse(r.name()), Some(r));
        }
        assert_eq!(Resolution::parse("HALF"), Some(Resolution::Half));
        assert_eq!(Resolution::parse("quarter"), None);
        assert_eq!(Resolution::default(), Resolution::Auto);
        for c in [AutoChoice::Size, AutoChoice::Full, AutoChoice::Half] {
            assert_eq!(AutoChoice::parse(c.name()), Some(c));
        }
        assert_eq!(AutoChoice::parse("quarter"), None);
    }

    #[test]
    fn auto_is_half_from_the_threshold_on() {
        let rule = AutoChoice::Size;
        assert_eq!(rule.resolve((1920, 1080)), Resolution::Half);
        assert_eq!(rule.resolve((3840, 2160)), Resolution::Half);
        // One pixel short of 1080p, and a taller frame of as many pixels.
        assert_eq!(rule.resolve((1920, 1079)), Resolution::Full);
        assert_eq!(rule.resolve((1080, 1920)), Resolution::Half);
        assert_eq!(rule.resolve((480, 270)), Resolution::Full);
        assert_eq!(AutoChoice::Full.resolve((3840, 2160)), Resolution::Full);
        assert_eq!(AutoChoice::Half.resolve((64, 64)), Resolution::Half);
    }
}
