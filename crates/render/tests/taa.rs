//! TAA over a jittered camera converges on a still scene towards the
//! supersampled image (rendered 8x8 larger and box-downsampled), much
//! closer than one aliased frame; a cut, a resize and a fresh target reset
//! the history (counted); a NaN held in the history never reaches the image.

use crate::post_common;

use std::sync::Arc;

use glam::{Mat4, Vec3};
use post_common::*;
use spreadlight_render::camera::{CameraInput, jitter_ndc, jittered};
use spreadlight_render::gbuffer::GBuffer;
use spreadlight_render::post::taa::RESET;
use spreadlight_render::post::{Taa, TaaQuality, TaaSettings};
use spreadlight_render::readback::{ImageF32, read_texture};
use spreadlight_render::recipe::Recipe;
use spreadlight_render::renderer::test_renderer;
use spreadlight_render::{FrameGraph, Renderer, TextureRef};

const SIZE: (u32, u32) = (32, 32);

fn camera() -> CameraInput {
    look(
        Vec3::new(0.0, 0.0, 8.0),
        Vec3::new(0.1, 0.05, 0.0),
        0.3,
        1.0,
    )
}

fn scene(renderer: &Renderer, camera: CameraInput, previous: Option<Mat4>) -> Arc<GBuffer> {
    let layer = balls(renderer, &[Ball::still(Vec3::ZERO, 0.5)]);
    gbuffer(renderer, layer, camera, previous)
}

fn albedo(g: &Arc<GBuffer>) -> TextureRef {
    TextureRef {
        recipe: g.clone(),
        name: g.targets.color.clone(),
    }
}

/// The G-buffer's albedo 8x8 larger, averaged down: the 64-sample reference.
fn supersampled(renderer: &Renderer) -> Vec<f32> {
    let g = scene(renderer, camera(), None);
    let big = (SIZE.0 * 8, SIZE.1 * 8);
    let (_, image) = render(renderer, g.as_ref(), &g.targets.color, big);
    let mut out = vec![0.0; (SIZE.0 * SIZE.1) as usize];
    for (i, p) in image.pixels.iter().enumerate() {
        let (x, y) = (i as u32 % big.0 / 8, i as u32 / big.0 / 8);
        out[(y * SIZE.0 + x) as usize] += p[0] / 64.0;
    }
    out
}

fn rmse(a: &ImageF32, b: &[f32]) -> f32 {
    let sum: f32 = a
        .pixels
        .iter()
        .zip(b)
        .map(|(p, r)| (p[0] - r).powi(2))
        .sum();
    (sum / b.len() as f32).sqrt()
}

/// Frame `n` of a still scene through a jittered camera, through TAA.
struct Run {
    renderer: Arc<Renderer>,
    history: String,
    previous: Option<(Mat4, glam::Vec2)>,
}

impl Run {
    fn new(history: &str) -> Self {
        Run {
            renderer: test_renderer(),
            history: history.to_owned(),
            previous: None,
        }
    }

    fn frame(
        &mut self,
        n: u64,
        size: (u32, u32),
        quality: TaaQuality,
        reset: bool,
    ) -> (ImageF32, u64) {
        self.frame_then(n, size, quality, reset, false)
    }

