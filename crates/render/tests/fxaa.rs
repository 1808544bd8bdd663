//! FXAA smooths a hard, aliased edge and leaves flat areas exactly alone, at
//! every quality; HDR extremes stay finite. And every built-in image effect
//! (FXAA, Glare, the built-in blur, eye adaptation) keeps the size of a
//! source that is not the frame's (`FrameGraph::effect_size`).

use spreadlight_render::TextureRef;
use spreadlight_render::post::{AdaptationSettings, EyeAdaptation, Fxaa, FxaaQuality};
use spreadlight_render::post::{Glare, GlareSettings};
use spreadlight_render::readback::{ImageF32, render_and_read};
use spreadlight_render::renderer::test_renderer;
use spreadlight_render::shader_nodes::builtin_blur::BuiltinBlur;
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

/// A 64x36 image, not the frame's size: a gradient over a floor of 0.25 (no
/// texel black), an aliased diagonal edge for FXAA, a bright block for Glare.
fn small_source() -> (u32, u32, Vec<[f32; 4]>) {
    let (w, h) = (64u32, 36u32);
    let pixels = (0..w * h)
        .map(|i| {
            let (x, y) = (i % w, i / w);
            let bright = (40..48).contains(&x) && (10..18).contains(&y);
            let edge = if x < 2 * y { 0.5 } else { 0.0 };
            let r = 0.25 + x as f32 / w as f32 + if bright { 6.0 } else { 0.0 };
            [r, 0.25 + y as f32 / h as f32 + edge, 0.25 + edge, 1.0]
        })
        .collect();
    (w, h, pixels)
}

/// An image effect of another size than the frame's keeps its source's
/// size: rendered in a 96x54 frame, each built-in effect of the 64x36 source
/// makes a 64x36 image (the eye adaptation a 1x1 of the same luminance),
/// the same texel for texel as in a 64x36 frame, and none of it is black
/// (the effects read their source texel for texel: at the frame's size they
/// read past the source's corner).
#[test]
fn every_image_effect_keeps_the_size_of_a_source_that_is_not_the_frames() {
    let renderer = test_renderer();
    let (w, h, pixels) = small_source();
    let source = StaticTexture::from_rgba32f(&renderer.gpu, w, h, &pixels, "small source");
    let source = || source.texture_ref();
    // Each effect anew per frame size: the eye adaptation's history is its
    // node's (owner), so the two do not blend with each other.
    type Make<'a> = Box<dyn Fn(u32) -> TextureRef + 'a>;
    let effects: Vec<(&str, Make<'_>)> = vec![
        (
            "FXAA",
            Box::new(|_| Fxaa::new(&renderer, None, source(), FxaaQuality::High, 0.75).texture()),
        ),
        (
            "Glare",
            Box::new(|_| Glare::new(&renderer, None, source(), GlareSettings::default()).texture()),
        ),
        (
            "BlurBuiltin",
            // Its sampler filters: an RGBA16F source, FXAA's (a chain of two effects).
            Box::new(|_| {
                let fxaa = Fxaa::new(&renderer, None, source(), FxaaQuality::Low, 0.75);
                BuiltinBlur::new(None, fxaa.texture(), 4.0).texture()
            }),
        ),
        (
            "EyeAdaptation",
            Box::new(|owner| {
                let settings = AdaptationSettings::default();
                EyeAdaptation::new(&renderer, Some(owner), source(), settings, 1.0 / 60.0).texture()
            }),
        ),
    ];
    for (k, (name, make)) in effects.iter().enumerate() {
        let render = |frame: (u32, u32), owner: u32| {
            let texture = make(owner);
            let (report, images) =
                render_and_read(&renderer, texture.recipe.as_ref(), frame, &[&texture.name])
                    .expect("renders");
            assert!(report.errors.is_empty(), "{name}: {:?}", report.errors);
            images.into_iter().next().expect("one image")
        };
        let own = render((w, h), 1000 + 2 * k as u32);
        let other = render((96, 54), 1001 + 2 * k as u32);
        let size = if *name == "EyeAdaptation" {
            (1, 1)
        } else {
            (w, h)
        };
        assert_eq!(
            (other.width, other.height),
            size,
            "{name}: its source's size"
        );
        assert_eq!(
            own.pixels, other.pixels,
            "{name}: the frame's size changes nothing"
        );
        for (i, p) in other.pixels.iter().enumerate() {
            assert!(
                p[..3].iter().any(|c| *c > 0.05),
                "{name}: texel ({}, {}) is black: {p:?}",
                i as u32 % other.width,
                i as u32 / other.width
            );
        }
    }
    // FXAA leaves the flat texels as they are: the image, not a corner of it.
    let fxaa = Fxaa::new(&renderer, None, source(), FxaaQuality::High, 0.75);
    let (_, images) =
        render_and_read(&renderer, fxaa.as_ref(), (96, 54), &[&fxaa.output]).expect("renders");
    let (x, y) = (60, 4);
    let (want, got) = (pixels[(y * w + x) as usize], images[0].pixel(x, y));
    assert!(
        (0..3).all(|c| (want[c] - got[c]).abs() < 2e-3),
        "FXAA at ({x}, {y}): {got:?}, source {want:?}"
    );
}
