//! Shadow maps on the GPU: a ball above a floor, lit from above by each
//! light type through each filter. The shadow falls where the ball hides
//! the light and nowhere else; only the maps a frame needs are rendered,
//! and unchanged ones are reused (the frame report counts both); the hard
//! cases of the stability suite never produce NaN or infinity.

use std::sync::Arc;

use glam::Vec3;
use spreadlight_render::camera::CameraInput;
use spreadlight_render::gbuffer::{GBuffer, Layer, RasterChoice};
use spreadlight_render::lighting::{
    CookTorrance, LightBuffer, LightLoop, PointLight, SpotLight, SunLight, Surfaces,
};
use spreadlight_render::readback::{ImageF32, render_and_read};
use spreadlight_render::renderer::test_renderer;
use spreadlight_render::scenes::balls_on_floor;
use spreadlight_render::shadows::{
    Cascades, ShadowFilter, ShadowLights, ShadowMaps, ShadowSettings,
};
use spreadlight_render::{FrameReport, Renderer, SizeRule};

const SIZE: (u32, u32) = (64, 64);

/// The casters: a ball of radius 0.5 at `ball`, over a 20 x 20 floor at y = 0.
fn casters(renderer: &Renderer, ball: Vec3) -> Vec<Arc<Layer>> {
    vec![balls_on_floor(renderer, &[(ball, 0.5)], 20.0, 32).expect("upload")]
}

/// Looking down at the floor's centre from above and in front, past the
/// ball's side: the image's centre is the floor under the ball.
/// A layer of one grey instance of `mesh`, still at `transform`.
fn one_instance(
    mesh: Arc<spreadlight_render::mesh_arena::GpuMesh>,
    transform: glam::Mat4,
) -> Arc<Layer> {
    use spreadlight_render::gbuffer::{DrawBatch, InstanceInput};
    Arc::new(Layer::plain(vec![DrawBatch {
        mesh,
        instances: vec![InstanceInput {
            transform,
            previous_transform: transform,
            color: [0.8; 4],
            material_id: 0,
            object_id: 0,
        }],
    }]))
}

fn camera() -> CameraInput {
    CameraInput {
        view: glam::camera::rh::view::look_at_mat4(Vec3::new(0.0, 8.0, 6.0), Vec3::ZERO, Vec3::Y),
        projection: glam::camera::rh::proj::directx::perspective(1.0, 1.0, 0.1, 50.0),
    }
}

/// [`camera`] moved `dx` along +X.
fn camera_moved(dx: f32) -> CameraInput {
    let mut c = camera();
    c.view *= glam::Mat4::from_translation(Vec3::new(-dx, 0.0, 0.0));
    c
}

/// The lit image (diffuse + specular) and the frame's report.
fn shade(
    renderer: &Renderer,
    layers: &[Arc<Layer>],
    lights: Arc<LightBuffer>,
    shadows: Option<Arc<ShadowMaps>>,
) -> (ImageF32, FrameReport) {
    shade_from(renderer, camera(), layers, lights, shadows)
}

/// [`shade`] seen from `camera`.
fn shade_from(
    renderer: &Renderer,
    camera: CameraInput,
    layers: &[Arc<Layer>],
    lights: Arc<LightBuffer>,
    shadows: Option<Arc<ShadowMaps>>,
) -> (ImageF32, FrameReport) {
    shade_sized(renderer, camera, layers, lights, shadows, SIZE)
}

/// [`shade_from`] at `size` (shadow_layers.rs shades its own scenes with it).
pub(crate) fn shade_sized(
    renderer: &Renderer,
    camera: CameraInput,
    layers: &[Arc<Layer>],
    lights: Arc<LightBuffer>,
    shadows: Option<Arc<ShadowMaps>>,
    size: (u32, u32),
) -> (ImageF32, FrameReport) {
    let g = GBuffer::new(
        renderer,
        None,
        layers.to_vec(),
        camera,
        None,
        SizeRule::Relative(1.0),
    );
    let ct = CookTorrance::with_shadows(
        renderer,
        Some(1),
        g,
        lights,
        LightLoop::Naive,
        true,
        Surfaces::PerMaterialId(vec![(0.7, 0.0)]),
        shadows,
    );
    let (report, images) =
        render_and_read(renderer, ct.as_ref(), size, &[&ct.diffuse, &ct.specular])
            .expect("renders");
    assert!(report.errors.is_empty(), "{:?}", report.errors);
    let (d, s) = (&images[0], &images[1]);
    assert!(
        d.all_finite() && s.all_finite(),
        "no NaN or infinity in the HDR targets"
    );
    let pixels = d
        .pixels
        .iter()
        .zip(&s.pixels)
        .map(|(a, b)| [a[0] + b[0], a[1] + b[1], a[2] + b[2], 1.0])
        .collect();
    (
        ImageF32 {
            width: d.width,
            height: d.height,
            pixels,
        },
        report,
    )
}

fn luminance(image: &ImageF32, x: u32, y: u32) -> f32 {
    let p = image.pixels[(y * image.width + x) as usize];
    p[0] + p[1] + p[2]
}

/// The ball hides the light from the floor straight below it (the image's
/// centre, ball at the origin's column) but not from the floor's edge.
fn assert_shadow_below_the_ball(lit: &ImageF32, shadowed: &ImageF32, what: &str) {
    let (cx, cy) = (SIZE.0 / 2, SIZE.1 / 2);
    let (under_lit, under_shadowed) = (luminance(lit, cx, cy), luminance(shadowed, cx, cy));
    assert!(
        under_lit > 1e-3,
        "{what}: the floor under the ball is lit without shadows"
    );
    assert!(
        under_shadowed < 0.25 * under_lit,
        "{what}: the shadow darkens the floor under the ball ({under_shadowed} vs {under_lit})"
    );
    // Away from the ball, a third of the way to the edge: as lit as without shadows.
    let (ex, ey) = (cx + SIZE.0 / 3, cy);
    let (edge_lit, edge_shadowed) = (luminance(lit, ex, ey), luminance(shadowed, ex, ey));
    assert!(
        (edge_shadowed - edge_lit).abs() <= 0.05 * edge_lit + 1e-4,
        "{what}: no shadow (or acne) away from the ball ({edge_shadowed} vs {edge_lit})"
    );
}

const FILTERS: [ShadowFilter; 4] = [
    ShadowFilter::Raw,
    ShadowFilter::Pcf { kernel: 3 },
    ShadowFilter::Pcss {
        light_size: 0.3,
        samples: 16,
    },
    ShadowFilter::Vsm {
        bleeding: 0.3,
        blur: 1,
    },
];

fn settings(filter: ShadowFilter) -> ShadowSettings {
    ShadowSettings {
        resolution: 256,
        filter,
        ..Default::default()
    }
}

/// A white sun of 5 lux along `direction`, casting into slice 0.
fn casting_sun(direction: Vec3) -> SunLight {
    SunLight {
        direction,
        color: Vec3::ONE,
        illuminance: 5.0,
        shadow: Some(0),
    }
}

