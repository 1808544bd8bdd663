//! The typed key of Extrude, [`ExtrudeKey`] (`geometry/extrude.wgsl`). It declares its shader
//! file (`shader_file!`), so no table below the effects names it; `geometry/extrude.rs`
//! re-exports it.

crate::flag_key! {
    /// `geometry/extrude.wgsl`.
    pub struct ExtrudeKey("geometry/extrude.wgsl") {
        /// The height is read from a texture.
        texture: "TEXTURE",
    }
}
