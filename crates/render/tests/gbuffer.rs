//! The G-buffer on a real (software) GPU: its contents checked numerically,
//! and the frame graph's culling proven by its statistics. Small sizes; runs
//! on lavapipe.

use std::sync::Arc;

use glam::{Mat4, Vec3, Vec4};
use spreadlight_render::camera::CameraInput;
use spreadlight_render::gbuffer::{
    Channel, DrawBatch, GBuffer, GBufferView, InstanceInput, Layer, LayerFeatures, RasterChoice,
    RasterMode, SURFACE_AND_MOTION_DISPATCHES,
};
use spreadlight_render::mesh::primitives::{SphereParams, sphere};
use spreadlight_render::readback::{ImageF32, read_texture};
use spreadlight_render::renderer::test_renderer;
use spreadlight_render::{FrameGraph, Renderer, SizeRule};

const SIZE: (u32, u32) = (64, 64);

fn camera_at(eye: Vec3) -> CameraInput {
    CameraInput {
        view: glam::camera::rh::view::look_at_mat4(eye, Vec3::ZERO, Vec3::Y),
        projection: glam::camera::rh::proj::directx::perspective(
            60f32.to_radians(),
            1.0,
            0.1,
            100.0,
        ),
    }
}

fn instance(transform: Mat4, previous: Mat4) -> InstanceInput {
    InstanceInput {
        transform,
        previous_transform: previous,
        color: [0.8, 0.5, 0.2, 1.0],
        material_id: 3,
        object_id: 7,
    }
}

fn sphere_layer(
    renderer: &Renderer,
    instances: Vec<InstanceInput>,
    features: LayerFeatures,
) -> Arc<Layer> {
    sphere_layer_of(renderer, (48, 24), instances, features)
}

/// [`sphere_layer`] with a sphere of `(sectors, stacks)`.
fn sphere_layer_of(
    renderer: &Renderer,
    (sectors, stacks): (u32, u32),
    instances: Vec<InstanceInput>,
    features: LayerFeatures,
) -> Arc<Layer> {
    let mesh = renderer
        .meshes
        .upload(
            &renderer.gpu,
            &sphere(SphereParams {
                radius: 1.0,
                sectors,
                stacks,
            }),
        )
        .expect("upload");
    Arc::new(
        Layer::new(Some(1), vec![DrawBatch { mesh, instances }], features, None)
            .expect("valid layer"),
    )
}

/// Render `gbuffer`, requesting the given targets, and read them back.
fn render(
    renderer: &Renderer,
    gbuffer: &Arc<GBuffer>,
    targets: &[&str],
) -> (spreadlight_render::FrameReport, Vec<ImageF32>) {
    let (report, images) =
        spreadlight_render::readback::render_and_read(renderer, gbuffer.as_ref(), SIZE, targets)
            .expect("frame executes");
    assert!(report.errors.is_empty(), "{:?}", report.errors);
    (report, images)
}

#[test]
fn a_sphere_faces_the_camera_and_depth_reconstructs_its_surface_hardware() {
    sphere_checks(RasterChoice::Hardware, RasterMode::Hardware);
}

#[test]
fn a_sphere_faces_the_camera_and_depth_reconstructs_its_surface_compute() {
    let renderer = test_renderer();
    assert!(
        renderer.gpu.has_compute_raster(),
        "the compute rasterizer needs 64-bit atomics, which {} lacks",
        renderer.gpu.adapter_name()
    );
    sphere_checks(RasterChoice::Compute, RasterMode::Compute);
}

fn sphere_checks(choice: RasterChoice, expected: RasterMode) {
    let renderer = test_renderer();
    let layer = sphere_layer(
        &renderer,
        vec![instance(Mat4::IDENTITY, Mat4::IDENTITY)],
        LayerFeatures::default(),
    );
    let camera = camera_at(Vec3::new(0.0, 0.0, 5.0));
    let g = GBuffer::with_raster(
        &renderer,
        Some(2),
        vec![layer],
        camera,
        None,
        SizeRule::Relative(1.0),
        choice,
    );
    assert_eq!(g.raster, expected);
    let t = g.targets.clone();
    let (_, images) = render(
        &renderer,
        &g,
        &[&t.color, &t.normals, &t.depth, &t.velocity_uv],
    );
    let [color, normals, depth, velocity] = &images[..] else {
        unreachable!()
    };
    for image in &images {
        assert!(image.all_finite(), "no NaN or infinity in any target");
    }

    // The centre pixel sees the sphere's front: its view-space normal points at the camera,
    // and equals the analytic normal of the surface point its depth reconstructs.
    let n = normals.pixel(32, 32);
    let n = Vec3::new(n[0], n[1], n[2]);
    assert!(n.z > 0.99, "normal at centre {n:?}");
    let inv_view_proj =
        (spreadlight_render::camera::reverse_z(camera.projection) * camera.view).inverse();
    let surface = |x: u32, y: u32| {
        let ndc = Vec4::new(
            (x as f32 + 0.5) / 32.0 - 1.0,
            1.0 - (y as f32 + 0.5) / 32.0,
            depth.pixel(x, y)[0],
            1.0,
        );
        let world = inv_view_proj * ndc;
        world.truncate() / world.w
    };
    let analytic = (camera.view * surface(32, 32).normalize().extend(0.0)).truncate();
    assert!(
        n.distance(analytic) < 0.01,
        "normal {n:?} vs analytic {analytic:?}"
    );
    let n = normals.pixel(32, 32);
    assert_eq!(n[3], 7.0, "object id in normals alpha");
    let c = color.pixel(32, 32);
    assert_eq!(c[3], 3.0, "material id in color alpha");
    assert!((c[0] - 0.8).abs() < 1e-3);
    // A corner sees nothing: cleared targets, depth at the far end (reversed-Z: 0).
    assert_eq!(normals.pixel(0, 0), [0.0; 4]);
    assert_eq!(depth.pixel(0, 0)[0], 0.0);

    // Depth reconstructs the world position of the sphere's surface: for
    // every covered pixel, the reconstructed point lies on the unit sphere.
    let mut worst: f32 = 0.0;
    let mut covered = 0;
    for y in 0..SIZE.1 {
        for x in 0..SIZE.0 {
            let d = depth.pixel(x, y)[0];
            if d == 0.0 {
                continue;
            }
            covered += 1;
            worst = worst.max((surface(x, y).length() - 1.0).abs());
        }
    }
    assert!(
        covered > 300,
        "the sphere covers a good part of the image ({covered} px)"
    );
    assert!(
        worst < 0.01,
        "reconstructed surface off the sphere by {worst}"
    );
    // A static scene has no velocity anywhere.
    assert!(velocity.pixels.iter().all(|p| p[0] == 0.0 && p[1] == 0.0));
}

