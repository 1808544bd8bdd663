//! Rendering a probe's six faces (shaders/environment/environment_probe.wgsl) into its
//! base cube's level 0 on the raster hardware: one render pass per face,
//! the layer's instances pulled from the mesh arena as the shadow depth
//! pass pulls them, each surface shaded forward with the probe's lighting,
//! its layer's Color Texture and Normal Map (one pipeline permutation per
//! kind of layer: none, by UVs, triplanar, a glTF layer's surface maps)
//! and, when the probe has one, the sun's shadow maps; then, in the same
//! render pass, each point or spot light buffer draws the layers again
//! (LIGHT_PASS, depth-tested equal, added), its lights shaded by the
//! forward passes' shared light function, with the material extensions'
//! lobes (clear coat, sheen, anisotropy, iridescence) of a glTF layer whose
//! world has them (`ProbeLobes`). The prefilter then makes the cube's
//! mips and roughness levels from it.

use std::hash::{Hash, Hasher};

use wgpu::util::DeviceExt;

use super::key::{ProbeFacesKey, ProbeLobes, ProbePass, ProbeUv};
use super::{ProbeScene, SURFACE_METALLIC, SURFACE_ROUGHNESS, face_view_projection};
use crate::error::RenderError;
use crate::frame_graph::{Bindings, PassContext, Tex};
use crate::gbuffer::{Draw, GpuInstance, Layer, pack_instances};
use crate::material::{FEATURE_CLEARCOAT, FEATURE_IRIDESCENCE, FEATURE_SHEEN, MaterialWorld};
use crate::mesh_arena::pulled_pipeline;
use crate::renderer::Renderer;
use crate::shaders::{Permutation, Sampling, ShaderKey};
use crate::shadows::ShadowKey;

const DEPTH_FORMAT: wgpu::TextureFormat = wgpu::TextureFormat::Depth32Float;
/// The base cube's format (prefilter.rs).
const COLOR_FORMAT: wgpu::TextureFormat = wgpu::TextureFormat::Rgba16Float;

/// A probe's layers packed as the G-buffer packs them, once per recipe:
/// hashed to decide a re-render, uploaded only when rendering.
pub(crate) struct PackedProbe {
    instances: Vec<GpuInstance>,
    draws: Vec<Draw>,
    /// Each layer's range of instances.
    ranges: Vec<(u32, u32)>,
    /// Each layer's textures as its faces sample them.
    maps: Vec<ProbeMaps>,
    /// Each layer's material world, when its glTF surface maps are read (MATERIAL_MAPS).
    worlds: Vec<Option<std::sync::Arc<MaterialWorld>>>,
}

/// How a layer's Color Texture and Normal Map reach the probe's faces (by name).
#[derive(Clone, Debug, PartialEq, Hash)]
struct ProbeMaps {
    color: Option<String>,
    normal: Option<String>,
    uv: ProbeUv,
    /// Triplanar: the normal's power that blends the three projections.
    sharpness: u32,
    /// A glTF layer's surface maps: a hash of its world's materials and map arrays.
    surface_maps: Option<u64>,
}

/// What a world shows the probe: its materials' features and parameters,
/// and which map arrays (kept across frames while the maps are the same).
fn world_hash(world: &MaterialWorld) -> u64 {
    let mut h = std::collections::hash_map::DefaultHasher::new();
    for m in world.materials() {
        m.flags().hash(&mut h);
        for (_, params) in m.features() {
            for c in params.iter().flatten() {
                c.to_bits().hash(&mut h);
            }
        }
    }
    (world.world_maps())
        .map(|w| std::sync::Arc::as_ptr(&w.textures) as usize)
        .hash(&mut h);
    h.finish()
}

