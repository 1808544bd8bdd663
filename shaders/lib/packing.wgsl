// Packing helpers shared by the G-buffer passes and their readers.
#define_import_path spreadlight::packing

// IDs are stored in half-float channels (the alpha of MRE targets): every
// integer up to 2048 is exact there, which is the contract for material and
// object IDs.
fn id_to_channel(id: u32) -> f32 {
    return f32(min(id, 2048u));
}

fn channel_to_id(v: f32) -> u32 {
    return u32(max(round(v), 0.0));
}

// normalize() of a zero vector is NaN; a G-buffer must never hold one.
fn safe_normalize(v: vec3<f32>, fallback: vec3<f32>) -> vec3<f32> {
    let len2 = dot(v, v);
    if (len2 > 1e-20) {
        return v * inverseSqrt(len2);
    }
    return fallback;
}

// Non-negative HDR colour in one u32, shared-exponent 9-9-9-5 (the
// RGB9E5 layout): 9-bit mantissas, exponent bias 15. Up to 65408.
fn pack_rgb9e5(rgb: vec3<f32>) -> u32 {
    let c = clamp(rgb, vec3<f32>(0.0), vec3<f32>(65408.0));
    let top = max(c.r, max(c.g, c.b));
    var exponent = i32(max(-16.0, floor(log2(max(top, 1e-30))))) + 16;
    var unit = exp2(f32(exponent - 24));
    if (floor(top / unit + 0.5) >= 512.0) {
        exponent += 1;
        unit *= 2.0;
    }
    let m = vec3<u32>(min(floor(c / unit + 0.5), vec3<f32>(511.0)));
    return m.r | (m.g << 9u) | (m.b << 18u) | (u32(exponent) << 27u);
}

fn unpack_rgb9e5(bits: u32) -> vec3<f32> {
    let unit = exp2(f32(i32(bits >> 27u) - 24));
    return vec3<f32>(f32(bits & 511u), f32((bits >> 9u) & 511u), f32((bits >> 18u) & 511u)) * unit;
}