#[test]
fn velocity_matches_a_known_motion() {
    let renderer = test_renderer();
    // The sphere moved +0.5 along X since last frame; the camera is still.
    let now = Mat4::from_translation(Vec3::new(0.5, 0.0, 0.0));
    let layer = sphere_layer(
        &renderer,
        vec![instance(now, Mat4::IDENTITY)],
        LayerFeatures::default(),
    );
    let camera = camera_at(Vec3::new(0.0, 0.0, 5.0));
    let g = GBuffer::new(
        &renderer,
        None,
        vec![layer],
        camera,
        Some(camera.view_projection()),
        SizeRule::Relative(1.0),
    );
    let (_, images) = render(&renderer, &g, &[&g.targets.velocity_uv]);
    // At the front pole (0.5, 0, 1) now, (0, 0, 1) before: project both.
    let vp = camera.view_projection();
    let project = |p: Vec3| {
        let c = vp * p.extend(1.0);
        (c.truncate() / c.w).truncate()
    };
    let expected = (project(Vec3::new(0.5, 0.0, 1.0)) - project(Vec3::new(0.0, 0.0, 1.0)))
        * glam::Vec2::new(0.5, -0.5);
    let pole_ndc = project(Vec3::new(0.5, 0.0, 1.0));
    let px = (((pole_ndc.x + 1.0) * 0.5) * SIZE.0 as f32) as u32;
    let py = (((1.0 - pole_ndc.y) * 0.5) * SIZE.1 as f32) as u32;
    let v = images[0].pixel(px, py);
    assert!(
        (v[0] - expected.x).abs() < 2e-3 && (v[1] - expected.y).abs() < 2e-3,
        "velocity {v:?}, expected {expected:?}"
    );
    assert!(expected.x > 0.01, "the test moves something visibly");
}

#[test]
fn a_pass_chain_nobody_requests_is_culled() {
    let renderer = test_renderer();
    let layer = sphere_layer(
        &renderer,
        vec![instance(Mat4::IDENTITY, Mat4::IDENTITY)],
        LayerFeatures::default(),
    );
    let g = GBuffer::new(
        &renderer,
        Some(2),
        vec![layer],
        camera_at(Vec3::new(0.0, 0.0, 5.0)),
        None,
        SizeRule::Relative(1.0),
    );
    // Viewing normals needs the visibility and surface passes, not the motion resolve.
    let view = GBufferView::new(&renderer, Some(3), g.clone(), Channel::Normals, 1.0);
    let texture = view.texture();
    let mut fg = FrameGraph::new(SIZE);
    texture.recipe.declare(&renderer, &mut fg);
    fg.request(&texture.name);
    let (report, outputs) = fg.execute(&renderer).expect("frame executes");
    assert!(report.errors.is_empty(), "{:?}", report.errors);
    let executed: Vec<(&str, Option<&str>, Option<u32>)> = report
        .passes
        .iter()
        .map(|p| (p.kind.as_ref(), p.step.as_deref(), p.owner))
        .collect();
    let raster = match g.raster {
        RasterMode::Hardware => "visibility",
        RasterMode::Compute => "compute raster",
    };
    assert_eq!(
        executed,
        [
            ("MRE", Some(raster), Some(2)),
            ("MRE", Some("resolve surface"), Some(2)),
            ("GBufferView", Some("Normals"), Some(3))
        ]
    );
    assert_eq!(report.culled, ["MRE #2: resolve motion"]);
    assert_eq!(report.draws, 1, "one instanced draw per mesh");
    let image = read_texture(&renderer.gpu, &outputs[&texture.name]).expect("readback");
    let centre = image.pixel(32, 32);
    assert!(
        (centre[2] - 1.0).abs() < 0.02,
        "normal (0,0,1) shows as blue: {centre:?}"
    );

    // The same frame again compiles nothing new.
    let mut fg = FrameGraph::new(SIZE);
    texture.recipe.declare(&renderer, &mut fg);
    fg.request(&texture.name);
    let (again, _) = fg.execute(&renderer).expect("frame executes");
    assert_eq!(again.pipelines_compiled, 0);
}

