//! `SSR`: screen-space reflection with roughness: rays traced through a
//! hierarchical depth in screen space, reading Lit (a lit image such as
//! CompositeLight's, so there is no cycle), falling back to Fallback
//! (Reflection's Specular) on misses and at the screen's edges.

use spreadlight_graph::{In, NodeDef, NodeError, Registry, ResourceKind};
use spreadlight_render::environment::{Ssr, SsrSettings};
use spreadlight_render::material::MaterialWorld;

use crate::gpu::renderer;
use crate::lighting::require_finite;
use crate::post::{gbuffer_input, set_texture, texture_input, texture_output};

pub fn register(r: &mut Registry) {
    let d = SsrSettings::default();
    r.add(
        crate::resolution::with_help(NodeDef::new(
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
        ))
        // Temporal history (with Temporal on) and rays turned by a count of its own frames.
        .stateful()
        .with_pins(|p| {
            let g_buffer = gbuffer_input(p);
            let material_world = p.input_resource::<MaterialWorld>("Material World", ResourceKind::MaterialWorld);
            let lit_in = texture_input(p, "Lit");
            let fallback_in = texture_input(p, "Fallback");
            let max_steps = p.input("Max Steps", i64::from(d.max_steps));
            let rays = p.input("Rays", i64::from(d.rays));
            let temporal = p.input("Temporal", d.temporal);
            let blend = p.input("Blend", d.blend);
            let thickness = p.input("Thickness", d.thickness);
            let reset = p.input("Reset", false);
            let resolution = crate::resolution::input(p);
            let out = texture_output(p, "Texture");
            move |cx| {
                let d = SsrSettings::default();
                require_finite(cx, blend)?;
                require_finite(cx, thickness)?;
                let int = |pin: In<i64>, fallback: u32| -> Result<u32, NodeError> {
                    let v = cx.first(pin, i64::from(fallback))?;
                    if v < 1 {
                        return Err(cx.error(pin, format!("must be at least 1, got {v}")));
                    }
                    Ok(v.min(i64::from(u32::MAX)) as u32)
                };
                let settings = SsrSettings {
                    max_steps: int(max_steps, d.max_steps)?,
                    rays: int(rays, d.rays)?,
                    temporal: cx.first(temporal, d.temporal)?,
                    blend: cx.first(blend, d.blend)?,
                    thickness: cx.first(thickness, d.thickness)?,
                    reset: cx.first(reset, false)?,
                    resolution: cx.choice(resolution)?,
                };
                let renderer = renderer(cx)?;
                let gbuffer = cx.first_resource(g_buffer)?.ok_or_else(|| cx.error(g_buffer, "no G-buffer connected"))?;
                let materials = match cx.first_resource(material_world)? {
                    Some(world) => world,
                    None => MaterialWorld::new(&renderer, Vec::new()),
                };
                let lit = crate::post::optional_texture(cx, lit_in)?
                    .ok_or_else(|| cx.error(lit_in, "no lit image connected (CompositeLight's output, for instance)"))?;
                let fallback = crate::post::optional_texture(cx, fallback_in)?
                    .ok_or_else(|| cx.error(fallback_in, "no fallback connected: Reflection's Specular, used where rays miss"))?;
                let ssr = Ssr::new(&renderer, Some(cx.node_id.0), gbuffer, materials, lit, fallback, settings);
                set_texture(cx, out, ssr.texture());
                Ok(())
            }
        }),
    );
}
