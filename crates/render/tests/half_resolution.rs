//! Resolution (render::resolution): at Half, SSAO/HBAO/SAO, SSGI, SSR and
//! DOF run their expensive pass for one pixel in four and upsample it with
//! depth awareness. Each stays within a stated RMSE of its Full image on a
//! ball over a floor, never writes NaN, and says in the frame report which
//! resolution ran; Full runs no half pass. The upsample itself does not
//! bleed across a silhouette: beside the ball every pixel keeps its own
//! side's value where a plain bilinear upsample would mix them.
//! (Full's images are those of before: tests/reference_images.rs.)

use std::sync::Arc;

use glam::{Vec3, Vec4};
use spreadlight_render::camera::{CameraInput, reverse_z};
use spreadlight_render::frame_graph::{FrameGraph, FrameReport, PassName, TextureDesc};
use spreadlight_render::gbuffer::GBuffer;
use spreadlight_render::lighting::{Ssgi, SsgiSettings};
use spreadlight_render::material::{Feature, Material, MaterialWorld};
use spreadlight_render::post::{Dof, DofSettings, Focus};
use spreadlight_render::readback::{ImageF32, render_and_read};
use spreadlight_render::renderer::test_renderer;
use spreadlight_render::resolution::{Resolution, UpsampleFormat, UpsamplePass, declare_upsample};
use spreadlight_render::scenes::{balls_on_floor, with_materials};
use spreadlight_render::ssao::{AmbientOcclusion, AoMode, AoSettings};
use spreadlight_render::static_texture::StaticTexture;
use spreadlight_render::{Recipe, Renderer, SizeRule};

/// Odd on purpose: the half grid's last row and column cover one pixel.
const SIZE: (u32, u32) = (97, 65);
const EYE: Vec3 = Vec3::new(0.0, 1.5, 4.0);
const BALL: (Vec3, f32) = (Vec3::new(0.0, 0.6, 0.0), 0.6);

fn camera() -> CameraInput {
    CameraInput {
        view: glam::camera::rh::view::look_at_mat4(EYE, Vec3::new(0.0, 0.3, 0.0), Vec3::Y),
        projection: glam::camera::rh::proj::directx::perspective(
            1.0,
            SIZE.0 as f32 / SIZE.1 as f32,
            0.1,
            100.0,
        ),
    }
}

/// The ball (material 0) over a floor (material 1).
fn gbuffer(renderer: &Renderer) -> Arc<GBuffer> {
    let layer = balls_on_floor(renderer, &[BALL], 8.0, 32).expect("upload");
    GBuffer::new(
        renderer,
        None,
        vec![with_materials(&layer, 0, 1)],
        camera(),
        None,
        SizeRule::Relative(1.0),
    )
}

/// What each pixel sees: None for the sky, else its view distance and
/// whether it is on the ball.
fn surfaces(renderer: &Renderer, g: &Arc<GBuffer>) -> Vec<Option<(f32, bool)>> {
    let (_, images) =
        render_and_read(renderer, g.as_ref(), SIZE, &[&g.targets.depth]).expect("renders");
    let c = camera();
    let inverse = (reverse_z(c.projection) * c.view).inverse();
    let mut out = Vec::new();
    for y in 0..SIZE.1 {
        for x in 0..SIZE.0 {
            let d = images[0].pixel(x, y)[0];
            if d <= 0.0 {
                out.push(None);
                continue;
            }
            let ndc = Vec4::new(
                (x as f32 + 0.5) / SIZE.0 as f32 * 2.0 - 1.0,
                1.0 - (y as f32 + 0.5) / SIZE.1 as f32 * 2.0,
                d,
                1.0,
            );
            let h = inverse * ndc;
            let p = h.truncate() / h.w;
            let distance = -(c.view * p.extend(1.0)).z;
            out.push(Some((distance, p.distance(BALL.0) < BALL.1 * 1.05)));
        }
    }
    out
}