#[test]
fn ten_thousand_instances_are_one_draw() {
    let renderer = test_renderer();
    let instances: Vec<InstanceInput> = (0..10_000)
        .map(|i| {
            let t = Mat4::from_translation(Vec3::new(
                (i % 100) as f32 * 3.0 - 150.0,
                0.0,
                (i / 100) as f32 * -3.0,
            ));
            instance(t, t)
        })
        .collect();
    // A coarse sphere: what is counted is instances and draws, and the
    // 48 x 24 sphere's 10,000 x 2,200 triangles were most of the test's CPU
    // on lavapipe (6.3 s of CPU; 0.7 s with the 16 x 8 sphere).
    let layer = sphere_layer_of(&renderer, (16, 8), instances, LayerFeatures::default());
    let g = GBuffer::new(
        &renderer,
        None,
        vec![layer],
        camera_at(Vec3::new(0.0, 20.0, 30.0)),
        None,
        SizeRule::Relative(1.0),
    );
    let (report, images) = render(&renderer, &g, &[&g.targets.normals]);
    assert_eq!(report.draws, 1);
    assert_eq!(g.instance_count(), 10_000);
    assert!(images[0].all_finite());
}

#[test]
fn normal_mapping_bends_normals_along_the_tangent() {
    use spreadlight_render::mesh::primitives::{GridParams, grid};
    use spreadlight_render::static_texture::StaticTexture;
    use spreadlight_render::texture::GpuTexture;
    let renderer = test_renderer();
    let mesh = renderer
        .meshes
        .upload(
            &renderer.gpu,
            &grid(GridParams {
                size: glam::Vec2::splat(4.0),
                resolution_x: 2,
                resolution_y: 2,
            }),
        )
        .expect("upload");
    // A normal map whose every texel says "along the tangent" (+X in tangent space).
    let texels = [255u8, 128, 128, 255].repeat(4);
    let normal_map = StaticTexture::new(GpuTexture::from_rgba8(
        &renderer.gpu,
        2,
        2,
        &texels,
        false,
        "normal map",
    ));
    let facing_camera = Mat4::from_rotation_x(std::f32::consts::FRAC_PI_2);
    let features = LayerFeatures {
        texcoords: true,
        normal_map: true,
        ..Default::default()
    };
    let layer = Layer::new(
        Some(1),
        vec![DrawBatch {
            mesh: mesh.clone(),
            instances: vec![instance(facing_camera, facing_camera)],
        }],
        features,
        Some(normal_map.texture_ref()),
    )
    .expect("a grid has UVs and tangents");
    let g = GBuffer::new(
        &renderer,
        None,
        vec![Arc::new(layer)],
        camera_at(Vec3::new(0.0, 0.0, 5.0)),
        None,
        SizeRule::Relative(1.0),
    );
    let (report, images) = render(&renderer, &g, &[&g.targets.normals]);
    let n = images[0].pixel(32, 32);
    assert!(
        (n[0] - 1.0).abs() < 0.02 && n[2].abs() < 0.05,
        "mapped normal {n:?}"
    );
    assert!(
        report.pipelines_compiled >= 2,
        "the normal-mapped permutation was compiled"
    );

    // The same layer without the switch keeps the geometric normal (facing the camera).
    let plain = Layer::new(
        Some(1),
        vec![DrawBatch {
            mesh,
            instances: vec![instance(facing_camera, facing_camera)],
        }],
        LayerFeatures::default(),
        None,
    )
    .expect("valid");
    let g = GBuffer::new(
        &renderer,
        None,
        vec![Arc::new(plain)],
        camera_at(Vec3::new(0.0, 0.0, 5.0)),
        None,
        SizeRule::Relative(1.0),
    );
    let (_, images) = render(&renderer, &g, &[&g.targets.normals]);
    let n = images[0].pixel(32, 32);
    assert!((n[2] - 1.0).abs() < 0.02, "geometric normal {n:?}");
}

#[test]
fn a_switch_the_geometry_cannot_serve_is_an_error_not_a_broken_image() {
    use spreadlight_render::gbuffer::LayerError;
    use spreadlight_render::mesh::MeshData;
    let renderer = test_renderer();
    // A mesh without texture coordinates.
    let mut data: MeshData = sphere(SphereParams::default());
    data.uvs = None;
    data.tangents = None;
    let mesh = renderer
        .meshes
        .upload(&renderer.gpu, &data)
        .expect("upload");
    let batch = || {
        vec![DrawBatch {
            mesh: mesh.clone(),
            instances: vec![instance(Mat4::IDENTITY, Mat4::IDENTITY)],
        }]
    };
    let texcoords = LayerFeatures {
        texcoords: true,
        ..Default::default()
    };
    assert_eq!(
        Layer::new(None, batch(), texcoords, None).err(),
        Some(LayerError::NoTexcoords {
            switch: "Texture Coordinates",
            mesh: 0
        })
    );
    let normal_map = LayerFeatures {
        normal_map: true,
        ..Default::default()
    };
    assert_eq!(
        Layer::new(None, batch(), normal_map, None).err(),
        Some(LayerError::NoNormalTexture)
    );
    // Triplanar serves texture coordinates for geometry that has none.
    let triplanar = LayerFeatures {
        triplanar: true,
        ..Default::default()
    };
    assert!(Layer::new(None, batch(), triplanar, None).is_ok());
}

