//! `Autofocus`: the focus distance from the depth under a screen point,
//! smoothed over time in a persistent 1x1 R32Float texture that holds the
//! *inverse* distance (shaders/post/autofocus.wgsl). `DOF` reads it on the
//! GPU (its AUTOFOCUS permutation), so focusing never waits for a readback.
//! The persistent target is named after the node, as `EyeAdaptation`'s is;
//! it is fresh (the measurement is taken as it is) on the first frame and
//! after `Renderer::reset_history`.

use std::sync::Arc;

use glam::Vec2;

use crate::error::RenderError;
use crate::frame_graph::{Bindings, FrameGraph, Lifetime, PassContext, SizeRule, Tex, TextureDesc};
use crate::gbuffer::GBuffer;
use crate::post::eye_adaptation::AdaptationSettings;
use crate::recipe::{Recipe, TextureRef, next_recipe_id};
use crate::renderer::Renderer;
use crate::report::PassName;
use crate::shaders::Permutation;

pub use super::autofocus_key::AutofocusKey;

const FORMAT: wgpu::TextureFormat = wgpu::TextureFormat::R32Float;
const ONE: SizeRule = SizeRule::Absolute {
    width: 1,
    height: 1,
};

pub struct Autofocus {
    id: u64,
    owner: Option<u32>,
    gbuffer: Arc<GBuffer>,
    point: Vec2,
    rate: f32,
    params: wgpu::Buffer,
    previous: String,
    /// The persistent 1x1 inverse focus distance.
    pub output: String,
}

impl Autofocus {
    /// `point` in UV (0..1, y down); `speed` per second (infinite: no smoothing);
    /// `delta` the frame's time step in seconds.
    pub fn new(
        renderer: &Renderer,
        owner: Option<u32>,
        gbuffer: Arc<GBuffer>,
        point: Vec2,
        speed: f32,
        delta: f64,
    ) -> Arc<Self> {
        let history = match owner {
            Some(node) => format!("autofocus #{node}"),
            None => format!("autofocus{}", next_recipe_id()),
        };
        Self::with_history(renderer, owner, gbuffer, point, speed, delta, history)
    }

    /// As [`Autofocus::new`], with the persistent target's name given (tests run several frames without a node).
    pub fn with_history(
        renderer: &Renderer,
        owner: Option<u32>,
        gbuffer: Arc<GBuffer>,
        point: Vec2,
        speed: f32,
        delta: f64,
        history: String,
    ) -> Arc<Self> {
        let id = next_recipe_id();
        let point = if point.is_finite() {
            point.clamp(Vec2::ZERO, Vec2::ONE)
        } else {
            Vec2::splat(0.5)
        };
        Arc::new(Autofocus {
            id,
            owner,
            gbuffer,
            point,
            rate: AdaptationSettings::rate(speed, delta),
            params: super::uniform(renderer, owner, "autofocus", &[0; 4]),
            previous: format!("autofocus{id} previous"),
            output: history,
        })
    }

    pub fn texture(self: &Arc<Self>) -> TextureRef {
        TextureRef {
            recipe: self.clone(),
            name: self.output.clone(),
        }
    }

    fn run(&self, cx: &mut PassContext<'_>, io: &AutofocusIo) -> Result<(), RenderError> {
        let fresh = cx.is_fresh(io.output);
        cx.gpu.queue.write_buffer(
            &self.params,
            0,
            bytemuck::cast_slice(&[
                self.point.x,
                self.point.y,
                self.rate,
                if fresh { 1.0 } else { 0.0 },
            ]),
        );
        // Last frame's value through a copy: one dispatch cannot read and write a texture.
        let (last, copy) = (
            cx.texture(io.output)?.clone(),
            cx.texture(io.previous)?.clone(),
        );
        cx.encoder().copy_texture_to_texture(
            last.as_image_copy(),
            copy.as_image_copy(),
            wgpu::Extent3d {
                width: 1,
                height: 1,
                depth_or_array_layers: 1,
            },
        );
        cx.dispatch_image(
            "autofocus",
            &AutofocusKey.key(),
            Bindings::new()
                .buffer("camera", self.gbuffer.camera_buffer())
                .buffer("params", &self.params)
                .texture("depth", io.depth)
                .texture("previous", io.previous)
                .texture("output", io.output),
            (1, 1),
        )
    }
}

/// What the autofocus pass declared: the persistent output and the copy
/// of last frame's value it reads.
struct AutofocusIo {
    depth: Tex,
    previous: Tex,
    output: Tex,
}

impl Recipe for Autofocus {
    fn declare<'a>(&'a self, renderer: &'a Renderer, fg: &mut FrameGraph<'a>) {
        if !fg.include(self.id) {
            return;
        }
        self.gbuffer.declare(renderer, fg);
        let target = TextureDesc {
            format: FORMAT,
            size: ONE,
            lifetime: Lifetime::Persistent,
            usage: wgpu::TextureUsages::STORAGE_BINDING
                | wgpu::TextureUsages::TEXTURE_BINDING
                | wgpu::TextureUsages::COPY_SRC,
            only_if_read: false,
        };
        let previous = TextureDesc {
            format: FORMAT,
            size: ONE,
            lifetime: Lifetime::Temporary,
            usage: wgpu::TextureUsages::TEXTURE_BINDING | wgpu::TextureUsages::COPY_DST,
            only_if_read: false,
        };
        let mut pass = fg.pass(PassName::new("Autofocus"), self.owner);
        let io = AutofocusIo {
            depth: pass.read(&self.gbuffer.targets.depth),
            output: pass.write(&self.output, target),
            previous: pass.write(&self.previous, previous),
        };
        pass.will_dispatch(&AutofocusKey.key(), "main");
        pass.run(move |cx| self.run(cx, &io));
    }
}
