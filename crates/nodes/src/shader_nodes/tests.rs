//! Shader nodes on the test GPU: pins from annotations, hot reload, errors
//! at file:line:col with the last good version still rendering, repeats,
//! skips, permutations and culling in the frame report, persistent targets,
//! and the eye-adaptation example against the built-in EyeAdaptation.

use std::path::Path;
use std::sync::Arc;

use spreadlight_graph::{Color, FrameClock, NodeDoc, Patch, PinType, Registry, Runtime, Spread};
use spreadlight_render::readback::ImageF32;
use spreadlight_render::renderer::test_renderer;
use spreadlight_render::{FrameReport, Renderer};

use super::{EXAMPLES, ShaderLibrary, ShaderType, type_name};
use crate::output::RenderedImages;

const SIZE: (u32, u32) = (32, 18);

pub(super) struct Rig {
    pub(super) rt: Runtime,
    images: Arc<RenderedImages>,
    renderer: Arc<Renderer>,
    frame: u64,
}

impl Rig {
    pub(super) fn new(registry: Registry, patch: &Patch) -> Rig {
        let mut rt = Runtime::new(registry);
        let renderer = test_renderer();
        renderer.set_output_size(SIZE);
        rt.provide(renderer.clone());
        // The example patches' folder, so their modules (patches/modules/) resolve.
        rt.provide(Arc::new(spreadlight_graph::PatchDir(
            Path::new(env!("CARGO_MANIFEST_DIR")).join("../../patches"),
        )));
        let images = Arc::new(RenderedImages::default());
        rt.provide(images.clone());
        let problems = rt.load(patch).to_vec();
        assert!(problems.is_empty(), "{problems:?}");
        Rig {
            rt,
            images,
            renderer,
            frame: 0,
        }
    }

    /// Evaluate one frame; the report of the last frame graph it ran.
    pub(super) fn step(&mut self) -> FrameReport {
        self.rt.evaluate(FrameClock::fixed(self.frame, 60.0));
        self.frame += 1;
        self.renderer.last_report()
    }

    /// Render at `size` from the next step on (the default is tiny).
    pub(super) fn resize(&self, size: (u32, u32)) {
        self.renderer.set_output_size(size);
    }

    pub(super) fn image(&self, name: &str) -> ImageF32 {
        self.images
            .get(name)
            .unwrap_or_else(|| panic!("no image `{name}`"))
            .0
    }

    pub(super) fn errors(&self) -> Vec<String> {
        self.rt
            .node_errors()
            .map(|(id, e)| format!("{id}: {e}"))
            .collect()
    }
}

pub(super) fn output(id: u32, name: &str) -> NodeDoc {
    NodeDoc::new(id, "Output")
        .with("Name", vec![name.to_owned()])
        .with("Write", vec![false])
}

pub(super) fn noise_into(patch: &mut Patch, id: u32) {
    patch.add(NodeDoc::new(id, "Noise (Shader)").with("Speed", vec![0.0f32]));
}

pub(super) fn mean(image: &ImageF32) -> [f32; 4] {
    let n = image.pixels.len() as f32;
    let mut m = [0.0; 4];
    for p in &image.pixels {
        for c in 0..4 {
            m[c] += p[c] / n;
        }
    }
    m
}

const TINT_V1: &str = "// @category Filter
// @help Multiplies by a colour.
// @input source \"Texture\"
// @target tinted temporary rgba16float scale=1
// @pass tint -> tinted
struct Params {
    // @pin \"Tint\" color default=1,0.5,0.25,1
    tint: vec4<f32>,
    gain: f32, // @pin default=1 min=0 max=4
    size: vec2<f32>,
}
@group(0) @binding(0) var<uniform> params: Params;
@group(0) @binding(1) var source: texture_2d<f32>;
@group(0) @binding(2) var tinted: texture_storage_2d<rgba16float, write>;
@compute @workgroup_size(8, 8)
fn tint(@builtin(global_invocation_id) id: vec3<u32>) {
    if (f32(id.x) >= params.size.x || f32(id.y) >= params.size.y) { return; }
    let c = textureLoad(source, id.xy, 0);
    textureStore(tinted, id.xy, vec4<f32>(c.rgb * params.tint.rgb * params.gain, 1.0));
}
";

fn write(dir: &Path, text: &str) {
    std::fs::write(dir.join("tint.wgsl"), text).expect("write shader");
}

/// A folder with tint.wgsl, a library over it, and a patch: noise -> Tint -> Output.
fn tint_rig(text: &str) -> (tempfile::TempDir, ShaderLibrary, Registry, Patch) {
    let dir = tempfile::tempdir().expect("tempdir");
    write(dir.path(), text);
    let mut library = ShaderLibrary::new(vec![dir.path().to_owned()]);
    let mut registry = crate::registry();
    let changes = library.poll(&mut registry);
    assert_eq!(changes.updated, ["Tint (Shader)"]);
    let mut patch = Patch::default();
    noise_into(&mut patch, 1);
    patch.add(NodeDoc::new(2, "Tint (Shader)").with("Gain", vec![0.5f32]));
    patch.add(output(3, "out"));
    patch.link(1, "Texture", 2, "Texture");
    patch.link(2, "Texture", 3, "Texture");
    (dir, library, registry, patch)
}

