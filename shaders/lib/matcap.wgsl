// Matcap lookup ("material capture", ZBrush's MatCap): a sphere's shading
// painted into an image, looked up by where a pixel's normal points. The CPU
// twin is crates/render/src/reference/matcap.rs (same names); a test runs both.
#define_import_path spreadlight::matcap

// Where on the matcap image a surface looks up, from its view-space unit
// normal `n` and the unit view vector `v` from the eye to the surface (view
// space: +x right, +y up, the eye looking down -z). Image v grows downwards.
// `reflected`: the view vector reflected about the normal, sphere-mapped
// (OpenGL's GL_SPHERE_MAP), instead of the normal itself.
fn matcap_uv(n: vec3<f32>, v: vec3<f32>, reflected: bool) -> vec2<f32> {
    var d = n;
    if (reflected) {
        let r = reflect(v, n);
        // The sphere map's half vector between r and the eye direction (0, 0, 1).
        let m = 2.0 * sqrt(max(r.x * r.x + r.y * r.y + (r.z + 1.0) * (r.z + 1.0), 1e-12));
        d = vec3<f32>(r.x / m * 2.0, r.y / m * 2.0, 0.0);
    }
    let xy = clamp(d.xy, vec2<f32>(-1.0), vec2<f32>(1.0));
    return vec2<f32>(0.5 + 0.5 * xy.x, 0.5 - 0.5 * xy.y);
}

// The built-in matcap when a material names no image: neutral clay, a soft
// key light from the upper left over a dim fill, so shapes read at once.
fn default_matcap(uv: vec2<f32>) -> vec3<f32> {
    let x = uv.x * 2.0 - 1.0;
    let y = 1.0 - uv.y * 2.0;
    let n = vec3<f32>(x, y, sqrt(max(1.0 - x * x - y * y, 0.0)));
    let key = max(dot(n, vec3<f32>(-0.48, 0.64, 0.6)), 0.0);
    return vec3<f32>(0.1 + 0.8 * key);
}
