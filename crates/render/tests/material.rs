//! `shaders/lib/material.wgsl` against `spreadlight_render::material`: a
//! compute shader importing the library composes and validates (no GPU
//! needed), its constants mirror the Rust ones, and on the GPU it reads back
//! `material_flags`, `has_feature` and `feature_param` for every material,
//! feature id (out of range ones included) and parameter index of a world,
//! compared with what the CPU-side `MaterialWorld` says.

use std::borrow::Cow;

use naga_oil::compose::{
    ComposableModuleDescriptor, Composer, NagaModuleDescriptor, ShaderLanguage, ShaderType,
};
use spreadlight_render::material::{
    FEATURE_AMBIENT_OCCLUSION, FEATURE_ANISOTROPY, FEATURE_CLEARCOAT, FEATURE_COOK_TORRANCE,
    FEATURE_EMISSION, FEATURE_FAKE_SSS, FEATURE_IRIDESCENCE, FEATURE_MATCAP, FEATURE_REFLECTION,
    FEATURE_SHEEN, FEATURE_TRANSMISSION, FEATURE_UNLIT, FIRST_CUSTOM_FEATURE, Feature,
    MAX_FEATURES, Material, MaterialWorld,
};
use spreadlight_render::renderer::test_renderer;
use spreadlight_render::shaders::library;
use wgpu::util::DeviceExt;

const LIBRARY: &str = "lib/material.wgsl";

/// One invocation per query (material id, feature id, parameter index).
const ENTRY: &str = r#"
#import spreadlight::material::{material_flags, has_feature, feature_param}

@group(0) @binding(0) var<storage, read> queries: array<vec4<u32>>;
@group(0) @binding(1) var<storage, read_write> params: array<vec4<f32>>;
@group(0) @binding(2) var<storage, read_write> flags: array<vec2<u32>>;

const FALLBACK: vec4<f32> = vec4<f32>(-1.0, -2.0, -3.0, -4.0);

@compute @workgroup_size(64)
fn main(@builtin(global_invocation_id) gid: vec3<u32>) {
    if (gid.x >= arrayLength(&queries)) {
        return;
    }
    let q = queries[gid.x];
    params[gid.x] = feature_param(q.x, q.y, q.z, FALLBACK);
    flags[gid.x] = vec2<u32>(material_flags(q.x), select(0u, 1u, has_feature(q.x, q.y)));
}
"#;

const FALLBACK: [f32; 4] = [-1.0, -2.0, -3.0, -4.0];

fn compose_entry() -> naga::Module {
    let mut composer = Composer::default();
    // The material library, after the one it imports (the G-buffer's
    // surface target, which feature_param_at reads under SURFACE_TARGET).
    for path in ["lib/surface_target.wgsl", LIBRARY] {
        let file = library(path).unwrap_or_else(|| panic!("{path} is in shaders::LIBRARIES"));
        assert!(file.library, "{path} is registered as a library");
        if let Err(e) = composer.add_composable_module(ComposableModuleDescriptor {
            source: file.source,
            file_path: file.path,
            language: ShaderLanguage::Wgsl,
            ..Default::default()
        }) {
            panic!("{}: {}", file.path, e.emit_to_string(&composer));
        }
    }
    let module = composer.make_naga_module(NagaModuleDescriptor {
        source: ENTRY,
        file_path: "tests/material.wgsl",
        shader_type: ShaderType::Wgsl,
        ..Default::default()
    });
    match module {
        Ok(m) => m,
        Err(e) => panic!("{}", e.emit_to_string(&composer)),
    }
}

