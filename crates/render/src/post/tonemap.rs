//! `Tonemap`: exposure and one of Emeshe's operators (plus ACES and AgX),
//! HDR in, display-referred linear 0..1 out. The operator maths lives in
//! shaders/lib/tonemap.wgsl and, for tests, in `crate::reference::tonemap`.

use std::sync::Arc;

use wgpu::util::DeviceExt;

use crate::error::RenderError;
use crate::frame_graph::{FrameGraph, PassContext, SizeRule, TextureDesc};
use crate::recipe::{Recipe, TextureRef, next_recipe_id};
use crate::renderer::Renderer;
use crate::shaders::ShaderKey;

pub struct Tonemap {
    id: u64,
    owner: Option<u32>,
    source: TextureRef,
    params: wgpu::Buffer,
    pub output: String,
}

impl Tonemap {
    /// `operator` is one of `reference::tonemap`'s `TONEMAP_*` ids; `exposure` a linear multiplier.
    pub fn new(
        renderer: &Renderer,
        owner: Option<u32>,
        source: TextureRef,
        operator: u32,
        exposure: f32,
        param: f32,
    ) -> Arc<Self> {
        let id = next_recipe_id();
        let finite = |v: f32, fallback: f32| if v.is_finite() { v } else { fallback };
        let params = renderer
            .gpu
            .device
            .create_buffer_init(&wgpu::util::BufferInitDescriptor {
                label: Some("tonemap params"),
                contents: bytemuck::cast_slice(&[
                    operator,
                    finite(exposure, 1.0).max(0.0).to_bits(),
                    finite(param, 1.0).to_bits(),
                    0,
                ]),
                usage: wgpu::BufferUsages::UNIFORM,
            });
        Arc::new(Tonemap {
            id,
            owner,
            source,
            params,
            output: format!("tonemap{id}"),
        })
    }

    pub fn texture(self: &Arc<Self>) -> TextureRef {
        TextureRef {
            recipe: self.clone(),
            name: self.output.clone(),
        }
    }

    fn run(&self, cx: &mut PassContext<'_>) -> Result<(), RenderError> {
        let device = cx.gpu.device.clone();
        let key = ShaderKey::new("post/tonemap.wgsl", []);
        let pipeline = cx.shaders.compute_pipeline(&device, &key, "main")?;
        let (source, output) = (cx.view(&self.source.name)?, cx.view(&self.output)?);
        let (w, h) = {
            let t = cx.texture(&self.output)?;
            (t.width(), t.height())
        };
        let all = [
            (0, self.params.as_entire_binding()),
            (1, wgpu::BindingResource::TextureView(&source)),
            (2, wgpu::BindingResource::TextureView(&output)),
        ];
        let group = cx
            .shaders
            .bind_group(&device, &key, "main", &pipeline, 0, &all)?;
        let timestamps = cx.compute_timestamps();
        let mut pass = cx.encoder.begin_compute_pass(&wgpu::ComputePassDescriptor {
            label: Some("tonemap"),
            timestamp_writes: timestamps,
        });
        pass.set_pipeline(&pipeline);
        pass.set_bind_group(0, &group, &[]);
        pass.dispatch_workgroups(w.div_ceil(8), h.div_ceil(8), 1);
        Ok(())
    }
}

impl Recipe for Tonemap {
    fn declare<'a>(&'a self, renderer: &'a Renderer, fg: &mut FrameGraph<'a>) {
        if !fg.include(self.id) {
            return;
        }
        self.source.recipe.declare(renderer, fg);
        let name = match self.owner {
            Some(node) => format!("Tonemap #{node}"),
            None => "Tonemap".to_owned(),
        };
        let desc =
            TextureDesc::storage(wgpu::TextureFormat::Rgba16Float).size(SizeRule::Relative(1.0));
        fg.add_pass(
            name,
            self.owner,
            &[&self.source.name],
            &[(&self.output, desc)],
            move |cx| self.run(cx),
        );
    }
}
