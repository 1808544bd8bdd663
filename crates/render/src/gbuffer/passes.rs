//! The G-buffer's three passes: visibility (hardware raster, or the compute
//! rasterizer in compute_raster.rs), surface and motion resolves (compute,
//! resolve.rs: one dispatch per run of alike layers with their permutation).

use crate::error::RenderError;
use crate::frame_graph::{FrameGraph, Lifetime, PassContext, Tex, TextureDesc};
use crate::mesh_arena::pulled_pipeline;
use crate::renderer::Renderer;
use crate::report::PassName;
use crate::shaders::{Permutation, ShaderKey};

use super::resolve::{LayerReads, Targets, resolve};
use super::{GBuffer, RasterMode};

pub use super::visibility_key::VisibilityKey;

const VISIBILITY_FORMAT: wgpu::TextureFormat = wgpu::TextureFormat::Rg32Uint;
const HARDWARE_DEPTH_FORMAT: wgpu::TextureFormat = wgpu::TextureFormat::Depth32Float;
const DEPTH_FORMAT: wgpu::TextureFormat = wgpu::TextureFormat::R32Float;
const TARGET_FORMAT: wgpu::TextureFormat = wgpu::TextureFormat::Rgba16Float;
const SURFACE_FORMAT: wgpu::TextureFormat = wgpu::TextureFormat::Rgba32Uint;

pub(super) fn declare<'a>(g: &'a GBuffer, renderer: &'a Renderer, fg: &mut FrameGraph<'a>) {
    let t = &g.targets;
    let label = |what: &'static str| PassName::new("MRE").step(what);
    let hardware = match (g.raster, &g.compute) {
        (RasterMode::Compute, Some(compute)) => {
            compute.announce(renderer, fg, false, false);
            // The 64-bit buffer belongs to the G-buffer; this 1x1 token
            // carries the dependency through the frame graph.
            let mut pass = fg.pass(label("compute raster"), g.owner);
            pass.write(&t.visibility, TextureDesc::token());
            pass.run(move |cx| compute.record(g, renderer, cx));
            false
        }
        _ => {
            let mut pass = fg.pass(label("visibility"), g.owner);
            let io = VisibilityIo {
                visibility: pass.write(
                    &t.visibility,
                    TextureDesc::attachment(VISIBILITY_FORMAT).size(g.size),
                ),
                depth: pass.write(
                    &t.hardware_depth,
                    TextureDesc::attachment(HARDWARE_DEPTH_FORMAT).size(g.size),
                ),
            };
            if pass.graph().gathers_pipelines() {
                announce_visibility(g, &mut pass);
            }
            pass.run(move |cx| visibility(g, renderer, cx, io));
            true
        }
    };
    // The surface resolve also reads the layers' maps. Its depth is
    // Permanent: readers (lighting, GBufferView) come later in the frame.
    let mut pass = fg.pass(label("resolve surface"), g.owner);
    // The hardware raster's IDs are a texture; the compute raster's a
    // buffer the run binds, its texture a token that orders the passes.
    let visibility = |pass: &mut crate::frame_graph::PassBuilder<'_, 'a>| match hardware {
        true => pass.input("visibility", &t.visibility),
        false => pass.read(&t.visibility),
    };
    visibility(&mut pass);
    if hardware {
        pass.input("hardware_depth", &t.hardware_depth);
    }
    let layers: Vec<LayerReads> = g
        .layers
        .iter()
        .map(|l| LayerReads {
            normal_map: l
                .normal_map
                .as_ref()
                .filter(|_| l.features.normal_map)
                .map(|m| pass.read(&m.name)),
            color_map: l.color_map.as_ref().map(|m| pass.read(&m.name)),
            textures: l.surface_textures().map(|m| pass.read(&m.name)).collect(),
        })
        .collect();
    let target = |format| TextureDesc::storage(format).size(g.size);
    pass.output("out_color", &t.color, target(TARGET_FORMAT));
    pass.output("out_normal", &t.normals, target(TARGET_FORMAT));
    let depth = target(DEPTH_FORMAT).lifetime(Lifetime::Permanent);
    pass.output("out_depth", &t.depth, depth);
    if let Some(name) = &t.surface {
        pass.output("out_surface", name, target(SURFACE_FORMAT));
    }
    if let Some(name) = &t.anisotropy {
        pass.output("out_anisotropy", name, target(TARGET_FORMAT));
    }
    if let Some(name) = &t.sheen_film {
        pass.output("out_sheen_film", name, target(super::SHEEN_FILM_FORMAT));
    }
    let surface = pass.bindings().clone();
    let surface_layers = layers.clone();
    pass.run_bound(move |cx, b| resolve(g, renderer, cx, Targets::Surface, &surface_layers, b));
    let mut pass = fg.pass(label("resolve motion"), g.owner);
    visibility(&mut pass);
    let velocity_uv = pass.output("out_velocity_uv", &t.velocity_uv, target(TARGET_FORMAT));
    pass.run_bound(move |cx, b| resolve(g, renderer, cx, Targets::Motion, &[], b));
    // Both read the visibility: one dispatch per run when the frame reads both,
    // where the device binds the five storage textures that takes with a
    // surface target (WebGPU's minimum is four), one more with an anisotropy
    // target, one more with a sheen and film target.
    let storage = renderer
        .gpu
        .device
        .limits()
        .max_storage_textures_per_shader_stage;
    let needed = 4
        + u32::from(t.surface.is_some())
        + u32::from(t.anisotropy.is_some())
        + u32::from(t.sheen_film.is_some());
    let fused = needed <= 4 || storage >= needed;
    // The resolves' pipelines, made on threads on a first frame, for the
    // passes the plan runs: the surface's alone, the motion's, or both in one.
    super::resolve::announce(g, fg, Targets::Surface, &label("resolve surface"));
    super::resolve::announce(g, fg, Targets::Motion, &label("resolve motion"));
    if fused {
        let both_label = label("resolve surface and motion");
        super::resolve::announce(g, fg, Targets::Both, &both_label);
        let both = surface.texture("out_velocity_uv", velocity_uv);
        fg.runs_together(label("resolve surface and motion"), move |cx| {
            resolve(g, renderer, cx, Targets::Both, &layers, both)
        });
    }
}

