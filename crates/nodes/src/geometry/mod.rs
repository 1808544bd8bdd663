//! Geometry nodes (category "Geometry"): primitives and glTF files, each
//! output a spread of meshes uploaded to the renderer's mesh arena.

pub mod gltf;
#[cfg(test)]
mod gltf_tests;
pub mod primitives;

use spreadlight_graph::Registry;

pub fn register(r: &mut Registry) {
    primitives::register(r);
    gltf::register(r);
}
