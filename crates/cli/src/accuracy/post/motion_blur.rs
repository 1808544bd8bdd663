//! MotionBlur's rows: every sample count, against the average of `--views`
//! sub-frame renders across the open shutter, the moving ball where it is at
//! each instant.

use std::sync::Arc;

use anyhow::Context;
use spreadlight_render::post::{MotionBlur, MotionBlurSettings};
use spreadlight_render::{Recipe, Renderer};

use super::measure::{error, run, time};
use super::scene::{albedo, camera, gbuffer, scene};
use super::{Effect, PostArgs, Row};
use crate::sequence::accumulate::{Average, shutter_offset};

/// The shutter angle (degrees) the blur and its reference share.
pub(super) const SHUTTER: f32 = 180.0;

fn blur_settings(samples: u32) -> MotionBlurSettings {
    MotionBlurSettings {
        shutter_angle: SHUTTER,
        samples,
        ..Default::default()
    }
}

pub(super) fn measure(
    renderer: &Renderer,
    args: &PostArgs,
    rows: &mut Vec<Row>,
) -> anyhow::Result<()> {
    let size = args.error_size;
    let cam = camera(size);
    eprintln!("MotionBlur reference: {} sub-frames ...", args.views);
    let mut average = Average::new((size.0 * size.1) as usize);
    let open = SHUTTER / 360.0;
    for i in 0..args.views {
        // The shutter is open for `open` of a frame, centred on the frame.
        let t = shutter_offset(i, args.views, f64::from(open)) as f32;
        let g = gbuffer(renderer, scene(renderer, t, false)?, cam, None);
        let (_, image) = run(renderer, g.as_ref(), &g.targets.color, size, true)?;
        average.add(&image.context("image")?);
    }
    let truth = average.image(size);
    let layer = scene(renderer, 0.0, true)?;
    for samples in [5, 9, 15, 25] {
        eprintln!("MotionBlur {samples} samples");
        let g = gbuffer(renderer, layer.clone(), cam, None);
        let blur = MotionBlur::new(renderer, None, albedo(&g), g, blur_settings(samples));
        let (_, image) = run(renderer, blur.as_ref(), &blur.output, size, true)?;
        let (rmse, ssim) = error(&image.context("image")?, &truth);
        let timed = camera(args.common.time_size);
        let ms = time(renderer, args, "MotionBlur", |_| {
            let g = gbuffer(renderer, layer.clone(), timed, None);
            let blur = MotionBlur::new(renderer, None, albedo(&g), g, blur_settings(samples));
            let name = blur.output.clone();
            Ok((blur as Arc<dyn Recipe>, name))
        })?;
        rows.push(Row {
            effect: Effect::MotionBlur,
            setting: format!("{samples} samples"),
            ms,
            rmse,
            ssim,
        });
    }
    Ok(())
}