fn texture(renderer: &Renderer, size: (u32, u32), pixels: &[[f32; 4]]) -> Arc<StaticTexture> {
    StaticTexture::from_rgba32f(&renderer.gpu, size.0, size.1, pixels, "test image")
}

/// The lit image light comes from: the ball red, the floor a blue checker,
/// the sky black; and its pixels.
fn lit(renderer: &Renderer, g: &Arc<GBuffer>) -> (Arc<StaticTexture>, ImageF32) {
    let pixels: Vec<[f32; 4]> = surfaces(renderer, g)
        .iter()
        .enumerate()
        .map(|(i, s)| {
            let (x, y) = (i as u32 % SIZE.0, i as u32 / SIZE.0);
            match s {
                None => [0.0, 0.0, 0.0, 1.0],
                Some((_, true)) => [1.0, 0.1, 0.1, 1.0],
                Some((_, false)) if (x / 4 + y / 4) % 2 == 0 => [0.1, 0.2, 0.8, 1.0],
                Some(_) => [0.05, 0.05, 0.3, 1.0],
            }
        })
        .collect();
    let image = ImageF32 {
        width: SIZE.0,
        height: SIZE.1,
        pixels,
    };
    (texture(renderer, SIZE, &image.pixels), image)
}

/// Root mean square difference over every channel of every pixel.
fn rmse(a: &ImageF32, b: &ImageF32, channels: usize) -> f32 {
    let mut sum = 0.0;
    for (p, q) in a.pixels.iter().zip(&b.pixels) {
        for c in 0..channels {
            sum += (p[c] - q[c]).powi(2);
        }
    }
    (sum / (a.pixels.len() * channels) as f32).sqrt()
}

/// Whether a pass of step `step` ran ("raw (half)", "upsample").
fn has_pass(report: &FrameReport, step: &str) -> bool {
    report
        .passes
        .iter()
        .any(|p| p.step.as_deref() == Some(step))
}

/// The report of a Full and a Half frame: only Half runs a half pass, an
/// upsample, and counts `counter`.
fn check_reports(full: &FrameReport, half: &FrameReport, pass: &str, counter: &str) {
    assert!(full.errors.is_empty() && half.errors.is_empty());
    assert_eq!(full.counter(counter), 0);
    assert_eq!(half.counter(counter), 1, "{:?}", half.counters);
    let halved = format!("{pass} (half)");
    assert!(!has_pass(full, &halved) && !has_pass(full, "upsample"));
    assert!(
        has_pass(half, &halved) && has_pass(half, "upsample"),
        "{:?}",
        half.passes.iter().map(|p| &p.name).collect::<Vec<_>>()
    );
}

fn ao_frame(renderer: &Renderer, settings: AoSettings) -> (FrameReport, ImageF32) {
    let ao = AmbientOcclusion::new(renderer, None, gbuffer(renderer), settings, None);
    let (report, mut images) =
        render_and_read(renderer, ao.as_ref(), SIZE, &[&ao.output]).expect("renders");
    (report, images.remove(0))
}

#[test]
fn ao_at_half_resolution_stays_within_its_stated_error_of_full() {
    let renderer = test_renderer();
    for mode in [AoMode::Stochastic, AoMode::Sao, AoMode::Hbao] {
        let settings = AoSettings {
            mode,
            samples: 32,
            steps: 8,
            temporal_blend: 0.0,
            ..Default::default()
        };
        let (full_report, full) = ao_frame(&renderer, settings);
        let (half_report, half) = ao_frame(
            &renderer,
            AoSettings {
                resolution: Resolution::Half,
                ..settings
            },
        );
        check_reports(
            &full_report,
            &half_report,
            "raw",
            spreadlight_render::ssao::HALF_RESOLUTION,
        );
        assert!(half.all_finite(), "{mode:?}");
        assert!(half.pixels.iter().all(|p| (0.0..=1.0).contains(&p[0])));
        let e = rmse(&full, &half, 1);
        // The stated bound (docs/indirect-light.md): visibility within 0.05 RMSE.
        assert!(e < 0.05, "{mode:?}: RMSE of Half against Full: {e}");
        assert!(e > 0.0, "{mode:?}: Half computed something of its own");
    }
}

