//! The typed key of `BlurBuiltin`, [`BuiltinBlurKey`] (`nodes/blur.wgsl`). It stands in a file of
//! its own that imports no pass, so that `shaders::SHADERS` names it without a circle through the
//! renderer (docs/architecture.md, "Layers inside render"); `shader_nodes/builtin_blur.rs`
//! re-exports it.

crate::flag_key! {
    /// `nodes/blur.wgsl` as a built-in pass: one permutation for both directions.
    pub struct BuiltinBlurKey("nodes/blur.wgsl");
}