/// What the hardware raster's visibility pass writes.
#[derive(Clone, Copy)]
struct VisibilityIo {
    visibility: Tex,
    depth: Tex,
}

fn visibility(
    g: &GBuffer,
    renderer: &Renderer,
    cx: &mut PassContext<'_>,
    io: VisibilityIo,
) -> Result<(), RenderError> {
    let (vertices, indices, _) = renderer.meshes.buffers();
    let extras = renderer.meshes.extras();
    const STAGES: [&str; 2] = ["vs", "fs"];
    // Culling back faces, and (for draws of double-sided materials) not.
    let mut plain: [Option<(wgpu::RenderPipeline, crate::frame_graph::BindGroups)>; 2] =
        [None, None];
    for sided in [false, true] {
        if g.draws.iter().any(|d| d.two_sided == sided) {
            let (pipeline, key) = visibility_pipeline(cx, false, sided)?;
            let bindings = g.geometry_bindings(&vertices, &indices);
            let groups = cx.render_bind_groups(&key, &STAGES, &pipeline, bindings)?;
            plain[usize::from(sided)] = Some((pipeline, groups));
        }
    }
    // Per layer with alpha-tested materials: the ALPHA_MASK pipeline and its world's groups.
    let mut masked = Vec::new();
    for (layer, range) in g.layers.iter().zip(&g.layer_ranges) {
        let Some(world) = layer.map_world().filter(|_| layer.alpha_masked()) else {
            continue;
        };
        for sided in [false, true] {
            let in_layer = |d: &&super::Draw| (range.0..range.1).contains(&d.first_instance);
            if !g
                .draws
                .iter()
                .filter(in_layer)
                .any(|d| d.two_sided == sided)
            {
                continue;
            }
            let (pipeline, key) = visibility_pipeline(cx, true, sided)?;
            let mut bindings = g
                .geometry_bindings(&vertices, &indices)
                .buffer("extras", &extras)
                .extend(world.bindings(None));
            if let Some(maps) = world.maps_bindings() {
                bindings = bindings.extend(maps);
            }
            let groups = cx.render_bind_groups(&key, &STAGES, &pipeline, bindings)?;
            masked.push((*range, sided, pipeline, groups));
        }
    }
    let vis = cx.view(io.visibility)?;
    let depth = cx.view(io.depth)?;
    // Publishing a depth for particle collisions: the meshes in a first
    // pass, the depth copied, then the particles (procedural draws).
    let phases: &[Option<bool>] = match g.published_depth() {
        Some(_) => &[Some(false), Some(true)],
        None => &[None],
    };
    let mut draws = 0;
    for (k, phase) in phases.iter().enumerate() {
        if let (1, Some(name)) = (k, g.published_depth()) {
            super::published_depth::publish(
                renderer,
                cx,
                name,
                super::published_depth::DepthSource::Hardware(&depth),
                g.pixel_size(cx.output_size),
                g.camera.view_projection(),
            )?;
        }
        let (color_load, depth_load) = match k {
            0 => (
                wgpu::LoadOp::Clear(wgpu::Color::TRANSPARENT),
                wgpu::LoadOp::Clear(0.0),
            ),
            _ => (wgpu::LoadOp::Load, wgpu::LoadOp::Load),
        };
        let timestamps = cx.render_timestamps();
        let mut pass = cx.encoder().begin_render_pass(&wgpu::RenderPassDescriptor {
            label: Some("visibility"),
            color_attachments: &[Some(wgpu::RenderPassColorAttachment {
                view: &vis,
                depth_slice: None,
                resolve_target: None,
                ops: wgpu::Operations {
                    load: color_load,
                    store: wgpu::StoreOp::Store,
                },
            })],
            depth_stencil_attachment: Some(wgpu::RenderPassDepthStencilAttachment {
                view: &depth,
                depth_ops: Some(wgpu::Operations {
                    load: depth_load,
                    store: wgpu::StoreOp::Store,
                }),
                stencil_ops: None,
            }),
            timestamp_writes: timestamps,
            occlusion_query_set: None,
            multiview_mask: None,
        });
        for draw in g.draws.iter().filter(|d| {
            d.instance_count > 0
                && d.index_count > 0
                && phase.is_none_or(|procedural| d.procedural == procedural)
        }) {
            let mask = masked.iter().find(|((first, end), sided, _, _)| {
                (*first..*end).contains(&draw.first_instance) && *sided == draw.two_sided
            });
            match mask {
                Some((_, _, pipeline, groups)) => {
                    pass.set_pipeline(pipeline);
                    for (i, group) in groups.iter().enumerate() {
                        pass.set_bind_group(i as u32, group, &[]);
                    }
                }
                None => {
                    let Some((pipeline, groups)) = &plain[usize::from(draw.two_sided)] else {
                        continue;
                    };
                    pass.set_pipeline(pipeline);
                    for (i, group) in groups.iter().enumerate() {
                        pass.set_bind_group(i as u32, group, &[]);
                    }
                }
            }
            pass.draw(
                0..draw.index_count,
                draw.first_instance..draw.first_instance + draw.instance_count,
            );
            draws += 1;
        }
    }
    cx.draws += draws;
    Ok(())
}

