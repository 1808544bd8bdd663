//! The light loop of `CookTorrance` against the CPU reference, pixel by
//! pixel: the shader sums its lights in a factored form (brdf.wgsl's
//! `LightSums`: F0 and the albedo applied once after the loop, N.H and V.H
//! without the half vector), which must give what the reference BRDF and
//! falloff give per light, for the clustered and the naive loop, for
//! dielectrics and metals, sharp and rough.

mod floor_view;

use std::sync::Arc;

use floor_view::{SIZE, camera, floor_mesh, floor_points};
use glam::{Mat4, Vec3};
use spreadlight_render::gbuffer::{DrawBatch, GBuffer, InstanceInput, Layer};
use spreadlight_render::lighting::{CookTorrance, LightBuffer, LightLoop, PointLight, Surfaces};
use spreadlight_render::readback::{ImageF32, render_and_read};
use spreadlight_render::reference::brdf::cook_torrance_f0;
use spreadlight_render::reference::lights::point_attenuation;
use spreadlight_render::renderer::test_renderer;
use spreadlight_render::{Renderer, SizeRule};

/// Exact in an 8-bit target, so the G-buffer's albedo is this.
const ALBEDO: Vec3 = Vec3::new(0.8, 0.6, 0.4);

fn floor(renderer: &Renderer) -> Arc<GBuffer> {
    let plane = floor_mesh(renderer);
    let batches = vec![DrawBatch {
        mesh: plane,
        instances: vec![InstanceInput {
            transform: Mat4::IDENTITY,
            previous_transform: Mat4::IDENTITY,
            color: ALBEDO.extend(1.0).to_array(),
            material_id: 0,
            object_id: 0,
        }],
    }];
    let layer = Arc::new(Layer::plain(batches));
    GBuffer::new(
        renderer,
        None,
        vec![layer],
        camera(),
        None,
        SizeRule::Relative(1.0),
    )
}

/// Lights near and over the floor, coloured, with ranges that end inside
/// the view, one just over the floor (light at grazing angles), and one without a range (it must
/// light nothing).
fn lights() -> Vec<PointLight> {
    let light = |x: f32, y: f32, z: f32, color: [f32; 3], intensity: f32, range: f32| PointLight {
        position: Vec3::new(x, y, z),
        color: Vec3::from(color),
        intensity,
        range,
        shadow: None,
    };
    vec![
        light(0.0, 1.0, 0.0, [1.0, 0.9, 0.8], 20.0, 6.0),
        light(-2.5, 0.4, 1.5, [0.2, 0.5, 1.0], 8.0, 2.5),
        light(2.0, 0.15, -1.0, [1.0, 0.3, 0.1], 5.0, 1.5),
        light(1.0, 2.5, 2.5, [0.6, 1.0, 0.6], 40.0, 9.0),
        light(-1.0, 0.05, -2.0, [1.0, 1.0, 1.0], 3.0, 2.0),
        light(0.5, 1.0, 0.5, [1.0, 1.0, 1.0], 1000.0, 0.0),
    ]
}

/// What the reference says the floor at `p`, seen along `v`, reflects.
fn expected(p: Vec3, v: Vec3, roughness: f32, metallic: f32) -> (Vec3, Vec3) {
    let mut diffuse = Vec3::ZERO;
    let mut specular = Vec3::ZERO;
    for light in lights() {
        let to_light = light.position - p;
        let distance = to_light.length();
        let attenuation = point_attenuation(distance, light.range);
        if attenuation <= 0.0 {
            continue;
        }
        let l = if distance > 1e-10 {
            to_light / distance
        } else {
            Vec3::Y
        };
        let brdf = cook_torrance_f0(Vec3::Y, v, l, ALBEDO, roughness, metallic, 0.04, true);
        let radiance = light.color * light.intensity * attenuation;
        diffuse += brdf.diffuse * radiance;
        specular += brdf.specular * radiance;
    }
    (diffuse, specular)
}

fn shade(
    renderer: &Renderer,
    g: &Arc<GBuffer>,
    light_loop: LightLoop,
    roughness: f32,
    metallic: f32,
) -> [ImageF32; 2] {
    let ct = CookTorrance::new(
        renderer,
        None,
        g.clone(),
        LightBuffer::points(renderer, &lights()),
        light_loop,
        true,
        Surfaces::PerMaterialId(vec![(roughness, metallic)]),
    );
    let (report, images) =
        render_and_read(renderer, ct.as_ref(), SIZE, &[&ct.diffuse, &ct.specular])
            .expect("the frame renders");
    assert!(report.errors.is_empty(), "{:?}", report.errors);
    images
        .try_into()
        .unwrap_or_else(|_| unreachable!("two images"))
}

#[test]
fn every_floor_pixel_is_lit_as_the_reference_brdf_and_falloff_say() {
    let renderer = test_renderer();
    let g = floor(&renderer);
    let points = floor_points();
    for light_loop in [LightLoop::Clustered, LightLoop::Naive] {
        for (roughness, metallic) in [(0.5, 0.0), (0.2, 0.0), (0.8, 1.0), (0.3, 0.5)] {
            let [diffuse, specular] = shade(&renderer, &g, light_loop, roughness, metallic);
            assert!(diffuse.all_finite() && specular.all_finite());
            let (mut checked, mut lit) = (0, 0);
            let mut worst = 0.0f32;
            for ((d, s), seen) in diffuse.pixels.iter().zip(&specular.pixels).zip(&points) {
                let Some((p, v)) = seen else { continue };
                let (want_d, want_s) = expected(*p, *v, roughness, metallic);
                for (got, want) in [(d, want_d), (s, want_s)] {
                    for c in 0..3 {
                        let error = (got[c] - want[c]).abs() / (want[c].abs() + 1e-3);
                        worst = worst.max(error);
                        assert!(
                            (got[c] - want[c]).abs() <= 1e-2 * want[c].abs() + 1e-4,
                            "{light_loop:?}, roughness {roughness}, metallic {metallic} at {p}: \
                             got {got:?}, the reference says {want}"
                        );
                    }
                }
                checked += 1;
                lit += usize::from(want_s.max_element() > 1e-3);
            }
            assert!(
                checked > (SIZE.0 * SIZE.1 / 2) as usize,
                "{checked} floor pixels"
            );
            assert!(
                lit > checked / 10,
                "{lit} of {checked} pixels have a highlight"
            );
            eprintln!(
                "{light_loop:?} roughness {roughness} metallic {metallic}: worst relative {worst}"
            );
        }
    }
}
