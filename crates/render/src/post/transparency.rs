//! `Transparency`: weighted blended order-independent transparency
//! (McGuire and Bavoil 2013; shaders/post/transparency.wgsl). Transparent
//! layers are rasterized (blending is what raster hardware is for) into an
//! RGBA16F accumulation and an R16F revealage target, depth-tested by hand
//! against the G-buffer's depth, then a compute pass composites them over
//! the opaque lit image. Lighting is simple: the layer's colour times an
//! ambient term plus one two-sided directional key light. The colour and
//! opacity are glTF's base colour: instance colour x the base colour map of
//! a layer whose material world has surface maps x COLOR_0, each layer drawn
//! with its own permutation (MATERIAL_MAPS, VERTEX_EXTRAS). Without
//! transparent instances the node costs a copy.

use std::sync::Arc;

use glam::Vec3;

use crate::error::RenderError;
use crate::frame_graph::{Bindings, FrameGraph, PassContext, Tex, TextureDesc};
use crate::gbuffer::{Draw, GBuffer, Layer, mesh_bindings, pack_instances};
use crate::recipe::{Recipe, TextureRef, next_recipe_id};
use crate::renderer::Renderer;
use crate::report::PassName;
use crate::shaders::ShaderKey;

const SHADER: &str = "post/transparency.wgsl";
const ACCUMULATION: wgpu::TextureFormat = wgpu::TextureFormat::Rgba16Float;
// Rgba16Float, not R16Float (only red is read): the targets are cleared by
// a compute pass, and half-float storage is only core in four channels.
const REVEALAGE: wgpu::TextureFormat = wgpu::TextureFormat::Rgba16Float;

/// Counted when there was nothing transparent to draw and the node only copied.
pub const SKIPPED: &str = "transparency skipped (nothing transparent)";
/// Transparent instances drawn.
pub const DRAWN: &str = "transparent instances drawn";

#[derive(Clone, Copy, Debug, PartialEq)]
pub struct TransparencySettings {
    pub ambient: Vec3,
    /// Towards the key light, in world space.
    pub light_direction: Vec3,
    pub light_color: Vec3,
}

impl Default for TransparencySettings {
    fn default() -> Self {
        TransparencySettings {
            ambient: Vec3::splat(0.3),
            light_direction: Vec3::new(0.3, 1.0, 0.5),
            light_color: Vec3::splat(1.0),
        }
    }
}

pub struct Transparency {
    id: u64,
    owner: Option<u32>,
    source: TextureRef,
    gbuffer: Arc<GBuffer>,
    layers: Vec<Arc<Layer>>,
    draws: Vec<Draw>,
    /// Per layer: its instance range.
    layer_ranges: Vec<(u32, u32)>,
    instances: wgpu::Buffer,
    instance_count: u32,
    params: wgpu::Buffer,
    accumulation: String,
    revealage: String,
    pub output: String,
}

impl Transparency {
    pub fn new(
        renderer: &Renderer,
        owner: Option<u32>,
        source: TextureRef,
        gbuffer: Arc<GBuffer>,
        layers: Vec<Arc<Layer>>,
        settings: TransparencySettings,
    ) -> Arc<Self> {
        let id = next_recipe_id();
        let (gpu_instances, draws, layer_ranges) = pack_instances(&layers);
        let instance_count = gpu_instances.len() as u32;
        let instances = renderer.kept_storage(owner, "transparent instances", &gpu_instances);
        let clean = |v: Vec3| {
            if v.is_finite() {
                v.clamp(Vec3::ZERO, Vec3::splat(super::HALF_MAX))
            } else {
                Vec3::ZERO
            }
        };
        let direction = settings.light_direction.normalize_or(Vec3::Y);
        let (a, l) = (clean(settings.ambient), clean(settings.light_color));
        let params = super::uniform(
            renderer,
            owner,
            "transparency",
            &super::words(&[
                a.x,
                a.y,
                a.z,
                0.0,
                direction.x,
                direction.y,
                direction.z,
                0.0,
                l.x,
                l.y,
                l.z,
                0.0,
            ]),
        );
        Arc::new(Transparency {
            id,
            owner,
            source,
            gbuffer,
            layers,
            draws,
            layer_ranges,
            instances,
            instance_count,
            params,
            accumulation: format!("transparency{id} accumulation"),
            revealage: format!("transparency{id} revealage"),
            output: format!("transparency{id}"),
        })
    }

    pub fn texture(self: &Arc<Self>) -> TextureRef {
        TextureRef {
            recipe: self.clone(),
            name: self.output.clone(),
        }
    }

