//! The light loop of `CookTorrance` against the CPU reference, pixel by
//! pixel: the shader sums its lights in a factored form (brdf.wgsl's
//! `LightSums`: F0 and the albedo applied once after the loop, N.H and V.H
//! without the half vector), which must give what the reference BRDF and
//! falloff give per light, for the clustered and the naive loop, for
//! dielectrics and metals, sharp and rough.

use crate::floor_view;

use std::sync::Arc;

use floor_view::{SIZE, camera, floor_mesh, floor_points};
use glam::{Mat4, Vec3};
use spreadlight_reference::brdf::cook_torrance_f0;
use spreadlight_reference::lights::{ShaderLight, point_attenuation};
use spreadlight_render::gbuffer::{DrawBatch, GBuffer, InstanceInput, Layer};
use spreadlight_render::lighting::{CookTorrance, LightBuffer, LightLoop, PointLight, Surfaces};
use spreadlight_render::readback::{ImageF32, render_and_read};
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

/// The shipped toon light shader node's file, spliced into the light loop.
const TOON: &str = include_str!("../../../shaders/nodes/toon_lights.wgsl");

const TOON_PARAMS: spreadlight_reference::toon::ToonParams =
    spreadlight_reference::toon::ToonParams {
        bands: 3.0,
        highlight_size: 0.06,
        specular: 0.8,
    };

/// A light of any type as the test places it and as the reference sees it.
#[derive(Clone, Copy)]
enum AnyLight {
    Point(PointLight),
    Spot(spreadlight_render::lighting::SpotLight),
    Sun(spreadlight_render::lighting::SunLight),
}

/// Whether the segment from `p` along unit `dir` for `length` meets the ball.
fn hits_ball(p: Vec3, dir: Vec3, length: f32, centre: Vec3, radius: f32) -> bool {
    let t = (centre - p).dot(dir).clamp(0.0, length);
    (p + dir * t).distance(centre) < radius
}

const BALL: Vec3 = Vec3::new(0.3, 1.5, 0.2);

/// A light shader reference's light at floor point `p`, with the shadow the ball
/// casts when `shadows` and the light has a shadow slice (None: too near
/// the shadow's edge to tell).
fn shader_light_at(light: &AnyLight, p: Vec3, shadows: bool) -> Option<ShaderLight> {
    use spreadlight_reference::lights::spot_attenuation;
    let (direction, radiance, attenuation, reach) = match light {
        AnyLight::Point(l) => {
            let to = l.position - p;
            let d = to.length();
            (
                to / d,
                l.color * l.intensity,
                point_attenuation(d, l.range),
                d,
            )
        }
        AnyLight::Spot(l) => {
            let position = l.view.inverse().w_axis.truncate();
            let to = position - p;
            let d = to.length();
            let clip = l.projection * l.view * p.extend(1.0);
            let ndc = clip.truncate() / clip.w;
            let inside = clip.w > 0.0
                && ndc.x.abs() <= 1.0
                && ndc.y.abs() <= 1.0
                && (0.0..=1.0).contains(&ndc.z);
            let mask = if inside {
                spot_attenuation(1.0 - ndc.truncate().length(), 0.0, l.softness)
            } else {
                0.0
            };
            // The far plane's distance is its range (SpotLight::cone).
            let range = (l.projection.inverse() * glam::Vec4::new(0.0, 0.0, 1.0, 1.0))
                .z
                .abs()
                / (l.projection.inverse() * glam::Vec4::new(0.0, 0.0, 1.0, 1.0))
                    .w
                    .abs();
            (
                to / d,
                l.color * l.intensity * mask,
                point_attenuation(d, range),
                d,
            )
        }
        AnyLight::Sun(l) => (
            -l.direction.normalize(),
            l.color * l.illuminance,
            1.0,
            100.0,
        ),
    };
    let casts = match light {
        AnyLight::Point(l) => l.shadow.is_some(),
        AnyLight::Spot(l) => l.shadow.is_some(),
        AnyLight::Sun(l) => l.shadow.is_some(),
    };
    let mut shadow = 1.0;
    if shadows && casts {
        // A margin around the ball's edge, where the map's texels and the
        // tessellated ball decide.
        let inner = hits_ball(p, direction, reach, BALL, 0.42);
        let outer = hits_ball(p, direction, reach, BALL, 0.58);
        if inner != outer {
            return None;
        }
        shadow = if inner { 0.0 } else { 1.0 };
    }
    Some(ShaderLight {
        direction,
        radiance,
        attenuation,
        shadow,
    })
}

