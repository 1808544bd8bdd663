// FXAA (after Lottes' FXAA 3.11, "quality" variant): per pixel, the local
// luma contrast decides whether it sits on an edge; if so, the edge's
// direction is found from the 3x3 neighbourhood, the edge is followed both
// ways (up to `steps` samples) to its ends, and the pixel is re-sampled,
// bilinearly, across the edge by how near it is to an end, blended with a
// sub-pixel term for features smaller than a pixel. Luma is computed from
// the input's rgb, so it works on HDR and on tonemapped images; very bright
// HDR pixels are compressed (x / (1 + x)) for the edge test only.

struct Params {
    // x: search steps, y: edge threshold (relative), z: minimum threshold, w: sub-pixel strength
    settings: vec4<f32>,
}

@group(0) @binding(0) var<uniform> params: Params;
@group(0) @binding(1) var source: texture_2d<f32>;
@group(0) @binding(3) var output: texture_storage_2d<rgba16float, write>;

// Bilinear by hand (four loads, edges clamped), so any float input works,
// filterable or not (RGBA32F images are not).
fn sample(uv: vec2<f32>) -> vec4<f32> {
    let size = vec2<i32>(textureDimensions(source));
    let p = uv * vec2<f32>(size) - 0.5;
    let base = floor(p);
    let f = p - base;
    let t = vec2<i32>(base);
    let hi = size - 1;
    let a = textureLoad(source, clamp(t, vec2<i32>(0), hi), 0);
    let b = textureLoad(source, clamp(t + vec2<i32>(1, 0), vec2<i32>(0), hi), 0);
    let c = textureLoad(source, clamp(t + vec2<i32>(0, 1), vec2<i32>(0), hi), 0);
    let d = textureLoad(source, clamp(t + vec2<i32>(1, 1), vec2<i32>(0), hi), 0);
    return mix(mix(a, b, f.x), mix(c, d, f.x), f.y);
}

// Within what a half float holds (the output is RGBA16F): 1e6 in, no infinity out.
fn clamp_half(c: vec3<f32>) -> vec3<f32> {
    return min(max(c, vec3<f32>(0.0)), vec3<f32>(65000.0));
}

fn luma(c: vec3<f32>) -> f32 {
    let l = dot(max(c, vec3<f32>(0.0)), vec3<f32>(0.299, 0.587, 0.114));
    // Compressed, so a 1e6 pixel does not make every neighbour an edge.
    return l / (1.0 + l);
}

fn luma_at(uv: vec2<f32>) -> f32 {
    return luma(sample(uv).rgb);
}

// The luma of the texel `offset` from `p` (edges clamped): the 3x3
// neighbourhood lies on texel centres, where the bilinear `sample` is the
// texel itself, so one load does instead of four.
fn luma_near(p: vec2<i32>, offset: vec2<i32>) -> f32 {
    let hi = vec2<i32>(textureDimensions(source)) - 1;
    return luma(textureLoad(source, clamp(p + offset, vec2<i32>(0), hi), 0).rgb);
}

