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
use crate::frame_graph::{PassContext, Tex};
use crate::mip_chain::MipChainShader;
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
        let texture = crate::mip_chain::texture(
            &gpu.device,
            "transparency refraction mips",
            size,
            FORMAT,
            wgpu::TextureUsages::TEXTURE_BINDING | wgpu::TextureUsages::STORAGE_BINDING,
        );
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

/// The chain's entry points and bindings in `post/transparency.wgsl`: one
/// level a dispatch (a box average has no `down2`).
const SHADER: MipChainShader = MipChainShader {
    copy: "refraction_mips_copy",
    first: "refraction_mips_first",
    down: "refraction_mips_down",
    down2: None,
    tail: None,
    source: "mips_image",
    level_in: "mips_source",
    out: "mips_out",
    out_next: "mips_out_next",
};

/// Builds every level of `mips` from `source` (the opaque image, any float
/// format): one compute pass, a dispatch per level after the first two.
pub(super) fn build(
    cx: &mut PassContext<'_>,
    source: Tex,
    mips: &wgpu::Texture,
) -> Result<(), RenderError> {
    let levels: Vec<wgpu::TextureView> = (0..mips.mip_level_count())
        .map(|m| cx.view_of(mips, ViewSpec::mip(m)))
        .collect();
    let key = TransparencyKey::COMPOSITE.key();
    let size = (mips.width(), mips.height());
    SHADER.build(
        cx,
        &key,
        "transparency refraction mips",
        source,
        &levels,
        size,
    )?;
    cx.count(MIP_CHAINS, 1);
    Ok(())
}
