//! Point lights on the G-buffer: the froxel walks (clustered, tiled, per
//! pixel) against the naive reference, and the hard cases of the stability suite that are in place
//! so far (no NaN or infinity in any HDR target).

use crate::floor_view;

use std::sync::Arc;

use std::f32::consts::PI;

use floor_view::floor_mesh;
use glam::{Mat4, Vec3};
use spreadlight_render::adapter_class::AdapterClass;
use spreadlight_render::camera::CameraInput;
use spreadlight_render::context::GpuContext;
use spreadlight_render::gbuffer::{DrawBatch, GBuffer, InstanceInput, Layer, LayerFeatures};
use spreadlight_render::lighting::{
    ClusterGrid, CookTorrance, FEW_LIGHTS, LightBuffer, LightLoop, PointLight, SpotLight, SunLight,
    Surfaces, Walk,
};
use spreadlight_render::mesh::primitives::{SphereParams, sphere};
use spreadlight_render::readback::{ImageF32, render_and_read};
use spreadlight_render::renderer::test_renderer;
use spreadlight_render::{Renderer, SizeRule};

const SIZE: (u32, u32) = (96, 54);

/// Spheres on a plane, seen from above and in front.
fn scene(renderer: &Renderer) -> Arc<GBuffer> {
    scene_with(renderer, LayerFeatures::default())
}

/// The scene with its layer's G-buffer features (texture coordinates, ...).
fn scene_with(renderer: &Renderer, features: LayerFeatures) -> Arc<GBuffer> {
    scene_with_far(renderer, features, 100.0)
}

/// The scene seen by a camera whose far plane is at `far`.
fn scene_with_far(renderer: &Renderer, features: LayerFeatures, far: f32) -> Arc<GBuffer> {
    let ball = renderer
        .meshes
        .upload(&renderer.gpu, &sphere(SphereParams::default()))
        .expect("upload");
    let floor = floor_mesh(renderer);
    let instance = |t: Mat4| InstanceInput {
        transform: t,
        previous_transform: t,
        color: [0.8, 0.8, 0.8, 1.0],
        material_id: 0,
        object_id: 0,
    };
    let balls = (0..25)
        .map(|i| {
            instance(Mat4::from_translation(Vec3::new(
                (i % 5) as f32 * 2.0 - 4.0,
                0.5,
                (i / 5) as f32 * -2.0 + 2.0,
            )))
        })
        .collect();
    let batches = vec![
        DrawBatch {
            mesh: ball,
            instances: balls,
        },
        DrawBatch {
            mesh: floor,
            instances: vec![instance(Mat4::IDENTITY)],
        },
    ];
    let layer = Arc::new(Layer::new(None, batches, features, None).expect("valid"));
    let camera = CameraInput {
        view: glam::camera::rh::view::look_at_mat4(Vec3::new(0.0, 6.0, 10.0), Vec3::ZERO, Vec3::Y),
        projection: glam::camera::rh::proj::directx::perspective(
            1.0,
            SIZE.0 as f32 / SIZE.1 as f32,
            0.1,
            far,
        ),
    };
    GBuffer::new(
        renderer,
        None,
        vec![layer],
        camera,
        None,
        SizeRule::Relative(1.0),
    )
}

/// Diffuse + specular of the scene under `lights`.
fn shade(
    renderer: &Renderer,
    g: &Arc<GBuffer>,
    lights: Vec<PointLight>,
    mode: LightLoop,
) -> ImageF32 {
    shade_buffer(renderer, g, LightBuffer::points(renderer, &lights), mode)
}

/// Diffuse + specular of the scene under a light buffer of any type.
fn shade_buffer(
    renderer: &Renderer,
    g: &Arc<GBuffer>,
    lights: Arc<LightBuffer>,
    mode: LightLoop,
) -> ImageF32 {
    shade_buffer_at(renderer, g, lights, mode, SIZE)
}

/// [`shade_buffer`] at `size`.
fn shade_buffer_at(
    renderer: &Renderer,
    g: &Arc<GBuffer>,
    lights: Arc<LightBuffer>,
    mode: LightLoop,
    size: (u32, u32),
) -> ImageF32 {
    let ct = CookTorrance::new(
        renderer,
        Some(1),
        g.clone(),
        lights,
        mode,
        true,
        Surfaces::PerMaterialId(vec![(0.5, 0.0)]),
    );
    let [d, s] = frame(renderer, ct.as_ref(), size, [&ct.diffuse, &ct.specular]);
    assert!(
        d.all_finite() && s.all_finite(),
        "no NaN or infinity in the HDR targets"
    );
    ImageF32 {
        width: d.width,
        height: d.height,
        pixels: d
            .pixels
            .iter()
            .zip(&s.pixels)
            .map(|(a, b)| [a[0] + b[0], a[1] + b[1], a[2] + b[2], 1.0])
            .collect(),
    }
}

/// Render `names` of `recipe` at `size` and read them back; no pass may fail.
fn frame<const N: usize>(
    renderer: &Renderer,
    recipe: &dyn spreadlight_render::Recipe,
    size: (u32, u32),
    names: [&str; N],
) -> [ImageF32; N] {
    let (report, images) =
        render_and_read(renderer, recipe, size, &names).expect("the frame renders");
    assert!(report.errors.is_empty(), "{:?}", report.errors);
    images
        .try_into()
        .unwrap_or_else(|_| unreachable!("one image per name"))
}

/// Lights scattered over the plane, deterministic.
fn scattered(count: usize) -> Vec<PointLight> {
    let mut state = 0x2545_F491_4F6C_DD1Du64;
    let mut u = move || {
        state ^= state << 13;
        state ^= state >> 7;
        state ^= state << 17;
        (state >> 11) as f32 / (1u64 << 53) as f32
    };
    (0..count)
        .map(|_| PointLight {
            shadow: None,
            position: Vec3::new(u() * 20.0 - 10.0, 0.3 + u() * 2.0, u() * 20.0 - 10.0),
            color: Vec3::new(u(), u(), u()),
            intensity: 5.0 + u() * 20.0,
            range: 1.0 + u() * 4.0,
        })
        .collect()
}

fn max_relative_difference(a: &ImageF32, b: &ImageF32) -> f32 {
    a.pixels
        .iter()
        .zip(&b.pixels)
        .flat_map(|(p, q)| (0..3).map(move |c| (p[c] - q[c]).abs() / (q[c].abs().max(1e-3))))
        .fold(0.0, f32::max)
}

/// The walks that read froxel lists.
const FROXEL_WALKS: [LightLoop; 3] = [LightLoop::Clustered, LightLoop::Tiled, LightLoop::PerPixel];

#[test]
fn clustered_tiled_and_per_pixel_shading_match_the_naive_reference() {
    let renderer = test_renderer();
    let g = scene(&renderer);
    let lights = scattered(300);
    let naive = shade(&renderer, &g, lights.clone(), LightLoop::Naive);
    let clustered = shade(&renderer, &g, lights.clone(), LightLoop::Clustered);
    for mode in FROXEL_WALKS {
        let walked = shade(&renderer, &g, lights.clone(), mode);
        // Same lights, same maths: only summation order may differ.
        let worst = max_relative_difference(&walked, &naive);
        assert!(worst < 1e-3, "{mode:?} differs from naive by up to {worst}");
        // Tiled and per pixel sum what the clustered walk sums, in list
        // order (the lights they drop reach no pixel); each frame fills
        // the lists in another order, so sums may differ in rounding.
        let worst = max_relative_difference(&walked, &clustered);
        assert!(
            worst < 1e-3,
            "{mode:?} differs from clustered by up to {worst}"
        );
    }
    assert!(
        naive.pixels.iter().any(|p| p[0] > 0.01),
        "the lights light something"
    );
}

#[test]
fn froxel_walks_stay_finite_and_agree_at_tile_edges_the_far_plane_and_zero_radius() {
    let renderer = test_renderer();
    // The far plane cuts the floor: its last pixels lie at the far plane's
    // depth, in the last slice, beside background in the same tiles.
    let g = scene_with_far(&renderer, LayerFeatures::default(), 12.0);
    let mut lights = scattered(200);
    let edge = PointLight {
        shadow: None,
        // x = 0 projects onto pixel column 48 of 96: the edge between two 16x16 tiles.
        position: Vec3::new(0.0, 0.5, 0.0),
        color: Vec3::ONE,
        intensity: 20.0,
        range: 3.0,
    };
    lights.push(edge);
    lights.push(PointLight { range: 0.0, ..edge });
    lights.push(PointLight {
        // On the floor at the tile edge, under the far plane's pixels.
        position: Vec3::new(0.0, 0.0, -1.5),
        ..edge
    });
    let naive = shade(&renderer, &g, lights.clone(), LightLoop::Naive);
    assert!(
        naive.pixels.iter().any(|p| p[0] > 0.01),
        "the lights light something"
    );
    for mode in FROXEL_WALKS {
        // `shade` asserts every pixel finite.
        let walked = shade(&renderer, &g, lights.clone(), mode);
        let worst = max_relative_difference(&walked, &naive);
        assert!(worst < 1e-3, "{mode:?} differs from naive by up to {worst}");
    }
}

