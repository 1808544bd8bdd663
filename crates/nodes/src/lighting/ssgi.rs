//! `SSGI`: one bounce of diffuse light from what the screen sees
//! (render::lighting::Ssgi), for CompositeLight's GI input.

use spreadlight_graph::{NodeDef, NodeError, PinType, Registry, ResourceKind, Spread};
use spreadlight_render::TextureRef;
use spreadlight_render::gbuffer::GBuffer;
use spreadlight_render::lighting::{Ssgi, SsgiSettings};

use crate::gpu::{renderer, resource_spread, resources};

pub fn register(r: &mut Registry) {
    let texture = || Spread::Resource(ResourceKind::Texture, vec![]);
    let d = SsgiSettings::default();
    r.add(
        crate::resolution::pin(NodeDef::new(
            "SSGI",
            super::CATEGORY,
            "Screen-space global illumination: one bounce of diffuse light, colour bleeding between nearby surfaces. \
             Samples rays per pixel (cosine-weighted, turned every frame), each marched Steps times up to Radius (world \
             units), gather the Texture (the lit diffuse image: CookTorrance's Diffuse, or a CompositeLight without GI) \
             where they hit; rays that escape bring nothing, and Ambient (optional: an environment's diffuse light) is \
             added. Output: radiance per unit albedo, for CompositeLight's GI. Temporal Blend 0..0.98, Blur Radius \
             (pixels), Reset: as SSAO's.",
        )
        .input_spread("G-Buffer", PinType::Resource(ResourceKind::GBuffer), Spread::Resource(ResourceKind::GBuffer, vec![]))
        .input_spread("Texture", PinType::Resource(ResourceKind::Texture), texture())
        .input_spread("Ambient", PinType::Resource(ResourceKind::Texture), texture())
        .input("Radius", d.radius)
        .input("Samples", i64::from(d.samples))
        .input("Steps", i64::from(d.steps))
        .input("Intensity", d.intensity)
        .input("Temporal Blend", d.temporal_blend)
        .input("Blur Radius", i64::from(d.blur_radius))
        .input("Reset", false))
        .output_typed("Texture", PinType::Resource(ResourceKind::Texture))
        // Temporal accumulation, and rays turned by a count of its own frames.
        .stateful()
        .evaluate(|cx| {
            let renderer = renderer(cx)?;
            let d = SsgiSettings::default();
            super::require_finite(cx, 3..9)?;
            let float = |pin: usize, fallback: f32| -> Result<f32, NodeError> {
                Ok(cx.slices::<f32>(pin)?.first().copied().unwrap_or(fallback))
            };
            let int = |pin: usize, fallback: u32| -> Result<u32, NodeError> {
                Ok(cx.slices::<i64>(pin)?.first().map_or(fallback, |v| (*v).clamp(0, 1 << 16) as u32))
            };
            let radius = float(3, d.radius)?;
            if radius < 0.0 {
                return Err(cx.input_error(3, "must be 0 or more (world units)"));
            }
            let blend = float(7, d.temporal_blend)?;
            if !(0.0..1.0).contains(&blend) {
                return Err(cx.input_error(7, "must be in 0..1 (0.98 at most is used)"));
            }
            let settings = SsgiSettings {
                radius,
                samples: int(4, d.samples)?,
                steps: int(5, d.steps)?,
                intensity: float(6, d.intensity)?,
                temporal_blend: blend,
                blur_radius: int(8, d.blur_radius)?,
                reset: cx.slices::<bool>(9)?.first().copied().unwrap_or(false),
                resolution: crate::resolution::read(cx, 10)?,
            };
            let g = resources::<GBuffer>(cx, 0)?
                .into_iter()
                .next()
                .ok_or_else(|| cx.input_error(0, "no G-buffer connected: SSGI marches its depth"))?;
            let source = resources::<TextureRef>(cx, 1)?
                .into_iter()
                .next()
                .ok_or_else(|| cx.input_error(1, "no lit image connected: light bounces from it"))?;
            let ambient = resources::<TextureRef>(cx, 2)?.into_iter().next().map(|t| (*t).clone());
            let gi = Ssgi::new(&renderer, Some(cx.node_id.0), g, (*source).clone(), ambient, settings);
            cx.set_output(0, resource_spread::<TextureRef>(ResourceKind::Texture, vec![std::sync::Arc::new(gi.texture())]));
            Ok(())
        }),
    );
}
