//! `PassChain` (category "Bench"): a chain of Passes passes that do almost
//! nothing on the GPU, to measure the frame graph's CPU cost per pass
//! (`patches/bench-pass-chain.ron`; spreadlight_render::bench::pass_chain).

use std::sync::Arc;

use spreadlight_graph::{NodeDef, Registry, ResourceKind};
use spreadlight_render::bench::pass_chain::{MAX_PASSES, PassChain};

use spreadlight_render::TextureRef;

use crate::gpu::renderer;

pub fn register(r: &mut Registry) {
    r.add(
        NodeDef::new(
            "PassChain",
            "Bench",
            "A chain of Passes compute passes, each reading the texture the one before wrote (64x64, so the GPU's \
             share is negligible): what a frame's CPU time grows by per graph pass. The result is a ramp turned \
             once per pass.",
        )
        .with_pins(|p| {
            let passes_in = p.input("Passes", 200i64);
            let texture = p.output_resource::<TextureRef>("Texture", ResourceKind::Texture);
            move |cx| {
                let passes = cx.first(passes_in, 200)?;
                let passes = u32::try_from(passes)
                    .ok()
                    .filter(|p| (1..=MAX_PASSES).contains(p))
                    .ok_or_else(|| cx.error(passes_in, format!("is {passes}; it must be 1..={MAX_PASSES}")))?;
                let renderer = renderer(cx)?;
                let chain = PassChain::new(&renderer, Some(cx.node_id.0), passes);
                cx.put_resources(texture, vec![Arc::new(chain.texture())]);
                Ok(())
            }
        }),
    );
}