#[test]
fn library_composes_validates_and_mirrors_the_rust_constants() {
    let module = compose_entry();
    let mut validator =
        naga::valid::Validator::new(naga::valid::ValidationFlags::all(), Default::default());
    if let Err(e) = validator.validate(&module) {
        panic!("{e:?}");
    }
    let source = library(LIBRARY).map(|f| f.source).unwrap_or_default();
    for (name, value) in [
        ("FEATURE_COOK_TORRANCE", FEATURE_COOK_TORRANCE),
        ("FEATURE_EMISSION", FEATURE_EMISSION),
        ("FEATURE_FAKE_SSS", FEATURE_FAKE_SSS),
        ("FEATURE_REFLECTION", FEATURE_REFLECTION),
        ("FEATURE_MATCAP", FEATURE_MATCAP),
        ("FEATURE_AMBIENT_OCCLUSION", FEATURE_AMBIENT_OCCLUSION),
        ("FEATURE_CLEARCOAT", FEATURE_CLEARCOAT),
        ("FEATURE_UNLIT", FEATURE_UNLIT),
        ("FEATURE_TRANSMISSION", FEATURE_TRANSMISSION),
        ("FEATURE_IRIDESCENCE", FEATURE_IRIDESCENCE),
        ("FEATURE_ANISOTROPY", FEATURE_ANISOTROPY),
        ("FEATURE_SHEEN", FEATURE_SHEEN),
        ("FIRST_CUSTOM_FEATURE", FIRST_CUSTOM_FEATURE),
        ("MAX_FEATURES", MAX_FEATURES),
    ] {
        let line = format!("const {name}: u32 = {value}u;");
        assert!(source.contains(&line), "{LIBRARY} lacks `{line}`");
    }
}

/// Every kind of material: the default, one without features, all built-ins,
/// custom features with several, one and no parameters, the last id (31).
fn materials() -> Vec<Material> {
    let set = |mut m: Material, f: Feature, p: &[[f32; 4]]| {
        m.set(f, p).expect("valid parameters");
        m
    };
    let mut all = Material::new();
    for (i, f) in Feature::BUILT_IN.iter().enumerate() {
        let x = i as f32 * 0.1;
        let p = [0.1 + x, 0.2 + x, 0.3 + x, 0.4 + x];
        // Transmission takes two vec4s (refraction, absorption).
        let params = vec![p; f.param_count().unwrap_or(1)];
        all = set(all, *f, &params);
    }
    let custom = set(
        Material::new(),
        Feature::Custom(17),
        &[[1.0, 2.0, 3.0, 4.0], [-5.0, 6.0, -7.0, 8.0], [9.0; 4]],
    );
    let custom = set(custom, Feature::Custom(31), &[[31.0; 4]]);
    let custom = set(custom, Feature::Emission, &[[0.0, 1.0, 0.0, 5.0]]);
    let flag_only = set(Material::default_material(), Feature::Custom(16), &[]);
    vec![
        Material::default_material(),
        Material::new(),
        all,
        custom,
        flag_only,
        set(Material::new(), Feature::MatCap, &[[0.75, 0.0, 0.0, 0.0]]),
    ]
}

/// What the shader should give for one query, from the CPU-side world.
fn expected(world: &MaterialWorld, id: u32, feature: u32, index: u32) -> ([f32; 4], u32, u32) {
    let flags = world.flags(id);
    let has = feature < MAX_FEATURES && flags & (1 << feature) != 0;
    let param = Feature::from_id(i64::from(feature))
        .ok()
        .and_then(|f| world.params(id, f))
        .and_then(|p| p.get(index as usize).copied())
        .unwrap_or(FALLBACK);
    (param, flags, u32::from(has))
}

#[test]
fn shader_reads_what_the_material_world_holds() {
    let renderer = test_renderer();
    let world = MaterialWorld::new(&renderer, materials());
    // A second world beside it: each has its own buffers.
    let other = MaterialWorld::new(&renderer, Vec::new());
    assert_eq!(other.len(), 1);
    assert_eq!(other.union_flags(), 1);
    // The built-ins (0..=5, Clearcoat 7, Unlit 8, Transmission 9, Sheen 10,
    // Iridescence 11, Anisotropy 12) and the custom ones.
    assert_eq!(
        world.union_flags(),
        0b1_1111_1011_1111 | 1 << 16 | 1 << 17 | 1 << 31
    );

    let mut queries: Vec<[u32; 4]> = Vec::new();
    for id in (0..world.len() as u32 + 2).chain([u32::MAX]) {
        for feature in 0..MAX_FEATURES + 2 {
            for index in 0..4 {
                queries.push([id, feature, index, 0]);
            }
        }
    }
    let (params, flags) = run(&renderer, &world, &queries);

    let mut failures = Vec::new();
    for (i, q) in queries.iter().enumerate() {
        let (want_param, want_flags, want_has) = expected(&world, q[0], q[1], q[2]);
        let got = (params[i], flags[i][0], flags[i][1]);
        if got != (want_param, want_flags, want_has) {
            failures.push(format!(
                "material {} feature {} index {}: gpu {got:?}, cpu {:?}",
                q[0],
                q[1],
                q[2],
                (want_param, want_flags, want_has)
            ));
        }
    }
    assert!(
        failures.is_empty(),
        "{} of {} queries differ on {}:\n{}",
        failures.len(),
        queries.len(),
        renderer.gpu.adapter_name(),
        failures[..failures.len().min(20)].join("\n")
    );
}

