//! The WGSL libraries `spreadlight::{brdf, lights, tonemap}` against their
//! CPU reference (`spreadlight_reference`): a small compute shader
//! that imports every function proves the libraries compose and validate
//! (no GPU needed), then runs on the GPU over a few hundred inputs, edge cases
//! included, and every output is compared with what the Rust functions give.

use std::borrow::Cow;

use glam::{Vec3, Vec4};
use naga_oil::compose::{
    ComposableModuleDescriptor, Composer, NagaModuleDescriptor, ShaderLanguage, ShaderType,
};
use spreadlight_reference::brdf::{
    Brdf, cook_torrance, d_ggx, diffuse_lambert, energy_compensation, f_schlick, specular_albedo,
    v_smith_ggx_correlated,
};
use spreadlight_reference::lights::{
    luminous_intensity_from_power, point_attenuation, spot_attenuation,
};
use spreadlight_reference::tonemap::{TonemapOperator, ev100_to_exposure, luminance, tonemap};
use spreadlight_render::renderer::test_renderer;
use spreadlight_render::shaders::{Reflection, library};
use wgpu::util::DeviceExt;

/// Calls every function of the three libraries. One invocation per case;
/// each case writes `ROWS` vec4s (the layout `expected` mirrors).
const ENTRY: &str = r#"
#import spreadlight::brdf::{Brdf, cook_torrance, d_ggx, v_smith_ggx_correlated, f_schlick, diffuse_lambert, specular_albedo, energy_compensation}
#import spreadlight::lights::{point_attenuation, point_attenuation_squared, spot_attenuation, luminous_intensity_from_power}
#import spreadlight::tonemap::{luminance, ev100_to_exposure, tonemap, tonemap_linear, tonemap_reinhard, tonemap_reinhard_modified, tonemap_filmic_uncharted2, tonemap_filmic_alu, tonemap_drago, tonemap_logarithmic, tonemap_exponential, tonemap_aces, tonemap_agx}
#import spreadlight::tonemap::{TONEMAP_LINEAR, TONEMAP_REINHARD, TONEMAP_REINHARD_MODIFIED, TONEMAP_UNCHARTED2, TONEMAP_FILMIC_ALU, TONEMAP_DRAGO, TONEMAP_LOGARITHMIC, TONEMAP_EXPONENTIAL, TONEMAP_ACES, TONEMAP_AGX}

struct Case {
    n: vec4<f32>,      // normal, roughness
    v: vec4<f32>,      // to the eye, metallic
    l: vec4<f32>,      // to the light, (unused)
    albedo: vec4<f32>, // albedo (and tonemap colour), tonemap colour scale
    p: vec4<f32>,      // a cosine, N.V, distance or lumens, range
    q: vec4<f32>,      // cos outer, cos inner, exposure, tonemap param
}

const ROWS: u32 = 30u;

@group(0) @binding(0) var<storage, read> cases: array<Case>;
@group(0) @binding(1) var<storage, read_write> results: array<vec4<f32>>;

