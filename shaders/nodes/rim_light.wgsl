// A custom material feature shaded by a shader node (issue 34, Emeshe's
// "custom features can be added without effort"): materials that have
// feature Feature ID (a FeatureManager id, 16..31; the AddRimLight module of
// patches/modules sets 16) glow at their silhouette. The feature's one vec4
// is the rim's linear colour (rgb) and its falloff power (w). Everything is
// read from the layer's material world through spreadlight::materials
// (shaders/lib/materials.wgsl), by the pixel's material id, so one node
// shades every material of the layer, each as its own parameters say.
// @category Material
// @material
// @help Rim light from a custom material feature: where the pixel's material has feature Feature ID (set by FeatureManager, or the AddRimLight module: rgb colour, w power), emission of colour x (1 - N.V)^power x Strength. Roughness and metallic are the material's CookTorrance parameters. Needs the DeferredBase's Material World.
#import spreadlight::surface::{SurfaceInput, SurfaceOutput, surface_default}
#import spreadlight::materials::{KnowFeature, GetFloats, GetParam, FEATURE_COOK_TORRANCE}

struct Params {
    feature: u32, // @pin "Feature ID" default=16 min=0 max=31
    strength: f32, // @pin "Strength" default=1 min=0 max=100
}

@group(1) @binding(0) var<uniform> params: Params;

fn surface(in: SurfaceInput) -> SurfaceOutput {
    var out = surface_default(in);
    let id = in.material_id;
    // What CookTorrance would have read for this material without a shader
    // node (the surface target replaces it wherever a material writes).
    let ct = GetParam(id, FEATURE_COOK_TORRANCE, 0u, vec4<f32>(0.5, 0.0, 0.04, 0.0));
    out.roughness = ct.x;
    out.metallic = ct.y;
    if (KnowFeature(id, params.feature)) {
        let rim = GetFloats(id, params.feature, 0u);
        let facing = clamp(dot(in.normal, in.view), 0.0, 1.0);
        let power = clamp(rim.w, 0.05, 64.0);
        out.emission += max(rim.rgb, vec3<f32>(0.0)) * pow(1.0 - facing, power) * params.strength;
    }
    return out;
}
