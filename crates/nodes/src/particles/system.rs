//! `Particles`: one particle system, simulated every frame on the GPU with
//! the clock's time step, its state kept in the node between frames (Reset,
//! a new Count or Seed start it over), drawn as a procedural mesh (straight
//! from the particle records) with previous positions. Depth collision reads
//! the depth an MRE published last frame under a name (no link: the MRE is
//! downstream of the particles).

use std::sync::Arc;

use glam::{Mat4, Vec3, Vec4};
use spreadlight_graph::{
    Choice, Choices, EvalContext, In, Node, NodeDef, NodeError, Out, Registry, Res, ResourceKind,
};
use spreadlight_render::gbuffer::PublishedDepths;
use spreadlight_render::mesh_arena::GpuMesh;
use spreadlight_render::particles::{
    DepthCollision, DrawShape, EmitterShape, Field, FieldTexture, Integrator, ParticleSettings,
    ParticleSystem, Plane, draw,
};

use crate::gpu::renderer;

/// The Emitter pin's options (a shape's measures come from other pins).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum EmitterKind {
    Point,
    Box,
    Sphere,
    MeshSurface,
}

pub static EMITTER: Choices<EmitterKind> = Choices::new(
    "Particle Emitter",
    &["Point", "Box", "Sphere", "Mesh Surface"],
    &[
        EmitterKind::Point,
        EmitterKind::Box,
        EmitterKind::Sphere,
        EmitterKind::MeshSurface,
    ],
);

/// The Field pin's options.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum FieldKind {
    None,
    CurlNoise,
    Texture,
}

pub static FIELD: Choices<FieldKind> = Choices::new(
    "Particle Field",
    &["None", "Curl Noise", "Texture"],
    &[FieldKind::None, FieldKind::CurlNoise, FieldKind::Texture],
);

pub static INTEGRATOR: Choices<Integrator> = Choices::new(
    "Particle Integrator",
    &["Exponential", "Explicit Euler"],
    &[Integrator::Exponential, Integrator::ExplicitEuler],
);

/// The Draw pin's options.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum DrawKind {
    Sprites,
    Mesh,
}

pub static DRAW: Choices<DrawKind> = Choices::new(
    "Particle Draw",
    &["Sprites", "Mesh"],
    &[DrawKind::Sprites, DrawKind::Mesh],
);

/// The node's pins, in order.
#[derive(Clone, Copy)]
struct Pins {
    count: In<i64>,
    seed: In<i64>,
    reset: In<bool>,
    emitter: In<Choice<EmitterKind>>,
    emitter_transform: In<Mat4>,
    emitter_size: In<Vec3>,
    emitter_mesh: In<Res<GpuMesh>>,
    rate: In<f32>,
    lifetime: In<f32>,
    lifetime_spread: In<f32>,
    velocity: In<Vec3>,
    velocity_spread: In<f32>,
    gravity: In<Vec3>,
    drag: In<f32>,
    field: In<Choice<FieldKind>>,
    field_strength: In<f32>,
    curl_frequency: In<f32>,
    field_texture: In<Res<FieldTexture>>,
    field_min: In<Vec3>,
    field_max: In<Vec3>,
    attractors: In<Vec4>,
    collide_plane: In<bool>,
    plane_normal: In<Vec3>,
    plane_offset: In<f32>,
    bounce: In<f32>,
    friction: In<f32>,
    world_radius: In<f32>,
    integrator: In<Choice<Integrator>>,
    draw: In<Choice<DrawKind>>,
    shape: In<Res<GpuMesh>>,
    size: In<f32>,
    shrink: In<bool>,
    collide_depth: In<String>,
    depth_thickness: In<f32>,
    out: Out<Res<GpuMesh>>,
}

