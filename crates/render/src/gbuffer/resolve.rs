//! The surface and motion resolves: the visibility buffer (or the hardware
//! raster's IDs and depth) into the MRE targets, one compute dispatch per
//! run of adjacent layers that one permutation serves.

use crate::error::RenderError;
use crate::frame_graph::{Bindings, PassContext, Tex};
use crate::renderer::Renderer;
use crate::shaders::Permutation;

use super::resolve_key::{ResolveKey, SurfaceResolve};
use super::{GBuffer, GpuLayer, RasterMode, SplicedGroup, shader_node_group};

/// Statistic: resolve dispatches that wrote the surface and the motion
/// targets at once (the frame read both).
pub const SURFACE_AND_MOTION_DISPATCHES: &str = "surface and motion resolve dispatches";

/// Which targets a resolve dispatch writes.
#[derive(Clone, Copy, PartialEq, Eq)]
pub(super) enum Targets {
    /// Colour, normals, depth (and the surface target).
    Surface,
    /// Velocity and texture coordinates.
    Motion,
    /// Both, in one dispatch per run of layers alike in both.
    Both,
}

impl Targets {
    /// The compute pass's name, for captures.
    fn label(self) -> &'static str {
        match self {
            Targets::Surface => "resolve surface",
            Targets::Motion => "resolve motion",
            Targets::Both => "resolve surface and motion",
        }
    }

    /// The counter of dispatches of this kind.
    fn counter(self) -> &'static str {
        match self {
            Targets::Surface => "surface resolve dispatches",
            Targets::Motion => "motion resolve dispatches",
            Targets::Both => SURFACE_AND_MOTION_DISPATCHES,
        }
    }
}

/// What one layer's surface resolve reads beside the visibility.
#[derive(Clone, Default)]
pub(super) struct LayerReads {
    pub normal_map: Option<Tex>,
    pub color_map: Option<Tex>,
    /// A shader node material's texture inputs, in `@input` order.
    pub textures: Vec<Tex>,
}

/// Record a resolve pass: `declared` binds the visibility (the hardware
/// raster's), its depth and the targets written, as the pass declared them;
/// `layers` are the surface resolve's reads.
pub(super) fn resolve(
    g: &GBuffer,
    renderer: &Renderer,
    cx: &mut PassContext<'_>,
    targets: Targets,
    layers: &[LayerReads],
    declared: Bindings<'_>,
) -> Result<(), RenderError> {
    let motion = targets == Targets::Motion;
    // Shown by `stats`: the sheen and film target exists only for a world
    // with a sheen or iridescence map (GBufferTargets::sheen_film).
    if !motion && g.targets.sheen_film.is_some() {
        cx.count("G-buffer sheen and film targets written", 1);
    }
    let device = cx.gpu.device.clone();
    let (vertices, indices, _) = renderer.meshes.buffers();
    let extras = renderer.meshes.extras();
    let compute = g
        .compute
        .as_ref()
        .filter(|_| g.raster == RasterMode::Compute);
    // The compute raster's 64-bit buffer, or the hardware raster's IDs.
    let visibility = match compute {
        Some(c) => Some((
            c.visibility().ok_or_else(|| RenderError::Pass {
                pass: "resolve".to_owned(),
                message: "the compute raster has not run this frame".to_owned(),
            })?,
            &c.first_triangle,
        )),
        None => None,
    };
    let (w, h) = g.pixel_size(cx.output_size);
    // Per dispatch: its layer and its layer uniform. With no layers, one
    // (background) dispatch still clears the targets; otherwise one per run
    // of adjacent layers the same permutation serves.
    let dispatches: Vec<(Option<usize>, Option<&wgpu::Buffer>)> = if g.layers.is_empty() {
        vec![(None, None)]
    } else {
        let runs = match targets {
            Targets::Surface => &g.surface_runs,
            Targets::Motion => &g.motion_runs,
            Targets::Both => &g.fused_runs,
        };
        runs.iter().map(|(i, b)| (Some(*i), Some(b))).collect()
    };
    cx.count(targets.counter(), dispatches.len() as u64);
    let mut work = Vec::with_capacity(dispatches.len());
    for (index, layer_buffer) in dispatches {
        let i = index.unwrap_or(0);
        let layer = index.and_then(|i| g.layers.get(i));
        let reads = index.and_then(|i| layers.get(i)).filter(|_| !motion);
        let key = dispatch_key(g, layer.map(|l| &**l), targets, compute.is_some());
        let layer_buffer = match layer_buffer {
            Some(b) => b.clone(),
            None => background_layer(&device),
        };
        let mut b = declared
            .clone()
            .buffer("camera", g.camera_buffer())
            .buffer("vertices", &vertices)
            .buffer("indices", &indices)
            .buffer("instances", &g.instances)
            .buffer("extras", &extras)
            .buffer("layer", &layer_buffer);
        if let Some((buffer, first_triangle)) = visibility.as_ref() {
            b = b
                .buffer("visibility", buffer)
                .buffer("first_triangle", first_triangle);
        }
        // The layer's maps, where its permutation samples them (a sampler
        // the permutation compiled out is not bound).
        let sampling = crate::shaders::Sampling::LinearRepeat;
        b = b
            .texture_opt("normal_map", reads.and_then(|r| r.normal_map))
            .texture_opt("color_map", reads.and_then(|r| r.color_map))
            .sampler("normal_sampler", sampling)
            .sampler("color_sampler", sampling);
        // A shader node material: the resolve composed with its file, whose
        // group 1 its own file lays out; else the material world and its
        // surface maps' arrays.
        let custom = layer.and_then(|l| l.surface.as_ref()).filter(|_| !motion);
        let groups = match custom {
            Some(s) => {
                let label = format!("{}: resolve surface", s.label);
                let (pipeline, reflection) = s.pipeline(cx, &key, super::SURFACE_MODULE, &label)?;
                let params = g.surface_buffers.get(i).and_then(Option::as_ref);
                let textures = reads.map_or(&[][..], |r| r.textures.as_slice());
                let spliced = SplicedGroup {
                    group: 1,
                    label: &label,
                    reflection: &reflection,
                };
                if let Some(group) =
                    shader_node_group(cx, &pipeline, s, params, textures, &spliced)?
                {
                    b = b.group(1, group);
                }
                // spreadlight::materials: the layer's world in group 3, its
                // texture array read after the material's own inputs.
                if s.reads_materials {
                    let world =
                        layer
                            .and_then(|l| l.library_world())
                            .ok_or_else(|| RenderError::Pass {
                                pass: label.clone(),
                                message: "it reads the material world (spreadlight::materials), \
                                      but its DeferredBase has no Material World connected"
                                    .to_owned(),
                            })?;
                    let array = layer
                        .and_then(|l| l.library_textures())
                        .and_then(|_| textures.get(s.textures.len()).copied());
                    b = b.extend(world.library_bindings(array));
                }
                let groups = cx.bind_groups_reflected(&label, &reflection, &pipeline, b)?;
                (pipeline, groups)
            }
            None => {
                if let Some(world) = layer.and_then(|l| l.map_world()).filter(|_| !motion) {
                    b = b.extend(world.bindings(None));
                    if let Some(maps) = world.maps_bindings() {
                        b = b.extend(maps);
                    }
                }
                let pipeline = cx.compute_pipeline(&key, "main")?;
                let groups = cx.bind_groups(&key, "main", &pipeline, b)?;
                (pipeline, groups)
            }
        };
        work.push(groups);
    }
    for (pipeline, groups) in &work {
        let groups: Vec<&wgpu::BindGroup> = groups.iter().collect();
        cx.dispatch(
            targets.label(),
            pipeline,
            &groups,
            (w.div_ceil(8), h.div_ceil(8), 1),
        );
    }
    Ok(())
}

