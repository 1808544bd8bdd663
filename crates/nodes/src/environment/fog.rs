//! `Fog`: distance and height fog over the lit image, exact along each view
//! ray (a closed form, not ray marching). Between `CompositeLight` and `Sky`:
//! the sky is left to `Sky`.

use glam::Vec3;
use spreadlight_graph::{Color, NodeDef, Registry};
use spreadlight_render::environment::{Fog, FogSettings};

use crate::gpu::renderer;
use crate::lighting::require_finite;
use crate::post::{gbuffer_input, set_texture, texture, texture_input, texture_output};

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
        .with_pins(|p| {
            let texture_in = texture_input(p, "Texture");
            let g_buffer = gbuffer_input(p);
            let color = p.input("Color", Color::rgba(d.color.x, d.color.y, d.color.z, 1.0));
            let density = p.input("Density", d.density);
            let falloff = p.input("Height Falloff", d.height_falloff);
            let base = p.input("Base Height", d.base_height);
            let start = p.input("Start", d.start);
            let out = texture_output(p, "Texture");
            move |cx| {
                let renderer = renderer(cx)?;
                require_finite(cx, color)?;
                for pin in [density, falloff, base, start] {
                    require_finite(cx, pin)?;
                }
                let source = texture(cx, texture_in)?;
                let gbuffer = cx
                    .first_resource(g_buffer)?
                    .ok_or_else(|| cx.error(g_buffer, "no G-buffer connected: fog needs each pixel's distance"))?;
                let c = cx.first(color, Color::WHITE)?;
                let d = FogSettings::default();
                let settings = FogSettings {
                    color: Vec3::new(c.r, c.g, c.b),
                    density: cx.first(density, d.density)?,
                    height_falloff: cx.first(falloff, d.height_falloff)?,
                    base_height: cx.first(base, d.base_height)?,
                    start: cx.first(start, d.start)?,
                };
                let fog = Fog::pass(&renderer, Some(cx.node_id.0), gbuffer, source, settings);
                set_texture(cx, out, fog.texture());
                Ok(())
            }
        }),
    );
}