impl Pins {
    fn declare(p: &mut spreadlight_graph::Pins<'_>) -> Self {
        let mesh = |p: &mut spreadlight_graph::Pins<'_>, name: &'static str| {
            p.input_resource::<GpuMesh>(name, ResourceKind::Mesh)
        };
        Pins {
            count: p.input("Count", 10_000i64),
            seed: p.input("Seed", 1i64),
            reset: p.input("Reset", false),
            emitter: p.input_choice("Emitter", &EMITTER, EmitterKind::Point),
            emitter_transform: p.input("Emitter Transform", Mat4::IDENTITY),
            emitter_size: p.input("Emitter Size", Vec3::splat(0.5)),
            emitter_mesh: mesh(p, "Emitter Mesh"),
            rate: p.input("Rate", 1000.0f32),
            lifetime: p.input("Lifetime", 3.0f32),
            lifetime_spread: p.input("Lifetime Spread", 0.5f32),
            velocity: p.input("Velocity", Vec3::new(0.0, 2.0, 0.0)),
            velocity_spread: p.input("Velocity Spread", 0.5f32),
            gravity: p.input("Gravity", Vec3::new(0.0, -9.81, 0.0)),
            drag: p.input("Drag", 0.1f32),
            field: p.input_choice("Field", &FIELD, FieldKind::None),
            field_strength: p.input("Field Strength", 1.0f32),
            curl_frequency: p.input("Curl Frequency", 1.0f32),
            field_texture: p.input_resource::<FieldTexture>("Field Texture", ResourceKind::Buffer),
            field_min: p.input("Field Min", Vec3::splat(-1.0)),
            field_max: p.input("Field Max", Vec3::splat(1.0)),
            attractors: p.input_spread("Attractors", Vec::<Vec4>::new()),
            collide_plane: p.input("Collide Plane", false),
            plane_normal: p.input("Plane Normal", Vec3::Y),
            plane_offset: p.input("Plane Offset", 0.0f32),
            bounce: p.input("Bounce", 0.5f32),
            friction: p.input("Friction", 0.1f32),
            world_radius: p.input("World Radius", 100.0f32),
            integrator: p.input_choice("Integrator", &INTEGRATOR, Integrator::Exponential),
            draw: p.input_choice("Draw", &DRAW, DrawKind::Sprites),
            shape: mesh(p, "Shape"),
            size: p.input("Size", 0.02f32),
            shrink: p.input("Shrink", true),
            collide_depth: p.input("Collide Depth", String::new()),
            depth_thickness: p.input("Depth Thickness", 0.5f32),
            out: p.output_resource::<GpuMesh>("Mesh", ResourceKind::Mesh),
        }
    }
}

/// The most slots one system may have (64 bytes each in the mesh arena,
/// which the GPU's storage buffer limit caps too).
const MAX_COUNT: i64 = 1 << 25;

pub fn register(r: &mut Registry) {
    r.add(
        NodeDef::new(
            "Particles",
            super::CATEGORY,
            "A particle system simulated on the GPU each frame with the clock's time step (at most 0.1 s a step): \
             Count slots in a ring, filled at Rate a second (negative: Count / Lifetime, the ring kept full) from the Emitter (Point, Box of half size Emitter Size, \
             Sphere of radius Emitter Size.x, or the surface of Emitter Mesh, placed by Emitter Transform); each lives \
             Lifetime ± Lifetime Spread seconds, starts at Velocity plus a random vector up to Velocity Spread long, \
             and is pushed by Gravity, Drag (per second), a Field (curl noise of Curl Frequency, or a VectorField \
             texture over Field Min..Field Max) times Field Strength, and Attractors (xyz position, w strength). \
             Collides with a plane (Bounce, Friction) and, when Collide Depth names the depth an MRE publishes \
             (its Publish Depth pin), with last frame's depth of that MRE's meshes (not its particles): a particle \
             that went behind the visible surface by less than Depth Thickness metres steps back and bounces off \
             the surface's normal. Dies beyond World Radius. Fixed Seed and frame rate: the same \
             particles every run; Reset starts over. Output: a mesh drawn straight from the particle state (quads \
             facing whichever view draws them, or copies of Shape; 64 bytes a particle, so ten million fit) with \
             previous positions and each particle's slot as geometry id: DeferredBase with Velocity \
             Geometry blurs them, Instance from GeomFX numbers them; into Transparency they blend unsorted.",
        )
        .time_dependent()
        .stateful()
        .with_pins_node(|p| {
            let pins = Pins::declare(p);
            move || Particles { pins, system: None }
        }),
    );
}

struct Particles {
    pins: Pins,
    system: Option<ParticleSystem>,
}

fn first_mesh(
    cx: &EvalContext<'_>,
    pin: In<Res<GpuMesh>>,
    what: &str,
) -> Result<Arc<GpuMesh>, NodeError> {
    cx.first_resource(pin)?
        .ok_or_else(|| cx.error(pin, format!("{what} needs a mesh here")))
}

impl Particles {
    /// The depth published under Collide Depth's name (None: off, or not
    /// published yet: the first frame, before the MRE has rendered once).
    fn depth(cx: &EvalContext<'_>, pins: Pins) -> Result<Option<DepthCollision>, NodeError> {
        let name = cx
            .get(pins.collide_depth)?
            .first()
            .cloned()
            .unwrap_or_default();
        if name.is_empty() {
            return Ok(None);
        }
        let renderer = renderer(cx)?;
        let thickness = cx.first(pins.depth_thickness, 0.5f32)?;
        if !(thickness.is_finite() && thickness >= 0.0) {
            return Err(cx.error(
                pins.depth_thickness,
                format!("{thickness} is not a distance (0 or more metres)"),
            ));
        }
        Ok(PublishedDepths::of(&renderer)
            .get(&name)
            .map(|d| DepthCollision {
                depth: d.texture.create_view(&Default::default()),
                view_projection: d.view_projection,
                size: d.size,
                thickness,
            }))
    }

