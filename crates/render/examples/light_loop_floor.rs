//! Probe: how fast is a light loop's BRDF in paired f16 (two lights a
//! step in vec2<f16>) against f32, on this adapter? Not part of the renderer.
//! cargo run --release -p spreadlight-render --example light_f16_probe

use std::time::Instant;

const COMMON: &str = r#"
@group(0) @binding(0) var<storage, read> lights: array<vec4<f32>>;
@group(0) @binding(1) var<storage, read> radiance: array<vec4<f32>>;
@group(0) @binding(2) var<storage, read_write> out: array<vec4<f32>>;
var<workgroup> wl: array<vec4<f32>, 256>;
var<workgroup> wr: array<vec4<f32>, 256>;
const PI: f32 = 3.14159265;
const MIN_COS: f32 = 1e-4;

struct Surface { n: vec3<f32>, v: vec3<f32>, n_dot_v: f32, view_cosine: f32, a2: f32, lambda_v: f32 }
struct Sums { s: vec3<f32>, g: vec3<f32>, d: vec3<f32> }

fn shade32(lv: vec4<f32>, rad: vec3<f32>, p: vec3<f32>, s: Surface, sums: ptr<function, Sums>) {
    let to_light = lv.xyz - p;
    let d2 = dot(to_light, to_light);
    let ratio2 = d2 * lv.w;
    if (!(ratio2 < 1.0)) { return; }
    let facing = dot(s.n, to_light);
    if (!(facing > 0.0) && d2 > 1e-20) { return; }
    let inv_d = inverseSqrt(max(d2, 1e-20));
    let window = clamp(1.0 - ratio2 * ratio2, 0.0, 1.0);
    let attenuation = window * window * min(inv_d * inv_d, 1e4);
    var n_dot_l = facing * inv_d;
    var v_dot_l = dot(s.v, to_light) * inv_d;
    if (!(d2 > 1e-20)) { n_dot_l = 1.0; v_dot_l = s.view_cosine; }
    let length2 = 2.0 + 2.0 * v_dot_l;
    var nh = 1.0;
    var vh = s.view_cosine;
    if (length2 > 1e-20) {
        let il = inverseSqrt(length2);
        nh = (s.view_cosine + n_dot_l) * il;
        vh = (1.0 + v_dot_l) * il;
    }
    if (n_dot_l <= 0.0) { return; }
    let nl = min(n_dot_l, 1.0);
    let x = 1.0 - clamp(vh, 0.0, 1.0);
    let x2 = x * x;
    let w = x2 * x2 * x;
    let c = clamp(nl, MIN_COS, 1.0);
    let lambda_l = sqrt(c * c * (1.0 - s.a2) + s.a2);
    let vden = 2.0 * (c * s.lambda_v + s.n_dot_v * lambda_l);
    let nhc = clamp(nh, 0.0, 1.0);
    let f = (1.0 - nhc) * (1.0 + nhc) + nhc * nhc * s.a2;
    let root = inverseSqrt(PI * f * f * vden);
    let scaled = nl * attenuation;
    let spec = s.a2 * root * root * scaled;
    (*sums).s += rad * spec;
    (*sums).g += rad * (spec * w);
    (*sums).d += rad * (scaled - scaled * w);
}

fn surface_at(gid: vec2<u32>) -> Surface {
    let fx = f32(gid.x) / 1920.0;
    let fy = f32(gid.y) / 1080.0;
    let n = normalize(vec3<f32>(0.1 * sin(fx * 40.0), 1.0, 0.1 * cos(fy * 40.0)));
    let p = vec3<f32>(fx * 2.0, 0.0, fy * 2.0);
    let v = normalize(vec3<f32>(0.0, 10.0, 20.0) - p);
    let a2 = 0.0625;
    let nv = clamp(dot(n, v), MIN_COS, 1.0);
    return Surface(n, v, nv, dot(n, v), a2, sqrt(nv * nv * (1.0 - a2) + a2));
}
"#;