#[test]
fn both_rasterizers_see_the_same_scene() {
    // A crowd of spheres on a plane that crosses the near plane: small
    // triangles, big tiled ones and near-clipped ones all at once.
    use spreadlight_render::mesh::primitives::{GridParams, grid};
    let renderer = test_renderer();
    let sphere_mesh = renderer
        .meshes
        .upload(&renderer.gpu, &sphere(SphereParams::default()))
        .expect("upload");
    let plane = renderer
        .meshes
        .upload(
            &renderer.gpu,
            &grid(GridParams {
                size: glam::Vec2::splat(100.0),
                resolution_x: 1,
                resolution_y: 1,
            }),
        )
        .expect("upload");
    let spheres: Vec<InstanceInput> = (0..400)
        .map(|i| {
            let t = Mat4::from_translation(Vec3::new(
                (i % 20) as f32 * 2.0 - 20.0,
                0.5,
                (i / 20) as f32 * -2.0 + 3.0,
            ));
            instance(t, t)
        })
        .collect();
    let batches = vec![
        DrawBatch {
            mesh: sphere_mesh,
            instances: spheres,
        },
        DrawBatch {
            mesh: plane.clone(),
            instances: vec![instance(Mat4::IDENTITY, Mat4::IDENTITY)],
        },
    ];
    let layer = Arc::new(Layer::plain(batches));
    let camera = camera_at(Vec3::new(0.0, 3.0, 6.0));
    // At 64x64 the plane's triangles are queued tile by tile; at 320x288
    // (90 tiles of 32 pixels) they are giants, whose tiles every workgroup
    // shares (raster.wgsl, GIANT_TILES).
    for size in [SIZE, (320, 288)] {
        both_rasterizers_agree(&renderer, &layer, camera, size);
    }
    // More giants than their queue holds (40 planes a step apart, 80
    // triangles): the rest go tile by tile, and the nearest plane still wins.
    let planes = vec![DrawBatch {
        mesh: plane,
        instances: (0..40)
            .map(|i| {
                let t = Mat4::from_translation(Vec3::new(0.0, -0.02 * i as f32, 0.0));
                instance(t, t)
            })
            .collect(),
    }];
    let stack = Arc::new(Layer::plain(planes));
    both_rasterizers_agree(&renderer, &stack, camera, (320, 288));
}

#[test]
fn more_meshes_than_one_dispatch_holds_are_rasterized_where_the_hardware_draws_them() {
    // 1,100 meshes, each its own draw: more than one compute dispatch holds
    // (RUN_BATCHES, 256), so the compute raster runs its draws in five
    // dispatches, each thread finding its draw among up to 256. Meshes of
    // two sizes in turn, so a workgroup's threads span draws of different
    // triangle counts.
    let renderer = test_renderer();
    let meshes = [(6, 3), (8, 4)].map(|(sectors, stacks)| {
        renderer
            .meshes
            .upload(
                &renderer.gpu,
                &sphere(SphereParams {
                    radius: 0.45,
                    sectors,
                    stacks,
                }),
            )
            .expect("upload")
    });
    let batches: Vec<DrawBatch> = (0..1_100)
        .map(|i| {
            let t = Mat4::from_translation(Vec3::new(
                (i % 44) as f32 - 22.0,
                0.0,
                3.0 - (i / 44) as f32,
            ));
            DrawBatch {
                mesh: meshes[i % 2].clone(),
                instances: vec![instance(t, t)],
            }
        })
        .collect();
    let layer = Arc::new(Layer::plain(batches));
    let camera = camera_at(Vec3::new(0.0, 12.0, 14.0));
    let g = drawn_by(&renderer, &layer, camera, RasterChoice::Compute);
    let (report, _) = render(&renderer, &g, &[&g.targets.depth]);
    assert_eq!(report.draws, 1_100, "every mesh is counted as a draw");
    both_rasterizers_agree(&renderer, &layer, camera, (160, 96));
}