#[test]
fn a_gpus_and_a_cpu_adapters_paths_draw_the_same_frame() {
    // One adapter (lavapipe in CI) made to take each class's paths: the
    // compute raster with and without the particle path (MESHES_ONLY), the
    // floor's big triangles' tiles shared by 1,024 workgroups or one a
    // thread, and the light assignment spread over 64 workgroups a light or one.
    let render = |class: AdapterClass| {
        let gpu = GpuContext::headless()
            .expect("GPU tests need a GPU adapter")
            .with_adapter_class(class);
        let renderer = Renderer::new(gpu).expect("a renderer");
        let g = scene(&renderer);
        let names = [g.targets.depth.as_str(), g.targets.color.as_str()];
        let [depth, color] = frame(&renderer, g.as_ref(), SIZE, names);
        let lights = scattered(100);
        // Auto's walk for the class: clustered on a GPU, per pixel on a CPU adapter.
        let auto = CookTorrance::new(
            &renderer,
            Some(1),
            g.clone(),
            LightBuffer::points(&renderer, &lights),
            LightLoop::Auto,
            true,
            Surfaces::PerMaterialId(vec![(0.5, 0.0)]),
        );
        let expected = match class {
            AdapterClass::Gpu => Walk::Clustered,
            AdapterClass::Cpu => Walk::PerPixel,
        };
        assert_eq!(auto.walk(), expected, "{class:?}");
        let lit = shade(&renderer, &g, lights.clone(), LightLoop::Auto);
        let tiled = shade(&renderer, &g, lights, LightLoop::Tiled);
        (depth, color, lit, tiled)
    };
    let (gpu_depth, gpu_color, gpu_lit, gpu_tiled) = render(AdapterClass::Gpu);
    let (cpu_depth, cpu_color, cpu_lit, _) = render(AdapterClass::Cpu);
    let worst = max_relative_difference(&gpu_tiled, &gpu_lit);
    assert!(worst < 1e-3, "the tiled walk differs by up to {worst}");
    // The same triangles win every pixel: the G-buffer is bit for bit the same.
    assert!(gpu_depth.pixels == cpu_depth.pixels, "depth differs");
    assert!(gpu_color.pixels == cpu_color.pixels, "colour differs");
    // Lists fill in another order: only the light sums' order may differ.
    let worst = max_relative_difference(&cpu_lit, &gpu_lit);
    assert!(worst < 1e-3, "the CPU path differs by up to {worst}");
    assert!(
        gpu_lit.pixels.iter().filter(|p| p[0] > 0.01).count() > 100,
        "the lights light something"
    );
}

#[test]
fn lights_packed_64_a_workgroup_and_split_are_listed_as_a_workgroup_a_light_lists_them() {
    // Made to take a GPU's paths on any adapter: from 512 lights the
    // assignment packs 64 lights a workgroup and splits their (light,
    // froxel) pairs among workgroups (clusters.rs, `Assignment`); below
    // it, each light has workgroups of its own.
    let gpu = GpuContext::headless()
        .expect("GPU tests need a GPU adapter")
        .with_adapter_class(AdapterClass::Gpu);
    let renderer = Renderer::new(gpu).expect("a renderer");
    let g = scene(&renderer);
    // Lights that reach across the frame: at 768x256 (three tiles by 32
    // slices) each touches most of the 96 froxels, so a workgroup's 64
    // lights have more pairs than its 64 lanes times the 64-way split
    // take in one round, and every workgroup goes round again.
    let size = (768, 256);
    for count in [600, 300] {
        let lights: Vec<PointLight> = scattered(count)
            .into_iter()
            .map(|l| PointLight {
                range: 40.0,
                intensity: l.intensity * 0.05,
                ..l
            })
            .collect();
        let shade = |mode| {
            shade_buffer_at(
                &renderer,
                &g,
                LightBuffer::points(&renderer, &lights),
                mode,
                size,
            )
        };
        let naive = shade(LightLoop::Naive);
        let clustered = shade(LightLoop::Clustered);
        let worst = max_relative_difference(&clustered, &naive);
        assert!(
            worst < 1e-3,
            "{count} lights differ from naive by up to {worst}"
        );
        assert!(
            naive.pixels.iter().filter(|p| p[0] > 0.01).count() > 1000,
            "the lights light something"
        );
    }
    // Light Merge's lists packed: coincident pairs, each alone in its cube,
    // merge into lights equal to them, so the merged image is the exact
    // one only if every froxel lists either a pair or its sum (as in
    // `a_light_merge_lists_a_cube_or_its_members_in_every_froxel_never_both`),
    // here 648 lights and 324 merged ones after them.
    let lights = coincident_pairs(18, 1.1, 2.0);
    let exact = shade(&renderer, &g, lights.clone(), LightLoop::Naive);
    let (merged, did) = shade_approximated(&renderer, &g, &lights, LightLoop::Clustered, 0.0, 0.5);
    assert!(did, "the pairs merge");
    let worst = max_relative_difference(&merged, &exact);
    assert!(worst < 2e-3, "the merged pairs differ by up to {worst}");
}

#[test]
fn clustered_shading_matches_the_naive_reference_past_one_round_of_the_froxel_scan() {
    // 11 x 3 tiles x 32 slices = 1,056 froxels; the scan sums 1,024 a
    // round and carries the total into the next.
    let (tiles, tile) = ((11, 3), ClusterGrid::TILE);
    assert!(tiles.0 * tiles.1 * ClusterGrid::SLICES > 1024);
    let size = (tiles.0 * tile, tiles.1 * tile);
    let renderer = test_renderer();
    let g = scene(&renderer);
    let lights = scattered(60);
    let shade = |mode| {
        shade_buffer_at(
            &renderer,
            &g,
            LightBuffer::points(&renderer, &lights),
            mode,
            size,
        )
    };
    let naive = shade(LightLoop::Naive);
    // Many tile columns: each walk finds its block's or pixel's froxel.
    for mode in FROXEL_WALKS {
        let walked = shade(mode);
        let worst = max_relative_difference(&walked, &naive);
        assert!(worst < 1e-3, "{mode:?} differs from naive by up to {worst}");
    }
    // Not a dark frame that would match anything: the lights reach across the screen.
    let lit_right = (0..size.1)
        .flat_map(|y| (size.0 / 2..size.0).map(move |x| (x, y)))
        .filter(|&(x, y)| naive.pixels[(y * size.0 + x) as usize][0] > 0.01)
        .count();
    assert!(
        lit_right > 100,
        "the lights light the right half ({lit_right} pixels)"
    );
}

#[test]
fn auto_walks_a_handful_of_lights_and_clusters_more() {
    let renderer = test_renderer();
    let g = scene(&renderer);
    let few = FEW_LIGHTS as usize;
    for (count, clustered) in [(3, false), (few, false), (few + 1, true)] {
        let lights = scattered(count);
        let ct = CookTorrance::new(
            &renderer,
            Some(1),
            g.clone(),
            LightBuffer::points(&renderer, &lights),
            LightLoop::Auto,
            true,
            Surfaces::PerMaterialId(vec![(0.5, 0.0)]),
        );
        let (report, images) = spreadlight_render::readback::render_and_read(
            &renderer,
            ct.as_ref(),
            SIZE,
            &[&ct.diffuse],
        )
        .expect("the frame renders");
        let assigned = report
            .passes_of("CookTorrance", Some("clustered light assignment"))
            .next()
            .is_some();
        assert_eq!(
            assigned,
            clustered,
            "{count} lights: {:?}",
            report.passes.iter().map(|p| &p.name).collect::<Vec<_>>()
        );
        drop(images);
        // The walk it picked, lighting as that walk does.
        let auto = shade(&renderer, &g, lights.clone(), LightLoop::Auto);
        let picked = if clustered {
            LightLoop::Clustered
        } else {
            LightLoop::Naive
        };
        let reference = shade(&renderer, &g, lights, picked);
        let worst = max_relative_difference(&auto, &reference);
        assert!(
            worst < 1e-3,
            "{count} lights: Auto differs from {picked:?} by {worst}"
        );
    }
}