fn ssgi_frame(
    renderer: &Renderer,
    g: &Arc<GBuffer>,
    source: &Arc<StaticTexture>,
    resolution: Resolution,
) -> (FrameReport, ImageF32) {
    let settings = SsgiSettings {
        samples: 16,
        temporal_blend: 0.0,
        resolution,
        ..Default::default()
    };
    // One node: each frame turns the rays, so two Full frames differ by the estimator's noise.
    let gi = Ssgi::new(
        renderer,
        Some(5),
        g.clone(),
        source.texture_ref(),
        None,
        settings,
    );
    let (report, mut images) =
        render_and_read(renderer, gi.as_ref(), SIZE, &[&gi.output]).expect("renders");
    (report, images.remove(0))
}

#[test]
fn ssgi_at_half_resolution_stays_within_its_stated_error_of_full() {
    let renderer = test_renderer();
    let g = gbuffer(&renderer);
    let (source, _) = lit(&renderer, &g);
    let (full_report, full) = ssgi_frame(&renderer, &g, &source, Resolution::Full);
    let (half_report, half) = ssgi_frame(&renderer, &g, &source, Resolution::Half);
    let (_, full_again) = ssgi_frame(&renderer, &g, &source, Resolution::Full);
    check_reports(
        &full_report,
        &half_report,
        "gather",
        spreadlight_render::lighting::SSGI_HALF_RESOLUTION,
    );
    assert!(half.all_finite());
    let (e, scale) = (rmse(&full, &half, 3), full_mean(&full));
    let noise = rmse(&full, &full_again, 3);
    assert!(scale > 0.005, "light bounces in this scene: {scale}");
    assert!(noise > 0.0, "the rays turn between frames");
    // The stated bound (docs/indirect-light.md): Half differs from Full by
    // no more than 2.5 times what Full differs from itself a frame later
    // (its own noise). A quarter of the rays per area leaves twice the noise
    // after the blur, so about sqrt(5/2) = 1.6 times is noise alone
    // (about 1.8 on lavapipe).
    assert!(
        e < 2.5 * noise,
        "RMSE {e} of Half against Full; Full's frame-to-frame noise {noise}; mean bounce {scale}"
    );
}

fn full_mean(image: &ImageF32) -> f32 {
    let sum: f32 = image.pixels.iter().map(|p| p[0] + p[1] + p[2]).sum();
    sum / (image.pixels.len() * 3) as f32
}

fn ssr_frame(
    renderer: &Renderer,
    g: &Arc<GBuffer>,
    source: &Arc<StaticTexture>,
    resolution: Resolution,
) -> (FrameReport, ImageF32) {
    use spreadlight_render::environment::{Ssr, SsrSettings};
    let mirror = Material::new()
        .with(Feature::CookTorrance, &[[0.0, 1.0, 0.04, 0.0]])
        .and_then(|m| m.with(Feature::Reflection, &[[1.0, 0.0, 0.0, 0.0]]))
        .expect("valid");
    let world = MaterialWorld::new(renderer, vec![Material::default_material(), mirror]);
    let fallback = texture(renderer, SIZE, &vec![[0.0; 4]; (SIZE.0 * SIZE.1) as usize]);
    let settings = SsrSettings {
        max_steps: 256,
        temporal: false,
        resolution,
        ..Default::default()
    };
    let ssr = Ssr::new(
        renderer,
        None,
        g.clone(),
        world,
        source.texture_ref(),
        fallback.texture_ref(),
        settings,
    );
    let (report, mut images) =
        render_and_read(renderer, ssr.as_ref(), SIZE, &[&ssr.output]).expect("renders");
    (report, images.remove(0))
}