@compute @workgroup_size(64)
fn main(@builtin(global_invocation_id) id: vec3<u32>) {
    if (id.x >= arrayLength(&cases)) {
        return;
    }
    let c = cases[id.x];
    let r = c.n.w;
    let o = id.x * ROWS;
    results[o + 0u] = vec4<f32>(d_ggx(c.p.x, r), v_smith_ggx_correlated(c.p.y, c.p.x, r), diffuse_lambert(), specular_albedo(c.p.y, r));
    results[o + 1u] = vec4<f32>(f_schlick(c.albedo.xyz, c.p.x), point_attenuation(c.p.z, c.p.w));
    results[o + 2u] = vec4<f32>(energy_compensation(c.albedo.xyz, c.p.y, r), spot_attenuation(c.p.x, c.q.x, c.q.y));
    let plain: Brdf = cook_torrance(c.n.xyz, c.v.xyz, c.l.xyz, c.albedo.xyz, r, c.v.w, false);
    let compensated = cook_torrance(c.n.xyz, c.v.xyz, c.l.xyz, c.albedo.xyz, r, c.v.w, true);
    results[o + 3u] = vec4<f32>(plain.diffuse, luminance(c.albedo.xyz));
    results[o + 4u] = vec4<f32>(plain.specular, luminous_intensity_from_power(c.p.z));
    results[o + 5u] = vec4<f32>(compensated.diffuse, ev100_to_exposure(c.p.y * 20.0 - 5.0));
    results[o + 6u] = vec4<f32>(compensated.specular, point_attenuation_squared(max(c.p.z, 0.0) * max(c.p.z, 0.0), c.p.w));
    let hdr = c.albedo.xyz * c.albedo.w;
    for (var op = 0u; op < 10u; op++) {
        results[o + 7u + op] = vec4<f32>(tonemap(hdr, op, c.q.z, c.q.w), 0.0);
    }
    // The operators by name, after the same exposure: the dispatch must agree with them.
    let x = hdr * c.q.z;
    results[o + 17u] = vec4<f32>(tonemap_linear(x), 0.0);
    results[o + 18u] = vec4<f32>(tonemap_reinhard(x), 0.0);
    results[o + 19u] = vec4<f32>(tonemap_reinhard_modified(x, c.q.w), 0.0);
    results[o + 20u] = vec4<f32>(tonemap_filmic_uncharted2(x), 0.0);
    results[o + 21u] = vec4<f32>(tonemap_filmic_alu(x), 0.0);
    results[o + 22u] = vec4<f32>(tonemap_drago(x, c.q.w), 0.0);
    results[o + 23u] = vec4<f32>(tonemap_logarithmic(x, c.q.w), 0.0);
    results[o + 24u] = vec4<f32>(tonemap_exponential(x), 0.0);
    results[o + 25u] = vec4<f32>(tonemap_aces(x), 0.0);
    results[o + 26u] = vec4<f32>(tonemap_agx(x), 0.0);
    results[o + 27u] = vec4<f32>(f32(TONEMAP_LINEAR), f32(TONEMAP_REINHARD), f32(TONEMAP_REINHARD_MODIFIED), f32(TONEMAP_UNCHARTED2));
    results[o + 28u] = vec4<f32>(f32(TONEMAP_FILMIC_ALU), f32(TONEMAP_DRAGO), f32(TONEMAP_LOGARITHMIC), f32(TONEMAP_EXPONENTIAL));
    results[o + 29u] = vec4<f32>(f32(TONEMAP_ACES), f32(TONEMAP_AGX), 0.0, 0.0);
}
"#;

const ROWS: usize = 30;
const LIBRARIES: [&str; 3] = ["lib/brdf.wgsl", "lib/lights.wgsl", "lib/tonemap.wgsl"];

/// One case: the WGSL `Case`, six vec4s.
#[derive(Clone, Copy, Debug)]
struct Case {
    n: Vec3,
    roughness: f32,
    v: Vec3,
    metallic: f32,
    l: Vec3,
    albedo: Vec3,
    hdr_scale: f32,
    p: Vec4,
    q: Vec4,
}

impl Case {
    fn to_floats(self) -> [f32; 24] {
        let mut out = [0.0; 24];
        let rows = [
            self.n.extend(self.roughness),
            self.v.extend(self.metallic),
            self.l.extend(0.0),
            self.albedo.extend(self.hdr_scale),
            self.p,
            self.q,
        ];
        for (i, row) in rows.iter().enumerate() {
            out[i * 4..i * 4 + 4].copy_from_slice(&row.to_array());
        }
        out
    }

    /// Below this roughness the GGX peak is so sharp that the last bit of
    /// N.H (computed from vectors, with or without FMA) changes D by
    /// percents: there the GPU is only checked to be finite.
    fn is_sharp(&self) -> bool {
        self.roughness < 0.2
    }