#[test]
fn pins_come_from_the_uniform_block_with_names_defaults_ranges_and_colours() {
    let ty = ShaderType::load("Tint (Shader)", "tint.wgsl", TINT_V1).expect("compiles");
    let def = ty.node_def(None);
    assert_eq!(&*def.category, "Shader/Filter");
    let pins: Vec<(&str, PinType)> = def.inputs.iter().map(|p| (&*p.name, p.ty)).collect();
    assert_eq!(
        pins,
        [
            (
                "Texture",
                PinType::Resource(spreadlight_graph::ResourceKind::Texture)
            ),
            ("Tint", PinType::Color),
            ("Gain", PinType::Float),
        ]
    );
    let default_of = |def: &spreadlight_graph::NodeDef, name: &str| {
        def.inputs
            .iter()
            .find(|p| p.name == name)
            .map(|p| p.default.clone())
            .unwrap_or_else(|| panic!("no input `{name}`"))
    };
    assert_eq!(
        default_of(&def, "Tint"),
        Spread::Color(vec![Color::rgba(1.0, 0.5, 0.25, 1.0)])
    );
    assert_eq!(default_of(&def, "Gain"), Spread::Float(vec![1.0]));
    let gain = &ty.params()[1];
    assert_eq!((gain.min, gain.max), (Some(0.0), Some(4.0)));
    assert!(def.help.contains("Gain 0..4"), "{}", def.help);
    // Built-ins (size) are not pins; the noise example's Int and switch are.
    let noise = crate::registry();
    let noise = noise.get("Noise (Shader)").expect("shipped");
    let names: Vec<&str> = noise.inputs.iter().map(|p| &*p.name).collect();
    assert_eq!(
        names,
        ["Scale", "Octaves", "Speed", "Color A", "Color B", "Ridged"]
    );
    assert_eq!(default_of(noise, "Octaves"), Spread::Int(vec![4]));
}

#[test]
fn hot_reload_keeps_links_and_values_and_a_broken_file_keeps_the_last_good_version() {
    let (dir, mut library, mut registry, patch) = tint_rig(TINT_V1);
    let mut rig = Rig::new(registry.clone(), &patch);
    rig.step();
    assert!(rig.errors().is_empty(), "{:?}", rig.errors());
    let before = mean(&rig.image("out"));
    // Gain 0.5 (the patch's value) times tint (1, 0.5, 0.25).
    assert!((before[1] / before[0] - 0.5).abs() < 0.02, "{before:?}");

    // Saved: the blue channel now comes out inverted; a new pin appears.
    let v2 = TINT_V1
        .replace(
            "c.rgb * params.tint.rgb * params.gain",
            "vec3<f32>(c.rg * params.tint.rg * params.gain, params.extra)",
        )
        .replace(
            "    size: vec2<f32>,",
            "    extra: f32, // @pin default=0.75\n    size: vec2<f32>,",
        );
    // A different length, so the change is seen even within the file system's time resolution.
    write(dir.path(), &v2);
    let changes = library.poll(&mut registry);
    assert_eq!(changes.updated, ["Tint (Shader)"]);
    rig.rt.set_registry(registry.clone());
    assert!(rig.rt.load(&patch).is_empty());
    rig.step();
    assert!(rig.errors().is_empty(), "{:?}", rig.errors());
    let after = mean(&rig.image("out"));
    // Still linked to the noise, still at Gain 0.5; blue is the new pin's default.
    assert!((after[0] - before[0]).abs() < 1e-3 && (after[1] - before[1]).abs() < 1e-3);
    assert!((after[2] - 0.75).abs() < 1e-3, "{after:?}");

    // Each documented class of broken shader (docs/shader-nodes.md, "Hot
    // reload and errors"): an error at file:line:col on the node, once, and
    // the last good version renders.
    let file = dir.path().join("tint.wgsl").display().to_string();
    for (text, at, what) in broken_versions(&v2) {
        write(dir.path(), &format!("{text}\n"));
        library.poll(&mut registry);
        let error = library.errors()["Tint (Shader)"].to_string();
        assert!(
            error.starts_with(&format!("{file}:{at}: ")),
            "{what}: {error}"
        );
        assert!(error.contains(what), "{error}");
        rig.rt.set_registry(registry.clone());
        assert!(rig.rt.load(&patch).is_empty());
        rig.step();
        let errors = rig.errors();
        assert!(
            errors.len() == 1 && errors[0].contains(&error),
            "{errors:?}"
        );
        let still = mean(&rig.image("out"));
        assert!(
            (still[2] - 0.75).abs() < 1e-3,
            "{what}: the last good version renders: {still:?}"
        );
        // Put the good version back (different length from the broken one).
        write(dir.path(), &v2);
        library.poll(&mut registry);
    }
    assert!(library.errors().is_empty());
}

