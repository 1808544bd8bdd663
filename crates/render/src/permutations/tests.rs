//! The exhaustive permutation tests, over every entry shader the catalogue
//! names, and the string rules the typed keys replaced, replayed to show
//! they allow the same permutations.

use super::*;
use crate::shaders::{LIBRARIES, ShaderComposer};
use std::collections::BTreeSet;

/// A constraint between the features of one shader, as the table of
/// shaders held them before the typed keys: replayed here only, to compare.
#[derive(Clone, Copy, Debug)]
enum Rule {
    /// The first feature only with the second (a third light pair only with a second).
    Requires(&'static str, &'static str),
    /// At most one of these (a choice, such as GBufferView's channel).
    AtMostOne(&'static [&'static str]),
}

impl Rule {
    fn check(&self, features: &BTreeSet<&'static str>) -> Result<(), String> {
        match *self {
            Rule::Requires(a, b) if features.contains(a) && !features.contains(b) => {
                Err(format!("`{a}` needs `{b}`"))
            }
            Rule::AtMostOne(set) if set.iter().filter(|f| features.contains(*f)).count() > 1 => {
                Err(format!(
                    "these features are a choice, set at most one: {}",
                    set.join(", ")
                ))
            }
            _ => Ok(()),
        }
    }
}

/// The subsets of `features` that `rules` allow, in the order of their
/// bitmasks (feature `i` is bit `i`). The rules are turned into masks once
/// and each subset is checked as an integer: the light loop's 20 switches
/// are a million subsets, and a set built for each took seconds in a debug
/// build. Only the allowed subsets are built, and each is checked again
/// with [`Rule::check`], the rules as written.
fn allowed_subsets(features: &[&'static str], rules: &[Rule]) -> Vec<BTreeSet<&'static str>> {
    let n = features.len();
    let mask_of = |names: &[&str]| -> u32 {
        (0..n)
            .filter(|&i| names.contains(&features[i]))
            .fold(0, |mask, i| mask | 1 << i)
    };
    // (what needs, what it needs) or (a choice, 0).
    let masks: Vec<(bool, u32, u32)> = rules
        .iter()
        .map(|rule| match *rule {
            Rule::Requires(a, b) => (true, mask_of(&[a]), mask_of(&[b])),
            Rule::AtMostOne(set) => (false, mask_of(set), 0),
        })
        .collect();
    let allowed = |mask: u32| {
        masks.iter().all(|&(requires, a, b)| match requires {
            true => mask & a == 0 || mask & b != 0,
            false => (mask & a).count_ones() <= 1,
        })
    };
    (0u32..1 << n)
        .filter(|&mask| allowed(mask))
        .map(|mask| {
            let set: BTreeSet<&'static str> = (0..n)
                .filter(|i| mask & (1 << i) != 0)
                .map(|i| features[i])
                .collect();
            for rule in rules {
                assert!(rule.check(&set).is_ok(), "{rule:?} refuses {set:?}");
            }
            set
        })
        .collect()
}

/// The entry shader at `path`.
fn entry(path: &str) -> &'static ShaderFile {
    ENTRY_SHADERS
        .iter()
        .copied()
        .find(|f| f.path == path)
        .unwrap_or_else(|| panic!("{path} is no entry shader of the catalogue"))
}

#[test]
fn the_replayed_rules_refuse_what_they_did() {
    let set = |f: &[&'static str]| f.iter().copied().collect::<BTreeSet<_>>();
    let choice = Rule::AtMostOne(&["DEPTH", "UV"]);
    let err = choice.check(&set(&["DEPTH", "UV"])).expect_err("refused");
    assert!(err.contains("set at most one"), "{err}");
    assert!(choice.check(&set(&["UV"])).is_ok());
    let needs = Rule::Requires("SHADOW_PCF", "SHADOWS");
    let err = needs.check(&set(&["SHADOW_PCF"])).expect_err("refused");
    assert!(err.contains("`SHADOW_PCF` needs `SHADOWS`"), "{err}");
}

/// Every WGSL file of `shaders/` is a library or an entry shader of the
/// catalogue, once: a key whose file is missing here would escape the
/// exhaustive test. (`shaders/nodes/` holds shader-node examples, composed
/// at run time; its blur is also a built-in pass.)
#[test]
fn every_shader_file_is_a_library_or_a_listed_entry() {
    let root = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("../../shaders");
    let mut on_disk = BTreeSet::new();
    let mut folders = vec![root.clone()];
    while let Some(dir) = folders.pop() {
        for entry in std::fs::read_dir(&dir).expect("shaders/ reads").flatten() {
            let path = entry.path();
            if path.is_dir() {
                folders.push(path);
            } else if path.extension().is_some_and(|e| e == "wgsl") {
                let rel = path.strip_prefix(&root).expect("below shaders/");
                on_disk.insert(rel.to_string_lossy().replace('\\', "/"));
            }
        }
    }
    let listed: Vec<&str> = LIBRARIES
        .iter()
        .chain(ENTRY_SHADERS.iter().copied())
        .map(|f| f.path)
        .collect();
    let unique: BTreeSet<&str> = listed.iter().copied().collect();
    assert_eq!(
        unique.len(),
        listed.len(),
        "a file listed twice: {listed:?}"
    );
    let missing: Vec<&String> = on_disk
        .iter()
        .filter(|p| !p.starts_with("nodes/") || *p == "nodes/blur.wgsl")
        .filter(|p| !unique.contains(p.as_str()))
        .collect();
    assert!(
        missing.is_empty(),
        "neither a library nor a listed entry: {missing:?}"
    );
    assert!(ENTRY_SHADERS.iter().all(|f| !f.library && f.keys.is_some()));
    assert!(LIBRARIES.iter().all(|f| f.library && f.keys.is_none()));
}

/// All the permutations there are: the composite's 6,720, the light loop's
/// 13,130 (ANISOTROPY, IRIDESCENCE and SHEEN each double its shadings with a
/// material world: 2,730 before them), the resolve's 1,752 (384 of them
/// writing the anisotropy target, 384 the sheen and film target), lit transparency's (with refraction's blurs,
/// compute shading's records and kernels, the clear coat's 1,652 (324 of
/// them its reflection of the environment in the base passes), the
/// anisotropic lobe's and the sheen's forward light passes over surface maps),
/// Reflection's 128 (CLEARCOAT, IRIDESCENCE, SHEEN and ANISOTROPY each
/// double it: the anisotropic bent normal, issue 34), SSR's 24 (CLEARCOAT
/// doubles its 12: the coat's lobe traced), the sheen's and the anisotropic
/// lobe's records in lit transparency's compute shading (their recording
/// base passes and shade passes: +2,217), the environment probe's lobes on
/// its light passes over surface maps (+180), the resolve's SHEEN_FILM
/// (+384), the compute rasterizer's LAYERED (shadow maps' layers in one
/// chain: its 8 doubled, +8), AO's half-size estimate blending its
/// history (+4, and its temporal pass gone, -2), scrolling a shadow cascade in
/// compute (+2) and the rest. A key left out of
/// [`ENTRY_SHADERS`] changes the count, and docs/architecture.md states it,
/// so the number there cannot go stale. The fused light loop
/// (`lighting::light_sets`, issue 33) adds no file and no key here: it is
/// composed from `lighting/cook_torrance.wgsl`'s own text for the sets a
/// frame fuses, up to four of the light loop's 65 kinds of set, too many
/// combinations to list; its own tests compose every kind of set.
#[test]
fn the_permutation_count_is_unchanged() {
    assert_eq!(ENTRY_SHADERS.len(), 47);
    let count = all_permutations().len();
    assert_eq!(count, 32_729);
    let doc = std::fs::read_to_string(concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/../../docs/architecture.md"
    ))
    .expect("docs/architecture.md");
    let written = format!("({},{:03})", count / 1000, count % 1000);
    assert!(
        doc.contains(&format!("node set can ask for {written}")),
        "docs/architecture.md should say the node set can ask for {written} permutations"
    );
}

/// Every permutation composes and validates. Each is composed: of the
/// 27,816, 27,814 compose to different modules (measured in session 21 by
/// preprocessing each file's switch-dependent lines with naga_oil's own
/// preprocessor: a key's rules already leave out the switches whose code
/// another switch compiles out), so composing only the distinct ones would
/// save nothing. The cost is naga_oil's preprocessing and naga's parse of
/// each permutation; docs/benchmarks.md has the figures.
#[test]
fn every_permutation_composes_and_validates() {
    let keys = all_permutations();
    assert!(keys.len() >= 32, "resolve alone has 2^5 permutations");
    let failures = validate(&keys);
    assert!(failures.is_empty(), "{}", failures.join("\n\n"));
}

/// Compose and validate `keys` on every core, a composer per thread that
/// keeps what it composes to itself ([`ShaderComposer::unshared`]): its
/// libraries added once, the library variants it composed reused for the
/// next permutations of the same file. The keys are handed out in blocks of
/// neighbours (the same file, mostly the same variants of its libraries),
/// block by block as a thread is free: the light loop's permutations cost
/// many times a blur's, and fixed halves left one core idle for the end.
/// The failures, each naming its permutation.
fn validate(keys: &[ShaderKey]) -> Vec<String> {
    use std::sync::atomic::{AtomicUsize, Ordering};
    const BLOCK: usize = 64;
    let threads = std::thread::available_parallelism().map_or(2, |n| n.get());
    let next = AtomicUsize::new(0);
    std::thread::scope(|scope| {
        let workers: Vec<_> = (0..threads.min(keys.len().div_ceil(BLOCK)))
            .map(|_| {
                scope.spawn(|| {
                    let mut composer = ShaderComposer::unshared().expect("libraries compose");
                    let mut failures = Vec::new();
                    loop {
                        let start = next.fetch_add(BLOCK, Ordering::Relaxed);
                        let Some(block) = keys.get(start..(start + BLOCK).min(keys.len())) else {
                            break;
                        };
                        failures.extend(
                            block
                                .iter()
                                .filter_map(|k| composer.compose(k).err().map(|e| e.to_string())),
                        );
                    }
                    failures
                })
            })
            .collect();
        workers
            .into_iter()
            .flat_map(|w| w.join().expect("no panic"))
            .collect()
    })
}

/// A tiny entry shader for the validation's own test: with `USED` and
/// `BROKEN` it reads a name it never declares.
static FIXTURE: ShaderFile = ShaderFile {
    path: "fixture/broken.wgsl",
    source: "#import spreadlight::packing::safe_normalize

@compute @workgroup_size(1)
fn main() {
    var v = vec3<f32>(1.0, 0.0, 0.0);
#ifdef USED
    v = safe_normalize(v, vec3<f32>(0.0, 0.0, 1.0));
#ifdef BROKEN
    v = undeclared_name;
#endif
#endif
}
",
    features: &["USED", "BROKEN"],
    library: false,
    keys: Some(fixture_keys),
};

/// Every subset of the fixture's switches.
fn fixture_keys() -> Vec<ShaderKey> {
    (0u32..4)
        .map(|mask| {
            let features = FIXTURE
                .features
                .iter()
                .enumerate()
                .filter(|(i, _)| mask & (1 << i) != 0)
                .map(|(_, f)| *f);
            ShaderKey::new(&FIXTURE, features)
        })
        .collect()
}

/// The exhaustive test's harness fails for a broken permutation, and only
/// for it, naming it and the error.
#[test]
fn a_broken_permutation_fails_the_validation_by_name() {
    let failures = validate(&fixture_keys());
    assert_eq!(failures.len(), 1, "{failures:#?}");
    let failure = &failures[0];
    assert!(
        failure.starts_with("shader `fixture/broken.wgsl` [BROKEN, USED]"),
        "{failure}"
    );
    assert!(failure.contains("undeclared_name"), "{failure}");
}

#[test]
fn the_composite_has_the_keys_its_rules_allowed() {
    let composite: Vec<_> = all_permutations()
        .into_iter()
        .filter(|k| k.path() == "lighting/composite.wgsl")
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
fn a_typed_key_names_its_file_and_only_its_features() {
    for file in ENTRY_SHADERS {
        let keyed = file.keys.expect("an entry shader has a typed key");
        let keys = keyed();
        assert!(!keys.is_empty(), "{}", file.path);
        let mut seen = std::collections::BTreeSet::new();
        for key in &keys {
            assert_eq!(
                key.path(),
                file.path,
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

/// The typed keys that replaced string rules (`flag_key!`, `choice_key!`,
/// TAA's quality) enumerate exactly the feature sets, in the same order,
/// that the rules did: the permutation set did not change.
#[test]
fn typed_keys_enumerate_what_the_string_rules_did() {
    use std::collections::BTreeSet;
    // As the table of shaders listed them before.
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
            // LAYERED (session 22): a shadow map's layers in one chain.
            &["TWO_SIDED", "MESHES_ONLY", "DEPTH_ONLY", "LAYERED"],
            vec![],
        ),
        ("gbuffer/published_depth.wgsl", &["COMPUTE_RASTER"], vec![]),
        // OCCUPIED (session 17): lit transparency's lists only in marked froxels.
        // MERGED (session 28): Light Merge's bands.
        ("lighting/clusters.wgsl", &["OCCUPIED", "MERGED"], vec![]),
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
            &[
                "MATERIAL_TEXTURES",
                "SURFACE_TARGET",
                "PARALLAX",
                "CLEARCOAT",
                "IRIDESCENCE",
                "SHEEN",
                "ANISOTROPY",
            ],
            vec![],
        ),
        (
            "post/taa.wgsl",
            &["VARIANCE_CLIP", "CATMULL_ROM"],
            vec![Rule::Requires("CATMULL_ROM", "VARIANCE_CLIP")],
        ),
        // AO, AO_COMBINE, AMBIENT (half22): the half chains' last pass.
        (
            "resolution/upsample.wgsl",
            &["R32", "DETAIL", "AO", "AO_COMBINE", "AMBIENT"],
            choice(&["R32", "DETAIL", "AO", "AO_COMBINE", "AMBIENT"]),
        ),
        (
            "lighting/ssgi.wgsl",
            &[
                "TEMPORAL", "GATHER", "BLUR", "AMBIENT", "HALF", "PACKED", "PACKED_Z",
            ],
            vec![
                Rule::AtMostOne(&["TEMPORAL", "BLUR"]),
                Rule::Requires("AMBIENT", "BLUR"),
                Rule::Requires("GATHER", "TEMPORAL"),
                // The half chain (half22): a blend and blurs at half size,
                // never with the gather fused, the ambient or the packed surface.
                Rule::AtMostOne(&["HALF", "GATHER"]),
                Rule::AtMostOne(&["HALF", "AMBIENT"]),
                Rule::AtMostOne(&["HALF", "PACKED"]),
                // The packed surface (ao21): a blur's taps, or a gather's rays.
                Rule::Requires("PACKED", "BLUR"),
                Rule::AtMostOne(&["PACKED_Z", "BLUR"]),
            ],
        ),
    ];
    for (path, features, rules) in old {
        let file = entry(path);
        let keyed = file
            .keys
            .unwrap_or_else(|| panic!("{path} has no typed key"));
        let keyed: Vec<BTreeSet<&str>> = keyed().into_iter().map(|k| k.features).collect();
        let ruled = allowed_subsets(features, &rules);
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
        allowed_subsets(features, rules).into_iter().collect()
    };
    let keyed = |path: &str| -> (Sets, usize) {
        let keys = entry(path)
            .keys
            .unwrap_or_else(|| panic!("{path} has no typed key"))();
        let n = keys.len();
        (keys.into_iter().map(|k| k.features).collect(), n)
    };
    // The rules as the table of shaders listed them before, over the key's own switches.
    let resolve: &[&str] = crate::gbuffer::resolve_key::ResolveKey::FEATURES;
    let resolve_rules = [
        Rule::AtMostOne(&["COLOR_MAP", "MOTION"]),
        Rule::AtMostOne(&["VELOCITY_OUT", "MOTION"]),
        Rule::AtMostOne(&["TEXCOORDS", "TRIPLANAR"]),
        Rule::AtMostOne(&["SURFACE_OUT", "MOTION"]),
        Rule::Requires("MATERIAL_MAPS", "SURFACE_OUT"),
        Rule::Requires("EXTENSION_MAPS", "MATERIAL_MAPS"),
        Rule::Requires("ANISOTROPY", "MATERIAL_MAPS"),
        Rule::Requires("SHEEN_FILM", "EXTENSION_MAPS"),
        Rule::Requires("CUSTOM_SURFACE", "SURFACE_OUT"),
        Rule::AtMostOne(&["CUSTOM_SURFACE", "MATERIAL_MAPS"]),
        Rule::AtMostOne(&["VERTEX_EXTRAS", "MOTION"]),
    ];
    let (sets, n) = keyed("gbuffer/resolve.wgsl");
    assert_eq!((sets, n), (ruled(resolve, &resolve_rules), 1752));
    let cook_torrance: &[&str] = crate::lighting::cook_torrance_key::CookTorranceKey::FEATURES;
    let cook_torrance_rules = [
        Rule::AtMostOne(&["LIGHT_SPOT", "LIGHT_SUN"]),
        Rule::AtMostOne(&["CUSTOM_LIGHT", "ENERGY_COMPENSATION"]),
        Rule::AtMostOne(&["CUSTOM_LIGHT", "FAKE_SSS"]),
        Rule::AtMostOne(&["CUSTOM_LIGHT", "CLEARCOAT"]),
        Rule::AtMostOne(&["CUSTOM_LIGHT", "ANISOTROPY"]),
        Rule::Requires("ANISOTROPY", "MATERIALS"),
        Rule::Requires("ANISOTROPY", "SURFACE_TARGET"),
        Rule::AtMostOne(&["CUSTOM_LIGHT", "IRIDESCENCE"]),
        Rule::AtMostOne(&["CUSTOM_LIGHT", "SHEEN"]),
        Rule::AtMostOne(&["SHADOW_PCF", "SHADOW_PCSS", "SHADOW_VSM"]),
        Rule::Requires("SHADOW_PCF", "SHADOWS"),
        Rule::Requires("SHADOW_PCSS", "SHADOWS"),
        Rule::Requires("SHADOW_VSM", "SHADOWS"),
        Rule::Requires("FAKE_SSS", "MATERIALS"),
        Rule::Requires("CLEARCOAT", "MATERIALS"),
        Rule::Requires("IRIDESCENCE", "MATERIALS"),
        Rule::Requires("SHEEN", "MATERIALS"),
        Rule::AtMostOne(&["LIGHT_SUN", "CLUSTERED"]),
        Rule::Requires("SPOT_TEXTURE", "LIGHT_SPOT"),
        Rule::Requires("MATERIAL_TEXTURES", "MATERIALS"),
        Rule::Requires("TILED", "CLUSTERED"),
        Rule::Requires("PER_PIXEL", "CLUSTERED"),
        Rule::AtMostOne(&["TILED", "PER_PIXEL"]),
        // Light Merge (session 28): point lights, walked by their own froxel's list.
        Rule::Requires("MERGED", "CLUSTERED"),
        Rule::AtMostOne(&["MERGED", "LIGHT_SPOT"]),
        Rule::AtMostOne(&["MERGED", "TILED"]),
    ];
    let (sets, n) = keyed("lighting/cook_torrance.wgsl");
    assert_eq!(
        (sets, n),
        (ruled(cook_torrance, &cook_torrance_rules), 15150)
    );
    // The G-buffer view: the rule's empty choice (no channel, a black
    // image) was never built, as every view shows a Channel.
    let channels: &[&str] = crate::gbuffer::view_key::Channel::FEATURES;
    let mut ruled_view = ruled(channels, &[Rule::AtMostOne(channels)]);
    assert!(ruled_view.remove(&BTreeSet::new()));
    let (sets, n) = keyed("gbuffer/view.wgsl");
    assert_eq!((sets, n), (ruled_view, 7));
}