@compute @workgroup_size(8, 8)
fn main(@builtin(global_invocation_id) id: vec3<u32>) {
    let size = textureDimensions(source);
    if (id.x >= size.x || id.y >= size.y) {
        return;
    }
    let texel = 1.0 / vec2<f32>(size);
    let uv = (vec2<f32>(id.xy) + 0.5) * texel;
    let center = textureLoad(source, vec2<i32>(id.xy), 0);
    let m = luma(center.rgb);
    let at = vec2<i32>(id.xy);
    let n = luma_near(at, vec2<i32>(0, -1));
    let s = luma_near(at, vec2<i32>(0, 1));
    let e = luma_near(at, vec2<i32>(1, 0));
    let w = luma_near(at, vec2<i32>(-1, 0));
    let highest = max(max(max(n, s), max(e, w)), m);
    let lowest = min(min(min(n, s), min(e, w)), m);
    let contrast = highest - lowest;
    if (contrast < max(params.settings.z, highest * params.settings.y)) {
        textureStore(output, id.xy, vec4<f32>(clamp_half(center.rgb), center.a));
        return;
    }
    let nw = luma_near(at, vec2<i32>(-1, -1));
    let ne = luma_near(at, vec2<i32>(1, -1));
    let sw = luma_near(at, vec2<i32>(-1, 1));
    let se = luma_near(at, vec2<i32>(1, 1));

    // Sub-pixel blend: how far the centre is from its neighbourhood's average.
    let average = (2.0 * (n + s + e + w) + nw + ne + sw + se) / 12.0;
    let sub = clamp(abs(average - m) / contrast, 0.0, 1.0);
    let sub_blend = smoothstep(0.0, 1.0, sub);
    let sub_amount = sub_blend * sub_blend * params.settings.w;

    // The edge runs horizontally when the vertical gradient dominates.
    let horizontal_edge = abs(nw + ne - 2.0 * n) + 2.0 * abs(w + e - 2.0 * m) + abs(sw + se - 2.0 * s);
    let vertical_edge = abs(nw + sw - 2.0 * w) + 2.0 * abs(n + s - 2.0 * m) + abs(ne + se - 2.0 * e);
    let horizontal = horizontal_edge >= vertical_edge;
    // Across the edge: towards the neighbour with the larger gradient.
    let positive = select(e, s, horizontal);
    let negative = select(w, n, horizontal);
    let gradient_p = abs(positive - m);
    let gradient_n = abs(negative - m);
    var across = select(texel.x, texel.y, horizontal);
    var edge_luma = 0.5 * (m + positive);
    var gradient = gradient_p;
    if (gradient_n > gradient_p) {
        across = -across;
        edge_luma = 0.5 * (m + negative);
        gradient = gradient_n;
    }
    let along = select(vec2<f32>(0.0, texel.y), vec2<f32>(texel.x, 0.0), horizontal);
    var edge_uv = uv;
    if (horizontal) {
        edge_uv.y += across * 0.5;
    } else {
        edge_uv.x += across * 0.5;
    }
    // Walk both ways to where the edge ends (its luma departs from the edge's).
    let threshold = gradient * 0.25;
    let steps = u32(params.settings.x);
    var p = edge_uv + along;
    var q = edge_uv - along;
    var end_p = false;
    var end_q = false;
    var delta_p = 0.0;
    var delta_q = 0.0;
    for (var i = 0u; i < steps; i++) {
        if (!end_p) {
            delta_p = luma_at(p) - edge_luma;
            end_p = abs(delta_p) >= threshold;
            if (!end_p) {
                p += along * f32(1u + i / 4u);
            }
        }
        if (!end_q) {
            delta_q = luma_at(q) - edge_luma;
            end_q = abs(delta_q) >= threshold;
            if (!end_q) {
                q -= along * f32(1u + i / 4u);
            }
        }
        if (end_p && end_q) {
            break;
        }
    }
    let dist_p = select(p.y - uv.y, p.x - uv.x, horizontal);
    let dist_q = select(uv.y - q.y, uv.x - q.x, horizontal);
    let nearest = min(dist_p, dist_q);
    let length = max(dist_p + dist_q, 1e-6);
    // Only blend towards the end whose far side differs from the centre the other way.
    let centre_below = (m - edge_luma) < 0.0;
    let good = select((delta_q < 0.0) != centre_below, (delta_p < 0.0) != centre_below, dist_p < dist_q);
    let edge_amount = select(0.0, 0.5 - nearest / length, good);
    let amount = max(edge_amount, sub_amount);
    var final_uv = uv;
    if (horizontal) {
        final_uv.y += amount * across;
    } else {
        final_uv.x += amount * across;
    }
    let color = sample(final_uv);
    textureStore(output, id.xy, vec4<f32>(clamp_half(color.rgb), center.a));
}