/// `good` (the tint shader with its `extra` pin) broken once per documented
/// class of error: (text, line:col, what the message says).
fn broken_versions(good: &str) -> Vec<(String, &'static str, &'static str)> {
    let swap = |from: &str, to: &str| {
        assert!(good.contains(from), "`{from}` is in the shader");
        good.replacen(from, to, 1)
    };
    vec![
        // WGSL syntax, at the token.
        (
            swap("let c = textureLoad", "let c = = textureLoad"),
            "19:13",
            "WGSL syntax",
        ),
        // A type error, at the value whose type is wrong.
        (
            swap("let c = textureLoad", "let c: vec3<f32> = textureLoad"),
            "19:24",
            "WGSL type: the type of `c` is expected to be `vec3<f32>`",
        ),
        // naga's validation, at the expression (vec3 times vec2), not the statement.
        (
            swap("c.rg * params.tint.rg", "c.rgb * params.tint.rg"),
            "20:53",
            "validation",
        ),
        // A binding the annotations do not describe, at its `var`.
        (
            swap(
                "@group(0) @binding(1) var source",
                "@group(0) @binding(3) var stray: texture_2d<f32>;\n@group(0) @binding(1) var source",
            ),
            "14:23",
            "`stray` is not described by the annotations",
        ),
        // An unknown target, entry point or lifetime, at the annotation.
        (
            swap("// @pass tint -> tinted", "// @pass tint -> nowhere"),
            "5:4",
            "unknown target `nowhere`",
        ),
        (
            swap("// @pass tint -> tinted", "// @pass tin -> tinted"),
            "5:4",
            "no entry point `tin`",
        ),
        (
            swap("temporary rgba16float", "forever rgba16float"),
            "4:4",
            "unknown lifetime `forever`",
        ),
        // An entry point that is no compute shader.
        (
            swap("// @pass tint -> tinted", "// @pass shade -> tinted")
                + "@fragment\nfn shade() -> @location(0) vec4<f32> { return vec4<f32>(1.0); }\n",
            "5:4",
            "entry point `shade` is not a compute shader",
        ),
        // A pass that never writes its destination.
        (
            swap(
                "// @pass tint -> tinted",
                "// @target spare temporary rgba16float scale=1\n// @pass tint -> tinted, spare",
            ),
            "6:4",
            "entry point `tint` never writes destination `spare`",
        ),
        // A storage texture of another format than its target's, at its `var`.
        (
            swap(
                "tinted: texture_storage_2d<rgba16float",
                "tinted: texture_storage_2d<rgba32float",
            ),
            "15:23",
            "storage texture `tinted` is Rgba32Float but its `@target` says Rgba16Float",
        ),
        // A pin annotation that does not fit its field, or itself, at the annotation.
        (
            swap(
                "extra: f32, // @pin default",
                "extra: f32, // @pin color default",
            ),
            "10:20",
            "field `extra` (f32): `color` is for vec4<f32>",
        ),
        (
            swap(
                "// @pin default=1 min=0 max=4",
                "// @pin default=1 min=4 max=0",
            ),
            "9:34",
            "`min=4` is above `max=0`",
        ),
        // An `#ifdef` without `#endif`, at the `#ifdef`.
        (
            swap("@compute", "#ifdef NEVER\n@compute"),
            "16:1",
            "`#ifdef` without `#endif`",
        ),
    ]
}

