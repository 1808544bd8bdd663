//! Tonemapping on the GPU, for the stability suite: an all-black frame and a
//! frame of 1e6 (and NaN, infinity, negatives) through every operator give
//! finite values in 0..1, and the GPU agrees with the CPU reference; a
//! source of another size than the frame's is tonemapped whole, at its size.

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

/// A 64x36 texture tonemapped in a 96x54 frame: the output is 64x36 and
/// every texel is the CPU reference's of its source texel (before image
/// effects took their source's size, the output was 96x54 with the texture
/// in its top-left corner and black past it).
#[test]
fn a_source_of_another_size_is_tonemapped_whole_at_its_size() {
    let renderer = test_renderer();
    let (w, h) = (64u32, 36u32);
    let pixels: Vec<[f32; 4]> = (0..w * h)
        .map(|i| {
            let (x, y) = ((i % w) as f32, (i / w) as f32);
            [0.1 + x / 16.0, 0.1 + y / 9.0, 0.5, 1.0]
        })
        .collect();
    let source = StaticTexture::from_rgba32f(&renderer.gpu, w, h, &pixels, "small");
    let op = TonemapOperator::Reinhard;
    let t = Tonemap::new(&renderer, None, source.texture_ref(), op, 1.0, 4.0);
    let (report, images) =
        render_and_read(&renderer, t.as_ref(), (96, 54), &[&t.output]).expect("executes");
    assert!(report.errors.is_empty(), "{:?}", report.errors);
    let image = &images[0];
    assert_eq!((image.width, image.height), (w, h));
    for (i, (p, q)) in pixels.iter().zip(&image.pixels).enumerate() {
        let want = tonemap(Vec3::new(p[0], p[1], p[2]), op, 1.0, 4.0);
        let got = Vec3::new(q[0], q[1], q[2]);
        assert!(
            (want - got).abs().max_element() < 2e-3,
            "texel ({}, {}): GPU {got} vs CPU {want}",
            i as u32 % w,
            i as u32 / w
        );
    }
}