#[test]
fn ssr_at_half_resolution_stays_within_its_stated_error_of_full() {
    let renderer = test_renderer();
    let g = gbuffer(&renderer);
    let (source, _) = lit(&renderer, &g);
    let (full_report, full) = ssr_frame(&renderer, &g, &source, Resolution::Full);
    let (half_report, half) = ssr_frame(&renderer, &g, &source, Resolution::Half);
    check_reports(
        &full_report,
        &half_report,
        "trace",
        spreadlight_render::environment::ssr::HALF_RESOLUTION,
    );
    assert!(half.all_finite());
    let reflected = full.pixels.iter().filter(|p| p[0] > 0.3).count();
    assert!(
        reflected > 20,
        "the mirror floor shows the ball: {reflected}"
    );
    let e = rmse(&full, &half, 3);
    // The stated bound: 0.05 RMSE on a scene whose reflections reach 0.8.
    assert!(e < 0.05, "RMSE of Half against Full: {e}");
}

fn dof_frame(
    renderer: &Renderer,
    g: &Arc<GBuffer>,
    source: &Arc<StaticTexture>,
    resolution: Resolution,
) -> (FrameReport, ImageF32) {
    let settings = DofSettings {
        focal_length_mm: 300.0,
        f_stop: 2.0,
        samples: 48,
        max_radius: 12.0,
        resolution,
    };
    // Focused on the ball's front: the floor before and behind it blurs.
    let dof = Dof::new(
        renderer,
        None,
        source.texture_ref(),
        g.clone(),
        Focus::Distance(EYE.distance(BALL.0) - BALL.1),
        None,
        settings,
    );
    let (report, mut images) =
        render_and_read(renderer, dof.as_ref(), SIZE, &[&dof.output]).expect("renders");
    (report, images.remove(0))
}

#[test]
fn dof_at_half_resolution_stays_near_full_and_keeps_in_focus_detail() {
    let renderer = test_renderer();
    let g = gbuffer(&renderer);
    let (source, sharp) = lit(&renderer, &g);
    let (full_report, full) = dof_frame(&renderer, &g, &source, Resolution::Full);
    let (half_report, half) = dof_frame(&renderer, &g, &source, Resolution::Half);
    check_reports(
        &full_report,
        &half_report,
        "blur",
        spreadlight_render::post::dof::HALF_RESOLUTION,
    );
    assert!(half.all_finite());
    let blurred = rmse(&full, &sharp, 3);
    assert!(blurred > 0.02, "the lens blurs this scene: {blurred}");
    let e = rmse(&full, &half, 3);
    // The stated bound (docs/post.md): RMSE under 0.02 of Full on colours
    // up to 0.8. The floor's 4-pixel checker is the half grid's worst case:
    // where the lens blurs it by a pixel or two, Full keeps detail that
    // one sample in four cannot hold (about 0.015 on lavapipe).
    assert!(
        e < 0.02,
        "RMSE of Half against Full {e}; of the sharp image {blurred}"
    );
    // The ball is in focus: where Full keeps its pixels, Half does too (its
    // detail comes back from the full image, not from the half grid).
    let surfaces = surfaces(&renderer, &g);
    let (mut kept, mut ball) = (0, 0);
    for (i, s) in surfaces.iter().enumerate() {
        if matches!(s, Some((_, true))) && (full.pixels[i][0] - sharp.pixels[i][0]).abs() < 0.02 {
            ball += 1;
            kept += usize::from((half.pixels[i][0] - sharp.pixels[i][0]).abs() < 0.05);
        }
    }
    assert!(ball > 50, "{ball} sharp ball pixels");
    assert!(
        kept as f32 >= 0.95 * ball as f32,
        "{kept} of {ball} stay sharp"
    );
}

/// Only an upsample: a half-size image in, the full-size result out.
struct UpsampleOnly {
    id: u64,
    g: Arc<GBuffer>,
    half: Arc<StaticTexture>,
    half_name: String,
    output: String,
}