    /// A frame; with `poison`, the history is filled with NaN afterwards, behind the pass's back.
    fn frame_then(
        &mut self,
        n: u64,
        size: (u32, u32),
        quality: TaaQuality,
        reset: bool,
        poison: bool,
    ) -> (ImageF32, u64) {
        let jitter = jitter_ndc(n, size);
        let base = camera();
        let cam = CameraInput {
            projection: jittered(base.projection, jitter),
            ..base
        };
        let g = scene(&self.renderer, cam, self.previous.map(|p| p.0));
        let settings = TaaSettings {
            quality,
            jitter,
            previous_jitter: self.previous.map_or(jitter, |p| p.1),
            reset,
            ..Default::default()
        };
        self.previous = Some((cam.view_projection(), jitter));
        let taa = Taa::new(
            &self.renderer,
            None,
            albedo(&g),
            g,
            settings,
            Some(self.history.clone()),
        );
        let mut graph = FrameGraph::new(size);
        taa.declare(&self.renderer, &mut graph);
        graph.request(&taa.output);
        graph.request(&taa.history);
        let (report, outputs) = graph.execute(&self.renderer).expect("renders");
        assert!(report.errors.is_empty(), "{:?}", report.errors);
        let image = read_texture(&self.renderer.gpu, &outputs[&taa.output]).expect("reads");
        assert!(image.all_finite());
        if poison {
            // Half-float NaN is 0x7E00.
            let nan = vec![0x7E00u16; (size.0 * size.1 * 4) as usize];
            self.renderer.gpu.queue.write_texture(
                outputs[&taa.history].as_image_copy(),
                bytemuck::cast_slice(&nan),
                wgpu::TexelCopyBufferLayout {
                    offset: 0,
                    bytes_per_row: Some(size.0 * 8),
                    rows_per_image: Some(size.1),
                },
                wgpu::Extent3d {
                    width: size.0,
                    height: size.1,
                    depth_or_array_layers: 1,
                },
            );
            let poisoned = read_texture(&self.renderer.gpu, &outputs[&taa.history]).expect("reads");
            assert!(
                poisoned.pixels.iter().all(|p| p[0].is_nan()),
                "the history holds NaN"
            );
        }
        (image, report.counter(RESET))
    }
}

#[test]
fn a_still_scene_converges_towards_the_supersampled_image() {
    let renderer = test_renderer();
    let reference = supersampled(&renderer);
    let g = scene(&renderer, camera(), None);
    let (_, aliased) = render(&renderer, g.as_ref(), &g.targets.color, SIZE);
    let aliased_error = rmse(&aliased, &reference);
    for quality in [TaaQuality::Low, TaaQuality::Medium, TaaQuality::High] {
        let mut run = Run::new(&format!("taa converge {quality:?}"));
        let mut last = None;
        for n in 0..32 {
            let (image, resets) = run.frame(n, SIZE, quality, false);
            assert_eq!(resets, u64::from(n == 0), "{quality:?} frame {n}");
            last = Some(image);
        }
        let error = rmse(&last.expect("frames"), &reference);
        assert!(
            error < 0.7 * aliased_error,
            "{quality:?}: TAA {error} vs one aliased frame {aliased_error}"
        );
    }
}

#[test]
fn a_cut_and_a_resize_reset_the_history() {
    let mut run = Run::new("taa cut");
    for n in 0..4 {
        run.frame(n, SIZE, TaaQuality::High, false);
    }
    let (cut, resets) = run.frame(4, SIZE, TaaQuality::High, true);
    assert_eq!(resets, 1);
    // After a cut the output is this frame as it is.
    let g = scene(
        &run.renderer,
        CameraInput {
            projection: jittered(camera().projection, jitter_ndc(4, SIZE)),
            ..camera()
        },
        None,
    );
    let (_, current) = render(&run.renderer, g.as_ref(), &g.targets.color, SIZE);
    for (a, b) in cut.pixels.iter().zip(&current.pixels) {
        assert!((a[0] - b[0]).abs() < 1e-3, "{a:?} vs {b:?}");
    }
    let (_, resets) = run.frame(5, SIZE, TaaQuality::High, false);
    assert_eq!(resets, 0);
    let (_, resets) = run.frame(6, (40, 24), TaaQuality::High, false);
    assert_eq!(resets, 1, "a new size is a new history");
}

#[test]
fn a_nan_in_the_history_does_not_spread() {
    let mut run = Run::new("taa nan");
    run.frame_then(0, SIZE, TaaQuality::High, false, true);
    for n in 1..4 {
        let (image, resets) = run.frame(n, SIZE, TaaQuality::High, false);
        assert_eq!(resets, 0, "the NaN is sanitized, not a reset");
        let (lo, hi) = range(&image);
        assert!(lo >= 0.0 && hi <= 1.0, "frame {n}: {lo}..{hi}");
    }
}