/// `sun` casting through `count` cascades out to `distance`, split by
/// `split_lambda` and held by `step`.
fn sun_cascades(
    sun: &SunLight,
    count: u32,
    split_lambda: f32,
    distance: f32,
    step: f32,
) -> ShadowLights {
    ShadowLights::Sun {
        lights: vec![(0, sun.direction)],
        cascades: Cascades {
            count,
            split_lambda,
            distance,
            step,
        },
    }
}

/// `casting`'s maps of `layers` seen from [`camera`], drawn by `raster`
/// and read through `filter` ([`settings`]).
fn maps_drawn_by(
    renderer: &Renderer,
    casting: &ShadowLights,
    layers: &[Arc<Layer>],
    raster: RasterChoice,
    filter: ShadowFilter,
) -> Arc<ShadowMaps> {
    ShadowMaps::new(
        renderer,
        None,
        casting,
        layers.to_vec(),
        &camera(),
        ShadowSettings {
            raster,
            ..settings(filter)
        },
    )
    .expect("valid shadows")
}

/// A spot, a point light and a sun (three cascades) over the ball, each
/// casting into slice 0 of its own maps.
fn three_lights(renderer: &Renderer) -> [(&'static str, Arc<LightBuffer>, ShadowLights); 3] {
    let spot = SpotLight {
        shadow: Some(0),
        ..SpotLight::cone(Vec3::new(0.0, 6.0, 0.0), Vec3::NEG_Y, 12.0, 0.5, 0.7)
            .with_light(Vec3::ONE, 300.0)
    };
    let point = PointLight {
        position: Vec3::new(0.0, 6.0, 0.0),
        color: Vec3::ONE,
        intensity: 300.0,
        range: 15.0,
        shadow: Some(0),
    };
    let sun = casting_sun(Vec3::NEG_Y);
    [
        (
            "spot",
            LightBuffer::spots(renderer, &[spot], None).expect("valid"),
            ShadowLights::Spot(vec![(0, spot.view, spot.projection)]),
        ),
        (
            "point",
            LightBuffer::points(renderer, &[point]),
            ShadowLights::Point(vec![(0, point.position, point.range)]),
        ),
        (
            "sun",
            LightBuffer::suns(renderer, &[sun]),
            sun_cascades(&sun, 3, 0.6, 30.0, 0.0),
        ),
    ]
}

#[test]
fn every_light_type_casts_through_every_filter() {
    let renderer = test_renderer();
    let layers = casters(&renderer, Vec3::new(0.0, 1.5, 0.0));
    for (name, lights, casting) in three_lights(&renderer) {
        let (lit, _) = shade(&renderer, &layers, lights.clone(), None);
        for filter in FILTERS {
            // A sun's light size is the tangent of its angular radius: 0.3 would be a
            // 17-degree sun, whose penumbra swallows a ball this size.
            let filter = match (name, filter) {
                ("sun", ShadowFilter::Pcss { samples, .. }) => ShadowFilter::Pcss {
                    light_size: 0.05,
                    samples,
                },
                _ => filter,
            };
            // Both rasterizers draw the same maps: the compute one's 32-bit
            // depth words run on any adapter.
            let mut images = Vec::new();
            let mut depths = Vec::new();
            for raster in [RasterChoice::Compute, RasterChoice::Hardware] {
                let maps = maps_drawn_by(&renderer, &casting, &layers, raster, filter);
                assert_eq!(maps.compute_raster(), raster == RasterChoice::Compute);
                let (shadowed, report) =
                    shade(&renderer, &layers, lights.clone(), Some(maps.clone()));
                let what = format!("{name} {filter:?} {raster:?}");
                assert_shadow_below_the_ball(&lit, &shadowed, &what);
                assert_eq!(report.counter("shadow maps rendered"), 1, "{what}");
                images.push(shadowed);
                depths.push(
                    maps.read_depth(&renderer.gpu)
                        .expect("reads back")
                        .expect("rendered"),
                );
            }
            assert_depths_agree(&depths[0], &depths[1], &format!("{name} {filter:?}"));
            let differ = images[0]
                .pixels
                .iter()
                .zip(&images[1].pixels)
                .filter(|(a, b)| (a[0] - b[0]).abs() > 0.05 * a[0].max(b[0]) + 1e-4)
                .count();
            assert!(
                differ * 50 < images[0].pixels.len(),
                "{name} {filter:?}: compute and hardware maps shade alike ({differ} pixels differ)"
            );
        }
    }
}

/// Casters placed at NaN or scaled to infinity (a broken transform) draw
/// nothing into the maps, on either rasterizer, for every light type: every
/// texel stays finite and within 0..=1, and the good ball beside them still
/// casts its shadow.
#[test]
fn non_finite_casters_never_reach_the_maps() {
    let renderer = test_renderer();
    let good = casters(&renderer, Vec3::new(0.0, 1.5, 0.0));
    let broken = vec![
        balls_on_floor(
            &renderer,
            &[
                (Vec3::new(f32::NAN, 1.5, 0.0), 0.5),
                (Vec3::new(0.0, 2.5, 0.0), f32::INFINITY),
                (Vec3::new(f32::INFINITY, 1.0, f32::NEG_INFINITY), 0.3),
                (Vec3::new(0.0, 1.5, 0.0), 0.5),
            ],
            20.0,
            16,
        )
        .expect("upload"),
    ];
    for (name, lights, casting) in three_lights(&renderer) {
        let (lit, _) = shade(&renderer, &good, lights.clone(), None);
        for raster in [RasterChoice::Compute, RasterChoice::Hardware] {
            let maps = ShadowMaps::new(
                &renderer,
                None,
                &casting,
                broken.clone(),
                &camera(),
                ShadowSettings {
                    raster,
                    ..settings(ShadowFilter::Pcf { kernel: 3 })
                },
            )
            .expect("valid shadows");
            let (shadowed, _) = shade(&renderer, &good, lights.clone(), Some(maps.clone()));
            let what = format!("{name} {raster:?} with non-finite casters");
            assert_shadow_below_the_ball(&lit, &shadowed, &what);
            let depth = maps
                .read_depth(&renderer.gpu)
                .expect("reads back")
                .expect("rendered");
            for (layer, image) in depth.iter().enumerate() {
                assert!(
                    image.pixels.iter().all(|p| (0.0..=1.0).contains(&p[0])),
                    "{what}: layer {layer} holds a depth outside 0..=1 (NaN or infinity)"
                );
            }
        }
    }
}

/// A static scene (casters, lights and camera unchanged) renders no map after
/// its first frame, for every light type (a sun's cascades included) and
/// either rasterizer: the frame report counts the maps reused.
#[test]
fn a_static_scene_renders_no_shadow_map_after_its_first_frame() {
    let renderer = test_renderer();
    let layers = casters(&renderer, Vec3::new(0.0, 1.5, 0.0));
    for (owner, (name, lights, casting)) in (20..).zip(three_lights(&renderer)) {
        for (k, raster) in [RasterChoice::Compute, RasterChoice::Hardware]
            .into_iter()
            .enumerate()
        {
            let owner = owner * 2 + k as u32;
            let maps = || {
                ShadowMaps::new(
                    &renderer,
                    Some(owner),
                    &casting,
                    layers.clone(),
                    &camera(),
                    ShadowSettings {
                        raster,
                        ..settings(ShadowFilter::Pcf { kernel: 3 })
                    },
                )
                .expect("valid shadows")
            };
            let what = format!("{name} {raster:?}");
            let (first, report) = shade(&renderer, &layers, lights.clone(), Some(maps()));
            assert_eq!(report.counter("shadow maps rendered"), 1, "{what}");
            for _ in 0..2 {
                let (again, report) = shade(&renderer, &layers, lights.clone(), Some(maps()));
                assert_eq!(
                    report.counter("shadow maps rendered"),
                    0,
                    "{what}: {:?}",
                    report.counters
                );
                assert_eq!(report.counter("shadow maps reused"), 1, "{what}");
                assert_eq!(again.pixels, first.pixels, "{what}");
            }
        }
    }
}

/// A moving camera moves a sun's cascades texel by texel, and each frame
/// re-renders them; with a Cascade Step they hold while it moves within a
/// step, and the maps are reused (counted), for either rasterizer.
#[test]
fn a_stepped_sun_renders_no_cascade_while_the_camera_moves_within_a_step() {
    let renderer = test_renderer();
    let (layers, sun, lights) = sun_scene(&renderer);
    for (owner, raster) in [(40, RasterChoice::Compute), (41, RasterChoice::Hardware)] {
        for step in [0.0, 0.25] {
            let casting = sun_cascades(&sun, 3, 0.6, 30.0, step);
            let owner = owner + if step > 0.0 { 10 } else { 0 };
            let (mut rendered, mut whole) = (Vec::new(), Vec::new());
            for frame in 0..4 {
                let camera = camera_moved(frame as f32 * 0.01);
                let maps = ShadowMaps::new(
                    &renderer,
                    Some(owner),
                    &casting,
                    layers.clone(),
                    &camera,
                    ShadowSettings {
                        raster,
                        ..settings(ShadowFilter::Pcf { kernel: 3 })
                    },
                )
                .expect("valid shadows");
                let (image, report) =
                    shade_from(&renderer, camera, &layers, lights.clone(), Some(maps));
                assert!(image.all_finite());
                rendered.push(report.counter("shadow maps rendered"));
                whole.push(report.counter("shadow layers drawn whole"));
            }
            if step > 0.0 {
                assert_eq!(rendered, [1, 0, 0, 0], "{raster:?}, step {step}");
            } else {
                // Following the camera texel by texel: its cascades scroll
                // (or hold), none is drawn whole after the first frame.
                assert_eq!(whole, [3, 0, 0, 0], "{raster:?}, step {step}");
            }
        }
    }
}

/// The compute rasterizer's maps (`compute`) against the raster hardware's,
/// layer by layer, in conventional depth (0 near, 1 far). The stated error:
/// a texel both draw differs by at most DEPTH_ERROR, beyond which only
/// OUTLIERS of the drawn texels may go (where the hardware's slope-scaled
/// bias, 1.5 times the depth's change across a texel, is large: the ball's
/// rim seen edge-on); and at most COVERAGE of the texels are drawn by one and
/// not the other (a silhouette's texel centres on an edge, where the two
/// rules for shared edges differ). Every texel of both is finite, within 0..=1.
fn assert_depths_agree(compute: &[ImageF32], hardware: &[ImageF32], what: &str) {
    const DEPTH_ERROR: f32 = 2e-3;
    const OUTLIERS: f64 = 0.02;
    const COVERAGE: f64 = 0.01;
    assert_eq!(compute.len(), hardware.len(), "{what}: layers");
    let (mut both, mut off, mut one_only, mut texels) = (0usize, 0usize, 0usize, 0usize);
    let mut worst = 0.0f32;
    for (c, h) in compute.iter().zip(hardware) {
        for (a, b) in c.pixels.iter().zip(&h.pixels) {
            let (a, b) = (a[0], b[0]);
            assert!(
                (0.0..=1.0).contains(&a) && (0.0..=1.0).contains(&b),
                "{what}: a map holds {a} / {b}"
            );
            texels += 1;
            match (a < 1.0, b < 1.0) {
                (true, true) => {
                    both += 1;
                    let e = (a - b).abs();
                    worst = worst.max(e);
                    if e > DEPTH_ERROR {
                        off += 1;
                    }
                }
                (false, false) => {}
                _ => one_only += 1,
            }
        }
    }
    // The figures docs/shadows.md states (shown with --nocapture).
    eprintln!(
        "{what}: worst {worst:.2e}; {off} of {both} drawn texels beyond {DEPTH_ERROR}; \
         {one_only} of {texels} drawn by one only"
    );
    assert!(both > 0, "{what}: the casters are in the maps");
    assert!(
        (off as f64) <= OUTLIERS * both as f64,
        "{what}: {off} of {both} texels differ by more than {DEPTH_ERROR} (worst {worst})"
    );
    assert!(
        (one_only as f64) <= COVERAGE * texels as f64,
        "{what}: {one_only} of {texels} texels are drawn by one rasterizer only"
    );
}

#[test]
fn only_the_maps_a_frame_needs_are_rendered_and_unchanged_ones_are_reused() {
    let renderer = test_renderer();
    let layers = casters(&renderer, Vec3::new(0.0, 1.5, 0.0));
    // Spot 0 over the ball; spot 1 far behind the camera's view, pointing away; spot 2 casts nothing.
    let over = SpotLight {
        shadow: Some(0),
        ..SpotLight::cone(Vec3::new(0.0, 6.0, 0.0), Vec3::NEG_Y, 12.0, 0.5, 0.7)
            .with_light(Vec3::ONE, 300.0)
    };
    let away = SpotLight {
        shadow: Some(1),
        ..SpotLight::cone(Vec3::new(0.0, 6.0, 200.0), Vec3::Z, 12.0, 0.5, 0.7)
            .with_light(Vec3::ONE, 300.0)
    };
    let silent = SpotLight::cone(Vec3::new(3.0, 6.0, 0.0), Vec3::NEG_Y, 12.0, 0.5, 0.7)
        .with_light(Vec3::ONE, 300.0);
    let spots = [over, away, silent];
    let lights = LightBuffer::spots(&renderer, &spots, None).expect("valid");
    let casting = ShadowLights::Spot(
        spots
            .iter()
            .filter_map(|s| s.shadow.map(|slice| (slice, s.view, s.projection)))
            .collect(),
    );
    let maps = |layers: &[Arc<Layer>]| {
        // The same node (owner 7) every frame, as a patch re-evaluates it.
        ShadowMaps::new(
            &renderer,
            Some(7),
            &casting,
            layers.to_vec(),
            &camera(),
            settings(FILTERS[1]),
        )
        .expect("valid")
    };
    let (first, report) = shade(&renderer, &layers, lights.clone(), Some(maps(&layers)));
    assert_eq!(
        report.counter("shadow maps rendered"),
        1,
        "only the spot in view: {:?}",
        report.counters
    );
    assert_eq!(report.counter("shadow maps culled"), 1);
    assert_eq!(report.counter("shadow maps reused"), 0);
    // Nothing changed: the map is reused and the image is the same.
    let (second, report) = shade(&renderer, &layers, lights.clone(), Some(maps(&layers)));
    assert_eq!(
        report.counter("shadow maps rendered"),
        0,
        "{:?}",
        report.counters
    );
    assert_eq!(report.counter("shadow maps reused"), 1);
    assert_eq!(first.pixels, second.pixels);
    // The ball moved: new casters, the map is rendered again.
    let moved = casters(&renderer, Vec3::new(1.0, 1.5, 0.0));
    let (_, report) = shade(&renderer, &moved, lights.clone(), Some(maps(&moved)));
    assert_eq!(
        report.counter("shadow maps rendered"),
        1,
        "{:?}",
        report.counters
    );
    // No light casts: no maps at all.
    let (_, report) = shade(&renderer, &layers, lights, None);
    assert_eq!(
        report.counter("shadow maps rendered") + report.counter("shadow maps reused"),
        0
    );
}

#[test]
fn shadow_hard_cases_stay_finite_and_bounded() {
    let renderer = test_renderer();
    // A ball resting on the floor (blocker touching the receiver: zero penumbra),
    // and a light inside a caster.
    let resting = casters(&renderer, Vec3::new(0.0, 0.5, 0.0));
    let point = |position: Vec3| PointLight {
        position,
        color: Vec3::ONE,
        intensity: 300.0,
        range: 15.0,
        shadow: Some(0),
    };
    for (what, layers, light) in [
        (
            "a ball resting on the floor",
            resting.clone(),
            point(Vec3::new(0.0, 6.0, 0.0)),
        ),
        (
            "a light inside the ball",
            resting.clone(),
            point(Vec3::new(0.0, 0.5, 0.0)),
        ),
        // A point light exactly at a vertex of the floor (its corner).
        (
            "a light at a vertex",
            resting.clone(),
            point(Vec3::new(10.0, 0.0, 10.0)),
        ),
    ] {
        for filter in FILTERS {
            let casting = ShadowLights::Point(vec![(0, light.position, light.range)]);
            let maps = ShadowMaps::new(
                &renderer,
                None,
                &casting,
                layers.clone(),
                &camera(),
                settings(filter),
            )
            .expect("valid");
            let (image, _) = shade(
                &renderer,
                &layers,
                LightBuffer::points(&renderer, &[light]),
                Some(maps),
            );
            // shade() asserts finiteness; the light never adds energy by being shadowed.
            let (unshadowed, _) = shade(
                &renderer,
                &layers,
                LightBuffer::points(&renderer, &[light]),
                None,
            );
            for (s, u) in image.pixels.iter().zip(&unshadowed.pixels) {
                assert!(
                    s[0] <= u[0] * 1.0001 + 1e-6,
                    "{what} {filter:?}: shadows only take light away"
                );
            }
        }
    }
    // VSM over a huge depth range: a sun whose cascades reach 10,000 units.
    let layers = casters(&renderer, Vec3::new(0.0, 1.5, 0.0));
    let sun = casting_sun(Vec3::new(-0.2, -1.0, 0.1));
    let casting = sun_cascades(&sun, 4, 1.0, 10_000.0, 0.0);
    let maps = ShadowMaps::new(
        &renderer,
        None,
        &casting,
        layers.clone(),
        &camera(),
        settings(ShadowFilter::Vsm {
            bleeding: 0.0,
            blur: 2,
        }),
    )
    .expect("valid");
    let (image, _) = shade(
        &renderer,
        &layers,
        LightBuffer::suns(&renderer, &[sun]),
        Some(maps),
    );
    let lit = image.pixels.iter().filter(|p| p[0] > 1e-4).count();
    assert!(
        lit > image.pixels.len() / 2,
        "not a wrong all-black frame: {lit} lit"
    );
}

#[test]
fn bad_shadow_setups_are_errors_naming_what() {
    let renderer = test_renderer();
    let layers = casters(&renderer, Vec3::ZERO);
    let twice = ShadowLights::Point(vec![(3, Vec3::ZERO, 1.0), (3, Vec3::ONE, 1.0)]);
    let err = ShadowMaps::new(
        &renderer,
        None,
        &twice,
        layers.clone(),
        &camera(),
        ShadowSettings::default(),
    )
    .expect_err("refused");
    assert_eq!(err.to_string(), "shadow slice 3 is given to two lights");
    let huge = ShadowLights::Point(vec![(100_000, Vec3::ZERO, 1.0)]);
    let err = ShadowMaps::new(
        &renderer,
        None,
        &huge,
        layers.clone(),
        &camera(),
        ShadowSettings::default(),
    )
    .expect_err("refused");
    assert!(
        err.to_string()
            .starts_with("shadow slice 100000 is too high"),
        "{err}"
    );
    let tiny = ShadowSettings {
        resolution: 4,
        ..Default::default()
    };
    let one = ShadowLights::Point(vec![(0, Vec3::ZERO, 1.0)]);
    assert!(ShadowMaps::new(&renderer, None, &one, layers, &camera(), tiny).is_err());
}

/// A layer of just the floor (nothing to cast a shadow on it but itself).
fn floor_only(renderer: &Renderer) -> Vec<Arc<Layer>> {
    let layers = casters(renderer, Vec3::new(0.0, -50.0, 0.0));
    // The ball sits far below the floor, out of every light's way.
    layers
}

#[test]
fn no_acne_at_grazing_angles_and_no_seams_at_cascade_borders_with_the_default_biases() {
    let renderer = test_renderer();
    let layers = floor_only(&renderer);
    // A sun 10 degrees above the horizon over a bare floor: nothing shadows
    // it, so every pixel must be as lit as without shadows, across all cascades.
    let sun = casting_sun(Vec3::new(1.0, -0.176, 0.3).normalize());
    let casting = sun_cascades(&sun, 4, 0.5, 40.0, 0.0);
    let (lit, _) = shade(
        &renderer,
        &layers,
        LightBuffer::suns(&renderer, &[sun]),
        None,
    );
    for filter in FILTERS {
        let defaults = ShadowSettings {
            filter,
            resolution: 512,
            ..Default::default()
        };
        let maps = ShadowMaps::new(
            &renderer,
            None,
            &casting,
            layers.clone(),
            &camera(),
            defaults,
        )
        .expect("valid");
        let (shadowed, _) = shade(
            &renderer,
            &layers,
            LightBuffer::suns(&renderer, &[sun]),
            Some(maps),
        );
        let dark = lit
            .pixels
            .iter()
            .zip(&shadowed.pixels)
            .filter(|(l, s)| l[0] > 1e-4 && s[0] < 0.95 * l[0])
            .count();
        assert_eq!(
            dark, 0,
            "{filter:?}: {dark} floor pixels darkened by acne or a cascade seam"
        );
    }
}

#[test]
fn a_ball_resting_on_the_floor_keeps_its_contact_shadow() {
    let renderer = test_renderer();
    // Peter-panning: too much bias lifts the shadow off the contact point. A
    // light 45 degrees up on +x throws the ball's shadow along -x, starting
    // where the ball touches the floor; seen from straight above, the floor
    // just past the ball's silhouette on -x must be dark.
    let layers = casters(&renderer, Vec3::new(0.0, 0.5, 0.0));
    let position = Vec3::new(4.0, 4.0, 0.0);
    let spot = SpotLight {
        shadow: Some(0),
        ..SpotLight::cone(position, -position, 12.0, 0.4, 0.5).with_light(Vec3::ONE, 300.0)
    };
    let lights = LightBuffer::spots(&renderer, &[spot], None).expect("valid");
    let casting = ShadowLights::Spot(vec![(0, spot.view, spot.projection)]);
    let top_down = CameraInput {
        view: glam::camera::rh::view::look_at_mat4(
            Vec3::new(0.0, 8.0, 0.0),
            Vec3::ZERO,
            Vec3::NEG_Z,
        ),
        projection: glam::camera::rh::proj::directx::perspective(0.6, 1.0, 0.1, 50.0),
    };
    // Diffuse and specular: the ball's shadow darkens both.
    let diffuse = |shadows| shade_from(&renderer, top_down, &layers, lights.clone(), shadows).0;
    let lit = diffuse(None);
    // The ball's silhouette is ~7 pixels in radius; its shadow reaches ~0.9
    // units (~12 pixels) along -x. Pixels 8 to 11 left of the centre.
    let row = (SIZE.1 / 2) * SIZE.0;
    let near: Vec<usize> = (8..=11)
        .map(|dx| (row + SIZE.0 / 2 - dx) as usize)
        .collect();
    assert!(
        near.iter().all(|&i| lit.pixels[i][0] > 1e-3),
        "the floor there is lit without shadows"
    );
    for filter in FILTERS {
        let maps = ShadowMaps::new(
            &renderer,
            None,
            &casting,
            layers.clone(),
            &top_down,
            settings(filter),
        )
        .expect("valid");
        let shadowed = diffuse(Some(maps));
        for &i in &near {
            assert!(
                shadowed.pixels[i][0] < 0.5 * lit.pixels[i][0],
                "{filter:?}: pixel {} left of centre is in the contact shadow ({} vs {})",
                SIZE.0 / 2 - (i as u32 - row),
                shadowed.pixels[i][0],
                lit.pixels[i][0]
            );
        }
    }
}

#[test]
fn a_one_sided_plane_facing_away_from_the_light_still_casts_on_either_rasterizer() {
    use spreadlight_render::mesh::primitives::{GridParams, grid};
    let renderer = test_renderer();
    let mut layers = casters(&renderer, Vec3::new(0.0, -50.0, 0.0));
    // A 2 x 2 roof at y = 2, turned upside down: its front faces the floor, its back the light.
    let roof = renderer
        .meshes
        .upload(
            &renderer.gpu,
            &grid(GridParams {
                size: glam::Vec2::splat(2.0),
                resolution_x: 1,
                resolution_y: 1,
            }),
        )
        .expect("upload");
    let t = glam::Mat4::from_translation(Vec3::new(0.0, 2.0, 0.0))
        * glam::Mat4::from_rotation_x(std::f32::consts::PI);
    layers.push(one_instance(roof, t));
    let spot = SpotLight {
        shadow: Some(0),
        ..SpotLight::cone(Vec3::new(0.0, 6.0, 0.0), Vec3::NEG_Y, 12.0, 0.5, 0.7)
            .with_light(Vec3::ONE, 300.0)
    };
    let lights = LightBuffer::spots(&renderer, &[spot], None).expect("valid");
    let casting = ShadowLights::Spot(vec![(0, spot.view, spot.projection)]);
    let (lit, _) = shade(&renderer, &layers, lights.clone(), None);
    for raster in [RasterChoice::Compute, RasterChoice::Hardware] {
        let maps = maps_drawn_by(&renderer, &casting, &layers, raster, ShadowFilter::Raw);
        let (shadowed, _) = shade(&renderer, &layers, lights.clone(), Some(maps));
        let (cx, cy) = (SIZE.0 / 2, SIZE.1 / 2);
        assert!(
            luminance(&shadowed, cx, cy) < 0.25 * luminance(&lit, cx, cy),
            "{raster:?}: the roof's shadow is under it"
        );
    }
}

#[test]
fn a_node_changing_its_cascades_or_slices_never_reuses_a_store_of_another_layout() {
    let renderer = test_renderer();
    let layers = casters(&renderer, Vec3::new(0.0, 1.5, 0.0));
    let sun = |shadow| SunLight {
        direction: Vec3::NEG_Y,
        color: Vec3::ONE,
        illuminance: 5.0,
        shadow,
    };
    // The same node (owner 11): first 4 cascades and no casting sun, then 1
    // cascade and a casting one (1 layer both times), then 2 suns x 3 and 3 x 2.
    let cascades = |count| Cascades {
        count,
        split_lambda: 0.5,
        distance: 30.0,
        step: 0.0,
    };
    let steps: [(Vec<(u32, Vec3)>, u32); 4] = [
        (vec![], 4),
        (vec![(0, Vec3::NEG_Y)], 1),
        (vec![(0, Vec3::NEG_Y), (1, Vec3::NEG_X)], 3),
        (
            vec![(0, Vec3::NEG_Y), (1, Vec3::NEG_X), (2, Vec3::NEG_Z)],
            2,
        ),
    ];
    for (lights, count) in steps {
        let suns: Vec<SunLight> = lights.iter().map(|(s, _)| sun(Some(*s))).collect();
        let buffer = LightBuffer::suns(&renderer, &suns);
        let maps = ShadowMaps::new(
            &renderer,
            Some(11),
            &ShadowLights::Sun {
                lights: lights.clone(),
                cascades: cascades(count),
            },
            layers.clone(),
            &camera(),
            settings(ShadowFilter::Raw),
        )
        .expect("valid");
        let (_, report) = shade(&renderer, &layers, buffer, Some(maps));
        assert_eq!(report.counter("shadow maps rendered"), lights.len() as u64);
    }
    // A slice so high its layers overflow u32 is an error, not a panic.
    let err = ShadowMaps::new(
        &renderer,
        None,
        &ShadowLights::Point(vec![(u32::MAX, Vec3::ZERO, 1.0)]),
        layers,
        &camera(),
        ShadowSettings::default(),
    )
    .expect_err("refused");
    assert!(err.to_string().contains("too high"), "{err}");
}

/// A ball of radius 0.4 that moves: each frame a layer of its own, new, as
/// a node upstream of it makes it.
struct Ball(Arc<spreadlight_render::mesh_arena::GpuMesh>);

impl Ball {
    fn new(renderer: &Renderer) -> Ball {
        Ball(
            renderer
                .meshes
                .upload(
                    &renderer.gpu,
                    &spreadlight_render::mesh::primitives::sphere(
                        spreadlight_render::mesh::primitives::SphereParams {
                            radius: 0.4,
                            sectors: 16,
                            stacks: 8,
                        },
                    ),
                )
                .expect("upload"),
        )
    }

    /// This frame's layer: the ball at `at`.
    fn at(&self, at: Vec3) -> Arc<Layer> {
        one_instance(self.0.clone(), glam::Mat4::from_translation(at))
    }
}

#[test]
fn still_casters_are_cached_and_only_moving_ones_drawn_over_them_with_the_same_image() {
    let renderer = test_renderer();
    let spot = SpotLight {
        shadow: Some(0),
        ..SpotLight::cone(Vec3::new(0.0, 6.0, 0.0), Vec3::NEG_Y, 12.0, 0.7, 0.8)
            .with_light(Vec3::ONE, 300.0)
    };
    let lights = LightBuffer::spots(&renderer, &[spot], None).expect("valid");
    let casting = ShadowLights::Spot(vec![(0, spot.view, spot.projection)]);
    // The floor and a ball stay; a second ball, half over the first in the
    // light's view, moves each frame (a layer of its own, new every frame, as
    // a node upstream of it makes it).
    let still = casters(&renderer, Vec3::new(0.0, 1.5, 0.0));
    let ball = Ball::new(&renderer);
    let moving = |x: f32| ball.at(Vec3::new(x, 1.2, 0.3));
    // PCF, and VSM, whose moments are filtered again about the moving ball.
    let filters = [
        ShadowFilter::Pcf { kernel: 3 },
        ShadowFilter::Vsm {
            bleeding: 0.2,
            blur: 2,
        },
    ];
    let cases = [RasterChoice::Compute, RasterChoice::Hardware]
        .into_iter()
        .flat_map(|raster| filters.map(|filter| (raster, filter)));
    for (case, (raster, filter)) in cases.enumerate() {
        let owner = 21 + case as u32;
        let maps = |layers: &[Arc<Layer>], owner| {
            ShadowMaps::new(
                &renderer,
                owner,
                &casting,
                layers.to_vec(),
                &camera(),
                ShadowSettings {
                    raster,
                    ..settings(filter)
                },
            )
            .expect("valid")
        };
        // Where the ball is each frame, the decision counted, and a counter
        // that must stay 0. Frames 0-3: every caster is new, so all are drawn
        // together; the ball moved, so the rest is cached and the ball drawn
        // over it; then the cache serves and only the ball is drawn. 4-7: the
        // ball leaves the spot's view: drawn over the cache once more (its
        // shadow must go), then the map is its cache and is reused while the
        // ball moves elsewhere; back in view, drawn over again. Drawn over
        // the cache a frame after the map was drawn through the same view,
        // only the texels about the ball are drawn: where it was then and
        // where it is now (the last column).
        let over = "shadow maps drawn over cached still casters";
        let cached = "shadow maps still casters cached";
        let elsewhere = "shadow maps reused, moving casters elsewhere";
        let steps = [
            (0.5, "shadow maps rendered", "shadow maps reused", 0),
            (0.6, cached, "shadow maps reused", 0),
            (0.7, over, cached, 1),
            (0.8, over, cached, 1),
            (40.0, over, elsewhere, 1),
            (41.0, elsewhere, over, 0),
            (42.0, elsewhere, over, 0),
            (0.5, over, elsewhere, 1),
        ];
        for (frame, (x, counted, not_counted, about)) in steps.into_iter().enumerate() {
            let layers = [still[0].clone(), moving(x)];
            let (image, report) = shade(
                &renderer,
                &layers,
                lights.clone(),
                Some(maps(&layers, Some(owner))),
            );
            assert_eq!(
                (
                    report.counter(counted),
                    report.counter(not_counted),
                    report.counter("shadow layers drawn about moving casters")
                ),
                (1, 0, about),
                "{raster:?} {filter:?}, frame {frame} (ball at x = {x}): {:?}",
                report.counters
            );
            if about > 0 {
                // A corner of the map, where the ball never was.
                assert!(
                    report.counter("shadow texels drawn") < 64 * 64,
                    "{raster:?} {filter:?}, frame {frame}: {:?}",
                    report.counters
                );
            }
            // The same frame drawn whole, by a recipe with no node (nothing cached).
            let (whole, _) = shade(
                &renderer,
                &layers,
                lights.clone(),
                Some(maps(&layers, None)),
            );
            assert!(
                image.pixels == whole.pixels,
                "{raster:?} {filter:?}, frame {frame}: the same image as drawing everything"
            );
            let (cx, cy) = (SIZE.0 / 2, SIZE.1 / 2);
            assert!(
                luminance(&image, cx, cy) < luminance(&image, cx + SIZE.0 / 3, cy),
                "{raster:?} {filter:?}, frame {frame}: the still ball shades the floor under it"
            );
        }
        // Nothing moves any more: the whole map is reused, as before.
        let layers = [still[0].clone(), moving(0.9)];
        shade(
            &renderer,
            &layers,
            lights.clone(),
            Some(maps(&layers, Some(owner))),
        );
        let (_, report) = shade(
            &renderer,
            &layers,
            lights.clone(),
            Some(maps(&layers, Some(owner))),
        );
        assert_eq!(
            report.counter("shadow maps reused"),
            1,
            "{raster:?}: {:?}",
            report.counters
        );
    }
}

/// Conventional depth of two renderings of the same maps, layer by layer:
/// texels both draw differ by at most SCROLL_DEPTH_ERROR, and at most
/// SCROLL_COVERAGE of the texels are drawn by one and not the other (a
/// silhouette's texel centre on an edge, where the two views' rounding
/// differs). Returns the worst depth difference.
fn assert_scrolled_depths_agree(scrolled: &[ImageF32], whole: &[ImageF32], what: &str) -> f32 {
    const SCROLL_DEPTH_ERROR: f32 = 1e-5;
    const SCROLL_COVERAGE: f64 = 0.002;
    assert_eq!(scrolled.len(), whole.len(), "{what}: layers");
    let (mut one_only, mut texels, mut both) = (0usize, 0usize, 0usize);
    let mut worst = 0.0f32;
    for (s, w) in scrolled.iter().zip(whole) {
        for (a, b) in s.pixels.iter().zip(&w.pixels) {
            let (a, b) = (a[0], b[0]);
            assert!(
                (0.0..=1.0).contains(&a) && (0.0..=1.0).contains(&b),
                "{what}: a map holds {a} / {b}"
            );
            texels += 1;
            if a < 1.0 && b < 1.0 {
                both += 1;
                worst = worst.max((a - b).abs());
            } else if (a - b).abs() > SCROLL_DEPTH_ERROR {
                // (A caster at the far plane, 1 - 6e-8, is drawn or clipped
                // as rounding goes: the same as nothing there.)
                one_only += 1;
            }
        }
    }
    eprintln!(
        "{what}: worst {worst:.2e} over {both} texels; {one_only} of {texels} drawn by one only"
    );
    assert!(both > 0, "{what}: the casters are in the maps");
    assert!(
        worst <= SCROLL_DEPTH_ERROR,
        "{what}: a scrolled texel differs from a whole drawing by {worst}"
    );
    assert!(
        (one_only as f64) <= SCROLL_COVERAGE * texels as f64,
        "{what}: {one_only} of {texels} texels are drawn by one only"
    );
    worst
}

/// Shadow maps of `casting` through `raster` at `resolution` with `filter`,
/// seen for `camera`, kept under `owner` (None: drawn whole, nothing kept).
fn maps_of<'r>(
    renderer: &'r Renderer,
    casting: &'r ShadowLights,
    raster: RasterChoice,
    resolution: u32,
    filter: ShadowFilter,
) -> impl Fn(&CameraInput, Option<u32>, &[Arc<Layer>]) -> Arc<ShadowMaps> + 'r {
    let settings = ShadowSettings {
        raster,
        resolution,
        ..settings(filter)
    };
    move |camera, owner, layers| {
        ShadowMaps::new(renderer, owner, casting, layers.to_vec(), camera, settings)
            .expect("valid shadows")
    }
}

