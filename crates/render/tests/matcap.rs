//! MatCap in CompositeLight: a sphere whose material has the feature shows
//! its matcap image across the silhouette, pixel by pixel as the analytic
//! sphere's normals say (the CPU twin `reference::matcap` gives the lookup);
//! materials without it are unchanged bit for bit; without a MatCap material
//! the MATCAP permutation is never compiled.

use std::sync::Arc;

use glam::{Mat4, Vec2, Vec3};
use spreadlight_reference::matcap::{default_matcap, matcap_uv};
use spreadlight_render::camera::CameraInput;
use spreadlight_render::gbuffer::{DrawBatch, GBuffer, InstanceInput, Layer};
use spreadlight_render::lighting::{
    CompositeInputs, CompositeLight, CookTorrance, LightBuffer, LightLoop, Surfaces,
};
use spreadlight_render::material::{
    Feature, MatCapMapping, MatCapMode, Material, MaterialWorld, matcap_params,
};
use spreadlight_render::mesh::primitives::{SphereParams, sphere};
use spreadlight_render::readback::{ImageF32, render_and_read};
use spreadlight_render::renderer::test_renderer;
use spreadlight_render::static_texture::StaticTexture;
use spreadlight_render::texture::GpuTexture;
use spreadlight_render::{Renderer, SizeRule};

const SIZE: (u32, u32) = (64, 48);
const RADIUS: f32 = 1.0;
const EYE: Vec3 = Vec3::new(0.0, 0.0, 4.0);
/// The matcap image's side in texels: R = u, G = v, a gradient a lookup reads back exactly.
const GRADIENT: u32 = 256;

fn camera() -> CameraInput {
    CameraInput {
        view: glam::camera::rh::view::look_at_mat4(EYE, Vec3::ZERO, Vec3::Y),
        projection: glam::camera::rh::proj::directx::perspective(
            0.7,
            SIZE.0 as f32 / SIZE.1 as f32,
            0.1,
            100.0,
        ),
    }
}

/// Spheres (centre, material id, albedo) under the test camera.
fn scene(renderer: &Renderer, spheres: &[(Vec3, u32)], albedo: f32) -> Arc<GBuffer> {
    let mesh = renderer
        .meshes
        .upload(
            &renderer.gpu,
            &sphere(SphereParams {
                radius: RADIUS,
                sectors: 96,
                stacks: 48,
            }),
        )
        .expect("upload");
    let instances = spheres
        .iter()
        .map(|&(centre, material_id)| InstanceInput {
            transform: Mat4::from_translation(centre),
            previous_transform: Mat4::from_translation(centre),
            color: [albedo, albedo, albedo, 1.0],
            material_id,
            object_id: 0,
        })
        .collect();
    let layer = Layer::plain(vec![DrawBatch { mesh, instances }]);
    GBuffer::new(
        renderer,
        None,
        vec![Arc::new(layer)],
        camera(),
        None,
        SizeRule::Relative(1.0),
    )
}

/// The gradient matcap image as a one-layer texture array: R = u, G = v.
fn gradient_images(renderer: &Renderer) -> spreadlight_render::TextureRef {
    let mut rgba = Vec::with_capacity((GRADIENT * GRADIENT * 4) as usize);
    for y in 0..GRADIENT {
        for x in 0..GRADIENT {
            rgba.extend([x as u8, y as u8, 0, 255]);
        }
    }
    let texture = GpuTexture::array_from_rgba8(
        &renderer.gpu,
        GRADIENT,
        GRADIENT,
        &[rgba],
        false,
        "matcap gradient",
    );
    StaticTexture::new(texture).texture_ref()
}

/// The lit image of `g` under no lights, `ambient` and the materials of `world`.
fn composite(
    renderer: &Renderer,
    g: &Arc<GBuffer>,
    world: Arc<MaterialWorld>,
    ambient: f32,
) -> (ImageF32, spreadlight_render::frame_graph::FrameReport) {
    let ct = CookTorrance::new(
        renderer,
        None,
        g.clone(),
        LightBuffer::points(renderer, &[]),
        LightLoop::Naive,
        false,
        Surfaces::PerMaterialId(vec![(0.5, 0.0)]),
    );
    let c = CompositeLight::new(
        renderer,
        None,
        g.clone(),
        CompositeInputs {
            components: vec![ct.components()],
            ambient: [ambient; 3],
            materials: Some(world),
            occlusion: None,
            gi: None,
            reflection: None,
        },
    )
    .expect("valid");
    let (report, mut images) =
        render_and_read(renderer, c.as_ref(), SIZE, &[&c.output]).expect("renders");
    assert!(report.errors.is_empty(), "{:?}", report.errors);
    let image = images.remove(0);
    assert!(image.all_finite());
    (image, report)
}

