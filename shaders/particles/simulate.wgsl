// Particles, simulation: one invocation per slot of a ring of `capacity`
// particles, kept as records in the mesh arena (shaders/lib/particle.wgsl)
// so that every drawing pass reads them straight from there. This step's emission is the `emit` slots from `head` on, each
// seeded by its global emission index, so the result depends only on the
// seed and the sequence of time steps (not on thread order): deterministic.
//
// Forces: gravity, linear drag, a vector field (curl noise or a 3D texture),
// attractors. Integrators: explicit Euler, or the exponential integrator:
// the step solved exactly for the acceleration at its start under linear
// drag (v' = v e^(-k dt) + a g, x' = x + v g + a (dt - g) / k, with
// g = (1 - e^(-k dt)) / k), stable for any drag and step. Collisions:
// a plane, and the previous frame's depth buffer (screen space), bouncing
// off the surface normal the depth gives.
// Nothing non-finite survives a step: such a particle dies.

#import spreadlight::mesh::Vertex
#import spreadlight::particle::{Particle, pack_particle, unpack_particle}

// Matches `GpuSim` in crates/render/src/particles/simulate.rs.
struct Sim {
    emitter: mat4x4<f32>,
    // Box half size (xyz) or sphere radius (x); w: shape (0 point, 1 box, 2 sphere, 3 mesh surface).
    emitter_size: vec4<f32>,
    // Initial velocity (xyz) and the radius of its random spread (w).
    velocity: vec4<f32>,
    // Gravity (xyz) and drag coefficient per second (w).
    gravity: vec4<f32>,
    // Field: x scale (curl frequency), y strength, z time, w kind (0 none, 1 curl, 2 texture).
    field: vec4<f32>,
    // Texture field bounds.
    field_min: vec4<f32>,
    field_max: vec4<f32>,
    // Plane: unit normal (xyz) and offset (w): dot(n, p) >= w is outside.
    plane: vec4<f32>,
    // x: plane on, y: bounce, z: friction, w: depth collision on.
    collide: vec4<f32>,
    // x: lifetime, y: lifetime spread, z: time step, w: world radius (particles beyond die).
    life: vec4<f32>,
    // x: capacity, y: head, z: emit count, w: emitted before this step (low 32 bits).
    counts: vec4<u32>,
    // x: integrator (0 explicit Euler, 1 exponential), y: attractor count, z: seed, w: mesh triangles.
    misc: vec4<u32>,
    // Depth collision: last frame's view-projection (reversed Z) and its
    // inverse, the depth target's size (xy) and the thickness in metres (z).
    view_projection: mat4x4<f32>,
    inverse_view_projection: mat4x4<f32>,
    depth_size: vec4<f32>,
    // x: the arena index of slot 0's record.
    records_at: vec4<u32>,
    // Attractors: position (xyz), strength (w).
    attractors: array<vec4<f32>, 8>,
}

// The mesh arena: particle records (from sim.records_at.x on) and the emitter mesh's vertices.
@group(0) @binding(0) var<storage, read_write> records: array<Vertex>;
@group(0) @binding(1) var<uniform> sim: Sim;
#ifdef FIELD_TEXTURE
@group(0) @binding(2) var field_texture: texture_3d<f32>;
#endif
#ifdef MESH_EMITTER
@group(0) @binding(4) var<storage, read> mesh_indices: array<u32>;
// x: first index, y: base vertex.
@group(0) @binding(5) var<uniform> mesh_range: vec4<u32>;
#endif
#ifdef DEPTH_COLLISION
@group(0) @binding(6) var depth: texture_2d<f32>;
#endif

const MAX_SPEED: f32 = 1.0e4;

fn pcg(v: u32) -> u32 {
    let state = v * 747796405u + 2891336453u;
    let word = ((state >> ((state >> 28u) + 4u)) ^ state) * 277803737u;
    return (word >> 22u) ^ word;
}

// A random number generator per emission: uniform floats in [0, 1).
struct Rng {
    state: u32,
}

fn next(rng: ptr<function, Rng>) -> f32 {
    (*rng).state = pcg((*rng).state);
    return f32((*rng).state >> 8u) / 16777216.0;
}