/// A file that has never compiled gives a node without pins: it shows the
/// cause once (not a problem per stored value and link), and the document's
/// values and links come back when the file compiles.
#[test]
fn a_file_that_never_compiled_reports_once_and_keeps_values_and_links_for_the_fix() {
    let broken = TINT_V1.replace("let c = textureLoad", "lett c = textureLoad");
    let (dir, mut library, mut registry, mut patch) = tint_rig(&broken);
    patch.add(output(4, "noise"));
    patch.link(1, "Texture", 4, "Texture");
    assert_eq!(library.errors().len(), 1);
    let def = registry.get("Tint (Shader)").expect("registered");
    assert!(def.inputs.is_empty() && def.pins_unknown, "{def:?}");
    // No problem for `Gain` or either link (Rig::new asserts none); the node
    // shows the cause alone (its Output, given nothing, says so on its own).
    let mut rig = Rig::new(registry.clone(), &patch);
    rig.step();
    let errors: Vec<String> = rig
        .errors()
        .into_iter()
        .filter(|e| e.starts_with("#2:"))
        .collect();
    assert_eq!(errors.len(), 1, "{errors:?}");
    assert!(
        errors[0].starts_with("#2: ") && errors[0].contains("tint.wgsl:18:10: WGSL syntax"),
        "{errors:?}"
    );

    write(dir.path(), TINT_V1);
    library.poll(&mut registry);
    rig.rt.set_registry(registry.clone());
    assert!(rig.rt.load(&patch).is_empty());
    rig.step();
    assert!(rig.errors().is_empty(), "{:?}", rig.errors());
    // Linked to the noise again, at the stored Gain 0.5: red is half the
    // noise's (the tint's red is 1).
    let (out, noise) = (mean(&rig.image("out")), mean(&rig.image("noise")));
    assert!(
        noise[0] > 0.05 && (out[0] / noise[0] - 0.5).abs() < 2e-3,
        "{out:?} from {noise:?}"
    );

    // A broken file that overrides a shipped example keeps the example's pins.
    std::fs::write(dir.path().join("blur.wgsl"), "fn broken(\n").expect("write");
    library.poll(&mut registry);
    let blur = registry.get("Blur (Shader)").expect("registered");
    let pins: Vec<&str> = blur.inputs.iter().map(|p| &*p.name).collect();
    assert_eq!(pins, ["Texture", "Radius"], "the shipped version stays");
    let error = library.errors()["Blur (Shader)"].to_string();
    assert!(
        error.contains("blur.wgsl:") && error.contains("WGSL syntax"),
        "{error}"
    );
}

/// noise -> `node` (its pin `from` read) -> Output "out": the first frame's report.
fn through(node: NodeDoc, from: &str) -> (Rig, FrameReport) {
    let mut patch = Patch::default();
    noise_into(&mut patch, 1);
    patch.add(node);
    patch.add(output(3, "out"));
    patch.link(1, "Texture", 2, "Texture");
    patch.link(2, from, 3, "Texture");
    let mut rig = Rig::new(crate::registry(), &patch);
    let report = rig.step();
    assert!(rig.errors().is_empty(), "{:?}", rig.errors());
    assert!(report.errors.is_empty(), "{:?}", report.errors);
    (rig, report)
}

#[test]
fn a_repeated_pass_runs_until_its_target_is_small_enough_and_is_counted() {
    let (rig, report) = through(NodeDoc::new(2, "EyeAdaptationChain (Shader)"), "Texture");
    // 32x18: log-luminance at 16x9, then 8x5, 4x3, 2x2, 1x1: four iterations, three repeats.
    assert_eq!(
        report.counter("shader node repeats"),
        3,
        "{:?}",
        report.counters
    );
    let downsamples = report
        .passes
        .iter()
        .filter(|p| {
            p.step
                .as_deref()
                .is_some_and(|s| s.starts_with("downsample"))
        })
        .count();
    assert_eq!(downsamples, 4);
    // The chain's 1x1 result, which the Output stretches to the output size: one value everywhere.
    assert_eq!(rig.images.source_size("out"), Some((1, 1)));
    let image = rig.image("out");
    assert_eq!((image.width, image.height), SIZE);
    assert!(image.pixels.iter().all(|p| *p == image.pixels[0]));
}

#[test]
fn a_skipped_pass_passes_its_input_on_and_is_counted() {
    let (rig, report) = through(
        NodeDoc::new(2, "EdgeDetect (Shader)").with("Bypass", vec![true]),
        "Texture",
    );
    assert_eq!(report.counter("shader node passes skipped"), 1);
    assert!(
        !report
            .passes
            .iter()
            .any(|p| p.step.as_deref() == Some("sobel"))
    );
    // The noise itself (grey levels: equal channels), not edges.
    let m = mean(&rig.image("out"));
    assert!(m[0] > 0.2 && (m[0] - m[1]).abs() < 1e-3, "{m:?}");
}

#[test]
fn a_shader_node_binds_last_frames_uniform_and_groups_again_beside_another_output() {
    // Two Outputs, so two frame graphs a frame; both read the noise, which
    // is made again every frame (its uniform holds the time).
    let mut patch = Patch::default();
    noise_into(&mut patch, 1);
    patch.add(NodeDoc::new(2, "EdgeDetect (Shader)"));
    patch.add(output(3, "edges"));
    patch.add(output(4, "noise"));
    patch.link(1, "Texture", 2, "Texture");
    patch.link(2, "Texture", 3, "Texture");
    patch.link(1, "Texture", 4, "Texture");
    let mut rig = Rig::new(crate::registry(), &patch);
    rig.step();
    let first = mean(&rig.image("edges"));
    for _ in 0..3 {
        rig.step();
    }
    let report = rig.step();
    assert!(report.errors.is_empty(), "{:?}", report.errors);
    let shader_passes = (report.passes.iter())
        .filter(|p| p.kind.ends_with("(Shader)"))
        .count() as u64;
    assert!(shader_passes >= 1, "{:?}", report.passes);
    // One group a pass, last frame's; the same views; each uniform either
    // unchanged (not written) or written in place.
    let kept = (
        report.counter("bind groups kept"),
        report.counter("texture views created"),
        report.counter("uniform uploads") + report.counter("uniform uploads skipped"),
    );
    assert_eq!(
        kept,
        (shader_passes, 0, shader_passes),
        "{:?}",
        report.counters
    );
    // A pin changed: its uniform is written, and the picture follows.
    set(
        &mut rig,
        &mut patch,
        2,
        "Strength",
        Spread::Float(vec![0.0]),
    );
    rig.step();
    let dark = mean(&rig.image("edges"));
    assert!(
        first[0] > 1e-3 && dark[0].abs() < 1e-6,
        "{first:?} {dark:?}"
    );
    assert!(rig.errors().is_empty(), "{:?}", rig.errors());
}

