//! The material kind (a DeferredBase layer's `surface` function), Enum
//! switches, and `#import` of the project's WGSL libraries, on the test GPU.

use std::path::Path;

use spreadlight_graph::{Color, NodeDoc, Patch, PinType, Spread};
use spreadlight_render::readback::ImageF32;

use super::tests::{Rig, mean, noise_into, output, set};
use super::{ShaderLibrary, ShaderType};

fn example_patch() -> Patch {
    let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../patches/shader-material.ron");
    spreadlight_graph::format::load(&path).expect("example patch")
}

/// The material node of patches/shader-material.ron.
const MATERIAL: u32 = 4;

/// Fraction of pixels whose RGB differs by more than `by` in some channel.
fn differing(a: &ImageF32, b: &ImageF32, by: f32) -> f64 {
    let n = a
        .pixels
        .iter()
        .zip(&b.pixels)
        .filter(|(p, q)| (0..3).any(|c| (p[c] - q[c]).abs() > by))
        .count();
    n as f64 / a.pixels.len() as f64
}

fn finite(image: &ImageF32) -> bool {
    image.pixels.iter().all(|p| p.iter().all(|c| c.is_finite()))
}

#[test]
fn a_material_shades_its_layer_in_the_g_buffer_and_its_pins_change_the_picture() {
    let mut patch = example_patch();
    let mut rig = Rig::new(crate::registry(), &patch);
    let report = rig.step();
    assert!(rig.errors().is_empty(), "{:?}", rig.errors());
    assert!(report.errors.is_empty(), "{:?}", report.errors);
    let shaded = rig.image("albedo");
    assert!(finite(&shaded) && finite(&rig.image("material")));

    // Without the material the spheres are DeferredBase's plain white.
    let mut plain_patch = example_patch();
    plain_patch
        .links
        .retain(|l| l.from.0.0 != MATERIAL && l.to.0.0 != MATERIAL);
    plain_patch.link(3, "Layer", 7, "Layer 1");
    let mut plain = Rig::new(crate::registry(), &plain_patch);
    plain.step();
    let unshaded = plain.image("albedo");
    assert!(
        differing(&shaded, &unshaded, 0.05) > 0.05,
        "the material changed no pixel's albedo"
    );

    // Color: the stone between the veins turns red.
    set(
        &mut rig,
        &mut patch,
        MATERIAL,
        "Color",
        Spread::Color(vec![Color::rgba(1.0, 0.0, 0.0, 1.0)]),
    );
    rig.step();
    let red = rig.image("albedo");
    let (before, after) = (mean(&shaded), mean(&red));
    assert!(
        after[1] < before[1] - 0.02 && after[0] > after[1] + 0.05,
        "Color: mean {before:?} -> {after:?}"
    );

    // Scale: a finer pattern moves the veins.
    set(
        &mut rig,
        &mut patch,
        MATERIAL,
        "Scale",
        Spread::Float(vec![9.0]),
    );
    rig.step();
    let finer = rig.image("albedo");
    assert!(
        differing(&red, &finer, 0.05) > 0.02,
        "Scale changed too few pixels"
    );
    assert!(finite(&finer) && finite(&rig.image("material")));
}

#[test]
fn the_material_roughness_pin_changes_the_lit_picture_and_not_the_albedo() {
    // CookTorrance's own Roughness pin (0.3) gives way to what the material
    // writes on its spheres (shaders/lib/surface_target.wgsl).
    let mut patch = example_patch();
    let mut rig = Rig::new(crate::registry(), &patch);
    // The example's size: the spheres' highlights are a few pixels there.
    rig.resize((160, 90));
    let mut lit = Vec::new();
    let mut albedo = Vec::new();
    for roughness in [0.12, 0.6] {
        set(
            &mut rig,
            &mut patch,
            MATERIAL,
            "Roughness",
            Spread::Float(vec![roughness]),
        );
        rig.step();
        assert!(rig.errors().is_empty(), "{:?}", rig.errors());
        lit.push(rig.image("material"));
        albedo.push(rig.image("albedo"));
    }
    assert!(finite(&lit[0]) && finite(&lit[1]));
    assert_eq!(differing(&albedo[0], &albedo[1], 0.0), 0.0);
    let largest = lit[0]
        .pixels
        .iter()
        .zip(&lit[1].pixels)
        .flat_map(|(p, q)| (0..3).map(move |c| (p[c] - q[c]).abs()))
        .fold(0.0, f32::max);
    assert!(
        largest > 0.1 && differing(&lit[0], &lit[1], 0.02) > 0.001,
        "Roughness changed too few lit pixels: {} (largest change {largest})",
        differing(&lit[0], &lit[1], 0.02)
    );
}

