//! How every post effect is measured: a recipe run and read back, the error
//! of an image against its reference (RMSE and SSIM over RGB), the median GPU
//! time of the effect's passes, and the supersampled reference TAA and FXAA
//! share. Apart from the scene (scene.rs) because it knows nothing of what
//! is drawn, and from the effects because they all use it the same way.

use std::sync::Arc;

use anyhow::Context;
use spreadlight_render::gbuffer::Layer;
use spreadlight_render::readback::{ImageF32, read_texture};
use spreadlight_render::{FrameGraph, Recipe, Renderer};

use super::PostArgs;
use super::scene::{camera, gbuffer};
use crate::accuracy::metrics::{self, Plane};
use crate::accuracy::{median, pass_ms};
use crate::sequence::accumulate::Average;

/// Run `recipe` at `size`; read `name` back when `read`. Returns the report and the image.
pub(super) fn run(
    renderer: &Renderer,
    recipe: &dyn Recipe,
    name: &str,
    size: (u32, u32),
    read: bool,
) -> anyhow::Result<(spreadlight_render::FrameReport, Option<ImageF32>)> {
    let mut graph = FrameGraph::new(size);
    recipe.declare(renderer, &mut graph);
    graph.request(name);
    let (report, outputs) = graph.execute(renderer)?;
    if let Some((_, e)) = report.errors.first() {
        anyhow::bail!("the frame failed: {e}");
    }
    let image = if read {
        Some(read_texture(
            &renderer.gpu,
            outputs.get(name).context("no output")?,
        )?)
    } else {
        None
    };
    Ok((report, image))
}

pub(super) fn error(approx: &ImageF32, truth: &ImageF32) -> (f64, f64) {
    let channel =
        |image: &ImageF32, c: usize| -> Vec<f32> { image.pixels.iter().map(|p| p[c]).collect() };
    let (a, t): (Vec<Vec<f32>>, Vec<Vec<f32>>) = (
        (0..3).map(|c| channel(approx, c)).collect(),
        (0..3).map(|c| channel(truth, c)).collect(),
    );
    let size = (truth.width, truth.height);
    let (approx, truth) = (
        Plane::channels(&a, None, size),
        Plane::channels(&t, None, size),
    );
    let e = metrics::Error::of(&approx, &truth);
    (e.rmse, e.ssim)
}

/// Median GPU time of the passes of kind `what` over frames made by `make`.
pub(super) fn time(
    renderer: &Renderer,
    args: &PostArgs,
    what: &str,
    mut make: impl FnMut(u64) -> anyhow::Result<(Arc<dyn Recipe>, String)>,
) -> anyhow::Result<Option<f64>> {
    let mut times = Vec::new();
    for i in 0..(args.common.warmup + args.common.frames.max(1)) {
        let (recipe, name) = make(i as u64)?;
        let (report, _) = run(
            renderer,
            recipe.as_ref(),
            &name,
            args.common.time_size,
            false,
        )?;
        if i >= args.common.warmup {
            times.extend(pass_ms(&report, what, None));
        }
    }
    Ok(median(times))
}

/// The still scene's albedo 8x8 larger, box-downsampled: 64 samples a pixel.
pub(super) fn supersampled(
    renderer: &Renderer,
    layer: &Arc<Layer>,
    size: (u32, u32),
) -> anyhow::Result<ImageF32> {
    let big = (size.0 * 8, size.1 * 8);
    let g = gbuffer(renderer, layer.clone(), camera(size), None);
    let (_, image) = run(renderer, g.as_ref(), &g.targets.color, big, true)?;
    let mut average = Average::new((size.0 * size.1) as usize);
    average.add_downsampled(&image.context("image")?, 8);
    Ok(average.image(size))
}
