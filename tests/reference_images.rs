//! Rendered images against the float references in `tests/reference/`.
//!
//! Every example patch with an Output (the whole frames, the bench patches,
//! the shader-node examples) is rendered through the runtime at a fixed
//! 60 fps at a small size, and each chosen Output's linear float image is
//! compared with `tests/reference/NAME.exr` (half float): per channel,
//! `|got - expected| <= absolute + relative * |expected|`, and at most a
//! stated share of pixels outside that. Each case below states its
//! tolerance and why (`spreadlight_tests::float_compare`). A failure names
//! the worst pixels and leaves the rendered image, the reference and a
//! difference image in `target/tmp/reference-images/NAME/`.
//!
//! Re-make the references after an intended change with
//! `SPREADLIGHT_BLESS=1 cargo test --workspace --test workspace -- reference_images::`
//! and look at each `target/tmp/reference-images/NAME/rendered.png` before
//! committing them.

use std::collections::BTreeSet;
use std::path::PathBuf;

use spreadlight_graph::{NodeDoc, NodeId, Patch, Spread, format};
use spreadlight_tests::float_compare::{BLESS, References, Tolerance, read_exr};
use spreadlight_tests::{PatchRun, example_patches, root};

/// The Output `output` of a case's patch at frame `frame`, checked against
/// `tests/reference/NAME.exr`.
struct Shot {
    name: &'static str,
    output: &'static str,
    frame: u64,
    tolerance: Tolerance,
}

/// A patch rendered once, from frame 0 to its last shot, at `size`, after
/// `edit` changed it.
struct Case {
    patch: &'static str,
    size: (u32, u32),
    edit: fn(&mut Patch),
    shots: &'static [Shot],
}

/// Values written from geometry alone (G-buffer normals, albedo): the same
/// arithmetic everywhere, so only pixels on an edge that another rasterizer
/// covers differently may be off.
const GEOMETRY_DATA: Tolerance = Tolerance {
    absolute: 0.01,
    relative: 0.002,
    outliers: 0.01,
    why: "data from geometry: only silhouette pixels may differ",
};

/// Lit, shadowed frames: BRDF and light-loop arithmetic (pow, exp, fused
/// multiply-adds) rounds differently between drivers, and a shadow map's
/// texels flip at a shadow's edge, so 3% of the value and a few edge pixels.
const LIT: Tolerance = Tolerance {
    absolute: 0.01,
    relative: 0.03,
    outliers: 0.02,
    why: "lighting rounds differently between drivers; silhouettes and shadow edges move by a pixel",
};

/// Lit frames through temporal post (TAA's jittered history, DOF, motion
/// blur, glare): each frame blends earlier ones, so a difference carries
/// on and spreads over a few pixels.
const POST: Tolerance = Tolerance {
    absolute: 0.02,
    relative: 0.05,
    outliers: 0.03,
    why: "temporal filters carry and spread a lit frame's small differences",
};

/// GPU simulations integrated for many frames (particles): the state is
/// deterministic for a seed, but a rounding difference moves a particle of a
/// pixel's size to the next pixel. Few pixels free all the same: the
/// particles cover only a few dozen pixels, and more would hide them.
const SIMULATION: Tolerance = Tolerance {
    absolute: 0.02,
    relative: 0.05,
    outliers: 0.005,
    why: "integrated state: a particle a pixel wide may land one pixel over",
};

/// Geometry deformed on the GPU (skinning, morph targets), seen as normals:
/// the blend of joint matrices rounds differently between drivers by a
/// little more than geometry that is drawn as it is stored.
const DEFORMED: Tolerance = Tolerance {
    absolute: 0.01,
    relative: 0.01,
    outliers: 0.01,
    why: "skinned normals: joint blends round differently; only silhouettes move",
};

/// Image filters in compute shaders over procedural noise: hashes and
/// filters of exactly stored values, nearly the same arithmetic everywhere.
const FILTER: Tolerance = Tolerance {
    absolute: 0.005,
    relative: 0.01,
    outliers: 0.01,
    why: "compute filters over procedural noise: little more than rounding",
};