/// The visibility pipeline and its permutation: culling back faces unless
/// `two_sided` (a draw of a double-sided material), with `alpha_mask`
/// testing MASK materials.
fn visibility_pipeline(
    cx: &mut PassContext<'_>,
    alpha_mask: bool,
    two_sided: bool,
) -> Result<(wgpu::RenderPipeline, ShaderKey), RenderError> {
    let device = cx.gpu.device.clone();
    let key = VisibilityKey { alpha_mask }.key();
    let (variant, build) = visibility_build(two_sided);
    let pipeline = cx
        .shaders
        .render_pipeline(&device, &key, variant, |module, cache| {
            build(&device, module, cache)
        })?;
    Ok((pipeline, key))
}

/// The visibility pipeline's variant name and how it is built (by the
/// pass, or on a thread where the pass announced it). Double-sided
/// materials: every face is drawn (the resolve flips their back faces'
/// normals).
fn visibility_build(
    two_sided: bool,
) -> (
    &'static str,
    impl Fn(&wgpu::Device, &wgpu::ShaderModule, Option<&wgpu::PipelineCache>) -> wgpu::RenderPipeline
    + Send
    + Sync
    + 'static,
) {
    let variant = if two_sided {
        "rg32uint+depth32f, two-sided"
    } else {
        "rg32uint+depth32f"
    };
    let build = move |device: &wgpu::Device,
                      module: &wgpu::ShaderModule,
                      cache: Option<&wgpu::PipelineCache>| {
        pulled_pipeline(
            device,
            module,
            cache,
            "visibility",
            wgpu::PrimitiveState {
                topology: wgpu::PrimitiveTopology::TriangleList,
                front_face: wgpu::FrontFace::Ccw,
                cull_mode: (!two_sided).then_some(wgpu::Face::Back),
                ..Default::default()
            },
            Some(wgpu::DepthStencilState {
                format: HARDWARE_DEPTH_FORMAT,
                depth_write_enabled: Some(true),
                depth_compare: Some(wgpu::CompareFunction::Greater),
                stencil: Default::default(),
                bias: Default::default(),
            }),
            &[Some(wgpu::ColorTargetState {
                format: VISIBILITY_FORMAT,
                blend: None,
                write_mask: wgpu::ColorWrites::ALL,
            })],
        )
    };
    (variant, build)
}

/// Announce the visibility pipelines [`visibility`] draws with
/// (frame_graph/gather.rs): per side its draws need, the plain one, and
/// the alpha-tested one for layers of MASK materials.
fn announce_visibility(g: &GBuffer, pass: &mut crate::frame_graph::PassBuilder<'_, '_>) {
    // [alpha_mask][two_sided]
    let mut wanted = [[false; 2]; 2];
    for d in &g.draws {
        wanted[0][usize::from(d.two_sided)] = true;
    }
    for (layer, range) in g.layers.iter().zip(&g.layer_ranges) {
        if layer.map_world().is_none() || !layer.alpha_masked() {
            continue;
        }
        for d in g
            .draws
            .iter()
            .filter(|d| (range.0..range.1).contains(&d.first_instance))
        {
            wanted[1][usize::from(d.two_sided)] = true;
        }
    }
    for alpha_mask in [false, true] {
        for two_sided in [false, true] {
            if wanted[usize::from(alpha_mask)][usize::from(two_sided)] {
                let key = VisibilityKey { alpha_mask }.key();
                let (variant, build) = visibility_build(two_sided);
                pass.will_render(&key, variant, std::sync::Arc::new(build));
            }
        }
    }
}
