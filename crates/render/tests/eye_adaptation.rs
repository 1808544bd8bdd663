//! Eye adaptation on the GPU: a fresh frame measures the image's geometric
//! mean luminance, later frames move towards a new one by the exponential
//! step, the pins hold for black and 1e6 frames, non-finite pixels are left
//! out, and tonemapping with the adapted exposure stays finite in 0..1.

use spreadlight_reference::tonemap::TonemapOperator;
use spreadlight_render::TextureRef;
use spreadlight_render::post::{AdaptationSettings, AdaptedExposure, EyeAdaptation, Tonemap};
use spreadlight_render::readback::render_and_read;
use spreadlight_render::renderer::{Renderer, test_renderer};
use spreadlight_render::static_texture::StaticTexture;

const SETTINGS: AdaptationSettings = AdaptationSettings {
    speed_up: 3.0,
    speed_down: 1.0,
    min_luminance: 0.01,
    max_luminance: 1000.0,
};

fn source(renderer: &Renderer, width: u32, height: u32, pixels: &[[f32; 4]]) -> TextureRef {
    StaticTexture::from_rgba32f(&renderer.gpu, width, height, pixels, "hdr").texture_ref()
}

fn grey(l: f32) -> [f32; 4] {
    [l, l, l, 1.0]
}

/// One frame, as the node makes it: a new recipe with the frame's delta. Returns the adapted luminance.
fn frame(
    renderer: &Renderer,
    source: &TextureRef,
    output_size: (u32, u32),
    settings: AdaptationSettings,
    delta: f64,
) -> f32 {
    let adaptation = EyeAdaptation::new(renderer, None, source.clone(), settings, delta);
    let (report, images) = render_and_read(
        renderer,
        adaptation.as_ref(),
        output_size,
        &[&adaptation.output],
    )
    .expect("executes");
    assert!(report.errors.is_empty(), "{:?}", report.errors);
    let image = images.into_iter().next().expect("one image");
    assert_eq!((image.width, image.height), (1, 1));
    let l = image.pixels[0][0];
    assert!(l.is_finite(), "adapted luminance {l}");
    l
}

fn uniform(renderer: &Renderer, l: f32) -> TextureRef {
    source(renderer, 16, 9, &vec![grey(l); 16 * 9])
}

fn close(got: f32, want: f32, tolerance: f32) -> bool {
    (got - want).abs() <= tolerance * want.abs()
}

#[test]
fn a_fresh_frame_measures_the_geometric_mean() {
    let renderer = test_renderer();
    // Uniform: the luminance itself, within 1%.
    for l in [0.05f32, 0.5, 1.0, 20.0] {
        let renderer = test_renderer();
        let got = frame(&renderer, &uniform(&renderer, l), (16, 9), SETTINGS, 0.0);
        assert!(close(got, l, 0.01), "uniform {l}: adapted {got}");
    }
    // Odd sizes, two levels in a checkerboard, a coloured pixel: exp of the mean log-luminance,
    // whatever the output size is (smaller, equal, larger than the image).
    let (w, h) = (37u32, 23u32);
    let mut pixels = Vec::new();
    for y in 0..h {
        for x in 0..w {
            pixels.push(if (x + y) % 2 == 0 {
                grey(0.1)
            } else {
                grey(4.0)
            });
        }
    }
    pixels[5] = [2.0, 1.0, 0.5, 1.0];
    let mean_log = pixels
        .iter()
        .map(|p| f64::from(0.2126 * p[0] + 0.7152 * p[1] + 0.0722 * p[2]).ln())
        .sum::<f64>()
        / pixels.len() as f64;
    let want = mean_log.exp() as f32;
    let hdr = source(&renderer, w, h, &pixels);
    for (i, size) in [(w, h), (8, 8), (640, 360), (1, 1)].into_iter().enumerate() {
        let history = format!("history {i}");
        let adaptation =
            EyeAdaptation::with_history(&renderer, None, hdr.clone(), SETTINGS, 0.0, history);
        let (report, images) =
            render_and_read(&renderer, adaptation.as_ref(), size, &[&adaptation.output])
                .expect("executes");
        assert!(report.errors.is_empty(), "{:?}", report.errors);
        let got = images.into_iter().next().expect("one image").pixels[0][0];
        assert!(
            close(got, want, 0.01),
            "output {size:?}: adapted {got}, want {want}"
        );
    }
}

#[test]
fn later_frames_take_the_exponential_step_and_converge() {
    let renderer = test_renderer();
    let delta = 1.0 / 60.0;
    let (dark, bright) = (uniform(&renderer, 0.2), uniform(&renderer, 3.2));
    let first = frame(&renderer, &dark, (16, 9), SETTINGS, delta);
    assert!(close(first, 0.2, 0.01), "fresh: {first}");

    // Brighter: in log space, 1 - exp(-dt * speed up) of the way.
    let step = frame(&renderer, &bright, (16, 9), SETTINGS, delta);
    let rate = 1.0 - (-delta * f64::from(SETTINGS.speed_up)).exp();
    let want = (f64::from(first).ln() + (3.2f64.ln() - f64::from(first).ln()) * rate).exp() as f32;
    assert!(close(step, want, 1e-3), "up: {step}, want {want}");
    assert!(close(SETTINGS.step(Some(first), 3.2, delta), want, 1e-5));
    assert!(step > first && step < 3.2);

    // Darker, at the other speed.
    let down = frame(&renderer, &dark, (16, 9), SETTINGS, delta);
    let rate = 1.0 - (-delta * f64::from(SETTINGS.speed_down)).exp();
    let want = (f64::from(step).ln() + (0.2f64.ln() - f64::from(step).ln()) * rate).exp() as f32;
    assert!(close(down, want, 1e-3), "down: {down}, want {want}");

    // A zero delta holds; many frames converge.
    let held = frame(&renderer, &bright, (16, 9), SETTINGS, 0.0);
    assert!(close(held, down, 1e-4), "held: {held} vs {down}");
    let mut l = held;
    for _ in 0..300 {
        l = frame(&renderer, &bright, (16, 9), SETTINGS, delta);
    }
    assert!(close(l, 3.2, 0.01), "converged to {l}");

    // A cut (history reset) takes the measurement again.
    renderer.reset_history();
    let cut = frame(&renderer, &dark, (16, 9), SETTINGS, delta);
    assert!(close(cut, 0.2, 0.01), "after a cut: {cut}");
}

