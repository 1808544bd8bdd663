//! `spreadlight view`: any glTF file in one command. It builds the patch a
//! user would and renders it: the file's materials (AddReflection, so the
//! environment lights every one) uploaded by MaterialBuffer, DeferredBase
//! and MRE with the file's first camera or one framing the model's bounds,
//! the file's own lights (`KHR_lights_punctual`) or else a sun with a
//! shadow, image-based light from the procedural sky (or `--environment`),
//! the sky behind, tonemapped; or, with `--channel`, a G-buffer view;
//! `--variant` shows a `KHR_materials_variants` variant (the glTF nodes'
//! Variant pin; an unknown one is a warning listing the file's, and the
//! default materials are shown).
//! A file whose lights give the model more than [`KEY_ILLUMINANCE`] lux
//! (photometric exports: suns of thousands of lux) is exposed down to it
//! ([`file_exposure`]), the sky scaled with it, so it is not burnt white.

use std::path::PathBuf;
use std::process::ExitCode;

use anyhow::Context;
use glam::{Mat4, Vec3};
use spreadlight_gltf::AlphaMode;
use spreadlight_gltf::{SceneLights, load_gltf};
use spreadlight_graph::{NodeDoc, Patch, format};

use crate::session::parse_size;

#[derive(clap::Args)]
pub struct Args {
    /// A .gltf or .glb file.
    model: PathBuf,
    /// The image to write (PNG, or EXR by extension).
    #[arg(short, long)]
    output: PathBuf,
    #[arg(long, default_value = "960x540", value_parser = parse_size)]
    size: (u32, u32),
    /// What to show: Lit (the shaded picture), or a G-buffer channel: Albedo,
    /// Normals, Velocity, UV, Depth, "Material ID", "Object ID".
    #[arg(long, default_value = "Lit")]
    channel: String,
    /// An equirectangular .hdr (or .exr) image to light the model with and show behind it,
    /// instead of the procedural sky.
    #[arg(long)]
    environment: Option<PathBuf>,
    /// Pose the model at this time (seconds) of its first animation (node TRS channels, skins and
    /// morph target weights).
    #[arg(long, default_value_t = 0.0)]
    time: f32,
    /// A KHR_materials_variants variant of the file, by name or index (default: the file's default
    /// materials). An unknown one is a warning naming the file's variants.
    #[arg(long)]
    variant: Option<String>,
    /// Also save the patch this command built, to open and change it.
    #[arg(long)]
    save_patch: Option<PathBuf>,
}

/// A camera looking at `bounds` from the front-right and above, the whole model in view.
pub fn framing(center: Vec3, radius: f32, aspect: f32) -> (Mat4, Mat4) {
    // Any positive size is framed (1e-18 as well as 1e18); none: a unit view.
    let radius = if radius.is_finite() && radius > f32::MIN_POSITIVE * 1e6 {
        radius
    } else {
        1.0
    };
    let fov = 45f32.to_radians();
    // The narrower of the vertical and horizontal half-angles must hold the bounding sphere.
    let horizontal_half = ((fov * 0.5).tan() * aspect.max(1e-3)).atan();
    let fit = (fov * 0.5).min(horizontal_half);
    let distance = radius / fit.sin() * 1.1;
    let eye = center + Vec3::new(0.6, 0.45, 1.0).normalize() * distance;
    let view = glam::camera::rh::view::look_at_mat4(eye, center, Vec3::Y);
    let projection = glam::camera::rh::proj::directx::perspective(
        fov,
        aspect,
        distance * 0.01,
        distance + radius * 4.0,
    );
    (view, projection)
}

/// The sun's direction (towards the ground) in the default lighting.
const SUN_DIRECTION: Vec3 = Vec3::new(-0.4, -1.0, -0.3);

/// The most light (lux at the model) `view` shows a file's lights with as
/// they are: view's own sun is 2 lux with the sky about as much again;
/// three stops above that, a white surface facing the light is near white
/// after ACES. Files lit within this keep their brightness (the generated
/// point-and-spot scene of the tests gives about 11); brighter ones
/// (photometric exports: Blender's suns of 1,000 lux and more, point lights
/// of thousands of candela) are exposed down to it.
pub const KEY_ILLUMINANCE: f32 = 16.0;

