//! `SSR`: screen-space reflection with roughness: rays traced through a
//! hierarchical depth in screen space, reading Lit (a lit image such as
//! CompositeLight's, so there is no cycle), falling back to Fallback
//! (Reflection's Specular) on misses and at the screen's edges.

use spreadlight_graph::{NodeDef, PinType, Registry, ResourceKind, Spread};
use spreadlight_render::TextureRef;
use spreadlight_render::environment::{Ssr, SsrSettings};
use spreadlight_render::gbuffer::GBuffer;
use spreadlight_render::material::MaterialWorld;

use crate::gpu::{renderer, resource_spread, resources};

pub fn register(r: &mut Registry) {
    let d = SsrSettings::default();
    r.add(
        crate::resolution::pin(NodeDef::new(
            "SSR",
            super::CATEGORY,
            "Screen-space reflection for materials with the Reflection feature (others get zero): per pixel, Rays rays \
             (the mirror direction at roughness below 0.02, GGX-jittered directions above) traced through a hierarchical \
             depth for at most Max Steps steps, reading Lit where they hit (surfaces are assumed Thickness deep). Misses, \
             rays leaving the screen and hits near its edges fade smoothly to Fallback (connect Reflection's Specular). \
             Output: reflected radiance times the split-sum factor, like Reflection's Specular, so either can be composited. \
             Temporal blends with last frame's result (weight Blend for the new frame), reprojected by the G-buffer's \
             velocity, only where the same surface was seen (its distance within 5%); a resize, Reset, or a camera cut (the \
             G-buffer's last camera is not the one seen last frame) starts the history afresh. Note: Blend is the new frame's \
             weight here, where SSAO's and SSGI's Temporal Blend is last frame's. Cost: about Rays x Max Steps texture reads a pixel.",
        )
        .input_spread("G-Buffer", PinType::Resource(ResourceKind::GBuffer), Spread::Resource(ResourceKind::GBuffer, vec![]))
        .input_spread(
            "Material World",
            PinType::Resource(ResourceKind::MaterialWorld),
            Spread::Resource(ResourceKind::MaterialWorld, vec![]),
        )
        .input_spread("Lit", PinType::Resource(ResourceKind::Texture), Spread::Resource(ResourceKind::Texture, vec![]))
        .input_spread("Fallback", PinType::Resource(ResourceKind::Texture), Spread::Resource(ResourceKind::Texture, vec![]))
        .input("Max Steps", i64::from(d.max_steps))
        .input("Rays", i64::from(d.rays))
        .input("Temporal", d.temporal)
        .input("Blend", d.blend)
        .input("Thickness", d.thickness)
        .input("Reset", false))
        .output_typed("Texture", PinType::Resource(ResourceKind::Texture))
        // Temporal history (with Temporal on) and rays turned by a count of its own frames.
        .stateful()
        .evaluate(|cx| {
            let d = SsrSettings::default();
            for pin in [7, 8] {
                if let Some(slice) = cx.input(pin).first_non_finite() {
                    return Err(cx.input_error(pin, format!("slice {slice} is NaN or infinite")));
                }
            }
            let int = |pin: usize, fallback: u32| -> Result<u32, spreadlight_graph::NodeError> {
                let v = cx.slices::<i64>(pin)?.first().copied().unwrap_or(i64::from(fallback));
                if v < 1 {
                    return Err(cx.input_error(pin, format!("must be at least 1, got {v}")));
                }
                Ok(v.min(i64::from(u32::MAX)) as u32)
            };
            let settings = SsrSettings {
                max_steps: int(4, d.max_steps)?,
                rays: int(5, d.rays)?,
                temporal: cx.slices::<bool>(6)?.first().copied().unwrap_or(d.temporal),
                blend: cx.slices::<f32>(7)?.first().copied().unwrap_or(d.blend),
                thickness: cx.slices::<f32>(8)?.first().copied().unwrap_or(d.thickness),
                reset: cx.slices::<bool>(9)?.first().copied().unwrap_or(false),
                resolution: crate::resolution::read(cx, 10)?,
            };
            let renderer = renderer(cx)?;
            let gbuffer = resources::<GBuffer>(cx, 0)?.into_iter().next().ok_or_else(|| cx.input_error(0, "no G-buffer connected"))?;
            let materials = match resources::<MaterialWorld>(cx, 1)?.into_iter().next() {
                Some(world) => world,
                None => MaterialWorld::new(&renderer, Vec::new()),
            };
            let lit = resources::<TextureRef>(cx, 2)?
                .into_iter()
                .next()
                .ok_or_else(|| cx.input_error(2, "no lit image connected (CompositeLight's output, for instance)"))?;
            let fallback = resources::<TextureRef>(cx, 3)?
                .into_iter()
                .next()
                .ok_or_else(|| cx.input_error(3, "no fallback connected: Reflection's Specular, used where rays miss"))?;
            let ssr = Ssr::new(&renderer, Some(cx.node_id.0), gbuffer, materials, (*lit).clone(), (*fallback).clone(), settings);
            cx.set_output(0, resource_spread::<TextureRef>(ResourceKind::Texture, vec![std::sync::Arc::new(ssr.texture())]));
            Ok(())
        }),
    );
}
