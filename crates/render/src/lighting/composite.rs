//! `CompositeLight`: CookTorrance's components and an ambient term into one
//! HDR image (later: emission, AO, GI and reflections, weighted per material).

use std::sync::Arc;

use wgpu::util::DeviceExt;

use crate::error::RenderError;
use crate::frame_graph::{FrameGraph, PassContext, TextureDesc};
use crate::gbuffer::GBuffer;
use crate::recipe::{Recipe, TextureRef, next_recipe_id};
use crate::renderer::Renderer;
use crate::shaders::ShaderKey;

pub struct CompositeLight {
    id: u64,
    owner: Option<u32>,
    gbuffer: Arc<GBuffer>,
    diffuse: TextureRef,
    specular: TextureRef,
    params: wgpu::Buffer,
    pub output: String,
}

impl CompositeLight {
    pub fn new(
        renderer: &Renderer,
        owner: Option<u32>,
        gbuffer: Arc<GBuffer>,
        diffuse: TextureRef,
        specular: TextureRef,
        ambient: [f32; 3],
    ) -> Arc<Self> {
        let id = next_recipe_id();
        let ambient = ambient.map(|a| {
            if a.is_finite() {
                a.clamp(0.0, 65000.0)
            } else {
                0.0
            }
        });
        let params = renderer
            .gpu
            .device
            .create_buffer_init(&wgpu::util::BufferInitDescriptor {
                label: Some("composite params"),
                contents: bytemuck::cast_slice(&[ambient[0], ambient[1], ambient[2], 0.0]),
                usage: wgpu::BufferUsages::UNIFORM,
            });
        Arc::new(CompositeLight {
            id,
            owner,
            gbuffer,
            diffuse,
            specular,
            params,
            output: format!("composite{id}"),
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
        let key = ShaderKey::new("lighting/composite.wgsl", []);
        let pipeline = cx.shaders.compute_pipeline(&device, &key, "main")?;
        let g = &self.gbuffer.targets;
        let views = [
            cx.view(&g.color)?,
            cx.view(&self.diffuse.name)?,
            cx.view(&self.specular.name)?,
            cx.view(&g.depth)?,
            cx.view(&self.output)?,
        ];
        let all = [
            (0, self.gbuffer.camera_buffer().as_entire_binding()),
            (1, self.params.as_entire_binding()),
            (2, wgpu::BindingResource::TextureView(&views[0])),
            (3, wgpu::BindingResource::TextureView(&views[1])),
            (4, wgpu::BindingResource::TextureView(&views[2])),
            (5, wgpu::BindingResource::TextureView(&views[3])),
            (6, wgpu::BindingResource::TextureView(&views[4])),
        ];
        let group = cx
            .shaders
            .bind_group(&device, &key, "main", &pipeline, 0, &all)?;
        let (w, h) = self.gbuffer.pixel_size(cx.output_size);
        let timestamps = cx.compute_timestamps();
        let mut pass = cx.encoder.begin_compute_pass(&wgpu::ComputePassDescriptor {
            label: Some("composite"),
            timestamp_writes: timestamps,
        });
        pass.set_pipeline(&pipeline);
        pass.set_bind_group(0, &group, &[]);
        pass.dispatch_workgroups(w.div_ceil(8), h.div_ceil(8), 1);
        Ok(())
    }
}

impl Recipe for CompositeLight {
    fn declare<'a>(&'a self, renderer: &'a Renderer, fg: &mut FrameGraph<'a>) {
        if !fg.include(self.id) {
            return;
        }
        self.gbuffer.declare(renderer, fg);
        self.diffuse.recipe.declare(renderer, fg);
        self.specular.recipe.declare(renderer, fg);
        let name = match self.owner {
            Some(node) => format!("CompositeLight #{node}"),
            None => "CompositeLight".to_owned(),
        };
        let g = &self.gbuffer.targets;
        fg.add_pass(
            name,
            self.owner,
            &[&g.color, &g.depth, &self.diffuse.name, &self.specular.name],
            &[(
                &self.output,
                TextureDesc::storage(wgpu::TextureFormat::Rgba16Float).size(self.gbuffer.size),
            )],
            move |cx| self.run(cx),
        );
    }
}
