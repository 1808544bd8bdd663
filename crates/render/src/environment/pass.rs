//! What the environment passes share: one compute dispatch per pixel that
//! reads the lit image, the G-buffer's depth and camera, and a uniform of
//! its own, and writes a new image of the G-buffer's size.
//!
//! Fog and Sky touch disjoint pixels (surfaces, the empty background), so
//! one over the other is one pass (shaders/environment/sky.wgsl's FOG):
//! the outer declares its pass and asks the frame graph to chain it into
//! the inner's ([`FrameGraph::chains_into`]), which it does when nothing
//! else reads the inner's image.

use std::sync::Arc;

use super::environment_map::Environment;
use super::fog_key::FogKey;
use super::sky_key::SkyKey;
use crate::error::RenderError;
use crate::frame_graph::{Bindings, FrameGraph, PassContext, Tex, TextureDesc};
use crate::gbuffer::GBuffer;
use crate::recipe::{AsAny, Recipe, TextureRef, next_recipe_id};
use crate::renderer::Renderer;
use crate::report::PassName;
use crate::shaders::{Permutation, ShaderKey};
use crate::texture_pool::ViewSpec;

/// Which environment pass an [`ImagePass`] is.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum ImageKind {
    Fog,
    Sky,
}

impl ImageKind {
    /// The node type, for pass names ("Sky #12").
    fn name(self) -> &'static str {
        match self {
            ImageKind::Fog => "Fog",
            ImageKind::Sky => "Sky",
        }
    }

    /// Its shader's permutation. Only the Sky's reads an environment's cube
    /// or runs a Fog's parameters too (a Fog and a Sky in one pass run the
    /// Sky's shader, [`ImagePass::run_over`]).
    fn key(self, environment: bool, fog: bool) -> ShaderKey {
        match self {
            ImageKind::Fog => FogKey.key(),
            ImageKind::Sky => SkyKey { environment, fog }.key(),
        }
    }

    /// The WGSL variable of its parameters (the Sky's `FOG` permutation binds the Fog's too).
    fn params(self) -> &'static str {
        match self {
            ImageKind::Fog => "fog",
            ImageKind::Sky => "sky",
        }
    }
}

/// Counted when a Fog and a Sky over it (or under it) ran as one pass.
pub const FOG_AND_SKY: &str = "fog and sky in one pass";

/// A pass over the lit image: the camera, its parameters, the image, depth
/// and the output (shaders/environment/*.wgsl).
pub struct ImagePass {
    id: u64,
    owner: Option<u32>,
    kind: ImageKind,
    gbuffer: Arc<GBuffer>,
    source: TextureRef,
    params: wgpu::Buffer,
    pub output: String,
    /// The Sky's background from an environment (its ENVIRONMENT permutation, bindings 5 and 6).
    environment: Option<Arc<Environment>>,
}

impl ImagePass {
    pub(crate) fn new(
        renderer: &Renderer,
        owner: Option<u32>,
        kind: ImageKind,
        gbuffer: Arc<GBuffer>,
        source: TextureRef,
        params: &[u8],
    ) -> Arc<Self> {
        let id = next_recipe_id();
        let name = kind.name();
        let params = renderer.uniform(owner, name, params);
        Arc::new(ImagePass {
            id,
            owner,
            kind,
            gbuffer,
            source,
            params,
            output: format!("{}{id}", name.to_lowercase()),
            environment: None,
        })
    }

    /// This pass reading `environment` too (only the Sky's shader has the switch).
    pub(crate) fn with_environment(self: Arc<Self>, environment: Arc<Environment>) -> Arc<Self> {
        match Arc::try_unwrap(self) {
            Ok(mut pass) => {
                pass.environment = Some(environment);
                Arc::new(pass)
            }
            // Just made by `new`: nobody else holds it.
            Err(shared) => shared,
        }
    }

    pub fn texture(self: &Arc<Self>) -> TextureRef {
        TextureRef {
            recipe: self.clone(),
            name: self.output.clone(),
        }
    }

