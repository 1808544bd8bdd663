//! TAA's rows: each quality after `--taa-frames` jittered frames of the
//! still scene, against the frame rendered 8x8 larger and box-downsampled
//! (measure.rs's `supersampled`).

use std::sync::Arc;

use anyhow::Context;
use glam::{Mat4, Vec2};
use spreadlight_render::camera::{CameraInput, jitter_ndc, jittered};
use spreadlight_render::gbuffer::Layer;
use spreadlight_render::post::{Taa, TaaQuality, TaaSettings};
use spreadlight_render::readback::ImageF32;
use spreadlight_render::{Recipe, Renderer};

use super::measure::{error, run, time};
use super::scene::{albedo, camera, gbuffer};
use super::{Effect, PostArgs, Row};

/// Frame `n` of TAA on the still scene with a jittered camera, for a target of `size`.
struct TaaRun {
    history: String,
    previous: Option<(Mat4, Vec2)>,
}

impl TaaRun {
    fn frame(
        &mut self,
        renderer: &Renderer,
        layer: &Arc<Layer>,
        n: u64,
        size: (u32, u32),
        quality: TaaQuality,
    ) -> Arc<Taa> {
        let jitter = jitter_ndc(n, size);
        let base = camera(size);
        let cam = CameraInput {
            projection: jittered(base.projection, jitter),
            ..base
        };
        let g = gbuffer(renderer, layer.clone(), cam, self.previous.map(|p| p.0));
        let settings = TaaSettings {
            quality,
            jitter,
            previous_jitter: self.previous.map_or(jitter, |p| p.1),
            ..Default::default()
        };
        self.previous = Some((cam.view_projection(), jitter));
        Taa::new(
            renderer,
            None,
            albedo(&g),
            g,
            settings,
            Some(self.history.clone()),
        )
    }
}

pub(super) fn measure(
    renderer: &Renderer,
    args: &PostArgs,
    truth: &ImageF32,
    layer: &Arc<Layer>,
    rows: &mut Vec<Row>,
) -> anyhow::Result<()> {
    for (name, quality) in [
        ("Low", TaaQuality::Low),
        ("Medium", TaaQuality::Medium),
        ("High", TaaQuality::High),
    ] {
        eprintln!("TAA {name}");
        let mut taa = TaaRun {
            history: format!("accuracy taa {name}"),
            previous: None,
        };
        let mut last = None;
        for n in 0..args.taa_frames.max(1) {
            let t = taa.frame(renderer, layer, n, args.error_size, quality);
            let read = n + 1 == args.taa_frames.max(1);
            last = run(renderer, t.as_ref(), &t.output, args.error_size, read)?.1;
        }
        let (rmse, ssim) = error(&last.context("image")?, truth);
        let mut timed = TaaRun {
            history: format!("accuracy taa time {name}"),
            previous: None,
        };
        let ms = time(renderer, args, "TAA", |n| {
            let t = timed.frame(renderer, layer, n, args.common.time_size, quality);
            let name = t.output.clone();
            Ok((t as Arc<dyn Recipe>, name))
        })?;
        rows.push(Row {
            effect: Effect::Taa,
            setting: format!("{name}, {} frames", args.taa_frames),
            ms,
            rmse,
            ssim,
        });
    }
    Ok(())
}
