//! The typed key of `Glare`, [`GlareKey`] (`post/glare.wgsl`). It declares its shader file
//! (`shader_file!`), so no table below the effects names it; `post/glare.rs` re-exports it.

crate::flag_key! {
    /// `post/glare.wgsl`: one key for every entry of the chain.
    pub struct GlareKey("post/glare.wgsl") {
        /// The composite samples a filterable source (else it reads texels).
        filtered_source: "FILTERED_SOURCE",
    }
}
