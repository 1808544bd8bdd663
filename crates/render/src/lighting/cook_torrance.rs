//! `CookTorrance` for point lights: the light assignment (clustered or
//! not) and the shading pass, as one recipe with two frame-graph passes.

use std::sync::Arc;

use super::clusters::{ClusterBuffers, ClusterGrid, ClusterStore};
use super::cook_torrance_key::{
    BrdfMaterials, CookTorranceKey, Lights, MaterialReads, Shading, ShadowSampling,
};
use super::{LightBuffer, LightKind};
use crate::adapter_class::AdapterClass;
use crate::error::RenderError;
use crate::frame_graph::{Bindings, FrameGraph, PassBuilder, PassContext, Tex, TextureDesc};
use crate::gbuffer::GBuffer;
use crate::gbuffer::SurfaceShader;
use crate::material::{
    FEATURE_CLEARCOAT, FEATURE_FAKE_SSS, FEATURE_IRIDESCENCE, FEATURE_SHEEN, MaterialTextures,
    MaterialWorld,
};
use crate::recipe::{Recipe, TextureRef, next_recipe_id};
use crate::renderer::Renderer;
use crate::report::PassName;
use crate::shaders::{Permutation, ShaderKey};
use crate::shadows::ShadowMaps;

pub use super::cook_torrance_key::Walk;

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
    /// Naive for a handful of lights ([`FEW_LIGHTS`] or fewer); beyond, what
    /// measures fastest on the adapter's class ([`auto_walk`]).
    Auto,
    /// Only the lights listed in the pixel's froxel, shared by 16x16 blocks
    /// through workgroup memory, slice by slice.
    Clustered,
    /// As Clustered over depth-bounded tiles: each 16x16 tile reads only the
    /// slices its pixels occupy, as one sequence, and drops lights outside
    /// its depth bins and its 8x4 lane groups' boxes (shaders/lighting/cook_torrance.wgsl, TILED).
    Tiled,
    /// Each pixel walks its froxel's list alone: no workgroup memory, no
    /// barrier (what a CPU adapter runs fastest).
    PerPixel,
    /// Every light for every pixel: the reference the clustered path is tested against.
    Naive,
}

/// Up to this many lights, `Auto` walks them all: assigning them to froxels
/// costs more than it saves (three spots: 0.059 ms of assignment plus a pass
/// boundary on the H100, where walking three lights per pixel costs nothing
/// measurable over walking their froxel lists).
pub const FEW_LIGHTS: u32 = 16;

// TILED keeps the slices a tile occupies in one 32-bit mask.
const _: () = assert!(super::clusters::ClusterGrid::SLICES <= 32);

/// The walk `mode` takes for `count` lights of `kind` on an adapter of `class`.
pub fn resolve_walk(mode: LightLoop, kind: LightKind, count: u32, class: AdapterClass) -> Walk {
    match mode {
        // Suns have no range to cluster by: every pixel sees every sun.
        _ if kind == LightKind::Sun => Walk::Naive,
        LightLoop::Auto if count <= FEW_LIGHTS => Walk::Naive,
        LightLoop::Auto => auto_walk(class),
        LightLoop::Clustered => Walk::Clustered,
        LightLoop::Tiled => Walk::Tiled,
        LightLoop::PerPixel => Walk::PerPixel,
        LightLoop::Naive => Walk::Naive,
    }
}

/// `Auto`'s walk past [`FEW_LIGHTS`]. A CPU adapter walks per pixel: the
/// shared-memory walks' barriers are coroutine switches on llvmpipe
/// (docs/benchmarks.md, "lavapipe"). A GPU keeps the clustered walk, the
/// one measured on the H200, until Tiled is measured there against it
/// (docs/benchmarks.md, "Tiled light shading").
pub fn auto_walk(class: AdapterClass) -> Walk {
    match class {
        AdapterClass::Gpu => Walk::Clustered,
        AdapterClass::Cpu => Walk::PerPixel,
    }
}

