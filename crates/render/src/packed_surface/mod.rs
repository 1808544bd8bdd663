//! A G-buffer's packed surface: per pixel its view distance and unit normal
//! in one RG32Uint texel (shaders/packed_surface/pack.wgsl), written once a
//! frame (the G-buffer node's pass "MRE: packed surface") for every
//! depth-aware blur that reads it (SSAO's, SAO's, HBAO's and
//! SSGI's x and y passes).
//!
//! Why: on the H200 those blurs look bound by texture reads, not memory
//! (issue 33: 0.05-0.06 ms a pass at 1080p for 29 reads a pixel at the
//! default radius 4, about the texture units' rate; not yet measured
//! otherwise). Each tap read the G-buffer's depth and normals (two reads)
//! and turned the depth into a view distance again (an inverse projection);
//! from the packed surface it is one read and no projection, 19 reads a
//! pixel instead of 29, and the
//! surface is written once for all the blurs of the frame.
//!
//! What it costs in accuracy: the view distance is the same f32 the blurs
//! computed (the same expression, its bits stored); the normal is
//! octahedron-encoded in two 16-bit snorms (under 5e-5 radians off), so a
//! tap's normal weight (the cosine to the 8th) moves by under 4e-4 of
//! itself: the blurred value by far less than a half float's step at 1
//! (tested in `crates/render/tests/depth_aware_blur.rs` against the CPU and
//! against the G-buffer way).
//!
//! The pass writes a second target, the view z itself (R32Float), for
//! SSAO's and SSGI's rays: each step read it instead of the depth and an
//! inverse projection (the same bits), and a ray's four steps' reads are
//! made together before their tests (screen.wgsl's `march_packed`), so they
//! are in flight at once rather than each waiting on the last one's test:
//! the same pixels, the same image.
//!
//! [`SurfaceInputs`] picks the way per renderer and [`Reader`]: `Packed`
//! (the default) or `GBuffer` (as before), from [`BLUR_INPUTS_VAR`] and
//! [`MARCH_INPUTS_VAR`] at first, so a benchmark measures every way in one
//! device call.

use crate::frame_graph::{FrameGraph, TextureDesc};
use crate::gbuffer::GBuffer;
use crate::renderer::Renderer;
use crate::report::PassName;
use crate::shaders::Permutation;

pub(crate) mod key;
pub use key::PackKey;

/// The environment variable that picks what the blurs read for a process
/// (`packed` or `gbuffer`), for benchmarking both ways in one call
/// (docs/benchmarks.md); [`set_inputs`] overrides it per renderer.
pub const BLUR_INPUTS_VAR: &str = "SPREADLIGHT_BLUR_INPUTS";

/// The same for SSAO's and SSGI's rays (`packed`: the packed view z, four
/// steps' reads at a time; `gbuffer`: depth and an inverse projection a step).
pub const MARCH_INPUTS_VAR: &str = "SPREADLIGHT_MARCH_INPUTS";

/// The pass's step in the frame report (its kind is the G-buffer's, "MRE").
pub const PASS_STEP: &str = "packed surface";

/// Statistic: packed surfaces written this frame (one per G-buffer whose
/// blurs read it).
pub const PACKED_SURFACES: &str = "packed surfaces written";

/// What the depth-aware blurs read for each tap's view distance and normal,
/// or SSAO's and SSGI's rays for each step's view z.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
pub enum SurfaceInputs {
    /// The packed surface: one RG32Uint read a blur tap, one R32Float read
    /// a ray step, written once a frame. Not the default: measured slower
    /// on the H200 (post.ron's frame span 2.446 ms against 2.408 reading
    /// the G-buffer, session 21, docs/benchmarks.md "Session 21 on the
    /// H200"): the blurs' and rays' reads hit the texture cache either way,
    /// and the packing pass costs more than the projections it saves.
    Packed,
    /// The G-buffer's depth (and normals), an inverse projection a tap or
    /// step (the blurs and rays before the packed surface).
    #[default]
    GBuffer,
}