    /// What the CPU reference says the shader writes, row by row.
    fn expected(&self) -> [Vec4; ROWS] {
        let (r, p, q) = (self.roughness, self.p, self.q);
        let plain: Brdf =
            cook_torrance(self.n, self.v, self.l, self.albedo, r, self.metallic, false);
        let compensated =
            cook_torrance(self.n, self.v, self.l, self.albedo, r, self.metallic, true);
        let mut rows = [Vec4::ZERO; ROWS];
        rows[0] = Vec4::new(
            d_ggx(p.x, r),
            v_smith_ggx_correlated(p.y, p.x, r),
            diffuse_lambert(),
            specular_albedo(p.y, r),
        );
        rows[1] = f_schlick(self.albedo, p.x).extend(point_attenuation(p.z, p.w));
        rows[2] = energy_compensation(self.albedo, p.y, r).extend(spot_attenuation(p.x, q.x, q.y));
        rows[3] = plain.diffuse.extend(luminance(self.albedo));
        rows[4] = plain.specular.extend(luminous_intensity_from_power(p.z));
        rows[5] = compensated
            .diffuse
            .extend(ev100_to_exposure(p.y * 20.0 - 5.0));
        // The squared-distance form must agree with the distance form.
        rows[6] = compensated.specular.extend(point_attenuation(p.z, p.w));
        let hdr = self.albedo * self.hdr_scale;
        for op in TonemapOperator::ALL {
            let mapped = tonemap(hdr, op, q.z, q.w);
            rows[7 + op.id() as usize] = mapped.extend(0.0);
            // By name, the same as through the dispatch.
            rows[17 + op.id() as usize] = mapped.extend(0.0);
        }
        // The operator ids, which the nodes and passes share.
        let ids = TonemapOperator::ALL.map(|op| op.id() as f32);
        rows[27] = Vec4::from_slice(&ids[0..4]);
        rows[28] = Vec4::from_slice(&ids[4..8]);
        rows[29] = Vec4::new(ids[8], ids[9], 0.0, 0.0);
        rows
    }
}

/// A small deterministic generator (PCG-style LCG): no rand crate needed.
struct Lcg(u64);

impl Lcg {
    fn next(&mut self) -> f32 {
        self.0 = self
            .0
            .wrapping_mul(6_364_136_223_846_793_005)
            .wrapping_add(1_442_695_040_888_963_407);
        (self.0 >> 40) as f32 / (1u64 << 24) as f32
    }

    fn range(&mut self, lo: f32, hi: f32) -> f32 {
        lo + (hi - lo) * self.next()
    }

    fn direction(&mut self) -> Vec3 {
        let z = self.range(-1.0, 1.0);
        let phi = self.range(0.0, std::f32::consts::TAU);
        let s = (1.0 - z * z).max(0.0).sqrt();
        Vec3::new(s * phi.cos(), s * phi.sin(), z)
    }
}