#[test]
fn the_material_pattern_enum_compiles_each_used_option_once_and_counts_it() {
    // One sink (the albedo), so the frame's one report holds the count.
    let mut patch = example_patch();
    patch.nodes.retain(|n| n.id.0 != 15);
    patch.links.retain(|l| l.to.0.0 != 15);
    let mut rig = Rig::new(crate::registry(), &patch);
    rig.step();
    let marble = rig.image("albedo");
    set(
        &mut rig,
        &mut patch,
        MATERIAL,
        "Pattern",
        Spread::Enum(vec!["Checker".to_owned()]),
    );
    let report = rig.step();
    assert!(rig.errors().is_empty(), "{:?}", rig.errors());
    let compiled = report.counter("shader node permutations compiled");
    assert_eq!(compiled, 1, "{:?}", report.counters);
    assert!(differing(&marble, &rig.image("albedo"), 0.05) > 0.02);
    // The same option again compiles nothing.
    rig.rt.invalidate_all();
    assert_eq!(rig.step().counter("shader node permutations compiled"), 0);
}

const MODES: &str = "// @category Source
// @enum MODE \"Mode\" Red|Green|Blue default=Green
// @target out temporary rgba16float scale=1
// @pass fill -> out
@group(0) @binding(0) var out: texture_storage_2d<rgba16float, write>;
@compute @workgroup_size(8, 8)
fn fill(@builtin(global_invocation_id) id: vec3<u32>) {
    let size = textureDimensions(out);
    if (id.x >= size.x || id.y >= size.y) { return; }
#ifdef MODE_RED
    let c = vec3<f32>(1.0, 0.0, 0.0);
#endif
#ifdef MODE_GREEN
    let c = vec3<f32>(0.0, 1.0, 0.0);
#endif
#ifdef MODE_BLUE
    let c = vec3<f32>(0.0, 0.0, 1.0);
#endif
    textureStore(out, id.xy, vec4<f32>(c, 1.0));
}
";

#[test]
fn an_enum_pin_selects_a_permutation_compiled_once_per_used_option() {
    let ty = ShaderType::load("Modes (Shader)", "modes.wgsl", MODES).expect("compiles");
    let def = ty.node_def(None);
    let pin = def
        .inputs
        .iter()
        .find(|p| p.name == "Mode")
        .expect("Mode pin");
    match pin.ty {
        PinType::Enum(e) => assert_eq!(e.options, ["Red", "Green", "Blue"]),
        other => panic!("Mode is {other}"),
    }
    assert_eq!(pin.default, Spread::Enum(vec!["Green".to_owned()]));

    let dir = tempfile::tempdir().expect("tempdir");
    std::fs::write(dir.path().join("modes.wgsl"), MODES).expect("write");
    let mut registry = crate::registry();
    ShaderLibrary::new(vec![dir.path().to_owned()]).poll(&mut registry);
    let mut patch = Patch::default();
    // Three slices over two options: Green (the default, compiled when the
    // file loaded) is not compiled again; Blue once, for both its slices.
    patch.add(NodeDoc::new(1, "Modes (Shader)").with(
        "Mode",
        Spread::Enum(vec!["Blue".into(), "Green".into(), "Blue".into()]),
    ));
    patch.add(output(2, "out"));
    patch.link(1, "Texture", 2, "Texture");
    let mut rig = Rig::new(registry, &patch);
    let report = rig.step();
    assert!(rig.errors().is_empty(), "{:?}", rig.errors());
    assert_eq!(
        report.counter("shader node permutations compiled"),
        1,
        "{:?}",
        report.counters
    );
    let m = mean(&rig.image("out"));
    assert!(m[2] > 0.99 && m[0] < 0.01 && m[1] < 0.01, "{m:?}");
    set(
        &mut rig,
        &mut patch,
        1,
        "Mode",
        Spread::Enum(vec!["Red".into()]),
    );
    let report = rig.step();
    assert_eq!(report.counter("shader node permutations compiled"), 1);
    let m = mean(&rig.image("out"));
    assert!(m[0] > 0.99 && m[1] < 0.01, "{m:?}");
}

