//! `MotionBlur`: blur along the G-buffer's velocity (McGuire et al. 2012).

use spreadlight_graph::{NodeDef, PinType, Registry, ResourceKind, Spread};
use spreadlight_render::post::{MotionBlur, MotionBlurSettings};

use super::{count, float, gbuffer, set_texture, texture};
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
        .input_spread("Texture", PinType::Resource(ResourceKind::Texture), Spread::Resource(ResourceKind::Texture, vec![]))
        .input_spread("G-Buffer", PinType::Resource(ResourceKind::GBuffer), Spread::Resource(ResourceKind::GBuffer, vec![]))
        .input("Shutter Angle", d.shutter_angle)
        .input("Samples", i64::from(d.samples))
        .input("Max Blur", i64::from(d.tile_size))
        .output_typed("Texture", PinType::Resource(ResourceKind::Texture))
        .evaluate(|cx| {
            let renderer = renderer(cx)?;
            let source = texture(cx, 0)?;
            let g = gbuffer(cx, 1, "motion blur follows its velocity")?;
            let shutter_angle = float(cx, 2, 180.0, false)?;
            if !(0.0..=360.0).contains(&shutter_angle) {
                return Err(cx.input_error(2, "must be 0 to 360 degrees"));
            }
            let samples = count(cx, 3, 15, 2, 256)?;
            let tile_size = count(cx, 4, 20, 4, 64)?;
            let settings = MotionBlurSettings { shutter_angle, samples, tile_size };
            let blur = MotionBlur::new(&renderer, Some(cx.node_id.0), source, g, settings);
            set_texture(cx, blur.texture());
            Ok(())
        }),
    );
}