/// Edge cases first (roughness and metallic at their ends, grazing and
/// back-facing vectors, distance 0, range 0, closed cones, black and huge
/// colours), then random ones.
fn cases() -> Vec<Case> {
    let mut out = Vec::new();
    let n = Vec3::Z;
    let dirs = [
        Vec3::Z,
        Vec3::new(0.6, 0.0, 0.8),
        Vec3::new(-0.8, 0.0, 0.6),
        Vec3::new(1.0, 0.0, 1e-6).normalize(),
        Vec3::new(0.0, 0.6, -0.8),
    ];
    let mut i = 0u32;
    for &v in &dirs {
        for &l in &dirs {
            for roughness in [0.0, 0.25, 1.0] {
                for metallic in [0.0, 1.0] {
                    i += 1;
                    out.push(Case {
                        n,
                        roughness,
                        v,
                        metallic,
                        l,
                        albedo: [Vec3::ZERO, Vec3::ONE, Vec3::new(0.9, 0.4, 0.05)][i as usize % 3],
                        hdr_scale: [0.0, 1.0, 1e6, 37.0][i as usize % 4],
                        p: Vec4::new(
                            [0.0, 1.0, -0.5, 1e-6, 0.999][i as usize % 5],
                            [0.0, 1.0, 1e-6, 0.5][i as usize % 4],
                            [0.0, 1.0, 15.0, 3.0][i as usize % 4],
                            [0.0, 10.0, -1.0][i as usize % 3],
                        ),
                        q: Vec4::new(
                            [1.0, 0.0, -1.0, 0.8][i as usize % 4],
                            [1.0, 0.0, -1.0, 0.9][i as usize % 4],
                            [1.0, 0.001, 4.0][i as usize % 3],
                            [4.0, 0.0, 100.0, -1.0, 1e4][i as usize % 5],
                        ),
                    });
                }
            }
        }
    }
    let mut rng = Lcg(0x5eed);
    for _ in 0..400 {
        let n = rng.direction();
        let mut v = rng.direction();
        if v.dot(n) < 0.0 && rng.next() < 0.8 {
            v = -v;
        }
        let mut l = rng.direction();
        if l.dot(n) < 0.0 && rng.next() < 0.8 {
            l = -l;
        }
        let outer = rng.range(-1.0, 1.0);
        out.push(Case {
            n,
            roughness: rng.range(0.0, 1.0),
            v,
            metallic: rng.range(0.0, 1.0),
            l,
            albedo: Vec3::new(rng.next(), rng.next(), rng.next()),
            hdr_scale: 10f32.powf(rng.range(-3.0, 5.0)),
            p: Vec4::new(
                rng.range(-0.2, 1.0),
                rng.range(0.0, 1.0),
                rng.range(0.0, 20.0),
                rng.range(-1.0, 20.0),
            ),
            q: Vec4::new(
                outer,
                rng.range(outer, 1.0),
                10f32.powf(rng.range(-2.0, 1.0)),
                rng.range(0.5, 200.0),
            ),
        });
    }
    out
}

/// A composer holding the libraries under test (and `packing`, which `brdf`
/// imports), taken from the renderer's table of libraries.
fn composer() -> Composer {
    let mut composer = Composer::default();
    let wanted = |path: &str| path == "lib/packing.wgsl" || LIBRARIES.contains(&path);
    let table = spreadlight_render::shaders::LIBRARIES;
    for file in table.iter().filter(|f| wanted(f.path)) {
        if let Err(e) = composer.add_composable_module(ComposableModuleDescriptor {
            source: file.source,
            file_path: file.path,
            language: ShaderLanguage::Wgsl,
            ..Default::default()
        }) {
            panic!("{}: {}", file.path, e.emit_to_string(&composer));
        }
    }
    composer
}

fn compose_entry() -> naga::Module {
    let mut composer = composer();
    let module = composer.make_naga_module(NagaModuleDescriptor {
        source: ENTRY,
        file_path: "tests/shader_reference.wgsl",
        shader_type: ShaderType::Wgsl,
        ..Default::default()
    });
    match module {
        Ok(m) => m,
        Err(e) => panic!("{}", e.emit_to_string(&composer)),
    }
}

#[test]
fn libraries_are_registered_and_compose_and_validate() {
    for path in LIBRARIES {
        assert!(
            library(path).is_some_and(|f| f.library),
            "{path} is not a library of shaders::LIBRARIES"
        );
    }
    let module = compose_entry();
    let mut validator =
        naga::valid::Validator::new(naga::valid::ValidationFlags::all(), Default::default());
    if let Err(e) = validator.validate(&module) {
        panic!("{e:?}");
    }
    assert_eq!(TonemapOperator::NAMES.len(), TonemapOperator::ALL.len());
}

/// Largest |gpu - cpu| allowed: relative to the larger magnitude, with an
/// absolute floor for values near 0 (pow, exp and log may differ by a few
/// ulps on a GPU).
fn close(gpu: f32, cpu: f32) -> bool {
    (gpu - cpu).abs() <= 1e-5 + 1e-3 * gpu.abs().max(cpu.abs())
}