#[test]
fn instances_reaching_into_the_view_from_outside_it_are_drawn() {
    // The compute raster leaves out an instance whose bounding sphere lies
    // wholly outside a side of the view (raster.wgsl, may_cover). Spheres
    // whose centres lie outside the view but whose bodies reach into it (a
    // stretch of 12 along x, of 0.1 along y, a shear) or lie just beyond
    // each side must come out as the raster hardware draws them.
    let renderer = test_renderer();
    let camera = camera_at(Vec3::new(0.0, 0.0, 6.0));
    // At z = 0 the 60-degree view reaches 6 tan(30) = 3.46 either side.
    let placed = |t: Mat4| instance(t, t);
    let mut instances = vec![
        placed(
            Mat4::from_translation(Vec3::new(-7.5, 0.0, 0.0))
                * Mat4::from_scale(Vec3::new(6.0, 1.5, 0.5)),
        ),
        placed(
            Mat4::from_translation(Vec3::new(0.0, 4.4, 0.0))
                * Mat4::from_scale(Vec3::new(2.5, 1.5, 0.5)),
        ),
        placed(Mat4::from_cols(
            Vec4::new(0.5, 0.0, 0.0, 0.0),
            Vec4::new(3.5, 1.5, 0.0, 0.0),
            Vec4::new(0.0, 0.0, 0.5, 0.0),
            Vec4::new(6.0, -1.0, 0.0, 1.0),
        )),
    ];
    for (x, y) in [(1.0, 0.0), (-1.0, 0.0), (0.0, 1.0), (0.0, -1.0)] {
        // Just outside each side (the sphere's radius is 1), then just in.
        for reach in [3.46 + 1.02, 3.46 + 0.95] {
            let t = Mat4::from_translation(Vec3::new(x * reach, y * reach, 0.0));
            instances.push(placed(t));
        }
    }
    let layer = sphere_layer_of(&renderer, (16, 8), instances, LayerFeatures::default());
    // Which pixels each rasterizer covers (depth > 0: reversed Z, the
    // background 0). They may disagree on silhouette pixels, a few per
    // object; an object left out would be hundreds.
    let size = (128, 128);
    let covered: Vec<Vec<bool>> = [RasterChoice::Hardware, RasterChoice::Compute]
        .into_iter()
        .map(|choice| {
            let g = drawn_by(&renderer, &layer, camera, choice);
            let (report, out) = spreadlight_render::readback::render_and_read(
                &renderer,
                g.as_ref(),
                size,
                &[&g.targets.depth],
            )
            .expect("frame executes");
            assert!(report.errors.is_empty(), "{:?}", report.errors);
            out[0].pixels.iter().map(|p| p[0] > 0.0).collect()
        })
        .collect();
    let drawn = covered[0].iter().filter(|&&c| c).count();
    let differing = covered[0]
        .iter()
        .zip(&covered[1])
        .filter(|(a, b)| a != b)
        .count();
    assert!(drawn > 1_500, "the scene covers {drawn} pixels");
    assert!(
        differing < 60,
        "{differing} of {drawn} covered pixels differ between the rasterizers"
    );
}

/// A G-buffer of `layer` seen by `camera`, drawn by the `choice` rasterizer.
fn drawn_by(
    renderer: &Renderer,
    layer: &Arc<Layer>,
    camera: CameraInput,
    choice: RasterChoice,
) -> Arc<GBuffer> {
    GBuffer::with_raster(
        renderer,
        None,
        vec![layer.clone()],
        camera,
        None,
        SizeRule::Relative(1.0),
        choice,
    )
}

fn both_rasterizers_agree(
    renderer: &Renderer,
    layer: &Arc<Layer>,
    camera: CameraInput,
    size: (u32, u32),
) {
    let mut images = Vec::new();
    for choice in [RasterChoice::Hardware, RasterChoice::Compute] {
        let g = drawn_by(renderer, layer, camera, choice);
        let (report, mut out) = spreadlight_render::readback::render_and_read(
            renderer,
            g.as_ref(),
            size,
            &[&g.targets.normals, &g.targets.depth],
        )
        .expect("frame executes");
        assert!(report.errors.is_empty(), "{:?}", report.errors);
        images.push((out.remove(0), out.remove(0)));
    }
    let (hw, cs) = (&images[0], &images[1]);
    let total = hw.0.pixels.len();
    let differing =
        hw.0.pixels
            .iter()
            .zip(&cs.0.pixels)
            .filter(|(a, b)| a.iter().zip(b.iter()).any(|(x, y)| (x - y).abs() > 0.05))
            .count();
    // Rasterizers may disagree on pixels exactly on silhouette edges, nowhere else.
    assert!(
        differing * 100 < total * 3,
        "{size:?}: {differing} of {total} pixels differ"
    );
    let depth_close =
        hw.1.pixels
            .iter()
            .zip(&cs.1.pixels)
            .filter(|(a, b)| (a[0] - b[0]).abs() < 1e-4)
            .count();
    assert!(
        depth_close * 100 > total * 97,
        "{size:?}: depth agrees on {depth_close} of {total} pixels"
    );
    assert!(cs.0.all_finite() && cs.1.all_finite());
}

