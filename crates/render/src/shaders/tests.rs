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
    let mut composer = ShaderComposer::new().expect("libraries compose");
    let err = composer
        .compose(&ShaderKey::new("gbuffer/view.wgsl", ["DEPTH", "UV"]))
        .expect_err("refused");
    assert!(err.to_string().contains("set at most one"), "{err}");
}

#[test]
fn a_feature_without_what_it_needs_is_refused_and_never_enumerated() {
    let mut composer = ShaderComposer::new().expect("libraries compose");
    let err = composer
        .compose(&ShaderKey::new("lighting/composite.wgsl", ["LIGHTS_3"]))
        .expect_err("refused");
    assert!(
        err.to_string().contains("`LIGHTS_3` needs `LIGHTS_2`"),
        "{err}"
    );
    let composite: Vec<_> = all_permutations()
        .into_iter()
        .filter(|k| k.path == "lighting/composite.wgsl")
        .collect();
    // Light pairs with the SSS terms they allow (2 + 4 + 8 + 16), times
    // GI (2), times the surface target (2), times the 56 ways of AO
    // (none, AO, per material), emission (none, plain, textured),
    // reflection (2), matcap (none, built-in, textured) and the material
    // library (forced on when one of them reads it, free otherwise:
    // 52 + 2 x 2): 6,720 of the 2^17 subsets.
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
