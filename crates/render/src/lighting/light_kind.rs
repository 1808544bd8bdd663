//! The light types: what a light buffer holds, one CookTorrance
//! permutation each. Apart from the passes, so that the permutation keys
//! and the shader-node compiler can name a type without the lighting passes.

/// Which light type a buffer holds; CookTorrance compiles one permutation per type.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum LightKind {
    Point,
    Spot,
    Sun,
}