#[test]
fn reversed_z_keeps_depth_precise_from_near_1e_minus_4_to_far_1e6() {
    // A sphere 50 units away seen through a projection with near 1e-4 and
    // far 1e6: reversed-Z float depth still reconstructs its surface.
    let renderer = test_renderer();
    let at = Vec3::new(0.0, 0.0, -50.0);
    let layer = sphere_layer(
        &renderer,
        vec![instance(
            Mat4::from_translation(at) * Mat4::from_scale(Vec3::splat(10.0)),
            Mat4::IDENTITY,
        )],
        LayerFeatures::default(),
    );
    let camera = CameraInput {
        view: Mat4::IDENTITY,
        projection: glam::camera::rh::proj::directx::perspective(
            60f32.to_radians(),
            1.0,
            1e-4,
            1e6,
        ),
    };
    let g = GBuffer::new(
        &renderer,
        None,
        vec![layer],
        camera,
        None,
        SizeRule::Relative(1.0),
    );
    let (_, images) = render(&renderer, &g, &[&g.targets.depth]);
    let depth = &images[0];
    let inv = (spreadlight_render::camera::reverse_z(camera.projection) * camera.view).inverse();
    let mut worst: f32 = 0.0;
    let mut covered = 0;
    for y in 0..SIZE.1 {
        for x in 0..SIZE.0 {
            let d = depth.pixel(x, y)[0];
            if d == 0.0 {
                continue;
            }
            covered += 1;
            let ndc = Vec4::new(
                (x as f32 + 0.5) / 32.0 - 1.0,
                1.0 - (y as f32 + 0.5) / 32.0,
                d,
                1.0,
            );
            let p = inv * ndc;
            let p = p.truncate() / p.w;
            worst = worst.max(((p - at).length() - 10.0).abs());
        }
    }
    assert!(covered > 200, "{covered}");
    // The sphere's tessellation alone deviates up to 10 * (1 - cos(pi / 48)) = 0.021 from the true sphere.
    assert!(
        worst < 0.05,
        "reconstructed position error {worst} at distance 40-60 with near 1e-4, far 1e6"
    );
    eprintln!(
        "near 1e-4 / far 1e6: worst reconstructed-position error {worst} units at 40-60 units"
    );
}

#[test]
fn a_color_texture_scales_albedo_at_the_uv_and_needs_uvs() {
    use spreadlight_render::static_texture::StaticTexture;
    use spreadlight_render::texture::GpuTexture;
    let renderer = test_renderer();
    // Left half of UV space red, right half green, on a sphere seen from +z.
    // 64 texels wide, so bilinear blending is a thin seam.
    let texels: Vec<u8> = (0..64 * 4)
        .flat_map(|i| {
            if i % 64 < 32 {
                [255u8, 0, 0, 255]
            } else {
                [0, 255, 0, 255]
            }
        })
        .collect();
    let map = StaticTexture::new(GpuTexture::from_rgba8(
        &renderer.gpu,
        64,
        4,
        &texels,
        false,
        "albedo",
    ));
    let features = LayerFeatures {
        texcoords: true,
        ..Default::default()
    };
    let layer = |map: Option<spreadlight_render::TextureRef>| {
        let plain = sphere_layer(
            &renderer,
            vec![instance(Mat4::IDENTITY, Mat4::IDENTITY)],
            features,
        );
        Arc::new(Layer::clone(&plain).with_color_map(map).expect("has UVs"))
    };
    let color_of = |layer: Arc<Layer>| {
        let g = GBuffer::new(
            &renderer,
            None,
            vec![layer],
            camera_at(Vec3::new(0.0, 0.0, 4.0)),
            None,
            SizeRule::Relative(1.0),
        );
        let (_, images) = render(&renderer, &g, &[&g.targets.color]);
        images.into_iter().next().expect("color")
    };
    let plain = color_of(layer(None));
    let mapped = color_of(layer(Some(map.texture_ref())));
    let covered: Vec<usize> = (0..plain.pixels.len())
        .filter(|&i| plain.pixels[i][0] > 0.0)
        .collect();
    assert!(!covered.is_empty());
    // Every covered pixel: the instance colour times pure red or pure green (bilinear between them at seams).
    let (mut red, mut green) = (0, 0);
    for &i in &covered {
        let (p, m) = (plain.pixels[i], mapped.pixels[i]);
        assert!(
            m[0] <= p[0] + 1e-3 && m[1] <= p[1] + 1e-3 && m[2] <= 1e-3,
            "{m:?} from {p:?}"
        );
        red += usize::from(m[0] > 0.9 * p[0] && m[1] < 0.05);
        green += usize::from(m[1] > 0.9 * p[1] && m[0] < 0.05);
    }
    assert!(
        red > covered.len() / 5 && green > covered.len() / 5,
        "{red} red, {green} green of {}",
        covered.len()
    );
    // The material id still rides in alpha.
    assert_eq!(plain.pixels[covered[0]][3], mapped.pixels[covered[0]][3]);
    // Without UVs, a colour map is an error, not a guess.
    let no_uvs = sphere_layer(
        &renderer,
        vec![instance(Mat4::IDENTITY, Mat4::IDENTITY)],
        LayerFeatures::default(),
    );
    let err = Layer::clone(&no_uvs)
        .with_color_map(Some(map.texture_ref()))
        .expect_err("refused");
    assert!(
        err.to_string().contains("Texture Coordinates or Triplanar"),
        "{err}"
    );
}