fn unchanged(_: &mut Patch) {}

/// The particle benchmark's particles 0.25 units wide instead of 0.02: at the
/// benchmark's 20 units' distance those are sub-pixel at 64x36, and its
/// velocity view would show 6 of 2,304 pixels, too few for a reference.
fn visible_particles(patch: &mut Patch) {
    let particles = patch
        .node_mut(NodeId(3))
        .expect("bench-particles.ron's Particles is node 3");
    assert_eq!(particles.type_name, "Particles");
    particles
        .values
        .insert("Size".to_owned(), Spread::Float(vec![0.25]));
}

/// The skinning benchmark's G-buffer normals as a second Output: its own
/// image is metallic tubes lit by one sun and no environment, a few
/// highlights a pixel wide at 64x36, too few for a reference; the normals
/// show every tube's pose.
fn skinned_normals(patch: &mut Patch) {
    let base = patch
        .node(NodeId(5))
        .expect("bench-skinning.ron's MRE is node 5");
    assert_eq!(base.type_name, "MRE");
    patch.add(
        NodeDoc::new(100, "GBufferView").with("Channel", Spread::Enum(vec!["Normals".to_owned()])),
    );
    patch.add(NodeDoc::new(101, "Output").with("Name", Spread::String(vec!["normals".to_owned()])));
    patch.link(5, "G-Buffer", 100, "G-Buffer");
    patch.link(100, "Texture", 101, "Texture");
}

/// The shader-node examples with the noise drifting 150 times as fast as the
/// example's 0.2 cells a second: the Feedback node keeps the brighter of
/// its input and its fading last frame, so only a noise that moves leaves a
/// trail a test can see (at the example's speed the trail is a tenth of a
/// pixel behind and the feedback image is the noise's).
fn fast_noise(patch: &mut Patch) {
    let noise = patch
        .node_mut(NodeId(1))
        .expect("shader-nodes.ron's Noise (Shader) is node 1");
    assert_eq!(noise.type_name, "Noise (Shader)");
    noise
        .values
        .insert("Speed".to_owned(), Spread::Float(vec![NOISE_SPEED]));
}

/// 0.5 cells a frame, about 3 pixels at 48x27: a blob moves away from its
/// last place faster than the trail fades (by 0.9 a frame).
const NOISE_SPEED: f32 = 30.0;

/// The frame the shader-node examples are rendered at: half a second,
/// long past the trail's first frames.
const SHADER_FRAME: u64 = 30;

const SCENE: (u32, u32) = (64, 36);

