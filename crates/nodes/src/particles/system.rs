//! `Particles`: one particle system, simulated every frame on the GPU with
//! the clock's time step, its state kept in the node between frames (Reset,
//! a new Count or Seed start it over), drawn as a procedural mesh (straight
//! from the particle records) with previous positions. Depth collision reads
//! the depth an MRE published last frame under a name (no link: the MRE is
//! downstream of the particles).

use std::sync::Arc;

use glam::{Mat4, Vec3, Vec4};
use spreadlight_graph::{
    EnumDef, EvalContext, Node, NodeDef, NodeError, PinType, Registry, ResourceKind, Spread,
};
use spreadlight_render::gbuffer::PublishedDepths;
use spreadlight_render::mesh_arena::GpuMesh;
use spreadlight_render::particles::{
    DepthCollision, DrawShape, EmitterShape, Field, FieldTexture, Integrator, ParticleSettings,
    ParticleSystem, Plane, draw,
};

use crate::gpu::{renderer, resource_spread, resources};

pub static EMITTER: EnumDef = EnumDef {
    name: "Particle Emitter",
    options: &["Point", "Box", "Sphere", "Mesh Surface"],
};
pub static FIELD: EnumDef = EnumDef {
    name: "Particle Field",
    options: &["None", "Curl Noise", "Texture"],
};
pub static INTEGRATOR: EnumDef = EnumDef {
    name: "Particle Integrator",
    options: &["Exponential", "Explicit Euler"],
};
pub static DRAW: EnumDef = EnumDef {
    name: "Particle Draw",
    options: &["Sprites", "Mesh"],
};

/// Input pins, in order.
mod pin {
    pub const COUNT: usize = 0;
    pub const SEED: usize = 1;
    pub const RESET: usize = 2;
    pub const EMITTER: usize = 3;
    pub const EMITTER_TRANSFORM: usize = 4;
    pub const EMITTER_SIZE: usize = 5;
    pub const EMITTER_MESH: usize = 6;
    pub const RATE: usize = 7;
    pub const LIFETIME: usize = 8;
    pub const LIFETIME_SPREAD: usize = 9;
    pub const VELOCITY: usize = 10;
    pub const VELOCITY_SPREAD: usize = 11;
    pub const GRAVITY: usize = 12;
    pub const DRAG: usize = 13;
    pub const FIELD: usize = 14;
    pub const FIELD_STRENGTH: usize = 15;
    pub const CURL_FREQUENCY: usize = 16;
    pub const FIELD_TEXTURE: usize = 17;
    pub const FIELD_MIN: usize = 18;
    pub const FIELD_MAX: usize = 19;
    pub const ATTRACTORS: usize = 20;
    pub const COLLIDE_PLANE: usize = 21;
    pub const PLANE_NORMAL: usize = 22;
    pub const PLANE_OFFSET: usize = 23;
    pub const BOUNCE: usize = 24;
    pub const FRICTION: usize = 25;
    pub const WORLD_RADIUS: usize = 26;
    pub const INTEGRATOR: usize = 27;
    pub const DRAW: usize = 28;
    pub const SHAPE: usize = 29;
    pub const SIZE: usize = 30;
    pub const SHRINK: usize = 31;
    pub const COLLIDE_DEPTH: usize = 32;
    pub const DEPTH_THICKNESS: usize = 33;
}

/// The most slots one system may have (64 bytes each in the mesh arena,
/// which the GPU's storage buffer limit caps too).
const MAX_COUNT: i64 = 1 << 25;

