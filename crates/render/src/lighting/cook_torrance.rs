//! `CookTorrance` for point lights: the light assignment (clustered or
//! not) and the shading pass, as one recipe with two frame-graph passes.

use std::sync::Arc;

use super::clusters::{ClusterGrid, ClusterStore};
use super::{LightBuffer, LightKind};
use crate::error::RenderError;
use crate::frame_graph::{FrameGraph, PassContext, TextureDesc};
use crate::gbuffer::GBuffer;
use crate::material::{FEATURE_FAKE_SSS, MaterialWorld};
use crate::recipe::{Recipe, TextureRef, next_recipe_id};
use crate::renderer::Renderer;
use crate::shaders::{Sampling, ShaderKey};
use crate::shadows::{ShadowFilter, ShadowMaps};

/// Where roughness and metallic come from.
#[derive(Clone, Debug)]
pub enum Surfaces {
    /// (roughness, metallic) per material id, wrapping: the node's own pins.
    PerMaterialId(Vec<(f32, f32)>),
    /// Each material's CookTorrance feature in a material buffer.
    Materials(Arc<MaterialWorld>),
}

/// How the shading pass finds its lights.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum LightLoop {
    /// Naive for a handful of lights ([`FEW_LIGHTS`] or fewer), Clustered beyond.
    Auto,
    /// Only the lights listed in the pixel's froxel.
    Clustered,
    /// Every light for every pixel: the reference the clustered path is tested against.
    Naive,
}

/// Up to this many lights, `Auto` walks them all: assigning them to froxels
/// costs more than it saves (three spots: 0.059 ms of assignment plus a pass
/// boundary on the H100, where walking three lights per pixel costs nothing
/// measurable over walking their froxel lists).
pub const FEW_LIGHTS: u32 = 16;

/// The walk a recipe does, `LightLoop` resolved for its lights.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum Walk {
    Clustered,
    Naive,
}

pub struct CookTorrance {
    id: u64,
    owner: Option<u32>,
    gbuffer: Arc<GBuffer>,
    lights: Arc<LightBuffer>,
    walk: Walk,
    energy_compensation: bool,
    surfaces: wgpu::Buffer,
    /// Roughness and metallic per material from the material buffer, when
    /// given (else `surfaces`); either way, where the G-buffer's surface
    /// target is written (surface maps, a shader node material), its own.
    materials: Option<Arc<MaterialWorld>>,
    grid: wgpu::Buffer,
    clusters: Arc<ClusterStore>,
    token: String,
    pub diffuse: String,
    pub specular: String,
    /// The subsurface output: only when some material of the world has FakeSSS.
    pub sss: Option<String>,
    /// Shadow maps for the lights whose `shadow` slice is set.
    shadows: Option<Arc<ShadowMaps>>,
}

/// Near and far of a conventional (0..1 depth) perspective projection; None for others.
fn near_far(projection: glam::Mat4) -> Option<(f32, f32)> {
    let (a, b) = (projection.z_axis.z, projection.w_axis.z);
    let near = b / a;
    let far = b / (a + 1.0);
    (near.is_finite() && far.is_finite() && near > 0.0 && far > near).then_some((near, far))
}

impl CookTorrance {
    /// `surfaces`: (roughness, metallic) per material id, wrapping.
    pub fn new(
        renderer: &Renderer,
        owner: Option<u32>,
        gbuffer: Arc<GBuffer>,
        lights: Arc<LightBuffer>,
        mode: LightLoop,
        energy_compensation: bool,
        surfaces: Surfaces,
    ) -> Arc<Self> {
        Self::with_shadows(
            renderer,
            owner,
            gbuffer,
            lights,
            mode,
            energy_compensation,
            surfaces,
            None,
        )
    }

