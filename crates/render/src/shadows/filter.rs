//! How shadows are filtered: a setting of the shadow maps and a switch of
//! the shaders that sample them. Apart from the passes, so that the
//! permutation keys name it without them.

/// How a shadow is filtered when it is sampled.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum ShadowFilter {
    /// One comparison at the nearest texel: hard, aliased edges.
    Raw,
    /// Percentage-closer filtering over `kernel` x `kernel` texels (odd, 1..=9).
    Pcf { kernel: u32 },
    /// Percentage-closer soft shadows (Fernando 2005; Emeshe's soft shadows):
    /// a blocker search, a penumbra from the light's size, then PCF over it.
    Pcss { light_size: f32, samples: u32 },
    /// Variance shadow maps (Donnelly and Lauritzen 2006): depth moments in
    /// RG32F, blurred, with light-bleeding reduction 0..1.
    Vsm { bleeding: f32, blur: u32 },
}