fn in_unit_ball(rng: ptr<function, Rng>) -> vec3<f32> {
    // Direction from the normal-free trick: uniform on the sphere, radius by cube root.
    let z = next(rng) * 2.0 - 1.0;
    let a = next(rng) * 6.2831853;
    let r = sqrt(max(1.0 - z * z, 0.0));
    return vec3<f32>(r * cos(a), r * sin(a), z) * pow(next(rng), 1.0 / 3.0);
}

fn emit_position(rng: ptr<function, Rng>) -> vec3<f32> {
    let shape = u32(sim.emitter_size.w);
    var local = vec3<f32>(0.0);
    if (shape == 1u) {
        local = (vec3<f32>(next(rng), next(rng), next(rng)) * 2.0 - 1.0) * sim.emitter_size.xyz;
    } else if (shape == 2u) {
        local = in_unit_ball(rng) * sim.emitter_size.x;
    }
#ifdef MESH_EMITTER
    if (shape == 3u && sim.misc.w > 0u) {
        // A triangle picked uniformly (not by area), a point uniform on it.
        let t = min(u32(next(rng) * f32(sim.misc.w)), sim.misc.w - 1u);
        let first = mesh_range.x + t * 3u;
        let a = records[mesh_indices[first] + mesh_range.y].position_u.xyz;
        let b = records[mesh_indices[first + 1u] + mesh_range.y].position_u.xyz;
        let c = records[mesh_indices[first + 2u] + mesh_range.y].position_u.xyz;
        var u = next(rng);
        var v = next(rng);
        if (u + v > 1.0) {
            u = 1.0 - u;
            v = 1.0 - v;
        }
        local = a + (b - a) * u + (c - a) * v;
    }
#endif
    return (sim.emitter * vec4<f32>(local, 1.0)).xyz;
}

// The curl of a trigonometric vector potential, two octaves (the second
// scaled and shifted, which keeps it a curl): divergence-free, smooth,
// animated by time.
fn curl_noise(p: vec3<f32>, t: f32) -> vec3<f32> {
    var total = vec3<f32>(0.0);
    var q = p * sim.field.x;
    var amplitude = 1.0;
    for (var octave = 0; octave < 2; octave++) {
        // Potential (sin(y + t) cos z, sin(z + t) cos x, sin(x + t) cos y).
        let sx = sin(q.x + t);
        let sy = sin(q.y + t);
        let sz = sin(q.z + t);
        let cx = cos(q.x);
        let cy = cos(q.y);
        let cz = cos(q.z);
        // curl = (dPz/dy - dPy/dz, dPx/dz - dPz/dx, dPy/dx - dPx/dy)
        let pz_y = -sx * sin(q.y);
        let py_z = cos(q.z + t) * cx;
        let px_z = -sy * sin(q.z);
        let pz_x = cos(q.x + t) * cy;
        let py_x = -sz * sin(q.x);
        let px_y = cos(q.y + t) * cz;
        total += amplitude * vec3<f32>(pz_y - py_z, px_z - pz_x, py_x - px_y);
        q = q * 2.0 + vec3<f32>(1.3, 2.7, 0.4);
        amplitude *= 0.5;
    }
    return total;
}

#ifdef FIELD_TEXTURE
fn texel(c: vec3<i32>) -> vec3<f32> {
    let v = textureLoad(field_texture, c, 0).xyz;
    // NaN or infinity in the field counts as no force.
    if (all(abs(v) < vec3<f32>(3.0e38))) {
        return v;
    }
    return vec3<f32>(0.0);
}

// Trilinear sample of the texture over its bounds; zero outside.
fn texture_field(p: vec3<f32>) -> vec3<f32> {
    let extent = sim.field_max.xyz - sim.field_min.xyz;
    let uvw = (p - sim.field_min.xyz) / max(extent, vec3<f32>(1e-20));
    if (any(uvw < vec3<f32>(0.0)) || any(uvw > vec3<f32>(1.0))) {
        return vec3<f32>(0.0);
    }
    let size = vec3<i32>(textureDimensions(field_texture));
    let x = uvw * vec3<f32>(size - 1);
    let i0 = clamp(vec3<i32>(floor(x)), vec3<i32>(0), size - 1);
    let i1 = min(i0 + 1, size - 1);
    let f = x - vec3<f32>(i0);
    let c00 = mix(texel(i0), texel(vec3<i32>(i1.x, i0.y, i0.z)), f.x);
    let c10 = mix(texel(vec3<i32>(i0.x, i1.y, i0.z)), texel(vec3<i32>(i1.x, i1.y, i0.z)), f.x);
    let c01 = mix(texel(vec3<i32>(i0.x, i0.y, i1.z)), texel(vec3<i32>(i1.x, i0.y, i1.z)), f.x);
    let c11 = mix(texel(vec3<i32>(i0.x, i1.y, i1.z)), texel(i1), f.x);
    return mix(mix(c00, c10, f.y), mix(c01, c11, f.y), f.z);
}
#endif

