//! Shadow-map layers rasterized together (`SPREADLIGHT_SHADOW_LAYERS=together`,
//! `shadows::ShadowLayers`) against one raster chain per layer (`each`):
//! a sun's four cascades, eight spots and a point light's six cube faces,
//! whole and as a panning camera's scrolled strips, and a still cache with
//! moving casters drawn over it, hold the same depth bit for bit, and shade
//! the same image (VSM's moments, computed in one dispatch, included). A
//! static scene still renders no map after its first frame.

use std::sync::Arc;

use glam::Vec3;
use spreadlight_render::camera::CameraInput;
use spreadlight_render::gbuffer::{Layer, RasterChoice};
use spreadlight_render::lighting::{LightBuffer, PointLight, SpotLight, SunLight};
use spreadlight_render::readback::ImageF32;
use spreadlight_render::renderer::test_renderer;
use spreadlight_render::scenes::balls_on_floor;
use spreadlight_render::shadows::{
    Cascades, ShadowFilter, ShadowLayers, ShadowLights, ShadowMaps, ShadowSettings,
    set_shadow_layers,
};
use spreadlight_render::{FrameReport, Renderer};

const SIZE: (u32, u32) = (48, 48);
/// Small maps: the compute rasterizer runs on the CPU here (lavapipe).
const RES: u32 = 96;
const TOGETHER: &str = "shadow layers rasterized together";
const CHAINS: &str = "shadow raster chains";

/// Balls of radius 0.5 at `balls` over a 20 x 20 floor at y = 0.
fn casters(renderer: &Renderer, balls: &[Vec3]) -> Vec<Arc<Layer>> {
    let balls: Vec<(Vec3, f32)> = balls.iter().map(|&b| (b, 0.5)).collect();
    vec![balls_on_floor(renderer, &balls, 20.0, 16).expect("upload")]
}

/// Looking down at the floor's centre from above and in front, moved `dx` along +X.
fn camera(dx: f32) -> CameraInput {
    CameraInput {
        view: glam::camera::rh::view::look_at_mat4(Vec3::new(0.0, 8.0, 6.0), Vec3::ZERO, Vec3::Y)
            * glam::Mat4::from_translation(Vec3::new(-dx, 0.0, 0.0)),
        projection: glam::camera::rh::proj::directx::perspective(1.0, 1.0, 0.1, 50.0),
    }
}

/// The lit image (diffuse + specular) of `layers` seen from `camera` and the frame's report.
fn shade(
    renderer: &Renderer,
    camera: CameraInput,
    layers: &[Arc<Layer>],
    lights: Arc<LightBuffer>,
    shadows: Arc<ShadowMaps>,
) -> (ImageF32, FrameReport) {
    super::shadows::shade_sized(renderer, camera, layers, lights, Some(shadows), SIZE)
}

/// A frame of `casting`'s maps kept under `owner`, drawn by the compute
/// rasterizer `layers` way through `filter`: its image, report and depth.
#[allow(clippy::too_many_arguments)]
fn frame(
    renderer: &Renderer,
    layers: ShadowLayers,
    owner: u32,
    casting: &ShadowLights,
    lights: &Arc<LightBuffer>,
    casters: &[Arc<Layer>],
    view: CameraInput,
    filter: ShadowFilter,
) -> (ImageF32, FrameReport, Vec<ImageF32>) {
    set_shadow_layers(renderer, layers);
    let maps = ShadowMaps::new(
        renderer,
        Some(owner),
        casting,
        casters.to_vec(),
        &view,
        ShadowSettings {
            resolution: RES,
            filter,
            raster: RasterChoice::Compute,
            ..Default::default()
        },
    )
    .expect("valid shadows");
    assert!(maps.compute_raster());
    let (image, report) = shade(renderer, view, casters, lights.clone(), maps.clone());
    let depth = maps
        .read_depth(&renderer.gpu)
        .expect("reads")
        .expect("rendered");
    (image, report, depth)
}

/// Both ways' depths are the same bits, layer by layer, and something was drawn.
fn assert_same_depth(each: &[ImageF32], together: &[ImageF32], what: &str) {
    assert_eq!(each.len(), together.len(), "{what}: layers");
    let mut drawn = 0;
    for (layer, (a, b)) in each.iter().zip(together).enumerate() {
        let differ = a
            .pixels
            .iter()
            .zip(&b.pixels)
            .filter(|(p, q)| p[0].to_bits() != q[0].to_bits())
            .count();
        assert_eq!(differ, 0, "{what}: layer {layer}: {differ} texels differ");
        drawn += a.pixels.iter().filter(|p| p[0] < 1.0).count();
    }
    assert!(drawn > 0, "{what}: the casters are in the maps");
}

