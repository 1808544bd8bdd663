//! `MotionBlur`: blur along the G-buffer's velocity with McGuire et al.'s
//! tile-max / neighbour-max reconstruction (shaders/post/motion_blur.wgsl),
//! three compute passes. A frame where nothing moves (the G-buffer knows:
//! camera and instances where they were, `GBuffer::is_still`) costs one copy
//! and does not even resolve the velocity target; on the GPU, tiles whose
//! neighbourhood moves less than half a pixel copy their pixels.

use std::sync::Arc;

use crate::error::RenderError;
use crate::frame_graph::{Bindings, FrameGraph, PassContext, SizeRule, Tex, TextureDesc};
use crate::gbuffer::GBuffer;
use crate::recipe::{Recipe, TextureRef, next_recipe_id};
use crate::renderer::Renderer;
use crate::report::PassName;
use crate::shaders::Permutation;

pub use super::motion_blur_key::MotionBlurKey;

/// Counted when a MotionBlur ran only its copy: nothing in the frame moves.
pub const SKIPPED: &str = "motion blur skipped (no motion)";
/// Counted when a MotionBlur blurred.
pub const BLURRED: &str = "motion blur blurred";

#[derive(Clone, Copy, Debug, PartialEq)]
pub struct MotionBlurSettings {
    /// Degrees of a frame the shutter is open (360: the whole frame, 180: the film default).
    pub shutter_angle: f32,
    /// Taps along the motion per pixel: the quality.
    pub samples: u32,
    /// The tile size K in pixels, which is also the longest blur each way.
    pub tile_size: u32,
}

impl Default for MotionBlurSettings {
    fn default() -> Self {
        MotionBlurSettings {
            shutter_angle: 180.0,
            samples: 15,
            tile_size: 20,
        }
    }
}

impl MotionBlurSettings {
    pub fn clean(self) -> Self {
        MotionBlurSettings {
            shutter_angle: if self.shutter_angle.is_finite() {
                self.shutter_angle.clamp(0.0, 360.0)
            } else {
                180.0
            },
            samples: self.samples.clamp(2, 256),
            tile_size: self.tile_size.clamp(4, 64),
        }
    }
}

pub struct MotionBlur {
    id: u64,
    owner: Option<u32>,
    source: TextureRef,
    gbuffer: Arc<GBuffer>,
    settings: MotionBlurSettings,
    params: wgpu::Buffer,
    tile_max: String,
    neighbor_max: String,
    pub output: String,
}

impl MotionBlur {
    pub fn new(
        renderer: &Renderer,
        owner: Option<u32>,
        source: TextureRef,
        gbuffer: Arc<GBuffer>,
        settings: MotionBlurSettings,
    ) -> Arc<Self> {
        let id = next_recipe_id();
        let s = settings.clean();
        let params = super::uniform(
            renderer,
            owner,
            "motion blur",
            &super::words(&[
                s.shutter_angle / 360.0,
                s.tile_size as f32,
                s.samples as f32,
                0.0,
            ]),
        );
        Arc::new(MotionBlur {
            id,
            owner,
            source,
            gbuffer,
            settings: s,
            params,
            tile_max: format!("motion blur{id} tile max"),
            neighbor_max: format!("motion blur{id} neighbour max"),
            output: format!("motion blur{id}"),
        })
    }

    pub fn texture(self: &Arc<Self>) -> TextureRef {
        TextureRef {
            recipe: self.clone(),
            name: self.output.clone(),
        }
    }

    /// One of motion_blur.wgsl's entry points writing `output`, with what
    /// its pass declared in `bindings` and the camera and parameters every entry binds.
    fn run(
        &self,
        cx: &mut PassContext<'_>,
        entry: &'static str,
        bindings: Bindings<'_>,
        output: Tex,
    ) -> Result<(), RenderError> {
        super::dispatch_entry(
            cx,
            &MotionBlurKey.key(),
            entry,
            entry == "tile_max",
            self.gbuffer.camera_buffer(),
            &self.params,
            bindings,
            output,
        )
    }
}

impl Recipe for MotionBlur {
    fn declare<'a>(&'a self, renderer: &'a Renderer, fg: &mut FrameGraph<'a>) {
        if !fg.include(self.id) {
            return;
        }
        self.source.recipe.declare(renderer, fg);
        let name = |what| PassName::new("MotionBlur").step(what);
        let desc = TextureDesc::storage(wgpu::TextureFormat::Rgba16Float).size(self.gbuffer.size);
        if self.gbuffer.is_still() || self.settings.shutter_angle == 0.0 {
            super::declare_copy(
                fg,
                name("copy"),
                self.owner,
                &self.source.name,
                (&self.output, desc),
                SKIPPED,
            );
            return;
        }
        self.gbuffer.declare(renderer, fg);
        let (w, h) = self.gbuffer.pixel_size(fg.output_size());
        let k = self.settings.tile_size;
        let tiles = TextureDesc::storage(wgpu::TextureFormat::Rg32Float).size(SizeRule::Absolute {
            width: w.div_ceil(k),
            height: h.div_ceil(k),
        });
        let t = &self.gbuffer.targets;
        let mut pass = fg.pass(name("tile max"), self.owner);
        let velocity_uv = pass.read(&t.velocity_uv);
        let tile_max = pass.write(&self.tile_max, tiles);
        pass.run(move |cx| {
            let b = Bindings::new()
                .texture("velocity_uv", velocity_uv)
                .texture("tiles_out", tile_max);
            self.run(cx, "tile_max", b, tile_max)
        });
        let mut pass = fg.pass(name("neighbour max"), self.owner);
        let tile_max = pass.read(&self.tile_max);
        let neighbor_max = pass.write(&self.neighbor_max, tiles);
        pass.run(move |cx| {
            let b = Bindings::new()
                .texture("tiles_in", tile_max)
                .texture("tiles_out", neighbor_max);
            self.run(cx, "neighbor_max", b, neighbor_max)
        });
        let mut pass = fg.pass(name("gather"), self.owner);
        let source = pass.read(&self.source.name);
        let depth = pass.read(&t.depth);
        let velocity_uv = pass.read(&t.velocity_uv);
        let neighbor_max = pass.read(&self.neighbor_max);
        let output = pass.write(&self.output, desc);
        pass.run(move |cx| {
            cx.count(BLURRED, 1);
            let b = Bindings::new()
                .texture("source", source)
                .texture("depth", depth)
                .texture("velocity_uv", velocity_uv)
                .texture("tiles_in", neighbor_max)
                .texture("output", output);
            self.run(cx, "main", b, output)
        });
    }
}
