//! The typed key of `Reflection`, [`ReflectionKey`] (`environment/reflection.wgsl`). It declares
//! its shader file (`shader_file!`), so no table below the effects names it;
//! `environment/reflection.rs` re-exports it.

crate::flag_key! {
    /// `environment/reflection.wgsl`: one key for every entry (the clear,
    /// the specular and diffuse light).
    pub struct ReflectionKey("environment/reflection.wgsl") {
        /// Some material's CookTorrance parameters read a texture.
        material_textures: "MATERIAL_TEXTURES",
        /// The G-buffer has a surface target (surface maps, shader node
        /// materials), read in place of the materials' parameters.
        surface_target: "SURFACE_TARGET",
        /// The cube is a probe's with a volume: the lookup is corrected by
        /// the volume (parallax), not taken as if infinitely far.
        parallax: "PARALLAX",
        /// Some material has a clear coat: coated pixels add the coat's
        /// reflection of the environment and dim the base's.
        clearcoat: "CLEARCOAT",
        /// Some material has a thin film (Iridescence): its Fresnel at
        /// N.V replaces the split sum's Schlick term, mixed by its factor.
        iridescence: "IRIDESCENCE",
        /// Some material has a sheen: its image-based light and the base's
        /// dimming under it are compiled in.
        sheen: "SHEEN",
        /// The G-buffer has an anisotropy target (some material has
        /// KHR_materials_anisotropy): an anisotropic pixel's reflection is
        /// mirrored about the extension's bent normal.
        anisotropy: "ANISOTROPY",
    }
}
