//! The typed key of `Sky`, [`SkyKey`] (`environment/sky.wgsl`). It declares its shader file
//! (`shader_file!`), so no table below the effects names it; `environment/sky.rs` re-exports it.

crate::flag_key! {
    /// `environment/sky.wgsl`.
    pub struct SkyKey("environment/sky.wgsl") {
        /// The background from an environment's cube, not the procedural sky.
        environment: "ENVIRONMENT",
        /// A Fog under (or over) the Sky in the same pass (`environment::FOG_AND_SKY`).
        fog: "FOG",
    }
}
