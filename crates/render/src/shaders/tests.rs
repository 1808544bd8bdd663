use super::*;

#[test]
fn every_permutation_composes_and_validates() {
    let keys = all_permutations();
    assert!(keys.len() >= 32, "resolve alone has 2^5 permutations");
    // Hundreds of permutations: a composer per thread, a share of the keys each.
    let threads = std::thread::available_parallelism().map_or(2, |n| n.get());
    let chunk = keys.len().div_ceil(threads);
    let failures: Vec<String> = std::thread::scope(|scope| {
        let workers: Vec<_> = keys
            .chunks(chunk)
            .map(|share| {
                scope.spawn(move || {
                    let mut composer = ShaderComposer::new().expect("libraries compose");
                    share
                        .iter()
                        .filter_map(|k| composer.compose(k).err().map(|e| e.to_string()))
                        .collect::<Vec<_>>()
                })
            })
            .collect();
        workers
            .into_iter()
            .flat_map(|w| w.join().expect("no panic"))
            .collect()
    });
    assert!(failures.is_empty(), "{}", failures.join("\n\n"));
}

#[test]
fn shaders_reload_from_disk_and_report_errors_with_the_file() {
    let dir = tempfile::tempdir().expect("tempdir");
    // A folder with one edited shader: the rest fall back to the embedded sources.
    std::fs::create_dir_all(dir.path().join("gbuffer")).expect("mkdir");
    std::fs::write(dir.path().join("gbuffer/view.wgsl"), "fn broken( {").expect("write");
    let mut composer = ShaderComposer::from_dir(dir.path()).expect("libraries still compose");
    assert!(
        composer
            .compose(&ShaderKey::new("gbuffer/visibility.wgsl", []))
            .is_ok()
    );
    let err = composer
        .compose(&ShaderKey::new("gbuffer/view.wgsl", []))
        .expect_err("broken");
    assert!(
        err.to_string().starts_with("shader `gbuffer/view.wgsl`"),
        "{err}"
    );
}

#[test]
fn an_exclusive_choice_takes_one_feature() {
    let rule = Rule::AtMostOne(&["DEPTH", "UV"]);
    let err = rule
        .check(&["DEPTH", "UV"].into_iter().collect())
        .expect_err("refused");
    assert!(err.contains("set at most one"), "{err}");
    assert!(rule.check(&["UV"].into_iter().collect()).is_ok());
    // The G-buffer view's channels are its typed key's values (Channel): two is none of them.
    let mut composer = ShaderComposer::new().expect("libraries compose");
    let err = composer
        .compose(&ShaderKey::new("gbuffer/view.wgsl", ["DEPTH", "UV"]))
        .expect_err("refused");
    assert!(err.to_string().contains("typed key"), "{err}");
}

#[test]
fn a_feature_without_what_it_needs_is_refused_and_never_enumerated() {
    let rule = Rule::Requires("SHADOW_PCF", "SHADOWS");
    let err = rule
        .check(&["SHADOW_PCF"].into_iter().collect())
        .expect_err("refused");
    assert!(err.contains("`SHADOW_PCF` needs `SHADOWS`"), "{err}");
    // The light loop's rules are its typed key's shape (CookTorranceKey):
    // a shadow filter without shadows is no value of it.
    let mut composer = ShaderComposer::new().expect("libraries compose");
    let err = composer
        .compose(&ShaderKey::new(
            "lighting/cook_torrance.wgsl",
            ["SHADOW_PCF"],
        ))
        .expect_err("refused");
    assert!(err.to_string().contains("typed key"), "{err}");
    // The composite's rules are its typed key's shape (CompositeKey): a
    // third light pair without a second is no value of it.
    let err = composer
        .compose(&ShaderKey::new("lighting/composite.wgsl", ["LIGHTS_3"]))
        .expect_err("refused");
    assert!(err.to_string().contains("typed key"), "{err}");
    let composite: Vec<_> = all_permutations()
        .into_iter()
        .filter(|k| k.path == "lighting/composite.wgsl")
        .collect();
    // Light pairs with the SSS terms they allow (2 + 4 + 8 + 16), times
    // GI (2), times the surface target (2), times the 56 ways of AO
    // (none, AO, per material), emission (none, plain, textured),
    // reflection (2), matcap (none, built-in, textured) and the material
    // library (forced on when one of them reads it, free otherwise:
    // 52 + 2 x 2): 6,720 of the 2^17 subsets, the count the string rules
    // allowed before CompositeKey replaced them.
    assert_eq!(composite.len(), 30 * 2 * 2 * 56);
}

