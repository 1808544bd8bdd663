//! `Fog`: distance and height fog over the lit image, exact along each view
//! ray (a closed form, not ray marching). Between `CompositeLight` and `Sky`:
//! the sky is left to `Sky`.

use glam::Vec3;
use spreadlight_graph::{Color, NodeDef, PinType, Registry, ResourceKind, Spread};
use spreadlight_render::TextureRef;
use spreadlight_render::environment::{Fog, FogSettings};
use spreadlight_render::gbuffer::GBuffer;

use crate::gpu::{renderer, resource_spread, resources};

pub fn register(r: &mut Registry) {
    let d = FogSettings::default();
    r.add(
        NodeDef::new(
            "Fog",
            super::CATEGORY,
            "Fog over the lit image where the G-buffer has geometry: Density (extinction per unit length at Base \
             Height) thinning with height by Height Falloff per unit (0: uniform), none nearer than Start; the fog \
             itself shines with Color (linear). Exact along each view ray.",
        )
        .input_spread("Texture", PinType::Resource(ResourceKind::Texture), Spread::Resource(ResourceKind::Texture, vec![]))
        .input_spread("G-Buffer", PinType::Resource(ResourceKind::GBuffer), Spread::Resource(ResourceKind::GBuffer, vec![]))
        .input("Color", Color::rgba(d.color.x, d.color.y, d.color.z, 1.0))
        .input("Density", d.density)
        .input("Height Falloff", d.height_falloff)
        .input("Base Height", d.base_height)
        .input("Start", d.start)
        .output_typed("Texture", PinType::Resource(ResourceKind::Texture))
        .evaluate(|cx| {
            let renderer = renderer(cx)?;
            for pin in 2..7 {
                if let Some(slice) = cx.input(pin).first_non_finite() {
                    return Err(cx.input_error(pin, format!("slice {slice} is NaN or infinite")));
                }
            }
            let source = resources::<TextureRef>(cx, 0)?
                .into_iter()
                .next()
                .ok_or_else(|| cx.input_error(0, "no texture connected"))?;
            let gbuffer = resources::<GBuffer>(cx, 1)?
                .into_iter()
                .next()
                .ok_or_else(|| cx.input_error(1, "no G-buffer connected: fog needs each pixel's distance"))?;
            let float = |pin: usize, fallback: f32| -> Result<f32, spreadlight_graph::NodeError> {
                Ok(cx.slices::<f32>(pin)?.first().copied().unwrap_or(fallback))
            };
            let c = cx.slices::<Color>(2)?.first().copied().unwrap_or(Color::WHITE);
            let d = FogSettings::default();
            let settings = FogSettings {
                color: Vec3::new(c.r, c.g, c.b),
                density: float(3, d.density)?,
                height_falloff: float(4, d.height_falloff)?,
                base_height: float(5, d.base_height)?,
                start: float(6, d.start)?,
            };
            let fog = Fog::pass(&renderer, Some(cx.node_id.0), gbuffer, (*source).clone(), settings);
            cx.set_output(0, resource_spread::<TextureRef>(ResourceKind::Texture, vec![std::sync::Arc::new(fog.texture())]));
            Ok(())
        }),
    );
}