    fn accumulate(
        &self,
        renderer: &Renderer,
        cx: &mut PassContext<'_>,
        io: &AccumulateIo,
    ) -> Result<(), RenderError> {
        let (vertices, indices, _) = renderer.meshes.buffers();
        let extras = renderer.meshes.extras();
        // Per layer: its permutation and bind groups (0, and 1 to 3 with maps).
        let mut work = Vec::with_capacity(self.layers.len());
        for (layer, range) in self.layers.iter().zip(&self.layer_ranges) {
            if range.0 == range.1 {
                continue;
            }
            let world = layer.map_world();
            let vertex_extras = layer.vertex_extras();
            let defines = [
                world.is_some().then_some("MATERIAL_MAPS"),
                vertex_extras.then_some("VERTEX_EXTRAS"),
            ];
            let key = ShaderKey::new(SHADER, defines.into_iter().flatten());
            // glTF materials (a world with maps): back faces culled unless
            // double-sided, as other viewers draw them; patch-built layers
            // show both faces (a glass shell's back through its front).
            for culled in [true, false] {
                let in_layer = |d: &&Draw| (range.0..range.1).contains(&d.first_instance);
                let culls = |d: &Draw| world.is_some() && !d.two_sided;
                if !self
                    .draws
                    .iter()
                    .filter(in_layer)
                    .any(|d| culls(d) == culled)
                {
                    continue;
                }
                let pipeline = accumulate_pipeline(cx, key.clone(), culled)?;
                let mut b = mesh_bindings(&vertices, &indices, &self.instances)
                    .buffer("camera", self.gbuffer.camera_buffer())
                    .texture("opaque_depth", io.depth)
                    .buffer("params", &self.params)
                    .buffer_opt("extras", vertex_extras.then_some(&extras));
                // With maps: the material world (group 1) and its map arrays
                // (group 3); group 2, unused, is bound empty.
                if let Some(world) = world {
                    b = b.extend(world.bindings(None));
                    if let Some(maps) = world.maps_bindings() {
                        b = b.extend(maps);
                    }
                }
                // Through the cache: the camera, meshes, kept instances and
                // parameters are the same buffers from frame to frame.
                let groups = cx.render_bind_groups(&key, &["vs", "fs"], &pipeline, b)?;
                work.push((*range, culled, world.is_some(), pipeline, groups));
            }
        }
        // Cleared in compute, then loaded: a render pass's clear goes through
        // the raster output, which on the H100 took 0.28 of this pass's
        // 0.41 ms at 1080p (docs/benchmarks.md, session 10); compute writes
        // the same bytes about a hundred times faster.
        let size = cx.size_of(io.accumulation)?;
        cx.dispatch_shader(
            "transparency clear",
            &ShaderKey::new(SHADER, []),
            "clear",
            Bindings::new()
                .texture("clear_accumulation", io.accumulation)
                .texture("clear_revealage", io.revealage),
            super::per_pixel(size),
        )?;
        let (accumulation, revealage) = (cx.view(io.accumulation)?, cx.view(io.revealage)?);
        let timestamps = cx.render_timestamps();
        let attachment = |view| {
            Some(wgpu::RenderPassColorAttachment {
                view,
                depth_slice: None,
                resolve_target: None,
                ops: wgpu::Operations {
                    load: wgpu::LoadOp::Load,
                    store: wgpu::StoreOp::Store,
                },
            })
        };
        let mut pass = cx.encoder().begin_render_pass(&wgpu::RenderPassDescriptor {
            label: Some("transparency accumulate"),
            color_attachments: &[attachment(&accumulation), attachment(&revealage)],
            depth_stencil_attachment: None,
            timestamp_writes: timestamps,
            occlusion_query_set: None,
            multiview_mask: None,
        });
        let mut draws = 0;
        for ((first, end), culled, maps, pipeline, groups) in &work {
            pass.set_pipeline(pipeline);
            for (i, group) in groups.iter().enumerate() {
                pass.set_bind_group(i as u32, group, &[]);
            }
            for draw in self.draws.iter().filter(|d| {
                d.instance_count > 0
                    && d.index_count > 0
                    && (*first..*end).contains(&d.first_instance)
                    && (*maps && !d.two_sided) == *culled
            }) {
                pass.draw(
                    0..draw.index_count,
                    draw.first_instance..draw.first_instance + draw.instance_count,
                );
                draws += 1;
            }
        }
        drop(pass);
        cx.draws += draws;
        cx.count(DRAWN, u64::from(self.instance_count));
        Ok(())
    }

    fn resolve(&self, cx: &mut PassContext<'_>, io: &ResolveIo) -> Result<(), RenderError> {
        let size = cx.size_of(io.output)?;
        cx.dispatch_shader(
            "transparency resolve",
            &ShaderKey::new(SHADER, []),
            "resolve",
            Bindings::new()
                .texture("opaque", io.opaque)
                .texture("accumulation", io.accumulation)
                .texture("revealage", io.revealage)
                .texture("output", io.output),
            super::per_pixel(size),
        )
    }
}