/// Per pixel of `shadows.rs`-like view from (0, 8, 6), the floor point it sees
/// and the unit vector to the eye; None where it may see the ball.
fn ball_floor_points(
    camera: &spreadlight_render::camera::CameraInput,
    size: (u32, u32),
    eye: Vec3,
) -> Vec<Option<(Vec3, Vec3)>> {
    use glam::Vec4Swizzles;
    let inverse = (camera.projection * camera.view).inverse();
    (0..size.1)
        .flat_map(|y| (0..size.0).map(move |x| (x, y)))
        .map(|(x, y)| {
            let ndc_x = (x as f32 + 0.5) / size.0 as f32 * 2.0 - 1.0;
            let ndc_y = 1.0 - (y as f32 + 0.5) / size.1 as f32 * 2.0;
            let h = inverse * glam::Vec4::new(ndc_x, ndc_y, 0.5, 1.0);
            let ray = (h.xyz() / h.w - eye).normalize();
            if ray.y >= -1e-3 {
                return None;
            }
            let t = -eye.y / ray.y;
            let p = eye + ray * t;
            // Pixels whose ray passes near the ball see it (or its edge).
            let seen = !hits_ball(eye, ray, t, BALL, 0.6) && p.x.abs() < 9.5 && p.z.abs() < 9.5;
            seen.then_some((p, -ray))
        })
        .collect()
}

/// A light shader node under test: its file, its uniform block, the light
/// loops each light type is walked by, and its CPU reference: (diffuse,
/// specular) at a floor point seen along `v` from `lights`, or None where
/// the pixel is too near a step of the model to compare.
struct LightShaderCase<'a> {
    node: &'a str,
    path: &'a str,
    source: &'a str,
    /// The compiled file's version key (a shader node's content hash).
    key: u64,
    params: [f32; 4],
    loops: fn(&str) -> &'static [LightLoop],
    reference: &'a ShaderReference<'a>,
}

/// (diffuse, specular) at a floor point seen along `v` from `lights`, or None to skip it.
type ShaderReference<'a> = dyn Fn(Vec3, &[ShaderLight]) -> Option<(Vec3, Vec3)> + 'a;