static CASES: &[Case] = &[
    Case {
        patch: "patches/gbuffer-spheres.ron",
        size: SCENE,
        edit: unchanged,
        shots: &[Shot {
            name: "gbuffer-spheres-normals",
            output: "normals",
            frame: 0,
            tolerance: GEOMETRY_DATA,
        }],
    },
    Case {
        patch: "patches/bench-gbuffer.ron",
        size: SCENE,
        edit: unchanged,
        shots: &[Shot {
            name: "bench-gbuffer-normals",
            output: "normals",
            frame: 0,
            tolerance: GEOMETRY_DATA,
        }],
    },
    Case {
        patch: "patches/bench-lights.ron",
        size: SCENE,
        edit: unchanged,
        shots: &[Shot {
            name: "bench-lights-lit",
            output: "bench",
            frame: 0,
            tolerance: LIT,
        }],
    },
    Case {
        patch: "patches/bench-transparency.ron",
        size: SCENE,
        edit: unchanged,
        shots: &[Shot {
            name: "bench-transparency",
            output: "bench",
            frame: 0,
            tolerance: LIT,
        }],
    },
    Case {
        patch: "patches/showcase.ron",
        size: SCENE,
        edit: unchanged,
        shots: &[Shot {
            name: "showcase",
            output: "showcase",
            frame: 0,
            tolerance: LIT,
        }],
    },
    Case {
        patch: "patches/matcap.ron",
        size: SCENE,
        edit: unchanged,
        shots: &[Shot {
            name: "matcap",
            output: "matcap",
            frame: 0,
            tolerance: LIT,
        }],
    },
    // Thin films on three balls: CookTorrance's sun highlight and
    // Reflection's sky through the film's Fresnel (pow, exp, cos in the
    // XYZ fit: lighting arithmetic).
    Case {
        patch: "patches/iridescence.ron",
        size: SCENE,
        edit: unchanged,
        shots: &[Shot {
            name: "iridescence",
            output: "iridescence",
            frame: 0,
            tolerance: LIT,
        }],
    },
    // The mirror ball reflecting the red box through an EnvironmentProbe
    // (box-projected), at the first frame: the probe's faces are lit by its
    // own ambient and sun, so the same lighting tolerance.
    Case {
        patch: "patches/environment-probe.ron",
        size: SCENE,
        edit: unchanged,
        shots: &[Shot {
            name: "environment-probe",
            output: "environment-probe",
            frame: 0,
            tolerance: LIT,
        }],
    },
    Case {
        patch: "patches/shadows.ron",
        size: SCENE,
        edit: unchanged,
        shots: &[Shot {
            name: "shadows",
            output: "showcase",
            frame: 0,
            tolerance: LIT,
        }],
    },
    // The shadows scene with three glass balls lit forward+ by its three
    // light buffers and their shadow maps (Transparency's Lights and Shadows).
    Case {
        patch: "patches/lit-transparency.ron",
        size: SCENE,
        edit: unchanged,
        shots: &[Shot {
            name: "lit-transparency",
            output: "lit-transparency",
            frame: 0,
            tolerance: LIT,
        }],
    },
    // The post chain (Transparency, DOF with Autofocus, MotionBlur on the
    // moving ball, Glare, TAA over the jittered camera, Tonemap) over the lit
    // showcase: at the first frame (TAA's history fresh), once it has
    // settled and later.
    Case {
        patch: "patches/post.ron",
        size: SCENE,
        edit: unchanged,
        shots: &[
            Shot {
                name: "post-frame-0",
                output: "post",
                frame: 0,
                tolerance: POST,
            },
            Shot {
                name: "post-frame-8",
                output: "post",
                frame: 8,
                tolerance: POST,
            },
            Shot {
                name: "post-frame-30",
                output: "post",
                frame: 30,
                tolerance: POST,
            },
        ],
    },
    // Every shipped shader-node example (shaders/nodes/, docs/shader-nodes.md)
    // over the procedural noise (its Color B is 2.0: half the pixels are
    // above 1), with a noise that moves (`fast_noise`).
    Case {
        patch: "patches/shader-nodes.ron",
        size: (48, 27),
        edit: fast_noise,
        shots: &[
            Shot {
                name: "shader-noise",
                output: "noise",
                frame: SHADER_FRAME,
                tolerance: FILTER,
            },
            Shot {
                name: "shader-blur",
                output: "blur",
                frame: SHADER_FRAME,
                tolerance: FILTER,
            },
            Shot {
                name: "shader-edges",
                output: "edges",
                frame: SHADER_FRAME,
                tolerance: FILTER,
            },
            Shot {
                name: "shader-aberration",
                output: "aberration",
                frame: SHADER_FRAME,
                tolerance: FILTER,
            },
            Shot {
                name: "shader-graded",
                output: "graded",
                frame: SHADER_FRAME,
                tolerance: FILTER,
            },
            Shot {
                name: "shader-feedback",
                output: "feedback",
                frame: SHADER_FRAME,
                tolerance: FILTER,
            },
            // The eye adaptation blends the scene's mean luminance over
            // frames: the exposure carries 30 frames of history.
            Shot {
                name: "shader-eye",
                output: "eye",
                frame: SHADER_FRAME,
                tolerance: Tolerance {
                    absolute: 0.005,
                    relative: 0.02,
                    outliers: 0.01,
                    why: "an exposure adapted over 30 frames scales every pixel: 2% for its carried rounding",
                },
            },
        ],
    },
    // The material shader-node example: three spheres shaded by
    // `ProceduralMaterial (Shader)`'s surface function in the G-buffer
    // resolve, lit by a sun, and the G-buffer's albedo.
    Case {
        patch: "patches/shader-material.ron",
        size: SCENE,
        edit: unchanged,
        shots: &[
            Shot {
                name: "shader-material",
                output: "material",
                frame: 0,
                tolerance: LIT,
            },
            Shot {
                name: "shader-material-albedo",
                output: "albedo",
                frame: 0,
                tolerance: GEOMETRY_DATA,
            },
        ],
    },
    // A custom material feature (id 16, set by the AddRimLight module) shaded
    // by `RimLight (Shader)` through the material world library: rims on the
    // outer balls, none on the middle one (docs/materials.md).
    Case {
        patch: "patches/custom-feature.ron",
        size: SCENE,
        edit: unchanged,
        shots: &[Shot {
            name: "custom-feature",
            output: "custom-feature",
            frame: 0,
            tolerance: LIT,
        }],
    },
    // `ToonLights (Shader)`, a light shader node, in place of CookTorrance
    // for two shadowed point lights and a shadowed sun.
    Case {
        patch: "patches/toon-lights.ron",
        size: SCENE,
        edit: unchanged,
        shots: &[Shot {
            name: "toon-lights",
            output: "toon",
            frame: 0,
            tolerance: LIT,
        }],
    },
    // `AshikhminShirley (Shader)`, the anisotropic Phong light shader node,
    // in place of CookTorrance for the toon example's lights.
    Case {
        patch: "patches/ashikhmin-shirley.ron",
        size: SCENE,
        edit: unchanged,
        shots: &[Shot {
            name: "ashikhmin-shirley",
            output: "ashikhmin-shirley",
            frame: 0,
            tolerance: LIT,
        }],
    },
    // Particles in a curl-noise field: lit by the sun, casting its shadow,
    // motion-blurred through Velocity From Geometry; frame 30 of a fixed
    // seed, so the same particles every run.
    Case {
        patch: "patches/particles.ron",
        size: SCENE,
        edit: unchanged,
        shots: &[Shot {
            name: "particles",
            output: "particles",
            frame: 30,
            tolerance: SIMULATION,
        }],
    },
    // The GPU geometry nodes: a sphere PN-tessellated, its faces extruded by
    // a spread of amounts, then spherized by an LFO (velocity from geometry
    // into MotionBlur), a tube and a subdivided ribbon along splines, lit and
    // shadowed; frame 20.
    Case {
        patch: "patches/geometry.ron",
        size: SCENE,
        edit: unchanged,
        shots: &[Shot {
            name: "geometry",
            output: "geometry",
            frame: 20,
            tolerance: POST,
        }],
    },
    // The flagship frame (docs/benchmarks.md): 1,000 lights, sun and spot
    // shadows, SSAO, sky reflections, SSR, DOF and motion blur on the moving
    // ball. Frame 3, the last of the four frames tests/patches.rs evaluates
    // (not the 120 of the other examples): a frame costs about 0.8 s of CPU
    // on lavapipe even at 64x36 (its six 1024 shadow maps are re-rendered as
    // the ball moves), so frame 119 would add a minute and a half to CI's
    // 15; the ball already moves from frame 1, with its shadows and blur.
    Case {
        patch: "patches/emeshe-frame.ron",
        size: SCENE,
        edit: unchanged,
        shots: &[Shot {
            name: "emeshe-frame",
            output: "bench",
            frame: 3,
            tolerance: POST,
        }],
    },
    // The heavy frame (issue 33's benchmark weight): 2,000 lights, eight
    // PCSS spot shadows, a four-cascade VSM sun, SAO times HBAO, SSGI, SSR,
    // SSSS, fog, TAA, DOF, motion blur and glare. Frame 3 for the reason the
    // Emeshe frame's is: the four frames tests/patches.rs evaluates.
    Case {
        patch: "patches/emeshe-heavy.ron",
        size: SCENE,
        edit: unchanged,
        shots: &[Shot {
            name: "emeshe-heavy",
            output: "bench",
            frame: 3,
            tolerance: POST,
        }],
    },
    Case {
        patch: "patches/bench-gltf.ron",
        size: SCENE,
        edit: unchanged,
        shots: &[Shot {
            name: "bench-gltf",
            output: "output",
            frame: 0,
            tolerance: LIT,
        }],
    },
    // Four metal discs, anisotropy strength 0 to 1 over a circular brush
    // map, each lit by a point light: the anisotropic lobe's arithmetic.
    Case {
        patch: "patches/brushed-metal.ron",
        size: SCENE,
        edit: unchanged,
        shots: &[Shot {
            name: "brushed-metal",
            output: "output",
            frame: 0,
            tolerance: LIT,
        }],
    },
    Case {
        patch: "patches/bench-particles.ron",
        size: SCENE,
        edit: visible_particles,
        shots: &[Shot {
            name: "bench-particles",
            output: "particles",
            frame: 30,
            tolerance: SIMULATION,
        }],
    },
    Case {
        patch: "patches/bench-tessellation.ron",
        size: SCENE,
        edit: unchanged,
        shots: &[Shot {
            name: "bench-tessellation",
            output: "tessellation",
            frame: 0,
            tolerance: LIT,
        }],
    },
    Case {
        patch: "patches/bench-builtin-blur.ron",
        size: SCENE,
        edit: unchanged,
        shots: &[Shot {
            name: "bench-builtin-blur",
            output: "builtin",
            frame: 0,
            tolerance: FILTER,
        }],
    },
    // 200 passes, each turning the one before's 64x64 image: exact
    // arithmetic on a ramp, in either recording mode.
    Case {
        patch: "patches/bench-pass-chain.ron",
        size: SCENE,
        edit: unchanged,
        shots: &[Shot {
            name: "bench-pass-chain",
            output: "chain",
            frame: 0,
            tolerance: FILTER,
        }],
    },
    Case {
        patch: "patches/bench-shader-blur.ron",
        size: SCENE,
        edit: unchanged,
        shots: &[Shot {
            name: "bench-shader-blur",
            output: "shader",
            frame: 0,
            tolerance: FILTER,
        }],
    },
    // 100 skinned and morphed tubes, deformed on the GPU; frame 3, posed.
    Case {
        patch: "patches/audio-reactive.ron",
        size: SCENE,
        edit: unchanged,
        shots: &[Shot {
            name: "audio-reactive",
            output: "audio-reactive",
            frame: 33,
            // Lights set by the analysed sound, and a particle burst.
            tolerance: SIMULATION,
        }],
    },
    Case {
        patch: "patches/video-surface.ron",
        size: SCENE,
        edit: unchanged,
        shots: &[Shot {
            name: "video-surface",
            output: "video-surface",
            frame: 30,
            tolerance: LIT,
        }],
    },
    Case {
        patch: "patches/bench-skinning.ron",
        size: SCENE,
        edit: skinned_normals,
        shots: &[Shot {
            name: "bench-skinning-normals",
            output: "normals",
            frame: 3,
            tolerance: DEFORMED,
        }],
    },
];

