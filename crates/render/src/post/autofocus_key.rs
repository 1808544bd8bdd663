//! The typed key of `Autofocus`, [`AutofocusKey`] (`post/autofocus.wgsl`). It stands in a file of
//! its own that imports no pass, so that `shaders::SHADERS` names it without a circle through the
//! renderer (docs/architecture.md, "Layers inside render"); `post/autofocus.rs` re-exports it.

crate::flag_key! {
    /// `post/autofocus.wgsl`: one permutation.
    pub struct AutofocusKey("post/autofocus.wgsl");
}
