//! Particles (Dagon's particles in vector fields): a ring of particle slots
//! kept as records in the mesh arena ([`ParticleSystem`]), stepped by a
//! compute pass (shaders/particles/simulate.wgsl: emitters, forces,
//! collisions) and drawn straight from those records: [`draw`] hands out a
//! procedural mesh whose triangles (a camera-facing quad or a copy of a
//! shape a particle) every mesh-pulling pass makes on the fly
//! (shaders/lib/mesh_fetch.wgsl). So particles enter the G-buffer, shadow
//! maps, Transparency and the post chain as a mesh with previous positions,
//! and cost 64 bytes a particle: ten million fit where their expanded
//! quads (2.5 GB) did not.
//!
//! Determinism: emission is counted on the CPU in f64 (`rate * dt` plus the
//! carried fraction) and each emitted particle is seeded by its global
//! emission index, so a fixed seed and sequence of time steps give the same
//! buffer bit for bit on one device.

mod draw;
mod expand;
pub(crate) mod expand_key;
mod field;
mod simulate;
pub(crate) mod simulate_key;

pub use draw::{DrawShape, draw};
pub use expand::read_drawn;
pub use field::FieldTexture;
pub use simulate::{
    DepthCollision, EmitterShape, Field, Integrator, MAX_ATTRACTORS, MAX_STEP, ParticleSettings,
    Plane,
};

use bytemuck::{Pod, Zeroable};

use std::sync::Arc;

use glam::Vec3;

use crate::error::RenderError;
use crate::mesh::Aabb;
use crate::mesh_arena::{GpuMesh, MeshLayout};
use crate::renderer::Renderer;

/// 64 bytes, one mesh-arena vertex; matches `Particle` as packed by
/// shaders/lib/particle.wgsl.
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, PartialEq, Pod, Zeroable)]
pub struct Particle {
    pub position: [f32; 3],
    pub age: f32,
    pub velocity: [f32; 3],
    pub lifetime: f32,
    pub previous: [f32; 3],
    pub alive: u32,
    pub reserved: [f32; 4],
}

const PARTICLE_SIZE: u64 = std::mem::size_of::<Particle>() as u64;

/// The persistent state of one particle system: its slots and its clock.
pub struct ParticleSystem {
    /// A header record (the draw's shape, see shaders/lib/particle.wgsl)
    /// then `capacity` particle records, in the mesh arena.
    records: Arc<GpuMesh>,
    capacity: u32,
    seed: u32,
    /// The next slot to emit into.
    head: u32,
    /// Particles emitted since the last reset (seeds the next ones).
    emitted: u64,
    /// The fraction of a particle owed to the next step.
    carry: f64,
    /// Seconds simulated since the last reset (animates the curl field).
    time: f64,
}

impl std::fmt::Debug for ParticleSystem {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(f, "ParticleSystem({} slots)", self.capacity)
    }
}

impl ParticleSystem {
    /// `capacity` slots, all dead: 64 bytes each (and one header) in the
    /// mesh arena. Fails when the arena cannot hold them (the GPU's storage
    /// buffer limit), naming how many bytes they need.
    pub fn new(renderer: &Renderer, capacity: u32, seed: u32) -> Result<Self, RenderError> {
        let capacity = capacity.max(1);
        let records = capacity.checked_add(1).ok_or_else(|| RenderError::Pass {
            pass: "particles".to_owned(),
            message: format!("{capacity} particles are too many"),
        })?;
        let layout = MeshLayout {
            bounds: Aabb {
                min: Vec3::ZERO,
                max: Vec3::ZERO,
            },
            has_uvs: false,
            has_tangents: false,
        };
        let records = renderer
            .meshes
            .allocate(&renderer.gpu, records, 0, layout)
            .map_err(|e| RenderError::Pass {
                pass: "particles".to_owned(),
                message: format!(
                    "{capacity} particles need {} bytes: {e}",
                    u64::from(records) * PARTICLE_SIZE
                ),
            })?;
        let mut system = ParticleSystem {
            records,
            capacity,
            seed,
            head: 0,
            emitted: 0,
            carry: 0.0,
            time: 0.0,
        };
        // The arena's range may hold a freed mesh's vertices: start dead.
        system.reset(renderer);
        Ok(system)
    }

    pub fn capacity(&self) -> u32 {
        self.capacity
    }

    pub fn seed(&self) -> u32 {
        self.seed
    }

    /// Kills every particle and restarts the clock and the emission sequence.
    pub fn reset(&mut self, renderer: &Renderer) {
        let mut encoder = renderer
            .gpu
            .device
            .create_command_encoder(&Default::default());
        let (vertices, _, _) = renderer.meshes.buffers();
        encoder.clear_buffer(
            &vertices,
            u64::from(self.records.vertices.start) * PARTICLE_SIZE,
            Some(self.records.vertices.len() as u64 * PARTICLE_SIZE),
        );
        renderer.gpu.submit([encoder.finish()]);
        self.head = 0;
        self.emitted = 0;
        self.carry = 0.0;
        self.time = 0.0;
    }

    /// The arena range of the header and the particle records.
    pub fn records(&self) -> &Arc<GpuMesh> {
        &self.records
    }

    /// The arena index of slot 0's record (the header is just before it).
    fn first_record(&self) -> u32 {
        self.records.vertices.start + 1
    }

    /// Every slot, read back (tests and tables).
    pub fn read(&self, renderer: &Renderer) -> Result<Vec<Particle>, RenderError> {
        let (vertices, _, _) = renderer.meshes.buffers();
        let bytes = crate::geometry::read_storage(
            renderer,
            &vertices,
            u64::from(self.first_record()) * PARTICLE_SIZE,
            u64::from(self.capacity) * PARTICLE_SIZE,
        )?;
        Ok(bytemuck::pod_collect_to_vec(
            &bytes[..self.capacity as usize * PARTICLE_SIZE as usize],
        ))
    }

    /// How many particles a step of `dt` seconds emits at `rate` a second,
    /// advancing the emission clock (never more than the ring holds).
    fn take_emission(&mut self, rate: f32, dt: f32) -> u32 {
        let rate = if rate.is_finite() {
            f64::from(rate.max(0.0))
        } else {
            0.0
        };
        let owed = self.carry + rate * f64::from(dt);
        let whole = owed.floor();
        self.carry = owed - whole;
        whole.min(f64::from(self.capacity)) as u32
    }
}