    /// As [`CookTorrance::new`], with the shadow maps its lights' slices index.
    #[allow(clippy::too_many_arguments)]
    pub fn with_shadows(
        renderer: &Renderer,
        owner: Option<u32>,
        gbuffer: Arc<GBuffer>,
        lights: Arc<LightBuffer>,
        mode: LightLoop,
        energy_compensation: bool,
        surfaces: Surfaces,
        shadows: Option<Arc<ShadowMaps>>,
    ) -> Arc<Self> {
        let (surfaces, materials) = match surfaces {
            Surfaces::PerMaterialId(list) => (list, None),
            Surfaces::Materials(world) => (Vec::new(), Some(world)),
        };
        let id = next_recipe_id();
        let mut packed: Vec<[f32; 2]> = surfaces
            .iter()
            .map(|&(r, m)| [sanitize(r), sanitize(m)])
            .collect();
        if packed.is_empty() {
            packed.push([0.5, 0.0]);
        }
        let surfaces = renderer.kept_init(
            owner,
            "cook torrance surfaces",
            bytemuck::cast_slice(&packed),
            wgpu::BufferUsages::STORAGE,
        );
        // Written each frame; kept under the node so its bind groups are reused.
        let grid = renderer.kept_buffer(
            owner,
            "cluster grid",
            32,
            wgpu::BufferUsages::UNIFORM | wgpu::BufferUsages::COPY_DST,
        );
        let sss = materials
            .as_ref()
            .filter(|w| w.scatters_subsurface())
            .map(|_| format!("cooktorrance{id}/sss"));
        let walk = match mode {
            // Suns have no range to cluster by: every pixel sees every sun.
            _ if lights.kind == LightKind::Sun => Walk::Naive,
            LightLoop::Auto if lights.count() <= FEW_LIGHTS => Walk::Naive,
            LightLoop::Auto | LightLoop::Clustered => Walk::Clustered,
            LightLoop::Naive => Walk::Naive,
        };
        Arc::new(CookTorrance {
            id,
            owner,
            gbuffer,
            lights,
            walk,
            energy_compensation,
            surfaces,
            materials,
            grid,
            clusters: match owner {
                Some(node) => renderer.state::<ClusterStore>(u64::from(node)),
                None => Arc::default(),
            },
            token: format!("cooktorrance{id}/lights"),
            diffuse: format!("cooktorrance{id}/diffuse"),
            specular: format!("cooktorrance{id}/specular"),
            sss,
            shadows,
        })
    }

    pub fn diffuse_texture(self: &Arc<Self>) -> TextureRef {
        TextureRef {
            recipe: self.clone(),
            name: self.diffuse.clone(),
        }
    }

    pub fn specular_texture(self: &Arc<Self>) -> TextureRef {
        TextureRef {
            recipe: self.clone(),
            name: self.specular.clone(),
        }
    }

    /// The subsurface term, when some material has the FakeSSS feature (else there is none to add).
    pub fn sss_texture(self: &Arc<Self>) -> Option<TextureRef> {
        self.sss.clone().map(|name| TextureRef {
            recipe: self.clone(),
            name,
        })
    }

    /// Diffuse, specular and (with FakeSSS) subsurface: one input of a CompositeLight.
    pub fn components(self: &Arc<Self>) -> super::LightComponents {
        super::LightComponents {
            diffuse: self.diffuse_texture(),
            specular: self.specular_texture(),
            sss: self.sss_texture(),
        }
    }

    pub fn gbuffer(&self) -> &Arc<GBuffer> {
        &self.gbuffer
    }

    /// Whether some material's CookTorrance or FakeSSS reads a texture.
    fn textured(&self) -> bool {
        self.materials.as_ref().is_some_and(|w| {
            w.textured(1 << crate::material::FEATURE_COOK_TORRANCE | 1 << FEATURE_FAKE_SSS)
        })
    }

    fn label(&self, what: &str) -> String {
        crate::recipe::pass_name("CookTorrance", self.owner, Some(what))
    }

    fn assign(&self, grid: ClusterGrid, cx: &mut PassContext<'_>) -> Result<(), RenderError> {
        let device = cx.gpu.device.clone();
        let count = self.lights.count();
        let guard = self.clusters.get(cx.gpu, grid.clusters(), count);
        let Some(b) = guard.as_ref() else {
            return Ok(());
        };
        cx.encoder().clear_buffer(&b.counts, 0, None);
        cx.gpu.queue.write_buffer(
            &b.totals,
            0,
            bytemuck::cast_slice(&[0u32, b.capacity, 0, 0]),
        );
        let key = ShaderKey::new("lighting/clusters.wgsl", []);
        let all = [
            (0, self.gbuffer.camera_buffer().as_entire_binding()),
            (1, self.grid.as_entire_binding()),
            (2, self.lights.buffer().as_entire_binding()),
            (3, b.view_lights.as_entire_binding()),
            (4, b.counts.as_entire_binding()),
            (5, b.offsets.as_entire_binding()),
            (6, b.indices.as_entire_binding()),
            (7, b.totals.as_entire_binding()),
        ];
        // Only the clustered walk runs this pass; the naive loop moves its
        // few lights to view space itself.
        let steps = ["transform", "count", "scan", "fill"];
        let mut work = Vec::new();
        for step in steps {
            let pipeline = cx.shaders.compute_pipeline(&device, &key, step)?;
            let group = cx
                .shaders
                .bind_group(&device, &key, step, &pipeline, 0, &all)?;
            // transform: a thread per light; count and fill: workgroups per
            // light (x up to 65,535, then y; z splits a light's froxels);
            // scan: one workgroup.
            let groups = match step {
                "scan" => (1, 1, 1),
                "transform" => (count.div_ceil(64).max(1), 1, 1),
                _ => (
                    count.clamp(1, 65_535),
                    count.div_ceil(65_535).max(1),
                    workgroups_per_light(count),
                ),
            };
            work.push((pipeline, group, groups));
        }
        let pass = cx.compute_pass("light assignment");
        for (pipeline, group, groups) in &work {
            pass.set_pipeline(pipeline);
            pass.set_bind_group(0, group, &[]);
            pass.dispatch_workgroups(groups.0, groups.1, groups.2);
        }
        Ok(())
    }

