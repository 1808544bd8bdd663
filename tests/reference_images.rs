//! Rendered images against the references in `tests/reference/`.
//!
//! Tolerance: a pixel matches when every channel is within 4/255 of the
//! reference (8-bit, as written); at least 99% of pixels must match. The
//! slack is for rasterizers that differ on edge pixels, not for drift.
//! Regenerate after an intended change with
//! `SPREADLIGHT_BLESS=1 cargo test -p spreadlight-tests --test reference_images`
//! and look at the new images before committing them.

use std::path::PathBuf;

use spreadlight_render::image_io::{Encoding, write_image};
use spreadlight_tests::{render_patch, root};

const CHANNEL_TOLERANCE: i32 = 4;
const MATCHING_FRACTION: f64 = 0.99;

fn check(name: &str, patch: &str, output: &str, size: (u32, u32), frame: u64) {
    let image = render_patch(&root().join(patch), size, frame, output);
    assert!(image.all_finite());
    let reference: PathBuf = root().join("tests/reference").join(format!("{name}.png"));
    let rendered =
        std::env::temp_dir().join(format!("spreadlight-{name}-{}.png", std::process::id()));
    write_image(&image, &rendered, Encoding::Srgb).expect("write");
    if std::env::var_os("SPREADLIGHT_BLESS").is_some() {
        std::fs::create_dir_all(reference.parent().expect("folder")).expect("mkdir");
        std::fs::copy(&rendered, &reference).expect("bless");
        return;
    }
    let want = image::open(&reference)
        .unwrap_or_else(|e| {
            panic!(
                "{}: {e}; create it with SPREADLIGHT_BLESS=1",
                reference.display()
            )
        })
        .to_rgba8();
    let got = image::open(&rendered).expect("re-read").to_rgba8();
    assert_eq!(
        want.dimensions(),
        got.dimensions(),
        "{name}: size differs from the reference"
    );
    let matching = want
        .pixels()
        .zip(got.pixels())
        .filter(|(a, b)| {
            a.0.iter()
                .zip(b.0.iter())
                .all(|(x, y)| (i32::from(*x) - i32::from(*y)).abs() <= CHANNEL_TOLERANCE)
        })
        .count();
    let fraction = matching as f64 / want.pixels().len() as f64;
    assert!(
        fraction >= MATCHING_FRACTION,
        "{name}: only {:.2}% of pixels match {} (rendered: {})",
        fraction * 100.0,
        reference.display(),
        rendered.display()
    );
    let _ = std::fs::remove_file(&rendered);
}

#[test]
fn gbuffer_spheres_normals() {
    check(
        "gbuffer-spheres-normals",
        "patches/gbuffer-spheres.ron",
        "normals",
        (160, 90),
        0,
    );
}

#[test]
fn bench_scene_normals() {
    check(
        "bench-gbuffer-normals",
        "patches/bench-gbuffer.ron",
        "normals",
        (160, 90),
        0,
    );
}

#[test]
fn bench_lights_lit() {
    check(
        "bench-lights-lit",
        "patches/bench-lights.ron",
        "bench",
        (160, 90),
        0,
    );
}

#[test]
fn showcase_all_three_light_types() {
    check("showcase", "patches/showcase.ron", "showcase", (160, 90), 0);
}

#[test]
fn matcaps_beside_pbr_materials() {
    check("matcap", "patches/matcap.ron", "matcap", (160, 90), 0);
}

#[test]
fn shadows_of_all_three_light_types() {
    check("shadows", "patches/shadows.ron", "showcase", (160, 90), 0);
}

/// The post chain (Transparency, DOF with Autofocus, MotionBlur on the moving
/// ball, Glare, TAA over the jittered camera, Tonemap) over the lit showcase,
/// at the first frame (TAA's history fresh), once it has settled and later.
#[test]
fn post_chain_over_several_frames() {
    for frame in [0, 8, 30] {
        check(
            &format!("post-frame-{frame}"),
            "patches/post.ron",
            "post",
            (160, 90),
            frame,
        );
    }
}

/// Every shipped shader node example (shaders/nodes/, docs/shader-nodes.md)
/// over the procedural noise, at frame 2 (the feedback has a trail, the eye
/// adaptation has blended twice).
#[test]
fn shader_node_examples() {
    for output in [
        "noise",
        "blur",
        "edges",
        "aberration",
        "graded",
        "feedback",
        "eye",
    ] {
        check(
            &format!("shader-{output}"),
            "patches/shader-nodes.ron",
            output,
            (48, 27),
            2,
        );
    }
}

/// The material shader node example (patches/shader-material.ron): three
/// spheres shaded by `ProceduralMaterial (Shader)`'s surface function in
/// the G-buffer resolve, lit by a sun, and the G-buffer's albedo.
#[test]
fn shader_material_example() {
    for (name, output) in [
        ("shader-material", "material"),
        ("shader-material-albedo", "albedo"),
    ] {
        check(name, "patches/shader-material.ron", output, (160, 90), 0);
    }
}

/// Particles in a curl-noise field (issue 17): lit by the sun, casting its
/// shadow, motion-blurred through Velocity From Geometry; frame 30 of a
/// fixed seed at 60 fps, so the same particles every run.
#[test]
fn particles_in_a_curl_noise_field() {
    check(
        "particles",
        "patches/particles.ron",
        "particles",
        (160, 90),
        30,
    );
}

/// The GPU geometry nodes (issue 17): a sphere PN-tessellated, its faces
/// extruded by a spread of amounts, then spherized by an LFO (so it deforms,
/// with velocity from geometry into MotionBlur), a tube and a subdivided
/// ribbon along splines, lit and shadowed; frame 20.
#[test]
fn geometry_nodes_extrude_and_spherize() {
    check(
        "geometry",
        "patches/geometry.ron",
        "geometry",
        (160, 90),
        20,
    );
}

/// A video texture on a deferred-lit surface (issue 37): frame 30 at 60 fps,
/// so the shipped test clip's frame at 0.5 s (its frame 15), shadowed by a
/// sphere; frame-exact, so the same every run.
#[test]
fn video_texture_on_a_lit_surface() {
    check(
        "video-surface",
        "patches/video-surface.ron",
        "video-surface",
        (160, 90),
        30,
    );
}
