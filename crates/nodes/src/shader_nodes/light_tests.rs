//! The light kind (`// @light`: a `light` function the CookTorrance loop
//! calls per light), on the test GPU: its pins, its errors at
//! file:line:col, and a light type its file does not declare refused at the
//! Lights pin while the rest of the patch runs.

use std::path::Path;

use spreadlight_graph::Patch;

use super::tests::Rig;
use super::{ShaderLibrary, ShaderType};

fn toon_patch() -> Patch {
    let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../patches/toon-lights.ron");
    spreadlight_graph::format::load(&path).expect("example patch")
}

/// A light shader for `kinds` whose `light` function is `body`.
fn light_file(kinds: &str, body: &str) -> String {
    format!(
        "// @light {kinds}\n#import spreadlight::light_shader::{{LightInput, LightOutput, light_lambert}}\n\n{body}"
    )
}

#[test]
fn a_light_shader_has_the_light_loops_pins_before_its_own_and_outputs_diffuse_and_specular() {
    let ty = super::shipped("ToonLights (Shader)").expect("the toon example compiles");
    let def = ty.node_def(None);
    let inputs: Vec<&str> = def.inputs.iter().map(|p| p.name.as_ref()).collect();
    assert_eq!(
        inputs,
        [
            "G-Buffer",
            "Lights",
            "Material World",
            "Shadows",
            "Light Loop",
            "Bands",
            "Highlight Size",
            "Specular"
        ]
    );
    let outputs: Vec<&str> = def.outputs.iter().map(|p| p.name.as_ref()).collect();
    assert_eq!(outputs, ["Diffuse", "Specular"]);
}

#[test]
fn broken_light_shaders_name_their_file_line_and_column() {
    let lambert = "fn light(in: LightInput) -> LightOutput { return LightOutput(light_lambert(in), vec3<f32>(0.0)); }\n";
    let cases = [
        (
            light_file(
                "point",
                "fn shade(in: LightInput) -> LightOutput { return LightOutput(light_lambert(in), vec3<f32>(0.0)); }\n",
            ),
            "l.wgsl:1:4:",
            "defines `fn light(in: LightInput) -> LightOutput`",
        ),
        (
            light_file(
                "point",
                "fn light(in: LightInput) -> vec3<f32> { return light_lambert(in); }\n",
            ),
            "l.wgsl:4:1:",
            "must be `fn light(in: LightInput) -> LightOutput`",
        ),
        (
            light_file(
                "sun",
                "struct P { a: f32 }\n@group(1) @binding(0) var<uniform> p: P;\n\
                 fn light(in: LightInput) -> LightOutput { return LightOutput(light_lambert(in) * p.a, vec3<f32>(0.0)); }\n",
            ),
            "l.wgsl:5:",
            "a light shader binds everything in group 2",
        ),
        (
            light_file(
                "spot",
                "fn light(in: LightInput) -> LightOutput {\n    let k: f32 = in.normal;\n    return LightOutput(light_lambert(in) * k, vec3<f32>(0.0));\n}\n",
            ),
            "l.wgsl:5:18:",
            "WGSL type",
        ),
        (
            light_file(
                "point",
                "fn light(in: LightInput) -> LightOutput { return LightOutput(light_lambert(in), vec3<f32>(0.0)) }\n",
            ),
            "l.wgsl:4:",
            "WGSL syntax",
        ),
        (
            light_file("area", lambert),
            "l.wgsl:1:4:",
            "unknown light type `area`",
        ),
        (
            format!("// @pass main -> t\n{}", light_file("point", lambert)),
            "l.wgsl:1:4:",
            "has no passes",
        ),
        (
            "fn light(in: vec3<f32>) -> vec3<f32> { return in; }\n// @light sun\n".to_string(),
            "l.wgsl:2:4:",
            "imports the light loop's structs",
        ),
    ];
    for (text, place, what) in &cases {
        let err = match ShaderType::load("L (Shader)", "l.wgsl", text) {
            Ok(_) => panic!("compiled:\n{text}"),
            Err(e) => e.to_string(),
        };
        assert!(err.starts_with(place), "{err}\nwanted {place}");
        assert!(err.contains(what), "{err}\nwanted {what}");
    }
}

#[test]
fn a_light_type_the_file_does_not_declare_is_refused_at_the_lights_pin_and_the_rest_runs() {
    let points_only = light_file(
        "point",
        "fn light(in: LightInput) -> LightOutput { return LightOutput(light_lambert(in), vec3<f32>(0.0)); }\n",
    );
    let dir = tempfile::tempdir().expect("tempdir");
    std::fs::write(dir.path().join("points_only.wgsl"), points_only).expect("write");
    let mut registry = crate::registry();
    let mut library = ShaderLibrary::new(vec![dir.path().to_owned()]);
    library.poll(&mut registry);
    assert!(library.errors().is_empty(), "{:?}", library.errors());
    let mut patch = toon_patch();
    // The sun's light shader (16) becomes one that shades point lights only.
    for node in &mut patch.nodes {
        if node.id.0 == 16 {
            node.type_name = "PointsOnly (Shader)".into();
            node.values.clear();
        }
    }
    let mut rig = Rig::new(registry, &patch);
    let report = rig.step();
    let errors = rig.errors();
    assert_eq!(errors.len(), 1, "{errors:?}");
    assert!(
        errors[0].contains("Lights")
            && errors[0].contains("holds sun lights")
            && errors[0].contains("`// @light point`"),
        "{errors:?}"
    );
    // The point lights' toon node still shades, and the picture is made.
    assert_eq!(
        report
            .passes_of("ToonLights (Shader) #12", Some("shade"))
            .count(),
        1
    );
    assert!(report.errors.is_empty(), "{:?}", report.errors);
    let image = rig.image("toon");
    assert!(image.pixels.iter().all(|p| p.iter().all(|c| c.is_finite())));
    assert!(image.pixels.iter().any(|p| p[0] > 0.05));
}
