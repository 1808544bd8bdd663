//! `Glare`: bloom through a mip-like chain, with chromatic aberration.

use spreadlight_graph::{NodeDef, PinType, Registry, ResourceKind, Spread};
use spreadlight_render::post::{Glare, GlareSettings};

use super::{count, float, set_texture, texture};
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
        .input_spread("Texture", PinType::Resource(ResourceKind::Texture), Spread::Resource(ResourceKind::Texture, vec![]))
        .input("Threshold", d.threshold)
        .input("Intensity", d.intensity)
        .input("Spread", d.spread)
        .input("Aberration", d.aberration)
        .input("Levels", i64::from(d.levels))
        .output_typed("Texture", PinType::Resource(ResourceKind::Texture))
        .evaluate(|cx| {
            let renderer = renderer(cx)?;
            let source = texture(cx, 0)?;
            let mut v = [0.0f32; 4];
            for (i, value) in v.iter_mut().enumerate() {
                *value = float(cx, i + 1, 0.0, false)?;
            }
            let [threshold, intensity, spread, aberration] = v;
            if threshold < 0.0 {
                return Err(cx.input_error(1, "is negative"));
            }
            if intensity < 0.0 {
                return Err(cx.input_error(2, "is negative"));
            }
            if !(0.0..=1.0).contains(&spread) {
                return Err(cx.input_error(3, "must be 0 to 1"));
            }
            let levels = count(cx, 5, 6, 1, 12)?;
            let settings = GlareSettings { threshold, intensity, spread, aberration, levels };
            let glare = Glare::new(&renderer, Some(cx.node_id.0), source, settings);
            set_texture(cx, glare.texture());
            Ok(())
        }),
    );
}