/// The analytic sphere at the origin under pixel `(x, y)`: its view-space
/// normal and the unit view vector to it, or None where the ray misses or
/// grazes (silhouette pixels, where a tessellated sphere may differ).
fn analytic(x: u32, y: u32) -> Option<(Vec3, Vec3)> {
    let cam = camera();
    let ndc = Vec2::new(
        (x as f32 + 0.5) / SIZE.0 as f32 * 2.0 - 1.0,
        1.0 - (y as f32 + 0.5) / SIZE.1 as f32 * 2.0,
    );
    let inverse = (cam.projection * cam.view).inverse();
    let far = inverse.project_point3(ndc.extend(0.5));
    let dir = (far - EYE).normalize();
    // |EYE + t dir| = RADIUS
    let b = EYE.dot(dir);
    let disc = b * b - (EYE.length_squared() - RADIUS * RADIUS);
    if disc <= 0.0 {
        return None;
    }
    let hit = EYE + (-b - disc.sqrt()) * dir;
    let n = cam.view.transform_vector3(hit / RADIUS).normalize();
    let v = cam.view.transform_point3(hit).normalize();
    // Keep to where the normal faces the eye well: the silhouette's pixels
    // mix sphere and background.
    (n.dot(-v) > 0.35).then_some((n, v))
}

/// Compare the image with `expected(n, v)` over the analytic sphere's
/// pixels; returns (pixels checked, largest error, mean error).
fn compare(image: &ImageF32, expected: impl Fn(Vec3, Vec3) -> Vec3) -> (usize, f32, f32) {
    let mut count = 0;
    let mut worst = 0.0f32;
    let mut sum = 0.0;
    for y in 0..SIZE.1 {
        for x in 0..SIZE.0 {
            let Some((n, v)) = analytic(x, y) else {
                continue;
            };
            let p = image.pixel(x, y);
            let got = Vec3::new(p[0], p[1], p[2]);
            let err = (got - expected(n, v)).abs().max_element();
            worst = worst.max(err);
            sum += err;
            count += 1;
        }
    }
    (count, worst, sum / count.max(1) as f32)
}

fn matcap_world(
    renderer: &Renderer,
    mode: MatCapMode,
    mapping: MatCapMapping,
    strength: f32,
    image: bool,
) -> Arc<MaterialWorld> {
    let mut m = Material::default_material()
        .with(Feature::MatCap, &[matcap_params(strength, mode, mapping)])
        .expect("valid");
    if image {
        m.set_texture(Feature::MatCap, Some(0));
    }
    MaterialWorld::with_textures(renderer, vec![m], Some(gradient_images(renderer)))
}

/// The gradient's value at a lookup: R = u, G = v (texel centres hold x/255).
fn gradient(uv: Vec2) -> Vec3 {
    let texel = |t: f32| ((t * GRADIENT as f32 - 0.5) / 255.0).clamp(0.0, 1.0);
    Vec3::new(texel(uv.x), texel(uv.y), 0.0)
}