#[test]
fn zero_one_and_many_lights_in_one_cluster_stay_finite_and_exact() {
    let renderer = test_renderer();
    let g = scene(&renderer);
    let dark = shade(&renderer, &g, Vec::new(), LightLoop::Clustered);
    assert!(
        dark.pixels
            .iter()
            .all(|p| p[0] == 0.0 && p[1] == 0.0 && p[2] == 0.0),
        "no light, no radiance"
    );
    let one = PointLight {
        shadow: None,
        position: Vec3::new(0.0, 2.0, 0.0),
        color: Vec3::ONE,
        intensity: 50.0,
        range: 6.0,
    };
    let single = shade(&renderer, &g, vec![one], LightLoop::Clustered);
    // 2,000 copies of the same light in one froxel: exactly 2,000 times the light.
    let crowd = shade(&renderer, &g, vec![one; 2000], LightLoop::Clustered);
    let worst = single
        .pixels
        .iter()
        .zip(&crowd.pixels)
        .filter(|(s, c)| s[0] > 1e-3 && c[0] < 60_000.0)
        .map(|(s, c)| (c[0] / (2000.0 * s[0]) - 1.0).abs())
        .fold(0.0f32, f32::max);
    assert!(
        worst < 1e-2,
        "all lights in one cluster are all counted (worst {worst})"
    );
}

#[test]
fn extreme_lights_never_produce_nan_or_infinity() {
    let renderer = test_renderer();
    let g = scene(&renderer);
    let on_surface = PointLight {
        shadow: None,
        position: Vec3::new(0.0, 0.0, 3.0),
        color: Vec3::ONE,
        intensity: 10.0,
        range: 3.0,
    };
    let cases = [
        on_surface,
        PointLight {
            range: 0.0,
            ..on_surface
        },
        PointLight {
            intensity: 0.0,
            ..on_surface
        },
        PointLight {
            intensity: 1e6,
            position: Vec3::new(0.0, 1.0, 0.0),
            ..on_surface
        },
    ];
    for light in cases {
        for mode in FROXEL_WALKS {
            // `shade` asserts every pixel finite.
            let image = shade(&renderer, &g, vec![light], mode);
            assert!(
                image.pixels.iter().all(|p| p[0] <= 65000.0 * 2.0),
                "{mode:?}: clamped below half-float overflow"
            );
        }
    }
}

#[test]
fn a_hundred_thousand_lights_fit() {
    let renderer = test_renderer();
    let g = scene(&renderer);
    let image = shade(&renderer, &g, scattered(100_000), LightLoop::Clustered);
    assert!(image.pixels.iter().any(|p| p[0] > 0.0));
}

fn lit_pixels(image: &ImageF32) -> usize {
    image
        .pixels
        .iter()
        .filter(|p| p[0] + p[1] + p[2] > 1e-4)
        .count()
}

#[test]
fn a_sun_lights_what_faces_it_and_nothing_else() {
    let renderer = test_renderer();
    let g = scene(&renderer);
    let from_above = SunLight {
        shadow: None,
        direction: Vec3::NEG_Y,
        color: Vec3::ONE,
        illuminance: 10.0,
    };
    let lit = shade_buffer(
        &renderer,
        &g,
        LightBuffer::suns(&renderer, &[from_above]),
        LightLoop::Clustered,
    );
    assert!(
        lit_pixels(&lit) > (SIZE.0 * SIZE.1 / 3) as usize,
        "the floor and the tops of the balls are lit"
    );
    // From below, only the undersides of the balls that the camera sees are lit; the floor is not.
    let from_below = SunLight {
        direction: Vec3::Y,
        ..from_above
    };
    let dark = shade_buffer(
        &renderer,
        &g,
        LightBuffer::suns(&renderer, &[from_below]),
        LightLoop::Naive,
    );
    let below = lit_pixels(&dark);
    assert!(
        below > 0 && below * 10 < lit_pixels(&lit),
        "{below} of {} pixels lit from below",
        lit_pixels(&lit)
    );
    // A zero direction falls back to straight down rather than NaN.
    let degenerate = SunLight {
        direction: Vec3::ZERO,
        ..from_above
    };
    let image = shade_buffer(
        &renderer,
        &g,
        LightBuffer::suns(&renderer, &[degenerate]),
        LightLoop::Naive,
    );
    assert_eq!(lit_pixels(&image), lit_pixels(&lit));
}

#[test]
fn spot_cones_from_zero_to_nearly_a_hemisphere_stay_finite_and_bounded() {
    let renderer = test_renderer();
    let g = scene(&renderer);
    let spot = |inner: f32, outer: f32| {
        SpotLight::cone(Vec3::new(0.0, 4.0, 0.0), Vec3::NEG_Y, 10.0, inner, outer)
            .with_light(Vec3::ONE, 200.0)
    };
    let count = |s: SpotLight, mode| {
        lit_pixels(&shade_buffer(
            &renderer,
            &g,
            LightBuffer::spots(&renderer, &[s], None).expect("a valid spot"),
            mode,
        ))
    };
    let zero = count(spot(0.0, 0.0), LightLoop::Clustered);
    let narrow = count(spot(0.1, 0.2), LightLoop::Clustered);
    let wide = count(spot(1.0, 1.2), LightLoop::Clustered);
    let widest = count(spot(PI, PI), LightLoop::Clustered);
    assert!(
        zero <= narrow && narrow < wide && wide <= widest,
        "{zero} {narrow} {wide} {widest}"
    );
    assert!(narrow > 0, "a narrow cone still lights a spot");
    // The same spot through the naive loop: the same pixels.
    assert_eq!(count(spot(0.1, 0.2), LightLoop::Naive), narrow);
    // The widest cone lights no more than a point light at its place.
    let point = lit_pixels(&shade(
        &renderer,
        &g,
        vec![PointLight {
            shadow: None,
            position: Vec3::new(0.0, 4.0, 0.0),
            color: Vec3::ONE,
            intensity: 200.0,
            range: 10.0,
        }],
        LightLoop::Clustered,
    ));
    assert!(widest <= point, "{widest} > {point}");
}

#[test]
fn a_spot_projects_the_layer_of_its_texture_array_and_wraps_past_its_end() {
    use spreadlight_render::static_texture::StaticTexture;
    use spreadlight_render::texture::GpuTexture;
    let renderer = test_renderer();
    let g = scene(&renderer);
    // Layer 0 black, layer 1 pure red, layer 2 green on the left half only.
    let (w, h) = (4u32, 4u32);
    let solid = |c: [u8; 4]| c.repeat((w * h) as usize);
    let half: Vec<u8> = (0..w * h)
        .flat_map(|i| {
            if i % w < w / 2 {
                [0, 255, 0, 255]
            } else {
                [0, 0, 0, 255]
            }
        })
        .collect();
    let layers = [solid([0, 0, 0, 255]), solid([255, 0, 0, 255]), half];
    let array = GpuTexture::array_from_rgba8(&renderer.gpu, w, h, &layers, false, "gobos");
    let textures = StaticTexture::new(array).texture_ref();
    let spot = |texture| SpotLight {
        texture,
        ..SpotLight::cone(Vec3::new(0.0, 4.0, 0.0), Vec3::NEG_Y, 10.0, 0.5, 0.6)
            .with_light(Vec3::ONE, 200.0)
    };
    let image = |texture| {
        let lights = LightBuffer::spots(&renderer, &[spot(texture)], Some(textures.clone()))
            .expect("a valid spot");
        shade_buffer(&renderer, &g, lights, LightLoop::Clustered)
    };
    let (round, black, red, wrapped, half) = (
        image(None),
        image(Some(0)),
        image(Some(1)),
        image(Some(4)),
        image(Some(2)),
    );
    assert_eq!(lit_pixels(&black), 0, "a black layer lights nothing");
    let lit = lit_pixels(&red);
    assert!(
        lit > lit_pixels(&round),
        "the full square frustum lights more than its round cone"
    );
    assert!(
        red.pixels.iter().all(|p| p[1] <= 1e-6 && p[2] <= 1e-6),
        "a red layer lights in red only"
    );
    assert_eq!(red.pixels, wrapped.pixels, "layer 4 of 3 is layer 1");
    let green = lit_pixels(&half);
    assert!(
        green > 0 && green < lit,
        "half a green layer lights part of the frustum: {green} of {lit}"
    );
    assert!(half.pixels.iter().all(|p| p[0] <= 1e-6));
}