impl Recipe for UpsampleOnly {
    fn declare<'a>(&'a self, renderer: &'a Renderer, fg: &mut FrameGraph<'a>) {
        if !fg.include(self.id) {
            return;
        }
        self.g.declare(renderer, fg);
        self.half.declare(renderer, fg);
        declare_upsample(
            fg,
            Resolution::Half,
            UpsamplePass {
                name: PassName::new("Upsample"),
                owner: None,
                gbuffer: &self.g,
                half: &self.half_name,
                full: &self.output,
                desc: TextureDesc::storage(wgpu::TextureFormat::Rgba16Float),
                format: UpsampleFormat::Rgba16,
                counter: "upsampled",
                label: "upsample",
                detail: None,
            },
        );
    }
}

#[test]
fn the_upsample_does_not_bleed_across_a_silhouette() {
    let renderer = test_renderer();
    let g = gbuffer(&renderer);
    let surfaces = surfaces(&renderer, &g);
    let at = |x: u32, y: u32| surfaces[(y.min(SIZE.1 - 1) * SIZE.0 + x.min(SIZE.0 - 1)) as usize];
    // Each side's own value: 1 on the ball, 0 on the floor and the sky.
    let value = |s: Option<(f32, bool)>| {
        if matches!(s, Some((_, true))) {
            1.0
        } else {
            0.0
        }
    };
    let half_size = (SIZE.0.div_ceil(2), SIZE.1.div_ceil(2));
    let half_pixels: Vec<[f32; 4]> = (0..half_size.0 * half_size.1)
        .map(|i| {
            let v = value(at(i % half_size.0 * 2, i / half_size.0 * 2));
            [v, v, v, 1.0]
        })
        .collect();
    let half = texture(&renderer, half_size, &half_pixels);
    let recipe = UpsampleOnly {
        id: spreadlight_render::recipe::next_recipe_id(),
        g: g.clone(),
        half_name: half.texture_ref().name,
        half,
        output: "upsampled".to_owned(),
    };
    let (report, images) =
        render_and_read(&renderer, &recipe, SIZE, &["upsampled"]).expect("renders");
    assert!(report.errors.is_empty(), "{:?}", report.errors);
    let out = &images[0];
    assert!(out.all_finite());
    // A silhouette: two surfaces whose view distances differ by 10% or more,
    // or a surface against the sky.
    let apart = |a: Option<(f32, bool)>, b: Option<(f32, bool)>| match (a, b) {
        (Some((za, _)), Some((zb, _))) => (za - zb).abs() > 0.1 * za,
        (None, None) => false,
        _ => true,
    };
    let (mut beside, mut bilinear_bleeds) = (0, 0);
    for y in 0..SIZE.1 {
        for x in 0..SIZE.0 {
            let here = at(x, y);
            // The half texels with a bilinear weight on this pixel.
            let xs: Vec<u32> = if x % 2 == 0 {
                vec![x]
            } else {
                vec![x - 1, x + 1]
            };
            let ys: Vec<u32> = if y % 2 == 0 {
                vec![y]
            } else {
                vec![y - 1, y + 1]
            };
            let texels: Vec<Option<(f32, bool)>> = ys
                .iter()
                .flat_map(|&ty| xs.iter().map(move |&tx| (tx, ty)))
                .map(|(tx, ty)| at(tx, ty))
                .collect();
            let across = texels
                .iter()
                .any(|t| apart(here, *t) && value(*t) != value(here));
            let same_side = texels
                .iter()
                .any(|t| !apart(here, *t) && value(*t) == value(here));
            if !(across && same_side) {
                continue;
            }
            beside += 1;
            let bilinear: f32 = texels.iter().map(|t| value(*t)).sum::<f32>() / texels.len() as f32;
            bilinear_bleeds += usize::from((bilinear - value(here)).abs() > 0.2);
            let got = out.pixel(x, y)[0];
            assert!(
                (got - value(here)).abs() < 0.05,
                "({x}, {y}) beside the silhouette took the other side's value: {got}, its own {}",
                value(here)
            );
        }
    }
    assert!(
        beside > 20,
        "{beside} pixels beside the silhouette were checked"
    );
    assert!(
        bilinear_bleeds > 20,
        "a plain bilinear upsample would bleed at {bilinear_bleeds} of them"
    );
}

