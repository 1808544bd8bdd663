//! Particles on a real (software) GPU: deterministic for a seed and a
//! sequence of steps, emission as counted, collisions hold, the hard cases
//! (time steps of 0 and huge, NaN in a field texture, forces of 1e6, every
//! particle dying at once, rate 0) leave nothing non-finite in the particle
//! buffer or in the mesh they draw.

use std::sync::Arc;

use glam::{Vec3, Vec4};
use spreadlight_render::Renderer;
use spreadlight_render::particles::{
    DrawShape, EmitterShape, Field, FieldTexture, Integrator, Particle, ParticleSettings,
    ParticleSystem, Plane, draw, read_drawn,
};
use spreadlight_render::renderer::test_renderer;

const DT: f32 = 1.0 / 60.0;

fn fountain() -> ParticleSettings {
    ParticleSettings {
        shape: EmitterShape::Sphere(0.2),
        rate: 600.0,
        lifetime: 1.0,
        lifetime_spread: 0.3,
        velocity: Vec3::new(0.0, 3.0, 0.0),
        velocity_spread: 1.0,
        drag: 0.5,
        field: Field::Curl {
            frequency: 1.5,
            strength: 4.0,
        },
        attractors: vec![Vec4::new(1.0, 1.0, 0.0, 2.0)],
        ..Default::default()
    }
}

fn simulate(
    renderer: &Renderer,
    seed: u32,
    settings: &ParticleSettings,
    steps: &[f32],
) -> Vec<Particle> {
    let mut system = ParticleSystem::new(renderer, 256, seed).expect("system");
    for &dt in steps {
        system.step(renderer, settings, dt).expect("step");
    }
    system.read(renderer).expect("readback")
}

fn all_finite(particles: &[Particle]) -> bool {
    particles.iter().all(|p| {
        p.position
            .iter()
            .chain(&p.velocity)
            .chain(&p.previous)
            .all(|x| x.is_finite())
            && p.age.is_finite()
            && p.lifetime.is_finite()
    })
}

fn alive(particles: &[Particle]) -> usize {
    particles.iter().filter(|p| p.alive == 1).count()
}

#[test]
fn a_fixed_seed_and_frame_rate_give_the_same_particles_bit_for_bit() {
    let renderer = test_renderer();
    let steps = [DT; 30];
    let a = simulate(&renderer, 7, &fountain(), &steps);
    let b = simulate(&renderer, 7, &fountain(), &steps);
    assert_eq!(a, b);
    assert!(alive(&a) > 100, "the fountain runs: {} alive", alive(&a));
    let other = simulate(&renderer, 8, &fountain(), &steps);
    assert_ne!(a, other, "the seed matters");

    // A reset starts the same sequence again.
    let mut system = ParticleSystem::new(&renderer, 256, 7).unwrap();
    for _ in 0..5 {
        system.step(&renderer, &fountain(), DT).unwrap();
    }
    system.reset(&renderer);
    assert_eq!(alive(&system.read(&renderer).unwrap()), 0);
    for &dt in &steps {
        system.step(&renderer, &fountain(), dt).unwrap();
    }
    assert_eq!(system.read(&renderer).unwrap(), a);
}

#[test]
fn emission_follows_the_rate_and_a_rate_of_zero_emits_nothing() {
    let renderer = test_renderer();
    let settings = ParticleSettings {
        rate: 90.0,
        lifetime: 100.0,
        ..Default::default()
    };
    // 90 a second for 10 frames at 60 fps: 15 particles (1.5 a frame, carried).
    let p = simulate(&renderer, 1, &settings, &[DT; 10]);
    assert_eq!(alive(&p), 15);
    let none = ParticleSettings {
        rate: 0.0,
        ..settings.clone()
    };
    let p = simulate(&renderer, 1, &none, &[DT; 10]);
    assert_eq!(alive(&p), 0);
    assert!(
        p.iter().all(|p| *p == Particle::default()),
        "untouched slots"
    );
}

#[test]
fn a_plane_keeps_particles_above_it() {
    let renderer = test_renderer();
    let settings = ParticleSettings {
        shape: EmitterShape::Box(Vec3::splat(0.5)),
        emitter: glam::Mat4::from_translation(Vec3::new(0.0, 1.0, 0.0)),
        rate: 3000.0,
        lifetime: 10.0,
        velocity: Vec3::new(0.0, -5.0, 0.0),
        velocity_spread: 2.0,
        plane: Some(Plane {
            normal: Vec3::Y,
            offset: 0.0,
        }),
        bounce: 0.3,
        ..Default::default()
    };
    let p = simulate(&renderer, 3, &settings, &[DT; 40]);
    assert!(alive(&p) > 200);
    for q in p.iter().filter(|p| p.alive == 1) {
        assert!(q.position[1] >= -1e-4, "below the plane: {q:?}");
    }
}

