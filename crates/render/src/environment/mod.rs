//! The environment around a scene: what is seen where no geometry is.
//! `Sky` fills the G-buffer's empty depth with a procedural sky.

pub mod sky;

pub use sky::{Sky, SkySettings};