// The shade of every light, through the walk every f32 kernel shares.
const F32_MAIN: &str = "MAIN_WITH(shade32)";

// What both f16 kernels share: the BRDF of two lights a step in vec2<f16>,
// from their N.L and V.L and a scale kept within f16's range (at most 1),
// the weights then scaled by `after` in f32 and added to the f32 sums.
const F16_BRDF: &str = r#"
struct Surface16 { nv: f16, vc: f16, a2: f16, lambda_v: f16 }
struct Pair { spec: vec2<f32>, graz: vec2<f32>, diff: vec2<f32> }

fn surface16(s: Surface) -> Surface16 {
    return Surface16(f16(s.n_dot_v), f16(s.view_cosine), f16(s.a2), f16(s.lambda_v));
}

fn weights16(n_dot_l: vec2<f16>, v_dot_l: vec2<f16>, scale: vec2<f16>, s: Surface16, after: vec2<f32>) -> Pair {
    let length2 = vec2<f16>(2.0) + vec2<f16>(2.0) * v_dot_l;
    let il = inverseSqrt(max(length2, vec2<f16>(6e-5)));
    let nh = clamp((vec2<f16>(s.vc) + n_dot_l) * il, vec2<f16>(0.0), vec2<f16>(1.0));
    let vh = (vec2<f16>(1.0) + v_dot_l) * il;
    let nl = clamp(n_dot_l, vec2<f16>(0.0), vec2<f16>(1.0));
    let x = vec2<f16>(1.0) - clamp(vh, vec2<f16>(0.0), vec2<f16>(1.0));
    let x2 = x * x;
    let w = x2 * x2 * x;
    let c = max(nl, vec2<f16>(0.001));
    let a2 = vec2<f16>(s.a2);
    let lambda_l = sqrt(c * c * (vec2<f16>(1.0) - a2) + a2);
    let vden = vec2<f16>(2.0) * (c * vec2<f16>(s.lambda_v) + vec2<f16>(s.nv) * lambda_l);
    let f = (vec2<f16>(1.0) - nh) * (vec2<f16>(1.0) + nh) + nh * nh * a2;
    let root = inverseSqrt(vec2<f16>(3.14159265h) * f * f * vden);
    let scaled = nl * scale;
    let spec = a2 * root * root * scaled;
    return Pair(vec2<f32>(spec) * after, vec2<f32>(spec * w) * after, vec2<f32>(scaled - scaled * w) * after);
}

fn add_pair(w: Pair, ra: vec3<f32>, rb: vec3<f32>, sums: ptr<function, Sums>) {
    (*sums).s += ra * w.spec.x + rb * w.spec.y;
    (*sums).g += ra * w.graz.x + rb * w.graz.y;
    (*sums).d += ra * w.diff.x + rb * w.diff.y;
}
"#;

// The geometry in f32 per light; the BRDF of two lights in vec2<f16>; the
// weights back to f32, scaled by the attenuation there, summed in f32.
const F16_MAIN: &str = r#"
fn geometry(lv: vec4<f32>, p: vec3<f32>, s: Surface) -> vec4<f32> {
    // (N.L, V.L, attenuation, live)
    let to_light = lv.xyz - p;
    let d2 = dot(to_light, to_light);
    let ratio2 = d2 * lv.w;
    let facing = dot(s.n, to_light);
    let live = ratio2 < 1.0 && (facing > 0.0 || d2 <= 1e-20);
    let inv_d = inverseSqrt(max(d2, 1e-20));
    let window = clamp(1.0 - ratio2 * ratio2, 0.0, 1.0);
    let attenuation = select(0.0, window * window * min(inv_d * inv_d, 1e4), live);
    var n_dot_l = facing * inv_d;
    var v_dot_l = dot(s.v, to_light) * inv_d;
    if (!(d2 > 1e-20)) { n_dot_l = 1.0; v_dot_l = s.view_cosine; }
    return vec4<f32>(n_dot_l, v_dot_l, attenuation, select(0.0, 1.0, live));
}