#[test]
fn an_effect_imports_a_library_function() {
    let text = "// @input source \"Texture\"
// @target unit temporary rgba16float scale=1
// @pass normalize -> unit
#import spreadlight::packing::safe_normalize
@group(0) @binding(0) var source: texture_2d<f32>;
@group(0) @binding(1) var unit: texture_storage_2d<rgba16float, write>;
@compute @workgroup_size(8, 8)
fn normalize(@builtin(global_invocation_id) id: vec3<u32>) {
    let size = textureDimensions(unit);
    if (id.x >= size.x || id.y >= size.y) { return; }
    let c = textureLoad(source, id.xy, 0).rgb;
    textureStore(unit, id.xy, vec4<f32>(safe_normalize(c, vec3<f32>(0.0, 0.0, 1.0)), 1.0));
}
";
    let dir = tempfile::tempdir().expect("tempdir");
    std::fs::write(dir.path().join("unit.wgsl"), text).expect("write");
    let mut registry = crate::registry();
    let mut library = ShaderLibrary::new(vec![dir.path().to_owned()]);
    library.poll(&mut registry);
    assert!(library.errors().is_empty(), "{:?}", library.errors());
    let mut patch = Patch::default();
    noise_into(&mut patch, 1);
    patch.add(NodeDoc::new(2, "Unit (Shader)"));
    patch.add(output(3, "out"));
    patch.link(1, "Texture", 2, "Texture");
    patch.link(2, "Texture", 3, "Texture");
    let mut rig = Rig::new(registry, &patch);
    rig.step();
    assert!(rig.errors().is_empty(), "{:?}", rig.errors());
    // Every pixel is a unit vector: the library's function ran.
    for p in &rig.image("out").pixels {
        let len = (p[0] * p[0] + p[1] * p[1] + p[2] * p[2]).sqrt();
        assert!((len - 1.0).abs() < 1e-2, "{p:?}");
    }
}

/// A material file with `body` after its header (line 4 on).
fn material(body: &str) -> String {
    format!(
        "// @material\n#import spreadlight::surface::{{SurfaceInput, SurfaceOutput, surface_default}}\n\n{body}"
    )
}

