//! `MotionBlur`: blur along the G-buffer's velocity (McGuire et al. 2012).

use spreadlight_graph::{NodeDef, Registry};
use spreadlight_render::post::{MotionBlur, MotionBlurSettings};

use super::{
    count, float, gbuffer, gbuffer_input, set_texture, texture, texture_input, texture_output,
};
use crate::gpu::renderer;

pub fn register(r: &mut Registry) {
    let d = MotionBlurSettings::default();
    r.add(
        NodeDef::new(
            "MotionBlur",
            "Post",
            "Blur along each pixel's motion (the G-buffer's velocity) over the exposure: Shutter Angle in degrees of a \
             frame (180: half the frame's motion; 0: none). Moving silhouettes extend over the still background \
             (tile-max and neighbour-max velocity, McGuire et al. 2012); Max Blur (pixels, the tile size) bounds the \
             blur each way; Samples per pixel is the quality. A frame where nothing moves costs one copy (counted as \
             \"motion blur skipped\"), and still tiles copy their pixels.",
        )
        .with_pins(|p| {
            let texture_in = texture_input(p, "Texture");
            let g_buffer = gbuffer_input(p);
            let shutter_angle = p.input("Shutter Angle", d.shutter_angle);
            let samples = p.input("Samples", i64::from(d.samples));
            let max_blur = p.input("Max Blur", i64::from(d.tile_size));
            let out = texture_output(p, "Texture");
            move |cx| {
                let renderer = renderer(cx)?;
                let source = texture(cx, texture_in)?;
                let g = gbuffer(cx, g_buffer, "motion blur follows its velocity")?;
                let angle = float(cx, shutter_angle, 180.0, false)?;
                if !(0.0..=360.0).contains(&angle) {
                    return Err(cx.error(shutter_angle, "must be 0 to 360 degrees"));
                }
                let settings = MotionBlurSettings {
                    shutter_angle: angle,
                    samples: count(cx, samples, 15, 2, 256)?,
                    tile_size: count(cx, max_blur, 20, 4, 64)?,
                };
                let blur = MotionBlur::new(&renderer, Some(cx.node_id.0), source, g, settings);
                set_texture(cx, out, blur.texture());
                Ok(())
            }
        }),
    );
}
