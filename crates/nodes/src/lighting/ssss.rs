//! `SSSS`: screen-space subsurface scattering of CookTorrance's SSS term
//! (render::lighting::Ssss), per material by its FakeSSS colour.

use spreadlight_graph::{EnumDef, NodeDef, PinType, Registry, ResourceKind, Spread};
use spreadlight_render::TextureRef;
use spreadlight_render::gbuffer::GBuffer;
use spreadlight_render::lighting::{Ssss, SsssQuality};
use spreadlight_render::material::MaterialWorld;

use crate::gpu::{renderer, resource_spread, resources};

pub static QUALITY: EnumDef = EnumDef {
    name: "SSSS Quality",
    options: &["Low", "Medium", "High"],
};

pub fn register(r: &mut Registry) {
    r.add(
        NodeDef::new(
            "SSSS",
            super::CATEGORY,
            "Screen-space subsurface scattering (a separable kernel as Jimenez et al.'s, one Gaussian per channel): blurs CookTorrance's SSS term (Texture) \
             over the surface, Width world units for the widest channel; each material's FakeSSS colour sets how far \
             each channel reaches (skin: red farthest). Taps stay on the same material and follow the surface across \
             depth steps. Quality: Low (4 taps a side), Medium (8), High (16). Without a material whose FakeSSS has a \
             colour and a strength above 0 it runs nothing and passes the Texture on; pixels of materials that \
             scatter nothing pass through. Wire the result to CompositeLight's SSS.",
        )
        .input_spread("G-Buffer", PinType::Resource(ResourceKind::GBuffer), Spread::Resource(ResourceKind::GBuffer, vec![]))
        .input_spread("Texture", PinType::Resource(ResourceKind::Texture), Spread::Resource(ResourceKind::Texture, vec![]))
        .input_spread(
            "Material World",
            PinType::Resource(ResourceKind::MaterialWorld),
            Spread::Resource(ResourceKind::MaterialWorld, vec![]),
        )
        .input("Width", 0.05f32)
        .input_enum("Quality", &QUALITY, "Medium")
        .output_typed("Texture", PinType::Resource(ResourceKind::Texture))
        .evaluate(|cx| {
            let renderer = renderer(cx)?;
            super::require_finite(cx, 3..4)?;
            let width = cx.slices::<f32>(3)?.first().copied().unwrap_or(0.05);
            if width < 0.0 {
                return Err(cx.input_error(3, "must be 0 or more (world units)"));
            }
            let quality = match cx.enum_slices(4)?.first().map(String::as_str) {
                Some("Low") => SsssQuality::Low,
                Some("High") => SsssQuality::High,
                _ => SsssQuality::Medium,
            };
            let g = resources::<GBuffer>(cx, 0)?
                .into_iter()
                .next()
                .ok_or_else(|| cx.input_error(0, "no G-buffer connected"))?;
            // One slice per light type, as CookTorrance gives them.
            let sss = resources::<TextureRef>(cx, 1)?;
            let materials = resources::<MaterialWorld>(cx, 2)?.into_iter().next();
            // One blur pass pair for up to three slices: they share their taps.
            let out = Ssss::textures(
                &renderer,
                Some(cx.node_id.0),
                g.clone(),
                sss.iter().map(|t| (**t).clone()).collect(),
                materials,
                width,
                quality,
            )
            .into_iter()
            .map(std::sync::Arc::new)
            .collect();
            cx.set_output(0, resource_spread::<TextureRef>(ResourceKind::Texture, out));
            Ok(())
        }),
    );
}
