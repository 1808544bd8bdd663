//! `AddClearcoat` and `AddUnlit` lighting a floor through the nodes (the
//! test GPU): the pixel at the centre of the view against the CPU
//! reference (`spreadlight_reference::brdf`), so a patch gets the
//! same Clearcoat and Unlit a glTF file does.

use std::sync::Arc;

use glam::Vec3;
use spreadlight_graph::{Color, FrameClock, NodeDoc, NodeId, Patch, Runtime, Spread};
use spreadlight_reference::brdf::{clearcoat, cook_torrance_f0};
use spreadlight_render::readback::ImageF32;

use crate::output::RenderedImages;

/// Odd, so that one pixel's centre is the view's centre: the camera's target.
const SIZE: (u32, u32) = (33, 19);
/// Exact in the G-buffer's 8-bit albedo.
const ALBEDO: Vec3 = Vec3::new(0.8, 0.6, 0.4);
const SUN_DIRECTION: Vec3 = Vec3::new(-0.4, -1.0, -0.3);
const ILLUMINANCE: f32 = 2.5;
const ROUGHNESS: f32 = 0.7;

/// A floor (material id 0) at the origin seen from above at an angle, a
/// sun, CookTorrance over a MaterialBuffer fed by AddCookTorrance and then
/// `feature` (node 4, with `values`), and Outputs: "diffuse" and "specular"
/// (CookTorrance's) and "lit" (CompositeLight's, no ambient).
fn floor_patch(feature: &str, values: &[(&str, f32)]) -> Patch {
    let mut patch = Patch::default();
    patch.add(NodeDoc::new(1, "Plane").with("Size", vec![glam::Vec2::splat(20.0)]));
    patch.add(
        NodeDoc::new(2, "DeferredBase")
            .with(
                "Color",
                vec![Color::rgba(ALBEDO.x, ALBEDO.y, ALBEDO.z, 1.0)],
            )
            .with("Material ID", vec![0i64]),
    );
    patch.add(NodeDoc::new(3, "AddCookTorrance").with("Roughness", vec![ROUGHNESS]));
    let mut node = NodeDoc::new(4, feature);
    for (pin, value) in values {
        node = node.with(pin, vec![*value]);
    }
    patch.add(node);
    patch.add(NodeDoc::new(5, "MaterialBuffer"));
    patch.add(
        NodeDoc::new(6, "Camera")
            .with("Pitch", vec![0.6f32])
            .with("Yaw", vec![0.3f32])
            .with("Distance", vec![6.0f32]),
    );
    patch.add(NodeDoc::new(7, "MRE"));
    patch.add(
        NodeDoc::new(8, "AddLight (Sun)")
            .with("Direction", vec![SUN_DIRECTION])
            .with("Illuminance", vec![ILLUMINANCE]),
    );
    patch.add(NodeDoc::new(9, "SunLightBuffer"));
    patch.add(NodeDoc::new(10, "CookTorrance"));
    patch.add(NodeDoc::new(11, "CompositeLight"));
    for (id, name) in [(12, "diffuse"), (13, "specular"), (14, "lit")] {
        patch.add(
            NodeDoc::new(id, "Output")
                .with("Name", vec![name.to_owned()])
                .with("Write", vec![false]),
        );
    }
    for (from, from_pin, to, to_pin) in [
        (1, "Mesh", 2, "Mesh"),
        (3, "Material", 4, "Material"),
        (4, "Material", 5, "Materials"),
        (2, "Layer", 7, "Layer"),
        (6, "View", 7, "View"),
        (6, "Projection", 7, "Projection"),
        (8, "Lights", 9, "Lights"),
        (7, "G-Buffer", 10, "G-Buffer"),
        (9, "Lights", 10, "Lights"),
        (5, "Material World", 10, "Material World"),
        (7, "G-Buffer", 11, "G-Buffer"),
        (10, "Diffuse", 11, "Diffuse"),
        (10, "Specular", 11, "Specular"),
        (5, "Material World", 11, "Material World"),
        (10, "Diffuse", 12, "Texture"),
        (10, "Specular", 13, "Texture"),
        (11, "Texture", 14, "Texture"),
    ] {
        patch.link(from, from_pin, to, to_pin);
    }
    patch
}

/// What the floor patch shows: its three outputs' centre pixels and the
/// unit vector from the floor point there (the camera's target, the
/// origin) to the eye.
struct Centre {
    diffuse: Vec3,
    specular: Vec3,
    lit: Vec3,
    view: Vec3,
}