impl SurfaceInputs {
    /// A value of [`BLUR_INPUTS_VAR`] (case-insensitive), `None` for any other.
    pub fn parse(value: &str) -> Option<Self> {
        match value.trim().to_ascii_lowercase().as_str() {
            "packed" => Some(SurfaceInputs::Packed),
            "gbuffer" => Some(SurfaceInputs::GBuffer),
            _ => None,
        }
    }

    pub fn name(self) -> &'static str {
        match self {
            SurfaceInputs::Packed => "packed",
            SurfaceInputs::GBuffer => "gbuffer",
        }
    }

    /// What the environment variable `var` asks for; unset, the default. A
    /// value it does not know is an error naming the variable and the value.
    pub fn from_env(var: &str) -> Result<Self, String> {
        crate::setting::from_env(var, Self::parse, "`packed` or `gbuffer`")
    }
}

/// Which reads a choice is for.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Reader {
    /// The depth-aware blurs' taps ([`BLUR_INPUTS_VAR`]).
    Blurs,
    /// SSAO's and SSGI's rays ([`MARCH_INPUTS_VAR`]).
    Rays,
}

impl Reader {
    fn var(self) -> &'static str {
        match self {
            Reader::Blurs => BLUR_INPUTS_VAR,
            Reader::Rays => MARCH_INPUTS_VAR,
        }
    }

    fn key(self) -> u64 {
        match self {
            Reader::Blurs => 0,
            Reader::Rays => 1,
        }
    }
}

/// What `renderer`'s `reader` reads (its variable until set).
pub fn inputs(renderer: &Renderer, reader: Reader) -> SurfaceInputs {
    renderer.setting(reader.key(), || {
        SurfaceInputs::from_env(reader.var()).unwrap_or_else(|e| {
            // Not fatal: the frame renders either way; the default stands.
            eprintln!("warning: {e}; the packed surface is read");
            SurfaceInputs::default()
        })
    })
}

/// Pick what `renderer`'s `reader` reads from the next frame on.
pub fn set_inputs(renderer: &Renderer, reader: Reader, inputs: SurfaceInputs) {
    renderer.set_setting(reader.key(), inputs);
}

/// The packed surface's two targets (frame-graph names).
pub(crate) struct Packed {
    /// RG32Uint: view distance bits and the octahedron normal.
    pub surface: String,
    /// R32Float: the view z (EMPTY_Z where depth is empty).
    pub view_z: String,
}

/// The packed surface of `gbuffer` this frame: its pass declared by the
/// first pass that asks (after the G-buffer is), the names handed to all.
pub(crate) fn declare<'a>(fg: &mut FrameGraph<'a>, gbuffer: &'a GBuffer) -> Packed {
    let depth = &gbuffer.targets.depth;
    let packed = Packed {
        surface: format!("{depth}/packed surface"),
        view_z: format!("{depth}/packed view z"),
    };
    if fg.planned(&packed.surface).is_some() {
        return packed;
    }
    fg.count(PACKED_SURFACES, 1);
    // A pass of the G-buffer's node: its targets, another form of them.
    let mut pass = fg.pass(PassName::new("MRE").step(PASS_STEP), gbuffer.owner());
    pass.input("depth", depth);
    pass.input("normals", &gbuffer.targets.normals);
    let desc = |format| TextureDesc::storage(format).size(gbuffer.size);
    pass.output(
        "output",
        &packed.surface,
        desc(wgpu::TextureFormat::Rg32Uint),
    );
    pass.output(
        "view_z",
        &packed.view_z,
        desc(wgpu::TextureFormat::R32Float),
    );
    pass.bind(|b| b.buffer("camera", gbuffer.camera_buffer()));
    pass.dispatch_image("packed surface", PackKey.key(), gbuffer.size);
    packed
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn names_round_trip() {
        for inputs in [SurfaceInputs::Packed, SurfaceInputs::GBuffer] {
            assert_eq!(SurfaceInputs::parse(inputs.name()), Some(inputs));
        }
        assert_eq!(
            SurfaceInputs::parse(" GBuffer "),
            Some(SurfaceInputs::GBuffer)
        );
        assert_eq!(SurfaceInputs::parse("tiled"), None);
        assert_eq!(SurfaceInputs::default(), SurfaceInputs::GBuffer);
    }
}
