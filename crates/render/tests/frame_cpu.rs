//! What a frame re-made from mostly unchanged inputs does not do again on
//! the CPU: a node re-makes its recipe when one input changes (one ball
//! moves among still spheres), but the still layers keep their packed
//! instances and bounds, only the changed bytes are uploaded, and the
//! passes bind the bind groups they made before. The frame report's
//! counters prove it, and the images are those of a recipe that caches
//! nothing. Small sizes; runs on lavapipe.

use std::sync::Arc;

use glam::{Mat4, Vec3};
use spreadlight_render::camera::CameraInput;
use spreadlight_render::gbuffer::{DrawBatch, GBuffer, InstanceInput, Layer};
use spreadlight_render::lighting::{CookTorrance, LightBuffer, LightLoop, SunLight, Surfaces};
use spreadlight_render::mesh::primitives::{SphereParams, sphere};
use spreadlight_render::readback::{ImageF32, render_and_read};
use spreadlight_render::renderer::test_renderer;
use spreadlight_render::shadows::{
    Cascades, ShadowFilter, ShadowLights, ShadowMaps, ShadowSettings,
};
use spreadlight_render::{FrameReport, Renderer, SizeRule};

const SIZE: (u32, u32) = (48, 48);
/// Bytes of one GPU instance (`GpuInstance`).
const INSTANCE_BYTES: u64 = 224;

fn camera() -> CameraInput {
    CameraInput {
        view: glam::camera::rh::view::look_at_mat4(Vec3::new(0.0, 6.0, 8.0), Vec3::ZERO, Vec3::Y),
        projection: glam::camera::rh::proj::directx::perspective(1.0, 1.0, 0.1, 50.0),
    }
}

/// Twenty still spheres in a row, and a ball at `x` (a layer of its own,
/// new each frame as the node upstream of it makes it).
struct Scene {
    still: Arc<Layer>,
    ball: Arc<spreadlight_render::mesh_arena::GpuMesh>,
}

impl Scene {
    fn new(renderer: &Renderer) -> Scene {
        let ball = renderer
            .meshes
            .upload(
                &renderer.gpu,
                &sphere(SphereParams {
                    radius: 0.4,
                    sectors: 16,
                    stacks: 8,
                }),
            )
            .expect("upload");
        let instances = (0..20)
            .map(|k| instance(Vec3::new(k as f32 * 0.5 - 5.0, 0.4, -1.0), Vec3::ZERO))
            .collect();
        Scene {
            still: layer(ball.clone(), instances),
            ball,
        }
    }

    fn layers(&self, x: f32) -> Vec<Arc<Layer>> {
        let moving = instance(Vec3::new(x, 1.0, 1.0), Vec3::new(0.1, 0.0, 0.0));
        vec![self.still.clone(), layer(self.ball.clone(), vec![moving])]
    }
}

fn instance(at: Vec3, moved: Vec3) -> InstanceInput {
    InstanceInput {
        transform: Mat4::from_translation(at),
        previous_transform: Mat4::from_translation(at - moved),
        color: [0.8, 0.6, 0.4, 1.0],
        material_id: 0,
        object_id: 1,
    }
}

fn layer(
    mesh: Arc<spreadlight_render::mesh_arena::GpuMesh>,
    instances: Vec<InstanceInput>,
) -> Arc<Layer> {
    Arc::new(Layer::plain(vec![DrawBatch { mesh, instances }]))
}

/// `images` (frame `frame` of a G-buffer that keeps what it can) are what
/// `fresh`, a G-buffer that keeps nothing, draws of the targets `names`.
fn same_as_fresh(
    renderer: &Renderer,
    fresh: &GBuffer,
    names: &[&str],
    images: &[ImageF32],
    frame: usize,
) {
    let (_, whole) = render_and_read(renderer, fresh, SIZE, names).expect("renders");
    for (k, (a, b)) in images.iter().zip(&whole).enumerate() {
        assert!(
            a.pixels == b.pixels,
            "frame {frame}, target {k}: the same image"
        );
    }
}