#[test]
fn a_spot_with_a_singular_projection_is_an_error_naming_it() {
    let renderer = test_renderer();
    let mut spot = SpotLight::cone(Vec3::ZERO, Vec3::NEG_Y, 10.0, 0.1, 0.2);
    spot.projection = Mat4::ZERO;
    let err = LightBuffer::spots(
        &renderer,
        &[SpotLight::cone(Vec3::ZERO, Vec3::X, 5.0, 0.1, 0.2), spot],
        None,
    )
    .expect_err("refused");
    assert!(
        err.to_string().starts_with("spot 1: the projection"),
        "{err}"
    );
    spot.projection = SpotLight::cone(Vec3::ZERO, Vec3::NEG_Y, 10.0, 0.1, 0.2).projection;
    spot.view = Mat4::ZERO;
    let err = LightBuffer::spots(&renderer, &[spot], None).expect_err("refused");
    assert!(err.to_string().starts_with("spot 0: the view"), "{err}");
}

#[test]
fn the_material_buffer_drives_shading_and_unused_features_cost_nothing() {
    use spreadlight_render::lighting::{CompositeInputs, CompositeLight};
    use spreadlight_render::material::{Feature, Material, MaterialWorld};
    let renderer = test_renderer();
    let g = scene(&renderer);
    let light = PointLight {
        shadow: None,
        position: Vec3::new(0.0, 2.0, 1.0),
        color: Vec3::ONE,
        intensity: 30.0,
        range: 8.0,
    };
    let shade_with = |surfaces: Surfaces| {
        let lights = LightBuffer::points(&renderer, &[light]);
        let ct = CookTorrance::new(
            &renderer,
            None,
            g.clone(),
            lights,
            LightLoop::Clustered,
            true,
            surfaces,
        );
        let [specular] = frame(&renderer, ct.as_ref(), SIZE, [&ct.specular]);
        specular
    };
    // The default material (roughness 0.5, metallic 0) is what the pins say by default.
    let pins = shade_with(Surfaces::PerMaterialId(vec![(0.5, 0.0)]));
    let default_world = MaterialWorld::new(&renderer, vec![Material::default_material()]);
    let from_world = shade_with(Surfaces::Materials(default_world.clone()));
    assert_eq!(pins.pixels, from_world.pixels);
    // A metal material changes the specular everywhere it is lit.
    let metal = Material::new()
        .with(Feature::CookTorrance, &[[0.2, 1.0, 0.04, 0.0]])
        .expect("valid");
    let metal_world = MaterialWorld::new(&renderer, vec![metal]);
    let shiny = shade_with(Surfaces::Materials(metal_world));
    assert_ne!(shiny.pixels, pins.pixels);
    // Reflectance is the dielectric F0 of direct light too: 0.5 instead of
    // 0.04 brightens every lit specular pixel (it was read by Reflection and
    // SSR only).
    let glossy = Material::new()
        .with(Feature::CookTorrance, &[[0.5, 0.0, 0.5, 0.0]])
        .expect("valid");
    let glossy = shade_with(Surfaces::Materials(MaterialWorld::new(
        &renderer,
        vec![glossy],
    )));
    let sum = |image: &ImageF32| image.pixels.iter().map(|p| p[0] as f64).sum::<f64>();
    assert!(
        sum(&glossy) > 5.0 * sum(&pins),
        "reflectance 0.5 vs 0.04: {} vs {}",
        sum(&glossy),
        sum(&pins)
    );

    // Emission: compiled in only for a world where some material has it.
    let composite = |world: Option<std::sync::Arc<MaterialWorld>>| {
        let ct = unlit_cook_torrance(&renderer, &g);
        let c = CompositeLight::new(
            &renderer,
            None,
            g.clone(),
            CompositeInputs {
                components: vec![ct.components()],
                ambient: [0.0; 3],
                materials: world,
                occlusion: None,
                gi: None,
                reflection: None,
            },
        )
        .expect("valid");
        let compiled_before = renderer.shaders().pipelines_compiled;
        let [image] = frame(&renderer, c.as_ref(), SIZE, [&c.output]);
        (
            image,
            renderer.shaders().pipelines_compiled - compiled_before,
        )
    };
    let (dark, _) = composite(None);
    let (same, _) = composite(Some(default_world));
    assert_eq!(
        dark.pixels, same.pixels,
        "a world without emission adds nothing"
    );
    let glowing = Material::default_material()
        .with(Feature::Emission, &[[1.0, 0.5, 0.25, 2.0]])
        .expect("valid");
    let (glow, compiled) = composite(Some(MaterialWorld::new(&renderer, vec![glowing])));
    assert!(
        compiled >= 1,
        "the emission permutation is compiled when first needed"
    );
    let lit = glow
        .pixels
        .iter()
        .filter(|p| (p[0] - 2.0).abs() < 1e-2 && (p[1] - 1.0).abs() < 1e-2)
        .count();
    assert!(
        lit > (SIZE.0 * SIZE.1 / 3) as usize,
        "every covered pixel glows with colour x strength ({lit})"
    );
}

/// The side of the [`uv_halves`] texture.
const HALVES: u32 = 8;

/// An RGBA8 texture of `HALVES` x `HALVES`, `left` on the left half of UV
/// space and `right` on the right.
fn uv_halves(left: [u8; 4], right: [u8; 4]) -> Vec<u8> {
    (0..HALVES * HALVES)
        .flat_map(|i| if i % HALVES < HALVES / 2 { left } else { right })
        .collect()
}

/// A CookTorrance over `g` with no lights (every material 0.5 rough,
/// dielectric): a composite's light input that adds nothing, so what shows
/// is the composite's own terms.
fn unlit_cook_torrance(renderer: &Renderer, g: &Arc<GBuffer>) -> Arc<CookTorrance> {
    CookTorrance::new(
        renderer,
        None,
        g.clone(),
        LightBuffer::points(renderer, &[]),
        LightLoop::Naive,
        false,
        Surfaces::PerMaterialId(vec![(0.5, 0.0)]),
    )
}

/// A world of one material: the default with `feature` of `params`.
fn world_with(
    renderer: &Renderer,
    feature: spreadlight_render::material::Feature,
    params: [f32; 4],
) -> Arc<spreadlight_render::material::MaterialWorld> {
    let material = spreadlight_render::material::Material::default_material()
        .with(feature, &[params])
        .expect("valid");
    spreadlight_render::material::MaterialWorld::new(renderer, vec![material])
}

/// CompositeLight over a CookTorrance with no lights and no ambient, both
/// reading `world`: what the materials add by themselves (emission).
fn unlit_composite(
    renderer: &Renderer,
    g: &Arc<GBuffer>,
    world: Arc<spreadlight_render::material::MaterialWorld>,
) -> ImageF32 {
    use spreadlight_render::lighting::{CompositeInputs, CompositeLight};
    let lights = LightBuffer::points(renderer, &[]);
    let ct = CookTorrance::new(
        renderer,
        None,
        g.clone(),
        lights,
        LightLoop::Naive,
        false,
        Surfaces::Materials(world.clone()),
    );
    let c = CompositeLight::new(
        renderer,
        None,
        g.clone(),
        CompositeInputs {
            components: vec![ct.components()],
            ambient: [0.0; 3],
            materials: Some(world),
            occlusion: None,
            gi: None,
            reflection: None,
        },
    )
    .expect("valid");
    let [image] = frame(renderer, c.as_ref(), SIZE, [&c.output]);
    image
}

