//! The typed key of `PassChain`, [`PassChainKey`] (`bench/pass_chain.wgsl`). It stands in a file of
//! its own that imports no pass, so that `shaders::SHADERS` names it without a circle through the
//! renderer (docs/architecture.md, "Layers inside render"); `bench/pass_chain.rs` re-exports it.

crate::flag_key! {
    /// `bench/pass_chain.wgsl`: one permutation.
    pub struct PassChainKey("bench/pass_chain.wgsl");
}