/// The floor and ball under a casting sun from the upper left: the casters,
/// the sun and its light buffer.
fn sun_scene(renderer: &Renderer) -> (Vec<Arc<Layer>>, SunLight, Arc<LightBuffer>) {
    let sun = casting_sun(Vec3::new(-0.2, -1.0, -0.1));
    let lights = LightBuffer::suns(renderer, &[sun]);
    (casters(renderer, Vec3::new(0.0, 1.5, 0.0)), sun, lights)
}

/// No layer of the frame drawn whole, and at most a `share`th of `texels`
/// (the layers it changed, whole) drawn.
fn assert_drawn_in_parts(report: &FrameReport, texels: u64, share: u64, what: &str) {
    assert_eq!(
        report.counter("shadow layers drawn whole"),
        0,
        "{what}: {:?}",
        report.counters
    );
    assert!(
        report.counter("shadow texels drawn") * share <= texels,
        "{what}: {:?}",
        report.counters
    );
}

/// The image `whole` (maps from a recipe with no node) shades, and its depth.
fn drawn_whole(
    renderer: &Renderer,
    (camera, layers, lights): (CameraInput, &[Arc<Layer>], &Arc<LightBuffer>),
    whole: &Arc<ShadowMaps>,
) -> (ImageF32, Vec<ImageF32>) {
    let (image, _) = shade_from(
        renderer,
        camera,
        layers,
        lights.clone(),
        Some(whole.clone()),
    );
    let depth = whole
        .read_depth(&renderer.gpu)
        .expect("reads")
        .expect("rendered");
    (image, depth)
}

