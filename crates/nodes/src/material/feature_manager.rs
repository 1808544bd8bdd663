//! `FeatureManager`: sets one feature, by id, on each material. Feature id n
//! is flag 1 << n (Emeshe's convention); 0..=5, 7 and 8 are the built-ins
//! (one vec4 each; 6 is a glTF material's maps), 16..=31 custom features with any number of vec4s. Bin Size says
//! how many Parameters slices go to each material, as vvvv's bin sizes do.

use glam::Vec4;
use spreadlight_graph::{NodeDef, Registry};
use spreadlight_render::material::Feature;

use super::{
    CATEGORY, TEXTURE_ID, material_input, material_output, not_finite, refused, set_feature,
    slice_count_with_materials,
};

pub fn register(r: &mut Registry) {
    r.add(
        NodeDef::new(
            "FeatureManager",
            CATEGORY,
            "Sets feature Feature ID on each material (none in: new ones), replacing an earlier setting. \
             Ids: 0 CookTorrance (roughness, metallic, reflectance), 1 Emission (rgb, strength), 2 FakeSSS \
             (rgb, strength), 3 Reflection, 4 MatCap, 5 AmbientOcclusion (strength), 7 Clearcoat (factor, \
             roughness), 8 Unlit (strength), 9 Transmission (factor, ior, thickness; then absorption rgb: \
             Transparency refracts what shows through), 10 Sheen (rgb, roughness: a velvet sheen CookTorrance \
             adds over the base); 16..31 custom. Each \
             material takes Bin Size slices of Parameters (built-ins take 1, Transmission 2; 0 sets a custom \
             flag alone). \
             Values are clamped to their physical ranges. Texture ID: the layer of the MaterialBuffer's \
             texture array that scales the first parameter at each pixel's UV (-1: none; MatCap: the matcap \
             image; Reflection and AmbientOcclusion read none).",
        )
        .with_pins(|p| {
            let material = material_input(p, "Material");
            let feature_id = p.input("Feature ID", 0i64);
            let parameters = p.input("Parameters", Vec4::new(0.5, 0.0, 0.04, 0.0));
            let bin_size = p.input("Bin Size", 1i64);
            let texture = p.input(TEXTURE_ID, -1i64);
            let out = material_output(p, "Material");
            move |cx| {
                let ids = cx.get(feature_id)?.to_vec();
                let layers = cx.get(texture)?.to_vec();
                let params = cx.get(parameters)?.to_vec();
                let bin = match cx.first(bin_size, 1)? {
                    b if b < 0 => return Err(cx.error(bin_size, format!("is {b}; it must be 0 or more"))),
                    b => usize::try_from(b).unwrap_or(usize::MAX),
                };
                // Bin size 0: every material gets no parameters, whatever Parameters holds.
                let bins = if bin == 0 { 1 } else { params.len().div_ceil(bin) };
                let n = slice_count_with_materials(cx.spread(material).len(), [ids.len(), bins]);
                if let Some(slice) = (0..n).find(|s| (0..bin).any(|k| !params[(s * bin + k) % params.len()].is_finite())) {
                    return Err(not_finite(cx, parameters, slice));
                }
                set_feature(cx, material, out, n, parameters, Some(texture), |cx, slice| {
                    let id = ids[slice % ids.len()];
                    let feature = Feature::from_id(id).map_err(|e| refused(cx, feature_id, slice, e))?;
                    if feature.param_count().is_some_and(|c| c != bin) {
                        return Err(cx.error(
                            bin_size,
                            format!("is {bin}, but feature {feature} (slice {slice}) takes exactly one parameter vec4"),
                        ));
                    }
                    if !feature.reads_texture() && layers.get(slice % layers.len().max(1)).is_some_and(|l| *l >= 0) {
                        return Err(cx.error(
                            texture,
                            format!("slice {slice}: feature {feature} reads no texture; set -1"),
                        ));
                    }
                    let values = (0..bin).map(|k| params[(slice * bin + k) % params.len()].to_array()).collect();
                    Ok((feature, values))
                })
            }
        }),
    );
}
