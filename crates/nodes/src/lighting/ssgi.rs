//! `SSGI`: one bounce of diffuse light from what the screen sees
//! (render::lighting::Ssgi), for CompositeLight's GI input.

use spreadlight_graph::{In, NodeDef, NodeError, Registry};
use spreadlight_render::lighting::{Ssgi, SsgiSettings};

use super::require_finite;
use crate::gpu::renderer;
use crate::post::{gbuffer_input, optional_texture, set_texture, texture_input, texture_output};

pub fn register(r: &mut Registry) {
    let d = SsgiSettings::default();
    r.add(
        crate::resolution::with_help(NodeDef::new(
            "SSGI",
            super::CATEGORY,
            "Screen-space global illumination: one bounce of diffuse light, colour bleeding between nearby surfaces. \
             Samples rays per pixel (cosine-weighted, turned every frame), each marched Steps times up to Radius (world \
             units), gather the Texture (the lit diffuse image: CookTorrance's Diffuse, or a CompositeLight without GI) \
             where they hit; rays that escape bring nothing, and Ambient (optional: an environment's diffuse light) is \
             added. Output: radiance per unit albedo, for CompositeLight's GI. Temporal Blend 0..0.98, Blur Radius \
             (pixels), Reset: as SSAO's.",
        ))
        // Temporal accumulation, and rays turned by a count of its own frames.
        .stateful()
        .with_pins(|p| {
            let g_buffer = gbuffer_input(p);
            let texture = texture_input(p, "Texture");
            let ambient = texture_input(p, "Ambient");
            let radius = p.input("Radius", d.radius);
            let samples = p.input("Samples", i64::from(d.samples));
            let steps = p.input("Steps", i64::from(d.steps));
            let intensity = p.input("Intensity", d.intensity);
            let blend = p.input("Temporal Blend", d.temporal_blend);
            let blur = p.input("Blur Radius", i64::from(d.blur_radius));
            let reset = p.input("Reset", false);
            let resolution = crate::resolution::input(p);
            let out = texture_output(p, "Texture");
            move |cx| {
                let renderer = renderer(cx)?;
                let d = SsgiSettings::default();
                require_finite(cx, radius)?;
                require_finite(cx, samples)?;
                require_finite(cx, steps)?;
                require_finite(cx, intensity)?;
                require_finite(cx, blend)?;
                require_finite(cx, blur)?;
                let int = |pin: In<i64>, fallback: u32| -> Result<u32, NodeError> {
                    Ok(cx.get(pin)?.first().map_or(fallback, |v| (*v).clamp(0, 1 << 16) as u32))
                };
                let radius_value = cx.first(radius, d.radius)?;
                if radius_value < 0.0 {
                    return Err(cx.error(radius, "must be 0 or more (world units)"));
                }
                let blend_value = cx.first(blend, d.temporal_blend)?;
                if !(0.0..1.0).contains(&blend_value) {
                    return Err(cx.error(blend, "must be in 0..1 (0.98 at most is used)"));
                }
                let settings = SsgiSettings {
                    radius: radius_value,
                    samples: int(samples, d.samples)?,
                    steps: int(steps, d.steps)?,
                    intensity: cx.first(intensity, d.intensity)?,
                    temporal_blend: blend_value,
                    blur_radius: int(blur, d.blur_radius)?,
                    reset: cx.first(reset, false)?,
                    resolution: cx.choice(resolution)?,
                };
                let g = cx
                    .first_resource(g_buffer)?
                    .ok_or_else(|| cx.error(g_buffer, "no G-buffer connected: SSGI marches its depth"))?;
                let source = optional_texture(cx, texture)?
                    .ok_or_else(|| cx.error(texture, "no lit image connected: light bounces from it"))?;
                let ambient = optional_texture(cx, ambient)?;
                let gi = Ssgi::new(&renderer, Some(cx.node_id.0), g, source, ambient, settings);
                set_texture(cx, out, gi.texture());
                Ok(())
            }
        }),
    );
}
