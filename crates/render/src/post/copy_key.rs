//! The typed key of the post passes' copy, [`CopyKey`] (`post/copy.wgsl`). It stands in a file of
//! its own that imports no pass, so that `shaders::SHADERS` names it without a circle through the
//! renderer (docs/architecture.md, "Layers inside render"); `post/mod.rs` re-exports it.

crate::flag_key! {
    /// `post/copy.wgsl`: one permutation.
    pub struct CopyKey("post/copy.wgsl");
}
