//! The fused light loop composes and validates for every kind of set
//! (each light type and walk, spot textures, each shadow filter), beside
//! others, and with the material switches shared.

use super::*;
use crate::lighting::cook_torrance_key::{Lights, Shading, ShadowSampling};

/// Every set a CookTorrance of the built-in BRDF can be, without materials.
fn set_kinds() -> Vec<CookTorranceKey> {
    CookTorranceKey::all()
        .into_iter()
        .filter(|k| {
            k.shading
                == Shading::Brdf {
                    energy_compensation: true,
                    materials: None,
                }
                && !k.surface_target
        })
        .collect()
}

/// The kind of set of `kinds` ([`set_kinds`]) with these lights and
/// shadows.
fn set_kind(
    kinds: &[CookTorranceKey],
    lights: Lights,
    shadows: Option<ShadowSampling>,
) -> CookTorranceKey {
    kinds
        .iter()
        .copied()
        .find(|k| k.lights == lights && k.shadows == shadows)
        .expect("a kind of set")
}

/// The sets' permutations, as the generator takes them.
fn shader_keys(keys: &[CookTorranceKey]) -> Vec<ShaderKey> {
    keys.iter().map(|k| k.key()).collect()
}

fn shares_memory(key: &CookTorranceKey) -> bool {
    matches!(
        key.lights,
        Lights::Point(Walk::Clustered | Walk::Tiled)
            | Lights::PointMerged(Walk::Clustered)
            | Lights::Spot {
                walk: Walk::Clustered | Walk::Tiled,
                ..
            }
    )
}

#[test]
fn every_kind_of_set_composes_in_a_fused_loop() {
    let kinds = set_kinds();
    // 15 light walks (13, and the two that merge point lights) x 5 shadow samplings.
    assert_eq!(kinds.len(), 75);
    let sun = kinds
        .iter()
        .copied()
        .find(|k| k.lights == Lights::Sun && k.shadows == Some(ShadowSampling::Vsm))
        .expect("a sun with VSM shadows");
    // Each kind beside a shadowed sun, three at a time (at most one walk in
    // workgroup memory each), so every kind is composed as set 1 or 2.
    let mut composer = ShaderComposer::new().expect("libraries compose");
    let (shared, alone): (Vec<_>, Vec<_>) = kinds.iter().copied().partition(shares_memory);
    let mut groups: Vec<Vec<CookTorranceKey>> = Vec::new();
    let mut alone = alone.into_iter();
    for walk in shared {
        groups.push(vec![sun, walk, alone.next().unwrap_or(sun)]);
    }
    let rest: Vec<_> = alone.collect();
    for pair in rest.chunks(2) {
        groups.push([&[sun][..], pair].concat());
    }
    let mut failures = Vec::new();
    for keys in &groups {
        let defs = switches(&shader_keys(keys));
        if let Err(e) = compose(&mut composer, keys.len(), &defs, false) {
            failures.push(format!("{defs:?}: {e}"));
        }
    }
    assert!(failures.is_empty(), "{}", failures.join("\n\n"));
}

#[test]
fn the_material_switches_are_shared_and_four_sets_compose() {
    let kinds = set_kinds();
    let with_materials = |mut k: CookTorranceKey| {
        k.shading = Shading::Brdf {
            energy_compensation: true,
            materials: Some(crate::lighting::cook_torrance_key::BrdfMaterials {
                reads: crate::lighting::cook_torrance_key::MaterialReads { textures: true },
                fake_sss: true,
                clearcoat: true,
                anisotropy: true,
                iridescence: true,
                sheen: true,
            }),
        };
        k.surface_target = true;
        k
    };
    let pick = |lights, shadows| set_kind(&kinds, lights, shadows);
    let keys = [
        pick(Lights::Sun, Some(ShadowSampling::Pcss)),
        pick(
            Lights::Spot {
                walk: Walk::Naive,
                textured: true,
            },
            Some(ShadowSampling::Pcf),
        ),
        pick(Lights::Point(Walk::Clustered), None),
        pick(Lights::Point(Walk::PerPixel), Some(ShadowSampling::Raw)),
    ]
    .map(with_materials);
    let defs = switches(&shader_keys(&keys));
    // The shared switches once, unrenamed; each set's renamed for its place.
    for shared in [
        "MATERIALS",
        "MATERIAL_TEXTURES",
        "FAKE_SSS",
        "CLEARCOAT",
        "ANISOTROPY",
        "IRIDESCENCE",
        "SHEEN",
        "SURFACE_TARGET",
    ] {
        assert_eq!(defs.iter().filter(|d| *d == shared).count(), 1, "{shared}");
    }
    for set in [
        "S0_LIGHT_SUN",
        "S0_SHADOW_PCSS",
        "S1_LIGHT_SPOT",
        "S1_SPOT_TEXTURE",
        "S1_SHADOW_PCF",
        "S2_CLUSTERED",
        "S3_PER_PIXEL",
        "S3_SHADOWS",
    ] {
        assert!(defs.iter().any(|d| d == set), "{set} in {defs:?}");
    }
    assert!(
        !defs.iter().any(|d| d == "SHADOWS" || d == "LIGHT_SUN"),
        "{defs:?}"
    );
    let mut composer = ShaderComposer::new().expect("libraries compose");
    let module = compose(&mut composer, keys.len(), &defs, false).expect("four sets compose");
    // Each set binds its own outputs, by its own names.
    let reflection = crate::shaders::reflection_of(&module, "main").expect("reflects");
    for i in 0..4 {
        for name in ["out_diffuse", "out_specular", "out_sss", "lights", "camera"] {
            let renamed = source::set_binding(i, name);
            assert!(reflection.position(&renamed).is_some(), "{renamed}");
        }
    }
    assert!(reflection.position("shadow_maps_s0").is_some());
    assert!(reflection.position("spot_textures_s1").is_some());
    assert!(reflection.position("indices_s2").is_some());
    assert!(
        reflection.position("indices_s0").is_none(),
        "a sun walks no froxels"
    );
}