#[test]
fn each_used_permutation_compiles_once_and_is_counted() {
    // Three slices, two inverted: the default permutation and INVERT.
    let (mut rig, report) = through(
        NodeDoc::new(2, "EdgeDetect (Shader)").with("Invert", vec![false, true, true]),
        "Texture",
    );
    assert_eq!(report.counter("shader node permutations compiled"), 1);
    assert_eq!(
        report
            .passes
            .iter()
            .filter(|p| p.step.as_deref() == Some("sobel"))
            .count(),
        1
    );
    rig.rt.invalidate_all();
    let again = rig.step();
    assert_eq!(again.counter("shader node permutations compiled"), 0);
}

#[test]
fn passes_whose_targets_nothing_reads_are_culled() {
    // Only the blur's half-size output is read: its vertical pass is culled.
    let (rig, report) = through(NodeDoc::new(2, "Blur (Shader)"), "Half");
    assert!(
        report.culled.iter().any(|p| p.contains("vertical")),
        "{:?}",
        report.culled
    );
    assert_eq!(
        rig.images.source_size("out"),
        Some((SIZE.0 / 2, SIZE.1 / 2))
    );
    assert_eq!(
        rig.image("out").width,
        SIZE.0,
        "stretched to the output size"
    );
}

#[test]
fn every_example_compiles_in_every_permutation() {
    for (stem, path, source) in EXAMPLES {
        let ty = ShaderType::load(&type_name(stem), path, source).unwrap_or_else(|e| panic!("{e}"));
        let switches: Vec<String> = ty.notes.switches.iter().map(|s| s.define.clone()).collect();
        // Every option of every enum, with every set of switches.
        let mut choices: Vec<Vec<String>> = vec![Vec::new()];
        for e in &ty.notes.enums {
            choices = choices
                .iter()
                .flat_map(|c| {
                    (0..e.options.len()).map(move |i| {
                        let mut c = c.clone();
                        c.extend(e.define(i));
                        c
                    })
                })
                .collect();
        }
        for chosen in &choices {
            for mask in 0..(1u32 << switches.len()) {
                let defines = (0..switches.len())
                    .filter(|i| mask & (1 << i) != 0)
                    .map(|i| switches[i].clone())
                    .chain(chosen.iter().cloned())
                    .collect();
                ty.program(&defines).unwrap_or_else(|e| panic!("{e}"));
            }
        }
    }
}

pub(super) fn set(rig: &mut Rig, patch: &mut Patch, node: u32, pin: &str, value: Spread) {
    let doc = patch
        .nodes
        .iter_mut()
        .find(|n| n.id.0 == node)
        .expect("node");
    doc.values.insert(pin.to_owned(), value);
    assert!(rig.rt.load(patch).is_empty());
}

fn grey(v: f32) -> Spread {
    Spread::Color(vec![Color::rgba(v, v, v, 1.0)])
}

#[test]
fn a_persistent_target_survives_frames_and_resets_on_a_cut() {
    let mut patch = Patch::default();
    noise_into(&mut patch, 1);
    patch.add(NodeDoc::new(2, "Feedback (Shader)").with("Decay", vec![0.5f32]));
    patch.add(output(3, "out"));
    patch.link(1, "Texture", 2, "Texture");
    patch.link(2, "Texture", 3, "Texture");
    let mut rig = Rig::new(crate::registry(), &patch);
    rig.step();
    let first = mean(&rig.image("out"));
    assert!(first[0] > 0.2, "{first:?}");
    // The input goes black: what is left is last frame's trail, halved.
    set(&mut rig, &mut patch, 1, "Color B", grey(0.0));
    rig.step();
    let second = mean(&rig.image("out"));
    assert!(
        (second[0] - 0.5 * first[0]).abs() < 2e-3,
        "{first:?} {second:?}"
    );
    // A cut: the trail starts again from its clear value.
    rig.renderer.reset_history();
    rig.step();
    let cut = mean(&rig.image("out"));
    assert!(cut[0].abs() < 1e-4, "{cut:?}");
    assert!(rig.errors().is_empty(), "{:?}", rig.errors());
}