impl ProbeMaps {
    fn of(layer: &Layer) -> Self {
        // A glTF layer's surface maps take the place of a layer's own
        // textures (as in the G-buffer resolve and Transparency).
        if let Some(world) = layer.map_world() {
            return ProbeMaps {
                color: None,
                normal: None,
                uv: ProbeUv::None,
                sharpness: layer.features.triplanar_sharpness,
                surface_maps: Some(world_hash(world)),
            };
        }
        let color = layer.color_map.as_ref().map(|m| m.name.clone());
        let normal = (layer.normal_map.as_ref())
            .filter(|_| layer.features.normal_map)
            .map(|m| m.name.clone());
        // As Transparency and the resolve choose: Triplanar unless the mesh's UVs are asked for.
        let uv = if color.is_none() && normal.is_none() {
            ProbeUv::None
        } else if layer.features.triplanar && !layer.features.texcoords {
            ProbeUv::Triplanar
        } else {
            ProbeUv::Texcoords
        };
        ProbeMaps {
            color,
            normal,
            uv,
            sharpness: layer.features.triplanar_sharpness,
            surface_maps: None,
        }
    }
}

impl PackedProbe {
    pub(crate) fn new(layers: &[std::sync::Arc<Layer>]) -> Self {
        let (instances, draws, ranges) = pack_instances(layers);
        let maps = layers.iter().map(|l| ProbeMaps::of(l)).collect();
        let worlds = layers.iter().map(|l| l.map_world().cloned()).collect();
        PackedProbe {
            instances,
            draws,
            ranges,
            maps,
            worlds,
        }
    }
}

/// The material extensions' lobes a light pass over `world`'s surface
/// maps draws: those some material of the world has.
fn lobes_of(world: &MaterialWorld) -> ProbeLobes {
    ProbeLobes {
        coat: world.any_has(FEATURE_CLEARCOAT),
        sheen: world.any_has(FEATURE_SHEEN),
        anisotropy: world.has_anisotropy(),
        iridescence: world.any_has(FEATURE_IRIDESCENCE),
    }
}

/// Each layer's Color Texture and Normal Map as the frame graph handed
/// them to the probe's pass (None: the layer has none).
#[derive(Clone, Debug, Default)]
pub(crate) struct ProbeTextures {
    pub color: Vec<Option<Tex>>,
    pub normal: Vec<Option<Tex>>,
    /// Per light buffer: its spots' texture array.
    pub spots: Vec<Option<Tex>>,
}

/// Matches `ProbeLayer` in shaders/environment/environment_probe.wgsl (TRIPLANAR).
#[repr(C)]
#[derive(Clone, Copy, Debug, bytemuck::Pod, bytemuck::Zeroable)]
struct GpuProbeLayer {
    triplanar_sharpness: f32,
    pad: [f32; 3],
}

impl Hash for PackedProbe {
    fn hash<H: Hasher>(&self, h: &mut H) {
        for i in &self.instances {
            for c in i.model.iter().flatten().chain(&i.color) {
                c.to_bits().hash(h);
            }
            i.info.hash(h);
        }
        for d in &self.draws {
            (d.index_count, d.first_instance, d.instance_count).hash(h);
        }
        // Which texture a layer shows (by name: a new file is a new
        // texture); a texture whose pixels change under the same name (a
        // video) needs EveryNFrames.
        self.ranges.hash(h);
        self.maps.hash(h);
    }
}

/// Matches `ProbeFace` in shaders/environment/environment_probe.wgsl.
#[repr(C)]
#[derive(Clone, Copy, Debug, bytemuck::Pod, bytemuck::Zeroable)]
struct GpuProbeFace {
    view_projection: [[f32; 4]; 4],
    /// Where the probe is (w unused).
    position: [f32; 4],
    /// Towards the sun, unit (w unused).
    towards_sun: [f32; 4],
    sun_color: [f32; 4],
    ambient: [f32; 4],
    /// x: the sun's slice of the shadow maps (SHADOWS).
    shadow: [u32; 4],
    /// LIGHT_PASS: x the most lights a face adds of a buffer; y, z the
    /// roughness and metallic of surfaces without a world (f32 bits).
    light_params: [u32; 4],
}

/// The faces' pipeline for one kind of layer (`key`).
fn pipeline(
    cx: &mut PassContext<'_>,
    key: &ShaderKey,
    light: bool,
) -> Result<wgpu::RenderPipeline, RenderError> {
    let device = cx.gpu.device.clone();
    let (variant, build) = pipeline_build(light);
    cx.shaders
        .render_pipeline(&device, key, variant, |module, cache| {
            build(&device, module, cache)
        })
}