/// Every light type's buffer (three points, two spots, two suns, some
/// casting shadows) over the ball on the floor, shaded by `case`'s light
/// shader, with and without shadow maps: the Diffuse and Specular targets
/// must be the sums the reference makes, pixel by pixel.
fn light_shader_sums_every_light_type_as_its_reference(case: &LightShaderCase<'_>) {
    use spreadlight_render::gbuffer::{SurfaceBinding, SurfaceShader};
    use spreadlight_render::lighting::{SpotLight, SunLight};
    use spreadlight_render::shadows::{
        Cascades, ShadowFilter, ShadowLights, ShadowMaps, ShadowSettings,
    };
    let renderer = test_renderer();
    let size = (80, 60);
    let eye = Vec3::new(0.0, 8.0, 6.0);
    let camera = spreadlight_render::camera::CameraInput {
        view: glam::camera::rh::view::look_at_mat4(eye, Vec3::ZERO, Vec3::Y),
        projection: glam::camera::rh::proj::directx::perspective(
            1.0,
            size.0 as f32 / size.1 as f32,
            0.1,
            50.0,
        ),
    };
    let layers = vec![
        spreadlight_render::scenes::balls_on_floor(&renderer, &[(BALL, 0.5)], 20.0, 32)
            .expect("upload"),
    ];
    let points = [
        PointLight {
            position: Vec3::new(0.5, 4.0, 0.3),
            color: Vec3::new(1.0, 0.9, 0.8),
            intensity: 40.0,
            range: 12.0,
            shadow: Some(0),
        },
        PointLight {
            position: Vec3::new(-3.0, 1.5, 1.0),
            color: Vec3::new(0.3, 0.5, 1.0),
            intensity: 12.0,
            range: 6.0,
            shadow: None,
        },
        PointLight {
            position: Vec3::new(2.5, 2.0, -1.5),
            color: Vec3::new(1.0, 0.4, 0.2),
            intensity: 15.0,
            range: 7.0,
            shadow: Some(1),
        },
    ];
    let spots = [
        SpotLight {
            shadow: Some(0),
            ..SpotLight::cone(
                Vec3::new(0.5, 6.0, 0.5),
                Vec3::new(-0.05, -1.0, -0.1),
                12.0,
                0.3,
                0.6,
            )
            .with_light(Vec3::new(1.0, 0.95, 0.8), 200.0)
        },
        SpotLight {
            shadow: None,
            ..SpotLight::cone(
                Vec3::new(-3.0, 3.0, 3.0),
                Vec3::new(0.6, -1.0, -0.6),
                10.0,
                0.2,
                0.5,
            )
            .with_light(Vec3::new(0.4, 0.6, 1.0), 80.0)
        },
    ];
    let suns = [
        SunLight {
            direction: Vec3::new(-0.3, -1.0, -0.2),
            color: Vec3::new(1.0, 0.95, 0.9),
            illuminance: 3.0,
            shadow: Some(0),
        },
        SunLight {
            direction: Vec3::new(0.7, -0.6, 0.3),
            color: Vec3::new(0.3, 0.4, 0.8),
            illuminance: 1.5,
            shadow: None,
        },
    ];
    let cases: Vec<(&str, Arc<LightBuffer>, Vec<AnyLight>, ShadowLights)> = vec![
        (
            "points",
            LightBuffer::points(&renderer, &points),
            points.iter().map(|l| AnyLight::Point(*l)).collect(),
            ShadowLights::Point(vec![
                (0, points[0].position, points[0].range),
                (1, points[2].position, points[2].range),
            ]),
        ),
        (
            "spots",
            LightBuffer::spots(&renderer, &spots, None).expect("valid"),
            spots.iter().map(|l| AnyLight::Spot(*l)).collect(),
            ShadowLights::Spot(vec![(0, spots[0].view, spots[0].projection)]),
        ),
        (
            "suns",
            LightBuffer::suns(&renderer, &suns),
            suns.iter().map(|l| AnyLight::Sun(*l)).collect(),
            ShadowLights::Sun {
                lights: vec![(0, suns[0].direction)],
                cascades: Cascades {
                    count: 2,
                    split_lambda: 0.6,
                    distance: 20.0,
                    step: 0.0,
                },
            },
        ),
    ];
    let params: Vec<u8> = case.params.iter().flat_map(|f| f.to_le_bytes()).collect();
    let seen = ball_floor_points(&camera, size, eye);
    for (name, buffer, lights, casting) in cases {
        // A few lights are walked naively; points and spots through the clusters too.
        let loops = (case.loops)(name);
        for (with_shadows, &light_loop) in [false, true]
            .into_iter()
            .flat_map(|s| loops.iter().map(move |l| (s, l)))
        {
            let g = GBuffer::new(
                &renderer,
                None,
                layers.clone(),
                camera,
                None,
                SizeRule::Relative(1.0),
            );
            let shadows = with_shadows.then(|| {
                ShadowMaps::new(
                    &renderer,
                    None,
                    &casting,
                    layers.clone(),
                    &camera,
                    ShadowSettings {
                        resolution: 512,
                        filter: ShadowFilter::Raw,
                        ..Default::default()
                    },
                )
                .expect("valid shadows")
            });
            let shader = SurfaceShader::new(
                format!("{} #1", case.node),
                case.path.into(),
                case.source.into(),
                case.key,
                vec![(0, SurfaceBinding::Uniform)],
                params.clone(),
                Vec::new(),
                1,
            );
            let shaded = CookTorrance::with_light_shader(
                &renderer,
                Some(1),
                g,
                buffer.clone(),
                light_loop,
                Surfaces::PerMaterialId(vec![(0.5, 0.0)]),
                shadows,
                Arc::new(shader),
            );
            let (report, images) = render_and_read(
                &renderer,
                shaded.as_ref(),
                size,
                &[&shaded.diffuse, &shaded.specular],
            )
            .expect("the frame renders");
            assert!(report.errors.is_empty(), "{name}: {:?}", report.errors);
            assert!(
                report
                    .passes
                    .iter()
                    .any(|p| p.is(&format!("{} #1", case.node), Some("shade"))),
                "the pass is named after the node"
            );
            let (diffuse, specular) = (&images[0], &images[1]);
            assert!(diffuse.all_finite() && specular.all_finite());
            let (mut checked, mut shadowed, mut highlit) = (0, 0, 0);
            for (i, seen) in seen.iter().enumerate() {
                let Some((p, v)) = seen else { continue };
                let Some(reference) = lights
                    .iter()
                    .map(|l| shader_light_at(l, *p, with_shadows))
                    .collect::<Option<Vec<_>>>()
                else {
                    continue;
                };
                let Some((want_d, want_s)) = (case.reference)(*v, &reference) else {
                    continue;
                };
                for (got, want, what) in [
                    (diffuse.pixels[i], want_d, "diffuse"),
                    (specular.pixels[i], want_s, "specular"),
                ] {
                    for c in 0..3 {
                        assert!(
                            (got[c] - want[c]).abs() <= 1e-2 * want[c].abs() + 1e-4,
                            "{name}, {light_loop:?}, shadows {with_shadows}, {what} at {p}: got {got:?}, the reference says {want}"
                        );
                    }
                }
                checked += 1;
                shadowed += usize::from(reference.iter().any(|l| {
                    l.shadow == 0.0
                        && l.radiance.max_element() * l.attenuation > 1e-3
                        && l.direction.y > 0.0
                }));
                highlit += usize::from(want_s.max_element() > 1e-4);
            }
            eprintln!(
                "{} {name}, {light_loop:?}, shadows {with_shadows}: {checked} pixels, {shadowed} in a shadow, {highlit} highlit",
                case.node
            );
            assert!(
                checked * 2 > (size.0 * size.1) as usize,
                "{name}: {checked} pixels compared"
            );
            assert!(
                highlit > 0,
                "{name}, shadows {with_shadows}: some pixel has a highlight"
            );
            if with_shadows {
                assert!(
                    shadowed >= 10,
                    "{name}: {shadowed} compared pixels lie in a shadow"
                );
            }
        }
    }
}

