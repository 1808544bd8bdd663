//! One simulation step: the settings a `Particles` node gathers, packed into
//! the uniform of shaders/particles/simulate.wgsl, and its dispatch.

use std::sync::Arc;

use bytemuck::{Pod, Zeroable};
use glam::{Mat4, Vec3, Vec4};

use super::{FieldTexture, ParticleSystem};
use crate::error::RenderError;
use crate::geometry::{dispatch, uniform};
use crate::mesh_arena::GpuMesh;
use crate::renderer::Renderer;
use crate::shaders::Permutation;

pub use super::simulate_key::SimulateKey;

/// The longest step simulated at once (seconds): a longer frame (a stall,
/// a huge time step) is clamped to it, so no step can blow up.
pub const MAX_STEP: f32 = 0.1;
pub const MAX_ATTRACTORS: usize = 8;

/// Where new particles appear, in the emitter's space.
#[derive(Clone, Debug)]
pub enum EmitterShape {
    Point,
    /// Uniform in a box of these half sizes.
    Box(Vec3),
    /// Uniform in a ball of this radius.
    Sphere(f32),
    /// Uniform on a triangle picked uniformly (not by area) of a mesh.
    MeshSurface(Arc<GpuMesh>),
}

/// The vector field particles are pushed by (an acceleration).
#[derive(Clone, Debug)]
pub enum Field {
    None,
    /// Procedural curl noise: divergence-free, so particles swirl without bunching.
    Curl {
        frequency: f32,
        strength: f32,
    },
    /// A texture over a box; zero outside it.
    Texture {
        texture: Arc<FieldTexture>,
        min: Vec3,
        max: Vec3,
        strength: f32,
    },
}

#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Integrator {
    /// x += v dt; v += a dt: the textbook scheme, first order, unstable under stiff drag.
    ExplicitEuler,
    /// The step solved exactly for the acceleration at its start under linear
    /// drag (an exponential integrator): exact for constant forces, first
    /// order only in how the field varies, stable for any drag and step.
    Exponential,
}

/// A collision plane: particles stay where `dot(normal, p) >= offset`.
#[derive(Clone, Copy, Debug)]
pub struct Plane {
    pub normal: Vec3,
    pub offset: f32,
}

/// Screen-space collision with a depth target (reversed Z, R32Float, 0
/// where nothing was drawn): usually last frame's, published by a G-buffer
/// ([`crate::gbuffer::PublishedDepths`]).
#[derive(Clone, Debug)]
pub struct DepthCollision {
    pub depth: wgpu::TextureView,
    pub view_projection: Mat4,
    pub size: (u32, u32),
    /// How far behind the visible surface (metres) a particle still counts
    /// as inside it; farther behind, it passes (it is behind the object).
    pub thickness: f32,
}

#[derive(Clone, Debug)]
pub struct ParticleSettings {
    pub emitter: Mat4,
    pub shape: EmitterShape,
    /// Particles a second.
    pub rate: f32,
    pub lifetime: f32,
    /// Lifetimes vary uniformly by ± this.
    pub lifetime_spread: f32,
    pub velocity: Vec3,
    /// A random velocity in a ball of this radius is added.
    pub velocity_spread: f32,
    pub gravity: Vec3,
    /// Linear drag per second.
    pub drag: f32,
    pub field: Field,
    /// Position (xyz) and strength (w) of softened inverse-square attractors.
    pub attractors: Vec<Vec4>,
    pub plane: Option<Plane>,
    pub bounce: f32,
    pub friction: f32,
    pub depth: Option<DepthCollision>,
    /// Particles farther than this from the origin die (it bounds the mesh too).
    pub world_radius: f32,
    pub integrator: Integrator,
}

impl Default for ParticleSettings {
    fn default() -> Self {
        ParticleSettings {
            emitter: Mat4::IDENTITY,
            shape: EmitterShape::Point,
            rate: 100.0,
            lifetime: 2.0,
            lifetime_spread: 0.0,
            velocity: Vec3::Y,
            velocity_spread: 0.0,
            gravity: Vec3::new(0.0, -9.81, 0.0),
            drag: 0.0,
            field: Field::None,
            attractors: Vec::new(),
            plane: None,
            bounce: 0.5,
            friction: 0.1,
            depth: None,
            world_radius: 100.0,
            integrator: Integrator::Exponential,
        }
    }
}