fn shade16(ga: vec4<f32>, gb: vec4<f32>, ra: vec3<f32>, rb: vec3<f32>, s16: Surface16, sums: ptr<function, Sums>) {
    if (ga.w == 0.0 && gb.w == 0.0) { return; }
    let n_dot_l = vec2<f16>(vec2<f32>(ga.x, gb.x));
    let v_dot_l = vec2<f16>(vec2<f32>(ga.y, gb.y));
    add_pair(weights16(n_dot_l, v_dot_l, vec2<f16>(1.0), s16, vec2<f32>(ga.z, gb.z)), ra, rb, sums);
}

@compute @workgroup_size(16, 16)
fn main(@builtin(global_invocation_id) gid: vec3<u32>, @builtin(local_invocation_index) lane: u32) {
    let s = surface_at(gid.xy);
    let p = vec3<f32>(f32(gid.x) / 1920.0 * 2.0, 0.0, f32(gid.y) / 1080.0 * 2.0);
    let s16 = surface16(s);
    var sums = Sums(vec3<f32>(0.0), vec3<f32>(0.0), vec3<f32>(0.0));
    for (var b = 0u; b < 4u; b++) {
        wl[lane] = lights[b * 256u + lane];
        wr[lane] = radiance[b * 256u + lane];
        workgroupBarrier();
        for (var i = 0u; i < 256u; i += 2u) {
            let ga = geometry(wl[i], p, s);
            let gb = geometry(wl[i + 1u], p, s);
            shade16(ga, gb, wr[i].xyz, wr[i + 1u].xyz, s16, &sums);
        }
        workgroupBarrier();
    }
    out[gid.y * 1920u + gid.x] = vec4<f32>(sums.s + sums.g + sums.d, 1.0);
}
"#;

// Everything per pair in vec2<f16>, positions relative to the workgroup's
// corner (the ceiling of what f16 could give), sums in f32.
const F16_ALL_MAIN: &str = r#"
var<workgroup> wh: array<vec4<f16>, 256>;
fn shade_all(la: vec4<f16>, lb: vec4<f16>, ra: vec3<f32>, rb: vec3<f32>, p: vec3<f16>, n: vec3<f16>, v: vec3<f16>, s16: Surface16, sums: ptr<function, Sums>) {
    let dx = vec2<f16>(la.x, lb.x) - vec2<f16>(p.x);
    let dy = vec2<f16>(la.y, lb.y) - vec2<f16>(p.y);
    let dz = vec2<f16>(la.z, lb.z) - vec2<f16>(p.z);
    let d2 = dx * dx + dy * dy + dz * dz;
    let ratio2 = d2 * vec2<f16>(la.w, lb.w);
    let facing = dx * n.x + dy * n.y + dz * n.z;
    if (!(any(ratio2 < vec2<f16>(1.0)) && any(facing > vec2<f16>(0.0)))) { return; }
    let live = (ratio2 < vec2<f16>(1.0)) & (facing > vec2<f16>(0.0));
    let inv_d = inverseSqrt(max(d2, vec2<f16>(1e-4)));
    let window = clamp(vec2<f16>(1.0) - ratio2 * ratio2, vec2<f16>(0.0), vec2<f16>(1.0));
    let n_dot_l = facing * inv_d;
    let v_dot_l = (dx * v.x + dy * v.y + dz * v.z) * inv_d;
    // The window in f16 (at most 1), the inverse square after, in f32.
    let att = select(vec2<f16>(0.0), window * window, live);
    add_pair(weights16(n_dot_l, v_dot_l, att, s16, vec2<f32>(inv_d * inv_d)), ra, rb, sums);
}

