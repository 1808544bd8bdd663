// Procedural fractal value noise, animated: a texture source. RIDGED
// switches to ridged noise (another permutation).
// @category Source
// @help Fractal value noise between two colours: Scale (cells across), Octaves (1..8), Speed (drift per second). Ridged folds it into ridges.
// @switch RIDGED "Ridged"
// @target noise temporary rgba16float scale=1
// @pass generate -> noise

struct Params {
    scale: f32, // @pin default=6 min=0.01 max=512
    octaves: i32, // @pin default=4 min=1 max=8
    speed: f32, // @pin default=0.2
    // @pin "Color A" color default=0,0,0,1
    color_a: vec4<f32>,
    // @pin "Color B" color default=1,1,1,1
    color_b: vec4<f32>,
    size: vec2<f32>,
    time: f32,
}

@group(0) @binding(0) var<uniform> params: Params;
@group(0) @binding(1) var noise: texture_storage_2d<rgba16float, write>;

fn hash(p: vec2<f32>) -> f32 {
    let q = fract(p * vec2<f32>(123.34, 456.21));
    let r = q + dot(q, q + 45.32);
    return fract(r.x * r.y);
}

fn value(p: vec2<f32>) -> f32 {
    let i = floor(p);
    let f = fract(p);
    let u = f * f * (3.0 - 2.0 * f);
    let a = hash(i);
    let b = hash(i + vec2<f32>(1.0, 0.0));
    let c = hash(i + vec2<f32>(0.0, 1.0));
    let d = hash(i + vec2<f32>(1.0, 1.0));
    return mix(mix(a, b, u.x), mix(c, d, u.x), u.y);
}

@compute @workgroup_size(8, 8)
fn generate(@builtin(global_invocation_id) id: vec3<u32>) {
    if (f32(id.x) >= params.size.x || f32(id.y) >= params.size.y) {
        return;
    }
    let aspect = params.size.x / max(params.size.y, 1.0);
    var p = (vec2<f32>(id.xy) + 0.5) / params.size * vec2<f32>(aspect, 1.0) * params.scale;
    p += vec2<f32>(params.time * params.speed, 0.0);
    var sum = 0.0;
    var amplitude = 0.5;
    var total = 0.0;
    for (var o = 0; o < clamp(params.octaves, 1, 8); o++) {
        var v = value(p);
#ifdef RIDGED
        v = 1.0 - abs(2.0 * v - 1.0);
#endif
        sum += amplitude * v;
        total += amplitude;
        amplitude *= 0.5;
        p *= 2.0;
    }
    let n = sum / total;
    textureStore(noise, id.xy, mix(params.color_a, params.color_b, n));
}