    fn shade(&self, cx: &mut PassContext<'_>) -> Result<(), RenderError> {
        let device = cx.gpu.device.clone();
        let mut features: Vec<&'static str> = self.lights.kind.feature().into_iter().collect();
        if self.walk == Walk::Clustered {
            features.push("CLUSTERED");
        }
        if self.energy_compensation {
            features.push("ENERGY_COMPENSATION");
        }
        if self.materials.is_some() {
            features.push("MATERIALS");
        }
        if self.sss.is_some() {
            features.push("FAKE_SSS");
        }
        if self.lights.textures().is_some() {
            features.push("SPOT_TEXTURE");
        }
        if self.textured() {
            features.push("MATERIAL_TEXTURES");
        }
        // Roughness and metallic where the G-buffer resolved them, with or without materials.
        features.extend(self.gbuffer.targets.surface_feature());
        if let Some(shadows) = &self.shadows {
            features.push("SHADOWS");
            match shadows.filter() {
                ShadowFilter::Raw => {}
                filter => features.push(filter.feature()),
            }
        }
        let key = ShaderKey::new("lighting/cook_torrance.wgsl", features);
        let pipeline = cx.shaders.compute_pipeline(&device, &key, "main")?;
        let g = &self.gbuffer;
        let (color, normals, depth) = (
            cx.view_named(&g.targets.color)?,
            cx.view_named(&g.targets.normals)?,
            cx.view_named(&g.targets.depth)?,
        );
        let (diffuse, specular) = (
            cx.view_named(&self.diffuse)?,
            cx.view_named(&self.specular)?,
        );
        let sss = match &self.sss {
            Some(name) => Some(cx.view_named(name)?),
            None => None,
        };
        let guard = self.clusters.get(cx.gpu, 1, self.lights.count());
        let Some(b) = guard.as_ref() else {
            return Ok(());
        };
        let all = [
            (0, g.camera_buffer().as_entire_binding()),
            (1, self.grid.as_entire_binding()),
            (2, self.lights.buffer().as_entire_binding()),
            (3, b.view_lights.as_entire_binding()),
            (4, b.counts.as_entire_binding()),
            (5, b.offsets.as_entire_binding()),
            (6, b.indices.as_entire_binding()),
            (7, self.surfaces.as_entire_binding()),
            (8, wgpu::BindingResource::TextureView(&color)),
            (9, wgpu::BindingResource::TextureView(&normals)),
            (10, wgpu::BindingResource::TextureView(&depth)),
            (11, wgpu::BindingResource::TextureView(&diffuse)),
            (12, wgpu::BindingResource::TextureView(&specular)),
        ];
        let mut all = all.to_vec();
        let surface = match &g.targets.surface {
            Some(name) => Some(cx.view_named(name)?),
            None => None,
        };
        if let Some(surface) = &surface {
            all.push((
                crate::gbuffer::SURFACE_TARGET_BINDING,
                wgpu::BindingResource::TextureView(surface),
            ));
        }
        if let Some(sss) = &sss {
            all.push((13, wgpu::BindingResource::TextureView(sss)));
        }
        if let Some(projections) = self.lights.projections() {
            all.push((14, projections.as_entire_binding()));
        }
        let spot_textures = match self.lights.textures() {
            Some(t) => {
                let texture = cx.texture_named(&t.name)?.clone();
                let view = cx.view_of(&texture, crate::texture_pool::ViewSpec::array());
                Some((view, cx.sampler(Sampling::LinearClamp)))
            }
            None => None,
        };
        if let Some((view, sampler)) = &spot_textures {
            all.push((15, wgpu::BindingResource::TextureView(view)));
            all.push((16, wgpu::BindingResource::Sampler(sampler)));
        }
        let shadow_views = match &self.shadows {
            Some(shadows) => {
                let (depth, moments) = shadows.textures().ok_or_else(|| RenderError::Pass {
                    pass: "cook torrance".to_owned(),
                    message: "the shadow maps were not rendered this frame".to_owned(),
                })?;
                let array =
                    |t: &wgpu::Texture| cx.view_of(t, crate::texture_pool::ViewSpec::array());
                let depth = array(&depth);
                let moments = moments.map(|m| array(&m));
                Some((shadows, depth, moments))
            }
            None => None,
        };
        if let Some((shadows, depth, moments)) = &shadow_views {
            all.push((17, wgpu::BindingResource::TextureView(depth)));
            all.push((19, shadows.views().as_entire_binding()));
            all.push((20, shadows.params().as_entire_binding()));
            if let Some(moments) = moments {
                all.push((21, wgpu::BindingResource::TextureView(moments)));
            }
        }
        let group = cx
            .shaders
            .bind_group(&device, &key, "main", &pipeline, 0, &all)?;
        let material_group = match &self.materials {
            Some(world) => Some(world.bind_group(
                cx,
                &key,
                &pipeline,
                self.textured(),
                g.targets.surface_targets(),
            )?),
            None => None,
        };
        let (w, h) = g.pixel_size(cx.output_size);
        let groups: Vec<&wgpu::BindGroup> = std::iter::once(&group)
            .chain(material_group.as_ref())
            .collect();
        cx.dispatch(
            "cook torrance",
            &pipeline,
            &groups,
            // 16x16 blocks: shaders/lighting/cook_torrance.wgsl's GROUP.
            (w.div_ceil(16), h.div_ceil(16), 1),
        );
        Ok(())
    }
}

