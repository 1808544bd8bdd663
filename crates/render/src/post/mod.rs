//! Post-processing passes: texture in, texture out, in compute.

pub mod tonemap;

pub use tonemap::Tonemap;