fn references() -> References {
    References {
        folder: root().join("tests/reference"),
        artifacts: PathBuf::from(env!("CARGO_TARGET_TMPDIR")).join("reference-images"),
    }
}

/// Render `patch`'s case once and check each of its shots at its frame.
fn check(patch: &str) {
    check_on(patch, |_| {});
}

/// [`check`] on a renderer that `setup` set (its recording mode).
fn check_on(patch: &str, setup: impl FnOnce(&spreadlight_render::Renderer)) {
    let case = CASES
        .iter()
        .find(|c| c.patch == patch)
        .unwrap_or_else(|| panic!("no case for {patch}"));
    let references = references();
    let mut shots: Vec<&Shot> = case.shots.iter().collect();
    shots.sort_by_key(|s| s.frame);
    let mut run = PatchRun::new(&root().join(case.patch), case.size, case.edit);
    setup(run.renderer());
    let mut failures = Vec::new();
    for shot in shots {
        run.run_to(shot.frame);
        let (image, encoding) = run.image(shot.output);
        assert!(image.all_finite(), "{}: NaN or infinity", shot.name);
        // Check every shot before failing, so one run reports them all.
        if let Err(report) = references.try_check(shot.name, &image, encoding, &shot.tolerance) {
            failures.push(report);
        }
    }
    assert!(failures.is_empty(), "{}", failures.join("\n\n"));
}