#[test]
fn a_re_made_g_buffer_packs_uploads_and_binds_only_what_its_moving_layer_changed() {
    let renderer = test_renderer();
    let scene = Scene::new(&renderer);
    let vp = camera().view_projection();
    let gbuffer = |layers: Vec<Arc<Layer>>, owner| {
        GBuffer::new(
            &renderer,
            owner,
            layers,
            camera(),
            Some(vp),
            SizeRule::Relative(1.0),
        )
    };
    for (frame, x) in [-1.0, -0.5, 0.0, 0.5].into_iter().enumerate() {
        let g = gbuffer(scene.layers(x), Some(80));
        let t = &g.targets;
        let names = [&t.color, &t.normals, &t.depth, &t.velocity_uv].map(String::as_str);
        let (report, images) =
            render_and_read(&renderer, g.as_ref(), SIZE, &names).expect("renders");
        assert!(report.errors.is_empty(), "{:?}", report.errors);
        let counters = |names: &[&str]| names.iter().map(|n| report.counter(n)).collect::<Vec<_>>();
        if frame == 0 {
            assert_eq!(
                counters(&["instance layers packed", "instance layers kept"]),
                [2, 0]
            );
        } else {
            // Only the ball's layer is packed; the still spheres' packing is kept.
            assert_eq!(
                counters(&["instance layers packed", "instance layers kept"]),
                [1, 1],
                "frame {frame}: {:?}",
                report.counters
            );
            // Of 21 instances only the ball's bytes change, and only they are written.
            let bytes = report.counter("uniform bytes uploaded");
            assert!(
                bytes > 0 && bytes <= INSTANCE_BYTES,
                "frame {frame}: {bytes} bytes uploaded: {:?}",
                report.counters
            );
            // The raster's and the resolves' groups bind the same buffers and
            // views: the raster's run (both draws in one dispatch), its tile
            // kernel's, and the resolve's.
            assert_eq!(
                report.counter("bind groups created"),
                0,
                "frame {frame}: {:?}",
                report.counters
            );
            assert!(
                report.counter("bind groups reused") >= 3,
                "{:?}",
                report.counters
            );
        }
        // The same frame from a G-buffer with no node: nothing kept, everything made.
        let fresh = gbuffer(scene.layers(x), None);
        let t = &fresh.targets;
        let names = [&t.color, &t.normals, &t.depth, &t.velocity_uv].map(String::as_str);
        same_as_fresh(&renderer, fresh.as_ref(), &names, &images, frame);
    }
}

#[test]
fn a_re_made_g_buffer_compares_only_the_instances_of_layers_that_changed_or_moved() {
    let renderer = test_renderer();
    let scene = Scene::new(&renderer);
    let still_bytes = 20 * INSTANCE_BYTES;
    let ball = |x: f32| {
        layer(
            scene.ball.clone(),
            vec![instance(Vec3::new(x, 1.0, 1.0), Vec3::X)],
        )
    };
    // The ball after the still spheres, moving; then a new ball layer in
    // front of them, so the still layer's instances lie one place later
    // (the buffer keeps its length) and must be compared and written; then
    // moving there.
    let frames: [(Vec<Arc<Layer>>, bool); 5] = [
        (scene.layers(-1.0), true),
        (scene.layers(-0.5), false),
        (scene.layers(0.0), false),
        (vec![ball(0.5), scene.still.clone()], true),
        (vec![ball(1.0), scene.still.clone()], false),
    ];
    for (frame, (layers, still_compared)) in frames.into_iter().enumerate() {
        let g = GBuffer::new(
            &renderer,
            Some(90),
            layers.clone(),
            camera(),
            None,
            SizeRule::Relative(1.0),
        );
        let t = &g.targets;
        let names = [&t.color, &t.normals, &t.depth].map(String::as_str);
        let (report, images) =
            render_and_read(&renderer, g.as_ref(), SIZE, &names).expect("renders");
        assert!(report.errors.is_empty(), "{:?}", report.errors);
        let compared = report.counter("kept bytes compared");
        if frame == 0 {
            // Made: nothing to compare the instances with.
            assert!(compared < still_bytes, "{:?}", report.counters);
        } else if still_compared {
            assert!(
                compared >= still_bytes,
                "frame {frame}: {:?}",
                report.counters
            );
        } else {
            // The ball's 224 bytes and the small uniforms, not the still spheres'.
            assert!(
                compared < still_bytes,
                "frame {frame}: {:?}",
                report.counters
            );
            assert!(report.counter("uniform bytes uploaded") <= INSTANCE_BYTES + 64);
        }
        let fresh = GBuffer::new(
            &renderer,
            None,
            layers,
            camera(),
            None,
            SizeRule::Relative(1.0),
        );
        let t = &fresh.targets;
        let names = [&t.color, &t.normals, &t.depth].map(String::as_str);
        same_as_fresh(&renderer, fresh.as_ref(), &names, &images, frame);
    }
}

