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