#[test]
fn adjacent_layers_alike_share_one_resolve_dispatch_and_keep_their_pixels() {
    let renderer = test_renderer();
    let camera = camera_at(Vec3::new(0.0, 0.0, 5.0));
    // Three small spheres, each in its own layer, each moved its own way
    // since last frame: right, up, left.
    let spheres = [
        (Vec3::new(-1.5, 0.0, 0.0), Vec3::new(0.2, 0.0, 0.0)),
        (Vec3::new(0.0, 0.0, 0.0), Vec3::new(0.0, 0.2, 0.0)),
        (Vec3::new(1.5, 0.0, 0.0), Vec3::new(-0.2, 0.0, 0.0)),
    ];
    let layers_with = |middle: LayerFeatures| -> Vec<Arc<Layer>> {
        spheres
            .iter()
            .enumerate()
            .map(|(k, &(at, moved))| {
                let scale = Mat4::from_scale(Vec3::splat(0.4));
                let now = Mat4::from_translation(at) * scale;
                let before = Mat4::from_translation(at - moved) * scale;
                let features = if k == 1 {
                    middle
                } else {
                    LayerFeatures::default()
                };
                sphere_layer(&renderer, vec![instance(now, before)], features)
            })
            .collect()
    };
    let vp = camera.view_projection();
    let project = |p: Vec3| {
        let c = vp * p.extend(1.0);
        (c.truncate() / c.w).truncate()
    };
    let alike = layers_with(LayerFeatures::default());
    // The middle layer adding its geometry ids to the object ids (a
    // uniform of its own), with texture coordinates (another motion
    // permutation): it resolves alone.
    let unlike = layers_with(LayerFeatures {
        texcoords: true,
        ids: true,
        geometry_ids: true,
        ..LayerFeatures::default()
    });
    let mut velocities = Vec::new();
    let mut colors = Vec::new();
    for (layers, dispatches) in [(alike, 1), (unlike, 3)] {
        let g = GBuffer::new(
            &renderer,
            Some(40),
            layers,
            camera,
            Some(vp),
            SizeRule::Relative(1.0),
        );
        // Read together, the surface and motion resolves are one pass.
        let (report, mut images) =
            render(&renderer, &g, &[&g.targets.velocity_uv, &g.targets.color]);
        assert_eq!(
            report.counter(SURFACE_AND_MOTION_DISPATCHES),
            dispatches,
            "{:?}",
            report.counters
        );
        assert!(
            report
                .passes
                .iter()
                .any(|p| p.is("MRE", Some("resolve surface and motion")) && p.owner == Some(40))
                && report.passes_of("MRE", Some("resolve motion")).count() == 0,
            "{:?}",
            report.passes
        );
        // Read apart, each resolve runs alone, with its own runs; the same images.
        let (motion, alone) = render(&renderer, &g, &[&g.targets.velocity_uv]);
        let (surface, alone_color) = render(&renderer, &g, &[&g.targets.color]);
        assert_eq!(motion.counter("motion resolve dispatches"), dispatches);
        assert_eq!(surface.counter("surface resolve dispatches"), dispatches);
        assert!(alone[0].pixels == images[0].pixels, "the same velocities");
        assert!(
            alone_color[0].pixels == images[1].pixels,
            "the same colours"
        );
        for &(at, moved) in &spheres {
            let pole = at + Vec3::new(0.0, 0.0, 0.4);
            let expected = (project(pole) - project(pole - moved)) * glam::Vec2::new(0.5, -0.5);
            let ndc = project(pole);
            let px = (((ndc.x + 1.0) * 0.5) * SIZE.0 as f32) as u32;
            let py = (((1.0 - ndc.y) * 0.5) * SIZE.1 as f32) as u32;
            let v = images[0].pixel(px, py);
            assert!(
                (v[0] - expected.x).abs() < 2e-3 && (v[1] - expected.y).abs() < 2e-3,
                "sphere at {at}: velocity {v:?}, expected {expected:?}"
            );
        }
        // Nothing moves where no sphere is.
        assert_eq!(images[0].pixel(1, 1)[..2], [0.0, 0.0]);
        colors.push(images.remove(1));
        velocities.push(images.remove(0));
    }
    assert!(
        colors[0].pixels == colors[1].pixels,
        "one surface dispatch or one per layer: the same colours"
    );
    // Whether one dispatch or three wrote them, the velocities are the same.
    let (a, b) = (&velocities[0], &velocities[1]);
    assert!(
        a.pixels
            .iter()
            .zip(&b.pixels)
            .all(|(p, q)| p[0] == q[0] && p[1] == q[1]),
        "one motion dispatch or one per layer: the same velocities"
    );
}