@compute @workgroup_size(16, 16)
fn main(@builtin(global_invocation_id) gid: vec3<u32>, @builtin(local_invocation_index) lane: u32, @builtin(workgroup_id) wid: vec3<u32>) {
    let s = surface_at(gid.xy);
    let corner = vec3<f32>(f32(wid.x * 16u) / 1920.0 * 2.0, 0.0, f32(wid.y * 16u) / 1080.0 * 2.0);
    let p = vec3<f32>(f32(gid.x) / 1920.0 * 2.0, 0.0, f32(gid.y) / 1080.0 * 2.0);
    let ph = vec3<f16>(p - corner);
    let nh = vec3<f16>(s.n);
    let vh = vec3<f16>(s.v);
    let s16 = surface16(s);
    var sums = Sums(vec3<f32>(0.0), vec3<f32>(0.0), vec3<f32>(0.0));
    for (var b = 0u; b < 4u; b++) {
        let l = lights[b * 256u + lane];
        wh[lane] = vec4<f16>(vec3<f16>(l.xyz - corner), f16(l.w));
        wr[lane] = radiance[b * 256u + lane];
        workgroupBarrier();
        for (var i = 0u; i < 256u; i += 2u) {
            shade_all(wh[i], wh[i + 1u], wr[i].xyz, wr[i + 1u].xyz, ph, nh, vh, s16, &sums);
        }
        workgroupBarrier();
    }
    out[gid.y * 1920u + gid.x] = vec4<f32>(sums.s + sums.g + sums.d, 1.0);
}
"#;

// Lower bounds: the loop, the range and facing tests, the attenuation and
// the nine sums, without the BRDF (weights made of N.L and the attenuation).
const NO_BRDF_MAIN: &str = r#"
fn shade_geo(lv: vec4<f32>, rad: vec3<f32>, p: vec3<f32>, s: Surface, sums: ptr<function, Sums>) {
    let to_light = lv.xyz - p;
    let d2 = dot(to_light, to_light);
    let ratio2 = d2 * lv.w;
    if (!(ratio2 < 1.0)) { return; }
    let facing = dot(s.n, to_light);
    if (!(facing > 0.0) && d2 > 1e-20) { return; }
    let inv_d = inverseSqrt(max(d2, 1e-20));
    let window = clamp(1.0 - ratio2 * ratio2, 0.0, 1.0);
    let attenuation = window * window * min(inv_d * inv_d, 1e4);
    let scaled = min(facing * inv_d, 1.0) * attenuation;
    (*sums).s += rad * scaled;
    (*sums).g += rad * (scaled * 0.5);
    (*sums).d += rad * (scaled * 0.25);
}
MAIN_WITH(shade_geo)
"#;

// The loop and the range test alone, one sum.
const RANGE_MAIN: &str = r#"
fn shade_range(lv: vec4<f32>, rad: vec3<f32>, p: vec3<f32>, s: Surface, sums: ptr<function, Sums>) {
    let to_light = lv.xyz - p;
    let d2 = dot(to_light, to_light);
    let ratio2 = d2 * lv.w;
    if (!(ratio2 < 1.0)) { return; }
    (*sums).d += rad * (1.0 - ratio2);
}
MAIN_WITH(shade_range)
"#;

// How many lights pass the range and facing tests at each pixel (untimed).
const COUNT_MAIN: &str = r#"
fn shade_count(lv: vec4<f32>, rad: vec3<f32>, p: vec3<f32>, s: Surface, sums: ptr<function, Sums>) {
    let to_light = lv.xyz - p;
    let d2 = dot(to_light, to_light);
    if (!(d2 * lv.w < 1.0)) { return; }
    if (!(dot(s.n, to_light) > 0.0)) { return; }
    (*sums).d.x += 1.0;
}
MAIN_WITH(shade_count)
"#;