/// The faces' pipeline's variant name and how it is built (by the pass, or
/// on a thread where the pass announced it). A light pass adds its light to
/// the base pass's where the base pass drew (depth equal: the same vertex
/// code, its position `@invariant`, so the same depths), writing no depth.
fn pipeline_build(
    light: bool,
) -> (
    &'static str,
    impl Fn(&wgpu::Device, &wgpu::ShaderModule, Option<&wgpu::PipelineCache>) -> wgpu::RenderPipeline
    + Send
    + Sync
    + 'static,
) {
    let variant = if light { "rgba16f, added" } else { "rgba16f" };
    let build = move |device: &wgpu::Device,
                      module: &wgpu::ShaderModule,
                      cache: Option<&wgpu::PipelineCache>| {
        let additive = wgpu::BlendComponent {
            src_factor: wgpu::BlendFactor::One,
            dst_factor: wgpu::BlendFactor::One,
            operation: wgpu::BlendOperation::Add,
        };
        let target = wgpu::ColorTargetState {
            format: COLOR_FORMAT,
            blend: light.then_some(wgpu::BlendState {
                color: additive,
                alpha: additive,
            }),
            write_mask: if light {
                wgpu::ColorWrites::COLOR
            } else {
                wgpu::ColorWrites::ALL
            },
        };
        // Both sides: the faces' handedness differs, and a probe
        // inside an object sees its inside (the shader turns each
        // normal towards the probe).
        pulled_pipeline(
            device,
            module,
            cache,
            "environment probe faces",
            wgpu::PrimitiveState::default(),
            Some(wgpu::DepthStencilState {
                format: DEPTH_FORMAT,
                depth_write_enabled: Some(!light),
                // Reversed-Z: nearer is greater.
                depth_compare: Some(if light {
                    wgpu::CompareFunction::Equal
                } else {
                    wgpu::CompareFunction::Greater
                }),
                stencil: Default::default(),
                bias: Default::default(),
            }),
            &[Some(target)],
        )
    };
    (variant, build)
}

/// The faces' passes: the base pass (with the sun's shadow maps when the
/// probe has them), then one per light buffer (`textures.spots`: its spot
/// textures as handed to the pass).
fn probe_passes(scene: &ProbeScene, textures: &ProbeTextures) -> Vec<ProbePass> {
    let base = ProbePass::Base {
        sun_shadow: scene.sun_shadow().is_some(),
    };
    let lights = scene.lights().iter().enumerate().map(|(index, set)| {
        let spot_texture = textures.spots.get(index).copied().flatten().is_some();
        light_pass(set, spot_texture)
    });
    std::iter::once(base).chain(lights).collect()
}

/// A light buffer's pass.
fn light_pass(set: &super::ProbeLights, spot_texture: bool) -> ProbePass {
    ProbePass::Light {
        spot: set.lights.kind == crate::lighting::LightKind::Spot,
        spot_texture,
        shadows: ShadowKey::of(set.shadows.as_ref().map(|s| s.filter())),
    }
}

/// Layer `index`'s permutation in `pass`: its Color Texture and Normal Map
/// as handed to the pass (a texture it was not handed is drawn without:
/// never the case when declared together; the key follows what is bound).
fn faces_key(
    packed: &PackedProbe,
    textures: &ProbeTextures,
    index: usize,
    pass: ProbePass,
) -> ProbeFacesKey {
    let color = textures.color.get(index).copied().flatten();
    let normal = textures.normal.get(index).copied().flatten();
    let uv = match (color, normal, packed.maps.get(index)) {
        (None, None, _) | (_, _, None) => ProbeUv::None,
        (_, _, Some(maps)) => maps.uv,
    };
    let world = packed.worlds.get(index).and_then(Option::as_ref);
    ProbeFacesKey {
        uv,
        color_map: color.is_some(),
        normal_map: normal.is_some(),
        surface_maps: world.is_some(),
        pass,
        // The lobes only a light pass over a world with them draws.
        lobes: match (pass, world) {
            (ProbePass::Light { .. }, Some(world)) => lobes_of(world),
            _ => ProbeLobes::default(),
        },
    }
}

