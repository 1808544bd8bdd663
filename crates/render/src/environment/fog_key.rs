//! The typed key of `Fog`, [`FogKey`] (`environment/fog.wgsl`). It declares its shader file
//! (`shader_file!`), so no table below the effects names it; `environment/fog.rs` re-exports it.

crate::flag_key! {
    /// `environment/fog.wgsl`: one permutation (a Fog run with a Sky is the
    /// Sky's `FOG` permutation, [`SkyKey`](crate::environment::sky::SkyKey)).
    pub struct FogKey("environment/fog.wgsl");
}
