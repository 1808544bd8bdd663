//! GBufferView: one channel of a G-buffer as a displayable texture. It reads
//! only the target its channel lives in, so the other resolve is culled.

use std::sync::Arc;

use crate::error::RenderError;
use crate::frame_graph::{Bindings, FrameGraph, PassContext, Tex, TextureDesc};
use crate::recipe::{Recipe, TextureRef, next_recipe_id};
use crate::renderer::Renderer;
use crate::report::PassName;
use crate::shaders::Permutation;

use super::GBuffer;
pub use super::view_key::Channel;

impl Channel {
    /// The target this channel lives in.
    fn source(self, g: &GBuffer) -> &str {
        match self {
            Channel::Albedo | Channel::MaterialId => &g.targets.color,
            Channel::Normals | Channel::ObjectId => &g.targets.normals,
            Channel::Velocity | Channel::Uv => &g.targets.velocity_uv,
            Channel::Depth => &g.targets.depth,
        }
    }
}

pub struct GBufferView {
    id: u64,
    owner: Option<u32>,
    gbuffer: Arc<GBuffer>,
    channel: Channel,
    output: String,
    params: wgpu::Buffer,
}

impl GBufferView {
    pub fn new(
        renderer: &Renderer,
        owner: Option<u32>,
        gbuffer: Arc<GBuffer>,
        channel: Channel,
        velocity_scale: f32,
    ) -> Arc<Self> {
        let id = next_recipe_id();
        let params = renderer.kept_init(
            owner,
            "gbuffer view params",
            bytemuck::cast_slice(&[velocity_scale, 0.0, 0.0, 0.0]),
            wgpu::BufferUsages::UNIFORM,
        );
        Arc::new(GBufferView {
            id,
            owner,
            gbuffer,
            channel,
            output: format!("gbufferview{id}"),
            params,
        })
    }

    pub fn texture(self: &Arc<Self>) -> TextureRef {
        TextureRef {
            recipe: self.clone(),
            name: self.output.clone(),
        }
    }

    fn run(&self, cx: &mut PassContext<'_>, source: Tex, output: Tex) -> Result<(), RenderError> {
        let key = self.channel.key();
        let size = cx.size_of(output)?;
        // The layout is derived from the permutation: only the velocity view
        // reads its parameters, the others leave them out.
        cx.dispatch_image(
            "gbuffer view",
            &key,
            Bindings::new()
                .buffer("camera", self.gbuffer.camera_buffer())
                .buffer("params", &self.params)
                .texture("source", source)
                .texture("output", output),
            size,
        )
    }
}

impl Recipe for GBufferView {
    fn declare<'a>(&'a self, renderer: &'a Renderer, fg: &mut FrameGraph<'a>) {
        if !fg.include(self.id) {
            return;
        }
        self.gbuffer.declare(renderer, fg);
        let name = PassName::new("GBufferView").step(self.channel.name());
        let desc = TextureDesc::storage(wgpu::TextureFormat::Rgba16Float).size(self.gbuffer.size);
        let mut pass = fg.pass(name, self.owner);
        let source = pass.read(self.channel.source(&self.gbuffer));
        let output = pass.write(&self.output, desc);
        // Its pipeline, made on a thread on a first frame (frame_graph/gather.rs).
        if pass.graph().gathers_pipelines() {
            pass.will_dispatch(&self.channel.key(), "main");
        }
        pass.run(move |cx| self.run(cx, source, output));
    }
}