#[test]
fn an_unknown_feature_is_refused_by_name() {
    let mut composer = ShaderComposer::new().expect("libraries compose");
    let err = composer
        .compose(&ShaderKey::new("gbuffer/resolve.wgsl", ["SPARKLES"]))
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
fn a_typed_key_names_its_file_and_only_its_features() {
    for file in SHADERS.iter() {
        let Some(keyed) = file.keyed else { continue };
        let keys = keyed();
        assert!(!keys.is_empty(), "{}", file.path);
        let mut seen = std::collections::BTreeSet::new();
        for key in &keys {
            assert_eq!(
                key.path, file.path,
                "a key of {} names another file",
                file.path
            );
            assert!(
                key.features.iter().all(|f| file.features.contains(f)),
                "{}: {:?} outside {:?}",
                file.path,
                key.features,
                file.features
            );
            assert!(
                seen.insert(key.features.clone()),
                "{}: {key:?} twice",
                file.path
            );
            assert!(file.check(&key.features).is_ok());
        }
        // Every switch the file declares is used by some permutation.
        for feature in file.features {
            assert!(
                keys.iter().any(|k| k.features.contains(feature)),
                "{}: `{feature}` is in no permutation",
                file.path
            );
        }
    }
}

#[test]
fn a_feature_set_no_typed_key_has_is_refused() {
    use crate::ssao::{AoKey, AoTarget};
    let ao = SHADERS
        .iter()
        .find(|f| f.path == <AoKey as super::Permutation>::PATH)
        .expect("ssao/ao.wgsl is listed");
    // Half resolution blends its history after the upsample: no AoTarget holds both.
    let both: std::collections::BTreeSet<_> = ["HALF", "TEMPORAL"].into_iter().collect();
    let err = ao.check(&both).expect_err("refused");
    assert!(err.contains("typed key"), "{err}");
    let half = AoKey {
        estimator: crate::ssao::AoMode::Hbao,
        target: AoTarget::Half,
    };
    assert!(ao.check(&super::Permutation::key(half).features).is_ok());
}

/// The typed keys that replaced string rules (`flag_key!`, `choice_key!`,
/// TAA's quality) enumerate exactly the feature sets, in the same order,
/// that the rules did: the permutation set did not change.
#[test]
fn typed_keys_enumerate_what_the_string_rules_did() {
    use std::collections::BTreeSet;
    // As `SHADERS` listed them before.
    let choice = |f: &'static [&'static str]| vec![Rule::AtMostOne(f)];
    let old: Vec<(&str, &[&str], Vec<Rule>)> = vec![
        ("gbuffer/visibility.wgsl", &["ALPHA_MASK"], vec![]),
        ("geometry/spherize.wgsl", &[], vec![]),
        ("geometry/extrude.wgsl", &["TEXTURE"], vec![]),
        ("geometry/pn_triangles.wgsl", &["FLAT"], vec![]),
        ("geometry/spline.wgsl", &["RIBBON", "BEZIER"], vec![]),
        (
            "geometry/tessellate.wgsl",
            &["COUNT", "SUMS"],
            choice(&["COUNT", "SUMS"]),
        ),
        (
            "geometry/displace.wgsl",
            &["ACCUMULATE", "NORMALS"],
            choice(&["ACCUMULATE", "NORMALS"]),
        ),
        ("geometry/skinning.wgsl", &[], vec![]),
        (
            "particles/simulate.wgsl",
            &["FIELD_TEXTURE", "MESH_EMITTER", "DEPTH_COLLISION"],
            vec![],
        ),
        ("particles/expand.wgsl", &[], vec![]),
        (
            "gbuffer/raster.wgsl",
            &["TWO_SIDED", "MESHES_ONLY", "DEPTH_ONLY"],
            vec![],
        ),
        ("gbuffer/published_depth.wgsl", &["COMPUTE_RASTER"], vec![]),
        // OCCUPIED (session 17): lit transparency's lists only in marked froxels.
        ("lighting/clusters.wgsl", &["OCCUPIED"], vec![]),
        (
            "lighting/ssss.wgsl",
            &["VERTICAL", "SOURCES_2", "SOURCES_3"],
            vec![],
        ),
        ("shadows/depth.wgsl", &[], vec![]),
        ("shadows/moments.wgsl", &[], vec![]),
        ("shadows/resolve.wgsl", &["OVER_STILL"], vec![]),
        ("environment/prefilter.wgsl", &[], vec![]),
        ("post/tonemap.wgsl", &["EYE_ADAPTATION"], vec![]),
        ("post/eye_adaptation.wgsl", &[], vec![]),
        ("post/fxaa.wgsl", &[], vec![]),
        ("post/copy.wgsl", &[], vec![]),
        ("bench/pass_chain.wgsl", &[], vec![]),
        ("post/autofocus.wgsl", &[], vec![]),
        ("post/motion_blur.wgsl", &[], vec![]),
        ("post/glare.wgsl", &["FILTERED_SOURCE"], vec![]),
        (
            "environment/reflection.wgsl",
            &["MATERIAL_TEXTURES", "SURFACE_TARGET", "PARALLAX"],
            vec![],
        ),
        (
            "post/taa.wgsl",
            &["VARIANCE_CLIP", "CATMULL_ROM"],
            vec![Rule::Requires("CATMULL_ROM", "VARIANCE_CLIP")],
        ),
        (
            "resolution/upsample.wgsl",
            &["R32", "DETAIL"],
            choice(&["R32", "DETAIL"]),
        ),
        (
            "lighting/ssgi.wgsl",
            &["TEMPORAL", "GATHER", "BLUR", "AMBIENT", "HALF"],
            vec![
                Rule::AtMostOne(&["TEMPORAL", "BLUR"]),
                Rule::Requires("AMBIENT", "BLUR"),
                Rule::Requires("GATHER", "TEMPORAL"),
                Rule::AtMostOne(&["HALF", "TEMPORAL"]),
                Rule::AtMostOne(&["HALF", "BLUR"]),
            ],
        ),
    ];
    for (path, features, rules) in old {
        let file = SHADERS.iter().find(|f| f.path == path).expect(path);
        let keyed = file
            .keyed
            .unwrap_or_else(|| panic!("{path} has no typed key"));
        let keyed: Vec<BTreeSet<&str>> = keyed().into_iter().map(|k| k.features).collect();
        let n = features.len();
        let ruled: Vec<BTreeSet<&str>> = (0u32..1 << n)
            .map(|mask| {
                (0..n)
                    .filter(|i| mask & (1 << i) != 0)
                    .map(|i| features[i])
                    .collect()
            })
            .filter(|set| rules.iter().all(|r| r.check(set).is_ok()))
            .collect();
        assert_eq!(keyed, ruled, "{path}");
        assert_eq!(file.features, features, "{path}");
    }
}

