//! Tonemapping on the GPU, for the stability suite: an all-black frame and a
//! frame of 1e6 (and NaN, infinity, negatives) through every operator give
//! finite values in 0..1, and the GPU agrees with the CPU reference.

use glam::Vec3;
use spreadlight_reference::tonemap::{TonemapOperator, tonemap};
use spreadlight_render::post::Tonemap;
use spreadlight_render::readback::render_and_read;
use spreadlight_render::renderer::test_renderer;
use spreadlight_render::static_texture::StaticTexture;

#[test]
fn every_operator_keeps_extreme_frames_finite_and_matches_the_reference() {
    let renderer = test_renderer();
    // One row: black, mid grey, bright, 1e6, and the values a user's maths can produce.
    let row: [[f32; 4]; 8] = [
        [0.0, 0.0, 0.0, 1.0],
        [0.18, 0.18, 0.18, 1.0],
        [4.0, 2.0, 1.0, 1.0],
        [1e6, 1e6, 1e6, 1.0],
        [f32::NAN, 0.5, 0.5, 1.0],
        [f32::INFINITY, 1.0, 1.0, 1.0],
        [-1.0, 0.5, 0.5, 1.0],
        [1e6, 0.0, 0.0, 1.0],
    ];
    let source = StaticTexture::from_rgba32f(&renderer.gpu, 8, 1, &row, "extremes");
    for op in TonemapOperator::ALL {
        let name = op.name();
        let t = Tonemap::new(&renderer, None, source.texture_ref(), op, 1.0, 4.0);
        let (report, images) =
            render_and_read(&renderer, t.as_ref(), (8, 1), &[&t.output]).expect("executes");
        assert!(report.errors.is_empty(), "{name}: {:?}", report.errors);
        let image = images.into_iter().next().expect("one image");
        for (i, p) in image.pixels.iter().enumerate() {
            assert!(
                p.iter()
                    .all(|c| c.is_finite() && (0.0..=1.0 + 1e-3).contains(c)),
                "{name}, pixel {i}: {p:?}"
            );
        }
        assert_eq!(
            &image.pixels[0][..3],
            &[0.0, 0.0, 0.0],
            "{name}: black stays black (log of 0 guarded)"
        );
        // The finite, non-negative inputs agree with the CPU reference (half-float output: 2e-3).
        for i in [1usize, 2, 3, 7] {
            let c = Vec3::new(row[i][0], row[i][1], row[i][2]);
            let want = tonemap(c, op, 1.0, 4.0);
            let got = Vec3::new(image.pixels[i][0], image.pixels[i][1], image.pixels[i][2]);
            assert!(
                (want - got).abs().max_element() < 2e-3,
                "{name}, pixel {i}: GPU {got} vs CPU {want}"
            );
        }
    }
}
