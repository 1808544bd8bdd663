//! SSR's hierarchical depth: mip 0 the G-buffer's reversed-Z depth, each
//! further mip the nearest (max) of the texels under it, two levels a
//! dispatch and the small ones in one workgroup
//! (shaders/environment/ssr.wgsl, `hiz_first` / `hiz_down2` / `hiz_tail`).

use super::super::prefilter::split_sum_table;
use super::{Ssr, SsrKey};
use crate::error::RenderError;
use crate::frame_graph::{PassContext, Tex};
use crate::mip_chain::{MipChainShader, MipTail};
use crate::shaders::Permutation;

/// Statistic: the dispatches that built the hierarchical depth (two levels
/// each where they can, the small levels in one).
pub const HIZ_DISPATCHES: &str = "SSR hi-z dispatches";

/// The hi-z's entry points and bindings in `environment/ssr.wgsl`: two
/// levels a dispatch where it can, and, where the chain and the device
/// allow a tail (mip_chain.rs), every level from the first after mip 1 of
/// at most 32 a side in one workgroup.
const SHADER: MipChainShader = MipChainShader {
    copy: "hiz_copy",
    first: "hiz_first",
    down: "hiz_down",
    down2: Some("hiz_down2"),
    tail: Some(MipTail {
        entry: "hiz_tail",
        outs: [
            "out_tail_0",
            "out_tail_1",
            "out_tail_2",
            "out_tail_3",
            "out_tail_4",
            "out_tail_5",
        ],
    }),
    source: "depth",
    level_in: "hiz_source",
    out: "out_hiz",
    out_next: "out_hiz_next",
};

impl Ssr {
    fn hiz_texture(&self, cx: &PassContext<'_>, size: (u32, u32)) -> wgpu::Texture {
        let mut guard = self.store.hiz.lock().unwrap_or_else(|e| e.into_inner());
        if let Some(t) = guard.as_ref()
            && (t.width(), t.height()) == size
        {
            return t.clone();
        }
        let t = crate::mip_chain::texture(
            &cx.gpu.device,
            "ssr hi-z",
            size,
            wgpu::TextureFormat::R32Float,
            // COPY_SRC: tests read its levels back ([`Ssr::hi_z`]).
            wgpu::TextureUsages::TEXTURE_BINDING
                | wgpu::TextureUsages::STORAGE_BINDING
                | wgpu::TextureUsages::COPY_SRC,
        );
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
        // Each level's view, kept across frames (so are the bind groups over them).
        let levels: Vec<wgpu::TextureView> = (0..hiz.mip_level_count())
            .map(|m| cx.view_of(&hiz, crate::texture_pool::ViewSpec::mip(m)))
            .collect();
        let dispatches =
            SHADER.build(cx, &SsrKey::PLAIN.key(), "ssr hi-z", depth, &levels, size)?;
        cx.count(HIZ_DISPATCHES, dispatches);
        Ok(())
    }
}
