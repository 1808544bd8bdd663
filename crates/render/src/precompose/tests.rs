use super::*;
use crate::post::copy_key::CopyKey;
use crate::shaders::{GeneratedKey, Permutation, ShaderCache};

/// A few permutations with features, and one without.
fn some_keys() -> Vec<ShaderKey> {
    let mut keys: Vec<ShaderKey> = crate::permutations::all_permutations()
        .into_iter()
        .filter(|k| k.features.len() >= 2)
        .take(4)
        .collect();
    keys.push(CopyKey.key());
    keys
}

#[test]
fn a_list_reads_back_as_the_permutations_it_was_written_from() {
    let keys = some_keys();
    let list = parse(&to_text(&keys, &[])).expect("a list");
    assert_eq!(list.keys, keys);
    assert_eq!(list.unknown, 0);
}

#[test]
fn entries_this_build_lacks_are_skipped_and_a_damaged_list_is_an_error_saying_where() {
    let text = format!(
        "{HEADER}\npost/copy.wgsl\t\nlighting/gone.wgsl\t\npost/copy.wgsl\tNOT_A_FEATURE\n"
    );
    let list = parse(&text).expect("a list");
    assert_eq!(list.keys, vec![CopyKey.key()]);
    assert_eq!(list.unknown, 2);
    let bad_header = parse("spreadlight permutations 0\npost/copy.wgsl\t\n").unwrap_err();
    assert!(bad_header.contains("first line"), "{bad_header}");
    let bad_line = parse(&format!("{HEADER}\npost/copy.wgsl\n")).unwrap_err();
    assert!(bad_line.contains("line 2"), "{bad_line}");
}

#[test]
fn remembered_lists_read_back_and_a_damaged_file_names_itself() {
    let dir = tempfile::tempdir().expect("temp dir");
    let path = dir.path().join("permutations").join("list.txt");
    assert!(matches!(read(&path), Ok(None)), "no list: a first run");
    let keys = some_keys();
    remember(&path, &keys, &[]).expect("written");
    let read_back = read(&path).expect("readable").expect("there");
    assert_eq!(read_back.keys, keys);
    std::fs::write(&path, [0xff, 0xfe, 0x00]).expect("damaged");
    let error = read(&path).unwrap_err();
    assert!(error.contains(&path.display().to_string()), "{error}");
    std::fs::write(&path, "garbage").expect("damaged");
    assert!(read(&path).unwrap_err().contains("first line"));
}

#[test]
fn what_the_threads_compose_a_renderer_finds_without_a_composer_of_its_own() {
    let keys = vec![CopyKey.key()];
    assert_eq!(compose_all(&keys, &[], 2), 1);
    let mut cache = ShaderCache::lazy();
    let reflection = cache.reflection(&keys[0], "main").expect("reflects");
    assert!(!reflection.vars().is_empty());
    let times = cache.compile_times;
    assert_eq!((times.ready, times.composed), (1, 0), "{times:?}");
    assert_eq!(times.libraries, Duration::ZERO, "no composer was made");
    // A permutation nobody composed ahead is composed by the cache itself,
    // which makes its composer then.
    let other = crate::permutations::all_permutations()
        .into_iter()
        .find(|k| k.path() == "post/tonemap.wgsl")
        .expect("a tonemap permutation");
    let composer = ShaderComposer::from_dir(Path::new("/nonexistent")).expect("libraries");
    let mut fresh = ShaderCache::new(composer);
    fresh.reflection(&other, "main").expect("reflects");
    assert_eq!(fresh.compile_times.composed, 1);
}

#[test]
fn threads_started_compose_the_list_and_say_so() {
    let keys = some_keys();
    let done = start(keys.clone(), Vec::new(), 3).finish();
    assert_eq!(done.listed, keys.len());
    assert_eq!(done.composed, keys.len());
    assert_eq!(done.threads, 3);
    for key in &keys {
        assert!(crate::shaders::is_composed(key), "{key:?}");
    }
}

