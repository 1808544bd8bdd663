//! A G-buffer's packed surface: per pixel its view distance and unit normal
//! in one RG32Uint texel (shaders/packed_surface/pack.wgsl), written once a
//! frame for every depth-aware blur that reads it (SSAO's, SAO's, HBAO's and
//! SSGI's x and y passes).
//!
//! Why: on the H200 those blurs are bound by texture reads, not memory
//! (issue 33: 0.05-0.06 ms a pass at 1080p for 27 reads a pixel at the
//! default radius 4, about the texture units' rate). Each tap read the
//! G-buffer's depth and normals (two reads) and turned the depth into a view
//! distance again (an inverse projection); from the packed surface it is
//! one read and no projection, 18 reads a pixel instead of 27, and the
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
//! [`BlurInputs`] picks the way per renderer: `Packed` (the default) or
//! `GBuffer` (the blurs as before), from [`BLUR_INPUTS_VAR`] at first, so a
//! benchmark measures both in one device call.

use std::sync::atomic::{AtomicU8, Ordering};

use crate::frame_graph::{FrameGraph, TextureDesc};
use crate::gbuffer::GBuffer;
use crate::renderer::Renderer;
use crate::report::PassName;
use crate::shaders::Permutation;

pub(crate) mod key;
pub use key::PackKey;

/// The environment variable that picks [`BlurInputs`] for a process
/// (`packed` or `gbuffer`), for benchmarking both ways in one call
/// (docs/benchmarks.md); [`set_blur_inputs`] overrides it per renderer.
pub const BLUR_INPUTS_VAR: &str = "SPREADLIGHT_BLUR_INPUTS";

/// Statistic: packed surfaces written this frame (one per G-buffer whose
/// blurs read it).
pub const PACKED_SURFACES: &str = "packed surfaces written";

/// What the depth-aware blurs read for each tap's view distance and normal.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
pub enum BlurInputs {
    /// The packed surface: one RG32Uint read a tap, written once a frame.
    #[default]
    Packed,
    /// The G-buffer's depth and normals, an inverse projection a tap (the
    /// blurs before the packed surface).
    GBuffer,
}

impl BlurInputs {
    /// A value of [`BLUR_INPUTS_VAR`] (case-insensitive), `None` for any other.
    pub fn parse(value: &str) -> Option<Self> {
        match value.trim().to_ascii_lowercase().as_str() {
            "packed" => Some(BlurInputs::Packed),
            "gbuffer" => Some(BlurInputs::GBuffer),
            _ => None,
        }
    }

    pub fn name(self) -> &'static str {
        match self {
            BlurInputs::Packed => "packed",
            BlurInputs::GBuffer => "gbuffer",
        }
    }

    /// What [`BLUR_INPUTS_VAR`] asks for; unset, the default. A value it does
    /// not know is an error naming the variable and the value (a benchmark
    /// must not measure another way than the one it asked for).
    pub fn from_env() -> Result<Self, String> {
        match std::env::var(BLUR_INPUTS_VAR) {
            Err(std::env::VarError::NotPresent) => Ok(BlurInputs::default()),
            Err(e) => Err(format!("{BLUR_INPUTS_VAR}: {e}")),
            Ok(value) => Self::parse(&value).ok_or_else(|| {
                format!("{BLUR_INPUTS_VAR} is `{value}`: it takes `packed` or `gbuffer`")
            }),
        }
    }

    fn code(self) -> u8 {
        match self {
            BlurInputs::Packed => 0,
            BlurInputs::GBuffer => 1,
        }
    }

    fn from_code(code: u8) -> Self {
        if code == 1 {
            BlurInputs::GBuffer
        } else {
            BlurInputs::Packed
        }
    }
}

/// A renderer's choice, kept in its states (`Renderer::state`).
struct Choice(AtomicU8);

impl Default for Choice {
    fn default() -> Self {
        let inputs = BlurInputs::from_env().unwrap_or_else(|e| {
            // Not fatal: the frame renders either way; the default stands.
            eprintln!("warning: {e}; the blurs read the packed surface");
            BlurInputs::default()
        });
        Choice(AtomicU8::new(inputs.code()))
    }
}

/// What `renderer`'s blurs read ([`BLUR_INPUTS_VAR`] until set).
pub fn blur_inputs(renderer: &Renderer) -> BlurInputs {
    BlurInputs::from_code(renderer.state::<Choice>(0).0.load(Ordering::Relaxed))
}

/// Pick what `renderer`'s blurs read from the next frame on.
pub fn set_blur_inputs(renderer: &Renderer, inputs: BlurInputs) {
    renderer
        .state::<Choice>(0)
        .0
        .store(inputs.code(), Ordering::Relaxed);
}

/// The packed surface of `gbuffer` this frame: its pass declared by the
/// first blur that asks (after the G-buffer is), the name handed to all.
pub(crate) fn declare<'a>(fg: &mut FrameGraph<'a>, gbuffer: &'a GBuffer) -> String {
    let name = format!("{}/packed surface", gbuffer.targets.depth);
    if fg.planned(&name).is_some() {
        return name;
    }
    fg.count(PACKED_SURFACES, 1);
    let mut pass = fg.pass(PassName::new("Packed surface"), None);
    pass.input("depth", &gbuffer.targets.depth);
    pass.input("normals", &gbuffer.targets.normals);
    pass.output(
        "output",
        &name,
        TextureDesc::storage(wgpu::TextureFormat::Rg32Uint).size(gbuffer.size),
    );
    pass.bind(|b| b.buffer("camera", gbuffer.camera_buffer()));
    pass.dispatch_image("packed surface", PackKey.key(), gbuffer.size);
    name
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn names_round_trip() {
        for inputs in [BlurInputs::Packed, BlurInputs::GBuffer] {
            assert_eq!(BlurInputs::parse(inputs.name()), Some(inputs));
            assert_eq!(BlurInputs::from_code(inputs.code()), inputs);
        }
        assert_eq!(BlurInputs::parse(" GBuffer "), Some(BlurInputs::GBuffer));
        assert_eq!(BlurInputs::parse("tiled"), None);
        assert_eq!(BlurInputs::default(), BlurInputs::Packed);
    }
}
