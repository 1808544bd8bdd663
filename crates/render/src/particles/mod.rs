//! Particles (Dagon's particles in vector fields): a ring of particle slots
//! in a persistent GPU buffer ([`ParticleSystem`]), stepped by a compute
//! pass (shaders/particles/simulate.wgsl: emitters, forces, collisions) and
//! drawn by expanding every slot into geometry in the mesh arena
//! (shaders/particles/draw.wgsl), so particles enter the G-buffer, shadow
//! maps and the post chain as an ordinary mesh with previous positions.
//!
//! Determinism: emission is counted on the CPU in f64 (`rate * dt` plus the
//! carried fraction) and each emitted particle is seeded by its global
//! emission index, so a fixed seed and sequence of time steps give the same
//! buffer bit for bit on one device.

mod draw;
mod field;
mod simulate;

pub use draw::{DrawShape, draw};
pub use field::FieldTexture;
pub use simulate::{
    DepthCollision, EmitterShape, Field, Integrator, MAX_ATTRACTORS, MAX_STEP, ParticleSettings,
    Plane,
};

use bytemuck::{Pod, Zeroable};

use crate::error::RenderError;
use crate::renderer::Renderer;

/// 48 bytes; matches `Particle` in shaders/particles/*.wgsl.
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, PartialEq, Pod, Zeroable)]
pub struct Particle {
    pub position: [f32; 3],
    pub age: f32,
    pub velocity: [f32; 3],
    pub lifetime: f32,
    pub previous: [f32; 3],
    pub alive: u32,
}

const PARTICLE_SIZE: u64 = std::mem::size_of::<Particle>() as u64;

/// The persistent state of one particle system: its slots and its clock.
pub struct ParticleSystem {
    buffer: wgpu::Buffer,
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
    /// `capacity` slots, all dead. Fails when the buffer would exceed the GPU's limits.
    pub fn new(renderer: &Renderer, capacity: u32, seed: u32) -> Result<Self, RenderError> {
        let capacity = capacity.max(1);
        let size = u64::from(capacity) * PARTICLE_SIZE;
        let limits = renderer.gpu.device.limits();
        let max = limits
            .max_storage_buffer_binding_size
            .min(limits.max_buffer_size);
        if size > max {
            return Err(RenderError::Pass {
                pass: "particles".to_owned(),
                message: format!(
                    "{capacity} particles need {size} bytes, over the GPU's storage buffer limit of {max}"
                ),
            });
        }
        let buffer = renderer.gpu.device.create_buffer(&wgpu::BufferDescriptor {
            label: Some("particles"),
            size,
            usage: wgpu::BufferUsages::STORAGE
                | wgpu::BufferUsages::COPY_DST
                | wgpu::BufferUsages::COPY_SRC,
            // Zeroed by wgpu: every slot starts dead.
            mapped_at_creation: false,
        });
        Ok(ParticleSystem {
            buffer,
            capacity,
            seed,
            head: 0,
            emitted: 0,
            carry: 0.0,
            time: 0.0,
        })
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
        encoder.clear_buffer(&self.buffer, 0, None);
        renderer.gpu.queue.submit([encoder.finish()]);
        self.head = 0;
        self.emitted = 0;
        self.carry = 0.0;
        self.time = 0.0;
    }

    /// The particle buffer (for the draw pass and readback).
    pub fn buffer(&self) -> &wgpu::Buffer {
        &self.buffer
    }

    /// Every slot, read back (tests and tables).
    pub fn read(&self, renderer: &Renderer) -> Result<Vec<Particle>, RenderError> {
        let bytes = crate::geometry::read_storage(
            renderer,
            &self.buffer,
            0,
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