/// The illuminance (lux) the file's lights give at `point`, each as if the
/// surface faced it: suns their lux, point lights and spots (where `point`
/// is inside the spot's cone) candela / distance², the distance at least a
/// tenth of the model's `radius` (a light inside the model lights its
/// surface, not its centre). Colours count by their luminance.
pub fn key_illuminance(lights: &SceneLights, point: Vec3, radius: f32) -> f32 {
    let luminance = |c: Vec3| c.dot(Vec3::new(0.2126, 0.7152, 0.0722)).max(0.0);
    let near = (radius * 0.1).max(1e-3);
    let at = |position: Vec3, candela: f32| candela / position.distance(point).max(near).powi(2);
    let suns = lights
        .suns
        .iter()
        .map(|(_, s)| s.illuminance * luminance(s.color));
    let points = lights
        .points
        .iter()
        .map(|(_, p)| at(p.position, p.intensity * luminance(p.color)));
    let spots = lights.spots.iter().map(|(_, s)| {
        let clip = s.projection * s.view * point.extend(1.0);
        let inside = clip.w > 0.0 && clip.x.abs() <= clip.w && clip.y.abs() <= clip.w;
        let position = s.view.inverse().transform_point3(Vec3::ZERO);
        if inside {
            at(position, s.intensity * luminance(s.color))
        } else {
            0.0
        }
    });
    suns.chain(points)
        .chain(spots)
        .filter(|e| !e.is_nan())
        .map(|e| e.max(0.0))
        .sum()
}

/// The Tonemap exposure for a file's lights: 1 up to [`KEY_ILLUMINANCE`]
/// lux at the model, then what brings their light down to it. Always
/// finite and positive (lights of infinite intensity count as f32::MAX).
pub fn file_exposure(lights: &SceneLights, point: Vec3, radius: f32) -> f32 {
    let lux = key_illuminance(lights, point, radius).min(f32::MAX);
    if lux > KEY_ILLUMINANCE {
        (KEY_ILLUMINANCE / lux).max(f32::MIN_POSITIVE)
    } else {
        1.0
    }
}

/// Where the camera is and what it sees, and what lights the scene.
pub struct Framing {
    pub view: Mat4,
    pub projection: Mat4,
    /// The model's bounding radius (for shadow distances).
    pub radius: f32,
    /// Which light types the file brings (point, spot, sun); none: view's sun.
    pub file_lights: [bool; 3],
    /// The animation time the glTF node poses the model at.
    pub time: f32,
    /// The material variant the glTF nodes show (their Variant pin; empty:
    /// the file's default materials).
    pub variant: String,
    /// Whether some instance has a BLEND material (drawn by Transparency).
    pub blend: bool,
    /// Tonemap's exposure ([`file_exposure`]; 1 with view's own sun). The
    /// procedural sky is scaled by its inverse, so it looks as it does
    /// with view's sun while the file's lights are exposed down.
    pub exposure: f32,
}

/// The patch `view` renders, as a user would wire it.
pub fn build_patch(
    model: &std::path::Path,
    framing: &Framing,
    channel: &str,
    environment: Option<&std::path::Path>,
) -> Patch {
    let mut patch = Patch::default();
    let file = model.to_string_lossy().into_owned();
    patch.add(
        NodeDoc::new(1, "glTF")
            .at(0.0, 0.0)
            .with("Filename", vec![file.clone()])
            .with("Time", vec![framing.time])
            .with("Variant", vec![framing.variant.clone()])
            .with(
                "Instances",
                spreadlight_graph::Spread::Enum(vec!["Opaque".to_owned()]),
            ),
    );
    patch.add(
        NodeDoc::new(2, "AddReflection")
            .at(160.0, 0.0)
            .with("Strength", vec![1.0f32]),
    );
    patch.add(NodeDoc::new(3, "MaterialBuffer").at(160.0, 80.0));
    patch.add(NodeDoc::new(4, "DeferredBase").at(0.0, 80.0));
    patch.add(
        NodeDoc::new(5, "MRE")
            .at(0.0, 160.0)
            .with("View", vec![framing.view])
            .with("Projection", vec![framing.projection]),
    );
    patch.link(1, "Materials", 2, "Material");
    patch.link(2, "Material", 3, "Materials");
    patch.link(1, "Mesh", 4, "Mesh");
    patch.link(1, "Transform", 4, "Transform");
    patch.link(1, "Base Color", 4, "Color");
    patch.link(1, "Material ID", 4, "Material ID");
    patch.link(3, "Material World", 4, "Material World");
    patch.link(4, "Layer", 5, "Layer");
    patch.add(NodeDoc::new(20, "Output").at(0.0, 640.0));
    if channel != "Lit" {
        patch.add(NodeDoc::new(6, "GBufferView").at(0.0, 240.0).with(
            "Channel",
            spreadlight_graph::Spread::Enum(vec![channel.to_owned()]),
        ));
        patch.link(5, "G-Buffer", 6, "G-Buffer");
        patch.link(6, "Texture", 20, "Texture");
        return patch;
    }
    // The light buffers (and shadow maps) the opaque scene is lit with
    // light the BLEND materials too.
    let lights = if framing.file_lights.contains(&true) {
        (file_lights(&mut patch, framing.file_lights), None)
    } else {
        sun(&mut patch, framing.radius);
        (vec![8], Some(9))
    };
    image_light(&mut patch, environment, framing.exposure);
    if framing.blend {
        transparent(&mut patch, file, framing, lights);
    } else {
        patch.link(14, "Texture", 15, "Texture");
    }
    patch
}

