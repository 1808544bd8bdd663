//! `Glare`: bloom through a mip-like chain, with chromatic aberration.

use spreadlight_graph::{NodeDef, Registry};
use spreadlight_render::post::{Glare, GlareSettings};

use super::{count, float, set_texture, texture, texture_input, texture_output};
use crate::gpu::renderer;

pub fn register(r: &mut Registry) {
    let d = GlareSettings::default();
    r.add(
        NodeDef::new(
            "Glare",
            "Post",
            "Bloom: what is brighter than Threshold (luminance) glows, through a chain of Levels half-size steps down \
             and back up (more levels reach wider; the quality); Spread 0..1 is how much each wider level adds; \
             Intensity scales the glow added to the image. Aberration pushes red and blue apart radially by that \
             fraction of the distance to the centre, over the image and the glow. Everything stays within half-float \
             range, whatever the input. Intensity and Aberration 0 cost one copy.",
        )
        .with_pins(|p| {
            let texture_in = texture_input(p, "Texture");
            let threshold = p.input("Threshold", d.threshold);
            let intensity = p.input("Intensity", d.intensity);
            let spread = p.input("Spread", d.spread);
            let aberration = p.input("Aberration", d.aberration);
            let levels = p.input("Levels", i64::from(d.levels));
            let out = texture_output(p, "Texture");
            move |cx| {
                let renderer = renderer(cx)?;
                let source = texture(cx, texture_in)?;
                let settings = GlareSettings {
                    threshold: float(cx, threshold, 0.0, false)?,
                    intensity: float(cx, intensity, 0.0, false)?,
                    spread: float(cx, spread, 0.0, false)?,
                    aberration: float(cx, aberration, 0.0, false)?,
                    levels: count(cx, levels, 6, 1, 12)?,
                };
                if settings.threshold < 0.0 {
                    return Err(cx.error(threshold, "is negative"));
                }
                if settings.intensity < 0.0 {
                    return Err(cx.error(intensity, "is negative"));
                }
                if !(0.0..=1.0).contains(&settings.spread) {
                    return Err(cx.error(spread, "must be 0 to 1"));
                }
                let glare = Glare::new(&renderer, Some(cx.node_id.0), source, settings);
                set_texture(cx, out, glare.texture());
                Ok(())
            }
        }),
    );
}
