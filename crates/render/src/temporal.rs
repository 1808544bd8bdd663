//! What temporal effects remember between frames, per node: a frame
//! counter (it turns their per-pixel sample patterns, so accumulation
//! converges to many more samples than a frame takes) and last frame's
//! camera, to tell when the history no longer fits. The history textures
//! themselves are persistent frame-graph textures ([`crate::frame_graph::TextureDesc::history`]).

use std::sync::Mutex;

use glam::Mat4;

use crate::gbuffer::GBuffer;

#[derive(Default)]
pub struct TemporalState {
    inner: Mutex<(u32, Option<Mat4>)>,
}

impl TemporalState {
    /// Start a frame over `gbuffer`: the frame's index, and whether the
    /// history is stale — asked for (`reset`), or the G-buffer's previous
    /// camera is not the one seen last frame (a cut, or frames skipped).
    pub fn advance(&self, gbuffer: &GBuffer, reset: bool) -> (u32, bool) {
        let mut state = self.inner.lock().unwrap_or_else(|e| e.into_inner());
        let now = gbuffer.camera.view_projection();
        let stale = match (state.1, gbuffer.previous_view_projection()) {
            (Some(seen), Some(previous)) => !seen.abs_diff_eq(previous, 1e-4),
            (Some(seen), None) => !seen.abs_diff_eq(now, 1e-4),
            (None, _) => false,
        };
        state.0 = state.0.wrapping_add(1);
        state.1 = Some(now);
        (state.0, reset || stale)
    }
}

/// What the screen-space ray passes (AO, SSGI) are told each frame:
/// `RayParams` in shaders/lib/screen.wgsl.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct RayParams {
    pub radius: f32,
    pub intensity: f32,
    pub blend: f32,
    pub samples: u32,
    pub steps: u32,
    pub blur_radius: u32,
}

impl RayParams {
    /// The uniform's 16 words for `frame`; `reset` drops the history.
    pub fn words(&self, frame: u32, reset: bool) -> [u32; 16] {
        let mut words = [0u32; 16];
        words[..9].copy_from_slice(&[
            self.radius.to_bits(),
            self.intensity.to_bits(),
            self.blend.to_bits(),
            // Bias: a small share of the radius, so flat surfaces do not self-occlude.
            (self.radius * 0.02).to_bits(),
            self.samples,
            self.steps,
            frame,
            self.blur_radius,
            u32::from(reset),
        ]);
        words
    }
}