#[test]
fn a_light_shader_node_sums_every_light_type_as_its_cpu_reference_with_and_without_shadows() {
    use spreadlight_reference::toon::{band_margin, toon_sum};
    light_shader_sums_every_light_type_as_its_reference(&LightShaderCase {
        node: "Toon (Shader)",
        path: "shaders/nodes/toon_lights.wgsl",
        source: TOON,
        key: 7,
        params: [
            TOON_PARAMS.bands,
            TOON_PARAMS.highlight_size,
            TOON_PARAMS.specular,
            0.0,
        ],
        // A few lights are walked naively; points and spots through the clusters too.
        loops: |name| match name {
            "suns" => &[LightLoop::Auto],
            _ => &[LightLoop::Auto, LightLoop::Clustered],
        },
        reference: &|v, lights| {
            (band_margin(Vec3::Y, v, lights, &TOON_PARAMS) >= 2e-3)
                .then(|| toon_sum(Vec3::Y, v, Vec3::splat(0.8), lights, &TOON_PARAMS))
        },
    });
}

/// The shipped Ashikhmin-Shirley light shader node's file.
const ASHIKHMIN_SHIRLEY: &str = include_str!("../../../shaders/nodes/ashikhmin_shirley.wgsl");

/// Anisotropic, so a wrong tangent frame or exponent shows.
const ASHIKHMIN_SHIRLEY_PARAMS: spreadlight_reference::ashikhmin_shirley::AshikhminShirleyParams =
    spreadlight_reference::ashikhmin_shirley::AshikhminShirleyParams {
        exponent_u: 60.0,
        exponent_v: 8.0,
        specular: 0.3,
    };

/// The Ashikhmin-Shirley example sums over lights as its CPU reference does
/// (smooth: every floor pixel is compared; the loop the toon test already
/// checks both ways is walked by Auto only, to keep the test cheap).
#[test]
fn the_ashikhmin_shirley_light_shader_sums_every_light_type_as_its_cpu_reference() {
    use spreadlight_reference::ashikhmin_shirley::ashikhmin_shirley_sum;
    let p = ASHIKHMIN_SHIRLEY_PARAMS;
    light_shader_sums_every_light_type_as_its_reference(&LightShaderCase {
        node: "AshikhminShirley (Shader)",
        path: "shaders/nodes/ashikhmin_shirley.wgsl",
        source: ASHIKHMIN_SHIRLEY,
        key: 8,
        params: [p.exponent_u, p.exponent_v, p.specular, 0.0],
        loops: |_| &[LightLoop::Auto],
        reference: &|v, lights| {
            Some(ashikhmin_shirley_sum(
                Vec3::Y,
                v,
                Vec3::splat(0.8),
                lights,
                &p,
            ))
        },
    });
}
