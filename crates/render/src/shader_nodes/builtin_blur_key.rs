//! The typed key of `BlurBuiltin`, [`BuiltinBlurKey`] (`nodes/blur.wgsl`). It declares its shader
//! file (`shader_file!`), so no table below the effects names it; `shader_nodes/builtin_blur.rs`
//! re-exports it.

crate::flag_key! {
    /// `nodes/blur.wgsl` as a built-in pass: one permutation for both directions.
    pub struct BuiltinBlurKey("nodes/blur.wgsl");
}