#[test]
fn material_textures_scale_parameters_at_the_gbuffer_uv_and_compile_only_when_read() {
    use spreadlight_render::material::{Feature, Material, MaterialWorld};
    use spreadlight_render::static_texture::StaticTexture;
    use spreadlight_render::texture::GpuTexture;
    let renderer = test_renderer();
    let g = scene_with(
        &renderer,
        LayerFeatures {
            texcoords: true,
            ..Default::default()
        },
    );
    // Layer 0 white; layer 1 white on the left half of UV space, black on the right.
    let white = [255u8; 4].repeat((HALVES * HALVES) as usize);
    let half = uv_halves([255; 4], [0, 0, 0, 255]);
    let array =
        GpuTexture::array_from_rgba8(&renderer.gpu, HALVES, HALVES, &[white, half], false, "maps");
    let textures = StaticTexture::new(array).texture_ref();
    let emissive = |layer: Option<u32>| {
        let mut m = Material::default_material()
            .with(Feature::Emission, &[[1.0, 0.5, 0.25, 2.0]])
            .expect("valid");
        m.set_texture(Feature::Emission, layer);
        MaterialWorld::with_textures(&renderer, vec![m], Some(textures.clone()))
    };
    let composite = |world: Arc<MaterialWorld>| {
        let image = unlit_composite(&renderer, &g, world);
        (image, renderer.last_report().passes)
    };
    let glowing = |image: &ImageF32| image.pixels.iter().filter(|p| p[0] > 1e-3).count();
    // No material reads a texture: the array is not even declared.
    let plain = emissive(None);
    assert!(plain.textures().is_none());
    let (flat, passes) = composite(plain);
    // Neither alone nor merged with the surface resolve ("resolve surface and motion").
    assert!(
        passes.iter().all(|p| !resolves_motion(p)),
        "no UV needed: {passes:?}"
    );
    // A white layer changes nothing.
    let (white, passes) = composite(emissive(Some(0)));
    assert!(
        passes.iter().any(resolves_motion),
        "UVs are resolved for the texture: {passes:?}"
    );
    assert_eq!(white.pixels, flat.pixels);
    // Half a layer: only part of what glowed still glows, and nothing turns negative.
    let (half, _) = composite(emissive(Some(1)));
    let (all, part) = (glowing(&flat), glowing(&half));
    assert!(part > 0 && part < all, "{part} of {all} pixels glow");
    assert!(half.all_finite() && half.pixels.iter().all(|p| p[0] >= 0.0));
    // Layer 3 of 2 wraps to layer 1.
    let (wrapped, _) = composite(emissive(Some(3)));
    assert_eq!(wrapped.pixels, half.pixels);
}

#[test]
fn a_parameter_with_its_own_layer_changes_with_the_texture_and_the_others_do_not() {
    use spreadlight_render::material::{Feature, Material, MaterialWorld};
    use spreadlight_render::static_texture::StaticTexture;
    use spreadlight_render::texture::GpuTexture;
    let renderer = test_renderer();
    let g = scene_with(
        &renderer,
        LayerFeatures {
            texcoords: true,
            ..Default::default()
        },
    );
    // Layer 0: red 1 on the left half of UV space, red 0 on the right, green
    // and blue 1 everywhere: only a red-channel read sees the halves.
    let halves = uv_halves([255; 4], [0, 255, 255, 255]);
    let array =
        GpuTexture::array_from_rgba8(&renderer.gpu, HALVES, HALVES, &[halves], false, "maps");
    let textures = StaticTexture::new(array).texture_ref();
    // Emission's parameters: Color (0) and Strength (1).
    let emissive = |param: Option<usize>| {
        let mut m = Material::default_material()
            .with(Feature::Emission, &[[1.0, 0.5, 0.25, 2.0]])
            .expect("valid");
        if let Some(p) = param {
            m.set_param_texture(Feature::Emission, p, Some(0));
        }
        MaterialWorld::with_textures(&renderer, vec![m], Some(textures.clone()))
    };
    let composite = |world: Arc<MaterialWorld>| unlit_composite(&renderer, &g, world);
    let flat = composite(emissive(None));
    let glowing = |image: &ImageF32| image.pixels.iter().filter(|p| p[0] > 1e-3).count();
    let all = glowing(&flat);
    assert!(all > 0);
    // Strength, the second parameter, by the red channel: the right half goes dark,
    // the left half glows exactly as before (red 1 scales by 1).
    let strength = composite(emissive(Some(1)));
    let part = glowing(&strength);
    assert!(part > 0 && part < all, "{part} of {all} pixels glow");
    // Every pixel is its old colour times one factor in 0..=1 (bilinear
    // between the halves at their border): only the strength moved.
    let mut unchanged = 0;
    for (s, f) in strength.pixels.iter().zip(&flat.pixels) {
        let t = if f[0] > 0.0 { s[0] / f[0] } else { 0.0 };
        assert!((0.0..=1.0 + 1e-3).contains(&t), "{s:?} vs {f:?}");
        for c in 0..3 {
            assert!((s[c] - f[c] * t).abs() < 1e-2, "{s:?} vs {f:?}");
        }
        unchanged += usize::from(f[0] > 0.0 && s[..3] == f[..3]);
    }
    assert!(
        unchanged > 0 && unchanged < all,
        "{unchanged} of {all} keep their glow"
    );
    assert!(strength.all_finite() && strength.pixels.iter().all(|p| p[0] >= 0.0));
    // The colour by the layer's rgb: red goes where red is 0, green and blue stay.
    let color = composite(emissive(Some(0)));
    assert!(color.all_finite());
    let (red_gone, green_kept) =
        color
            .pixels
            .iter()
            .zip(&flat.pixels)
            .fold((0, 0), |(r, g), (c, f)| {
                (
                    r + usize::from(f[0] > 1e-3 && c[0] < 1e-4),
                    g + usize::from(f[1] > 1e-3 && (c[1] - f[1]).abs() < 1e-4),
                )
            });
    assert!(
        red_gone > 0 && red_gone < all,
        "{red_gone} of {all} lose their red"
    );
    assert!(
        green_kept >= all,
        "green kept on every glowing pixel: {green_kept} of {all}"
    );
}

#[test]
fn fake_sss_adds_light_past_the_terminator_only_for_materials_that_have_it() {
    use spreadlight_render::material::{Feature, Material, MaterialWorld};
    let renderer = test_renderer();
    let g = scene(&renderer);
    // A light low at the side: the balls have a lit and a dark half.
    let light = PointLight {
        shadow: None,
        position: Vec3::new(-6.0, 0.5, 0.0),
        color: Vec3::ONE,
        intensity: 200.0,
        range: 20.0,
    };
    let plain = MaterialWorld::new(&renderer, vec![Material::default_material()]);
    let lights = LightBuffer::points(&renderer, &[light]);
    let without = CookTorrance::new(
        &renderer,
        None,
        g.clone(),
        lights.clone(),
        LightLoop::Naive,
        true,
        Surfaces::Materials(plain),
    );
    assert!(
        without.sss_texture().is_none(),
        "no material has FakeSSS: no subsurface pass output"
    );

    let skin = Material::default_material()
        .with(Feature::FakeSss, &[[1.0, 0.3, 0.2, 1.0]])
        .expect("valid");
    let with = CookTorrance::new(
        &renderer,
        None,
        g.clone(),
        lights,
        LightLoop::Naive,
        true,
        Surfaces::Materials(MaterialWorld::new(&renderer, vec![skin])),
    );
    let sss = with
        .sss_texture()
        .expect("a FakeSSS material gets a subsurface output");
    let [sss, diffuse] = frame(&renderer, with.as_ref(), SIZE, [&sss.name, &with.diffuse]);
    assert!(sss.all_finite());
    // Somewhere the surface faces away from the light (no diffuse) yet scatters light.
    let past_terminator = sss
        .pixels
        .iter()
        .zip(&diffuse.pixels)
        .filter(|(s, d)| s[0] > 1e-4 && d[0] < 1e-6)
        .count();
    assert!(
        past_terminator > 0,
        "wrap lighting reaches past the terminator"
    );
    // Tinted by the material: more red than green.
    assert!(
        sss.pixels
            .iter()
            .filter(|p| p[0] > 1e-4)
            .all(|p| p[0] >= p[1])
    );
}

