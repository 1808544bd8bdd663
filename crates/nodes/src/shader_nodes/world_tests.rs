//! Shader nodes reading the material world (`spreadlight::materials`,
//! shaders/lib/materials.wgsl) on the test GPU: what a shader reads back is
//! what FeatureManager set, hard cases read as documented, and a node that
//! has no world says so.

use std::path::Path;

use glam::Vec4;
use spreadlight_graph::{NodeDoc, Patch, Spread};

use super::ShaderLibrary;
use super::tests::{Rig, output, set};

/// An image effect that writes, at pixel (x, y), something of material y:
/// x = 0 and 1 the custom feature 17's two parameter vec4s (GetFloats at
/// float offsets 0 and 4), x = 2 (KnowFeature, GetTexID, GetParamCount,
/// MaterialCount) for it, x = 3 CookTorrance's roughness and metallic by
/// GetFloat, then KnowFeature and GetFloats of feature 40 (no such id), x = 4
/// GetFloat past the parameters and GetTexID of a feature the material lacks,
/// x = 5 the feature's texture at uv (0.25, 0.5) (SampleFeature).
const PROBE: &str = "// @target shown temporary rgba32float scale=1
// @pass show -> shown
#import spreadlight::materials::{KnowFeature, GetFloat, GetFloats, GetTexID, GetParamCount, MaterialCount, SampleFeature}
@group(0) @binding(0) var shown: texture_storage_2d<rgba32float, write>;
@compute @workgroup_size(8, 8)
fn show(@builtin(global_invocation_id) id: vec3<u32>) {
    let size = textureDimensions(shown);
    if (id.x >= size.x || id.y >= size.y) { return; }
    let m = id.y;
    var v = vec4<f32>(0.0);
    switch id.x {
        case 0u: { v = GetFloats(m, 17u, 0u); }
        case 1u: { v = GetFloats(m, 17u, 4u); }
        case 2u: { v = vec4<f32>(select(0.0, 1.0, KnowFeature(m, 17u)), f32(GetTexID(m, 17u)), f32(GetParamCount(m, 17u)), f32(MaterialCount())); }
        case 3u: { v = vec4<f32>(GetFloat(m, 0u, 0u), GetFloat(m, 0u, 1u), select(0.0, 1.0, KnowFeature(m, 40u)), dot(GetFloats(m, 40u, 0u), vec4<f32>(1.0))); }
        case 4u: { v = vec4<f32>(GetFloat(m, 17u, 8u), f32(GetTexID(m, 1u)), select(0.0, 1.0, KnowFeature(m, 1u)), 0.0); }
        case 5u: { v = SampleFeature(m, 17u, vec2<f32>(0.25, 0.5)); }
        default: {}
    }
    textureStore(shown, id.xy, v);
}
";

fn tiles() -> String {
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("../../patches/assets/tiles.png")
        .to_string_lossy()
        .into_owned()
}

/// FeatureManager (custom feature 17, two vec4s per material, texture
/// layers -1 and 0) over AddCookTorrance, a MaterialBuffer with a one-layer
/// texture array, the probe reading it into Output `world`.
fn world_patch() -> Patch {
    let mut patch = Patch::default();
    patch.add(NodeDoc::new(1, "AddCookTorrance").with("Roughness", vec![0.25f32, 0.75]));
    patch.add(
        NodeDoc::new(2, "FeatureManager")
            .with("Feature ID", vec![17i64])
            .with(
                "Parameters",
                vec![
                    Vec4::new(0.25, 1.5, -2.0, 8.0),
                    Vec4::new(0.125, 3.0, 4.0, -0.5),
                    Vec4::new(1.0, 2.0, 3.0, 4.0),
                    Vec4::new(5.0, 6.0, 7.0, 0.75),
                ],
            )
            .with("Bin Size", vec![2i64])
            .with("Texture ID", vec![-1i64, 0]),
    );
    patch.add(NodeDoc::new(3, "FileTexture (Array)").with("Filenames", vec![tiles()]));
    patch.add(NodeDoc::new(4, "MaterialBuffer"));
    patch.add(NodeDoc::new(5, "WorldProbe (Shader)"));
    patch.add(output(6, "world"));
    patch.link(1, "Material", 2, "Material");
    patch.link(2, "Material", 4, "Materials");
    patch.link(3, "Texture", 4, "Textures");
    patch.link(4, "Material World", 5, "Material World");
    patch.link(5, "Texture", 6, "Texture");
    patch
}

fn registry_with_probe() -> (tempfile::TempDir, spreadlight_graph::Registry) {
    let dir = tempfile::tempdir().expect("tempdir");
    std::fs::write(dir.path().join("world_probe.wgsl"), PROBE).expect("write");
    let mut registry = crate::registry();
    let changes = ShaderLibrary::new(vec![dir.path().to_owned()]).poll(&mut registry);
    assert_eq!(changes.updated, ["WorldProbe (Shader)"]);
    (dir, registry)
}