fn sun() -> SunLight {
    SunLight {
        direction: Vec3::new(-0.2, -1.0, -0.1),
        color: Vec3::ONE,
        illuminance: 5.0,
        shadow: Some(0),
    }
}

fn four_cascades(sun: &SunLight) -> ShadowLights {
    ShadowLights::Sun {
        lights: vec![(0, sun.direction)],
        cascades: Cascades {
            count: 4,
            split_lambda: 0.6,
            distance: 30.0,
            step: 0.0,
        },
    }
}

/// A sun's four cascades, eight spots and a point light's cube faces,
/// each through PCF and VSM: the same depth and image either way; together,
/// every layer is one chain, counted.
#[test]
fn every_layer_rasterized_together_holds_the_depth_each_alone_gives() {
    let renderer = test_renderer();
    let casters = casters(
        &renderer,
        &[Vec3::new(0.0, 1.5, 0.0), Vec3::new(2.0, 0.8, -1.0)],
    );
    let sun = sun();
    let spots: Vec<SpotLight> = (0..8)
        .map(|k| {
            let angle = k as f32 * std::f32::consts::TAU / 8.0;
            let at = Vec3::new(3.0 * angle.cos(), 6.0, 3.0 * angle.sin());
            SpotLight {
                shadow: Some(k),
                ..SpotLight::cone(at, (Vec3::ZERO - at).normalize(), 14.0, 0.5, 0.7)
                    .with_light(Vec3::ONE, 40.0)
            }
        })
        .collect();
    let point = PointLight {
        position: Vec3::new(0.5, 4.0, 0.5),
        color: Vec3::ONE,
        intensity: 300.0,
        range: 15.0,
        shadow: Some(0),
    };
    let cases = [
        (
            "sun, 4 cascades",
            LightBuffer::suns(&renderer, &[sun]),
            four_cascades(&sun),
            4,
        ),
        (
            "8 spots",
            LightBuffer::spots(&renderer, &spots, None).expect("valid"),
            ShadowLights::Spot(
                spots
                    .iter()
                    .map(|s| (s.shadow.unwrap_or(0), s.view, s.projection))
                    .collect(),
            ),
            8,
        ),
        (
            "point light",
            LightBuffer::points(&renderer, &[point]),
            ShadowLights::Point(vec![(0, point.position, point.range)]),
            6,
        ),
    ];
    let mut owner = 100;
    for (name, lights, casting, layers) in cases {
        for filter in [
            ShadowFilter::Pcf { kernel: 3 },
            ShadowFilter::Vsm {
                bleeding: 0.2,
                blur: 2,
            },
        ] {
            let what = format!("{name} {filter:?}");
            let mut runs = Vec::new();
            for way in [ShadowLayers::Each, ShadowLayers::Together] {
                owner += 1;
                let run = frame(
                    &renderer,
                    way,
                    owner,
                    &casting,
                    &lights,
                    &casters,
                    camera(0.0),
                    filter,
                );
                let together = if way == ShadowLayers::Together {
                    (layers, 1)
                } else {
                    (0, 0)
                };
                assert_eq!(
                    (run.1.counter(TOGETHER), run.1.counter(CHAINS)),
                    together,
                    "{what} {way:?}: {:?}",
                    run.1.counters
                );
                runs.push(run);
            }
            assert_same_depth(&runs[0].2, &runs[1].2, &what);
            assert!(
                runs[0].0.pixels == runs[1].0.pixels,
                "{what}: the same image either way"
            );
        }
    }
}