// Acceleration without drag at `p`.
fn acceleration(p: vec3<f32>) -> vec3<f32> {
    var a = sim.gravity.xyz;
    let kind = u32(sim.field.w);
    if (kind == 1u) {
        a += curl_noise(p, sim.field.z) * sim.field.y;
    }
#ifdef FIELD_TEXTURE
    if (kind == 2u) {
        a += texture_field(p) * sim.field.y;
    }
#endif
    for (var i = 0u; i < min(sim.misc.y, 8u); i++) {
        let d = sim.attractors[i].xyz - p;
        // Softened inverse square: finite at the centre.
        let r2 = dot(d, d) + 0.01;
        a += d * (sim.attractors[i].w / (r2 * sqrt(r2)));
    }
    return a;
}

fn clamp_speed(v: vec3<f32>) -> vec3<f32> {
    let s = length(v);
    if (s > MAX_SPEED) {
        return v * (MAX_SPEED / s);
    }
    return v;
}

fn collide_plane(p: ptr<function, Particle>) {
    let n = sim.plane.xyz;
    let d = dot(n, (*p).position) - sim.plane.w;
    if (d < 0.0) {
        (*p).position -= n * d;
        let vn = dot((*p).velocity, n);
        if (vn < 0.0) {
            let tangential = (*p).velocity - n * vn;
            (*p).velocity = tangential * (1.0 - sim.collide.z) - n * vn * sim.collide.y;
        }
    }
}

#ifdef DEPTH_COLLISION
// The world point of last frame's depth at `pixel` (None: no surface there).
fn surface_point(pixel: vec2<i32>) -> vec4<f32> {
    let size = vec2<i32>(sim.depth_size.xy);
    let p = clamp(pixel, vec2<i32>(0), size - 1);
    let z = textureLoad(depth, p, 0).x;
    if (!(z > 0.0)) {
        return vec4<f32>(0.0);
    }
    let ndc = vec2<f32>((f32(p.x) + 0.5) / sim.depth_size.x * 2.0 - 1.0, 1.0 - (f32(p.y) + 0.5) / sim.depth_size.y * 2.0);
    let world = sim.inverse_view_projection * vec4<f32>(ndc, z, 1.0);
    if (abs(world.w) < 1e-20) {
        return vec4<f32>(0.0);
    }
    return vec4<f32>(world.xyz / world.w, 1.0);
}

