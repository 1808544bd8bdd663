//! The typed key of `SSSS`, [`SsssKey`] (`lighting/ssss.wgsl`). It declares its shader file
//! (`shader_file!`), so no table below the effects names it; `lighting/ssss.rs` re-exports it.

crate::flag_key! {
    /// `lighting/ssss.wgsl`: the pass's direction and how many sources it blurs.
    pub struct SsssKey("lighting/ssss.wgsl") {
        vertical: "VERTICAL",
        /// A second source (the second light type's subsurface term).
        sources_2: "SOURCES_2",
        sources_3: "SOURCES_3",
    }
}
