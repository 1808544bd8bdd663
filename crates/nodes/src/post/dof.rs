//! `DOF`: depth of field from a thin lens, focused by a distance or by an
//! `Autofocus` texture.

use spreadlight_graph::{NodeDef, Registry};
use spreadlight_render::post::{Dof, DofSettings, Focus};

use super::{
    count, float, gbuffer, gbuffer_input, optional_texture, set_texture, texture, texture_input,
    texture_output,
};
use crate::gpu::renderer;

pub fn register(r: &mut Registry) {
    let d = DofSettings::default();
    r.add(
        crate::resolution::with_full_half_help(NodeDef::new(
            "DOF",
            "Post",
            "Depth of field from a thin lens: Focal Length (mm, the scene in metres), F-Stop (0.5 and up; larger is \
             sharper) and Focus Distance along the view axis (0: as near as the lens focuses, infinity allowed), or the \
             Focus texture of an Autofocus node when one is connected. Near and far fields without halos: a sharp \
             subject keeps its edge against a blurred background, a blurred foreground spreads over what is behind. \
             Bokeh: an optional texture whose luminance shapes the blur (the unit disk mapped to it). Samples per pixel \
             is the quality; Max Radius (pixels) bounds the blur and the cost. When the lens cannot blur anything by \
             half a pixel it costs one copy (counted as \"dof skipped\").",
        ))
        .with_pins(|p| {
            let texture_in = texture_input(p, "Texture");
            let g_buffer = gbuffer_input(p);
            let focus_texture = texture_input(p, "Focus");
            let bokeh = texture_input(p, "Bokeh");
            let focal_length = p.input("Focal Length", d.focal_length_mm);
            let f_stop = p.input("F-Stop", d.f_stop);
            let focus_distance = p.input("Focus Distance", 5.0f32);
            let samples = p.input("Samples", i64::from(d.samples));
            let max_radius = p.input("Max Radius", d.max_radius);
            let resolution = crate::resolution::input_full_half(p);
            let out = texture_output(p, "Texture");
            move |cx| {
                let d = DofSettings::default();
                let renderer = renderer(cx)?;
                let source = texture(cx, texture_in)?;
                let g = gbuffer(cx, g_buffer, "depth of field needs each pixel's depth")?;
                let focal_length_mm = float(cx, focal_length, d.focal_length_mm, false)?;
                if focal_length_mm <= 0.0 {
                    return Err(cx.error(focal_length, "must be above 0"));
                }
                let f_stop_value = float(cx, f_stop, d.f_stop, true)?;
                if f_stop_value < spreadlight_render::post::dof::MIN_F_STOP {
                    return Err(cx.error(f_stop, "must be 0.5 or more"));
                }
                let distance = float(cx, focus_distance, 5.0, true)?;
                let focus = match optional_texture(cx, focus_texture)? {
                    Some(t) => Focus::Texture(t),
                    None => Focus::Distance(distance),
                };
                let settings = DofSettings {
                    focal_length_mm,
                    f_stop: f_stop_value,
                    samples: count(cx, samples, 32, 1, 512)?,
                    max_radius: float(cx, max_radius, d.max_radius, false)?,
                    resolution: cx.choice(resolution)?,
                };
                let bokeh = optional_texture(cx, bokeh)?;
                let dof = Dof::new(&renderer, Some(cx.node_id.0), source, g, focus, bokeh, settings);
                set_texture(cx, out, dof.texture());
                Ok(())
            }
        }),
    );
}