/// The sun-lit diffuse of `layers` with `shadows`, and the frame's report;
/// the G-buffer and the lighting are `owner`'s (None: they keep nothing).
fn shade(
    renderer: &Renderer,
    owner: Option<u32>,
    layers: &[Arc<Layer>],
    sun: &Arc<LightBuffer>,
    shadows: Arc<ShadowMaps>,
) -> (ImageF32, FrameReport) {
    let g = GBuffer::new(
        renderer,
        owner,
        layers.to_vec(),
        camera(),
        None,
        SizeRule::Relative(1.0),
    );
    let ct = CookTorrance::with_shadows(
        renderer,
        owner.map(|o| o + 1),
        g,
        sun.clone(),
        LightLoop::Naive,
        true,
        Surfaces::PerMaterialId(vec![(0.7, 0.0)]),
        Some(shadows),
    );
    let (report, mut images) =
        render_and_read(renderer, ct.as_ref(), SIZE, &[&ct.diffuse]).expect("renders");
    assert!(report.errors.is_empty(), "{:?}", report.errors);
    (images.remove(0), report)
}

#[test]
fn a_re_made_sun_shadow_keeps_the_bounds_of_its_still_casters() {
    let renderer = test_renderer();
    let scene = Scene::new(&renderer);
    // The same frames drawn whole, on a renderer of their own: frames drawn
    // in between would take the pooled textures the cached frames bind.
    let whole_renderer = test_renderer();
    let whole_scene = Scene::new(&whole_renderer);
    let sun = SunLight {
        direction: Vec3::new(0.3, -1.0, 0.2).normalize(),
        color: Vec3::ONE,
        illuminance: 5.0,
        shadow: Some(0),
    };
    let lights = LightBuffer::suns(&renderer, &[sun]);
    let whole_lights = LightBuffer::suns(&whole_renderer, &[sun]);
    let casting = ShadowLights::Sun {
        lights: vec![(0, sun.direction)],
        cascades: Cascades {
            count: 2,
            split_lambda: 0.6,
            distance: 20.0,
            step: 0.0,
        },
    };
    let maps = |renderer: &Renderer, layers: &[Arc<Layer>], owner| {
        ShadowMaps::new(
            renderer,
            owner,
            &casting,
            layers.to_vec(),
            &camera(),
            ShadowSettings {
                resolution: 128,
                filter: ShadowFilter::Pcf { kernel: 3 },
                ..Default::default()
            },
        )
        .expect("valid shadows")
    };
    for (frame, x) in [-1.0, 0.0, 1.0, 1.5, 2.0].into_iter().enumerate() {
        let layers = scene.layers(x);
        let maps_now = maps(&renderer, &layers, Some(81));
        let (image, report) = shade(&renderer, Some(82), &layers, &lights, maps_now);
        let counted = (
            report.counter("caster bounds computed"),
            report.counter("caster bounds kept"),
        );
        let expected = if frame == 0 { (2, 0) } else { (1, 1) };
        assert_eq!(counted, expected, "frame {frame}: {:?}", report.counters);
        // Once the still casters are cached (frames 0-2: all drawn, the
        // cache drawn, the ball drawn over it), the frame makes no bind
        // group: the maps' layer views are kept, not made each frame.
        if frame >= 3 {
            assert_eq!(
                report.counter("bind groups created"),
                0,
                "frame {frame}: {:?}",
                report.counters
            );
        }
        // Maps whose bounds were all computed anew shade the same.
        let layers = whole_scene.layers(x);
        let whole_maps = maps(&whole_renderer, &layers, None);
        let (whole, _) = shade(&whole_renderer, None, &layers, &whole_lights, whole_maps);
        assert!(
            image.pixels == whole.pixels,
            "frame {frame}: the same image"
        );
    }
}

