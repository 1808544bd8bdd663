//! `PassChain` (category "Bench"): a chain of Passes passes that do almost
//! nothing on the GPU, to measure the frame graph's CPU cost per pass
//! (`patches/bench-pass-chain.ron`; spreadlight_render::bench::pass_chain).

use std::sync::Arc;

use spreadlight_graph::{NodeDef, PinType, Registry, ResourceKind};
use spreadlight_render::bench::pass_chain::{MAX_PASSES, PassChain};

use crate::gpu::{renderer, resource_spread};

pub fn register(r: &mut Registry) {
    r.add(
        NodeDef::new(
            "PassChain",
            "Bench",
            "A chain of Passes compute passes, each reading the texture the one before wrote (64x64, so the GPU's \
             share is negligible): what a frame's CPU time grows by per graph pass. The result is a ramp turned \
             once per pass.",
        )
        .input("Passes", 200i64)
        .output_typed("Texture", PinType::Resource(ResourceKind::Texture))
        .evaluate(|cx| {
            let passes = cx.slices::<i64>(0)?.first().copied().unwrap_or(200);
            let passes = u32::try_from(passes)
                .ok()
                .filter(|p| (1..=MAX_PASSES).contains(p))
                .ok_or_else(|| cx.input_error(0, format!("is {passes}; it must be 1..={MAX_PASSES}")))?;
            let renderer = renderer(cx)?;
            let chain = PassChain::new(&renderer, Some(cx.node_id.0), passes);
            cx.set_output(
                0,
                resource_spread(ResourceKind::Texture, vec![Arc::new(chain.texture())]),
            );
            Ok(())
        }),
    );
}