/// What a declared (not executed) frame of `size` plans for AO's and
/// SSGI's half-size raw targets: their sizes, None where the effect runs
/// at Full.
fn planned_half(
    renderer: &Renderer,
    ao: &AmbientOcclusion,
    gi: &Ssgi,
    size: (u32, u32),
) -> [Option<(u32, u32)>; 2] {
    let mut fg = FrameGraph::new(size);
    ao.declare(renderer, &mut fg);
    gi.declare(renderer, &mut fg);
    let planned = |name: &str| fg.planned(name).map(|k| (k.width, k.height));
    // The blurs' half-size results: only a half chain has them (AO's
    // half-size estimate is its history, which Full has at full size).
    [
        planned(&ao.half_targets()[1]),
        planned(&gi.half_targets()[1]),
    ]
}

/// `Resolution::Auto`, the default, is Half for frames of 1920x1080 pixels
/// and more and Full below (the frame graph is declared at each size, not
/// rendered), and the renderer's choice (what SPREADLIGHT_RESOLUTION_AUTO
/// sets) forces it either way; Full and Half as set are never changed.
#[test]
fn auto_is_half_from_1080p_on_and_the_choice_forces_it() {
    use spreadlight_render::resolution::{AUTO_HALF_FROM_PIXELS, AutoChoice, set_auto_choice};
    assert_eq!(AUTO_HALF_FROM_PIXELS, 1920 * 1080);
    let renderer = test_renderer();
    let g = gbuffer(&renderer);
    let (source, _) = lit(&renderer, &g);
    let effects = |resolution| {
        let ao = AmbientOcclusion::new(
            &renderer,
            None,
            g.clone(),
            AoSettings {
                resolution,
                ..Default::default()
            },
            None,
        );
        let gi = Ssgi::new(
            &renderer,
            None,
            g.clone(),
            source.texture_ref(),
            None,
            SsgiSettings {
                resolution,
                ..Default::default()
            },
        );
        (ao, gi)
    };
    assert_eq!(AoSettings::default().resolution, Resolution::Auto);
    assert_eq!(SsgiSettings::default().resolution, Resolution::Auto);
    let (ao, gi) = effects(Resolution::Auto);
    let half = |w: u32, h: u32| Some((w.div_ceil(2), h.div_ceil(2)));
    // The renderer's choice until set: the variable, unset in tests, so the rule.
    for (size, want) in [
        ((1920, 1080), half(1920, 1080)),
        ((3840, 2160), half(3840, 2160)),
        ((1921, 1081), half(1921, 1081)),
        ((1920, 1079), None),
        ((SIZE.0, SIZE.1), None),
    ] {
        set_auto_choice(&renderer, AutoChoice::Size);
        assert_eq!(
            planned_half(&renderer, &ao, &gi, size),
            [want; 2],
            "{size:?}"
        );
    }
    set_auto_choice(&renderer, AutoChoice::Full);
    assert_eq!(planned_half(&renderer, &ao, &gi, (3840, 2160)), [None; 2]);
    set_auto_choice(&renderer, AutoChoice::Half);
    assert_eq!(
        planned_half(&renderer, &ao, &gi, SIZE),
        [half(SIZE.0, SIZE.1); 2]
    );
    // Set resolutions ignore the choice.
    let (full_ao, full_gi) = effects(Resolution::Full);
    assert_eq!(planned_half(&renderer, &full_ao, &full_gi, SIZE), [None; 2]);
    set_auto_choice(&renderer, AutoChoice::Full);
    let (half_ao, half_gi) = effects(Resolution::Half);
    assert_eq!(
        planned_half(&renderer, &half_ao, &half_gi, SIZE),
        [half(SIZE.0, SIZE.1); 2]
    );
}