#[test]
fn ambient_occlusion_darkens_the_ambient_term_as_each_material_says() {
    use spreadlight_render::lighting::{CompositeInputs, CompositeLight};
    use spreadlight_render::material::{Feature, MaterialWorld};
    use spreadlight_render::static_texture::StaticTexture;
    let renderer = test_renderer();
    let g = scene(&renderer);
    let half = vec![[0.5f32, 0.5, 0.5, 1.0]; (SIZE.0 * SIZE.1) as usize];
    let ao = StaticTexture::from_rgba32f(&renderer.gpu, SIZE.0, SIZE.1, &half, "ao");
    let composite = |occlusion: bool, world: Option<std::sync::Arc<MaterialWorld>>| {
        let ct = unlit_cook_torrance(&renderer, &g);
        let inputs = CompositeInputs {
            components: vec![ct.components()],
            ambient: [1.0; 3],
            materials: world,
            occlusion: occlusion.then(|| ao.texture_ref()),
            gi: None,
            reflection: None,
        };
        let c = CompositeLight::new(&renderer, None, g.clone(), inputs).expect("valid");
        let [image] = frame(&renderer, c.as_ref(), SIZE, [&c.output]);
        image
    };
    let open = composite(false, None);
    let occluded = composite(true, None);
    let weighted_off = composite(
        true,
        Some(world_with(
            &renderer,
            Feature::AmbientOcclusion,
            [0.0, 0.0, 0.0, 0.0],
        )),
    );
    let weighted_on = composite(
        true,
        Some(world_with(
            &renderer,
            Feature::AmbientOcclusion,
            [1.0, 0.0, 0.0, 0.0],
        )),
    );
    for (i, p) in open.pixels.iter().enumerate() {
        if p[0] == 0.0 {
            continue; // background
        }
        assert!(
            (occluded.pixels[i][0] - 0.5 * p[0]).abs() < 1e-3,
            "AO 0.5 halves the ambient term"
        );
        assert!(
            (weighted_off.pixels[i][0] - p[0]).abs() < 1e-3,
            "strength 0: the material ignores AO"
        );
        assert!(
            (weighted_on.pixels[i][0] - 0.5 * p[0]).abs() < 1e-3,
            "strength 1: full AO"
        );
    }
    assert!(open.pixels.iter().any(|p| p[0] > 0.0));
}

#[test]
fn gi_and_reflection_are_weighted_per_material_and_unreflective_scenes_render_no_reflection() {
    use spreadlight_render::lighting::{CompositeInputs, CompositeLight};
    use spreadlight_render::material::{Feature, Material, MaterialWorld};
    use spreadlight_render::ssao::{AmbientOcclusion, AoSettings};
    use spreadlight_render::static_texture::StaticTexture;
    let renderer = test_renderer();
    let g = scene(&renderer);
    let constant = |v: f32, name: &str| {
        StaticTexture::from_rgba32f(
            &renderer.gpu,
            SIZE.0,
            SIZE.1,
            &vec![[v, v, v, 1.0]; (SIZE.0 * SIZE.1) as usize],
            name,
        )
    };
    let (gi, reflection) = (constant(0.25, "gi"), constant(0.5, "reflection"));
    let world = |reflective: Option<f32>| {
        let m = Material::default_material();
        let m = match reflective {
            Some(strength) => m
                .with(Feature::Reflection, &[[strength, 0.0, 0.0, 0.0]])
                .expect("valid"),
            None => m,
        };
        MaterialWorld::new(&renderer, vec![m])
    };
    let composite = |gi_on: bool, reflection: Option<spreadlight_render::TextureRef>, materials| {
        let ct = unlit_cook_torrance(&renderer, &g);
        let inputs = CompositeInputs {
            components: vec![ct.components()],
            ambient: [0.0; 3],
            materials: Some(materials),
            occlusion: None,
            gi: gi_on.then(|| gi.texture_ref()),
            reflection,
        };
        let c = CompositeLight::new(&renderer, None, g.clone(), inputs).expect("valid");
        let (report, images) =
            render_and_read(&renderer, c.as_ref(), SIZE, &[&c.output, &g.targets.color])
                .expect("renders");
        assert!(report.errors.is_empty(), "{:?}", report.errors);
        (report, images)
    };
    // GI alone: 0.25 times albedo.
    let (_, images) = composite(true, None, world(None));
    let (lit, albedo) = (&images[0], &images[1]);
    let mut surface = 0;
    for (p, a) in lit.pixels.iter().zip(&albedo.pixels) {
        if a[0] > 0.0 {
            assert!((p[0] - 0.25 * a[0]).abs() < 2e-3, "{p:?} albedo {a:?}");
            surface += 1;
        }
    }
    assert!(surface > 0);
    // Metals reflect, they do not diffuse: no GI on a metallic material.
    let metal = world_with(&renderer, Feature::CookTorrance, [0.3, 1.0, 0.04, 0.0]);
    let (_, images) = composite(true, None, metal);
    assert!(
        images[0].pixels.iter().all(|p| p[0].abs() < 1e-4),
        "metals take no diffuse GI"
    );
    // Reflection at strength 0.5 adds half the reflection texture; no Reflection feature adds none.
    let (_, images) = composite(false, Some(reflection.texture_ref()), world(Some(0.5)));
    let (lit, albedo) = (&images[0], &images[1]);
    for (p, a) in lit.pixels.iter().zip(&albedo.pixels) {
        if a[0] > 0.0 {
            assert!((p[0] - 0.25).abs() < 2e-3, "0.5 x 0.5: {p:?}");
        }
    }
    // The scene's material (id 0) without the feature, another (id 1) with it:
    // the reflection is bound, and adds nothing to the pixels of id 0.
    let mixed = MaterialWorld::new(
        &renderer,
        vec![
            Material::default_material(),
            Material::default_material()
                .with(Feature::Reflection, &[[1.0, 0.0, 0.0, 0.0]])
                .expect("valid"),
        ],
    );
    let (report, images) = composite(false, Some(reflection.texture_ref()), mixed);
    assert_eq!(
        report.counter("reflection culled: no reflective material"),
        0
    );
    assert!(
        images[0].pixels.iter().all(|p| p[0].abs() < 1e-4),
        "material 0 does not reflect"
    );
    // A reflection made by a real pass (here an AO recipe stands in for one):
    // without a reflective material it is not declared, so none of its passes run.
    let stand_in = AmbientOcclusion::new(&renderer, None, g.clone(), AoSettings::default(), None);
    let (report, images) = composite(false, Some(stand_in.texture()), world(None));
    assert!(images[0].all_finite());
    assert_eq!(
        report.counter("reflection culled: no reflective material"),
        1
    );
    assert!(
        report.passes_of("SSAO", None).count() == 0,
        "{:?}",
        report.passes.iter().map(|p| &p.name).collect::<Vec<_>>()
    );
    let (report, _) = composite(false, Some(stand_in.texture()), world(Some(1.0)));
    assert_eq!(
        report.counter("reflection culled: no reflective material"),
        0
    );
    assert!(report.passes_of("SSAO", None).count() > 0);
}

/// The white furnace, rendered: a white metal sphere (F0 = 1) under uniform
/// white light from every direction (4,096 suns on a Fibonacci sphere, each
/// 4 pi / 4,096 lux: radiance 1 everywhere). Each pixel then shows the
/// directional albedo of the specular lobe: at most 1 without energy
/// compensation, close to 1 with it.
#[test]
fn white_furnace_returns_at_most_the_incoming_energy() {
    let renderer = test_renderer();
    let size = (48u32, 48u32);
    let mesh = renderer
        .meshes
        .upload(
            &renderer.gpu,
            &sphere(SphereParams {
                radius: 1.0,
                sectors: 64,
                stacks: 32,
            }),
        )
        .expect("upload");
    let white = InstanceInput {
        transform: Mat4::IDENTITY,
        previous_transform: Mat4::IDENTITY,
        color: [1.0; 4],
        material_id: 0,
        object_id: 0,
    };
    let layer = Arc::new(Layer::plain(vec![DrawBatch {
        mesh,
        instances: vec![white],
    }]));
    let camera = CameraInput {
        view: glam::camera::rh::view::look_at_mat4(Vec3::new(0.0, 0.0, 4.0), Vec3::ZERO, Vec3::Y),
        projection: glam::camera::rh::proj::directx::perspective(0.7, 1.0, 0.1, 100.0),
    };
    let g = GBuffer::new(
        &renderer,
        None,
        vec![layer],
        camera,
        None,
        SizeRule::Relative(1.0),
    );
    let n = 4096;
    let golden = std::f32::consts::PI * (3.0 - 5f32.sqrt());
    let suns: Vec<SunLight> = (0..n)
        .map(|i| {
            let z = 1.0 - 2.0 * (i as f32 + 0.5) / n as f32;
            let r = (1.0 - z * z).sqrt();
            let phi = i as f32 * golden;
            SunLight {
                shadow: None,
                direction: -Vec3::new(r * phi.cos(), r * phi.sin(), z),
                color: Vec3::ONE,
                illuminance: 4.0 * std::f32::consts::PI / n as f32,
            }
        })
        .collect();
    let lights = LightBuffer::suns(&renderer, &suns);
    let furnace = |roughness: f32, compensate: bool| {
        let ct = CookTorrance::new(
            &renderer,
            None,
            g.clone(),
            lights.clone(),
            LightLoop::Naive,
            compensate,
            Surfaces::PerMaterialId(vec![(roughness, 1.0)]),
        );
        let [image] = frame(&renderer, ct.as_ref(), size, [&ct.specular]);
        assert!(image.all_finite());
        // Only pixels that see the sphere head-on enough (N.V > ~0.3: the inner part of the disc).
        let values: Vec<f32> = (0..size.1)
            .flat_map(|y| (0..size.0).map(move |x| (x, y)))
            .filter(|&(x, y)| {
                let (dx, dy) = (x as f32 - 23.5, y as f32 - 23.5);
                (dx * dx + dy * dy).sqrt() < 11.0
            })
            .map(|(x, y)| image.pixel(x, y)[0])
            .collect();
        assert!(!values.is_empty());
        let max = values.iter().copied().fold(0.0f32, f32::max);
        let min = values.iter().copied().fold(f32::MAX, f32::min);
        (min, max)
    };
    for roughness in [0.5f32, 0.75, 1.0] {
        let (lo, hi) = furnace(roughness, false);
        let (clo, chi) = furnace(roughness, true);
        eprintln!(
            "roughness {roughness}: without compensation {lo:.3}..{hi:.3}, with {clo:.3}..{chi:.3}"
        );
        // 4,096 discrete suns sample the lobe; 3% covers their error.
        assert!(
            hi <= 1.03,
            "roughness {roughness}: returns {hi} of the incoming energy without compensation"
        );
        assert!(
            chi <= 1.03 && clo >= 0.9,
            "roughness {roughness}: compensated albedo {clo}..{chi}"
        );
        assert!(clo >= lo, "compensation only adds energy");
    }
}