#[test]
fn the_pins_hold_and_non_finite_pixels_are_left_out() {
    // All black: the minimum, never 0.
    let renderer = test_renderer();
    let black = frame(&renderer, &uniform(&renderer, 0.0), (16, 9), SETTINGS, 0.0);
    assert!(close(black, SETTINGS.min_luminance, 1e-3), "black: {black}");
    // 1e6: the maximum, never infinity; and it stays pinned over time.
    let renderer = test_renderer();
    let huge = uniform(&renderer, 1e6);
    for delta in [0.0, 1.0 / 60.0, 10.0] {
        let l = frame(&renderer, &huge, (16, 9), SETTINGS, delta);
        assert!(close(l, SETTINGS.max_luminance, 1e-3), "1e6: {l}");
    }
    // NaN, infinities and negatives among grey pixels: the grey (negatives count as black).
    let renderer = test_renderer();
    let mut pixels = vec![grey(0.5); 16 * 9];
    pixels[0] = [f32::NAN, 0.5, 0.5, 1.0];
    pixels[17] = grey(f32::INFINITY);
    pixels[40] = [f32::NEG_INFINITY, f32::NAN, 1.0, 1.0];
    pixels[100] = grey(f32::NAN);
    let l = frame(
        &renderer,
        &source(&renderer, 16, 9, &pixels),
        (16, 9),
        SETTINGS,
        0.0,
    );
    assert!(close(l, 0.5, 0.01), "with non-finite pixels: {l}");
    // Only non-finite pixels: nothing to measure, so the minimum.
    let renderer = test_renderer();
    let nan = source(&renderer, 4, 4, &[grey(f32::NAN); 16]);
    let l = frame(&renderer, &nan, (4, 4), SETTINGS, 0.0);
    assert!(close(l, SETTINGS.min_luminance, 1e-3), "all NaN: {l}");
    // Nonsense settings still give a finite, positive luminance.
    let renderer = test_renderer();
    let broken = AdaptationSettings {
        speed_up: f32::NAN,
        speed_down: -1.0,
        min_luminance: 0.0,
        max_luminance: f32::INFINITY,
    };
    for delta in [0.0, f64::NAN, f64::INFINITY, -1.0] {
        let l = frame(&renderer, &uniform(&renderer, 0.0), (16, 9), broken, delta);
        assert!(l > 0.0 && l.is_finite(), "broken settings: {l}");
    }
}

#[test]
fn tonemapping_with_adapted_exposure_stays_finite_and_maps_to_the_key() {
    let renderer = test_renderer();
    // A uniform frame of 5 through Linear: adapted to 5, so 5 * 0.18 / 5 = the key.
    let hdr = uniform(&renderer, 5.0);
    let adaptation = EyeAdaptation::new(&renderer, None, hdr.clone(), SETTINGS, 0.0);
    let t = Tonemap::with_adaptation(
        &renderer,
        None,
        hdr,
        TonemapOperator::Linear,
        1.0,
        4.0,
        Some(AdaptedExposure::new(adaptation.texture())),
    );
    let (report, images) =
        render_and_read(&renderer, t.as_ref(), (16, 9), &[&t.output]).expect("executes");
    assert!(report.errors.is_empty(), "{:?}", report.errors);
    let image = images.into_iter().next().expect("one image");
    for p in &image.pixels {
        assert!(close(p[0], 0.18, 0.01), "key: {p:?}");
    }

    // Extreme frames through every operator, adapted: finite, in 0..1.
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
    let frames = [row.to_vec(), vec![grey(0.0); 8], vec![grey(1e6); 8]];
    for pixels in frames {
        let renderer = test_renderer();
        let hdr = source(&renderer, 8, 1, &pixels);
        for op in TonemapOperator::ALL {
            let name = op.name();
            for delta in [0.0, 1.0 / 60.0] {
                let adaptation = EyeAdaptation::new(&renderer, None, hdr.clone(), SETTINGS, delta);
                let t = Tonemap::with_adaptation(
                    &renderer,
                    None,
                    hdr.clone(),
                    op,
                    1.0,
                    4.0,
                    Some(AdaptedExposure::new(adaptation.texture())),
                );
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
            }
        }
    }
}

#[test]
fn a_black_background_does_not_over_expose_the_rest() {
    // Half the image black (a sky with nothing in it), half at luminance 1:
    // black counts as the Minimum pin (0.01), so the geometric mean is 0.1,
    // not the 0.001 that counting black as 1e-6 would give.
    let renderer = test_renderer();
    let pixels: Vec<[f32; 4]> = (0..16 * 8)
        .map(|i| if i < 64 { grey(0.0) } else { grey(1.0) })
        .collect();
    let half = source(&renderer, 16, 8, &pixels);
    let l = frame(&renderer, &half, (16, 8), SETTINGS, 0.0);
    assert!(close(l, 0.1, 0.01), "adapted {l}");
}