#[test]
fn wgsl_libraries_match_the_cpu_reference_on_the_gpu() {
    let renderer = test_renderer();
    let gpu = &renderer.gpu;
    let cases = cases();
    let inputs: Vec<f32> = cases.iter().flat_map(|c| c.to_floats()).collect();
    let size = (cases.len() * ROWS * 16) as u64;
    let device = &gpu.device;
    let input = device.create_buffer_init(&wgpu::util::BufferInitDescriptor {
        label: Some("shader_reference cases"),
        contents: bytemuck::cast_slice(&inputs),
        usage: wgpu::BufferUsages::STORAGE,
    });
    let output = device.create_buffer(&wgpu::BufferDescriptor {
        label: Some("shader_reference results"),
        size,
        usage: wgpu::BufferUsages::STORAGE | wgpu::BufferUsages::COPY_SRC,
        mapped_at_creation: false,
    });
    let staging = device.create_buffer(&wgpu::BufferDescriptor {
        label: Some("shader_reference readback"),
        size,
        usage: wgpu::BufferUsages::MAP_READ | wgpu::BufferUsages::COPY_DST,
        mapped_at_creation: false,
    });
    let composed = compose_entry();
    let reflection = Reflection::of_module(&composed, "main").expect("reflects");
    let module = device.create_shader_module(wgpu::ShaderModuleDescriptor {
        label: Some("shader_reference"),
        source: wgpu::ShaderSource::Naga(Cow::Owned(composed)),
    });
    let pipeline = device.create_compute_pipeline(&wgpu::ComputePipelineDescriptor {
        label: Some("shader_reference"),
        layout: None,
        module: &module,
        entry_point: Some("main"),
        compilation_options: Default::default(),
        cache: None,
    });
    let bind_group = device.create_bind_group(&wgpu::BindGroupDescriptor {
        label: Some("shader_reference"),
        layout: &pipeline.get_bind_group_layout(0),
        entries: &reflection
            .entries(
                0,
                &[
                    ("cases", input.as_entire_binding()),
                    ("results", output.as_entire_binding()),
                ],
            )
            .expect("binds by name"),
    });
    let mut encoder = device.create_command_encoder(&Default::default());
    {
        let mut pass = encoder.begin_compute_pass(&Default::default());
        pass.set_pipeline(&pipeline);
        pass.set_bind_group(0, &bind_group, &[]);
        pass.dispatch_workgroups((cases.len() as u32).div_ceil(64), 1, 1);
    }
    encoder.copy_buffer_to_buffer(&output, 0, &staging, 0, size);
    gpu.queue.submit([encoder.finish()]);
    let slice = staging.slice(..);
    let (tx, rx) = std::sync::mpsc::channel();
    slice.map_async(wgpu::MapMode::Read, move |r| {
        let _ = tx.send(r);
    });
    device
        .poll(wgpu::PollType::wait_indefinitely())
        .expect("GPU finishes");
    rx.recv().expect("map callback").expect("buffer maps");
    let bytes = slice.get_mapped_range().expect("mapped").to_vec();
    let results: &[f32] = bytemuck::cast_slice(&bytes);

    let mut failures = Vec::new();
    for (i, case) in cases.iter().enumerate() {
        let expected = case.expected();
        for (row, want) in expected.iter().enumerate() {
            let at = (i * ROWS + row) * 4;
            let got = Vec4::from_slice(&results[at..at + 4]);
            let brdf_row = (3..=6).contains(&row);
            let ok = if brdf_row && case.is_sharp() {
                got.is_finite() && got.min_element() >= 0.0
            } else {
                (0..4).all(|k| close(got[k], want[k]))
            };
            if !ok {
                failures.push(format!(
                    "case {i} row {row}: gpu {got}, cpu {want}\n  {case:?}"
                ));
            }
        }
    }
    assert!(
        failures.is_empty(),
        "{} of {} values differ on {}:\n{}",
        failures.len(),
        cases.len() * ROWS,
        gpu.adapter_name(),
        failures
            .iter()
            .take(20)
            .cloned()
            .collect::<Vec<_>>()
            .join("\n")
    );
}
