//! SSR's hierarchical depth: mip 0 the G-buffer's reversed-Z depth, each
//! further mip the nearest (max) of the texels under it, two levels a
//! dispatch (shaders/environment/ssr.wgsl, `hiz_first` / `hiz_down2`).

use super::super::prefilter::split_sum_table;
use super::{Ssr, SsrKey};
use crate::error::RenderError;
use crate::frame_graph::{Bindings, PassContext, Tex};
use crate::shaders::Permutation;

/// Statistic: the dispatches that built the hierarchical depth (two levels
/// each where they can).
pub const HIZ_DISPATCHES: &str = "SSR hi-z dispatches";

impl Ssr {
    fn hiz_texture(&self, cx: &PassContext<'_>, size: (u32, u32)) -> wgpu::Texture {
        let mut guard = self.store.hiz.lock().unwrap_or_else(|e| e.into_inner());
        if let Some(t) = guard.as_ref()
            && (t.width(), t.height()) == size
        {
            return t.clone();
        }
        let mips = size.0.max(size.1).max(1).ilog2() + 1;
        let t = cx.gpu.device.create_texture(&wgpu::TextureDescriptor {
            label: Some("ssr hi-z"),
            size: wgpu::Extent3d {
                width: size.0,
                height: size.1,
                depth_or_array_layers: 1,
            },
            mip_level_count: mips,
            sample_count: 1,
            dimension: wgpu::TextureDimension::D2,
            format: wgpu::TextureFormat::R32Float,
            // COPY_SRC: tests read its levels back ([`Ssr::hi_z`]).
            usage: wgpu::TextureUsages::TEXTURE_BINDING
                | wgpu::TextureUsages::STORAGE_BINDING
                | wgpu::TextureUsages::COPY_SRC,
            view_formats: &[],
        });
        *guard = Some(t.clone());
        t
    }

    pub(super) fn build_hiz(
        &self,
        cx: &mut PassContext<'_>,
        depth: Tex,
    ) -> Result<(), RenderError> {
        let size = self.gbuffer.pixel_size(cx.output_size);
        let hiz = self.hiz_texture(cx, size);
        split_sum_table(cx, &self.table)?;
        let device = cx.gpu.device.clone();
        let key = SsrKey::PLAIN.key();
        // Each level's view, kept across frames (so are the bind groups over them).
        let mips: Vec<wgpu::TextureView> = (0..hiz.mip_level_count())
            .map(|m| cx.view_of(&hiz, crate::texture_pool::ViewSpec::mip(m)))
            .collect();
        let levels = mips.len();
        let mip = |m: usize| mips[m].clone();
        // Two levels a dispatch where it can (shaders/environment/ssr.wgsl):
        // each step's entry point, what it binds and the last level it writes.
        let mut plan: Vec<(&str, Bindings<'_>, usize)> = Vec::new();
        let mut made = 0;
        if levels == 1 {
            let b = Bindings::new()
                .texture("depth", depth)
                .view("out_hiz", mip(0));
            plan.push(("hiz_copy", b, 0));
        } else {
            let b = Bindings::new()
                .texture("depth", depth)
                .view("out_hiz", mip(0))
                .view("out_hiz_next", mip(1));
            plan.push(("hiz_first", b, 1));
            made = 1;
        }
        while made + 2 < levels {
            let b = Bindings::new()
                .view("hiz_source", mip(made))
                .view("out_hiz", mip(made + 1))
                .view("out_hiz_next", mip(made + 2));
            plan.push(("hiz_down2", b, made + 2));
            made += 2;
        }
        if made + 1 < levels {
            let b = Bindings::new()
                .view("hiz_source", mip(made))
                .view("out_hiz", mip(made + 1));
            plan.push(("hiz_down", b, made + 1));
        }
        let mut steps = Vec::with_capacity(plan.len());
        for (entry, bindings, level) in plan {
            let pipeline = cx.shaders.compute_pipeline(&device, &key, entry)?;
            let groups = cx.bind_groups(&key, entry, &pipeline, bindings)?;
            let (w, h) = ((size.0 >> level).max(1), (size.1 >> level).max(1));
            steps.push((pipeline, groups, (w.div_ceil(8), h.div_ceil(8))));
        }
        cx.count(HIZ_DISPATCHES, steps.len() as u64);
        let pass = cx.compute_pass("ssr hi-z");
        for (pipeline, groups, (x, y)) in &steps {
            pass.set_pipeline(pipeline);
            for (i, group) in groups.iter().enumerate() {
                pass.set_bind_group(i as u32, group, &[]);
            }
            pass.dispatch_workgroups(*x, *y, 1);
        }
        Ok(())
    }
}
