//! The typed key of shifting a scrolled cascade's layer into place:
//! [`ShadowScrollKey`] (`shadows/scroll.wgsl`, scroll.rs).

crate::flag_key! {
    /// `shadows/scroll.wgsl`.
    pub struct ShadowScrollKey("shadows/scroll.wgsl") {
        /// VSM's two-channel moments (rg32float) instead of depth (r32float).
        moments: "MOMENTS",
    }
}