#[test]
fn hard_cases_leave_no_nan_in_buffers_or_meshes() {
    let renderer = test_renderer();
    let mut nan_field = vec![Vec3::new(0.0, 1.0, 0.0); 4 * 4 * 4];
    nan_field[5] = Vec3::new(f32::NAN, 0.0, f32::INFINITY);
    nan_field[21] = Vec3::splat(f32::NAN);
    let texture = Arc::new(FieldTexture::new(&renderer, 4, &nan_field).expect("field"));
    let cases: Vec<(&str, ParticleSettings, Vec<f32>)> = vec![
        ("time step 0", fountain(), vec![0.0; 5]),
        (
            "huge time steps",
            fountain(),
            vec![1e9, f32::MAX, f32::INFINITY, f32::NAN, DT],
        ),
        (
            "NaN in the field texture",
            ParticleSettings {
                field: Field::Texture {
                    texture,
                    min: Vec3::splat(-2.0),
                    max: Vec3::splat(2.0),
                    strength: 5.0,
                },
                ..fountain()
            },
            vec![DT; 20],
        ),
        (
            "forces of 1e6",
            ParticleSettings {
                gravity: Vec3::new(1e6, -1e6, 1e6),
                attractors: vec![
                    Vec4::new(0.0, 0.5, 0.0, 1e6),
                    Vec4::new(0.0, 0.5, 0.0, -1e6),
                ],
                field: Field::Curl {
                    frequency: 1e6,
                    strength: 1e6,
                },
                drag: 1e6,
                ..fountain()
            },
            vec![DT; 20],
        ),
        (
            "forces of 1e6, explicit Euler",
            ParticleSettings {
                gravity: Vec3::splat(1e6),
                drag: 1e6,
                integrator: Integrator::ExplicitEuler,
                ..fountain()
            },
            vec![DT; 20],
        ),
        (
            "NaN on every pin",
            ParticleSettings {
                rate: f32::NAN,
                gravity: Vec3::splat(f32::NAN),
                drag: f32::NAN,
                velocity: Vec3::splat(f32::INFINITY),
                ..fountain()
            },
            vec![DT; 5],
        ),
        (
            "rate 0",
            ParticleSettings {
                rate: 0.0,
                ..fountain()
            },
            vec![DT; 5],
        ),
    ];
    for (name, settings, steps) in cases {
        let mut system = ParticleSystem::new(&renderer, 256, 1).unwrap();
        for dt in steps {
            system.step(&renderer, &settings, dt).expect(name);
        }
        let particles = system.read(&renderer).unwrap();
        assert!(all_finite(&particles), "{name}: non-finite particle state");
        let mesh = draw(
            &renderer,
            &system,
            DrawShape::Sprites,
            0.05,
            true,
            settings.world_radius,
        )
        .expect(name);
        let (vertices, _) = read_drawn(&renderer, &mesh, Vec3::X, Vec3::Y).unwrap();
        assert!(
            vertices
                .iter()
                .all(|v| bytemuck::cast_slice::<_, f32>(std::slice::from_ref(v))
                    .iter()
                    .all(|x| x.is_finite())),
            "{name}: non-finite vertex"
        );
    }
}

#[test]
fn every_particle_dying_at_once_leaves_an_empty_finite_system() {
    let renderer = test_renderer();
    let settings = ParticleSettings {
        rate: 1e6,
        lifetime: DT * 1.5,
        lifetime_spread: 0.0,
        ..fountain()
    };
    let mut system = ParticleSystem::new(&renderer, 256, 5).unwrap();
    system.step(&renderer, &settings, DT).unwrap();
    assert_eq!(
        alive(&system.read(&renderer).unwrap()),
        256,
        "the ring is full"
    );
    let stopped = ParticleSettings {
        rate: 0.0,
        ..settings
    };
    system.step(&renderer, &stopped, DT).unwrap();
    system.step(&renderer, &stopped, DT).unwrap();
    let p = system.read(&renderer).unwrap();
    assert_eq!(alive(&p), 0);
    assert!(all_finite(&p));
}

