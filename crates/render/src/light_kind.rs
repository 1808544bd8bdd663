//! The light types: what a light buffer holds, one CookTorrance
//! permutation each. Apart from the lighting passes, below them and the
//! shadow maps, so that the permutation keys, the shadow maps (a sun's
//! cascades, a point light's cube) and the shader-node compiler can name a
//! type without the lighting passes; `lighting::LightKind` re-exports it.

/// Which light type a buffer holds; CookTorrance compiles one permutation per type.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum LightKind {
    Point,
    Spot,
    Sun,
}
