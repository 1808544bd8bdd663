//! The typed key of the environment reflection, [`ReflectionKey`]
//! (`environment/reflection.wgsl`). It stands in a file of its own that imports no pass, so that
//! `shaders::SHADERS` names it without a circle through the renderer (docs/architecture.md, "Layers
//! inside render"); `environment/reflection.rs` re-exports it.

crate::flag_key! {
    /// `environment/reflection.wgsl`.
    pub struct ReflectionKey("environment/reflection.wgsl") {
        /// Some material's CookTorrance parameters read the world's texture array.
        material_textures: "MATERIAL_TEXTURES",
        /// Roughness and metallic where the G-buffer resolved them (its surface target).
        surface_target: "SURFACE_TARGET",
        /// A probe volume's box corrects the lookup direction.
        parallax: "PARALLAX",
    }
}