#[test]
fn the_eye_adaptation_example_agrees_with_the_built_in_eye_adaptation() {
    let mut patch = Patch::default();
    noise_into(&mut patch, 1);
    patch.add(NodeDoc::new(2, "EyeAdaptationChain (Shader)"));
    patch.add(NodeDoc::new(3, "EyeAdaptation"));
    patch.add(output(4, "shader"));
    patch.add(output(5, "built-in"));
    patch.link(1, "Texture", 2, "Texture");
    patch.link(1, "Texture", 3, "Texture");
    patch.link(2, "Texture", 4, "Texture");
    patch.link(3, "Luminance", 5, "Texture");
    let mut rig = Rig::new(crate::registry(), &patch);
    let mut seen = Vec::new();
    for frame in 0..6 {
        // Bright for three frames, then dark: both adapt down at the same speed.
        if frame == 3 {
            set(&mut rig, &mut patch, 1, "Color B", grey(0.05));
        }
        rig.step();
        let (a, b) = (
            rig.image("shader").pixel(0, 0)[0],
            rig.image("built-in").pixel(0, 0)[0],
        );
        assert!(
            (a - b).abs() <= 1e-4 * b.abs().max(1e-3),
            "frame {frame}: shader {a}, built-in {b}"
        );
        seen.push(a);
    }
    assert!(
        seen[5] < seen[2],
        "it adapted to the darker image: {seen:?}"
    );
}

/// Each device limit a shader can exceed (docs/shader-nodes.md): checked
/// when the node evaluates, so the device never sees it. The node shows the
/// error at the annotation or binding that asks too much, its last good
/// version keeps rendering, and the rest of the patch runs.
#[test]
fn a_shader_beyond_each_device_limit_shows_it_and_keeps_its_last_good_version() {
    let (dir, mut library, mut registry, mut patch) = tint_rig(TINT_V1);
    patch.add(output(4, "noise"));
    patch.link(1, "Texture", 4, "Texture");
    let mut rig = Rig::new(registry.clone(), &patch);
    rig.step();
    let good = mean(&rig.image("out"));
    let limits = rig.renderer.gpu.device.limits();
    let file = dir.path().join("tint.wgsl").display().to_string();

    // One more storage texture than a stage may bind: extra targets the pass writes.
    let writes = limits.max_storage_textures_per_shader_stage + 1;
    let extra = 1..writes;
    let targets: String = extra
        .clone()
        .map(|i| format!("// @target t{i} temporary rgba16float scale=1\n"))
        .collect();
    let names: String = extra.clone().map(|i| format!(", t{i}")).collect();
    let vars: String = extra
        .clone()
        .map(|i| {
            format!(
                "@group(0) @binding({}) var t{i}: texture_storage_2d<rgba16float, write>;\n",
                2 + i
            )
        })
        .collect();
    let stores: String = extra
        .map(|i| format!("    textureStore(t{i}, id.xy, vec4<f32>(0.0));\n"))
        .collect();
    let storage = TINT_V1
        .replace(
            "// @pass tint -> tinted",
            &format!("{targets}// @pass tint -> tinted{names}"),
        )
        .replace("@compute", &format!("{vars}@compute"))
        .replace(
            "    let c = textureLoad",
            &format!("{stores}    let c = textureLoad"),
        );
    let pass_line = 5 + writes - 1;
    // A uniform block one 64-byte matrix bigger than a binding may be (`_`
    // fields are padding, not pins).
    let matrices = limits.max_uniform_buffer_binding_size / 64 + 1;
    let padding: String = (0..matrices)
        .map(|i| format!("    _m{i}: mat4x4<f32>,\n"))
        .collect();
    let uniform = TINT_V1.replace(
        "    size: vec2<f32>,",
        &format!("{padding}    size: vec2<f32>,"),
    );
    let var_line = 12 + matrices;
    let side = limits.max_texture_dimension_2d + 1;
    let cases = [
        (
            TINT_V1.replace("@workgroup_size(8, 8)", "@workgroup_size(1024, 1024)"),
            "5:4".to_owned(),
            "workgroup size 1024x1024x1 exceeds the device's limits".to_owned(),
        ),
        (
            storage,
            format!("{pass_line}:4"),
            format!(
                "entry point `tint` writes {writes} targets; the device allows {}",
                limits.max_storage_textures_per_shader_stage
            ),
        ),
        (
            TINT_V1.replace("rgba16float scale=1", &format!("rgba16float size={side}x1")),
            "4:4".to_owned(),
            format!(
                "target `tinted` would be {side}x1; the device allows {} pixels a side",
                side - 1
            ),
        ),
        (
            uniform,
            format!("{var_line}:23"),
            format!(
                "the uniform block is {} bytes; the device allows {}",
                64 * matrices + 48,
                limits.max_uniform_buffer_binding_size
            ),
        ),
    ];
    for (text, at, what) in cases {
        write(dir.path(), &text);
        library.poll(&mut registry);
        assert!(library.errors().is_empty(), "{:?}", library.errors());
        rig.rt.set_registry(registry.clone());
        assert!(rig.rt.load(&patch).is_empty());
        rig.step();
        let errors = rig.errors();
        assert_eq!(errors.len(), 1, "{errors:?}");
        assert!(
            errors[0].starts_with(&format!("#2: {file}:{at}: ")) && errors[0].contains(&what),
            "{errors:?}"
        );
        let shown = mean(&rig.image("out"));
        assert!(
            (0..3).all(|c| (shown[c] - good[c]).abs() < 1e-4),
            "{what}: the last good version renders: {shown:?}, not {good:?}"
        );
        assert!(mean(&rig.image("noise"))[0] > 0.05, "the rest renders");
        assert!(rig.renderer.last_report().errors.is_empty());
        write(dir.path(), &format!("{TINT_V1}\n"));
        library.poll(&mut registry);
    }
}

