//! The typed key of `Glare`, [`GlareKey`] (`post/glare.wgsl`). It stands in a file of its own that
//! imports no pass, so that `shaders::SHADERS` names it without a circle through the renderer
//! (docs/architecture.md, "Layers inside render"); `post/glare.rs` re-exports it.

crate::flag_key! {
    /// `post/glare.wgsl`: one key for every entry of the chain.
    pub struct GlareKey("post/glare.wgsl") {
        /// The composite samples a filterable source (else it reads texels).
        filtered_source: "FILTERED_SOURCE",
    }
}