/// Roughness and metallic from a pin: finite and in 0..1.
fn sanitize(v: f32) -> f32 {
    if v.is_finite() {
        v.clamp(0.0, 1.0)
    } else {
        0.5
    }
}

impl Recipe for CookTorrance {
    fn declare<'a>(&'a self, renderer: &'a Renderer, fg: &mut FrameGraph<'a>) {
        if !fg.include(self.id) {
            return;
        }
        self.gbuffer.declare(renderer, fg);
        let size = self.gbuffer.pixel_size(fg.output_size());
        let (near, far) = near_far(self.gbuffer.camera.projection).unwrap_or((0.1, 1000.0));
        let grid = ClusterGrid::new(size, near, far);
        // Only when it changed (size, near and far, light count): most frames it did not.
        renderer.write_kept(
            self.owner,
            "cluster grid",
            &self.grid,
            bytemuck::cast_slice(&grid.uniform(self.lights.count())),
        );
        // Clustered: assignment is a pass of its own, timed apart. Naive:
        // the shade pass moves each light to view space as it reads it. (A
        // dispatch of its own before the shade, 6 µs on the H100, cost a
        // compute-pass boundary and barrier more: 17 µs of idle before each
        // naive shade against 7.6 before other passes, session 10.)
        let clustered = self.walk == Walk::Clustered;
        if clustered {
            fg.add_pass(
                self.label("clustered light assignment"),
                self.owner,
                &[],
                &[(&self.token, TextureDesc::token())],
                move |cx| self.assign(grid, cx),
            );
        }
        let g = &self.gbuffer.targets;
        let hdr = TextureDesc::storage(wgpu::TextureFormat::Rgba16Float).size(self.gbuffer.size);
        let mut outputs = vec![(self.diffuse.as_str(), hdr), (self.specular.as_str(), hdr)];
        if let Some(sss) = &self.sss {
            outputs.push((sss.as_str(), hdr));
        }
        let mut reads = vec![g.color.as_str(), g.normals.as_str(), g.depth.as_str()];
        if clustered {
            reads.push(self.token.as_str());
        }
        if let Some(textures) = self.lights.textures() {
            textures.recipe.declare(renderer, fg);
            reads.push(&textures.name);
        }
        reads.extend(g.surface.as_deref());
        if let Some(world) = &self.materials {
            reads.extend(world.declare_textures(
                renderer,
                fg,
                self.textured(),
                g.surface_targets(),
            ));
        }
        if let Some(shadows) = &self.shadows {
            shadows.declare(renderer, fg);
            reads.push(shadows.token());
        }
        fg.add_pass(
            self.label("shade"),
            self.owner,
            &reads,
            &outputs,
            move |cx| self.shade(cx),
        );
    }
}

/// How many workgroups share each light's froxels when `lights` are
/// assigned: enough that a few lights still fill the GPU (three big spots
/// took 0.22 ms at one workgroup each on the H100, walking 16,000 froxels
/// 64 at a time), one where lights alone are plenty.
fn workgroups_per_light(lights: u32) -> u32 {
    (16_384 / lights.max(1)).clamp(1, 64)
}
