//! FXAA's rows: the aliased frame (FXAA off) and each quality, against the
//! frame rendered 8x8 larger and box-downsampled (measure.rs's `supersampled`).

use std::sync::Arc;

use anyhow::Context;
use spreadlight_render::gbuffer::Layer;
use spreadlight_render::post::{Fxaa, FxaaQuality};
use spreadlight_render::readback::ImageF32;
use spreadlight_render::{Recipe, Renderer};

use super::measure::{error, run, time};
use super::scene::{albedo, camera, gbuffer};
use super::{Effect, PostArgs, Row};

pub(super) fn measure(
    renderer: &Renderer,
    args: &PostArgs,
    truth: &ImageF32,
    layer: &Arc<Layer>,
    rows: &mut Vec<Row>,
) -> anyhow::Result<()> {
    let g = gbuffer(renderer, layer.clone(), camera(args.error_size), None);
    let (_, aliased) = run(
        renderer,
        g.as_ref(),
        &g.targets.color,
        args.error_size,
        true,
    )?;
    let (rmse, ssim) = error(&aliased.context("image")?, truth);
    rows.push(Row {
        effect: Effect::Fxaa,
        setting: "off (one sample)".to_owned(),
        ms: Some(0.0),
        rmse,
        ssim,
    });
    for (name, quality) in [
        ("Low", FxaaQuality::Low),
        ("Medium", FxaaQuality::Medium),
        ("High", FxaaQuality::High),
    ] {
        eprintln!("FXAA {name}");
        let g = gbuffer(renderer, layer.clone(), camera(args.error_size), None);
        let fxaa = Fxaa::new(renderer, None, albedo(&g), quality, 0.75);
        let (_, image) = run(renderer, fxaa.as_ref(), &fxaa.output, args.error_size, true)?;
        let (rmse, ssim) = error(&image.context("image")?, truth);
        let timed = camera(args.common.time_size);
        let ms = time(renderer, args, "FXAA", |_| {
            let g = gbuffer(renderer, layer.clone(), timed, None);
            let fxaa = Fxaa::new(renderer, None, albedo(&g), quality, 0.75);
            let name = fxaa.output.clone();
            Ok((fxaa as Arc<dyn Recipe>, name))
        })?;
        rows.push(Row {
            effect: Effect::Fxaa,
            setting: name.to_owned(),
            ms,
            rmse,
            ssim,
        });
    }
    Ok(())
}