/// A frame's `image` and maps' `depth` against `whole`, the same frame's
/// maps from a recipe with no node (drawn whole): the depths agree as
/// [`assert_scrolled_depths_agree`] asks, and the images within 0.1% of the
/// brightest pixel.
fn assert_as_drawn_whole(
    renderer: &Renderer,
    (camera, layers, lights): (CameraInput, &[Arc<Layer>], &Arc<LightBuffer>),
    (image, depth): (&ImageF32, &[ImageF32]),
    whole: &Arc<ShadowMaps>,
    what: &str,
) {
    let (whole_image, whole_depth) = drawn_whole(renderer, (camera, layers, lights), whole);
    assert_scrolled_depths_agree(depth, &whole_depth, what);
    let worst = image
        .pixels
        .iter()
        .zip(&whole_image.pixels)
        .map(|(a, b)| (a[0] - b[0]).abs().max((a[1] - b[1]).abs()))
        .fold(0.0f32, f32::max);
    let peak = whole_image
        .pixels
        .iter()
        .map(|p| p[0])
        .fold(0.0f32, f32::max);
    assert!(
        worst <= 1e-3 * peak,
        "{what}: the maps shade as the whole ones ({worst} of {peak})"
    );
}

/// A still camera jittered every frame (TAA's sub-pixel offsets): the sun's
/// cascades hold their boxes, so its maps are drawn once and reused while
/// nothing moves, where snapped afresh a cascade near a texel's edge flipped
/// between two places and was scrolled or drawn every frame.
#[test]
fn a_jittering_still_camera_reuses_its_sun_cascades() {
    let renderer = test_renderer();
    let (layers, sun, lights) = sun_scene(&renderer);
    let casting = sun_cascades(&sun, 4, 0.6, 30.0, 0.0);
    let (raster, pcf) = (
        ShadowSettings::default().raster,
        ShadowFilter::Pcf { kernel: 3 },
    );
    for (owner, resolution) in [(110, 256), (111, 1024)] {
        let mut drawn_after_first = 0;
        for frame in 0..16u64 {
            let mut camera = camera();
            camera.projection = spreadlight_render::camera::jittered(
                camera.projection,
                // A 1080p frame's jitter (what TAA moves the projection by).
                spreadlight_render::camera::jitter_ndc(frame, (1920, 1080)),
            );
            let maps = maps_of(&renderer, &casting, raster, resolution, pcf)(
                &camera,
                Some(owner),
                &layers,
            );
            let (image, report) =
                shade_from(&renderer, camera, &layers, lights.clone(), Some(maps));
            assert!(image.all_finite());
            if frame > 0 {
                drawn_after_first += report.counter("shadow texels drawn")
                    + report.counter("shadow texels kept by scrolling");
            }
        }
        assert_eq!(drawn_after_first, 0, "{resolution}: maps drawn again");
    }
}