pub fn register(r: &mut Registry) {
    let mesh = || Spread::Resource(ResourceKind::Mesh, vec![]);
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
        .input("Count", 10_000i64)
        .input("Seed", 1i64)
        .input("Reset", false)
        .input_enum("Emitter", &EMITTER, "Point")
        .input("Emitter Transform", Mat4::IDENTITY)
        .input("Emitter Size", Vec3::splat(0.5))
        .input_spread("Emitter Mesh", PinType::Resource(ResourceKind::Mesh), mesh())
        .input("Rate", 1000.0f32)
        .input("Lifetime", 3.0f32)
        .input("Lifetime Spread", 0.5f32)
        .input("Velocity", Vec3::new(0.0, 2.0, 0.0))
        .input("Velocity Spread", 0.5f32)
        .input("Gravity", Vec3::new(0.0, -9.81, 0.0))
        .input("Drag", 0.1f32)
        .input_enum("Field", &FIELD, "None")
        .input("Field Strength", 1.0f32)
        .input("Curl Frequency", 1.0f32)
        .input_spread(
            "Field Texture",
            PinType::Resource(ResourceKind::Buffer),
            Spread::Resource(ResourceKind::Buffer, vec![]),
        )
        .input("Field Min", Vec3::splat(-1.0))
        .input("Field Max", Vec3::splat(1.0))
        .input_spread("Attractors", PinType::Vec4, Spread::Vec4(vec![]))
        .input("Collide Plane", false)
        .input("Plane Normal", Vec3::Y)
        .input("Plane Offset", 0.0f32)
        .input("Bounce", 0.5f32)
        .input("Friction", 0.1f32)
        .input("World Radius", 100.0f32)
        .input_enum("Integrator", &INTEGRATOR, "Exponential")
        .input_enum("Draw", &DRAW, "Sprites")
        .input_spread("Shape", PinType::Resource(ResourceKind::Mesh), mesh())
        .input("Size", 0.02f32)
        .input("Shrink", true)
        .input("Collide Depth", String::new())
        .input("Depth Thickness", 0.5f32)
        .output_typed("Mesh", PinType::Resource(ResourceKind::Mesh))
        .time_dependent()
        .stateful()
        .construct(Particles::default),
    );
}

#[derive(Default)]
struct Particles {
    system: Option<ParticleSystem>,
}

fn first<T: spreadlight_graph::SliceValue + Copy>(
    cx: &EvalContext<'_>,
    pin: usize,
    or: T,
) -> Result<T, NodeError> {
    Ok(cx.slices::<T>(pin)?.first().copied().unwrap_or(or))
}

fn choice<'c>(cx: &'c EvalContext<'_>, pin: usize) -> Result<&'c str, NodeError> {
    Ok(cx.enum_slices(pin)?.first().map_or("", String::as_str))
}

fn first_mesh(cx: &EvalContext<'_>, pin: usize, what: &str) -> Result<Arc<GpuMesh>, NodeError> {
    resources::<GpuMesh>(cx, pin)?
        .into_iter()
        .next()
        .ok_or_else(|| cx.input_error(pin, format!("{what} needs a mesh here")))
}

