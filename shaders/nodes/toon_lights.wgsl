// Cel shading as a light shader node: the CookTorrance light loop calls
// `light` for every point, spot or sun light reaching a pixel (through its
// clusters and shadow maps) and sums what it returns into Diffuse and
// Specular. The CPU reference is crates/render/src/reference/toon.rs; a
// test compares the two over several lights, with and without shadows.
// @category Lighting
// @light point spot sun
// @help Toon (cel) shading in place of CookTorrance: the diffuse term in Bands flat steps of N.L times the shadow, and a hard-edged highlight where N.H is above 1 - Highlight Size, scaled by Specular. Wire G-Buffer, Lights (and their Shadows) as for CookTorrance, Diffuse and Specular into CompositeLight.
#import spreadlight::light_shader::{LightInput, LightOutput, LIGHT_PI}
#import spreadlight::packing::safe_normalize

struct Params {
    // @pin "Bands" default=3 min=1 max=16
    bands: f32,
    // @pin "Highlight Size" default=0.04 min=0 max=1
    highlight_size: f32,
    // @pin "Specular" default=0.5 min=0 max=10
    specular: f32,
    _pad: f32,
}

@group(2) @binding(0) var<uniform> params: Params;

fn light(in: LightInput) -> LightOutput {
    // How lit the surface is, 0..1, quantised up: any light at all is the
    // first band, full light the last.
    let lit = clamp(in.n_dot_l, 0.0, 1.0) * in.shadow;
    let bands = max(round(params.bands), 1.0);
    let band = ceil(lit * bands) / bands;
    let incident = in.radiance * in.attenuation;
    let diffuse = in.albedo * incident * (band / LIGHT_PI);
    // A flat highlight: on where the half vector is within the size of the normal.
    let h = safe_normalize(in.direction + in.view, in.normal);
    let on = dot(in.normal, h) > 1.0 - params.highlight_size && lit > 0.0;
    let specular = select(vec3<f32>(0.0), incident * (params.specular * in.shadow / LIGHT_PI), on);
    return LightOutput(diffuse, specular);
}