/// The keys written by hand in place of string rules (their own order of
/// enumeration) allow the feature sets the rules did: the same sets, save
/// those the code never built, each named here.
#[test]
fn hand_written_keys_allow_what_the_string_rules_did() {
    use std::collections::BTreeSet;
    type Sets = BTreeSet<BTreeSet<&'static str>>;
    let ruled = |features: &[&'static str], rules: &[Rule]| -> Sets {
        let n = features.len();
        (0u32..1 << n)
            .map(|mask| {
                (0..n)
                    .filter(|i| mask & (1 << i) != 0)
                    .map(|i| features[i])
                    .collect::<BTreeSet<_>>()
            })
            .filter(|set| rules.iter().all(|r| r.check(set).is_ok()))
            .collect()
    };
    let keyed = |path: &str| -> (Sets, usize) {
        let file = SHADERS.iter().find(|f| f.path == path).expect(path);
        let keys = file
            .keyed
            .unwrap_or_else(|| panic!("{path} has no typed key"))();
        let n = keys.len();
        (keys.into_iter().map(|k| k.features).collect(), n)
    };
    // The rules as `SHADERS` listed them before, over the key's own switches.
    let resolve: &[&str] = crate::gbuffer::resolve_key::ResolveKey::FEATURES;
    let resolve_rules = [
        Rule::AtMostOne(&["COLOR_MAP", "MOTION"]),
        Rule::AtMostOne(&["VELOCITY_OUT", "MOTION"]),
        Rule::AtMostOne(&["TEXCOORDS", "TRIPLANAR"]),
        Rule::AtMostOne(&["SURFACE_OUT", "MOTION"]),
        Rule::Requires("MATERIAL_MAPS", "SURFACE_OUT"),
        Rule::Requires("EXTENSION_MAPS", "MATERIAL_MAPS"),
        Rule::Requires("CUSTOM_SURFACE", "SURFACE_OUT"),
        Rule::AtMostOne(&["CUSTOM_SURFACE", "MATERIAL_MAPS"]),
        Rule::AtMostOne(&["VERTEX_EXTRAS", "MOTION"]),
    ];
    let (sets, n) = keyed("gbuffer/resolve.wgsl");
    assert_eq!((sets, n), (ruled(resolve, &resolve_rules), 984));
    let cook_torrance: &[&str] = crate::lighting::cook_torrance_key::CookTorranceKey::FEATURES;
    let cook_torrance_rules = [
        Rule::AtMostOne(&["LIGHT_SPOT", "LIGHT_SUN"]),
        Rule::AtMostOne(&["CUSTOM_LIGHT", "ENERGY_COMPENSATION"]),
        Rule::AtMostOne(&["CUSTOM_LIGHT", "FAKE_SSS"]),
        Rule::AtMostOne(&["CUSTOM_LIGHT", "CLEARCOAT"]),
        Rule::AtMostOne(&["SHADOW_PCF", "SHADOW_PCSS", "SHADOW_VSM"]),
        Rule::Requires("SHADOW_PCF", "SHADOWS"),
        Rule::Requires("SHADOW_PCSS", "SHADOWS"),
        Rule::Requires("SHADOW_VSM", "SHADOWS"),
        Rule::Requires("FAKE_SSS", "MATERIALS"),
        Rule::Requires("CLEARCOAT", "MATERIALS"),
        Rule::AtMostOne(&["LIGHT_SUN", "CLUSTERED"]),
        Rule::Requires("SPOT_TEXTURE", "LIGHT_SPOT"),
        Rule::Requires("MATERIAL_TEXTURES", "MATERIALS"),
        Rule::Requires("TILED", "CLUSTERED"),
        Rule::Requires("PER_PIXEL", "CLUSTERED"),
        Rule::AtMostOne(&["TILED", "PER_PIXEL"]),
    ];
    let (sets, n) = keyed("lighting/cook_torrance.wgsl");
    assert_eq!(
        (sets, n),
        (ruled(cook_torrance, &cook_torrance_rules), 2730)
    );
    // The G-buffer view: the rule's empty choice (no channel, a black
    // image) was never built, as every view shows a Channel.
    let channels: &[&str] = crate::gbuffer::view_key::Channel::FEATURES;
    let mut ruled_view = ruled(channels, &[Rule::AtMostOne(channels)]);
    assert!(ruled_view.remove(&BTreeSet::new()));
    let (sets, n) = keyed("gbuffer/view.wgsl");
    assert_eq!((sets, n), (ruled_view, 7));
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
