//! `spreadlight view`: any glTF file in one command. It builds the patch a
//! user would (glTF -> DeferredBase -> MRE -> GBufferView -> Output), with a
//! camera framing the model's bounds, and renders it.

use std::path::PathBuf;
use std::process::ExitCode;

use anyhow::Context;
use glam::{Mat4, Vec3};
use spreadlight_graph::{NodeDoc, Patch, format};
use spreadlight_render::mesh::gltf_import::load_gltf;

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
    /// The G-buffer channel to show: Albedo, Normals, Velocity, UV, Depth, "Material ID", "Object ID".
    #[arg(long, default_value = "Albedo")]
    channel: String,
    /// Also save the patch this command built, to open and change it.
    #[arg(long)]
    save_patch: Option<PathBuf>,
}

/// A camera looking at `bounds` from the front-right and above, the whole model in view.
pub fn framing(center: Vec3, radius: f32, aspect: f32) -> (Mat4, Mat4) {
    let radius = if radius.is_finite() && radius > 1e-6 {
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

pub fn run(args: &Args) -> anyhow::Result<ExitCode> {
    // Load once here for the bounds (and a clear error before any GPU work).
    let scene = load_gltf(&args.model)?;
    let (view, projection) = framing(
        scene.bounds.center(),
        scene.bounds.size().length() * 0.5,
        args.size.0 as f32 / args.size.1 as f32,
    );
    let model = std::path::absolute(&args.model).unwrap_or_else(|_| args.model.clone());
    let mut patch = Patch::default();
    patch.add(
        NodeDoc::new(1, "glTF")
            .at(0.0, 0.0)
            .with("Filename", vec![model.to_string_lossy().into_owned()]),
    );
    patch.add(NodeDoc::new(2, "DeferredBase").at(0.0, 80.0));
    patch.add(
        NodeDoc::new(3, "MRE")
            .at(0.0, 160.0)
            .with("View", vec![view])
            .with("Projection", vec![projection]),
    );
    patch.add(NodeDoc::new(4, "GBufferView").at(0.0, 240.0).with(
        "Channel",
        spreadlight_graph::Spread::Enum(vec![args.channel.clone()]),
    ));
    patch.add(NodeDoc::new(5, "Output").at(0.0, 320.0));
    patch.link(1, "Mesh", 2, "Mesh");
    patch.link(1, "Transform", 2, "Transform");
    patch.link(1, "Base Color", 2, "Color");
    patch.link(1, "Material ID", 2, "Material ID");
    patch.link(2, "Layer", 3, "Layer");
    patch.link(3, "G-Buffer", 4, "G-Buffer");
    patch.link(4, "Texture", 5, "Texture");
    if let Some(path) = &args.save_patch {
        format::save(&patch, path)?;
        eprintln!("saved the patch to {}", path.display());
    }
    let mut session =
        crate::session::Session::from_patch(&patch, &args.model, true, Some(args.size))?;
    if session.load_errors {
        anyhow::bail!("--channel `{}` is not a G-buffer channel", args.channel);
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