// The loop and the range test alone, without reading the radiance: whether
// workgroup-memory reads, not arithmetic, bound the walk.
const RANGE_NO_READ_MAIN: &str = r#"
fn shade_range_no_read(lv: vec4<f32>, rad: vec3<f32>, p: vec3<f32>, s: Surface, sums: ptr<function, Sums>) {
    let to_light = lv.xyz - p;
    let d2 = dot(to_light, to_light);
    let ratio2 = d2 * lv.w;
    if (!(ratio2 < 1.0)) { return; }
    (*sums).d += vec3<f32>(1.0 - ratio2);
}
MAIN_WITH(shade_range_no_read)
"#;

// `f32`, with the radiance kept as four halves (8 bytes, not 16) in
// workgroup memory: what halving the second read gives.
const F32_PACKED_MAIN: &str = r#"
var<workgroup> wp: array<vec2<u32>, 256>;
@compute @workgroup_size(16, 16)
fn main(@builtin(global_invocation_id) gid: vec3<u32>, @builtin(local_invocation_index) lane: u32) {
    let s = surface_at(gid.xy);
    let p = vec3<f32>(f32(gid.x) / 1920.0 * 2.0, 0.0, f32(gid.y) / 1080.0 * 2.0);
    var sums = Sums(vec3<f32>(0.0), vec3<f32>(0.0), vec3<f32>(0.0));
    for (var b = 0u; b < 4u; b++) {
        wl[lane] = lights[b * 256u + lane];
        let r = radiance[b * 256u + lane];
        wp[lane] = vec2<u32>(pack2x16float(r.xy), pack2x16float(r.zw));
        workgroupBarrier();
        for (var i = 0u; i < 256u; i += 2u) {
            let a = wl[i];
            let c = wl[i + 1u];
            let ra = wp[i];
            let rc = wp[i + 1u];
            shade32(a, vec3<f32>(unpack2x16float(ra.x), unpack2x16float(ra.y).x), p, s, &sums);
            shade32(c, vec3<f32>(unpack2x16float(rc.x), unpack2x16float(rc.y).x), p, s, &sums);
        }
        workgroupBarrier();
    }
    out[gid.y * 1920u + gid.x] = vec4<f32>(sums.s + sums.g + sums.d, 1.0);
}
"#;

const MAIN_TEMPLATE: &str = r#"
@compute @workgroup_size(16, 16)
fn main(@builtin(global_invocation_id) gid: vec3<u32>, @builtin(local_invocation_index) lane: u32) {
    let s = surface_at(gid.xy);
    let p = vec3<f32>(f32(gid.x) / 1920.0 * 2.0, 0.0, f32(gid.y) / 1080.0 * 2.0);
    var sums = Sums(vec3<f32>(0.0), vec3<f32>(0.0), vec3<f32>(0.0));
    for (var b = 0u; b < 4u; b++) {
        wl[lane] = lights[b * 256u + lane];
        wr[lane] = radiance[b * 256u + lane];
        workgroupBarrier();
        for (var i = 0u; i < 256u; i += 2u) {
            let a = wl[i];
            let c = wl[i + 1u];
            SHADE(a, wr[i].xyz, p, s, &sums);
            SHADE(c, wr[i + 1u].xyz, p, s, &sums);
        }
        workgroupBarrier();
    }
    out[gid.y * 1920u + gid.x] = vec4<f32>(sums.s + sums.g + sums.d, sums.d.x);
}
"#;

fn with_main(body: &str, shade: &str) -> String {
    let main = MAIN_TEMPLATE.replace("SHADE", shade);
    format!(
        "{COMMON}{}",
        body.replace(&format!("MAIN_WITH({shade})"), &main)
    )
}

