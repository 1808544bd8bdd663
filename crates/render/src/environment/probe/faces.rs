//! Rendering a probe's six faces (shaders/environment/environment_probe.wgsl) into its
//! base cube's level 0 on the raster hardware: one render pass per face,
//! the layer's instances pulled from the mesh arena as the shadow depth
//! pass pulls them, each surface shaded forward with the probe's lighting,
//! its layer's Color Texture and Normal Map (one pipeline permutation per
//! kind of layer: none, by UVs, triplanar) and, when the probe has one, the
//! sun's shadow maps. The prefilter then makes the cube's mips and
//! roughness levels from it.

use std::hash::{Hash, Hasher};

use wgpu::util::DeviceExt;

use super::key::{ProbeFacesKey, ProbeUv};
use super::{ProbeScene, face_view_projection};
use crate::error::RenderError;
use crate::frame_graph::{Bindings, PassContext, Tex};
use crate::gbuffer::{Draw, GpuInstance, Layer, pack_instances};
use crate::mesh_arena::pulled_pipeline;
use crate::renderer::Renderer;
use crate::shaders::{Permutation, Sampling, ShaderKey};

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
}

/// How a layer's Color Texture and Normal Map reach the probe's faces (by name).
#[derive(Clone, Debug, PartialEq, Hash)]
struct ProbeMaps {
    color: Option<String>,
    normal: Option<String>,
    uv: ProbeUv,
    /// Triplanar: the normal's power that blends the three projections.
    sharpness: u32,
}

impl ProbeMaps {
    fn of(layer: &Layer) -> Self {
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
        }
    }
}

impl PackedProbe {
    pub(crate) fn new(layers: &[std::sync::Arc<Layer>]) -> Self {
        let (instances, draws, ranges) = pack_instances(layers);
        let maps = layers.iter().map(|l| ProbeMaps::of(l)).collect();
        PackedProbe {
            instances,
            draws,
            ranges,
            maps,
        }
    }
}

/// Each layer's Color Texture and Normal Map as the frame graph handed
/// them to the probe's pass (None: the layer has none).
#[derive(Clone, Debug, Default)]
pub(crate) struct ProbeTextures {
    pub color: Vec<Option<Tex>>,
    pub normal: Vec<Option<Tex>>,
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
}

/// The faces' pipeline for one kind of layer (`key`).
fn pipeline(
    cx: &mut PassContext<'_>,
    key: &ShaderKey,
) -> Result<wgpu::RenderPipeline, RenderError> {
    let device = cx.gpu.device.clone();
    cx.shaders
        .render_pipeline(&device, key, "rgba16f", |module, cache| {
            // Both sides: the faces' handedness differs, and a probe
            // inside an object sees its inside (the shader turns each
            // normal towards the probe).
            pulled_pipeline(
                &device,
                module,
                cache,
                "environment probe faces",
                wgpu::PrimitiveState::default(),
                Some(wgpu::DepthStencilState {
                    format: DEPTH_FORMAT,
                    depth_write_enabled: Some(true),
                    // Reversed-Z: nearer is greater.
                    depth_compare: Some(wgpu::CompareFunction::Greater),
                    stencil: Default::default(),
                    bias: Default::default(),
                }),
                &[Some(COLOR_FORMAT.into())],
            )
        })
}

/// Draw `scene` into level 0 of `base` (a cube, RENDER_ATTACHMENT), one
/// render pass per face. `textures`: each layer's Color Texture and Normal
/// Map as the frame graph handed them to this pass.
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
    // The sun's shadow maps, when the probe has them: rendered this frame
    // (the pass read their token) or kept from an earlier one.
    let shadow = match scene.sun_shadow() {
        Some(sun) => {
            let (depth, _) = sun.maps.textures().ok_or_else(|| RenderError::Pass {
                pass: "EnvironmentProbe".to_owned(),
                message: "the sun's shadow maps were not rendered this frame".to_owned(),
            })?;
            let view = depth.create_view(&wgpu::TextureViewDescriptor {
                dimension: Some(wgpu::TextureViewDimension::D2Array),
                ..Default::default()
            });
            Some((sun, view))
        }
        None => None,
    };
    // Per layer with instances: its permutation, pipeline, textures and (triplanar) uniform.
    let mut layers = Vec::new();
    for (index, (range, maps)) in packed.ranges.iter().zip(&packed.maps).enumerate() {
        if range.0 == range.1 {
            continue;
        }
        // A texture the pass was not handed is drawn without (never the
        // case when declared together); the key follows what is bound.
        let color = textures.color.get(index).copied().flatten();
        let normal = textures.normal.get(index).copied().flatten();
        let uv = if color.is_none() && normal.is_none() {
            ProbeUv::None
        } else {
            maps.uv
        };
        let faces_key = ProbeFacesKey {
            uv,
            color_map: color.is_some(),
            normal_map: normal.is_some(),
            sun_shadow: shadow.is_some(),
        };
        let key = faces_key.key();
        let pipeline = pipeline(cx, &key)?;
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
        layers.push((*range, key, pipeline, (color, normal), uniform));
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
        };
        let buffer = device.create_buffer_init(&wgpu::util::BufferInitDescriptor {
            label: Some("environment probe face"),
            contents: bytemuck::bytes_of(&uniform),
            usage: wgpu::BufferUsages::UNIFORM,
        });
        let mut per_layer = Vec::with_capacity(layers.len());
        for (_, key, pipeline, (color, normal), uniform) in &layers {
            let mut b = Bindings::new()
                .buffer("face", &buffer)
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
            if let Some((sun, depth)) = &shadow {
                b = b
                    .view("shadow_maps", depth.clone())
                    .buffer("shadow_views", sun.maps.views())
                    .buffer("shadow_params", sun.maps.params());
            }
            per_layer.push(cx.render_bind_groups(key, &["vs", "fs"], pipeline, b)?);
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
        faces.push((per_layer, target));
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
        for ((range, _, pipeline, _, _), groups) in layers.iter().zip(groups) {
            pass.set_pipeline(pipeline);
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
                shadow
            ]
        );
    }
}