/// A camera panning while a ball moves over a still scene: the sun's still
/// casters' cache scrolls with the maps (only its new strips drawn from the
/// still casters), and the maps are drawn over it only in those strips and
/// about the ball, where it was and where it is. What the maps hold and the
/// shadows they cast are what drawing them whole gives, on both rasterizers.
#[test]
fn a_panning_camera_scrolls_the_still_cache_and_draws_the_moving_ball_alone() {
    let renderer = test_renderer();
    let floor = casters(&renderer, Vec3::new(0.0, 1.5, 0.0));
    let ball = Ball::new(&renderer);
    let moving = |x: f32| ball.at(Vec3::new(x, 1.0, 1.0));
    let sun = casting_sun(Vec3::new(-0.2, -1.0, -0.1));
    let lights = LightBuffer::suns(&renderer, &[sun]);
    let casting = sun_cascades(&sun, 3, 0.6, 30.0, 0.0);
    const RES: u64 = 128;
    let vsm = ShadowFilter::Vsm {
        bleeding: 0.2,
        blur: 2,
    };
    let cases = [
        (RasterChoice::Compute, ShadowFilter::Pcf { kernel: 3 }),
        (RasterChoice::Compute, vsm),
        (RasterChoice::Hardware, vsm),
    ];
    for (case, (raster, filter)) in cases.into_iter().enumerate() {
        let owner = Some(90 + case as u32);
        let what = format!("{raster:?} {filter:?}");
        let maps = maps_of(&renderer, &casting, raster, RES as u32, filter);
        // Frames 0 and 1 from a still camera: the still casters' cache is
        // made; then the camera pans and the ball moves every frame.
        let steps = [
            (0.0, -1.0),
            (0.0, -0.9),
            (0.2, -0.8),
            (0.4, -0.7),
            (0.6, -0.6),
        ];
        for (k, (pan, x)) in steps.into_iter().enumerate() {
            let camera = camera_moved(pan);
            let layers = [floor[0].clone(), moving(x)];
            let m = maps(&camera, owner, &layers);
            let (image, report) =
                shade_from(&renderer, camera, &layers, lights.clone(), Some(m.clone()));
            let counted = |name: &str| report.counter(name);
            if k >= 2 {
                let n = counted("shadow layers scrolled over still casters");
                assert!(n >= 1, "{what}, frame {k}: {:?}", report.counters);
                // The still casters' strips and the map's strips and ball:
                // a small part of drawing the layers whole.
                assert_drawn_in_parts(&report, n * RES * RES, 3, &format!("{what}, frame {k}"));
            }
            let depth = m
                .read_depth(&renderer.gpu)
                .expect("reads")
                .expect("rendered");
            // The same frame drawn whole, by a recipe with no node.
            let whole = maps(&camera, None, &layers);
            assert_as_drawn_whole(
                &renderer,
                (camera, &layers, &lights),
                (&image, &depth),
                &whole,
                &format!("{what}, frame {k}"),
            );
        }
    }
}