// Screen-space collision with last frame's depth (reversed Z: larger is
// nearer): a particle that went behind the visible surface, by less than
// the thickness (metres), goes back to where it was and bounces off the
// surface's normal (from the neighbouring pixels' depths, facing the eye).
fn collide_depth(p: ptr<function, Particle>) {
    let clip = sim.view_projection * vec4<f32>((*p).position, 1.0);
    if (clip.w <= 1e-6) {
        return;
    }
    let ndc = clip.xyz / clip.w;
    if (any(abs(ndc.xy) > vec2<f32>(1.0))) {
        return;
    }
    let pixel = vec2<i32>((ndc.xy * vec2<f32>(0.5, -0.5) + 0.5) * sim.depth_size.xy);
    let centre = surface_point(pixel);
    if (centre.w == 0.0) {
        return;
    }
    let size = vec2<i32>(sim.depth_size.xy);
    let z = textureLoad(depth, clamp(pixel, vec2<i32>(0), size - 1), 0).x;
    if (ndc.z >= z) {
        return;
    }
    // How far behind the surface, along the particle's own view ray (not
    // to the pixel's centre: a far pixel spans metres of a grazing floor).
    let behind = sim.inverse_view_projection * vec4<f32>(ndc.xy, z, 1.0);
    if (!(abs(behind.w) > 1e-20) || distance(behind.xyz / behind.w, (*p).position) > sim.depth_size.z) {
        return;
    }
    // Normal from the neighbours (the nearer side's difference on each axis, so edges stay sharp).
    let right = surface_point(pixel + vec2<i32>(1, 0));
    let left = surface_point(pixel - vec2<i32>(1, 0));
    let down = surface_point(pixel + vec2<i32>(0, 1));
    let up = surface_point(pixel - vec2<i32>(0, 1));
    var dx = right.xyz - centre.xyz;
    if (right.w == 0.0 || (left.w != 0.0 && distance(left.xyz, centre.xyz) < length(dx))) {
        dx = centre.xyz - left.xyz;
    }
    var dy = centre.xyz - up.xyz;
    if (up.w == 0.0 || (down.w != 0.0 && distance(down.xyz, centre.xyz) < length(dy))) {
        dy = down.xyz - centre.xyz;
    }
    let eye = sim.inverse_view_projection * vec4<f32>(ndc.xy, 1.0, 1.0);
    let towards_eye = eye.xyz / eye.w - centre.xyz;
    var n = cross(dx, dy);
    let len = length(n);
    if (!(len > 1e-12)) {
        n = towards_eye;
    }
    n = n / max(length(n), 1e-20);
    if (dot(n, towards_eye) < 0.0) {
        n = -n;
    }
    let v = (*p).velocity;
    let vn = dot(v, n);
    (*p).position = (*p).previous;
    if (vn < 0.0) {
        let tangential = v - n * vn;
        (*p).velocity = tangential * (1.0 - sim.collide.z) - n * vn * sim.collide.y;
    }
}
#endif

@compute @workgroup_size(64)
fn main(@builtin(global_invocation_id) id: vec3<u32>, @builtin(num_workgroups) groups: vec3<u32>) {
    let i = id.x + id.y * groups.x * 64u;
    let capacity = sim.counts.x;
    if (i >= capacity) {
        return;
    }
    let record = sim.records_at.x + i;
    var p = unpack_particle(records[record]);
    let dt = sim.life.z;
    let slot = (i + capacity - sim.counts.y) % capacity;
    if (slot < sim.counts.z) {
        var rng = Rng(pcg(sim.misc.z ^ pcg(sim.counts.w + slot)));
        p.position = emit_position(&rng);
        p.previous = p.position;
        p.velocity = sim.velocity.xyz + in_unit_ball(&rng) * sim.velocity.w;
        p.lifetime = max(sim.life.x + (next(&rng) * 2.0 - 1.0) * sim.life.y, 1e-3);
        p.age = 0.0;
        p.alive = 1u;
    } else if (p.alive == 1u) {
        p.previous = p.position;
        let a = acceleration(p.position);
        let k = max(sim.gravity.w, 0.0);
        if (sim.misc.x == 0u) {
            // Explicit Euler: position with the old velocity, then velocity.
            p.position += p.velocity * dt;
            p.velocity += (a - k * p.velocity) * dt;
        } else {
            // Exact for a constant acceleration under linear drag over the step.
            let decay = exp(-k * dt);
            // g = (1 - e^(-k dt)) / k and h = (dt - g) / k, by series as k dt -> 0.
            var g = dt - 0.5 * k * dt * dt;
            var h = 0.5 * dt * dt;
            if (k * dt > 1e-3) {
                g = (1.0 - decay) / k;
                h = (dt - g) / k;
            }
            p.position += p.velocity * g + a * h;
            p.velocity = p.velocity * decay + a * g;
        }
        p.velocity = clamp_speed(p.velocity);
        if (sim.collide.x > 0.5) {
            collide_plane(&p);
        }
#ifdef DEPTH_COLLISION
        if (sim.collide.w > 0.5) {
            collide_depth(&p);
        }
#endif
        p.age += dt;
    }
    let finite = all(abs(p.position) < vec3<f32>(3.0e38)) && all(abs(p.velocity) < vec3<f32>(3.0e38))
        && all(abs(p.previous) < vec3<f32>(3.0e38));
    if (p.alive == 1u && (p.age >= p.lifetime || !finite || length(p.position) > sim.life.w)) {
        p.alive = 0u;
    }
    if (!finite) {
        p.position = vec3<f32>(0.0);
        p.previous = vec3<f32>(0.0);
        p.velocity = vec3<f32>(0.0);
    }
    records[record] = pack_particle(p);
}