/// BLEND materials: a second glTF node giving only them, their layer drawn
/// by Transparency over the lit image before tonemapping, with their maps
/// and vertex colours (the layer carries the material world), lit by the
/// scene's light buffers (`lights`: their nodes, and the shadow maps' node).
fn transparent(
    patch: &mut Patch,
    file: String,
    framing: &Framing,
    lights: (Vec<u32>, Option<u32>),
) {
    patch.add(
        NodeDoc::new(40, "glTF")
            .at(800.0, 0.0)
            .with("Filename", vec![file])
            .with("Time", vec![framing.time])
            .with("Variant", vec![framing.variant.clone()])
            .with(
                "Instances",
                spreadlight_graph::Spread::Enum(vec!["Blend".to_owned()]),
            ),
    );
    patch.add(NodeDoc::new(41, "DeferredBase").at(800.0, 80.0));
    patch.add(
        NodeDoc::new(42, "Transparency")
            .at(0.0, 520.0)
            .with("Light Direction", vec![-SUN_DIRECTION]),
    );
    patch.link(40, "Mesh", 41, "Mesh");
    patch.link(40, "Transform", 41, "Transform");
    patch.link(40, "Base Color", 41, "Color");
    // The same world as the opaque layer's (same file, same first id): the
    // Transparency pass samples the base colour texture from it.
    patch.link(40, "Material ID", 41, "Material ID");
    patch.link(3, "Material World", 41, "Material World");
    patch.link(14, "Texture", 42, "Texture");
    patch.link(5, "G-Buffer", 42, "G-Buffer");
    patch.link(41, "Layer", 42, "Layer");
    patch.link(42, "Texture", 15, "Texture");
    // The image-based light the opaque surfaces get (Reflection) lights them too.
    patch.link(11, "Environment", 42, "Environment");
    let (buffers, shadows) = lights;
    if let [only] = buffers[..] {
        patch.link(only, "Lights", 42, "Lights");
    } else if !buffers.is_empty() {
        patch.add(NodeDoc::new(43, "Group (Lights)").at(160.0, 520.0));
        for (i, buffer) in buffers.iter().enumerate() {
            patch.link(*buffer, "Lights", 43, &format!("Lights {}", i + 1));
        }
        patch.link(43, "Lights", 42, "Lights");
    }
    if let Some(shadows) = shadows {
        patch.link(shadows, "Shadows", 42, "Shadows");
    }
}

/// The file's lights: a buffer and a CookTorrance per type it has, their
/// components grouped for CompositeLight (node 13). Returns the buffers' nodes.
fn file_lights(patch: &mut Patch, present: [bool; 3]) -> Vec<u32> {
    let types = [
        ("Point Lights", "PointLightBuffer"),
        ("Spot Lights", "SpotLightBuffer"),
        ("Sun Lights", "SunLightBuffer"),
    ];
    patch.add(NodeDoc::new(16, "Group (Texture)").at(320.0, 320.0));
    patch.add(NodeDoc::new(17, "Group (Texture)").at(480.0, 320.0));
    let used = types.iter().zip(present).filter(|(_, p)| *p);
    let mut buffers = Vec::new();
    for (slot, ((output, buffer), _)) in used.enumerate() {
        let (b, c) = (30 + 2 * slot as u32, 31 + 2 * slot as u32);
        let x = 320.0 + 160.0 * slot as f32;
        patch.add(NodeDoc::new(b, buffer).at(x, 80.0));
        patch.add(NodeDoc::new(c, "CookTorrance").at(x, 240.0));
        patch.link(1, output, b, "Lights");
        patch.link(5, "G-Buffer", c, "G-Buffer");
        patch.link(b, "Lights", c, "Lights");
        patch.link(3, "Material World", c, "Material World");
        let pin = format!("Texture {}", slot + 1);
        patch.link(c, "Diffuse", 16, &pin);
        patch.link(c, "Specular", 17, &pin);
        buffers.push(b);
    }
    patch.link(16, "Texture", 13, "Diffuse");
    patch.link(17, "Texture", 13, "Specular");
    buffers
}