#[test]
fn the_blur_node_matches_the_same_blur_written_as_a_built_in_pass() {
    let mut patch = Patch::default();
    noise_into(&mut patch, 1);
    patch.add(NodeDoc::new(2, "Blur (Shader)").with("Radius", vec![6.0f32]));
    patch.add(NodeDoc::new(3, "BlurBuiltin").with("Radius", vec![6.0f32]));
    patch.add(output(4, "shader"));
    patch.add(output(5, "built-in"));
    patch.link(1, "Texture", 2, "Texture");
    patch.link(1, "Texture", 3, "Texture");
    patch.link(2, "Texture", 4, "Texture");
    patch.link(3, "Texture", 5, "Texture");
    let mut rig = Rig::new(crate::registry(), &patch);
    rig.step();
    assert!(rig.errors().is_empty(), "{:?}", rig.errors());
    let (a, b) = (rig.image("shader"), rig.image("built-in"));
    assert_eq!(a.pixels, b.pixels);
    // And it did blur: less contrast than the noise.
    let spread = |img: &ImageF32| {
        let m = mean(img)[0];
        img.pixels.iter().map(|p| (p[0] - m).abs()).sum::<f32>()
    };
    let mut noise_only = Patch::default();
    noise_into(&mut noise_only, 1);
    noise_only.add(output(4, "noise"));
    noise_only.link(1, "Texture", 4, "Texture");
    let mut plain = Rig::new(crate::registry(), &noise_only);
    plain.step();
    assert!(spread(&a) < 0.8 * spread(&plain.image("noise")));
}

#[test]
fn a_shader_reads_the_g_buffer_and_its_camera_by_name() {
    let dir = tempfile::tempdir().expect("tempdir");
    std::fs::write(
        dir.path().join("normal_view.wgsl"),
        "// @gbuffer depth normals camera
// @target shown temporary rgba16float scale=1
// @pass show -> shown
@group(0) @binding(0) var depth: texture_2d<f32>;
@group(0) @binding(1) var normals: texture_2d<f32>;
@group(0) @binding(2) var shown: texture_storage_2d<rgba16float, write>;
struct Camera {
    view: mat4x4<f32>,
    view_inverse: mat4x4<f32>,
    projection: mat4x4<f32>,
    projection_inverse: mat4x4<f32>,
    view_projection: mat4x4<f32>,
    previous_view_projection: mat4x4<f32>,
    position: vec4<f32>,
    size: vec4<f32>,
}
@group(0) @binding(3) var<uniform> camera: Camera;
@compute @workgroup_size(8, 8)
fn show(@builtin(global_invocation_id) id: vec3<u32>) {
    let size = textureDimensions(shown);
    if (id.x >= size.x || id.y >= size.y) { return; }
    let covered = textureLoad(depth, id.xy, 0).r > 0.0;
    let n = textureLoad(normals, id.xy, 0).xyz * 0.5 + 0.5;
    // Alpha: whether the camera block says the G-buffer's size.
    let camera_ok = abs(camera.size.x - f32(size.x)) < 0.5 && abs(camera.size.y - f32(size.y)) < 0.5;
    let a = select(0.25, 1.0, camera_ok);
    textureStore(shown, id.xy, select(vec4<f32>(0.0, 0.0, 0.0, a), vec4<f32>(n, a), covered));
}
",
    )
    .expect("write");
    let mut registry = crate::registry();
    ShaderLibrary::new(vec![dir.path().to_owned()]).poll(&mut registry);
    let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../patches/gbuffer-spheres.ron");
    let mut patch = spreadlight_graph::format::load(&path).expect("example patch");
    patch.add(NodeDoc::new(50, "NormalView (Shader)"));
    patch.add(output(51, "normals"));
    patch.link(7, "G-Buffer", 50, "G-Buffer");
    patch.link(50, "Texture", 51, "Texture");
    let mut rig = Rig::new(registry, &patch);
    rig.step();
    assert!(rig.errors().is_empty(), "{:?}", rig.errors());
    let image = rig.image("normals");
    // The camera block is bound; the spheres' normals vary where the plane's
    // are one (depth and normals read).
    assert!(image.pixels.iter().all(|p| p[3] == 1.0), "camera block");
    let reds = image.pixels.iter().map(|p| p[0]);
    let (lo, hi) = reds.fold((f32::MAX, f32::MIN), |(lo, hi), r| (lo.min(r), hi.max(r)));
    assert!(hi - lo > 0.2, "normals {lo}..{hi}");
    assert!(image.pixels.iter().all(|p| p.iter().all(|c| c.is_finite())));
}