#[test]
fn sprites_carry_previous_positions_and_slot_ids() {
    let renderer = test_renderer();
    let mut system = ParticleSystem::new(&renderer, 16, 2).unwrap();
    let settings = ParticleSettings {
        rate: 1e6,
        lifetime: 10.0,
        velocity: Vec3::new(1.0, 0.0, 0.0),
        gravity: Vec3::ZERO,
        ..Default::default()
    };
    system.step(&renderer, &settings, DT).unwrap();
    system
        .step(
            &renderer,
            &ParticleSettings {
                rate: 0.0,
                ..settings
            },
            DT,
        )
        .unwrap();
    let particles = system.read(&renderer).unwrap();
    let mesh = draw(&renderer, &system, DrawShape::Sprites, 0.1, false, 100.0).unwrap();
    // Two triangles a particle, three corners each, made from the records.
    let (vertices, _) = read_drawn(&renderer, &mesh, Vec3::X, Vec3::Y).unwrap();
    assert_eq!((vertices.len(), mesh.index_count()), (96, 96));
    assert!(mesh.has_previous_positions && mesh.is_procedural());
    for (i, v) in vertices.iter().enumerate() {
        let p = &particles[i / 6];
        let moved = Vec3::from_slice(&v.position_u) - Vec3::from_slice(&v.previous_position);
        let expected = Vec3::from(p.position) - Vec3::from(p.previous);
        assert!((moved - expected).length() < 1e-6);
        assert!((moved.x - DT).abs() < 1e-4, "one step at 1 m/s: {moved}");
        assert_eq!(v.previous_position[3], (i / 6) as f32, "geometry id = slot");
        // A quad of half size 0.1 facing +Z around the particle.
        let offset = Vec3::from_slice(&v.position_u) - Vec3::from(p.position);
        assert!((offset.x.abs() - 0.1).abs() < 1e-5 && (offset.y.abs() - 0.1).abs() < 1e-5);
        assert!(offset.z.abs() < 1e-6 && (v.normal_v[2] - 1.0).abs() < 1e-6);
    }
}

#[test]
fn particles_collide_with_the_depth_buffer() {
    let renderer = test_renderer();
    // A camera looking down -Z at a wall of depth: every pixel's surface is
    // at z = -1 in world space (the camera at the origin).
    let camera = spreadlight_render::camera::CameraInput {
        view: glam::Mat4::IDENTITY,
        projection: glam::camera::rh::proj::directx::perspective(1.0, 1.0, 0.1, 100.0),
    };
    let view_projection = camera.view_projection();
    let clip = view_projection * glam::Vec4::new(0.0, 0.0, -1.0, 1.0);
    let surface = clip.z / clip.w;
    let (w, h) = (8u32, 8u32);
    let texture = renderer
        .gpu
        .device
        .create_texture(&wgpu::TextureDescriptor {
            label: Some("test depth"),
            size: wgpu::Extent3d {
                width: w,
                height: h,
                depth_or_array_layers: 1,
            },
            mip_level_count: 1,
            sample_count: 1,
            dimension: wgpu::TextureDimension::D2,
            format: wgpu::TextureFormat::R32Float,
            usage: wgpu::TextureUsages::TEXTURE_BINDING | wgpu::TextureUsages::COPY_DST,
            view_formats: &[],
        });
    renderer.gpu.queue.write_texture(
        texture.as_image_copy(),
        bytemuck::cast_slice(&vec![surface; (w * h) as usize]),
        wgpu::TexelCopyBufferLayout {
            offset: 0,
            bytes_per_row: Some(w * 4),
            rows_per_image: Some(h),
        },
        texture.size(),
    );
    let settings = |depth| ParticleSettings {
        shape: EmitterShape::Sphere(0.05),
        emitter: glam::Mat4::from_translation(Vec3::new(0.0, 0.0, -0.5)),
        rate: 1e6,
        lifetime: 100.0,
        velocity: Vec3::new(0.0, 0.0, -2.0),
        gravity: Vec3::ZERO,
        depth,
        ..Default::default()
    };
    let depth = Some(spreadlight_render::particles::DepthCollision {
        depth: texture.create_view(&Default::default()),
        view_projection,
        size: (w, h),
        thickness: 1.0,
    });
    // Born in one step, then 60 steps at 2 m/s: from z = -0.5 to about -2.5
    // when nothing stops them.
    let run = |settings: ParticleSettings| {
        let mut system = ParticleSystem::new(&renderer, 64, 4).unwrap();
        system.step(&renderer, &settings, DT).unwrap();
        let quiet = ParticleSettings {
            rate: 0.0,
            ..settings
        };
        for _ in 0..60 {
            system.step(&renderer, &quiet, DT).unwrap();
        }
        system.read(&renderer).unwrap()
    };
    let through = run(settings(None));
    let stopped = run(settings(depth));
    let deepest = |p: &[Particle]| {
        p.iter()
            .filter(|p| p.alive == 1)
            .map(|p| p.position[2])
            .fold(f32::INFINITY, f32::min)
    };
    assert!(
        deepest(&through) < -2.0,
        "without collision they pass the wall"
    );
    assert!(
        deepest(&stopped) > -1.0 - 0.05,
        "with it they stay in front: {}",
        deepest(&stopped)
    );
    assert!(all_finite(&stopped));
}