pub struct CookTorrance {
    id: u64,
    owner: Option<u32>,
    gbuffer: Arc<GBuffer>,
    lights: Arc<LightBuffer>,
    walk: Walk,
    energy_compensation: bool,
    /// The light cutoff (illuminance; 0: none, the exact image): each light
    /// reaches only as far as its illuminance stays above it
    /// ([`CookTorrance::with_light_cutoff`]).
    light_cutoff: f32,
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
    /// A light shader node's `light` function in place of the BRDF (CUSTOM_LIGHT).
    custom: Option<CustomLight>,
}

/// A light shader node's file spliced into the light loop: described as a
/// material's is (the file, its bindings, pins and textures), its pins'
/// uniform block uploaded under the node.
struct CustomLight {
    shader: Arc<SurfaceShader>,
    params: Option<wgpu::Buffer>,
}

/// Near and far of a conventional (0..1 depth) perspective projection; None for others.
pub(crate) fn near_far(projection: glam::Mat4) -> Option<(f32, f32)> {
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
            super::GRID_BYTES,
            wgpu::BufferUsages::UNIFORM | wgpu::BufferUsages::COPY_DST,
        );
        let sss = materials
            .as_ref()
            .filter(|w| w.scatters_subsurface())
            .map(|_| format!("cooktorrance{id}/sss"));
        let walk = resolve_walk(
            mode,
            lights.kind,
            lights.count(),
            renderer.gpu.adapter_class(),
        );
        Arc::new(CookTorrance {
            id,
            owner,
            gbuffer,
            lights,
            walk,
            energy_compensation,
            light_cutoff: 0.0,
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
            custom: None,
        })
    }

    /// As [`CookTorrance::with_shadows`], each light shaded by a light shader
    /// node's `light` function (`shader`: its file, pins and textures) in
    /// place of the BRDF; no energy compensation or subsurface term, which are
    /// the BRDF's. The passes are named after the node (`shader.label`).
    #[allow(clippy::too_many_arguments)]
    pub fn with_light_shader(
        renderer: &Renderer,
        owner: Option<u32>,
        gbuffer: Arc<GBuffer>,
        lights: Arc<LightBuffer>,
        mode: LightLoop,
        surfaces: Surfaces,
        shadows: Option<Arc<ShadowMaps>>,
        shader: Arc<SurfaceShader>,
    ) -> Arc<Self> {
        let mut made = Self::with_shadows(
            renderer, owner, gbuffer, lights, mode, false, surfaces, shadows,
        );
        let params = (!shader.params.is_empty()).then(|| {
            renderer.kept_init(
                owner,
                "light shader pins",
                &shader.params,
                wgpu::BufferUsages::UNIFORM,
            )
        });
        let this = Arc::get_mut(&mut made).expect("just made");
        this.sss = None;
        this.custom = Some(CustomLight { shader, params });
        made
    }

    /// This recipe with a light cutoff: an illuminance (in the lights'
    /// units: candela over distance squared) below which a light is left
    /// out. Each light's range shrinks to where its brightest channel's
    /// inverse-square illuminance falls to `cutoff` (never past its own
    /// range), and its window fades it to 0 there: fewer lights per pixel,
    /// each a little dimmer towards its new edge. 0, NaN, infinity or less
    /// than 0: no cutoff, the exact image. Call it on the recipe just made.
    pub fn with_light_cutoff(mut made: Arc<Self>, cutoff: f32) -> Arc<Self> {
        let this = Arc::get_mut(&mut made).expect("a recipe just made is not shared");
        this.light_cutoff = super::light_cutoff(cutoff);
        made
    }

    /// The light cutoff in use (0: none).
    pub fn light_cutoff(&self) -> f32 {
        self.light_cutoff
    }

    /// This recipe with a light merge distance (`light_merge.rs`): point
    /// lights whose cube's centroid lies at least `distance` from a pixel
    /// are shaded there as one light per cube, the near ones one by one.
    /// Fewer evaluations per pixel, each far cube approximated. 0, NaN,
    /// infinity or less than 0: no merging, the exact image; so too for the
    /// naive and tiled walks ([`Walk::merges`]) and for spots and suns. The
    /// merge is kept under the node while the lights and the distance stay.
    /// Call it on the recipe just made.
    pub fn with_light_merge(mut made: Arc<Self>, renderer: &Renderer, distance: f32) -> Arc<Self> {
        let this = Arc::get_mut(&mut made).expect("a recipe just made is not shared");
        if this.walk.merges()
            && let Some(merged) = this.lights.merged(renderer, this.owner, distance)
        {
            this.lights = merged;
        }
        made
    }

    /// Whether its lights are merged ([`CookTorrance::with_light_merge`]).
    pub fn merges_lights(&self) -> bool {
        self.lights.bands().is_some()
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

    /// Whether some material has a clear coat: its lobe is compiled in.
    fn clearcoat(&self) -> bool {
        self.materials
            .as_ref()
            .is_some_and(|w| w.union_flags() & (1 << FEATURE_CLEARCOAT) != 0)
    }

    /// Whether some material has a thin film: its Fresnel is compiled in.
    fn iridescence(&self) -> bool {
        self.materials
            .as_ref()
            .is_some_and(|w| w.union_flags() & (1 << FEATURE_IRIDESCENCE) != 0)
    }

    /// Whether some material has a sheen: its lobe is compiled in.
    fn sheen(&self) -> bool {
        self.materials
            .as_ref()
            .is_some_and(|w| w.union_flags() & (1 << FEATURE_SHEEN) != 0)
    }

    /// Whether the shade pass reads the sheen and film target (SHEEN or
    /// IRIDESCENCE under the built-in BRDF).
    fn sheen_or_film(&self) -> bool {
        self.custom.is_none() && (self.sheen() || self.iridescence())
    }

    /// The walk this recipe's shade pass does.
    pub fn walk(&self) -> Walk {
        self.walk
    }

    fn label(&self, what: impl Into<std::borrow::Cow<'static, str>>) -> PassName {
        match &self.custom {
            Some(c) => PassName::new(c.shader.label.clone()).step(what),
            None => PassName::new("CookTorrance").step(what),
        }
    }

    fn assign(&self, grid: ClusterGrid, cx: &mut PassContext<'_>) -> Result<(), RenderError> {
        super::clusters::assign_lights(
            cx,
            &self.clusters,
            grid,
            &self.grid,
            self.gbuffer.camera_buffer(),
            &self.lights,
            None,
        )
    }

    /// The permutation: what the lights, materials and shadows call for.
    fn key(&self) -> ShaderKey {
        self.shade_key().key()
    }

    /// [`CookTorrance::key`] as its typed key.
    pub(super) fn shade_key(&self) -> CookTorranceKey {
        let reads = MaterialReads {
            textures: self.textured(),
        };
        let materials = self.materials.as_ref().map(|_| reads);
        let shading = match self.custom {
            Some(_) => Shading::Custom { materials },
            None => Shading::Brdf {
                energy_compensation: self.energy_compensation,
                materials: materials.map(|reads| BrdfMaterials {
                    reads,
                    fake_sss: self.sss.is_some(),
                    clearcoat: self.clearcoat(),
                    anisotropy: self.gbuffer.targets.anisotropy.is_some(),
                    iridescence: self.iridescence(),
                    sheen: self.sheen(),
                }),
            },
        };
        let lights = match Lights::new(
            self.lights.kind,
            self.walk,
            self.lights.textures().is_some(),
        ) {
            Lights::Point(walk) if self.merges_lights() => Lights::PointMerged(walk),
            lights => lights,
        };
        CookTorranceKey {
            lights,
            shading,
            shadows: self
                .shadows
                .as_ref()
                .map(|s| ShadowSampling::of(s.filter())),
            // Roughness and metallic where the G-buffer resolved them, with or without materials.
            surface_target: self.gbuffer.targets.surface.is_some(),
        }
    }

    pub(super) fn id(&self) -> u64 {
        self.id
    }

    pub(super) fn owner(&self) -> Option<u32> {
        self.owner
    }

    pub(super) fn lights(&self) -> &LightBuffer {
        &self.lights
    }

    pub(super) fn materials(&self) -> Option<&Arc<MaterialWorld>> {
        self.materials.as_ref()
    }

    pub(super) fn shadow_maps(&self) -> Option<&ShadowMaps> {
        self.shadows.as_deref()
    }

    pub(super) fn cluster_store(&self) -> &ClusterStore {
        &self.clusters
    }

    /// Whether `other` keeps its light assignment in this one's store (two
    /// recipes of one node): their shade passes cannot hold both at once.
    pub(super) fn shares_clusters(&self, other: &CookTorrance) -> bool {
        Arc::ptr_eq(&self.clusters, &other.clusters)
    }

    /// Whether its shade pass may join others' (`light_sets`): a light
    /// shader node's function is spliced into its own composition.
    pub(super) fn fusable(&self) -> bool {
        self.custom.is_none()
    }

    /// The shade pass's resources, by the names the light loop declares
    /// (the fused loop renames them per set, `light_sets`).
    pub(super) fn shade_bindings<'r>(
        &'r self,
        cx: &PassContext<'_>,
        io: &ShadeIo,
        clusters: &'r ClusterBuffers,
    ) -> Result<Bindings<'r>, RenderError> {
        let g = &self.gbuffer;
        let mut b = Bindings::new()
            .buffer("camera", g.camera_buffer())
            .buffer("grid", &self.grid)
            .buffer("lights", self.lights.buffer())
            .buffer("view_lights", &clusters.view_lights)
            .buffer("counts", &clusters.counts)
            .buffer("offsets", &clusters.offsets)
            .buffer("indices", &clusters.indices)
            .buffer_opt(
                "view_bands",
                self.merges_lights().then_some(&clusters.view_bands),
            )
            .buffer("surfaces", &self.surfaces)
            .texture("color", io.color)
            .texture("normals", io.normals)
            .texture("depth", io.depth)
            .texture("out_diffuse", io.diffuse)
            .texture("out_specular", io.specular)
            .texture_opt("out_sss", io.sss)
            .texture_opt("surface_target", io.surface)
            .texture_opt("anisotropy_target", io.anisotropy);
        // SHEEN and IRIDESCENCE read the sheen and film target, or a stand-in
        // of factors only where the G-buffer has none.
        if let Some(world) = self.materials.as_ref().filter(|_| self.sheen_or_film()) {
            b = match io.sheen_film {
                Some(t) => b.texture("sheen_film_target", t),
                None => b.view("sheen_film_target", world.sheen_film_stand_in()),
            };
        }
        b = super::bind_light_buffer(
            b,
            cx,
            &self.lights,
            self.shadows.as_deref(),
            io.spot_textures,
            "cook torrance",
        )?;
        if let Some(world) = &self.materials {
            b = b.extend(world.bindings(io.material_textures));
        }
        Ok(b)
    }

    /// 16x16 blocks: shaders/lighting/cook_torrance.wgsl's GROUP.
    pub(super) fn workgroups(&self, output_size: (u32, u32)) -> (u32, u32, u32) {
        let (w, h) = self.gbuffer.pixel_size(output_size);
        (w.div_ceil(16), h.div_ceil(16), 1)
    }

    fn shade(&self, cx: &mut PassContext<'_>, io: &ShadeIo) -> Result<(), RenderError> {
        let guard = self.clusters.get(cx.gpu, 1, self.lights.count());
        let Some(clusters) = guard.as_ref() else {
            return Ok(());
        };
        let b = self.shade_bindings(cx, io, clusters)?;
        let groups = self.workgroups(cx.output_size);
        match &self.custom {
            Some(custom) => self.shade_custom(cx, custom, io, b, groups),
            None => cx.dispatch_shader("cook torrance", &self.key(), "main", b, groups),
        }
    }

    /// The light loop composed with a light shader node's file in place of
    /// `spreadlight::custom_light`, its own bindings in group 2.
    fn shade_custom(
        &self,
        cx: &mut PassContext<'_>,
        custom: &CustomLight,
        io: &ShadeIo,
        mut b: Bindings<'_>,
        groups: (u32, u32, u32),
    ) -> Result<(), RenderError> {
        let s = &custom.shader;
        let device = cx.gpu.device.clone();
        let splice = crate::shaders::Splice {
            key: s.key,
            module: super::cook_torrance_key::LIGHT_MODULE,
            file_path: &s.file,
            source: &s.text,
        };
        let label = format!("{}: shade", s.label);
        let (pipeline, reflection) = cx
            .shaders
            .surface_pipeline(&device, &self.key(), &splice, "main")
            .map_err(|e| RenderError::Pass {
                pass: label.clone(),
                message: e.to_string(),
            })?;
        let spliced = crate::gbuffer::SplicedGroup {
            group: super::cook_torrance_key::LIGHT_GROUP,
            label: &label,
            reflection: &reflection,
        };
        if let Some(group) = crate::gbuffer::shader_node_group(
            cx,
            &pipeline,
            s,
            custom.params.as_ref(),
            &io.custom_textures,
            &spliced,
        )? {
            b = b.group(spliced.group, group);
        }
        let bind_groups = cx.bind_groups_reflected(&label, &reflection, &pipeline, b)?;
        let bind_groups: Vec<&wgpu::BindGroup> = bind_groups.iter().collect();
        cx.dispatch(&label, &pipeline, &bind_groups, groups);
        Ok(())
    }
}