/// A 64x36 gradient, not the frame's size: a source shader node with an
/// absolute-size target.
const GRADIENT: &str = "// @category Source
// @help A 64x36 gradient.
// @target gradient temporary rgba16float size=64x36
// @pass paint -> gradient
@group(0) @binding(0) var gradient: texture_storage_2d<rgba16float, write>;
@compute @workgroup_size(8, 8)
fn paint(@builtin(global_invocation_id) id: vec3<u32>) {
    let size = textureDimensions(gradient);
    if (id.x >= size.x || id.y >= size.y) { return; }
    let uv = (vec2<f32>(id.xy) + 0.5) / vec2<f32>(size);
    textureStore(gradient, id.xy, vec4<f32>(0.25 + 0.5 * uv.x, 0.25 + 0.5 * uv.y, 0.5, 1.0));
}
";

/// Image effects keep the size of a source that is not the frame's, and
/// the Output stretches what they make to the frame: a 64x36 gradient
/// through an image-effect shader node (Tint), and through FXAA and
/// Tonemap, rendered at 96x54, is the whole gradient stretched over the
/// frame (the CPU's gradient, tinted or tonemapped, resized bilinearly),
/// not the gradient in a corner of a black frame.
#[test]
fn image_effects_of_a_small_texture_fill_the_frame_at_another_size() {
    use glam::Vec3;
    use spreadlight_reference::tonemap::{TonemapOperator, tonemap};
    let dir = tempfile::tempdir().expect("tempdir");
    std::fs::write(dir.path().join("gradient.wgsl"), GRADIENT).expect("write");
    write(dir.path(), TINT_V1);
    let mut registry = crate::registry();
    let mut library = ShaderLibrary::new(vec![dir.path().to_owned()]);
    library.poll(&mut registry);
    let mut patch = Patch::default();
    patch.add(NodeDoc::new(1, "Gradient (Shader)"));
    patch.add(NodeDoc::new(2, "Tint (Shader)"));
    patch.add(NodeDoc::new(3, "FXAA"));
    patch.add(NodeDoc::new(4, "Tonemap"));
    patch.add(output(5, "tint"));
    patch.add(output(6, "post"));
    patch.link(1, "Texture", 2, "Texture");
    patch.link(2, "Texture", 5, "Texture");
    patch.link(1, "Texture", 3, "Texture");
    patch.link(3, "Texture", 4, "Texture");
    patch.link(4, "Texture", 6, "Texture");
    let mut rig = Rig::new(registry, &patch);
    let frame = (96, 54);
    rig.resize(frame);
    let report = rig.step();
    assert!(rig.errors().is_empty(), "{:?}", rig.errors());
    assert!(report.errors.is_empty(), "{:?}", report.errors);
    let (w, h) = (64u32, 36u32);
    let gradient = |f: &dyn Fn(Vec3) -> Vec3| ImageF32 {
        width: w,
        height: h,
        pixels: (0..w * h)
            .map(|i| {
                let (x, y) = ((i % w) as f32 + 0.5, (i / w) as f32 + 0.5);
                let c = f(Vec3::new(0.25 + 0.5 * x / 64.0, 0.25 + 0.5 * y / 36.0, 0.5));
                [c.x, c.y, c.z, 1.0]
            })
            .collect(),
    };
    // Tint's defaults: colour (1, 0.5, 0.25), gain 1.
    let tinted = gradient(&|c| c * Vec3::new(1.0, 0.5, 0.25));
    // FXAA leaves a gradient this smooth alone; Tonemap's defaults: ACES, exposure 1.
    let tonemapped = gradient(&|c| tonemap(c, TonemapOperator::Aces, 1.0, 4.0));
    for (name, want) in [("tint", tinted), ("post", tonemapped)] {
        assert_eq!(
            rig.images.source_size(name),
            Some((w, h)),
            "{name}: the effects made their source's size"
        );
        let got = rig.image(name);
        let want = want.resized(frame);
        assert_eq!((got.width, got.height), frame);
        for (i, (a, b)) in want.pixels.iter().zip(&got.pixels).enumerate() {
            assert!(
                (0..3).all(|c| (a[c] - b[c]).abs() < 4e-3),
                "{name}: pixel ({}, {}) is {b:?}, the stretched gradient {a:?}",
                i as u32 % frame.0,
                i as u32 / frame.0
            );
        }
    }
}