/// The G-buffer's motion resolve, alone or merged with the surface resolve.
fn resolves_motion(p: &spreadlight_render::frame_graph::PassReport) -> bool {
    p.is("MRE", Some("resolve motion")) || p.is("MRE", Some("resolve surface and motion"))
}

/// [`shade_buffer`] with CookTorrance's light cutoff.
fn shade_cut(
    renderer: &Renderer,
    g: &Arc<GBuffer>,
    lights: &[PointLight],
    mode: LightLoop,
    cutoff: f32,
) -> ImageF32 {
    shade_approximated(renderer, g, lights, mode, cutoff, 0.0).0
}

/// [`shade_buffer`] with CookTorrance's light cutoff and light merge, and
/// whether the recipe merged its lights.
fn shade_approximated(
    renderer: &Renderer,
    g: &Arc<GBuffer>,
    lights: &[PointLight],
    mode: LightLoop,
    cutoff: f32,
    merge: f32,
) -> (ImageF32, bool) {
    let ct = CookTorrance::new(
        renderer,
        Some(1),
        g.clone(),
        LightBuffer::points(renderer, lights),
        mode,
        true,
        Surfaces::PerMaterialId(vec![(0.5, 0.0)]),
    );
    let ct = CookTorrance::with_light_cutoff(ct, cutoff);
    let ct = CookTorrance::with_light_merge(ct, renderer, merge);
    let [d, s] = frame(renderer, ct.as_ref(), SIZE, [&ct.diffuse, &ct.specular]);
    assert!(
        d.all_finite() && s.all_finite(),
        "cutoff {cutoff}, merge {merge}, {mode:?}: no NaN or infinity in the HDR targets"
    );
    let image = ImageF32 {
        width: d.width,
        height: d.height,
        pixels: d
            .pixels
            .iter()
            .zip(&s.pixels)
            .map(|(a, b)| [a[0] + b[0], a[1] + b[1], a[2] + b[2], 1.0])
            .collect(),
    };
    (image, ct.merges_lights())
}

/// `side` x `side` pairs of equal lights at one point each, `spacing` apart
/// and centred over the floor: with Light Merge at 0.5 (cubes of 0.25) and
/// `spacing` over 0.25, each pair alone in its cube.
fn coincident_pairs(side: usize, spacing: f32, intensity: f32) -> Vec<PointLight> {
    let start = -10.0 + 0.125 + (20.0 - spacing * side as f32).max(0.0) / 2.0;
    let step = 0.8 / side as f32;
    let mut lights = Vec::new();
    for (i, j) in (0..side).flat_map(|i| (0..side).map(move |j| (i, j))) {
        let light = PointLight {
            shadow: None,
            position: Vec3::new(
                start + spacing * i as f32,
                1.125,
                start + spacing * j as f32,
            ),
            color: Vec3::new(0.2 + step * i as f32, 0.5, 1.0 - step * j as f32),
            intensity,
            range: 3.0,
        };
        lights.extend([light, light]);
    }
    lights
}

/// Light Merge's partition: a cube of two equal lights at one point merges
/// into one light equal to both, so the merged image is the exact one only
/// if every froxel lists either the pair or their sum. One listing both
/// doubles the pair's light there; one listing neither loses it.
#[test]
fn a_light_merge_lists_a_cube_or_its_members_in_every_froxel_never_both() {
    let renderer = test_renderer();
    let g = scene(&renderer);
    // Pairs on a lattice 2 apart, each at the centre of a cube of 0.25 (a
    // merge distance of 0.5): no cube holds two pairs.
    let lights = coincident_pairs(10, 2.0, 6.0);
    let exact = shade(&renderer, &g, lights.clone(), LightLoop::Naive);
    for mode in FROXEL_WALKS {
        let (merged, did) = shade_approximated(&renderer, &g, &lights, mode, 0.0, 0.5);
        // The tiled walk culls by depth bins a band does not follow: it does not merge.
        assert_eq!(did, mode != LightLoop::Tiled, "{mode:?}");
        let worst = max_relative_difference(&merged, &exact);
        assert!(
            worst < 2e-3,
            "{mode:?}: the merged pairs differ by up to {worst}"
        );
    }
    // The naive walk reads every light: it does not merge, and stays exact.
    let (naive, did) = shade_approximated(&renderer, &g, &lights, LightLoop::Naive, 0.0, 0.5);
    assert!(!did);
    assert!(
        naive.pixels == exact.pixels,
        "the naive walk does not merge"
    );
}

/// Merging lights that do not coincide approximates: the walks agree (they
/// read the same lists), the light's total stays near the exact one, and
/// off (0, NaN, infinity, less than 0) or a distance no froxel reaches is exact.
#[test]
fn a_light_merge_of_scattered_lights_is_close_and_off_or_out_of_reach_is_exact() {
    let renderer = test_renderer();
    let g = scene(&renderer);
    let lights = scattered(300);
    let exact = shade(&renderer, &g, lights.clone(), LightLoop::Clustered);
    for off in [0.0, -1.0, f32::NAN, f32::INFINITY] {
        let (image, did) =
            shade_approximated(&renderer, &g, &lights, LightLoop::Clustered, 0.0, off);
        assert!(!did, "{off} merges nothing");
        // The fill's atomics order a froxel's list anew each frame: the
        // sums may differ in their last bits (the walks' own tolerance).
        let worst = max_relative_difference(&image, &exact);
        assert!(worst < 1e-3, "merge {off} is no merge: {worst}");
    }
    // Cubes of 500: every froxel lies nearer than 1,000 to every centroid,
    // so every froxel lists the members, never a cube.
    let (far, did) = shade_approximated(&renderer, &g, &lights, LightLoop::Clustered, 0.0, 1_000.0);
    assert!(
        did,
        "the 300 lights merge in the few cubes of 500 they lie in"
    );
    let worst = max_relative_difference(&far, &exact);
    assert!(
        worst < 1e-3,
        "out of reach, the merge differs by up to {worst}"
    );
    // Cubes of 2 (about three lights each): pixels 4 or more from a
    // centroid shade the cube as one light, alike in both walks that merge.
    let (merged, did) = shade_approximated(&renderer, &g, &lights, LightLoop::Clustered, 0.0, 4.0);
    let (per_pixel, also) =
        shade_approximated(&renderer, &g, &lights, LightLoop::PerPixel, 0.0, 4.0);
    assert!(did && also);
    let worst = max_relative_difference(&per_pixel, &merged);
    assert!(
        worst < 1e-3,
        "PerPixel differs from Clustered by up to {worst}"
    );
    let total = |image: &ImageF32| -> f64 {
        image
            .pixels
            .iter()
            .map(|p| f64::from(p[0] + p[1] + p[2]))
            .sum()
    };
    let ratio = total(&merged) / total(&exact);
    assert!(
        (0.9..1.1).contains(&ratio),
        "the merged light's total is {ratio} of the exact"
    );
    let changed = merged
        .pixels
        .iter()
        .zip(&exact.pixels)
        .filter(|(m, e)| (0..3).any(|c| (m[c] - e[c]).abs() > 1e-3 * e[c].abs().max(1e-3)))
        .count();
    assert!(changed > 0, "the far cubes are approximated");
}