#[test]
fn broken_imports_and_materials_name_their_file_line_and_column() {
    let cases = [
        (
            "// @material\n#import spreadlight::surface::{SurfaceInput, SurfaceOutput, surface_default}\n\
             #import spreadlight::no_such_library::helper\n\
             fn surface(in: SurfaceInput) -> SurfaceOutput {\n\
             var o = surface_default(in); o.roughness = helper(); return o; }\n",
            "m.wgsl:3:1:",
            "no such library",
        ),
        (
            &*material(
                "fn shade(in: SurfaceInput) -> SurfaceOutput { return surface_default(in); }\n",
            ),
            "m.wgsl:1:4:",
            "defines `fn surface",
        ),
        (
            &*material("fn surface(in: SurfaceInput) -> vec4<f32> { return vec4<f32>(1.0); }\n"),
            "m.wgsl:4:1:",
            "must be `fn surface(in: SurfaceInput) -> SurfaceOutput`",
        ),
        (
            &*material(
                "struct P { a: f32 }\n@group(0) @binding(0) var<uniform> p: P;\n\
                 fn surface(in: SurfaceInput) -> SurfaceOutput { var o = surface_default(in); o.roughness = p.a; return o; }\n",
            ),
            "m.wgsl:5:",
            "a material binds everything in group 1",
        ),
        (
            &*material(
                "fn surface(in: SurfaceInput) -> SurfaceOutput { return surface_default(in) }\n",
            ),
            "m.wgsl:4:",
            "WGSL syntax",
        ),
        (
            &*format!("// @target t temporary rgba8unorm\n{}", material("")),
            "m.wgsl:1:4:",
            "has no render targets",
        ),
        // In a file composed with its imports too: a type error at the
        // value, naga's validation at the expression (f32 + u32), not at the
        // statement or function around it.
        (
            &*material(
                "fn surface(in: SurfaceInput) -> SurfaceOutput {\n    var o = surface_default(in);\n    \
                 let r: f32 = in.uv;\n    return o;\n}\n",
            ),
            "m.wgsl:6:18:",
            "WGSL type: the type of `r` is expected to be `f32`",
        ),
        (
            &*material(
                "fn surface(in: SurfaceInput) -> SurfaceOutput {\n    var o = surface_default(in);\n    \
                 o.roughness = 0.5 * (in.uv.x + in.pixel.x);\n    return o;\n}\n",
            ),
            "m.wgsl:6:26:",
            "validation: ",
        ),
    ];
    for (text, place, what) in cases {
        let err = match ShaderType::load("M (Shader)", "m.wgsl", text) {
            Ok(_) => panic!("compiled:\n{text}"),
            Err(e) => e.to_string(),
        };
        assert!(err.starts_with(place), "{err}\nwanted {place}");
        assert!(err.contains(what), "{err}\nwanted {what}");
    }
}

#[test]
fn a_material_samples_its_texture_inputs_at_the_surfaces_uv() {
    let textured = "// @material
// @input tex \"Texture\"
// @sampler smp repeat
#import spreadlight::surface::{SurfaceInput, SurfaceOutput, surface_default}
@group(1) @binding(0) var tex: texture_2d<f32>;
@group(1) @binding(1) var smp: sampler;
fn surface(in: SurfaceInput) -> SurfaceOutput {
    var o = surface_default(in);
    o.albedo = textureSampleLevel(tex, smp, in.uv, 0.0).rgb;
    return o;
}
";
    let dir = tempfile::tempdir().expect("tempdir");
    std::fs::write(dir.path().join("textured.wgsl"), textured).expect("write");
    std::fs::write(dir.path().join("modes.wgsl"), MODES).expect("write");
    let mut registry = crate::registry();
    let mut library = ShaderLibrary::new(vec![dir.path().to_owned()]);
    library.poll(&mut registry);
    assert!(library.errors().is_empty(), "{:?}", library.errors());
    let mut patch = example_patch();
    patch.nodes.retain(|n| n.id.0 != 15);
    patch.links.retain(|l| l.to.0.0 != 15);
    for node in &mut patch.nodes {
        match node.id.0 {
            3 => {
                node.values
                    .insert("Texture Coordinates".into(), Spread::Bool(vec![true]));
            }
            MATERIAL => {
                node.type_name = "Textured (Shader)".into();
                node.values.clear();
            }
            _ => {}
        }
    }
    patch.add(NodeDoc::new(30, "Modes (Shader)").with("Mode", Spread::Enum(vec!["Blue".into()])));
    patch.link(30, "Texture", MATERIAL, "Texture");
    let mut rig = Rig::new(registry, &patch);
    let report = rig.step();
    assert!(rig.errors().is_empty(), "{:?}", rig.errors());
    assert!(report.errors.is_empty(), "{:?}", report.errors);
    // The spheres take the texture's blue; nothing else in the scene is blue.
    let image = rig.image("albedo");
    let blue = image
        .pixels
        .iter()
        .filter(|p| p[2] > 0.5 && p[0] < 0.05 && p[1] < 0.05)
        .count();
    assert!(
        blue as f64 > 0.05 * image.pixels.len() as f64,
        "{blue} blue pixels"
    );
}
