//! Refracted transmission for lit transparency (TRANSMISSION in
//! `post/transparency.wgsl`): what shows through a transmissive layer is
//! the opaque lit image (before the composite) sampled where the refracted
//! ray meets the opaque scene, found in screen space, as glTF viewers draw
//! `KHR_materials_transmission` (Khronos' sample viewer, three.js,
//! Filament); blurred by roughness (over a few taps, or one trilinear read
//! of a mip chain of the opaque image: [`RefractionBlur`],
//! `refraction_mips.rs`), tinted by the base colour and absorbed by
//! Beer-Lambert over the path through the volume. A ray that leaves the
//! screen sees the layer's Environment where it has one, faded in over a
//! band beyond the screen's border (no seam); without one, the edge.
//! A layer's material world's Transmission feature says it per material;
//! these settings (the node's pins) are the fallback for layers without.

use glam::Vec3;

use crate::material::transmission_params;

/// The most blur taps (the shader's loop bound).
pub const MAX_TAPS: u32 = 32;
/// The most depth-search steps.
pub const MAX_STEPS: u32 = 8;

/// How rough glass blurs what it refracts.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
pub enum RefractionBlur {
    /// [`RefractionBlur::Mips`]: the same kernel as the taps' for one read.
    #[default]
    Auto,
    /// One trilinear read of a mip chain of the opaque image, at the level
    /// whose filter is as wide as the roughness's disc (the chain is built
    /// each frame a layer refracts: one compute pass).
    Mips,
    /// The settings' taps over the disc: the reference-quality choice, its
    /// cost growing with the count.
    Taps,
}

impl RefractionBlur {
    /// What Auto stands for.
    pub fn resolved(self) -> RefractionBlur {
        match self {
            RefractionBlur::Auto | RefractionBlur::Mips => RefractionBlur::Mips,
            RefractionBlur::Taps => RefractionBlur::Taps,
        }
    }
}

/// How a transparent layer without a Transmission material transmits, and
/// how every transmissive fragment samples what is behind it.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct TransmissionSettings {
    /// How much of what shows through is refracted (0..1; 0: off, the
    /// straight blend, and no TRANSMISSION permutation for such layers).
    pub factor: f32,
    /// Index of refraction (1: no bend; NaN, zero or negative: 1).
    pub ior: f32,
    /// The volume's thickness in world units (0: thin-walled, no offset).
    pub thickness: f32,
    /// White light turns this colour after `attenuation_distance` inside.
    pub attenuation_color: Vec3,
    /// World units; infinite: no absorption.
    pub attenuation_distance: f32,
    /// Blur taps over the roughness's disc (1..=[`MAX_TAPS`]); the quality
    /// setting `spreadlight accuracy` measures.
    pub taps: u32,
    /// Depth-search steps that walk the ray leaving the volume onto the
    /// opaque depth (0..=[`MAX_STEPS`]; 0 samples where the exit point
    /// projects, as Khronos' viewer does).
    pub steps: u32,
    /// Taps or the mip chain, for every refracting layer.
    pub blur: RefractionBlur,
}

impl Default for TransmissionSettings {
    fn default() -> Self {
        TransmissionSettings {
            factor: 0.0,
            ior: 1.5,
            thickness: 0.0,
            attenuation_color: Vec3::ONE,
            attenuation_distance: f32::INFINITY,
            taps: 8,
            steps: 2,
            blur: RefractionBlur::Auto,
        }
    }
}

impl TransmissionSettings {
    /// Whether layers without a Transmission material refract.
    pub fn on(&self) -> bool {
        self.factor > 0.0
    }

    /// The two vec4s of the shader's `Params`: (factor, ior, thickness,
    /// taps) and (absorption rgb, steps), every one finite.
    pub fn words(&self) -> [f32; 8] {
        let [[factor, ior, thickness, _], [sr, sg, sb, _]] = transmission_params(
            self.factor,
            self.ior,
            self.thickness,
            self.attenuation_color.to_array(),
            self.attenuation_distance,
            // The node's layers refract red, green and blue alike; a
            // material's Transmission carries its own dispersion.
            0.0,
        );
        [
            factor,
            ior,
            thickness,
            self.taps.clamp(1, MAX_TAPS) as f32,
            sr,
            sg,
            sb,
            self.steps.min(MAX_STEPS) as f32,
        ]
    }
}
