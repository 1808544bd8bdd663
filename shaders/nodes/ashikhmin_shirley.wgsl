// Ashikhmin-Shirley's anisotropic Phong BRDF (M. Ashikhmin, P. Shirley,
// "An Anisotropic Phong BRDF Model", 2000) as a light shader node: the
// CookTorrance light loop calls `light` for every point, spot or sun light
// reaching a pixel (through its clusters and shadow maps) and sums what it
// returns into Diffuse and Specular. Emeshe promised it beside its toon
// shading. The CPU reference is crates/render/src/reference/ashikhmin_shirley.rs;
// a test compares the two over several lights, with and without shadows.
// @category Lighting
// @light point spot sun
// @help Ashikhmin-Shirley anisotropic Phong shading in place of CookTorrance: a specular lobe of Phong exponents Exponent U along the surface's tangent and Exponent V along its bitangent (equal: round highlights; unequal: brushed-metal streaks), Fresnel-weighted from Specular (the reflectance head on, 0..1), over a diffuse term that loses what the specular takes. The tangent frame is built from the normal alone (Frisvad 2012), so on a floor U runs along +X and V along -Z. Wire G-Buffer, Lights (and their Shadows) as for CookTorrance, Diffuse and Specular into CompositeLight.
#import spreadlight::light_shader::{LightInput, LightOutput, LIGHT_PI, light_incident, light_output_none}
#import spreadlight::packing::safe_normalize

struct Params {
    // @pin "Exponent U" default=200 min=1 max=10000
    exponent_u: f32,
    // @pin "Exponent V" default=20 min=1 max=10000
    exponent_v: f32,
    // @pin "Specular" default=0.05 min=0 max=1
    specular: f32,
    _pad: f32,
}

@group(2) @binding(0) var<uniform> params: Params;

fn pow5(x: f32) -> f32 {
    let x2 = x * x;
    return x2 * x2 * x;
}

// A unit tangent perpendicular to `n`, the surface's U direction (the first
// vector of Frisvad's orthonormal basis, "Building an Orthonormal Basis from
// a 3D Unit Vector Without Normalization", 2012): continuous over every
// normal but the one facing -Z, where it turns fast (held at -Y there). Its
// bitangent is cross(n, t).
fn tangent_of(n: vec3<f32>) -> vec3<f32> {
    if (n.z < -0.9999999) {
        return vec3<f32>(0.0, -1.0, 0.0);
    }
    let a = 1.0 / (1.0 + n.z);
    return vec3<f32>(1.0 - n.x * n.x * a, -n.x * n.y * a, -n.x);
}

fn light(in: LightInput) -> LightOutput {
    let n_dot_l = in.n_dot_l;
    let n_dot_v = dot(in.normal, in.view);
    // Light from behind, or a surface seen from behind: nothing (and no
    // pow of a negative base below).
    if (n_dot_l <= 0.0 || n_dot_v <= 0.0) {
        return light_output_none();
    }
    let irradiance = light_incident(in) * n_dot_l;
    let rs = params.specular;
    // The diffuse lobe: 28 / 23pi x Rd x (1 - Rs), fading at grazing angles
    // as the specular takes the light (the paper's eq. 5).
    let diffuse = in.albedo * (28.0 / (23.0 * LIGHT_PI)) * (1.0 - rs)
        * (1.0 - pow5(1.0 - 0.5 * n_dot_l)) * (1.0 - pow5(1.0 - 0.5 * n_dot_v));
    // The specular lobe (eq. 4): the Phong exponent interpolated between
    // nu and nv by where the half vector leans. (h.u)^2 + (h.v)^2 is
    // 1 - (n.h)^2 written so that it is exact near the normal, where both
    // are 0 and the power is 1 whatever the exponent.
    let h = safe_normalize(in.direction + in.view, in.normal);
    let t = tangent_of(in.normal);
    let b = cross(in.normal, t);
    let hu = dot(h, t);
    let hv = dot(h, b);
    let nu = params.exponent_u;
    let nv = params.exponent_v;
    let exponent = (nu * hu * hu + nv * hv * hv) / max(hu * hu + hv * hv, 1e-12);
    let n_dot_h = clamp(dot(in.normal, h), 0.0, 1.0);
    let h_dot_l = max(dot(h, in.direction), 1e-4);
    let fresnel = rs + (1.0 - rs) * pow5(1.0 - h_dot_l);
    let specular = sqrt((nu + 1.0) * (nv + 1.0)) / (8.0 * LIGHT_PI) * pow(n_dot_h, exponent)
        / (h_dot_l * max(n_dot_l, n_dot_v)) * fresnel;
    return LightOutput(diffuse * irradiance, irradiance * specular);
}