#[test]
fn gbuffer_spheres_normals() {
    check("patches/gbuffer-spheres.ron");
}

#[test]
fn bench_gbuffer_normals() {
    check("patches/bench-gbuffer.ron");
}

#[test]
fn bench_lights_lit() {
    check("patches/bench-lights.ron");
}

#[test]
fn bench_transparency_glass_under_a_thousand_lights() {
    check("patches/bench-transparency.ron");
}

#[test]
fn showcase_all_three_light_types() {
    check("patches/showcase.ron");
}

#[test]
fn brushed_metal_discs_of_four_anisotropy_strengths() {
    check("patches/brushed-metal.ron");
}

#[test]
fn matcaps_beside_pbr_materials() {
    check("patches/matcap.ron");
}

#[test]
fn thin_films_on_a_bubble_an_oil_slick_and_a_metal() {
    check("patches/iridescence.ron");
}

#[test]
fn environment_probe_mirror_beside_a_red_box() {
    check("patches/environment-probe.ron");
}

#[test]
fn shadows_of_all_three_light_types() {
    check("patches/shadows.ron");
}

#[test]
fn glass_lit_by_the_scenes_lights_and_shadows() {
    check("patches/lit-transparency.ron");
}

#[test]
fn post_chain_over_several_frames() {
    check("patches/post.ron");
}

