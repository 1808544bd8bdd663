//! The environment around a scene: what is seen where no geometry is.
//! `Sky` fills the G-buffer's empty depth with a procedural sky; `Fog`
//! veils what is far or low.

pub mod fog;
mod pass;
pub mod sky;

pub use fog::{Fog, FogSettings};
pub use pass::ImagePass;
pub use sky::{Sky, SkySettings};
