//! Geometry nodes (category "Geometry"): primitives and glTF files, each
//! output a spread of meshes uploaded to the renderer's mesh arena, and GPU
//! geometry (Emeshe's GeomFX list: `Spherize`, `Extrude`, `Tube`, `Ribbon`, `Spline`, `PN Triangles`, `Subdivide`,
//! `Tessellate`, `Displace`, `Decimate`), mesh in, mesh out,
//! computed in the arena without a readback.

mod continuity;
pub mod decimate;
pub mod displace;
pub mod extrude;
pub mod gltf;
mod gltf_deform;
#[cfg(test)]
mod gltf_tests;
mod height;
pub mod pn_triangles;
pub mod primitives;
pub mod spherize;
pub mod spline;
pub mod tessellate;

use spreadlight_graph::{In, Out, Pins, Registry, Res, ResourceKind};
use spreadlight_render::mesh_arena::GpuMesh;

const CATEGORY: &str = "Geometry";

/// A pin of meshes (the GPU geometry nodes' first).
fn mesh_input(p: &mut Pins<'_>) -> In<Res<GpuMesh>> {
    p.input_resource::<GpuMesh>("Mesh", ResourceKind::Mesh)
}

/// The mesh output every geometry node gives.
fn mesh_output(p: &mut Pins<'_>, name: &'static str) -> Out<Res<GpuMesh>> {
    p.output_resource::<GpuMesh>(name, ResourceKind::Mesh)
}

pub fn register(r: &mut Registry) {
    primitives::register(r);
    gltf::register(r);
    spherize::register(r);
    extrude::register(r);
    spline::register(r);
    pn_triangles::register(r);
    tessellate::register(r);
    displace::register(r);
    decimate::register(r);
}

#[cfg(test)]
mod adaptive_tests;
#[cfg(test)]
mod gltf_deform_tests;
#[cfg(test)]
pub(crate) mod tests;