/// A panning camera scrolls the sun's cascades: their strips (two a
/// cascade at most) go through one chain with the cascades drawn whole,
/// and hold what drawing them one at a time holds; a still frame draws
/// nothing, and a static scene renders no map.
#[test]
fn scrolled_strips_rasterized_together_hold_the_depth_each_alone_gives() {
    let renderer = test_renderer();
    let casters = casters(&renderer, &[Vec3::new(0.0, 1.5, 0.0)]);
    let sun = sun();
    let lights = LightBuffer::suns(&renderer, &[sun]);
    let casting = four_cascades(&sun);
    let vsm = ShadowFilter::Vsm {
        bleeding: 0.2,
        blur: 1,
    };
    for (filter, owners) in [
        (ShadowFilter::Pcf { kernel: 3 }, (200, 201)),
        (vsm, (202, 203)),
    ] {
        let mut scrolled = 0;
        for k in 0..4 {
            let view = camera(k as f32 * 0.15);
            let mut runs = Vec::new();
            for (way, owner) in [
                (ShadowLayers::Each, owners.0),
                (ShadowLayers::Together, owners.1),
            ] {
                runs.push(frame(
                    &renderer, way, owner, &casting, &lights, &casters, view, filter,
                ));
            }
            let what = format!("{filter:?}, frame {k}");
            let (each, together) = (&runs[0].1, &runs[1].1);
            for counter in [
                "shadow layers scrolled",
                "shadow layers drawn whole",
                "shadow texels drawn",
            ] {
                assert_eq!(
                    each.counter(counter),
                    together.counter(counter),
                    "{what}: {counter}"
                );
            }
            let n = together.counter("shadow layers scrolled");
            scrolled += n;
            // Every layer drawn whole and every strip of each scrolled one, in one chain.
            assert!(
                together.counter(TOGETHER) >= together.counter("shadow layers drawn whole") + n,
                "{what}: {:?}",
                together.counters
            );
            assert_eq!(
                together.counter(CHAINS),
                u64::from(together.counter("shadow texels drawn") > 0),
                "{what}"
            );
            assert_same_depth(&runs[0].2, &runs[1].2, &what);
            assert!(
                runs[0].0.pixels == runs[1].0.pixels,
                "{what}: the same image either way"
            );
        }
        assert!(scrolled >= 3, "{filter:?}: {scrolled} cascades scrolled");
        // A still camera over a still scene renders no map, either way.
        for _ in 0..2 {
            let (_, report, _) = frame(
                &renderer,
                ShadowLayers::Together,
                owners.1,
                &casting,
                &lights,
                &casters,
                camera(0.45),
                filter,
            );
            assert_eq!(report.counter("shadow texels drawn"), 0, "{filter:?}");
            assert_eq!(report.counter(TOGETHER), 0, "{filter:?}");
            assert_eq!(report.counter("shadow maps rendered"), 0, "{filter:?}");
        }
    }
}

/// Still casters cached and a moving ball drawn over them: the cache's
/// chain first, then the moving casters' over it, the same depth either way.
#[test]
fn a_still_cache_and_moving_casters_over_it_hold_the_same_depth_together() {
    let renderer = test_renderer();
    let still = casters(&renderer, &[Vec3::new(0.0, 1.5, 0.0)]);
    let spots: Vec<SpotLight> = [-1.0f32, 1.0]
        .iter()
        .enumerate()
        .map(|(k, &x)| SpotLight {
            shadow: Some(k as u32),
            ..SpotLight::cone(Vec3::new(x, 6.0, 0.0), Vec3::NEG_Y, 12.0, 0.7, 0.8)
                .with_light(Vec3::ONE, 150.0)
        })
        .collect();
    let lights = LightBuffer::spots(&renderer, &spots, None).expect("valid");
    let casting = ShadowLights::Spot(
        spots
            .iter()
            .map(|s| (s.shadow.unwrap_or(0), s.view, s.projection))
            .collect(),
    );
    let mut chains = 0;
    for (frame_index, x) in [0.5f32, 0.6, 0.7, 0.8].into_iter().enumerate() {
        // A layer of its own, new every frame: moving.
        let ball = casters(&renderer, &[Vec3::new(x, 1.0, 0.3)]);
        let layers = [still[0].clone(), ball[0].clone()];
        let mut runs = Vec::new();
        for (way, owner) in [(ShadowLayers::Each, 300), (ShadowLayers::Together, 301)] {
            runs.push(frame(
                &renderer,
                way,
                owner,
                &casting,
                &lights,
                &layers,
                camera(0.0),
                ShadowFilter::Pcf { kernel: 3 },
            ));
        }
        let what = format!("frame {frame_index}");
        for counter in [
            "shadow maps rendered",
            "shadow maps still casters cached",
            "shadow maps drawn over cached still casters",
        ] {
            assert_eq!(
                runs[0].1.counter(counter),
                runs[1].1.counter(counter),
                "{what}: {counter}"
            );
        }
        chains += runs[1].1.counter(CHAINS);
        assert_same_depth(&runs[0].2, &runs[1].2, &what);
        assert!(
            runs[0].0.pixels == runs[1].0.pixels,
            "{what}: the same image"
        );
    }
    // The frame that caches the still casters draws two chains (the cache,
    // then the moving ball over it).
    assert!(chains > 4, "{chains} chains in four frames");
}