#[test]
fn shader_node_examples() {
    check("patches/shader-nodes.ron");
}

#[test]
fn shader_material_example() {
    check("patches/shader-material.ron");
}

#[test]
fn custom_feature_example() {
    check("patches/custom-feature.ron");
}

#[test]
fn toon_lights_example() {
    check("patches/toon-lights.ron");
}

#[test]
fn ashikhmin_shirley_example() {
    check("patches/ashikhmin-shirley.ron");
}

#[test]
fn particles_in_a_curl_noise_field() {
    check("patches/particles.ron");
}

#[test]
fn geometry_nodes_extrude_and_spherize() {
    check("patches/geometry.ron");
}

#[test]
fn emeshe_frame() {
    check("patches/emeshe-frame.ron");
}

#[test]
fn emeshe_heavy() {
    check("patches/emeshe-heavy.ron");
}

#[test]
fn bench_gltf() {
    check("patches/bench-gltf.ron");
}

#[test]
fn bench_particles() {
    check("patches/bench-particles.ron");
}

#[test]
fn bench_tessellation() {
    check("patches/bench-tessellation.ron");
}

#[test]
fn bench_builtin_blur() {
    check("patches/bench-builtin-blur.ron");
}

/// The 200-pass chain renders the same, the reference, whether each pass
/// records into its own encoder or the frame into one (with its dispatches
/// sharing compute passes), timed per pass or not at all.
#[test]
fn bench_pass_chain_in_every_recording_mode() {
    use spreadlight_render::renderer::{Recording, Timing};
    for (recording, timing) in [
        (Recording::Isolated, Timing::PerPass),
        (Recording::Batched, Timing::PerPass),
        (Recording::Batched, Timing::Off),
    ] {
        check_on("patches/bench-pass-chain.ron", |renderer| {
            renderer.set_recording(recording);
            renderer.set_timing(timing);
        });
    }
}

#[test]
fn bench_shader_blur() {
    check("patches/bench-shader-blur.ron");
}