impl Particles {
    /// The depth published under Collide Depth's name (None: off, or not
    /// published yet: the first frame, before the MRE has rendered once).
    fn depth(cx: &EvalContext<'_>) -> Result<Option<DepthCollision>, NodeError> {
        let name = cx
            .slices::<String>(pin::COLLIDE_DEPTH)?
            .first()
            .cloned()
            .unwrap_or_default();
        if name.is_empty() {
            return Ok(None);
        }
        let renderer = renderer(cx)?;
        let thickness = first(cx, pin::DEPTH_THICKNESS, 0.5f32)?;
        if !(thickness.is_finite() && thickness >= 0.0) {
            return Err(cx.input_error(
                pin::DEPTH_THICKNESS,
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

    fn settings(cx: &EvalContext<'_>, count: i64) -> Result<ParticleSettings, NodeError> {
        let size = first(cx, pin::EMITTER_SIZE, Vec3::ONE)?;
        let shape = match choice(cx, pin::EMITTER)? {
            "Box" => EmitterShape::Box(size),
            "Sphere" => EmitterShape::Sphere(size.x),
            "Mesh Surface" => EmitterShape::MeshSurface(first_mesh(
                cx,
                pin::EMITTER_MESH,
                "Emitter Mesh Surface",
            )?),
            _ => EmitterShape::Point,
        };
        let strength = first(cx, pin::FIELD_STRENGTH, 1.0f32)?;
        let field = match choice(cx, pin::FIELD)? {
            "Curl Noise" => Field::Curl {
                frequency: first(cx, pin::CURL_FREQUENCY, 1.0f32)?,
                strength,
            },
            "Texture" => Field::Texture {
                texture: resources::<FieldTexture>(cx, pin::FIELD_TEXTURE)?
                    .into_iter()
                    .next()
                    .ok_or_else(|| {
                        cx.input_error(pin::FIELD_TEXTURE, "Field Texture needs a VectorField here")
                    })?,
                min: first(cx, pin::FIELD_MIN, Vec3::splat(-1.0))?,
                max: first(cx, pin::FIELD_MAX, Vec3::ONE)?,
                strength,
            },
            _ => Field::None,
        };
        let plane = first(cx, pin::COLLIDE_PLANE, false)?.then_some(Plane {
            normal: first(cx, pin::PLANE_NORMAL, Vec3::Y)?,
            offset: first(cx, pin::PLANE_OFFSET, 0.0f32)?,
        });
        Ok(ParticleSettings {
            emitter: first(cx, pin::EMITTER_TRANSFORM, Mat4::IDENTITY)?,
            shape,
            rate: match (
                first(cx, pin::RATE, 0.0f32)?,
                first(cx, pin::LIFETIME, 1.0f32)?,
            ) {
                // Negative: keep the ring full (Count a Lifetime).
                (rate, lifetime) if rate < 0.0 && lifetime > 0.0 => count as f32 / lifetime,
                (rate, _) => rate,
            },
            lifetime: first(cx, pin::LIFETIME, 1.0f32)?,
            lifetime_spread: first(cx, pin::LIFETIME_SPREAD, 0.0f32)?,
            velocity: first(cx, pin::VELOCITY, Vec3::ZERO)?,
            velocity_spread: first(cx, pin::VELOCITY_SPREAD, 0.0f32)?,
            gravity: first(cx, pin::GRAVITY, Vec3::ZERO)?,
            drag: first(cx, pin::DRAG, 0.0f32)?,
            field,
            attractors: cx.slices::<Vec4>(pin::ATTRACTORS)?.to_vec(),
            plane,
            bounce: first(cx, pin::BOUNCE, 0.5f32)?,
            friction: first(cx, pin::FRICTION, 0.1f32)?,
            depth: Self::depth(cx)?,
            world_radius: first(cx, pin::WORLD_RADIUS, 100.0f32)?,
            integrator: match choice(cx, pin::INTEGRATOR)? {
                "Explicit Euler" => Integrator::ExplicitEuler,
                _ => Integrator::Exponential,
            },
        })
    }
}

impl Node for Particles {
    fn evaluate(&mut self, cx: &mut EvalContext<'_>) -> Result<(), NodeError> {
        let count = first(cx, pin::COUNT, 0i64)?;
        if !(1..=MAX_COUNT).contains(&count) {
            return Err(cx.input_error(pin::COUNT, format!("{count} is not within 1..{MAX_COUNT}")));
        }
        let seed = first(cx, pin::SEED, 0i64)? as u32;
        let settings = Self::settings(cx, count)?;
        let renderer = renderer(cx)?;
        let fresh = self
            .system
            .as_ref()
            .is_none_or(|s| s.capacity() != count as u32 || s.seed() != seed);
        if fresh {
            self.system = Some(
                ParticleSystem::new(&renderer, count as u32, seed)
                    .map_err(|e| cx.input_error(pin::COUNT, e.to_string()))?,
            );
        }
        let Some(system) = self.system.as_mut() else {
            return Ok(());
        };
        if first(cx, pin::RESET, false)? && !fresh {
            system.reset(&renderer);
        }
        let other = |e: spreadlight_render::RenderError| NodeError::Other(e.to_string());
        system
            .step(&renderer, &settings, cx.clock.delta as f32)
            .map_err(other)?;
        let shape_mesh;
        let shape = match choice(cx, pin::DRAW)? {
            "Mesh" => {
                shape_mesh = first_mesh(cx, pin::SHAPE, "Draw Mesh")?;
                DrawShape::Mesh(&shape_mesh)
            }
            _ => DrawShape::Sprites,
        };
        let mesh = draw(
            &renderer,
            system,
            shape,
            first(cx, pin::SIZE, 0.02f32)?,
            first(cx, pin::SHRINK, true)?,
            settings.world_radius,
        )
        .map_err(|e| cx.input_error(pin::SHAPE, e.to_string()))?;
        cx.set_output(0, resource_spread(ResourceKind::Mesh, vec![mesh]));
        Ok(())
    }
}