#[test]
fn summed_sets_write_their_sums_and_only_the_targets_asked_for() {
    let kinds = set_kinds();
    let pick = |lights, shadows| set_kind(&kinds, lights, shadows);
    // emeshe-frame.ron's three sets.
    let keys = [
        pick(Lights::Sun, Some(ShadowSampling::Pcss)),
        pick(
            Lights::Spot {
                walk: Walk::Naive,
                textured: false,
            },
            Some(ShadowSampling::Pcss),
        ),
        pick(Lights::Point(Walk::Clustered), None),
    ];
    let used = |module: &naga::Module, name: &str| {
        let reflection = crate::shaders::reflection_of(module, "main").expect("reflects");
        reflection
            .position(name)
            .is_some_and(|i| reflection.vars()[i].used)
    };
    let mut composer = ShaderComposer::new().expect("libraries compose");
    // The sums alone (a CompositeLight reads them, nothing reads the sets'
    // own), then the sums and set 1's specular (something else reads it),
    // then every set's own and no sums (no CompositeLight of these sets).
    let mut some = Written {
        sums: [true, true],
        ..Written::default()
    };
    some.sets[1][1] = true;
    let every = Written {
        sets: [[true, true, false]; MAX_SETS],
        sums: [false, false],
    };
    for written in [
        Written {
            sums: [true, true],
            ..Written::default()
        },
        some,
        every,
    ] {
        let mut defs = switches(&shader_keys(&keys));
        defs.extend(summed_switches(keys.len(), &written));
        let module = compose(&mut composer, keys.len(), &defs, true)
            .unwrap_or_else(|e| panic!("{defs:?}: {e}"));
        for (var, on) in ["sum_diffuse", "sum_specular"].iter().zip(written.sums) {
            assert_eq!(used(&module, var), on, "{var} with {defs:?}");
        }
        for i in 0..keys.len() {
            for (k, var) in ["out_diffuse", "out_specular"].iter().enumerate() {
                let renamed = source::set_binding(i, var);
                assert_eq!(
                    used(&module, &renamed),
                    written.sets[i][k],
                    "{renamed} with {defs:?}"
                );
            }
            // The G-buffer is read once, by the entry, not by each set.
            for var in ["color", "normals", "depth"] {
                let renamed = source::set_binding(i, var);
                assert!(!used(&module, &renamed), "{renamed} with {defs:?}");
            }
        }
        for var in ["gbuffer_color", "gbuffer_normals", "gbuffer_depth"] {
            assert!(used(&module, var), "{var} with {defs:?}");
        }
    }
}

/// `auto`, the default, fuses on a GPU and never on a CPU adapter
/// (lavapipe crashed under load with fusion forced).
#[test]
fn light_sets_fuse_by_default_on_a_gpu_only() {
    use crate::adapter_class::AdapterClass;
    assert_eq!(LightFusion::default(), LightFusion::Auto);
    assert!(LightFusion::default().fuses_on(AdapterClass::Gpu));
    assert!(!LightFusion::default().fuses_on(AdapterClass::Cpu));
    assert!(LightFusion::Fused.fuses_on(AdapterClass::Cpu));
    assert!(!LightFusion::Separate.fuses_on(AdapterClass::Gpu));
}
