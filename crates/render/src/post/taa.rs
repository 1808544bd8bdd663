//! `TAA`: temporal anti-aliasing over a jittered camera
//! (`camera::jitter_ndc`, applied by the `Camera` node), one compute pass
//! (shaders/post/taa.wgsl) and a copy of its result into a persistent
//! history texture named after the node. The history is fresh, and the
//! frame taken as it is, on the first frame, after a resize (a new size is
//! a new texture), after `Renderer::reset_history` and when the node says
//! the camera cut (`TaaSettings::reset`).

use std::sync::Arc;

use glam::{Mat4, Vec2};

use crate::error::RenderError;
use crate::frame_graph::{Bindings, FrameGraph, PassContext, Tex, TextureDesc};
use crate::gbuffer::GBuffer;
use crate::recipe::{Recipe, TextureRef, next_recipe_id};
use crate::renderer::Renderer;
use crate::report::PassName;
use crate::shaders::{Permutation, Sampling};

pub use super::taa_key::TaaQuality;

/// Counted when the history was thrown away (fresh target or a cut).
pub const RESET: &str = "taa history reset";

#[derive(Clone, Copy, Debug, PartialEq)]
pub struct TaaSettings {
    pub quality: TaaQuality,
    /// How much of the history is kept each frame (0.9: about ten frames' average).
    pub feedback: f32,
    /// How much of the current frame's detail is added back (0: none).
    pub sharpen: f32,
    /// This frame's jitter and last frame's, in NDC (the camera's Jitter output).
    pub jitter: Vec2,
    pub previous_jitter: Vec2,
    /// Throw the history away (a camera cut).
    pub reset: bool,
}

impl Default for TaaSettings {
    fn default() -> Self {
        TaaSettings {
            quality: TaaQuality::High,
            feedback: 0.9,
            sharpen: 0.0,
            jitter: Vec2::ZERO,
            previous_jitter: Vec2::ZERO,
            reset: false,
        }
    }
}

/// Whether the camera cut between two frames' views: its eye moved further
/// than `distance` (0 or less: never by distance) or it turned more than 45
/// degrees. Hosts and nodes reset TAA's history on a cut.
pub fn is_cut(previous_view: Mat4, view: Mat4, distance: f32) -> bool {
    let (a, b) = (
        crate::camera::safe_inverse(previous_view),
        crate::camera::safe_inverse(view),
    );
    let moved = (a.w_axis - b.w_axis).truncate().length();
    let turned = a
        .z_axis
        .truncate()
        .normalize_or_zero()
        .dot(b.z_axis.truncate().normalize_or_zero());
    (distance > 0.0 && moved > distance)
        || turned < std::f32::consts::FRAC_1_SQRT_2
        || !moved.is_finite()
}

pub struct Taa {
    id: u64,
    owner: Option<u32>,
    source: TextureRef,
    gbuffer: Arc<GBuffer>,
    settings: TaaSettings,
    params: wgpu::Buffer,
    /// The persistent history.
    pub history: String,
    pub output: String,
}

impl Taa {
    /// The history is named after `owner` (the node); without one, after `history`.
    pub fn new(
        renderer: &Renderer,
        owner: Option<u32>,
        source: TextureRef,
        gbuffer: Arc<GBuffer>,
        settings: TaaSettings,
        history: Option<String>,
    ) -> Arc<Self> {
        let id = next_recipe_id();
        let history = history.unwrap_or_else(|| match owner {
            Some(node) => format!("taa history #{node}"),
            None => format!("taa{id} history"),
        });
        let clean = |v: f32, lo: f32, hi: f32, fallback: f32| {
            if v.is_finite() {
                v.clamp(lo, hi)
            } else {
                fallback
            }
        };
        let jitter = |v: Vec2| if v.is_finite() { v } else { Vec2::ZERO };
        let settings = TaaSettings {
            feedback: clean(settings.feedback, 0.0, 0.99, 0.9),
            sharpen: clean(settings.sharpen, 0.0, 2.0, 0.0),
            jitter: jitter(settings.jitter),
            previous_jitter: jitter(settings.previous_jitter),
            ..settings
        };
        // NDC to UV: half the size, y flipped.
        let delta = (settings.jitter - settings.previous_jitter) * Vec2::new(0.5, -0.5);
        let params = super::uniform(
            renderer,
            owner,
            "taa",
            &super::words(&[
                delta.x,
                delta.y,
                settings.feedback,
                settings.sharpen,
                0.0,
                0.0,
                0.0,
                0.0,
            ]),
        );
        Arc::new(Taa {
            id,
            owner,
            source,
            gbuffer,
            settings,
            params,
            history,
            output: format!("taa{id}"),
        })
    }