#[test]
fn pipelines_read_back_in_their_order_their_permutations_first_and_an_old_list_still_reads() {
    let keys = some_keys();
    let copy = CopyKey.key();
    let pipelines = [
        PipelineId::entry(&keys[1], "main"),
        PipelineId::entry(&copy, "main"),
    ];
    let list = parse(&to_text(&keys, &pipelines)).expect("a list");
    assert_eq!(list.pipelines, pipelines);
    // Composed in the order the frame wants them, each once.
    assert_eq!(list.keys[..2], [keys[1].clone(), copy]);
    assert_eq!(list.keys.len(), keys.len());
    // A list of a build before pipelines were listed: its permutations.
    let old = format!("{HEADER_1}\npost/copy.wgsl\t\n");
    let old = parse(&old).expect("an old list");
    assert_eq!((old.keys.len(), old.pipelines.len()), (1, 0));
    // One before generated shaders were listed.
    let old = parse(&format!("{HEADER_2}\npost/copy.wgsl\t\tmain\n")).expect("an old list");
    assert_eq!((old.keys.len(), old.pipelines.len()), (1, 1));
    let bad = parse(&format!("{HEADER}\npost/copy.wgsl\t\tma in\n")).unwrap_err();
    assert!(
        bad.contains("line 2") && bad.contains("entry point"),
        "{bad}"
    );
}

/// Two CookTorrance permutations of different lights: a fused pair's parts.
fn light_set_parts() -> Vec<ShaderKey> {
    let mut parts: Vec<ShaderKey> = Vec::new();
    for light in ["LIGHT_SUN", "LIGHT_SPOT"] {
        let part = crate::permutations::all_permutations()
            .into_iter()
            .filter(|k| k.path() == "lighting/cook_torrance.wgsl" && k.features.contains(light))
            .min_by_key(|k| k.features.len())
            .expect("a permutation of the light");
        parts.push(part);
    }
    parts
}

/// A generated shader's line reads back as the same key (its generator
/// and parts in order), counts among the pipelines and the generated
/// shaders to compose; one naming a generator or a part this build lacks is
/// skipped as unknown, and the rest of the list still reads.
#[test]
fn generated_shaders_read_back_and_unknown_generators_or_parts_are_skipped() {
    let copy = CopyKey.key();
    let fused = GeneratedKey {
        generator: &crate::lighting::light_sets::GENERATOR,
        parts: light_set_parts(),
        options: Vec::new(),
    };
    // The summed variant: the same parts, the generator's own switches.
    let summed = GeneratedKey {
        options: vec![
            "LIGHT_SUM".to_owned(),
            "S0_OUT_SSS".to_owned(),
            "SUM_DIFFUSE".to_owned(),
        ],
        ..fused.clone()
    };
    let pipelines = [
        PipelineId::entry(&copy, "main"),
        PipelineId::Generated(fused.clone()),
        PipelineId::Generated(summed.clone()),
    ];
    let text = to_text(std::slice::from_ref(&copy), &pipelines);
    assert!(
        text.contains("\ngenerated\tlight_sets\t"),
        "a line of its own: {text}"
    );
    let list = parse(&text).expect("a list");
    assert_eq!(list.pipelines, pipelines);
    assert_eq!(list.generated, [fused.clone(), summed.clone()]);
    assert_eq!((list.keys.len(), list.unknown), (1, 0));
    let stale = format!(
        "{text}generated\tno_such_generator\tLIGHT_SUN\tLIGHT_SPOT\n\
         generated\tlight_sets\tLIGHT_SUN\tNOT_A_FEATURE\n"
    );
    let list = parse(&stale).expect("a list");
    assert_eq!(list.pipelines, pipelines);
    assert_eq!(list.unknown, 2);
}

/// The threads compose a list's generated shader ahead: a renderer's
/// look-up finds it composed, as it finds a permutation.
#[test]
fn threads_compose_a_generated_shader_and_its_generator_refuses_a_lone_part() {
    let parts = light_set_parts();
    let fused = GeneratedKey {
        generator: &crate::lighting::light_sets::GENERATOR,
        parts: parts.clone(),
        options: Vec::new(),
    };
    let lone = GeneratedKey {
        generator: &crate::lighting::light_sets::GENERATOR,
        parts: parts[..1].to_vec(),
        options: Vec::new(),
    };
    let done = start(Vec::new(), vec![fused.clone(), lone.clone()], 2).finish();
    assert_eq!((done.listed, done.composed), (2, 1), "{done:?}");
    let (label, module) =
        crate::shaders::embedded_generated_or_wait(&fused).expect("composed ahead");
    assert!(label.contains("light_sets x2"), "{label}");
    assert!(module.entry_points.iter().any(|e| e.name == "main"));
    assert!(crate::shaders::embedded_generated_or_wait(&lone).is_none());
}