/// The surface and motion resolves in one dispatch write what each writes
/// alone, with either rasterizer, with no layer at all (the background
/// dispatch), and for a triplanar layer (UVs the surface pass computes).
#[test]
fn one_resolve_dispatch_for_both_writes_what_each_writes_alone() {
    let renderer = test_renderer();
    let camera = camera_at(Vec3::new(0.0, 0.0, 5.0));
    let moved = Mat4::from_translation(Vec3::new(0.1, 0.0, 0.0));
    let triplanar = LayerFeatures {
        triplanar: true,
        ..LayerFeatures::default()
    };
    let scenes = [
        Vec::new(),
        vec![sphere_layer(
            &renderer,
            vec![instance(Mat4::IDENTITY, moved)],
            triplanar,
        )],
    ];
    for choice in [RasterChoice::Hardware, RasterChoice::Compute] {
        for layers in &scenes {
            let g = GBuffer::with_raster(
                &renderer,
                Some(41),
                layers.clone(),
                camera,
                Some(camera.view_projection()),
                SizeRule::Relative(1.0),
                choice,
            );
            let t = &g.targets;
            let (both, merged) = render(&renderer, &g, &[&t.velocity_uv, &t.color, &t.normals]);
            assert_eq!(
                both.counter(SURFACE_AND_MOTION_DISPATCHES),
                layers.len().max(1) as u64
            );
            let (_, motion) = render(&renderer, &g, &[&t.velocity_uv]);
            let (_, surface) = render(&renderer, &g, &[&t.color, &t.normals]);
            let what = format!("{choice:?}, {} layers", layers.len());
            assert!(
                motion[0].pixels == merged[0].pixels,
                "{what}: velocity and UV"
            );
            assert!(surface[0].pixels == merged[1].pixels, "{what}: colour");
            assert!(surface[1].pixels == merged[2].pixels, "{what}: normals");
            if !layers.is_empty() {
                let moving = merged[0].pixels.iter().filter(|p| p[0] != 0.0).count();
                assert!(moving > 100, "{what}: {moving} pixels move");
            }
        }
    }
}

/// Triplanar colour blends its three projections by the normal's weights:
/// on a sphere seen from a diagonal, where the axis the surface faces most
/// changes, neighbouring pixels' albedo does not jump at the default
/// sharpness, while a near-hard switch between projections (sharpness 32,
/// what one projection per pixel was) jumps there.
#[test]
fn triplanar_colour_blends_three_projections_without_a_seam() {
    use spreadlight_render::gbuffer::TRIPLANAR_SHARPNESS;
    use spreadlight_render::static_texture::StaticTexture;
    use spreadlight_render::texture::GpuTexture;
    let renderer = test_renderer();
    // A pattern that tiles: red a sine of u, green a sine of v, one period each.
    let n = 32u32;
    let wave = |t: u32| 0.5 + 0.5 * (std::f32::consts::TAU * (t as f32 + 0.5) / n as f32).sin();
    let texels: Vec<u8> = (0..n * n)
        .flat_map(|i| {
            let (r, g) = (wave(i % n), wave(i / n));
            [
                (r * 255.0).round() as u8,
                (g * 255.0).round() as u8,
                128,
                255,
            ]
        })
        .collect();
    let map = StaticTexture::new(GpuTexture::from_rgba8(
        &renderer.gpu,
        n,
        n,
        &texels,
        false,
        "pattern",
    ));
    let camera = camera_at(Vec3::new(1.6, 1.9, 2.2));
    let albedo = |sharpness: u32, textured: bool| {
        let features = LayerFeatures {
            triplanar: true,
            triplanar_sharpness: sharpness,
            ..Default::default()
        };
        let plain = sphere_layer(
            &renderer,
            vec![instance(Mat4::IDENTITY, Mat4::IDENTITY)],
            features,
        );
        let map = textured.then(|| map.texture_ref());
        let layer = Arc::new(
            Layer::clone(&plain)
                .with_color_map(map)
                .expect("triplanar UVs"),
        );
        let g = GBuffer::new(
            &renderer,
            None,
            vec![layer],
            camera,
            None,
            SizeRule::Relative(1.0),
        );
        let (_, images) = render(&renderer, &g, &[&g.targets.color]);
        images.into_iter().next().expect("color")
    };
    let coverage = albedo(TRIPLANAR_SHARPNESS, false);
    let (w, h) = (coverage.width as i32, coverage.height as i32);
    // Pixels whose 5x5 neighbourhood is all sphere: no silhouette in the comparison.
    let covered = |x: i32, y: i32| {
        (-2..=2).all(|dy| {
            (-2..=2).all(|dx| {
                let (px, py) = (x + dx, y + dy);
                px >= 0
                    && py >= 0
                    && px < w
                    && py < h
                    && coverage.pixel(px as u32, py as u32)[0] > 0.0
            })
        })
    };
    let largest_jump = |image: &ImageF32| {
        let mut largest = 0.0f32;
        for y in 0..h - 1 {
            for x in 0..w - 1 {
                if !covered(x, y) {
                    continue;
                }
                let p = image.pixel(x as u32, y as u32);
                for (nx, ny) in [(x + 1, y), (x, y + 1)] {
                    let q = image.pixel(nx as u32, ny as u32);
                    for c in 0..3 {
                        largest = largest.max((p[c] - q[c]).abs());
                    }
                }
            }
        }
        largest
    };
    let interior = (0..h).flat_map(|y| (0..w).map(move |x| (x, y)));
    assert!(interior.filter(|&(x, y)| covered(x, y)).count() > 300);
    let blended = albedo(TRIPLANAR_SHARPNESS, true);
    let hard = albedo(32, true);
    assert!(blended.all_finite() && hard.all_finite());
    let (smooth, seams) = (largest_jump(&blended), largest_jump(&hard));
    assert!(
        seams > 0.3,
        "a near-hard switch jumps at the seams: {seams}"
    );
    assert!(
        smooth < 0.5 * seams && smooth < 0.2,
        "blended: largest step {smooth} between neighbours (hard switch: {seams})"
    );
}