    pub fn texture(self: &Arc<Self>) -> TextureRef {
        TextureRef {
            recipe: self.clone(),
            name: self.output.clone(),
        }
    }

    fn run(&self, cx: &mut PassContext<'_>, io: &TaaIo) -> Result<(), RenderError> {
        let fresh = cx.is_fresh(io.history) || self.settings.reset;
        if fresh {
            cx.count(RESET, 1);
        }
        cx.gpu.queue.write_buffer(
            &self.params,
            16,
            bytemuck::cast_slice(&[if fresh { 1.0f32 } else { 0.0 }, 0.0, 0.0, 0.0]),
        );
        let size = cx.size_of(io.output)?;
        cx.dispatch_image(
            "taa",
            &self.settings.quality.key(),
            Bindings::new()
                .buffer("params", &self.params)
                .texture("source", io.source)
                .texture("velocity_uv", io.velocity_uv)
                .texture("depth", io.depth)
                .texture("history", io.history)
                .texture("output", io.output)
                .sampler("linear", Sampling::LinearClamp),
            size,
        )?;
        // The result is next frame's history.
        cx.keep_as_history(io.output, io.history)?;
        Ok(())
    }
}

/// What the TAA pass declared: it reads last frame's history and writes
/// the output, which then becomes the history.
struct TaaIo {
    source: Tex,
    velocity_uv: Tex,
    depth: Tex,
    history: Tex,
    output: Tex,
}

impl Recipe for Taa {
    fn declare<'a>(&'a self, renderer: &'a Renderer, fg: &mut FrameGraph<'a>) {
        if !fg.include(self.id) {
            return;
        }
        self.source.recipe.declare(renderer, fg);
        self.gbuffer.declare(renderer, fg);
        // Alike, so the output becomes the history without a copy.
        let output =
            TextureDesc::history_twin(wgpu::TextureFormat::Rgba16Float).size(self.gbuffer.size);
        let history =
            TextureDesc::history(wgpu::TextureFormat::Rgba16Float).size(self.gbuffer.size);
        let t = &self.gbuffer.targets;
        let mut pass = fg.pass(PassName::new("TAA"), self.owner);
        let io = TaaIo {
            source: pass.read(&self.source.name),
            velocity_uv: pass.read(&t.velocity_uv),
            depth: pass.read(&t.depth),
            output: pass.write(&self.output, output),
            history: pass.write(&self.history, history),
        };
        pass.will_dispatch(&self.settings.quality.key(), "main");
        pass.run(move |cx| self.run(cx, &io));
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use glam::Vec3;

    fn view(eye: Vec3, target: Vec3) -> Mat4 {
        glam::camera::rh::view::look_at_mat4(eye, target, Vec3::Y)
    }

    #[test]
    fn a_jump_or_a_sharp_turn_is_a_cut_and_a_small_move_is_not() {
        let a = view(Vec3::new(0.0, 1.0, 5.0), Vec3::ZERO);
        assert!(!is_cut(a, view(Vec3::new(0.05, 1.0, 5.0), Vec3::ZERO), 1.0));
        assert!(is_cut(
            a,
            view(Vec3::new(3.0, 1.0, 5.0), Vec3::new(3.0, 0.0, 0.0)),
            1.0
        ));
        assert!(!is_cut(
            a,
            view(Vec3::new(3.0, 1.0, 5.0), Vec3::new(3.0, 0.0, 0.0)),
            0.0
        ));
        // Turned around on the spot.
        assert!(is_cut(
            a,
            view(Vec3::new(0.0, 1.0, 5.0), Vec3::new(0.0, 1.0, 10.0)),
            1.0
        ));
    }
}
