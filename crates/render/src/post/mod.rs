//! Post-processing passes: texture in, texture out, in compute.

pub mod eye_adaptation;
pub mod fxaa;
pub mod tonemap;

pub use eye_adaptation::{AdaptationSettings, EyeAdaptation};
pub use fxaa::{Fxaa, FxaaQuality};
pub use tonemap::{AdaptedExposure, Tonemap};