/// Dispatch the query shader over `world`; read back the params and (flags, has) per query.
fn run(
    renderer: &spreadlight_render::Renderer,
    world: &MaterialWorld,
    queries: &[[u32; 4]],
) -> (Vec<[f32; 4]>, Vec<[u32; 2]>) {
    let device = &renderer.gpu.device;
    let n = queries.len() as u64;
    let input = device.create_buffer_init(&wgpu::util::BufferInitDescriptor {
        label: Some("material queries"),
        contents: bytemuck::cast_slice(queries),
        usage: wgpu::BufferUsages::STORAGE,
    });
    let output = |label, size| {
        device.create_buffer(&wgpu::BufferDescriptor {
            label: Some(label),
            size,
            usage: wgpu::BufferUsages::STORAGE | wgpu::BufferUsages::COPY_SRC,
            mapped_at_creation: false,
        })
    };
    let (params, flags) = (output("params", n * 16), output("flags", n * 8));
    let module = device.create_shader_module(wgpu::ShaderModuleDescriptor {
        label: Some("material test"),
        source: wgpu::ShaderSource::Naga(Cow::Owned(compose_entry())),
    });
    let pipeline = device.create_compute_pipeline(&wgpu::ComputePipelineDescriptor {
        label: Some("material test"),
        layout: None,
        module: &module,
        entry_point: Some("main"),
        compilation_options: Default::default(),
        cache: None,
    });
    let io = device.create_bind_group(&wgpu::BindGroupDescriptor {
        label: Some("material test io"),
        layout: &pipeline.get_bind_group_layout(0),
        entries: &entries([&input, &params, &flags]),
    });
    let (meta, offsets, data) = world.buffers();
    let materials = device.create_bind_group(&wgpu::BindGroupDescriptor {
        label: Some("material world"),
        layout: &pipeline.get_bind_group_layout(1),
        entries: &entries([meta, offsets, data]),
    });
    let mut encoder = device.create_command_encoder(&Default::default());
    {
        let mut pass = encoder.begin_compute_pass(&Default::default());
        pass.set_pipeline(&pipeline);
        pass.set_bind_group(0, &io, &[]);
        pass.set_bind_group(1, &materials, &[]);
        pass.dispatch_workgroups((n as u32).div_ceil(64), 1, 1);
    }
    renderer.gpu.queue.submit([encoder.finish()]);
    let params: Vec<[f32; 4]> = bytemuck::cast_slice(&read(renderer, &params)).to_vec();
    let flags: Vec<[u32; 2]> = bytemuck::cast_slice(&read(renderer, &flags)).to_vec();
    (params, flags)
}

fn entries<'a>(buffers: [&'a wgpu::Buffer; 3]) -> Vec<wgpu::BindGroupEntry<'a>> {
    buffers
        .into_iter()
        .enumerate()
        .map(|(i, b)| wgpu::BindGroupEntry {
            binding: i as u32,
            resource: b.as_entire_binding(),
        })
        .collect()
}

fn read(renderer: &spreadlight_render::Renderer, buffer: &wgpu::Buffer) -> Vec<u8> {
    let device = &renderer.gpu.device;
    let staging = device.create_buffer(&wgpu::BufferDescriptor {
        label: Some("material readback"),
        size: buffer.size(),
        usage: wgpu::BufferUsages::MAP_READ | wgpu::BufferUsages::COPY_DST,
        mapped_at_creation: false,
    });
    let mut encoder = device.create_command_encoder(&Default::default());
    encoder.copy_buffer_to_buffer(buffer, 0, &staging, 0, buffer.size());
    renderer.gpu.queue.submit([encoder.finish()]);
    let slice = staging.slice(..);
    let (tx, rx) = std::sync::mpsc::channel();
    slice.map_async(wgpu::MapMode::Read, move |r| {
        let _ = tx.send(r);
    });
    device
        .poll(wgpu::PollType::wait_indefinitely())
        .expect("GPU finishes");
    rx.recv().expect("map callback").expect("buffer maps");
    slice.get_mapped_range().expect("mapped").to_vec()
}