/// What the accumulation pass declared: the depth it tests against and the
/// two targets it clears and draws into.
struct AccumulateIo {
    depth: Tex,
    accumulation: Tex,
    revealage: Tex,
}

/// What the resolve pass declared.
struct ResolveIo {
    opaque: Tex,
    accumulation: Tex,
    revealage: Tex,
    output: Tex,
}

/// The accumulation pipeline of one permutation: additive accumulation,
/// multiplicative revealage; back faces culled when `culled`.
fn accumulate_pipeline(
    cx: &mut PassContext<'_>,
    key: ShaderKey,
    culled: bool,
) -> Result<wgpu::RenderPipeline, RenderError> {
    let device = cx.gpu.device.clone();
    let variant = if culled { "wboit, culled" } else { "wboit" };
    cx.shaders
        .render_pipeline(&device, &key, variant, |module| {
            let additive = wgpu::BlendComponent {
                src_factor: wgpu::BlendFactor::One,
                dst_factor: wgpu::BlendFactor::One,
                operation: wgpu::BlendOperation::Add,
            };
            let reveal = wgpu::BlendComponent {
                src_factor: wgpu::BlendFactor::Zero,
                dst_factor: wgpu::BlendFactor::OneMinusSrc,
                operation: wgpu::BlendOperation::Add,
            };
            device.create_render_pipeline(&wgpu::RenderPipelineDescriptor {
                label: Some("transparency accumulate"),
                layout: None,
                vertex: wgpu::VertexState {
                    module,
                    entry_point: Some("vs"),
                    compilation_options: Default::default(),
                    buffers: &[],
                },
                primitive: wgpu::PrimitiveState {
                    topology: wgpu::PrimitiveTopology::TriangleList,
                    front_face: wgpu::FrontFace::Ccw,
                    cull_mode: culled.then_some(wgpu::Face::Back),
                    ..Default::default()
                },
                depth_stencil: None,
                multisample: Default::default(),
                fragment: Some(wgpu::FragmentState {
                    module,
                    entry_point: Some("fs"),
                    compilation_options: Default::default(),
                    targets: &[
                        Some(wgpu::ColorTargetState {
                            format: ACCUMULATION,
                            blend: Some(wgpu::BlendState {
                                color: additive,
                                alpha: additive,
                            }),
                            write_mask: wgpu::ColorWrites::ALL,
                        }),
                        Some(wgpu::ColorTargetState {
                            format: REVEALAGE,
                            blend: Some(wgpu::BlendState {
                                color: reveal,
                                alpha: reveal,
                            }),
                            // Only red is read.
                            write_mask: wgpu::ColorWrites::RED,
                        }),
                    ],
                }),
                multiview_mask: None,
                cache: None,
            })
        })
}

impl Recipe for Transparency {
    fn declare<'a>(&'a self, renderer: &'a Renderer, fg: &mut FrameGraph<'a>) {
        if !fg.include(self.id) {
            return;
        }
        self.source.recipe.declare(renderer, fg);
        let name = |what| PassName::new("Transparency").step(what);
        let output = TextureDesc::storage(wgpu::TextureFormat::Rgba16Float).size(self.gbuffer.size);
        if self.instance_count == 0 {
            super::declare_copy(
                fg,
                name("copy"),
                self.owner,
                &self.source.name,
                (&self.output, output),
                SKIPPED,
            );
            return;
        }
        self.gbuffer.declare(renderer, fg);
        for map in self.layers.iter().flat_map(|l| l.maps()) {
            map.recipe.declare(renderer, fg);
        }
        // Drawn into, and cleared by a compute pass first.
        let target = |format| {
            let mut desc = TextureDesc::attachment(format).size(self.gbuffer.size);
            desc.usage |= wgpu::TextureUsages::STORAGE_BINDING;
            desc
        };
        let mut pass = fg.pass(name("accumulate"), self.owner);
        let io = AccumulateIo {
            depth: pass.read(&self.gbuffer.targets.depth),
            accumulation: pass.write(&self.accumulation, target(ACCUMULATION)),
            revealage: pass.write(&self.revealage, target(REVEALAGE)),
        };
        pass.run(move |cx| self.accumulate(renderer, cx, &io));
        let mut pass = fg.pass(name("resolve"), self.owner);
        let io = ResolveIo {
            opaque: pass.read(&self.source.name),
            accumulation: pass.read(&self.accumulation),
            revealage: pass.read(&self.revealage),
            output: pass.write(&self.output, output),
        };
        pass.run(move |cx| self.resolve(cx, &io));
    }
}