fn main() {
    let small = std::env::var_os("LIGHT_LOOP_SMALL").is_some();
    let (width, height, reps, runs) = if small {
        (160u32, 96u32, 1u32, 1usize)
    } else {
        (1920, 1080, 20, 5)
    };
    let lights_per_pixel = 1024u32;
    let instance =
        wgpu::Instance::new(wgpu::InstanceDescriptor::new_without_display_handle_from_env());
    let adapter = pollster::block_on(instance.request_adapter(&wgpu::RequestAdapterOptions {
        power_preference: wgpu::PowerPreference::HighPerformance,
        ..Default::default()
    }))
    .expect("no adapter");
    let adapter_name = adapter.get_info().name;
    let f16 = adapter.features().contains(wgpu::Features::SHADER_F16);
    let (device, queue) = pollster::block_on(adapter.request_device(&wgpu::DeviceDescriptor {
        required_features: if f16 {
            wgpu::Features::SHADER_F16
        } else {
            wgpu::Features::empty()
        },
        ..Default::default()
    }))
    .expect("no device");

    // The lights: positions over 4 x 4 units around the pixels' 2 x 2, 0.5..3
    // above them, range 5 (w: 1 / range^2); radiance in 0..40 a channel.
    let mut seed = 1u32;
    let mut random = || {
        seed = seed.wrapping_mul(1_664_525).wrapping_add(1_013_904_223);
        (seed >> 8) as f32 / (1u32 << 24) as f32
    };
    let mut lights = Vec::new();
    let mut radiance = Vec::new();
    for _ in 0..lights_per_pixel {
        lights.extend_from_slice(&[
            random() * 4.0 - 1.0,
            0.5 + random() * 2.5,
            random() * 4.0 - 1.0,
            1.0 / 25.0,
        ]);
        radiance.extend_from_slice(&[random() * 40.0, random() * 40.0, random() * 40.0, 0.0]);
    }
    use wgpu::util::DeviceExt;
    let storage = |data: &[f32]| {
        device.create_buffer_init(&wgpu::util::BufferInitDescriptor {
            label: None,
            contents: bytemuck::cast_slice(data),
            usage: wgpu::BufferUsages::STORAGE,
        })
    };
    let light_buffer = storage(&lights);
    let radiance_buffer = storage(&radiance);
    let out_size = u64::from(width * height * 16);
    let buffer = |usage| {
        device.create_buffer(&wgpu::BufferDescriptor {
            label: None,
            size: out_size,
            usage,
            mapped_at_creation: false,
        })
    };
    let out = buffer(wgpu::BufferUsages::STORAGE | wgpu::BufferUsages::COPY_SRC);
    let readback = buffer(wgpu::BufferUsages::MAP_READ | wgpu::BufferUsages::COPY_DST);

    let mut kernels = vec![
        ("count", with_main(COUNT_MAIN, "shade_count")),
        ("f32", with_main(F32_MAIN, "shade32")),
        ("f32 no brdf", with_main(NO_BRDF_MAIN, "shade_geo")),
        ("f32 range only", with_main(RANGE_MAIN, "shade_range")),
        (
            "f32 range only, no radiance read",
            with_main(RANGE_NO_READ_MAIN, "shade_range_no_read"),
        ),
        (
            "f32 radiance in halves",
            format!("{COMMON}{F32_PACKED_MAIN}"),
        ),
    ];
    if f16 {
        kernels.push((
            "f16 brdf",
            format!("enable f16;\n{COMMON}{F16_BRDF}{F16_MAIN}"),
        ));
        kernels.push((
            "f16 all",
            format!("enable f16;\n{COMMON}{F16_BRDF}{F16_ALL_MAIN}"),
        ));
    }
    let pixels = f64::from(width * height);
    let mut reference: Option<Vec<f32>> = None;
    let mut live_per_pixel = f64::from(lights_per_pixel);
    for (name, source) in kernels {
        let source = source.replace("1920u + gid.x", &format!("{width}u + gid.x"));
        let module = device.create_shader_module(wgpu::ShaderModuleDescriptor {
            label: Some(name),
            source: wgpu::ShaderSource::Wgsl(source.into()),
        });
        let pipeline = device.create_compute_pipeline(&wgpu::ComputePipelineDescriptor {
            label: Some(name),
            layout: None,
            module: &module,
            entry_point: Some("main"),
            compilation_options: Default::default(),
            cache: None,
        });
        let bind = device.create_bind_group(&wgpu::BindGroupDescriptor {
            label: None,
            layout: &pipeline.get_bind_group_layout(0),
            entries: &[
                wgpu::BindGroupEntry {
                    binding: 0,
                    resource: light_buffer.as_entire_binding(),
                },
                wgpu::BindGroupEntry {
                    binding: 1,
                    resource: radiance_buffer.as_entire_binding(),
                },
                wgpu::BindGroupEntry {
                    binding: 2,
                    resource: out.as_entire_binding(),
                },
            ],
        });
        // `count` dispatches back to back in one pass and one submission, so
        // the GPU keeps its clock; the wall time over them is the kernel's.
        let run = |count: u32| {
            let mut encoder = device.create_command_encoder(&Default::default());
            {
                let mut pass = encoder.begin_compute_pass(&Default::default());
                pass.set_pipeline(&pipeline);
                pass.set_bind_group(0, &bind, &[]);
                for _ in 0..count {
                    pass.dispatch_workgroups(width / 16, height.div_ceil(16), 1);
                }
            }
            queue.submit([encoder.finish()]);
            device
                .poll(wgpu::PollType::wait_indefinitely())
                .expect("poll");
        };
        run(reps.min(3));
        let mut times: Vec<f64> = (0..runs)
            .map(|_| {
                let started = Instant::now();
                run(reps);
                started.elapsed().as_secs_f64() * 1000.0 / f64::from(reps)
            })
            .collect();
        times.sort_by(f64::total_cmp);
        let ms = times[times.len() / 2];

        let mut encoder = device.create_command_encoder(&Default::default());
        encoder.copy_buffer_to_buffer(&out, 0, &readback, 0, out_size);
        queue.submit([encoder.finish()]);
        readback.slice(..).map_async(wgpu::MapMode::Read, |_| {});
        device
            .poll(wgpu::PollType::wait_indefinitely())
            .expect("poll");
        let values: Vec<f32> =
            bytemuck::cast_slice(&readback.slice(..).get_mapped_range().expect("mapped")).to_vec();
        readback.unmap();
        if name == "count" {
            // w: how many lights passed the range and facing tests.
            live_per_pixel = values
                .iter()
                .skip(3)
                .step_by(4)
                .map(|&c| f64::from(c))
                .sum::<f64>()
                / pixels;
            println!(
                "{{\"adapter\":{adapter_name:?},\"kernel\":\"count\",\"live_lights_per_pixel\":{live_per_pixel:.1}}}"
            );
            continue;
        }
        // The error only where the kernel computes the same sums (f16); the
        // lower bounds compute others.
        let error = match &reference {
            None => {
                reference = Some(values);
                String::from("0")
            }
            Some(_) if !(name.starts_with("f16") || name.contains("halves")) => {
                String::from("null")
            }
            Some(exact) => {
                let (mut sum, mut worst) = (0.0f64, 0.0f64);
                for (a, b) in exact.iter().zip(&values).step_by(4) {
                    let error = f64::from((a - b).abs() / a.abs().max(1e-6));
                    worst = worst.max(error);
                    sum += error;
                }
                format!("{{\"mean\":{:.2e},\"worst\":{worst:.2e}}}", sum / pixels)
            }
        };
        let ps = ms * 1e9 / (pixels * live_per_pixel);
        println!(
            "{{\"adapter\":{adapter_name:?},\"kernel\":{name:?},\"size\":\"{width}x{height}\",\"ms\":{ms:.3},\"ps_per_evaluation\":{ps:.3},\"relative_error\":{error}}}"
        );
    }
}
