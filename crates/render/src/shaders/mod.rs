//! Shaders: the WGSL sources (embedded in the binary), their feature
//! switches, and the permutation cache, which is the only place that compiles
//! shaders and pipelines.
//!
//! Feature switches work like Emeshe's `#define` switches: a shader marks
//! optional code with `#ifdef FEATURE` (naga_oil's preprocessor), a pass asks
//! for a set of features, and the cache composes, validates and compiles that
//! permutation once. A combination no pass asks for is never compiled.
//! Shared libraries are imported by name (`#import spreadlight::packing`).
//!
//! An entry shader is declared by its effect's typed key ([`Permutation`],
//! `ssao/key.rs`), whose keys carry the file: this layer lists only the
//! libraries ([`LIBRARIES`]). Every key type is named in one place above the
//! effects, `crate::permutations`, which the exhaustive tests walk.

// `shader_source!` by its textual scope (it is exported at the crate's root,
// which this layer does not import).
#[macro_use]
pub mod permutation;

/// A library of `shaders/`: imported by the entry shaders, no entry points.
macro_rules! library {
    ($path:literal) => {
        ShaderFile {
            path: $path,
            source: shader_source!($path),
            features: &[],
            library: true,
            keys: None,
        }
    };
}

/// Every library, in dependency order (one only after those it imports).
pub const LIBRARIES: &[ShaderFile] = &[
    library!("lib/packing.wgsl"),
    library!("lib/camera.wgsl"),
    library!("lib/mesh.wgsl"),
    library!("lib/geometry.wgsl"),
    library!("lib/particle.wgsl"),
    library!("lib/mesh_fetch.wgsl"),
    library!("lib/vertex_extras.wgsl"),
    library!("lib/brdf.wgsl"),
    library!("lib/iridescence.wgsl"),
    library!("lib/anisotropy.wgsl"),
    library!("lib/sheen.wgsl"),
    library!("lib/lights.wgsl"),
    library!("lib/spot.wgsl"),
    library!("lib/tonemap.wgsl"),
    library!("lib/surface_target.wgsl"),
    library!("lib/material.wgsl"),
    library!("lib/sheen_film.wgsl"),
    library!("lib/materials.wgsl"),
    library!("lib/material_maps.wgsl"),
    library!("lib/matcap.wgsl"),
    library!("lib/screen.wgsl"),
    library!("lib/ao_history.wgsl"),
    library!("lib/sky.wgsl"),
    library!("lib/fog.wgsl"),
    library!("lib/ibl.wgsl"),
    library!("lib/post.wgsl"),
    library!("lighting/shadow_sampling.wgsl"),
    library!("lib/forward_light.wgsl"),
    library!("lib/surface.wgsl"),
    library!("lib/custom_surface.wgsl"),
    library!("lib/light_shader.wgsl"),
    library!("lib/custom_light.wgsl"),
];

/// The library at `path` below `shaders/` (`lib/camera.wgsl`), if there is one.
pub fn library(path: &str) -> Option<&'static ShaderFile> {
    LIBRARIES.iter().find(|f| f.path == path)
}

mod cache;
mod composer;
mod flags;
/// Shaders generated from the sources' text (the fused light loop), by name.
pub mod generated;
pub mod layout;
/// Compute pipelines created on threads ahead of the frame's look-up (the
/// last run's list, or what a first frame's passes announce): the cache's
/// own helper, so it lives beside the cache.
pub mod pipelines_ahead;
mod preprocess;
mod reflection;
mod uniform;

pub(crate) use cache::compute_pipeline_of;
pub use cache::{CompileTimes, PipelineRef, Sampling, ShaderCache};
#[cfg(test)]
pub(crate) use composer::is_composed;
pub use composer::{ShaderComposer, Splice};
pub(crate) use composer::{embedded_generated_or_wait, embedded_module};
pub use generated::{GeneratedKey, Generator};
pub use permutation::{Permutation, ShaderFile, ShaderKey};
pub(crate) use reflection::INLINE_BINDINGS;
#[cfg(test)]
pub(crate) use reflection::reflect as reflection_of;
pub use reflection::{BindGroups, Reflection, ShaderVar};
pub use uniform::Uniform;

#[cfg(test)]
mod tests;