/// A sun from above and behind the camera's right, its shadow covering the model.
fn sun(patch: &mut Patch, radius: f32) {
    patch.add(
        NodeDoc::new(7, "AddLight (Sun)")
            .at(320.0, 0.0)
            .with("ID", vec!["sun".to_owned()])
            .with("Direction", vec![SUN_DIRECTION])
            .with("Illuminance", vec![2.0f32]),
    );
    patch.add(NodeDoc::new(8, "SunLightBuffer").at(320.0, 80.0));
    patch.add(
        NodeDoc::new(9, "ShadowMap (Sun)")
            .at(480.0, 80.0)
            .with("Cascades", vec![1i64])
            .with("Distance", vec![radius * 8.0]),
    );
    patch.add(NodeDoc::new(10, "CookTorrance").at(320.0, 240.0));
    patch.link(7, "Lights", 8, "Lights");
    patch.link(4, "Layer", 9, "Layer");
    patch.link(5, "G-Buffer", 9, "G-Buffer");
    patch.link(7, "Lights", 9, "Lights");
    patch.link(5, "G-Buffer", 10, "G-Buffer");
    patch.link(8, "Lights", 10, "Lights");
    patch.link(3, "Material World", 10, "Material World");
    patch.link(9, "Shadows", 10, "Shadows");
    patch.link(10, "Diffuse", 13, "Diffuse");
    patch.link(10, "Specular", 13, "Specular");
}

/// Image-based light (the environment's irradiance and prefiltered
/// reflection) into CompositeLight, the sky behind (node 14), Tonemap (15)
/// to the Output; the caller links 14 to 15, or through Transparency.
fn image_light(patch: &mut Patch, environment: Option<&std::path::Path>, exposure: f32) {
    // Image-based light: the environment's irradiance and prefiltered reflection.
    let environment_node = match environment {
        Some(file) => NodeDoc::new(11, "Environment (File)")
            .at(640.0, 160.0)
            .with("Filename", vec![file.to_string_lossy().into_owned()]),
        None => NodeDoc::new(11, "Environment (Sky)")
            .at(640.0, 160.0)
            .with("Intensity", vec![(0.5 / exposure).min(f32::MAX)])
            .with("Sun Direction", vec![SUN_DIRECTION]),
    };
    patch.add(environment_node);
    patch.add(NodeDoc::new(12, "Reflection").at(640.0, 240.0));
    patch.link(5, "G-Buffer", 12, "G-Buffer");
    patch.link(3, "Material World", 12, "Material World");
    patch.link(11, "Environment", 12, "Environment");
    patch.add(NodeDoc::new(13, "CompositeLight").at(0.0, 400.0).with(
        "Ambient",
        vec![spreadlight_graph::Color::rgba(0.0, 0.0, 0.0, 1.0)],
    ));
    patch.link(5, "G-Buffer", 13, "G-Buffer");
    patch.link(3, "Material World", 13, "Material World");
    patch.link(12, "Diffuse", 13, "GI");
    patch.link(12, "Specular", 13, "Reflection");
    let mut sky = NodeDoc::new(14, "Sky").at(0.0, 480.0);
    if environment.is_none() {
        sky = sky.with("Sun Direction", vec![SUN_DIRECTION]);
    }
    patch.add(sky);
    patch.link(13, "Texture", 14, "Texture");
    patch.link(5, "G-Buffer", 14, "G-Buffer");
    patch.link(11, "Environment", 14, "Environment");
    let mut tonemap = NodeDoc::new(15, "Tonemap").at(0.0, 560.0).with(
        "Operator",
        spreadlight_graph::Spread::Enum(vec!["ACES".to_owned()]),
    );
    if exposure != 1.0 {
        tonemap = tonemap.with("Exposure", vec![exposure]);
    }
    patch.add(tonemap);
    patch.link(15, "Texture", 20, "Texture");
}