#[test]
fn a_sphere_shows_its_matcap_gradient_across_the_silhouette() {
    let renderer = test_renderer();
    let g = scene(&renderer, &[(Vec3::ZERO, 0)], 0.5);
    // Add: the matcap as light, untinted, times strength 1.
    let world = matcap_world(&renderer, MatCapMode::Add, MatCapMapping::Normal, 1.0, true);
    let (image, report) = composite(&renderer, &g, world, 0.0);
    assert_eq!(report.counter("matcap shaded"), 1);
    let (count, worst, mean) = compare(&image, |n, v| gradient(matcap_uv(n, v, false)));
    // The tessellated sphere's interpolated normals, 8-bit texels and
    // half-float targets stay within 0.01 of the analytic sphere's lookup at
    // every pixel (lavapipe: 0.0023 worst, 0.0014 mean).
    assert!(count > 500, "the sphere covers the view: {count}");
    assert!(worst < 0.01 && mean < 0.004, "worst {worst}, mean {mean}");
    // The gradient runs the right way: left of centre is less red than right.
    let (cx, cy) = (SIZE.0 / 2, SIZE.1 / 2);
    assert!(image.pixel(cx - 10, cy)[0] < image.pixel(cx + 10, cy)[0]);
    assert!(image.pixel(cx, cy - 10)[1] < image.pixel(cx, cy + 10)[1]);

    // Multiply: tinted by albedo 0.5, at strength 2.
    let world = matcap_world(
        &renderer,
        MatCapMode::Multiply,
        MatCapMapping::Normal,
        2.0,
        true,
    );
    let (image, _) = composite(&renderer, &g, world, 0.0);
    let (_, worst, _) = compare(&image, |n, v| gradient(matcap_uv(n, v, false)) * 0.5 * 2.0);
    assert!(worst < 0.01, "multiply: worst {worst}");

    // Reflected: the sphere-mapped reflection of the view vector.
    let world = matcap_world(
        &renderer,
        MatCapMode::Add,
        MatCapMapping::Reflected,
        1.0,
        true,
    );
    let (image, _) = composite(&renderer, &g, world, 0.0);
    let (_, worst, mean) = compare(&image, |n, v| gradient(matcap_uv(n, v, true)));
    assert!(
        worst < 0.01 && mean < 0.004,
        "reflected: worst {worst}, mean {mean}"
    );

    // No image named: the built-in clay matcap.
    let world = matcap_world(
        &renderer,
        MatCapMode::Add,
        MatCapMapping::Normal,
        1.0,
        false,
    );
    let (image, _) = composite(&renderer, &g, world, 0.0);
    let (_, worst, _) = compare(&image, |n, v| default_matcap(matcap_uv(n, v, false)));
    assert!(worst < 0.01, "built-in: worst {worst}");
}

#[test]
fn materials_without_matcap_stay_bit_for_bit_and_compile_no_matcap_code() {
    let renderer = test_renderer();
    // Two balls: material 0 left, material 1 right.
    let g = scene(
        &renderer,
        &[
            (Vec3::new(-1.2, 0.0, -1.0), 0),
            (Vec3::new(1.2, 0.0, -1.0), 1),
        ],
        0.8,
    );
    let plain = MaterialWorld::new(
        &renderer,
        vec![Material::default_material(), Material::default_material()],
    );
    let (before, report) = composite(&renderer, &g, plain, 0.3);
    assert_eq!(report.counter("matcap shaded"), 0);
    assert!(
        renderer
            .shaders()
            .compiled_keys()
            .all(|k| !k.features.contains("MATCAP")),
        "no MatCap material: the matcap permutation is never compiled"
    );
    let matcap = Material::default_material()
        .with(
            Feature::MatCap,
            &[matcap_params(1.0, MatCapMode::Add, MatCapMapping::Normal)],
        )
        .expect("valid");
    let world = MaterialWorld::new(&renderer, vec![Material::default_material(), matcap]);
    let (after, report) = composite(&renderer, &g, world, 0.3);
    assert_eq!(report.counter("matcap shaded"), 1);
    assert!(
        renderer
            .shaders()
            .compiled_keys()
            .any(|k| k.path() == "lighting/composite.wgsl" && k.features.contains("MATCAP"))
    );
    let (mut same, mut changed) = (0, 0);
    for y in 0..SIZE.1 {
        for x in 0..SIZE.0 {
            let (a, b) = (before.pixel(x, y), after.pixel(x, y));
            if x < SIZE.0 / 2 {
                assert_eq!(a, b, "pixel ({x}, {y}) of the plain ball or background");
                same += 1;
            } else if a != b {
                changed += 1;
            }
        }
    }
    assert!(
        same > 0 && changed > 100,
        "the matcap ball changed: {changed}"
    );
}

#[test]
fn matcap_at_strength_zero_or_on_a_degenerate_view_stays_finite_and_adds_nothing() {
    let renderer = test_renderer();
    let g = scene(&renderer, &[(Vec3::ZERO, 0)], 0.5);
    let off = matcap_world(
        &renderer,
        MatCapMode::Add,
        MatCapMapping::Reflected,
        0.0,
        true,
    );
    let (image, _) = composite(&renderer, &g, off, 0.0);
    assert!(image.pixels.iter().all(|p| p[..3] == [0.0; 3]));
    // A huge strength is clamped below half-float overflow, never infinite.
    let huge = matcap_world(
        &renderer,
        MatCapMode::Add,
        MatCapMapping::Reflected,
        1e30,
        false,
    );
    let (image, _) = composite(&renderer, &g, huge, 0.0);
    assert!(image.pixels.iter().all(|p| p[0] <= 65000.0));
}