#[test]
fn bench_skinning() {
    check("patches/bench-skinning.ron");
}

/// Every example with an Output has a case (a new example fails here until
/// it gets a reference), every case's patch exists, and every file in
/// `tests/reference/` is a shot's: none left over from a renamed case.
#[test]
fn every_example_with_an_output_has_a_reference() {
    let cased: BTreeSet<&str> = CASES.iter().map(|c| c.patch).collect();
    assert_eq!(cased.len(), CASES.len(), "a patch has two cases");
    for path in example_patches() {
        let patch = format::load(&path).unwrap_or_else(|e| panic!("{e}"));
        let relative = format!(
            "patches/{}",
            path.file_name()
                .and_then(|n| n.to_str())
                .unwrap_or_default()
        );
        let has_output = patch.nodes.iter().any(|n| n.type_name == "Output");
        assert_eq!(
            has_output,
            cased.contains(relative.as_str()),
            "{relative}: an example with an Output needs a case in tests/reference_images.rs, and only those"
        );
    }
    let shots: BTreeSet<String> = CASES
        .iter()
        .flat_map(|c| c.shots.iter().map(|s| format!("{}.exr", s.name)))
        .collect();
    let files: BTreeSet<String> = std::fs::read_dir(root().join("tests/reference"))
        .expect("tests/reference")
        .filter_map(|e| e.ok()?.file_name().into_string().ok())
        .filter(|n| !n.starts_with("view-"))
        .collect();
    assert_eq!(
        files, shots,
        "tests/reference/ holds exactly the shots' references (view-*.png are crates/cli/tests/view.rs')"
    );
}

/// Sound driving light and particles (issue 37): at 0.55 s, just after the
/// second beat of the example's loop, the spectrum sets four point lights and
/// the envelope a particle burst (the file is analysed at each frame's time).
#[test]
fn audio_reactive_lights_and_particles() {
    check("patches/audio-reactive.ron");
}

/// The feedback reference shows the feedback: the Feedback node keeps the
/// brighter of the noise and its own fading last frame, so its image is
/// never below the noise's and is well above it behind every moving blob.
/// (Its old 8-bit reference was the noise's, byte for byte.)
#[test]
fn the_feedback_reference_shows_a_trail() {
    if std::env::var_os(BLESS).is_some() {
        // Being re-made side by side by shader_node_examples.
        return;
    }
    let folder = root().join("tests/reference");
    let noise = read_exr(&folder.join("shader-noise.exr")).unwrap_or_else(|e| panic!("{e}"));
    let feedback = read_exr(&folder.join("shader-feedback.exr")).unwrap_or_else(|e| panic!("{e}"));
    let luminance = |p: &[f32; 4]| 0.2126 * p[0] + 0.7152 * p[1] + 0.0722 * p[2];
    let mut below = 0;
    let mut trail = 0;
    let (mut sum_noise, mut sum_gain) = (0.0f64, 0.0f64);
    for (n, f) in noise.pixels.iter().zip(&feedback.pixels) {
        // The same half-float rounding of the same value, or brighter.
        if (0..3).any(|c| f[c] < n[c] - 2e-3 * n[c].abs()) {
            below += 1;
        }
        let gain = luminance(f) - luminance(n);
        if gain > 0.1 {
            trail += 1;
        }
        sum_noise += f64::from(luminance(n));
        sum_gain += f64::from(gain);
    }
    let pixels = noise.pixels.len();
    assert_eq!(
        below, 0,
        "the feedback is below its input at {below} pixels"
    );
    assert!(
        trail * 5 >= pixels,
        "only {trail} of {pixels} feedback pixels are 0.1 brighter than the noise: no visible trail"
    );
    assert!(
        sum_gain >= 0.1 * sum_noise,
        "the feedback is only {:.1}% brighter than the noise on average",
        100.0 * sum_gain / sum_noise
    );
}

