//! What every effect does to a number from a pin before it reaches a
//! shader: finite and in range, or a fallback. A NaN radius would reach
//! every pixel; an infinite one no pixel at all.

/// `v` clamped to `lo..=hi`; `fallback` where `v` is NaN or infinite.
pub fn finite_in(v: f32, lo: f32, hi: f32, fallback: f32) -> f32 {
    if v.is_finite() {
        v.clamp(lo, hi)
    } else {
        fallback
    }
}
