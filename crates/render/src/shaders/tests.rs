use super::*;
use crate::gbuffer::view_key::Channel;
use crate::lighting::composite::key::CompositeKey;
use crate::lighting::cook_torrance_key::CookTorranceKey;

/// A key of `K`'s file with any features, as no typed key would make it.
fn raw<K: Permutation>(features: impl IntoIterator<Item = &'static str>) -> ShaderKey {
    ShaderKey::new(K::FILE, features)
}

#[test]
fn shaders_reload_from_disk_and_report_errors_with_the_file() {
    let dir = tempfile::tempdir().expect("tempdir");
    // A folder with one edited shader: the rest fall back to the embedded sources.
    std::fs::create_dir_all(dir.path().join("gbuffer")).expect("mkdir");
    std::fs::write(dir.path().join("gbuffer/view.wgsl"), "fn broken( {").expect("write");
    let mut composer = ShaderComposer::from_dir(dir.path()).expect("libraries still compose");
    let visibility = crate::gbuffer::visibility_key::VisibilityKey { alpha_mask: false };
    assert!(composer.compose(&visibility.key()).is_ok());
    let err = composer.compose(&Channel::Depth.key()).expect_err("broken");
    assert!(
        err.to_string().starts_with("shader `gbuffer/view.wgsl`"),
        "{err}"
    );
}

#[test]
fn an_exclusive_choice_takes_one_feature() {
    // The G-buffer view's channels are its typed key's values (Channel): two is none of them.
    let mut composer = ShaderComposer::new().expect("libraries compose");
    let err = composer
        .compose(&raw::<Channel>(["DEPTH", "UV"]))
        .expect_err("refused");
    assert!(err.to_string().contains("typed key"), "{err}");
}

#[test]
fn a_feature_without_what_it_needs_is_refused() {
    // The light loop's rules are its typed key's shape (CookTorranceKey):
    // a shadow filter without shadows is no value of it.
    let mut composer = ShaderComposer::new().expect("libraries compose");
    let err = composer
        .compose(&raw::<CookTorranceKey>(["SHADOW_PCF"]))
        .expect_err("refused");
    assert!(err.to_string().contains("typed key"), "{err}");
    // The composite's rules are its typed key's shape (CompositeKey): a
    // third light pair without a second is no value of it.
    let err = composer
        .compose(&raw::<CompositeKey>(["LIGHTS_3"]))
        .expect_err("refused");
    assert!(err.to_string().contains("typed key"), "{err}");
}

#[test]
fn an_unknown_feature_is_refused_by_name() {
    let mut composer = ShaderComposer::new().expect("libraries compose");
    let err = composer
        .compose(&raw::<crate::gbuffer::resolve_key::ResolveKey>([
            "SPARKLES",
        ]))
        .expect_err("refused");
    assert!(
        err.to_string().contains("`SPARKLES` is not a feature"),
        "{err}"
    );
}

#[test]
fn a_cached_bind_group_is_found_by_what_it_binds() {
    let renderer = crate::renderer::test_renderer();
    let device = &renderer.gpu.device;
    let wgsl = "@group(0) @binding(0) var<storage, read_write> data: array<u32>;
        @compute @workgroup_size(1) fn main() { data[0] = 1u; }";
    let mut cache = renderer.shaders();
    let pipeline = cache.external_compute_pipeline(
        device,
        1,
        "bind group cache test",
        || naga::front::wgsl::parse_str(wgsl).expect("parses"),
        "main",
    );
    let pipeline = PipelineRef::Compute(pipeline);
    let buffer = |label| {
        device.create_buffer(&wgpu::BufferDescriptor {
            label: Some(label),
            size: 512,
            usage: wgpu::BufferUsages::STORAGE,
            mapped_at_creation: false,
        })
    };
    let (a, b) = (buffer("a"), buffer("b"));
    let reflection = Reflection::of_wgsl(wgsl, "main").expect("reflects");
    let mut group = |buffer: &wgpu::Buffer, offset: u64| {
        let range = wgpu::BindingResource::Buffer(wgpu::BufferBinding {
            buffer,
            offset,
            size: wgpu::BufferSize::new(256),
        });
        let entries = reflection.entries(0, &[("data", range)]).expect("binds");
        let before = (cache.bind_groups_created, cache.bind_groups_reused);
        let group = cache.group(device, &pipeline, 0, "test", &entries);
        let made = cache.bind_groups_created - before.0;
        assert_eq!(made + cache.bind_groups_reused - before.1, 1);
        (group, made == 1)
    };
    let (first, made) = group(&a, 0);
    assert!(made);
    // The same buffer and range: the same group, none made.
    let (again, made) = group(&a, 0);
    assert!(!made && again == first);
    // Another buffer, or another range of the same one: groups of their own.
    let (other, made) = group(&b, 0);
    assert!(made && other != first);
    let (offset, made) = group(&a, 256);
    assert!(made && offset != first);
    assert!(!group(&b, 0).1 && !group(&a, 256).1 && !group(&a, 0).1);
}

#[test]
fn a_feature_set_no_typed_key_has_is_refused() {
    use crate::ssao::{AoKey, AoTarget};
    let ao = <AoKey as Permutation>::FILE;
    // One estimator at a time: no AoMode is both SAO and HBAO.
    let both: std::collections::BTreeSet<_> = ["SAO", "HBAO"].into_iter().collect();
    let err = ao.check(&both).expect_err("refused");
    assert!(err.contains("typed key"), "{err}");
    let half = AoKey {
        estimator: crate::ssao::AoMode::Hbao,
        target: AoTarget::Half,
        packed: false,
    };
    assert!(ao.check(&half.key().features).is_ok());
}

#[test]
fn a_module_of_its_own_binds_by_name() {
    let wgsl = "@group(0) @binding(3) var<storage, read> input: array<u32>;
        @group(0) @binding(7) var<storage, read_write> output: array<u32>;
        @group(0) @binding(9) var<storage, read_write> unused: array<u32>;
        @compute @workgroup_size(1) fn main() { output[0] = input[0]; }";
    let reflection = Reflection::of_wgsl(wgsl, "main").expect("reflects");
    let renderer = crate::renderer::test_renderer();
    let buffer = renderer.gpu.device.create_buffer(&wgpu::BufferDescriptor {
        label: Some("by name"),
        size: 16,
        usage: wgpu::BufferUsages::STORAGE,
        mapped_at_creation: false,
    });
    let whole = || buffer.as_entire_binding();
    // Each by the number the WGSL gave it; `unused`, which `main` never
    // touches and a derived layout leaves out, is left out too.
    let entries = reflection
        .entries(
            0,
            &[("output", whole()), ("input", whole()), ("unused", whole())],
        )
        .expect("binds");
    let numbers: Vec<u32> = entries.iter().map(|e| e.binding).collect();
    assert_eq!(numbers, [7, 3]);
    let err = reflection
        .entries(0, &[("input", whole())])
        .expect_err("output unbound");
    assert!(err.contains("`output`"), "{err}");
    let err = reflection
        .entries(
            0,
            &[("input", whole()), ("output", whole()), ("typo", whole())],
        )
        .expect_err("no such variable");
    assert!(err.contains("`typo`"), "{err}");
    assert!(Reflection::of_wgsl("fn broken( {", "main").is_err());
}