/// Auto renders as Full below the threshold (the reference images' sizes)
/// and as Half when forced, with the report saying which ran.
#[test]
fn auto_renders_as_what_it_resolves_to() {
    use spreadlight_render::resolution::{AutoChoice, set_auto_choice};
    let renderer = test_renderer();
    let settings = AoSettings {
        mode: AoMode::Hbao,
        temporal_blend: 0.0,
        ..Default::default()
    };
    let full = AoSettings {
        resolution: Resolution::Full,
        ..settings
    };
    let (_, auto) = ao_frame(&renderer, settings);
    let (_, reference) = ao_frame(&renderer, full);
    assert_eq!(auto.pixels, reference.pixels, "Auto below 1080p is Full");
    set_auto_choice(&renderer, AutoChoice::Half);
    let (auto_report, auto) = ao_frame(&renderer, settings);
    let (full_report, _) = ao_frame(&renderer, full);
    check_reports(
        &full_report,
        &auto_report,
        "raw",
        spreadlight_render::ssao::HALF_RESOLUTION,
    );
    let half = AoSettings {
        resolution: Resolution::Half,
        ..settings
    };
    let (_, forced) = ao_frame(&renderer, half);
    assert_eq!(auto.pixels, forced.pixels, "Auto forced to half is Half");
}

/// The half chains with their temporal blend over several frames of one
/// node: finite, in range, the history at half size started once and then
/// reused; switching the node to Full starts it anew (a change of size, as
/// a resize).
#[test]
fn the_half_chains_accumulate_at_half_size_and_stay_finite() {
    let renderer = test_renderer();
    let g = gbuffer(&renderer);
    let (source, _) = lit(&renderer, &g);
    let ao_settings = |resolution| AoSettings {
        mode: AoMode::Stochastic,
        samples: 4,
        temporal_blend: 0.9,
        resolution,
        ..Default::default()
    };
    let gi_settings = |resolution| SsgiSettings {
        samples: 2,
        temporal_blend: 0.9,
        resolution,
        ..Default::default()
    };
    let mut frames = Vec::new();
    for resolution in [
        Resolution::Half,
        Resolution::Half,
        Resolution::Half,
        Resolution::Full,
    ] {
        let ao = AmbientOcclusion::new(
            &renderer,
            Some(21),
            g.clone(),
            ao_settings(resolution),
            None,
        );
        let gi = Ssgi::new(
            &renderer,
            Some(22),
            g.clone(),
            source.texture_ref(),
            None,
            gi_settings(resolution),
        );
        let both = Both(ao.clone(), gi.clone());
        let (report, images) =
            render_and_read(&renderer, &both, SIZE, &[&ao.output, &gi.output]).expect("renders");
        assert!(report.errors.is_empty(), "{:?}", report.errors);
        for image in &images {
            assert!(image.all_finite(), "{resolution:?}");
        }
        assert!(images[0].pixels.iter().all(|p| (0.0..=1.0).contains(&p[0])));
        if resolution.is_half() {
            assert!(has_pass(&report, "temporal (half)"), "{:?}", report.passes);
        }
        frames.push((
            report.counter("AO history reset"),
            report.counter("SSGI history reset"),
        ));
        let _ = images;
    }
    assert_eq!(frames, [(1, 1), (0, 0), (0, 0), (1, 1)]);
}

/// Two effects declared in one frame.
struct Both(Arc<AmbientOcclusion>, Arc<Ssgi>);

impl Recipe for Both {
    fn declare<'a>(&'a self, renderer: &'a Renderer, fg: &mut FrameGraph<'a>) {
        self.0.declare(renderer, fg);
        self.1.declare(renderer, fg);
    }
}