pub fn run(args: &Args) -> anyhow::Result<ExitCode> {
    // Load once here for the bounds (and a clear error before any GPU work).
    let scene = load_gltf(&args.model)?;
    for warning in &scene.warnings {
        eprintln!("{}: {warning}", args.model.display());
    }
    // An image of the sky alone would look like a result: a file none of
    // whose primitives loaded (points and lines only, no triangles) is an
    // error, with the warnings above saying what was skipped.
    if scene.instances.is_empty() {
        let why = if scene.meshes.is_empty() {
            "no primitive of the file loaded as triangles (the warnings above say what was skipped)"
                .to_owned()
        } else {
            format!(
                "the loaded scene places none of its {} triangle mesh(es) (no node of it refers to one)",
                scene.meshes.len()
            )
        };
        anyhow::bail!("{}: nothing to show: {why}", args.model.display());
    }
    // An unknown variant is a warning; the default materials are shown.
    let variant = match args.variant.as_deref().map(|v| scene.variant(v)) {
        None => None,
        Some(Ok(chosen)) => chosen,
        Some(Err(e)) => {
            eprintln!("{}: warning: {e}", args.model.display());
            None
        }
    };
    let radius = scene.bounds.size().length() * 0.5;
    let aspect = args.size.0 as f32 / args.size.1 as f32;
    // The file's first camera, as the file places it at the posed time's
    // rest (its aspect rebuilt for the output when the file states none).
    if let Some(camera) = scene.cameras.first() {
        eprintln!(
            "{}: viewed from camera `{}`",
            args.model.display(),
            camera.name
        );
    }
    let (view, projection) = match scene.cameras.first() {
        Some(camera) => (camera.view, camera.projection_for(aspect)),
        None => framing(scene.bounds.center(), radius, aspect),
    };
    let lights = &scene.lights;
    let model = std::path::absolute(&args.model).unwrap_or_else(|_| args.model.clone());
    let environment = args
        .environment
        .as_ref()
        .map(|e| std::path::absolute(e).unwrap_or_else(|_| e.clone()));
    let framing = Framing {
        view,
        projection,
        radius: if radius.is_finite() && radius > 0.0 {
            radius
        } else {
            1.0
        },
        file_lights: [
            !lights.points.is_empty(),
            !lights.spots.is_empty(),
            !lights.suns.is_empty(),
        ],
        time: args.time,
        // The variant by its name (what a saved patch reads best), or by
        // its index where an earlier variant has the same name.
        variant: variant
            .map(|v| match scene.variant(&scene.variants[v]) {
                Ok(Some(same)) if same == v => scene.variants[v].clone(),
                _ => v.to_string(),
            })
            .unwrap_or_default(),
        blend: scene.instances.iter().any(|i| {
            i.material_in(variant)
                .and_then(|m| scene.materials.get(m))
                .is_some_and(|m| m.alpha_mode == AlphaMode::Blend)
        }),
        exposure: file_exposure(lights, scene.bounds.center(), radius),
    };
    if framing.exposure != 1.0 {
        eprintln!(
            "{}: its lights give the model {:.0} lux; exposed by {:.3e} (down to {KEY_ILLUMINANCE} lux)",
            args.model.display(),
            key_illuminance(lights, scene.bounds.center(), radius),
            framing.exposure
        );
    }
    let patch = build_patch(&model, &framing, &args.channel, environment.as_deref());
    if let Some(path) = &args.save_patch {
        format::save(&patch, path)?;
        eprintln!("saved the patch to {}", path.display());
    }
    let mut session =
        crate::session::Session::from_patch(&patch, &args.model, true, Some(args.size))?;
    if session.load_errors {
        anyhow::bail!(
            "--channel `{}` is not Lit or a G-buffer channel",
            args.channel
        );
    }
    let mut reported = Default::default();
    let failed = session.step(0, 60.0, &args.model, &mut reported);
    let (image, encoding) = session
        .images
        .get("output")
        .context("the model rendered nothing (see the errors above)")?;
    spreadlight_render::image_io::write_image(&image, &args.output, encoding)?;
    eprintln!(
        "wrote {} ({} mesh instances, {} triangles)",
        args.output.display(),
        scene.instances.len(),
        scene
            .instances
            .iter()
            .map(|i| scene.meshes[i.mesh].triangle_count())
            .sum::<usize>()
    );
    Ok(if failed {
        ExitCode::from(1)
    } else {
        ExitCode::SUCCESS
    })
}