#[test]
fn a_light_cutoff_of_zero_is_exact_and_a_cutoff_shortens_every_lights_reach_alike_in_every_walk() {
    let renderer = test_renderer();
    let g = scene(&renderer);
    let lights = scattered(300);
    let exact = shade(&renderer, &g, lights.clone(), LightLoop::Naive);
    // Off, and every value that means off (not a finite positive number):
    // the image of no cutoff, bit for bit in the naive walk's fixed order.
    for off in [0.0, -1.0, f32::NAN, f32::INFINITY, f32::NEG_INFINITY] {
        let image = shade_cut(&renderer, &g, &lights, LightLoop::Naive, off);
        assert_eq!(image.pixels, exact.pixels, "cutoff {off} is no cutoff");
    }
    // A cutoff of 2: a light of intensity 5..25 reaches sqrt(I / 2), 1.6..3.5,
    // against its range of 1..5.
    let cutoff = 2.0;
    let cut = shade_cut(&renderer, &g, &lights, LightLoop::Naive, cutoff);
    // Every walk lists and shades the same shortened spheres.
    for mode in FROXEL_WALKS {
        let walked = shade_cut(&renderer, &g, &lights, mode, cutoff);
        let worst = max_relative_difference(&walked, &cut);
        assert!(
            worst < 1e-3,
            "{mode:?} with the cutoff differs from naive by up to {worst}"
        );
    }
    // A shorter reach only dims: no pixel brighter than without (the window
    // over a shorter range is smaller everywhere), some darker, none lit
    // that was not, and most of the light kept.
    let mut darker = 0;
    let (mut kept, mut total) = (0.0f64, 0.0f64);
    for (c, e) in cut.pixels.iter().zip(&exact.pixels) {
        for k in 0..3 {
            assert!(c[k] <= e[k] * (1.0 + 1e-4) + 1e-6, "{} > {}", c[k], e[k]);
            if e[k] == 0.0 {
                assert_eq!(c[k], 0.0, "nothing lit that was not");
            }
            darker += usize::from(c[k] < e[k] * 0.999);
            kept += f64::from(c[k]);
            total += f64::from(e[k]);
        }
    }
    assert!(
        darker > 100,
        "the cutoff dims the scene ({darker} channels)"
    );
    assert!(
        kept > 0.1 * total && kept < total,
        "a cutoff of 2 keeps most of the light ({kept} of {total})"
    );
}

#[test]
fn a_light_cutoff_stays_finite_for_extreme_lights_and_cutoffs() {
    let renderer = test_renderer();
    let g = scene(&renderer);
    let light = PointLight {
        shadow: None,
        // Between the balls (their centres are at even x).
        position: Vec3::new(1.0, 1.0, 1.0),
        color: Vec3::ONE,
        intensity: 10.0,
        range: 3.0,
    };
    let lights = [
        light,
        // On the floor: the surface point at the light.
        PointLight {
            position: Vec3::new(-1.0, 0.0, 1.0),
            ..light
        },
        PointLight {
            intensity: 0.0,
            ..light
        },
        PointLight {
            range: 0.0,
            ..light
        },
        PointLight {
            intensity: 1e20,
            position: Vec3::new(-3.0, 0.5, 1.0),
            ..light
        },
        PointLight {
            color: Vec3::new(-1.0, 0.5, 0.0),
            position: Vec3::new(3.0, 0.5, 1.0),
            ..light
        },
    ];
    for cutoff in [1e-30, 1e-3, 1.0, 1e20, f32::MAX] {
        for mode in [
            LightLoop::Naive,
            LightLoop::Clustered,
            LightLoop::Tiled,
            LightLoop::PerPixel,
        ] {
            // `shade_cut` asserts every pixel finite.
            let image = shade_cut(&renderer, &g, &lights, mode, cutoff);
            if cutoff >= 1e20 {
                // No light is that bright at any distance worth a pixel but
                // the one of 1e20 candela, which reaches a metre at most.
                let lit = lit_pixels(&image);
                assert!(lit < image.pixels.len() / 4, "{mode:?}: {lit} pixels lit");
            }
        }
    }
}

/// The largest difference between two images, relative to the brighter of
/// the two texels (and at least 1, so near-black texels compare absolutely).
fn worst_relative(a: &ImageF32, b: &ImageF32) -> f32 {
    a.pixels
        .iter()
        .zip(&b.pixels)
        .flat_map(|(a, b)| {
            a.iter()
                .zip(b)
                .map(|(a, b)| (a - b).abs() / a.abs().max(b.abs()).max(1.0))
        })
        .fold(0.0f32, f32::max)
}

#[test]
fn summed_light_sets_write_one_pair_and_a_sets_own_target_only_where_read() {
    use spreadlight_render::frame_graph::TARGETS_NOT_MADE;
    use spreadlight_render::lighting::light_sets::{
        self, LIGHT_SUMS_READ, LightFusion, LightSums, SUMMED_LIGHT_SETS,
    };
    use spreadlight_render::lighting::{CompositeInputs, CompositeLight};
    let renderer = test_renderer();
    light_sets::set_light_fusion(&renderer, LightFusion::Fused);
    let g = scene(&renderer);
    let points = LightBuffer::points(&renderer, &scattered(6));
    let spot = SpotLight::cone(Vec3::new(0.0, 4.0, 0.0), Vec3::NEG_Y, 10.0, 0.5, 0.6)
        .with_light(Vec3::ONE, 200.0);
    let spots = LightBuffer::spots(&renderer, &[spot], None).expect("a valid spot");
    let shade = |lights| {
        CookTorrance::new(
            &renderer,
            None,
            g.clone(),
            lights,
            LightLoop::Naive,
            true,
            Surfaces::PerMaterialId(vec![(0.5, 0.0)]),
        )
    };
    let (point_shade, spot_shade) = (shade(points), shade(spots));
    let composite = CompositeLight::new(
        &renderer,
        None,
        g.clone(),
        CompositeInputs {
            components: vec![point_shade.components(), spot_shade.components()],
            ambient: [0.01; 3],
            materials: None,
            occlusion: None,
            gi: None,
            reflection: None,
        },
    )
    .expect("valid");
    let render = |sums: LightSums, names: &[&str]| {
        light_sets::set_light_sums(&renderer, sums);
        let (report, images) =
            render_and_read(&renderer, composite.as_ref(), SIZE, names).expect("renders");
        assert!(report.errors.is_empty(), "{sums:?}: {:?}", report.errors);
        let counts =
            [SUMMED_LIGHT_SETS, LIGHT_SUMS_READ, TARGETS_NOT_MADE].map(|name| report.counter(name));
        (images, counts)
    };
    let with_diffuse = [composite.output.as_str(), point_shade.diffuse.as_str()];
    let (each, each_counts) = render(LightSums::Off, &with_diffuse);
    assert_eq!(each_counts, [0, 0, 0], "each set writes its own targets");
    // Summed: the composite reads the pair; the point set's diffuse, asked
    // for too, is still written, the other three targets are not made.
    let (summed, summed_counts) = render(LightSums::On, &with_diffuse);
    assert_eq!(summed_counts, [2, 1, 3]);
    assert_eq!(
        each[1].pixels, summed[1].pixels,
        "a set's own target, where read, is what it was"
    );
    assert!(summed[0].all_finite());
    // The lights reach part of the floor (287 pixels of 5,184 on lavapipe).
    let lit = |image: &ImageF32| image.pixels.iter().filter(|p| p[0] > 0.05).count();
    assert!(lit(&summed[0]) > 100, "{} lit pixels", lit(&summed[0]));
    // The sum rounded to half floats once, not each set's terms: within
    // a few half-float steps (2^-11 relative each).
    let worst = worst_relative(&each[0], &summed[0]);
    assert!(worst <= 2e-3, "summed against each set's: {worst}");
    // Nothing else reads the sets: none of their four targets is made.
    let (_, alone) = render(LightSums::On, &[composite.output.as_str()]);
    assert_eq!(alone, [2, 1, 4]);
}