#[test]
fn a_re_made_g_buffer_writes_its_camera_only_when_the_camera_moved() {
    let renderer = test_renderer();
    let scene = Scene::new(&renderer);
    // The ball stands still: only the camera may change what is uploaded.
    let layers = scene.layers(0.0);
    let moved = |z: f32| CameraInput {
        view: glam::camera::rh::view::look_at_mat4(Vec3::new(0.0, 6.0, z), Vec3::ZERO, Vec3::Y),
        ..camera()
    };
    for (frame, z) in [8.0, 8.0, 8.0, 7.5, 7.5].into_iter().enumerate() {
        let g = GBuffer::new(
            &renderer,
            Some(90),
            layers.clone(),
            moved(z),
            None,
            SizeRule::Relative(1.0),
        );
        let names = [g.targets.color.as_str(), g.targets.depth.as_str()];
        let (report, images) =
            render_and_read(&renderer, g.as_ref(), SIZE, &names).expect("renders");
        assert!(report.errors.is_empty(), "{:?}", report.errors);
        let bytes = report.counter("uniform bytes uploaded");
        match frame {
            0 => assert!(bytes > 0, "the first frame writes its camera"),
            // Same camera, same instances: nothing is written.
            1 | 2 | 4 => assert_eq!(
                (bytes, report.counter("uniform uploads")),
                (0, 0),
                "frame {frame}: {:?}",
                report.counters
            ),
            // The camera moved: its bytes, and no instance's, are written.
            _ => assert!(
                bytes > 0 && report.counter("uniform uploads") == 1,
                "frame {frame}: {:?}",
                report.counters
            ),
        }
        // A G-buffer that keeps nothing draws the same.
        let fresh = GBuffer::new(
            &renderer,
            None,
            layers.clone(),
            moved(z),
            None,
            SizeRule::Relative(1.0),
        );
        let names = [fresh.targets.color.as_str(), fresh.targets.depth.as_str()];
        same_as_fresh(&renderer, fresh.as_ref(), &names, &images, frame);
    }
}

#[test]
fn a_re_made_g_buffer_publishes_its_depth_through_kept_bind_groups() {
    use spreadlight_render::gbuffer::{PublishedDepths, RasterChoice};
    let renderer = test_renderer();
    let scene = Scene::new(&renderer);
    let layers = scene.layers(0.0);
    let make = |name: &str| {
        GBuffer::publishing_depth(
            &renderer,
            Some(91),
            layers.clone(),
            camera(),
            None,
            SizeRule::Relative(1.0),
            RasterChoice::Auto,
            name.to_owned(),
        )
    };
    let reused = |g: &GBuffer| {
        let (report, _) =
            render_and_read(&renderer, g, SIZE, &[g.targets.color.as_str()]).expect("renders");
        assert!(report.errors.is_empty(), "{:?}", report.errors);
        (
            report.counter("bind groups created"),
            report.counter("bind groups reused"),
        )
    };
    // The same G-buffer without publishing, to count its own groups.
    reused(&make(""));
    let (_, plain) = reused(&make(""));
    for frame in 0..3 {
        let (created, groups) = reused(&make("cpu3 depth"));
        if frame > 0 {
            // The publishing pass binds the same source and kept target: its
            // group is the one made in the first frame.
            assert_eq!((created, groups), (0, plain + 1), "frame {frame}");
        }
    }
    let published = PublishedDepths::of(&renderer)
        .get("cpu3 depth")
        .expect("published");
    assert_eq!(published.writes, 3);
}

/// A re-made CookTorrance over a still G-buffer writes its cluster grid
/// only when the grid changed: with the camera, the size and the lights
/// the same, a frame after the first uploads nothing at all.
#[test]
fn a_re_made_light_pass_writes_its_grid_only_when_it_changed() {
    let renderer = test_renderer();
    let scene = Scene::new(&renderer);
    let layers = scene.layers(0.0);
    let sun = SunLight {
        direction: Vec3::new(0.3, -1.0, 0.2).normalize(),
        color: Vec3::ONE,
        illuminance: 5.0,
        shadow: None,
    };
    let lights = LightBuffer::suns(&renderer, &[sun]);
    // The node's recipe made again over a still G-buffer: its report and image.
    let frame = |owner: Option<u32>| {
        let g = GBuffer::new(
            &renderer,
            Some(70),
            layers.clone(),
            camera(),
            None,
            SizeRule::Relative(1.0),
        );
        let ct = CookTorrance::with_shadows(
            &renderer,
            owner,
            g,
            lights.clone(),
            LightLoop::Naive,
            true,
            Surfaces::PerMaterialId(vec![(0.7, 0.0)]),
            None,
        );
        let (report, mut images) =
            render_and_read(&renderer, ct.as_ref(), SIZE, &[&ct.diffuse]).expect("renders");
        assert!(report.errors.is_empty(), "{:?}", report.errors);
        (report, images.remove(0))
    };
    let (_, first) = frame(Some(71));
    for n in 1..3 {
        let (report, image) = frame(Some(71));
        assert_eq!(
            report.counter("uniform uploads"),
            0,
            "frame {n}: {:?}",
            report.counters
        );
        assert!(report.counter("uniform uploads skipped") > 0);
        assert!(first.pixels == image.pixels, "frame {n}: the same image");
    }
    // A light pass that keeps nothing writes its grid whole, and says so.
    let (report, image) = frame(None);
    assert_eq!(
        report.counter("uniform uploads"),
        1,
        "{:?}",
        report.counters
    );
    assert!(first.pixels == image.pixels);
}
