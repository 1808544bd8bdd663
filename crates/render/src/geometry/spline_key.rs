//! The typed key of Spline, [`SplineKey`] (`geometry/spline.wgsl`). It declares its shader file
//! (`shader_file!`), so no table below the effects names it; `geometry/spline.rs` re-exports it.

crate::flag_key! {
    /// `geometry/spline.wgsl`.
    pub struct SplineKey("geometry/spline.wgsl") {
        /// Swept into a flat ribbon (else a tube).
        ribbon: "RIBBON",
        /// Interpolated as a Bézier curve (else Catmull-Rom).
        bezier: "BEZIER",
    }
}
