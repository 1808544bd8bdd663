//! Rough refraction's mip chain (`RefractionBlur::Mips`): the opaque lit
//! image copied into a half-float texture with every mip level, each a box
//! average of the one above, built by one compute pass
//! (`post/transparency.wgsl`: `refraction_mips_first` writes levels 0 and
//! 1, `refraction_mips_down` each level after) only in frames where a layer
//! refracts. The accumulation then blurs by roughness with one trilinear
//! read at the level whose filter is as wide as the taps' disc, as
//! Filament blurs screen-space refraction, instead of N taps.
//!
//! Why a copy: the opaque image can be any float format (an Rgba32Float
//! cannot be filtered without a device feature), and a mip chain needs
//! levels of its own anyway. The texture and its sampler are kept per node
//! across frames (a new one only when the size changes), as SSR keeps its
//! hierarchical depth.

use std::sync::Mutex;

use super::TransparencyKey;
use crate::context::GpuContext;
use crate::error::RenderError;
use crate::frame_graph::{Bindings, PassContext, Tex};
use crate::shaders::Permutation;
use crate::texture_pool::ViewSpec;

/// Counted once per frame the chain was built: 0 when nothing refracts or
/// every refracting layer blurs by taps.
pub const MIP_CHAINS: &str = "transparency refraction mip chains";

const FORMAT: wgpu::TextureFormat = wgpu::TextureFormat::Rgba16Float;

/// The chain and its trilinear sampler, kept across frames.
#[derive(Default)]
pub(super) struct RefractionMips(Mutex<Option<(wgpu::Texture, wgpu::Sampler)>>);

impl RefractionMips {
    /// The chain for an opaque image of `size` (made or remade when the size
    /// changed) and the sampler that blends between its levels.
    pub(super) fn get(&self, gpu: &GpuContext, size: (u32, u32)) -> (wgpu::Texture, wgpu::Sampler) {
        let mut kept = self.0.lock().unwrap_or_else(|e| e.into_inner());
        if let Some((t, s)) = kept.as_ref()
            && (t.width(), t.height()) == size
        {
            return (t.clone(), s.clone());
        }
        let (w, h) = (size.0.max(1), size.1.max(1));
        let levels = crate::texture::mips::level_count(w, h);
        let texture = gpu.device.create_texture(&wgpu::TextureDescriptor {
            label: Some("transparency refraction mips"),
            size: wgpu::Extent3d {
                width: w,
                height: h,
                depth_or_array_layers: 1,
            },
            mip_level_count: levels,
            sample_count: 1,
            dimension: wgpu::TextureDimension::D2,
            format: FORMAT,
            usage: wgpu::TextureUsages::TEXTURE_BINDING | wgpu::TextureUsages::STORAGE_BINDING,
            view_formats: &[],
        });
        // Trilinear and clamped: a fractional level blends the two either
        // side, and the border repeats the edge as the taps' clamp does.
        let sampler = gpu.device.create_sampler(&wgpu::SamplerDescriptor {
            label: Some("transparency refraction mips"),
            address_mode_u: wgpu::AddressMode::ClampToEdge,
            address_mode_v: wgpu::AddressMode::ClampToEdge,
            mag_filter: wgpu::FilterMode::Linear,
            min_filter: wgpu::FilterMode::Linear,
            mipmap_filter: wgpu::MipmapFilterMode::Linear,
            ..Default::default()
        });
        *kept = Some((texture.clone(), sampler.clone()));
        (texture, sampler)
    }
}

/// Builds every level of `mips` from `source` (the opaque image, any float
/// format): one compute pass, a dispatch per level after the first two.
pub(super) fn build(
    cx: &mut PassContext<'_>,
    source: Tex,
    mips: &wgpu::Texture,
) -> Result<(), RenderError> {
    let device = cx.gpu.device.clone();
    let key = TransparencyKey::COMPOSITE.key();
    let levels = mips.mip_level_count() as usize;
    let level = |m: usize| cx.view_of(mips, ViewSpec::mip(m as u32));
    // Each step: its entry point, bindings and the level its threads cover
    // (a thread per texel of the last level it writes).
    let mut plan: Vec<(&'static str, Bindings<'_>, usize)> = Vec::new();
    if levels == 1 {
        // A 1x1 image: the copy alone (the first step writes two levels).
        let b = Bindings::new()
            .texture("mips_image", source)
            .view("mips_out", level(0));
        plan.push(("refraction_mips_copy", b, 0));
    } else {
        let b = Bindings::new()
            .texture("mips_image", source)
            .view("mips_out", level(0))
            .view("mips_out_next", level(1));
        plan.push(("refraction_mips_first", b, 1));
        for m in 2..levels {
            let b = Bindings::new()
                .view("mips_source", level(m - 1))
                .view("mips_out", level(m));
            plan.push(("refraction_mips_down", b, m));
        }
    }
    let (w, h) = (mips.width(), mips.height());
    let mut steps = Vec::with_capacity(plan.len());
    for (entry, bindings, m) in plan {
        let pipeline = cx.shaders.compute_pipeline(&device, &key, entry)?;
        let groups = cx.bind_groups(&key, entry, &pipeline, bindings)?;
        let (x, y) = ((w >> m).max(1), (h >> m).max(1));
        steps.push((pipeline, groups, (x.div_ceil(8), y.div_ceil(8))));
    }
    cx.count(MIP_CHAINS, 1);
    let pass = cx.compute_pass("transparency refraction mips");
    for (pipeline, groups, (x, y)) in &steps {
        pass.set_pipeline(pipeline);
        for (i, group) in groups.iter().enumerate() {
            pass.set_bind_group(i as u32, group, &[]);
        }
        pass.dispatch_workgroups(*x, *y, 1);
    }
    Ok(())
}