    /// This pass from `io.source` into `io.output`: its shader and
    /// parameters, its environment's cube, and with `fog` that pass's
    /// parameters in the Sky's `FOG` permutation.
    fn record(
        &self,
        cx: &mut PassContext<'_>,
        io: &ImageIo,
        fog: Option<&ImagePass>,
    ) -> Result<(), RenderError> {
        let mut b = Bindings::new()
            .buffer("camera", self.gbuffer.camera_buffer())
            .buffer(self.kind.params(), &self.params)
            .texture("source", io.source)
            .texture("depth", io.depth)
            .texture("output", io.output)
            .buffer_opt("fog", fog.map(|f| &f.params));
        let maps = match &self.environment {
            Some(e) => Some(e.maps_for(self.kind.name())?),
            None => None,
        };
        if let Some(maps) = &maps {
            b = b
                .view("environment", cx.view_of(&maps.base, ViewSpec::cube()))
                .sampler_object("environment_sampler", maps.sampler.clone());
        }
        let size = self.gbuffer.pixel_size(cx.output_size);
        cx.dispatch_image(
            self.kind.name(),
            &self.kind.key(maps.is_some(), fog.is_some()),
            b,
            size,
        )
    }

    /// The pass under this one when the two can be one: a Fog under a Sky
    /// or a Sky under a Fog, over the same G-buffer.
    fn over(&self) -> Option<&ImagePass> {
        let inner =
            <dyn Recipe as AsAny>::as_any(&*self.source.recipe).downcast_ref::<ImagePass>()?;
        (inner.kind != self.kind && Arc::ptr_eq(&inner.gbuffer, &self.gbuffer)).then_some(inner)
    }

    /// This pass and `inner` (the pass under it) in one dispatch: the Sky's
    /// over the inner pass's source (`io`), with the Fog's parameters.
    fn run_over(
        &self,
        inner: &ImagePass,
        cx: &mut PassContext<'_>,
        io: &ImageIo,
    ) -> Result<(), RenderError> {
        cx.count(FOG_AND_SKY, 1);
        let (fog, sky) = match self.kind {
            ImageKind::Fog => (self, inner),
            ImageKind::Sky => (inner, self),
        };
        // The Sky's shader and cube, whichever is outer; the outer's output.
        sky.record(cx, io, Some(fog))
    }
}

/// What an image pass declared (or, joint with the pass under it, what both did).
#[derive(Clone, Copy)]
struct ImageIo {
    source: Tex,
    depth: Tex,
    output: Tex,
}

impl Recipe for ImagePass {
    fn declare<'a>(&'a self, renderer: &'a Renderer, fg: &mut FrameGraph<'a>) {
        if !fg.include(self.id) {
            return;
        }
        self.gbuffer.declare(renderer, fg);
        // The environment before the source: its passes then come before
        // the source's, so a chain with the pass under this one can form.
        if let Some(environment) = &self.environment {
            environment.declare(renderer, fg);
        }
        self.source.recipe.declare(renderer, fg);
        let name = PassName::new(self.kind.name());
        let desc = TextureDesc::storage(wgpu::TextureFormat::Rgba16Float).size(self.gbuffer.size);
        let mut pass = fg.pass(name.clone(), self.owner);
        if let Some(environment) = &self.environment {
            pass.read(environment.token());
        }
        let io = ImageIo {
            source: pass.read(&self.source.name),
            depth: pass.read(&self.gbuffer.targets.depth),
            output: pass.write(&self.output, desc),
        };
        // The joint pass's pipeline where it can run joint with the pass
        // under it, as it does when the frame needs both (frame_graph/gather.rs).
        // A pass alone announces none: it cannot know whether a pass over
        // it will take it in, and a pipeline announced and not used is
        // made in vain at every start.
        if let Some(inner) = self.over() {
            let sky = match self.kind {
                ImageKind::Sky => self,
                ImageKind::Fog => inner,
            };
            pass.will_dispatch(&sky.kind.key(sky.environment.is_some(), true), "main");
        }
        pass.run(move |cx| self.record(cx, &io, None));
        // Its own pipeline only where the plan runs it alone.
        fg.will_dispatch_if_run(
            name,
            self.owner,
            &self.kind.key(self.environment.is_some(), false),
            "main",
        );
        if let Some(inner) = self.over() {
            // Of both kinds; the report names both nodes (owner and partner).
            let both = PassName::new(format!("{} and {}", inner.kind.name(), self.kind.name()));
            // The joint pass reads what the inner pass read.
            let io = ImageIo {
                source: fg.handle(&inner.source.name),
                ..io
            };
            fg.chains_into(&self.source.name, both, move |cx| {
                self.run_over(inner, cx, &io)
            });
        }
    }
}
