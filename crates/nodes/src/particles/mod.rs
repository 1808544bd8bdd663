//! Particle nodes (category "Particles"): `Particles` simulates a system on
//! the GPU (render::particles) and outputs it as a mesh with previous
//! positions, for DeferredBase (Velocity: Geometry) and shadow maps;
//! `VectorField` makes a 3D texture field from a spread of vectors.

mod field;
mod system;

use spreadlight_graph::Registry;

const CATEGORY: &str = "Particles";

pub fn register(r: &mut Registry) {
    system::register(r);
    field::register(r);
}

#[cfg(test)]
mod tests;
