//! The typed key of `Sky`, [`SkyKey`] (`environment/sky.wgsl`). It stands in a file of its own that
//! imports no pass, so that `shaders::SHADERS` names it without a circle through the renderer
//! (docs/architecture.md, "Layers inside render"); `environment/sky.rs` re-exports it.

crate::flag_key! {
    /// `environment/sky.wgsl`.
    pub struct SkyKey("environment/sky.wgsl") {
        /// The background from an environment's cube, not the procedural sky.
        environment: "ENVIRONMENT",
        /// A Fog under (or over) the Sky in the same pass (`environment::FOG_AND_SKY`).
        fog: "FOG",
    }
}
