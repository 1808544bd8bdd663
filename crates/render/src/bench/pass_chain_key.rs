//! The typed key of `PassChain`, [`PassChainKey`] (`bench/pass_chain.wgsl`). It declares its shader
//! file (`shader_file!`), so no table below the effects names it; `bench/pass_chain.rs` re-exports
//! it.

crate::flag_key! {
    /// `bench/pass_chain.wgsl`: one permutation.
    pub struct PassChainKey("bench/pass_chain.wgsl");
}