/// The comparison itself, on images made up here.
mod comparison {
    use spreadlight_render::readback::ImageF32;
    use spreadlight_tests::float_compare::{
        Tolerance, compare, read_exr, report, to_half, write_exr,
    };

    fn image(pixels: Vec<[f32; 4]>, width: u32) -> ImageF32 {
        ImageF32 {
            width,
            height: pixels.len() as u32 / width,
            pixels,
        }
    }

    const TOLERANCE: Tolerance = Tolerance {
        absolute: 0.01,
        relative: 0.01,
        outliers: 0.25,
        why: "test",
    };

    /// A change above 1.0 is seen (an 8-bit sRGB comparison clips both
    /// values to 255), and the worst pixel is named with its values.
    #[test]
    fn values_above_one_are_compared() {
        let expected = image(vec![[4.0, 2.0, 0.5, 1.0]; 4], 2);
        let mut got = expected.clone();
        got.pixels[3] = [5.0, 2.0, 0.5, 1.0];
        let c = compare(&expected, &got, &TOLERANCE);
        assert_eq!(c.outside, 1);
        assert_eq!((c.worst[0].x, c.worst[0].y), (1, 1));
        assert_eq!(c.worst[0].difference()[0], 1.0);
        // 1.0 against a slack of 0.01 + 0.01 * 4.0.
        assert!(
            (c.worst[0].excess - 20.0).abs() < 1e-3,
            "{}",
            c.worst[0].excess
        );
        let text = report("t", &c, &TOLERANCE);
        assert!(
            text.contains("1,   1: (4.0000, 2.0000, 0.5000, 1.0000) -> (5.0000"),
            "{text}"
        );
        // One of four pixels is within the 25% allowed; a second is not.
        assert!(c.passes(&TOLERANCE));
        got.pixels[0][1] = f32::NAN;
        let c = compare(&expected, &got, &TOLERANCE);
        assert_eq!(c.outside, 2);
        assert!(!c.passes(&TOLERANCE));
        assert!(c.worst[0].excess.is_infinite());
    }

    /// The relative slack grows with the value: 2% off passes at 0.5 only
    /// through the absolute part, and at 8.0 fails with it.
    #[test]
    fn the_slack_is_absolute_plus_relative() {
        let expected = image(vec![[0.5, 8.0, 0.0, 1.0]], 1);
        let got = image(vec![[0.51, 8.0, 0.0, 1.0]], 1);
        assert_eq!(compare(&expected, &got, &TOLERANCE).outside, 0);
        let got = image(vec![[0.5, 8.0 * 1.02, 0.0, 1.0]], 1);
        assert_eq!(compare(&expected, &got, &TOLERANCE).outside, 1);
    }

    /// An EXR reference keeps HDR values to a half float's precision.
    #[test]
    fn exr_round_trip_keeps_hdr_values() {
        let dir = std::env::temp_dir().join(format!("spreadlight-exr-{}", std::process::id()));
        std::fs::create_dir_all(&dir).expect("mkdir");
        let path = dir.join("t.exr");
        let original = image(
            vec![
                [0.0, 1e-3, 0.25, 1.0],
                [1.5, 37.0, 1000.0, 0.5],
                [0.2, 0.3, 0.4, 0.0],
            ],
            3,
        );
        write_exr(&original, &path).expect("write");
        let read = read_exr(&path).expect("read");
        assert_eq!((read.width, read.height), (3, 1));
        assert_eq!(read, to_half(&original));
        for (a, b) in read
            .pixels
            .iter()
            .flatten()
            .zip(original.pixels.iter().flatten())
        {
            assert!((a - b).abs() <= 5e-4 * b.abs() + 1e-7, "{a} vs {b}");
        }
        let _ = std::fs::remove_dir_all(&dir);
    }
}

/// A video texture on a deferred-lit surface (issue 37): frame 30 at 60 fps,
/// so the shipped test clip's frame at 0.5 s (its frame 15), shadowed by a
/// sphere; frame-exact, so the same every run.
#[test]
fn video_texture_on_a_lit_surface() {
    check("patches/video-surface.ron");
}