/// What the shade pass declared.
pub(super) struct ShadeIo {
    color: Tex,
    normals: Tex,
    depth: Tex,
    diffuse: Tex,
    specular: Tex,
    /// Where some material has FakeSSS.
    sss: Option<Tex>,
    surface: Option<Tex>,
    /// The G-buffer's anisotropy target, where it has one.
    anisotropy: Option<Tex>,
    /// The G-buffer's sheen and film target, where it has one and the
    /// shade reads it.
    sheen_film: Option<Tex>,
    /// Textured spot lights' images.
    spot_textures: Option<Tex>,
    material_textures: Option<MaterialTextures>,
    /// A light shader node's texture inputs, in `@input` order.
    custom_textures: Vec<Tex>,
}

impl ShadeIo {
    /// The shade's outputs: diffuse, specular and the subsurface term.
    pub(super) fn outputs(&self) -> [Option<Tex>; 3] {
        [Some(self.diffuse), Some(self.specular), self.sss]
    }

    /// The G-buffer's color, normals and depth, as the shade reads them.
    pub(super) fn gbuffer(&self) -> [Tex; 3] {
        [self.color, self.normals, self.depth]
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

impl CookTorrance {
    /// Everything the shade pass needs declared before it: the G-buffer,
    /// the light assignment (a pass of its own when the walk reads froxels),
    /// spot textures, materials, shadow maps. The caller has included the
    /// recipe (`fg.include`).
    pub(super) fn declare_inputs<'a>(&'a self, renderer: &'a Renderer, fg: &mut FrameGraph<'a>) {
        self.gbuffer.declare(renderer, fg);
        let size = self.gbuffer.pixel_size(fg.output_size());
        let (near, far) = near_far(self.gbuffer.camera.projection).unwrap_or((0.1, 1000.0));
        let grid = ClusterGrid::new(size, near, far);
        // Only when it changed (size, near and far, light count): most frames it did not.
        renderer.write_kept(
            self.owner,
            "cluster grid",
            &self.grid,
            bytemuck::cast_slice(&grid.uniform_with_cutoff(self.lights.count(), self.light_cutoff)),
        );
        // Clustered: assignment is a pass of its own, timed apart. Naive:
        // the shade pass moves each light to view space as it reads it. (A
        // dispatch of its own before the shade, 6 µs on the H100, cost a
        // compute-pass boundary and barrier more: 17 µs of idle before each
        // naive shade against 7.6 before other passes, session 10.)
        if self.walk.uses_froxels() {
            let mut pass = fg.pass(self.label("clustered light assignment"), self.owner);
            super::clusters::announce_assignment(
                &mut pass,
                false,
                self.merges_lights(),
                self.lights.count(),
                renderer.gpu.adapter_class(),
            );
            // The assignment's buffers live in the cluster store; the token orders the shade after it.
            pass.write(&self.token, TextureDesc::token());
            pass.run(move |cx| self.assign(grid, cx));
        }
        if let Some(textures) = self.lights.textures() {
            textures.recipe.declare(renderer, fg);
        }
        if let Some(world) = &self.materials {
            world.declare_upstream(renderer, fg, self.textured());
        }
        if let Some(shadows) = &self.shadows {
            shadows.declare(renderer, fg);
        }
        if let Some(custom) = &self.custom {
            for texture in &custom.shader.textures {
                texture.recipe.declare(renderer, fg);
            }
            let compiled = custom.shader.take_compiled();
            if compiled > 0 {
                fg.count("shader node permutations compiled", compiled);
            }
        }
    }

    /// What the shade pass reads and writes, declared on `pass` (its own,
    /// or the fused pass of several recipes). `only_if_read`: its outputs
    /// are made only where something reads them (a fused pass that also
    /// writes the sets' sums, `light_sets`).
    pub(super) fn declare_shade_io(
        &self,
        pass: &mut PassBuilder<'_, '_>,
        only_if_read: bool,
    ) -> ShadeIo {
        let g = &self.gbuffer.targets;
        let mut hdr =
            TextureDesc::storage(wgpu::TextureFormat::Rgba16Float).size(self.gbuffer.size);
        if only_if_read {
            hdr = hdr.only_if_read();
        }
        // Ordering tokens: the light assignment's buffers and the shadow
        // maps live outside the graph.
        if self.walk.uses_froxels() {
            pass.read(&self.token);
        }
        if let Some(shadows) = &self.shadows {
            pass.read(shadows.token());
        }
        ShadeIo {
            color: pass.read(&g.color),
            normals: pass.read(&g.normals),
            depth: pass.read(&g.depth),
            surface: pass.read_opt(g.surface.as_deref()),
            anisotropy: self
                .materials
                .as_ref()
                .and_then(|_| pass.read_opt(g.anisotropy.as_deref())),
            sheen_film: self
                .materials
                .as_ref()
                .filter(|_| self.sheen_or_film())
                .and_then(|_| pass.read_opt(g.sheen_film.as_deref())),
            spot_textures: self.lights.textures().map(|t| pass.read(&t.name)),
            material_textures: self
                .materials
                .as_ref()
                .and_then(|w| w.read_textures(pass, self.textured(), g.surface_targets())),
            diffuse: pass.write(&self.diffuse, hdr),
            specular: pass.write(&self.specular, hdr),
            sss: self.sss.as_ref().map(|sss| pass.write(sss, hdr)),
            custom_textures: self
                .custom
                .iter()
                .flat_map(|c| &c.shader.textures)
                .map(|t| pass.read(&t.name))
                .collect(),
        }
    }
}

impl Recipe for CookTorrance {
    fn declare<'a>(&'a self, renderer: &'a Renderer, fg: &mut FrameGraph<'a>) {
        if !fg.include(self.id) {
            return;
        }
        self.declare_inputs(renderer, fg);
        let mut pass = fg.pass(self.label("shade"), self.owner);
        let io = self.declare_shade_io(&mut pass, false);
        if self.custom.is_none() {
            pass.will_dispatch(&self.key(), "main");
        }
        pass.run(move |cx| self.shade(cx, &io));
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn auto_walks_few_lights_naively_and_more_by_the_adapters_walk() {
        use AdapterClass::{Cpu, Gpu};
        let point = LightKind::Point;
        for class in [Gpu, Cpu] {
            let auto = |n| resolve_walk(LightLoop::Auto, point, n, class);
            assert_eq!(auto(0), Walk::Naive);
            assert_eq!(auto(FEW_LIGHTS), Walk::Naive);
            assert_eq!(auto(FEW_LIGHTS + 1), auto_walk(class));
            assert_eq!(auto(100_000), auto_walk(class));
            // Suns are never clustered, whatever was asked.
            for mode in [LightLoop::Auto, LightLoop::Tiled, LightLoop::PerPixel] {
                assert_eq!(resolve_walk(mode, LightKind::Sun, 100, class), Walk::Naive);
            }
            // A walk asked for is the walk taken.
            for (mode, walk) in [
                (LightLoop::Clustered, Walk::Clustered),
                (LightLoop::Tiled, Walk::Tiled),
                (LightLoop::PerPixel, Walk::PerPixel),
                (LightLoop::Naive, Walk::Naive),
            ] {
                assert_eq!(resolve_walk(mode, point, 100, class), walk);
                assert_eq!(resolve_walk(mode, point, 3, class), walk);
            }
        }
        // A CPU adapter shares nothing through workgroup memory; a GPU keeps
        // the walk measured on the H200.
        assert_eq!(auto_walk(Cpu), Walk::PerPixel);
        assert_eq!(auto_walk(Gpu), Walk::Clustered);
        assert!(!Walk::Naive.uses_froxels());
        assert!(Walk::Tiled.uses_froxels() && Walk::PerPixel.uses_froxels());
    }
}