/// The permutation of the dispatch for `layer` (None: the background
/// dispatch of a G-buffer with no layers), as recorded and as announced.
fn dispatch_key(
    g: &GBuffer,
    layer: Option<&super::Layer>,
    targets: Targets,
    compute_raster: bool,
) -> crate::shaders::ShaderKey {
    let key = match (layer, targets) {
        (Some(l), Targets::Motion) => l.features.motion_key(),
        (Some(l), Targets::Surface) => l.surface_key(),
        (Some(l), Targets::Both) => l.fused_key(),
        (None, Targets::Motion) => ResolveKey::motion(),
        (None, Targets::Surface) => ResolveKey::surface(SurfaceResolve::default()),
        (None, Targets::Both) => ResolveKey::surface(SurfaceResolve {
            velocity: true,
            ..SurfaceResolve::default()
        }),
    };
    let key = ResolveKey {
        compute_raster,
        ..key
    };
    match g.targets.surface {
        Some(_) => key.with_surface_target(),
        None => key,
    }
    .key()
}

/// Announce the pipelines a `targets` resolve will dispatch, where the
/// G-buffer is declared (frame_graph/gather.rs): their keys are known from
/// the layers and the raster mode, so a first frame makes them on threads
/// instead of in the pass. A shader node material's surface pipeline is
/// made its own way (surface_shader.rs) and is left to the pass.
/// The pass that records them is named `pass`: it may be culled (no one
/// reads the motion) or merged (the surface and motion run as one), so they
/// are made only where it runs.
pub(super) fn announce(
    g: &GBuffer,
    fg: &mut crate::frame_graph::FrameGraph<'_>,
    targets: Targets,
    pass: &crate::report::PassName,
) {
    if !fg.gathers_pipelines() {
        return;
    }
    let compute = g.compute.is_some() && g.raster == RasterMode::Compute;
    let mut announce = |key: crate::shaders::ShaderKey| {
        fg.will_dispatch_if_run(pass.clone(), g.owner, &key, "main");
    };
    if g.layers.is_empty() {
        announce(dispatch_key(g, None, targets, compute));
        return;
    }
    let runs = match targets {
        Targets::Surface => &g.surface_runs,
        Targets::Motion => &g.motion_runs,
        Targets::Both => &g.fused_runs,
    };
    for (i, _) in runs {
        let Some(layer) = g.layers.get(*i) else {
            continue;
        };
        if layer.surface.is_some() && targets != Targets::Motion {
            continue;
        }
        announce(dispatch_key(g, Some(&**layer), targets, compute));
    }
}

/// The layer record of a G-buffer with no layers: covers nothing, clears everything.
fn background_layer(device: &wgpu::Device) -> wgpu::Buffer {
    let layer = GpuLayer {
        write_background: 1,
        ..bytemuck::Zeroable::zeroed()
    };
    wgpu::util::DeviceExt::create_buffer_init(
        device,
        &wgpu::util::BufferInitDescriptor {
            label: Some("mre background layer"),
            contents: bytemuck::bytes_of(&layer),
            usage: wgpu::BufferUsages::UNIFORM,
        },
    )
}