#[test]
fn an_image_effect_reads_back_what_feature_manager_set() {
    let (_dir, registry) = registry_with_probe();
    let mut rig = Rig::new(registry, &world_patch());
    rig.step();
    assert!(rig.errors().is_empty(), "{:?}", rig.errors());
    let image = rig.image("world");
    assert!(image.all_finite());
    let at = |x: u32, y: u32| image.pixels[(y * image.width + x) as usize];
    // Material 0: the first bin, no texture; material 1: the second, layer 0.
    assert_eq!(at(0, 0), [0.25, 1.5, -2.0, 8.0]);
    assert_eq!(at(1, 0), [0.125, 3.0, 4.0, -0.5]);
    assert_eq!(at(0, 1), [1.0, 2.0, 3.0, 4.0]);
    assert_eq!(at(1, 1), [5.0, 6.0, 7.0, 0.75]);
    assert_eq!(
        at(2, 0),
        [1.0, -1.0, 2.0, 2.0],
        "known, no texture, 2 vec4s, 2 materials"
    );
    assert_eq!(at(2, 1), [1.0, 0.0, 2.0, 2.0], "texture layer 0");
    // CookTorrance through the same library; feature 40 does not exist.
    assert_eq!(at(3, 0), [0.25, 0.0, 0.0, 0.0]);
    assert_eq!(at(3, 1), [0.75, 0.0, 0.0, 0.0]);
    // Past the parameters reads 0; Emission (1) is not set: no texture, unknown.
    assert_eq!(at(4, 1), [0.0, -1.0, 0.0, 0.0]);
    // Material 1 samples its layer; material 0 has none and reads white.
    assert_eq!(at(5, 0), [1.0; 4]);
    let texel = at(5, 1);
    assert!(texel[3] > 0.99 && texel[..3].iter().all(|c| (0.0..=1.0).contains(c)));
    assert!(
        texel[..3].iter().any(|c| *c < 0.99),
        "tiles.png is not white there: {texel:?}"
    );
    // Material ids past the world's read material 0, as every pass does.
    for x in 0..5 {
        assert_eq!(at(x, 7), at(x, 0), "row 7 = material 0 at x {x}");
    }
}

#[test]
fn an_image_effect_without_a_world_says_which_pin() {
    let (_dir, registry) = registry_with_probe();
    let mut patch = world_patch();
    patch
        .links
        .retain(|l| l.to.0.0 != 5 || l.to.1 != "Material World");
    let mut rig = Rig::new(registry, &patch);
    rig.step();
    let errors = rig.errors();
    assert!(
        errors
            .iter()
            .any(|e| e.contains("Material World") && e.contains("MaterialBuffer")),
        "{errors:?}"
    );
}

#[test]
fn a_material_without_a_world_on_its_layer_says_so() {
    let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../patches/custom-feature.ron");
    let mut patch = spreadlight_graph::format::load(&path).expect("example patch");
    // Unplug the MaterialBuffer from the DeferredBase the rim material shades.
    patch
        .links
        .retain(|l| !(l.from.1 == "Material World" && l.to.1 == "Material World"));
    let mut rig = Rig::new(crate::registry(), &patch);
    rig.step();
    let errors = rig.errors();
    assert!(
        errors
            .iter()
            .any(|e| e.contains("spreadlight::materials") && e.contains("Material World")),
        "{errors:?}"
    );
}

/// The RimLight node of patches/custom-feature.ron.
const RIM: u32 = 4;

#[test]
fn the_custom_feature_example_lights_rims_only_where_the_feature_is_set() {
    let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../patches/custom-feature.ron");
    let mut patch = spreadlight_graph::format::load(&path).expect("example patch");
    let mut rig = Rig::new(crate::registry(), &patch);
    rig.resize((96, 54));
    rig.step();
    assert!(rig.errors().is_empty(), "{:?}", rig.errors());
    let with = rig.image("custom-feature");
    // A Feature ID no material has: no rim anywhere, the rest as it was.
    set(
        &mut rig,
        &mut patch,
        RIM,
        "Feature ID",
        Spread::Int(vec![20]),
    );
    rig.step();
    assert!(rig.errors().is_empty(), "{:?}", rig.errors());
    let without = rig.image("custom-feature");
    assert!(with.all_finite() && without.all_finite());
    let (w, h) = (with.width, with.height);
    // How much brighter the rims made a band of columns, and the least change in it.
    let gained = |x0: u32, x1: u32| -> (f32, f32) {
        let mut sum = 0.0f32;
        let mut lowest = 0.0f32;
        for y in 0..h {
            for x in x0..x1 {
                let (a, b) = (with.pixel(x, y), without.pixel(x, y));
                let d = (a[0] + a[1] + a[2]) - (b[0] + b[1] + b[2]);
                sum += d;
                lowest = lowest.min(d);
            }
        }
        (sum, lowest)
    };
    // The balls stand side by side: the middle one (material 0) is the
    // columns about the centre, the others lie left and right of it.
    let centre = w / 2;
    let (left, left_low) = gained(0, centre - 9);
    let (middle, _) = gained(centre - 7, centre + 8);
    let (right, right_low) = gained(centre + 10, w);
    assert!(
        left > 0.5 && right > 0.5,
        "rims on the outer balls: {left} {right}"
    );
    assert!(
        left_low > -1e-3 && right_low > -1e-3,
        "a rim only adds light"
    );
    assert_eq!(
        middle, 0.0,
        "the middle ball (material 0, no feature 16) is unchanged"
    );
}
