//! FXAA smooths a hard, aliased edge and leaves flat areas exactly alone, at
//! every quality; HDR extremes stay finite.

use spreadlight_render::post::{Fxaa, FxaaQuality};
use spreadlight_render::readback::{ImageF32, render_and_read};
use spreadlight_render::renderer::test_renderer;
use spreadlight_render::static_texture::StaticTexture;

const N: u32 = 32;

fn fxaa(pixels: &[[f32; 4]], quality: FxaaQuality) -> ImageF32 {
    let renderer = test_renderer();
    let input = StaticTexture::from_rgba32f(&renderer.gpu, N, N, pixels, "aliased");
    let pass = Fxaa::new(&renderer, None, input.texture_ref(), quality, 0.75);
    let (report, images) =
        render_and_read(&renderer, pass.as_ref(), (N, N), &[&pass.output]).expect("renders");
    assert!(report.errors.is_empty(), "{:?}", report.errors);
    images.into_iter().next().expect("one image")
}

/// White above a shallow line (one pixel up every four across), black below: a staircase.
fn staircase() -> Vec<[f32; 4]> {
    (0..N * N)
        .map(|i| {
            let (x, y) = (i % N, i / N);
            if y * 4 < x + 40 {
                [1.0, 1.0, 1.0, 1.0]
            } else {
                [0.0, 0.0, 0.0, 1.0]
            }
        })
        .collect()
}

fn grey(p: &[f32; 4]) -> bool {
    p[0] > 0.05 && p[0] < 0.95
}

#[test]
fn a_staircase_edge_gets_smoothed_and_flat_areas_stay_exact() {
    let input = staircase();
    for quality in [FxaaQuality::Low, FxaaQuality::Medium, FxaaQuality::High] {
        let out = fxaa(&input, quality);
        assert!(out.all_finite());
        let smoothed = out.pixels.iter().filter(|p| grey(p)).count();
        assert!(
            smoothed >= 16,
            "{quality:?}: {smoothed} edge pixels blended"
        );
        for (i, (a, b)) in input.iter().zip(&out.pixels).enumerate() {
            let (x, y) = (i as u32 % N, i as u32 / N);
            // Two pixels or more from the edge: untouched.
            let distance = (y as i32 * 4 - (x as i32 + 40)).abs();
            if distance > 8 {
                assert_eq!(
                    a[..3],
                    b[..3],
                    "{quality:?}: pixel ({x}, {y}) is flat and must not change"
                );
            }
            assert!(
                (0.0..=1.0).contains(&b[0]),
                "{quality:?}: ({x}, {y}) = {b:?}"
            );
        }
    }
}

#[test]
fn hdr_extremes_stay_finite() {
    let zeros = vec![[0.0, 0.0, 0.0, 1.0]; (N * N) as usize];
    let out = fxaa(&zeros, FxaaQuality::High);
    assert!(out.pixels.iter().all(|p| p[..3] == [0.0, 0.0, 0.0]));
    let bright: Vec<[f32; 4]> = staircase()
        .iter()
        .map(|p| [p[0] * 1e6, p[1] * 1e6, p[2] * 1e6, 1.0])
        .collect();
    let out = fxaa(&bright, FxaaQuality::High);
    assert!(out.all_finite() && out.pixels.iter().all(|p| p[0] <= 65000.0 && p[0] >= 0.0));
}
