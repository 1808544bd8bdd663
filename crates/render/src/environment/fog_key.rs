//! The typed key of `Fog`, [`FogKey`] (`environment/fog.wgsl`). It stands in a file of its own that
//! imports no pass, so that `shaders::SHADERS` names it without a circle through the renderer
//! (docs/architecture.md, "Layers inside render"); `environment/fog.rs` re-exports it.

crate::flag_key! {
    /// `environment/fog.wgsl`: one permutation (a Fog run with a Sky is the
    /// Sky's `FOG` permutation, [`SkyKey`](crate::environment::sky::SkyKey)).
    pub struct FogKey("environment/fog.wgsl");
}