/// A camera panning over a still scene: a sun's cascades scroll (their kept
/// texels copied, only the uncovered strips drawn, counted), and what they
/// hold, and the shadows they cast through PCF and VSM, are what drawing
/// them whole gives, on both rasterizers. A still camera then draws nothing;
/// a moving caster, a camera jumping further than a cascade, and a camera at
/// NaN or infinity draw whole and never put NaN in the maps or the image.
#[test]
fn a_panning_camera_scrolls_sun_cascades_and_draws_only_their_new_strips() {
    let renderer = test_renderer();
    let (layers, sun, lights) = sun_scene(&renderer);
    let casting = sun_cascades(&sun, 3, 0.6, 30.0, 0.0);
    // Small maps: the compute rasterizer runs on the CPU here (lavapipe).
    const RES: u64 = 128;
    let vsm = ShadowFilter::Vsm {
        bleeding: 0.2,
        blur: 2,
    };
    // PCF reads the depth alone, VSM its moments too: each rasterizer's
    // strips under VSM, and compute (the GPUs' default) under PCF as well.
    let mut owner = 60;
    for (raster, filters) in [
        (
            RasterChoice::Compute,
            vec![ShadowFilter::Pcf { kernel: 3 }, vsm],
        ),
        (RasterChoice::Hardware, vec![vsm]),
    ] {
        for filter in filters {
            owner += 1;
            let what = format!("{raster:?} {filter:?}");
            let maps = maps_of(&renderer, &casting, raster, RES as u32, filter);
            // A frame of the node's maps seen from `camera`: its image, report and depth.
            let frame =
                |camera: CameraInput, shadow_camera: &CameraInput, layers: &[Arc<Layer>]| {
                    let m = maps(shadow_camera, Some(owner), layers);
                    let (image, report) =
                        shade_from(&renderer, camera, layers, lights.clone(), Some(m.clone()));
                    let depth = m
                        .read_depth(&renderer.gpu)
                        .expect("reads")
                        .expect("rendered");
                    (image, report, depth)
                };
            let (_, first, _) = frame(camera_moved(0.0), &camera_moved(0.0), &layers);
            assert_eq!(first.counter("shadow layers drawn whole"), 3, "{what}");
            assert_eq!(
                first.counter("shadow texels drawn"),
                3 * RES * RES,
                "{what}"
            );
            let mut scrolled = 0;
            for k in 1..=3 {
                let camera = camera_moved(k as f32 * 0.2);
                let (image, report, depth) = frame(camera, &camera, &layers);
                let counted = |name: &str| report.counter(name);
                // Every cascade that changed scrolled; none was drawn whole,
                // and the strips are a small part of what drawing them whole takes.
                let n = counted("shadow layers scrolled");
                assert_drawn_in_parts(&report, n * RES * RES, 4, &format!("{what}, frame {k}"));
                assert_eq!(
                    counted("shadow texels drawn") + counted("shadow texels kept by scrolling"),
                    n * RES * RES,
                    "{what}, frame {k}"
                );
                scrolled += n;
                // The same frame drawn whole, by a recipe with no node.
                let whole = maps(&camera, None, &layers);
                assert_as_drawn_whole(
                    &renderer,
                    (camera, &layers, &lights),
                    (&image, &depth),
                    &whole,
                    &format!("{what}, frame {k}"),
                );
            }
            // The finest cascade moves a few texels a frame here: it scrolls every time.
            assert!(scrolled >= 3, "{what}: {scrolled} cascades scrolled");
            // A still camera over a still scene: nothing is drawn.
            let still = camera_moved(0.6);
            let (_, report, _) = frame(still, &still, &layers);
            assert_eq!(
                report.counter("shadow maps reused"),
                1,
                "{what}: {:?}",
                report.counters
            );
            assert_eq!(report.counter("shadow texels drawn"), 0, "{what}");
            // A moving caster (a layer new this frame) draws the cascades whole.
            let moved = casters(&renderer, Vec3::new(0.3, 1.5, 0.0));
            let panned = camera_moved(0.75);
            let (_, report, _) = frame(panned, &panned, &moved);
            assert_eq!(report.counter("shadow layers scrolled"), 0, "{what}");
            assert_eq!(report.counter("shadow layers drawn whole"), 3, "{what}");
            // A jump further than any cascade is wide: drawn whole.
            let far = camera_moved(500.0);
            let (_, report, _) = frame(far, &far, &moved);
            assert_eq!(report.counter("shadow layers scrolled"), 0, "{what}");
            assert_eq!(report.counter("shadow layers drawn whole"), 3, "{what}");
            // Cascades following a camera at NaN or infinity: no NaN in the
            // maps or the image (the image seen from a sound camera), and
            // whatever the next sound frame keeps of them, its maps are what
            // drawing them whole gives.
            for broken in [f32::NAN, f32::INFINITY] {
                let (image, _, depth) = frame(camera_moved(0.0), &camera_moved(broken), &moved);
                assert!(image.all_finite(), "{what}, camera at {broken}");
                assert!(
                    depth
                        .iter()
                        .all(|l| l.pixels.iter().all(|p| (0.0..=1.0).contains(&p[0]))),
                    "{what}, camera at {broken}: the maps hold depths"
                );
                let (_, _, depth) = frame(camera_moved(0.0), &camera_moved(0.0), &moved);
                let whole = maps(&camera_moved(0.0), None, &moved);
                let (_, whole_depth) =
                    drawn_whole(&renderer, (camera_moved(0.0), &moved, &lights), &whole);
                assert_scrolled_depths_agree(
                    &depth,
                    &whole_depth,
                    &format!("{what}, after {broken}"),
                );
            }
        }
    }
}