fn render_centre(patch: &Patch) -> Centre {
    let mut rt = Runtime::new(crate::registry());
    let renderer = spreadlight_render::renderer::test_renderer();
    renderer.set_output_size(SIZE);
    rt.provide(renderer);
    let images = Arc::new(RenderedImages::default());
    rt.provide(images.clone());
    let problems = rt.load(patch).to_vec();
    assert!(problems.is_empty(), "{problems:?}");
    rt.evaluate(FrameClock::fixed(0, 60.0));
    let errors: Vec<_> = rt
        .node_errors()
        .map(|(id, e)| format!("{id}: {e}"))
        .collect();
    assert!(errors.is_empty(), "{errors:?}");
    let centre = |name: &str| {
        let (image, _): (ImageF32, _) = images.get(name).unwrap_or_else(|| panic!("no `{name}`"));
        assert!(image.all_finite(), "{name}");
        let p = image.pixel(SIZE.0 / 2, SIZE.1 / 2);
        Vec3::new(p[0], p[1], p[2])
    };
    let eye = match rt.output(NodeId(6), "Position").map(|s| s.as_ref()) {
        Some(Spread::Vec3(v)) if !v.is_empty() => v[0],
        other => panic!("Camera Position {other:?}"),
    };
    Centre {
        diffuse: centre("diffuse"),
        specular: centre("specular"),
        lit: centre("lit"),
        view: eye.normalize(),
    }
}

/// Half-float targets (11 significant bits) against f32, and the G-buffer's
/// packed normal and reconstructed position.
fn assert_close(got: Vec3, want: Vec3, what: &str) {
    for c in 0..3 {
        assert!(
            (got[c] - want[c]).abs() <= 1e-2 * want[c].abs() + 2e-4,
            "{what}: got {got}, the reference says {want}"
        );
    }
}

#[test]
fn add_clearcoat_lights_a_floor_as_the_reference_coat_does() {
    let l = -SUN_DIRECTION.normalize();
    let radiance = Vec3::splat(ILLUMINANCE);
    let plain = render_centre(&floor_patch("AddClearcoat", &[("Factor", 0.0)]));
    for (factor, coat_roughness) in [(1.0, 0.15), (0.5, 0.4)] {
        let coated = render_centre(&floor_patch(
            "AddClearcoat",
            &[("Factor", factor), ("Roughness", coat_roughness)],
        ));
        let v = coated.view;
        let brdf = cook_torrance_f0(Vec3::Y, v, l, ALBEDO, ROUGHNESS, 0.0, 0.04, true);
        let (dim, lobe) = clearcoat(Vec3::Y, v, l, factor, coat_roughness);
        let want_d = brdf.diffuse * radiance * dim;
        let want_s = (brdf.specular * dim + Vec3::splat(factor * lobe)) * radiance;
        let what = format!("coat {factor}/{coat_roughness}");
        assert_close(coated.diffuse, want_d, &format!("{what} diffuse"));
        assert_close(coated.specular, want_s, &format!("{what} specular"));
        // The coat takes light from the base.
        assert!(
            coated.diffuse.x < plain.diffuse.x,
            "{what}: {}",
            coated.diffuse
        );
    }
    // Factor 0: no coat at all, CookTorrance's plain BRDF.
    let brdf = cook_torrance_f0(Vec3::Y, plain.view, l, ALBEDO, ROUGHNESS, 0.0, 0.04, true);
    assert_close(plain.diffuse, brdf.diffuse * radiance, "no coat: diffuse");
    assert_close(
        plain.specular,
        brdf.specular * radiance,
        "no coat: specular",
    );
}

#[test]
fn add_unlit_shows_the_albedo_mixed_over_the_reference_lighting_by_strength() {
    let l = -SUN_DIRECTION.normalize();
    let radiance = Vec3::splat(ILLUMINANCE);
    for strength in [0.0, 0.5, 1.0] {
        let centre = render_centre(&floor_patch("AddUnlit", &[("Strength", strength)]));
        let brdf = cook_torrance_f0(Vec3::Y, centre.view, l, ALBEDO, ROUGHNESS, 0.0, 0.04, true);
        let lit = (brdf.diffuse + brdf.specular) * radiance;
        // The sun is bright enough that lit and unlit differ clearly.
        assert!((lit - ALBEDO).abs().max_element() > 0.1, "{lit}");
        let want = lit.lerp(ALBEDO, strength);
        assert_close(centre.lit, want, &format!("unlit {strength}"));
    }
}