    fn settings(
        cx: &EvalContext<'_>,
        pins: Pins,
        count: i64,
    ) -> Result<ParticleSettings, NodeError> {
        let size = cx.first(pins.emitter_size, Vec3::ONE)?;
        let shape = match cx.choice(pins.emitter)? {
            EmitterKind::Box => EmitterShape::Box(size),
            EmitterKind::Sphere => EmitterShape::Sphere(size.x),
            EmitterKind::MeshSurface => EmitterShape::MeshSurface(first_mesh(
                cx,
                pins.emitter_mesh,
                "Emitter Mesh Surface",
            )?),
            EmitterKind::Point => EmitterShape::Point,
        };
        let strength = cx.first(pins.field_strength, 1.0f32)?;
        let field = match cx.choice(pins.field)? {
            FieldKind::CurlNoise => Field::Curl {
                frequency: cx.first(pins.curl_frequency, 1.0f32)?,
                strength,
            },
            FieldKind::Texture => Field::Texture {
                texture: cx.first_resource(pins.field_texture)?.ok_or_else(|| {
                    cx.error(pins.field_texture, "Field Texture needs a VectorField here")
                })?,
                min: cx.first(pins.field_min, Vec3::splat(-1.0))?,
                max: cx.first(pins.field_max, Vec3::ONE)?,
                strength,
            },
            FieldKind::None => Field::None,
        };
        let plane = cx.first(pins.collide_plane, false)?.then_some(Plane {
            normal: cx.first(pins.plane_normal, Vec3::Y)?,
            offset: cx.first(pins.plane_offset, 0.0f32)?,
        });
        Ok(ParticleSettings {
            emitter: cx.first(pins.emitter_transform, Mat4::IDENTITY)?,
            shape,
            rate: match (
                cx.first(pins.rate, 0.0f32)?,
                cx.first(pins.lifetime, 1.0f32)?,
            ) {
                // Negative: keep the ring full (Count a Lifetime).
                (rate, lifetime) if rate < 0.0 && lifetime > 0.0 => count as f32 / lifetime,
                (rate, _) => rate,
            },
            lifetime: cx.first(pins.lifetime, 1.0f32)?,
            lifetime_spread: cx.first(pins.lifetime_spread, 0.0f32)?,
            velocity: cx.first(pins.velocity, Vec3::ZERO)?,
            velocity_spread: cx.first(pins.velocity_spread, 0.0f32)?,
            gravity: cx.first(pins.gravity, Vec3::ZERO)?,
            drag: cx.first(pins.drag, 0.0f32)?,
            field,
            attractors: cx.get(pins.attractors)?.to_vec(),
            plane,
            bounce: cx.first(pins.bounce, 0.5f32)?,
            friction: cx.first(pins.friction, 0.1f32)?,
            depth: Self::depth(cx, pins)?,
            world_radius: cx.first(pins.world_radius, 100.0f32)?,
            integrator: cx.choice(pins.integrator)?,
        })
    }
}

impl Node for Particles {
    fn evaluate(&mut self, cx: &mut EvalContext<'_>) -> Result<(), NodeError> {
        let pins = self.pins;
        let count = cx.first(pins.count, 0i64)?;
        if !(1..=MAX_COUNT).contains(&count) {
            return Err(cx.error(pins.count, format!("{count} is not within 1..{MAX_COUNT}")));
        }
        let seed = cx.first(pins.seed, 0i64)? as u32;
        let settings = Self::settings(cx, pins, count)?;
        let renderer = renderer(cx)?;
        let fresh = self
            .system
            .as_ref()
            .is_none_or(|s| s.capacity() != count as u32 || s.seed() != seed);
        if fresh {
            self.system = Some(
                ParticleSystem::new(&renderer, count as u32, seed)
                    .map_err(|e| cx.error(pins.count, e.to_string()))?,
            );
        }
        let Some(system) = self.system.as_mut() else {
            return Ok(());
        };
        if cx.first(pins.reset, false)? && !fresh {
            system.reset(&renderer);
        }
        let other = |e: spreadlight_render::RenderError| NodeError::Other(e.to_string());
        system
            .step(&renderer, &settings, cx.clock.delta as f32)
            .map_err(other)?;
        let shape_mesh;
        let shape = match cx.choice(pins.draw)? {
            DrawKind::Mesh => {
                shape_mesh = first_mesh(cx, pins.shape, "Draw Mesh")?;
                DrawShape::Mesh(&shape_mesh)
            }
            DrawKind::Sprites => DrawShape::Sprites,
        };
        let mesh = draw(
            &renderer,
            system,
            shape,
            cx.first(pins.size, 0.02f32)?,
            cx.first(pins.shrink, true)?,
            settings.world_radius,
        )
        .map_err(|e| cx.error(pins.shape, e.to_string()))?;
        cx.put_resources(pins.out, vec![mesh]);
        Ok(())
    }
}
