//! `SSSS`: screen-space subsurface scattering of CookTorrance's SSS term
//! (render::lighting::Ssss), per material by its FakeSSS colour.

use spreadlight_graph::{Choices, NodeDef, Registry, ResourceKind};
use spreadlight_render::lighting::{Ssss, SsssQuality};
use spreadlight_render::material::MaterialWorld;

use crate::gpu::renderer;
use crate::post::{gbuffer_input, texture_input, texture_output};

pub static QUALITY: Choices<SsssQuality> = Choices::new(
    "SSSS Quality",
    &["Low", "Medium", "High"],
    &[SsssQuality::Low, SsssQuality::Medium, SsssQuality::High],
);

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
        .with_pins(|p| {
            let g_buffer = gbuffer_input(p);
            let texture = texture_input(p, "Texture");
            let material_world = p.input_resource::<MaterialWorld>("Material World", ResourceKind::MaterialWorld);
            let width = p.input("Width", 0.05f32);
            let quality = p.input_choice("Quality", &QUALITY, SsssQuality::Medium);
            let out = texture_output(p, "Texture");
            move |cx| {
                let renderer = renderer(cx)?;
                super::require_finite(cx, width)?;
                let width_value = cx.first(width, 0.05)?;
                if width_value < 0.0 {
                    return Err(cx.error(width, "must be 0 or more (world units)"));
                }
                let quality = cx.choice(quality)?;
                let g = cx.first_resource(g_buffer)?.ok_or_else(|| cx.error(g_buffer, "no G-buffer connected"))?;
                // One slice per light type, as CookTorrance gives them.
                let sss = cx.resources(texture)?;
                let materials = cx.first_resource(material_world)?;
                // One blur pass pair for up to three slices: they share their taps.
                let textures = Ssss::textures(
                    &renderer,
                    Some(cx.node_id.0),
                    g.clone(),
                    sss.iter().map(|t| (**t).clone()).collect(),
                    materials,
                    width_value,
                    quality,
                )
                .into_iter()
                .map(std::sync::Arc::new)
                .collect();
                cx.put_resources(out, textures);
                Ok(())
            }
        }),
    );
}