/// Matches `Sim` in shaders/particles/simulate.wgsl.
#[repr(C)]
#[derive(Clone, Copy, Pod, Zeroable)]
struct GpuSim {
    emitter: [[f32; 4]; 4],
    emitter_size: [f32; 4],
    velocity: [f32; 4],
    gravity: [f32; 4],
    field: [f32; 4],
    field_min: [f32; 4],
    field_max: [f32; 4],
    plane: [f32; 4],
    collide: [f32; 4],
    life: [f32; 4],
    counts: [u32; 4],
    misc: [u32; 4],
    view_projection: [[f32; 4]; 4],
    inverse_view_projection: [[f32; 4]; 4],
    depth_size: [f32; 4],
    layout: [u32; 4],
    attractors: [[f32; 4]; MAX_ATTRACTORS],
}

/// `v` where finite, else `or`: NaN on a pin never reaches the GPU.
fn finite(v: f32, or: f32) -> f32 {
    if v.is_finite() { v } else { or }
}

fn finite3(v: Vec3) -> Vec3 {
    Vec3::new(finite(v.x, 0.0), finite(v.y, 0.0), finite(v.z, 0.0))
}

impl ParticleSystem {
    /// Advances the system by `dt` seconds (clamped to 0..[`MAX_STEP`]):
    /// emits, applies forces, collides, ages. One dispatch.
    pub fn step(
        &mut self,
        renderer: &Renderer,
        settings: &ParticleSettings,
        dt: f32,
    ) -> Result<(), RenderError> {
        let dt = finite(dt, 0.0).clamp(0.0, MAX_STEP);
        let emit = self.take_emission(settings.rate, dt);
        let s = settings;
        let (shape, size) = match &s.shape {
            EmitterShape::Point => (0.0, Vec3::ZERO),
            EmitterShape::Box(half) => (1.0, finite3(*half)),
            EmitterShape::Sphere(r) => (2.0, Vec3::splat(finite(*r, 0.0))),
            EmitterShape::MeshSurface(_) => (3.0, Vec3::ZERO),
        };
        let (field_kind, frequency, strength, min, max) = match &s.field {
            Field::None => (0.0, 0.0, 0.0, Vec3::ZERO, Vec3::ONE),
            Field::Curl {
                frequency,
                strength,
            } => (
                1.0,
                finite(*frequency, 1.0),
                finite(*strength, 0.0),
                Vec3::ZERO,
                Vec3::ONE,
            ),
            Field::Texture {
                min, max, strength, ..
            } => (
                2.0,
                1.0,
                finite(*strength, 0.0),
                finite3(*min),
                finite3(*max),
            ),
        };
        let plane = s.plane.map_or(Vec4::ZERO, |p| {
            finite3(p.normal)
                .try_normalize()
                .unwrap_or(Vec3::Y)
                .extend(finite(p.offset, 0.0))
        });
        let mut attractors = [[0.0; 4]; MAX_ATTRACTORS];
        for (slot, a) in attractors.iter_mut().zip(&s.attractors) {
            *slot = [
                finite(a.x, 0.0),
                finite(a.y, 0.0),
                finite(a.z, 0.0),
                finite(a.w, 0.0),
            ];
        }
        let emitter = if s.emitter.is_finite() {
            s.emitter
        } else {
            Mat4::IDENTITY
        };
        let (triangles, mesh) = match &s.shape {
            EmitterShape::MeshSurface(m) => ((m.indices.len() / 3) as u32, Some(m.clone())),
            _ => (0, None),
        };
        let depth_view_projection = s
            .depth
            .as_ref()
            .map(|d| d.view_projection)
            .filter(|m| m.is_finite())
            .unwrap_or(Mat4::IDENTITY);
        let gpu_sim = GpuSim {
            emitter: emitter.to_cols_array_2d(),
            emitter_size: size.extend(shape).into(),
            velocity: finite3(s.velocity)
                .extend(finite(s.velocity_spread, 0.0).max(0.0))
                .into(),
            gravity: finite3(s.gravity)
                .extend(finite(s.drag, 0.0).max(0.0))
                .into(),
            field: [frequency, strength, self.time as f32, field_kind],
            field_min: min.extend(0.0).into(),
            field_max: max.extend(0.0).into(),
            plane: plane.into(),
            collide: [
                if s.plane.is_some() { 1.0 } else { 0.0 },
                finite(s.bounce, 0.0).clamp(0.0, 1.0),
                finite(s.friction, 0.0).clamp(0.0, 1.0),
                if s.depth.is_some() { 1.0 } else { 0.0 },
            ],
            life: [
                finite(s.lifetime, 0.0).max(0.0),
                finite(s.lifetime_spread, 0.0).max(0.0),
                dt,
                finite(s.world_radius, 100.0).max(0.0),
            ],
            counts: [self.capacity, self.head, emit, self.emitted as u32],
            misc: [
                u32::from(s.integrator == Integrator::Exponential),
                s.attractors.len().min(MAX_ATTRACTORS) as u32,
                self.seed,
                triangles,
            ],
            view_projection: depth_view_projection.to_cols_array_2d(),
            inverse_view_projection: crate::camera::safe_inverse(depth_view_projection)
                .to_cols_array_2d(),
            depth_size: s.depth.as_ref().map_or([1.0, 1.0, 0.0, 0.0], |d| {
                [
                    d.size.0 as f32,
                    d.size.1 as f32,
                    finite(d.thickness, 0.0).max(0.0),
                    0.0,
                ]
            }),
            layout: [self.first_record(), 0, 0, 0],
            attractors,
        };
        let key = SimulateKey {
            field_texture: matches!(s.field, Field::Texture { .. }),
            mesh_emitter: mesh.is_some(),
            depth_collision: s.depth.is_some(),
        }
        .key();
        let sim = uniform(renderer, "particle sim", bytemuck::bytes_of(&gpu_sim));
        let (vertices, indices, _) = renderer.meshes.buffers();
        let mesh_range = uniform(
            renderer,
            "particle emitter mesh",
            bytemuck::bytes_of(
                &mesh
                    .as_ref()
                    .map_or([0u32; 4], |m| [m.indices.start, m.vertices.start, 0, 0]),
            ),
        );
        let mut resources = vec![
            ("records", vertices.as_entire_binding()),
            ("sim", sim.as_entire_binding()),
            ("mesh_indices", indices.as_entire_binding()),
            ("mesh_range", mesh_range.as_entire_binding()),
        ];
        if let Field::Texture { texture, .. } = &s.field {
            resources.push((
                "field_texture",
                wgpu::BindingResource::TextureView(&texture.view),
            ));
        }
        if let Some(d) = &s.depth {
            resources.push(("depth", wgpu::BindingResource::TextureView(&d.depth)));
        }
        dispatch(renderer, &key, resources, self.capacity)?;
        self.head = ((u64::from(self.head) + u64::from(emit)) % u64::from(self.capacity)) as u32;
        self.emitted += u64::from(emit);
        self.time += f64::from(dt);
        Ok(())
    }
}

/// The layout the shader sees (shaders/layout.rs).
#[cfg(test)]
mod wgsl_layout {
    use super::*;

    #[test]
    fn gpu_sim_matches_sim_in_the_shader() {
        crate::assert_wgsl_layout!(
            GpuSim,
            crate::particles::simulate_key::SimulateKey,
            [],
            "Sim",
            [
                emitter,
                emitter_size,
                velocity,
                gravity,
                field,
                field_min,
                field_max,
                plane,
                collide,
                life,
                counts,
                misc,
                view_projection,
                inverse_view_projection,
                depth_size,
                layout,
                attractors
            ]
        );
    }
}
