//! `DOF`: depth of field from a thin lens, focused by a distance or by an
//! `Autofocus` texture.

use spreadlight_graph::{NodeDef, PinType, Registry, ResourceKind, Spread};
use spreadlight_render::post::{Dof, DofSettings, Focus};

use super::{count, float, gbuffer, optional_texture, set_texture, texture};
use crate::gpu::renderer;

pub fn register(r: &mut Registry) {
    let d = DofSettings::default();
    r.add(
        crate::resolution::pin(NodeDef::new(
            "DOF",
            "Post",
            "Depth of field from a thin lens: Focal Length (mm, the scene in metres), F-Stop (0.5 and up; larger is \
             sharper) and Focus Distance along the view axis (0: as near as the lens focuses, infinity allowed), or the \
             Focus texture of an Autofocus node when one is connected. Near and far fields without halos: a sharp \
             subject keeps its edge against a blurred background, a blurred foreground spreads over what is behind. \
             Bokeh: an optional texture whose luminance shapes the blur (the unit disk mapped to it). Samples per pixel \
             is the quality; Max Radius (pixels) bounds the blur and the cost. When the lens cannot blur anything by \
             half a pixel it costs one copy (counted as \"dof skipped\").",
        )
        .input_spread("Texture", PinType::Resource(ResourceKind::Texture), Spread::Resource(ResourceKind::Texture, vec![]))
        .input_spread("G-Buffer", PinType::Resource(ResourceKind::GBuffer), Spread::Resource(ResourceKind::GBuffer, vec![]))
        .input_spread("Focus", PinType::Resource(ResourceKind::Texture), Spread::Resource(ResourceKind::Texture, vec![]))
        .input_spread("Bokeh", PinType::Resource(ResourceKind::Texture), Spread::Resource(ResourceKind::Texture, vec![]))
        .input("Focal Length", d.focal_length_mm)
        .input("F-Stop", d.f_stop)
        .input("Focus Distance", 5.0f32)
        .input("Samples", i64::from(d.samples))
        .input("Max Radius", d.max_radius))
        .output_typed("Texture", PinType::Resource(ResourceKind::Texture))
        .evaluate(|cx| {
            let d = DofSettings::default();
            let renderer = renderer(cx)?;
            let source = texture(cx, 0)?;
            let g = gbuffer(cx, 1, "depth of field needs each pixel's depth")?;
            let focal_length_mm = float(cx, 4, d.focal_length_mm, false)?;
            if focal_length_mm <= 0.0 {
                return Err(cx.input_error(4, "must be above 0"));
            }
            let f_stop = float(cx, 5, d.f_stop, true)?;
            if f_stop < spreadlight_render::post::dof::MIN_F_STOP {
                return Err(cx.input_error(5, "must be 0.5 or more"));
            }
            let distance = float(cx, 6, 5.0, true)?;
            let samples = count(cx, 7, 32, 1, 512)?;
            let max_radius = float(cx, 8, d.max_radius, false)?;
            let focus = match optional_texture(cx, 2)? {
                Some(t) => Focus::Texture(t),
                None => Focus::Distance(distance),
            };
            let bokeh = optional_texture(cx, 3)?;
            let resolution = crate::resolution::read(cx, 9)?;
            let settings = DofSettings { focal_length_mm, f_stop, samples, max_radius, resolution };
            let dof = Dof::new(&renderer, Some(cx.node_id.0), source, g, focus, bokeh, settings);
            set_texture(cx, dof.texture());
            Ok(())
        }),
    );
}