/// Announce the faces' render pipelines (frame_graph/gather.rs): each
/// layer with instances in each pass, as [`render`] will look them up.
pub(crate) fn announce(
    pass: &mut crate::frame_graph::PassBuilder<'_, '_>,
    scene: &ProbeScene,
    packed: &PackedProbe,
    textures: &ProbeTextures,
) {
    let passes = probe_passes(scene, textures);
    for (index, range) in packed.ranges.iter().enumerate() {
        if range.0 == range.1 {
            continue;
        }
        for &probe_pass in &passes {
            let key = faces_key(packed, textures, index, probe_pass).key();
            let (variant, build) = pipeline_build(matches!(probe_pass, ProbePass::Light { .. }));
            pass.will_render(&key, variant, std::sync::Arc::new(build));
        }
    }
}

/// One pipeline of the faces: the layer's instances `range`, drawn by
/// `pipeline` with the bind groups each face makes from `bindings`.
struct LayerDraw<'b> {
    range: (u32, u32),
    key: ShaderKey,
    pipeline: wgpu::RenderPipeline,
    bindings: crate::frame_graph::Bindings<'b>,
    /// A light buffer's pass (drawn after every base pass).
    lit: bool,
}

/// Draw `scene` into level 0 of `base` (a cube, RENDER_ATTACHMENT), one
/// render pass per face: every layer's base pass, then every layer again
/// per light buffer. `textures`: each layer's Color Texture and Normal Map,
/// and each light buffer's spot textures, as the frame graph handed them
/// to this pass.
pub(crate) fn render(
    cx: &mut PassContext<'_>,
    renderer: &Renderer,
    scene: &ProbeScene,
    packed: &PackedProbe,
    textures: &ProbeTextures,
    base: &wgpu::Texture,
) -> Result<(), RenderError> {
    let device = cx.gpu.device.clone();
    let size = base.width();
    let s = scene.settings();
    let l = s.lighting;
    let towards_sun = (-l.sun_direction).try_normalize().unwrap_or(glam::Vec3::Y);
    let not_rendered = |what: &str| RenderError::Pass {
        pass: "EnvironmentProbe".to_owned(),
        message: format!("the {what} shadow maps were not rendered this frame"),
    };
    // The sun's shadow maps, when the probe has them: rendered this frame
    // (the pass read their token) or kept from an earlier one.
    let shadow = match scene.sun_shadow() {
        Some(sun) => {
            let (depth, _) = sun.maps.textures().ok_or_else(|| not_rendered("sun's"))?;
            let view = depth.create_view(&wgpu::TextureViewDescriptor {
                dimension: Some(wgpu::TextureViewDimension::D2Array),
                ..Default::default()
            });
            Some((sun, view))
        }
        None => None,
    };
    // Each light buffer's bindings: its lights, spots' projections and
    // texture array, and shadow maps (lit transparency binds the same).
    let mut light_sets = Vec::with_capacity(scene.lights().len());
    for (index, set) in scene.lights().iter().enumerate() {
        let spot_textures = textures.spots.get(index).copied().flatten();
        let b = crate::lighting::bind_light_buffer(
            Bindings::new().buffer("lights", set.lights.buffer()),
            cx,
            &set.lights,
            set.shadows.as_deref(),
            spot_textures,
            "environment probe",
        )?;
        light_sets.push((light_pass(set, spot_textures.is_some()), b));
    }
    let (vertices, indices, _) = renderer.meshes.buffers();
    // A storage binding cannot be empty: an empty layer binds one unused instance.
    let empty: [GpuInstance; 1] = [bytemuck::Zeroable::zeroed()];
    let instances: &[GpuInstance] = if packed.instances.is_empty() {
        &empty
    } else {
        &packed.instances
    };
    let instances = device.create_buffer_init(&wgpu::util::BufferInitDescriptor {
        label: Some("environment probe instances"),
        contents: bytemuck::cast_slice(instances),
        usage: wgpu::BufferUsages::STORAGE,
    });
    // Per layer with instances and pass: its permutation, pipeline and the
    // bindings every face shares (textures, world, lights).
    let base_pass = ProbePass::Base {
        sun_shadow: shadow.is_some(),
    };
    let mut draws_of = Vec::new();
    let mut layer_uniforms = Vec::new();
    for (index, (range, maps)) in packed.ranges.iter().zip(&packed.maps).enumerate() {
        if range.0 == range.1 {
            continue;
        }
        // A texture the pass was not handed is drawn without (never the
        // case when declared together); the key follows what is bound.
        let color = textures.color.get(index).copied().flatten();
        let normal = textures.normal.get(index).copied().flatten();
        let world = packed.worlds.get(index).cloned().flatten();
        let uv = if color.is_none() && normal.is_none() {
            ProbeUv::None
        } else {
            maps.uv
        };
        let uniform = (uv == ProbeUv::Triplanar).then(|| {
            device.create_buffer_init(&wgpu::util::BufferInitDescriptor {
                label: Some("environment probe layer"),
                contents: bytemuck::bytes_of(&GpuProbeLayer {
                    triplanar_sharpness: maps.sharpness as f32,
                    pad: [0.0; 3],
                }),
                usage: wgpu::BufferUsages::UNIFORM,
            })
        });
        layer_uniforms.push((index, color, normal, world, uniform));
    }
    for (index, color, normal, world, uniform) in &layer_uniforms {
        let range = packed.ranges[*index];
        let passes = std::iter::once((base_pass, None))
            .chain(light_sets.iter().map(|(pass, b)| (*pass, Some(b))));
        for (pass, light) in passes {
            let key = faces_key(packed, textures, *index, pass).key();
            let lit = matches!(pass, ProbePass::Light { .. });
            let pipeline = pipeline(cx, &key, lit)?;
            let mut b = Bindings::new()
                .buffer("vertices", &vertices)
                .buffer("indices", &indices)
                .buffer("instances", &instances)
                .buffer_opt("probe_layer", uniform.as_ref());
            if let Some(color) = color {
                b = b
                    .texture("color_map", *color)
                    .sampler("color_sampler", Sampling::LinearRepeat);
            }
            if let Some(normal) = normal {
                b = b
                    .texture("normal_map", *normal)
                    .sampler("normal_sampler", Sampling::LinearRepeat);
            }
            if let Some(world) = world {
                b = b.extend(world.bindings(None));
                if let Some(maps) = world.maps_bindings() {
                    b = b.extend(maps);
                }
            }
            match (light, &shadow) {
                (Some(light), _) => b = b.extend(light.clone()),
                (None, Some((sun, depth))) => {
                    b = b
                        .view("shadow_maps", depth.clone())
                        .buffer("shadow_views", sun.maps.views())
                        .buffer("shadow_params", sun.maps.params());
                }
                (None, None) => {}
            }
            draws_of.push(LayerDraw {
                range,
                key,
                pipeline,
                bindings: b,
                lit,
            });
        }
    }
    let depth = device.create_texture(&wgpu::TextureDescriptor {
        label: Some("environment probe depth"),
        size: wgpu::Extent3d {
            width: size,
            height: size,
            depth_or_array_layers: 1,
        },
        mip_level_count: 1,
        sample_count: 1,
        dimension: wgpu::TextureDimension::D2,
        format: DEPTH_FORMAT,
        usage: wgpu::TextureUsages::RENDER_ATTACHMENT,
        view_formats: &[],
    });
    let depth_view = depth.create_view(&Default::default());
    let mut faces = Vec::with_capacity(6);
    for face in 0..6u32 {
        let uniform = GpuProbeFace {
            view_projection: face_view_projection(face, s.position).to_cols_array_2d(),
            position: s.position.extend(1.0).to_array(),
            towards_sun: towards_sun.extend(0.0).to_array(),
            sun_color: l.sun_color.extend(0.0).to_array(),
            ambient: l.ambient.extend(0.0).to_array(),
            shadow: [shadow.as_ref().map_or(0, |(sun, _)| sun.slice), 0, 0, 0],
            light_params: [
                scene.max_lights(),
                SURFACE_ROUGHNESS.to_bits(),
                SURFACE_METALLIC.to_bits(),
                0,
            ],
        };
        let buffer = device.create_buffer_init(&wgpu::util::BufferInitDescriptor {
            label: Some("environment probe face"),
            contents: bytemuck::bytes_of(&uniform),
            usage: wgpu::BufferUsages::UNIFORM,
        });
        let mut per_draw = Vec::with_capacity(draws_of.len());
        for d in &draws_of {
            let b = d.bindings.clone().buffer("face", &buffer);
            per_draw.push(cx.render_bind_groups(&d.key, &["vs", "fs"], &d.pipeline, b)?);
        }
        let target = base.create_view(&wgpu::TextureViewDescriptor {
            label: Some("environment probe face"),
            dimension: Some(wgpu::TextureViewDimension::D2),
            base_mip_level: 0,
            mip_level_count: Some(1),
            base_array_layer: face,
            array_layer_count: Some(1),
            ..Default::default()
        });
        faces.push((per_draw, target));
    }
    let clear = wgpu::Color {
        r: f64::from(l.background.x),
        g: f64::from(l.background.y),
        b: f64::from(l.background.z),
        a: 1.0,
    };
    let pair = cx.render_timestamps();
    let mut draws = 0;
    for (index, (groups, target)) in faces.iter().enumerate() {
        // The six faces timed as one: the first begins, the last ends.
        let timestamps = pair.as_ref().and_then(|p| {
            let begin = (index == 0)
                .then_some(p.beginning_of_pass_write_index)
                .flatten();
            let end = (index == 5).then_some(p.end_of_pass_write_index).flatten();
            (begin.is_some() || end.is_some()).then_some(wgpu::RenderPassTimestampWrites {
                query_set: p.query_set,
                beginning_of_pass_write_index: begin,
                end_of_pass_write_index: end,
            })
        });
        let mut pass = cx.encoder().begin_render_pass(&wgpu::RenderPassDescriptor {
            label: Some("environment probe face"),
            color_attachments: &[Some(wgpu::RenderPassColorAttachment {
                view: target,
                depth_slice: None,
                resolve_target: None,
                ops: wgpu::Operations {
                    load: wgpu::LoadOp::Clear(clear),
                    store: wgpu::StoreOp::Store,
                },
            })],
            depth_stencil_attachment: Some(wgpu::RenderPassDepthStencilAttachment {
                view: &depth_view,
                depth_ops: Some(wgpu::Operations {
                    load: wgpu::LoadOp::Clear(0.0),
                    store: wgpu::StoreOp::Discard,
                }),
                stencil_ops: None,
            }),
            timestamp_writes: timestamps,
            occlusion_query_set: None,
            multiview_mask: None,
        });
        // Every base pass before any light pass: a light pass adds only
        // where the nearest surface of all layers lies (depth equal).
        let order = |lit: bool| {
            draws_of
                .iter()
                .zip(groups)
                .filter(move |(d, _)| d.lit == lit)
        };
        for (d, groups) in order(false).chain(order(true)) {
            let range = d.range;
            pass.set_pipeline(&d.pipeline);
            for (i, group) in groups.iter().enumerate() {
                pass.set_bind_group(i as u32, group, &[]);
            }
            for draw in packed.draws.iter().filter(|d| {
                d.instance_count > 0
                    && d.index_count > 0
                    && (range.0..range.1).contains(&d.first_instance)
            }) {
                pass.draw(
                    0..draw.index_count,
                    draw.first_instance..draw.first_instance + draw.instance_count,
                );
                draws += 1;
            }
        }
    }
    cx.draws += draws;
    Ok(())
}

/// The layout the shader sees (shaders/layout.rs).
#[cfg(test)]
mod wgsl_layout {
    use super::*;

    #[test]
    fn gpu_probe_face_matches_probe_face_in_the_shader() {
        crate::assert_wgsl_layout!(
            GpuProbeFace,
            crate::environment::probe::key::ProbeFacesKey,
            [],
            "ProbeFace",
            [
                view_projection,
                position,
                towards_sun,
                sun_color,
                ambient,
                shadow,
                light_params
            ]
        );
    }
}
