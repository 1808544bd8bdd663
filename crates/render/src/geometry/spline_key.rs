//! The typed key of Spline, [`SplineKey`] (`geometry/spline.wgsl`). It stands in a file of its own
//! that imports no pass, so that `shaders::SHADERS` names it without a circle through the renderer
//! (docs/architecture.md, "Layers inside render"); `geometry/spline.rs` re-exports it.

crate::flag_key! {
    /// `geometry/spline.wgsl`.
    pub struct SplineKey("geometry/spline.wgsl") {
        /// Swept into a flat ribbon (else a tube).
        ribbon: "RIBBON",
        /// Interpolated as a Bézier curve (else Catmull-Rom).
        bezier: "BEZIER",
    }
}
