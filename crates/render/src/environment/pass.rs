//! What the environment passes share: one compute dispatch per pixel that
//! reads the lit image, the G-buffer's depth and camera, and a uniform of
//! its own, and writes a new image of the G-buffer's size.

use std::sync::Arc;

use super::environment_map::Environment;
use crate::error::RenderError;
use crate::frame_graph::{FrameGraph, PassContext, TextureDesc};
use crate::gbuffer::GBuffer;
use crate::recipe::{Recipe, TextureRef, next_recipe_id};
use crate::renderer::Renderer;
use crate::shaders::ShaderKey;
use crate::texture_pool::ViewSpec;

/// A pass over the lit image: bindings 0 camera, 1 `params`, 2 the image,
/// 3 depth, 4 the output (shaders/environment/*.wgsl).
pub struct ImagePass {
    id: u64,
    owner: Option<u32>,
    /// The node type, for pass names ("Sky #12").
    name: &'static str,
    shader: &'static str,
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
        (name, shader): (&'static str, &'static str),
        gbuffer: Arc<GBuffer>,
        source: TextureRef,
        params: &[u8],
    ) -> Arc<Self> {
        let id = next_recipe_id();
        let params = renderer.uniform(owner, name, params);
        Arc::new(ImagePass {
            id,
            owner,
            name,
            shader,
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

    fn run(&self, cx: &mut PassContext<'_>) -> Result<(), RenderError> {
        let (source, depth, output) = (
            cx.view(&self.source.name)?,
            cx.view(&self.gbuffer.targets.depth)?,
            cx.view(&self.output)?,
        );
        let mut all = vec![
            (0, self.gbuffer.camera_buffer().as_entire_binding()),
            (1, self.params.as_entire_binding()),
            (2, wgpu::BindingResource::TextureView(&source)),
            (3, wgpu::BindingResource::TextureView(&depth)),
            (4, wgpu::BindingResource::TextureView(&output)),
        ];
        let maps = match &self.environment {
            Some(e) => Some(e.maps_for(self.name)?),
            None => None,
        };
        let cube = maps.as_ref().map(|m| cx.view_of(&m.base, ViewSpec::cube()));
        if let (Some(maps), Some(cube)) = (&maps, &cube) {
            all.push((5, wgpu::BindingResource::TextureView(cube)));
            all.push((6, wgpu::BindingResource::Sampler(&maps.sampler)));
        }
        let features: &[&'static str] = if maps.is_some() {
            &["ENVIRONMENT"]
        } else {
            &[]
        };
        let size = self.gbuffer.pixel_size(cx.output_size);
        cx.dispatch_image(
            self.name,
            &ShaderKey::new(self.shader, features.iter().copied()),
            &all,
            size,
        )
    }
}

impl Recipe for ImagePass {
    fn declare<'a>(&'a self, renderer: &'a Renderer, fg: &mut FrameGraph<'a>) {
        if !fg.include(self.id) {
            return;
        }
        self.gbuffer.declare(renderer, fg);
        self.source.recipe.declare(renderer, fg);
        let mut reads = vec![
            self.source.name.as_str(),
            self.gbuffer.targets.depth.as_str(),
        ];
        if let Some(environment) = &self.environment {
            environment.declare(renderer, fg);
            reads.push(environment.token());
        }
        let name = crate::recipe::pass_name(self.name, self.owner, None);
        let desc = TextureDesc::storage(wgpu::TextureFormat::Rgba16Float).size(self.gbuffer.size);
        fg.add_pass(
            name,
            self.owner,
            &reads,
            &[(&self.output, desc)],
            move |cx| self.run(cx),
        );
    }
}
