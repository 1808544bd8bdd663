//! What temporal effects remember between frames, per node: a frame
//! counter (it turns their per-pixel sample patterns, so accumulation
//! converges to many more samples than a frame takes) and last frame's
//! camera, to tell when the history no longer fits. The history textures
//! themselves are persistent frame-graph textures ([`crate::frame_graph::TextureDesc::history`]).

use std::sync::{Arc, Mutex};

use glam::Mat4;

use crate::error::RenderError;
use crate::frame_graph::{History, PassContext};
use crate::gbuffer::GBuffer;
use crate::renderer::Renderer;
use crate::shaders::Uniform;

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

/// `RayParams` as the shader lays it out (64 bytes).
#[repr(C)]
#[derive(Clone, Copy, Debug, bytemuck::Pod, bytemuck::Zeroable)]
pub struct GpuRayParams {
    radius: f32,
    intensity: f32,
    blend: f32,
    bias: f32,
    samples: u32,
    steps: u32,
    frame: u32,
    blur_radius: u32,
    reset: u32,
    spare: [u32; 7],
}

impl RayParams {
    /// The uniform for `frame`; `reset` drops the history.
    pub fn gpu(&self, frame: u32, reset: bool) -> GpuRayParams {
        GpuRayParams {
            radius: self.radius,
            intensity: self.intensity,
            blend: self.blend,
            // Bias: a small share of the radius, so flat surfaces do not self-occlude.
            bias: self.radius * 0.02,
            samples: self.samples,
            steps: self.steps,
            frame,
            blur_radius: self.blur_radius,
            reset: u32::from(reset),
            spare: [0; 7],
        }
    }
}

/// What a screen-space ray effect (AO, SSGI) keeps under its node: the
/// frame counter and last camera ([`TemporalState`]), the parameters'
/// uniform and the `fresh` flags its temporal pass binds. Kept per node, so
/// a recipe made again carries the history on and reuses its bind groups.
pub struct RayUniforms {
    /// The node (without one, the recipe): what the history is named by.
    pub key: u64,
    params: Uniform<GpuRayParams>,
    /// [history kept, history reset].
    fresh: [wgpu::Buffer; 2],
    state: Arc<TemporalState>,
    /// The counter of histories started anew.
    reset: &'static str,
}

impl RayUniforms {
    /// For recipe `id` of node `owner`; `labels`: the parameters' and the
    /// flags' buffers, and the counter of resets.
    pub fn new(
        renderer: &Renderer,
        owner: Option<u32>,
        id: u64,
        [params, fresh, reset]: [&'static str; 3],
    ) -> Self {
        // The history outlives recipes: a node makes a new one whenever a pin
        // changes, and its history must carry over. Without a node, per recipe.
        let key = owner.map_or(id, u64::from);
        RayUniforms {
            key,
            params: renderer.kept_uniform(owner, params),
            fresh: renderer.kept_flags(owner, fresh),
            state: renderer.state::<TemporalState>(key),
            reset,
        }
    }

    /// Start a frame in the pass that estimates: the frame index advanced
    /// (it turns the samples) and uploaded with `ray`; a history stale or
    /// asked to `reset` is reset where the effect is `temporal`, and counted.
    pub fn begin(
        &self,
        cx: &mut PassContext<'_>,
        gbuffer: &GBuffer,
        ray: &RayParams,
        reset: bool,
        temporal: bool,
    ) {
        let (frame, stale) = self.state.advance(gbuffer, reset);
        let reset = stale && temporal;
        if reset {
            cx.count(self.reset, 1);
        }
        self.params.write(&cx.gpu.queue, &ray.gpu(frame, reset));
    }

    pub fn params(&self) -> &wgpu::Buffer {
        self.params.buffer()
    }

    /// The `fresh` flag to bind: whether the history holds nothing yet.
    pub fn fresh(&self, fresh: bool) -> &wgpu::Buffer {
        &self.fresh[usize::from(fresh)]
    }

    /// Hand last frame's history over ([`PassContext::hand_over_history`], a
    /// fresh one counted as a reset): the `fresh` flag to bind.
    pub fn hand_over(
        &self,
        cx: &mut PassContext<'_>,
        h: History,
    ) -> Result<&wgpu::Buffer, RenderError> {
        Ok(self.fresh(cx.hand_over_history(h, self.reset)?))
    }
}

#[cfg(test)]
mod tests {
    use super::GpuRayParams;

    #[test]
    fn gpu_ray_params_match_the_shader() {
        crate::assert_wgsl_layout!(
            GpuRayParams,
            "lib/screen.wgsl",
            [],
            "RayParams",
            [
                radius,
                intensity,
                blend,
                bias,
                samples,
                steps,
                frame,
                blur_radius,
                reset,
                spare
            ]
        );
    }
}
