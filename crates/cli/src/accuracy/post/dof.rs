//! DOF's rows: every sample count at every `--resolutions`, against the
//! average of `--views` views from points spread over the lens's aperture,
//! each re-aimed at the focus plane (the thin lens, exactly, in the limit).

use std::sync::Arc;

use anyhow::Context;
use glam::{Mat4, Vec2, Vec3};
use spreadlight_render::camera::{CameraInput, jittered};
use spreadlight_render::post::{Dof, DofSettings, Focus};
use spreadlight_render::resolution::Resolution;
use spreadlight_render::{Recipe, Renderer};

use super::measure::{error, run, time};
use super::scene::{albedo, camera, gbuffer, scene};
use super::{Effect, HALF_SUFFIX, PostArgs, Row};
use crate::sequence::accumulate::Average;

/// The lens of the DOF measurement, focused on the middle ball: a long lens
/// wide open, so the blur is several pixels even at the small error size.
pub(super) const FOCAL_MM: f32 = 300.0;
pub(super) const F_STOP: f32 = 1.4;
pub(super) const FOCUS: f32 = 7.0;

/// Points spread evenly over the unit disk (a golden-angle spiral).
fn disk(n: u32) -> Vec<Vec2> {
    (0..n)
        .map(|i| {
            let r = ((i as f32 + 0.5) / n as f32).sqrt();
            let a = i as f32 * 2.399_963;
            Vec2::new(a.cos(), a.sin()) * r
        })
        .collect()
}

fn dof_settings(samples: u32, resolution: Resolution) -> DofSettings {
    DofSettings {
        focal_length_mm: FOCAL_MM,
        f_stop: F_STOP,
        samples,
        max_radius: 32.0,
        resolution,
    }
}

pub(super) fn measure(
    renderer: &Renderer,
    args: &PostArgs,
    rows: &mut Vec<Row>,
) -> anyhow::Result<()> {
    let size = args.error_size;
    let layer = scene(renderer, 0.0, false)?;
    let base = camera(size);
    let aperture = dof_settings(1, Resolution::Full).aperture();
    eprintln!(
        "DOF reference: {} views over a {aperture:.4} aperture ...",
        args.views
    );
    let mut average = Average::new((size.0 * size.1) as usize);
    let (p00, p11) = (base.projection.x_axis.x, base.projection.y_axis.y);
    for lens in disk(args.views) {
        let d = lens * aperture / 2.0;
        // Moved across the lens and re-aimed so the focus plane projects where it did.
        let cam = CameraInput {
            view: Mat4::from_translation(Vec3::new(-d.x, -d.y, 0.0)) * base.view,
            projection: jittered(
                base.projection,
                Vec2::new(p00 * d.x / FOCUS, p11 * d.y / FOCUS),
            ),
        };
        let g = gbuffer(renderer, layer.clone(), cam, None);
        let (_, image) = run(renderer, g.as_ref(), &g.targets.color, size, true)?;
        average.add(&image.context("image")?);
    }
    let truth = average.image(size);
    let settings = [8, 16, 32, 64]
        .into_iter()
        .flat_map(|s| args.resolutions.iter().map(move |r| (s, *r)));
    for (samples, resolution) in settings {
        eprintln!("DOF {samples} samples {resolution}");
        // The same DOF over the scene seen by `camera`: measured, then timed.
        let dof_of = |camera| {
            let g = gbuffer(renderer, layer.clone(), camera, None);
            Dof::new(
                renderer,
                None,
                albedo(&g),
                g,
                Focus::Distance(FOCUS),
                None,
                dof_settings(samples, resolution),
            )
        };
        let dof = dof_of(base);
        let (_, image) = run(renderer, dof.as_ref(), &dof.output, size, true)?;
        let (rmse, ssim) = error(&image.context("image")?, &truth);
        let timed = camera(args.common.time_size);
        let ms = time(renderer, args, "DOF", |_| {
            let dof = dof_of(timed);
            let name = dof.output.clone();
            Ok((dof as Arc<dyn Recipe>, name))
        })?;
        rows.push(Row {
            effect: Effect::Dof,
            setting: format!(
                "{samples} samples{}",
                if resolution.is_half() {
                    HALF_SUFFIX
                } else {
                    ""
                }
            ),
            ms,
            rmse,
            ssim,
        });
    }
    Ok(())
}
