//! `Transparency`: weighted blended order-independent transparency
//! (McGuire and Bavoil 2013; shaders/post/transparency.wgsl), lit forward+.
//! Transparent layers are rasterized (blending is what raster hardware is
//! for) into an RGBA16F accumulation and an R16F revealage target,
//! depth-tested by hand against the G-buffer's depth, then a compute pass
//! composites them over the opaque lit image.
//!
//! Lighting: a base pass draws each layer's alpha and its unlit colour
//! (the colour times an ambient term, emission, an Environment's
//! irradiance and prefiltered reflection, and, without light buffers, one
//! two-sided directional key light); then each connected
//! light buffer draws the layer again, adding its Cook-Torrance light to
//! the colour alone (the sum is linear, so this equals one pass that loops
//! over every buffer). A light pass walks the buffer's lights as
//! CookTorrance does: every light for a handful ([`FEW_LIGHTS`]), else
//! froxel lists made by the same clustered assignment
//! (`lighting::assign_lights`), with the buffer's shadow maps. The lists
//! are the forward grid's (`ClusterGrid::forward`: thin slices), filled
//! only in the froxels the base passes marked, so the accumulation draws
//! every base pass, then assigns, then draws the light passes. The surface
//! is the layer's: glTF's base colour (instance colour x base colour map x
//! COLOR_0), normal, metallic-roughness, occlusion and emissive maps, or a
//! DeferredBase layer's Color Texture and normal map; roughness, metallic
//! and emission from the material world's CookTorrance and Emission
//! features (the layer's world, else the node's), else the node's pins.
//! Each layer and pass is drawn with its own permutation (`key.rs`).
//! Without transparent instances the node costs a copy, and without light
//! buffers no light pass runs.
//!
//! Shading (`compute.rs`): under `TransparencyShading::Compute` no layer
//! is drawn per light buffer; the base pass records each fragment's
//! lighting inputs per pixel, a compute pass per light buffer lights them
//! with the same walk, and the resolve adds the sums.
//!
//! Transmission (`transmission.rs`): a layer whose world has a Transmission
//! material, or any layer when the settings' factor is on, is drawn with
//! TRANSMISSION: what shows through is the opaque image refracted, not
//! blended. Layers without it compile none of that code, and the opaque
//! image is bound to the accumulation only when some layer refracts. Rough
//! glass blurs by taps or by one read of a mip chain of the opaque image
//! (`refraction_mips.rs`), built in a pass of its own only then.

pub mod compute;
pub(crate) mod key;
pub mod refraction_mips;
pub mod transmission;

use std::sync::{Arc, Mutex};

use glam::Vec3;
use smallvec::SmallVec;

pub use compute::TransparencyShading;
pub use key::{
    LayerMaps, LayerUv, LightKey, MatCapKey, RefractionKey, ShadowKey, SurfaceKey, TransparencyKey,
    TransparencyPass,
};
pub use refraction_mips::MIP_CHAINS;
pub use transmission::{RefractionBlur, TransmissionSettings};

use refraction_mips::RefractionMips;

use compute::{FragmentLists, ListBuffers};

use crate::environment::Environment;
use crate::error::RenderError;
use crate::frame_graph::{Bindings, FrameGraph, PassContext, Tex, TextureDesc};
use crate::gbuffer::{Draw, GBuffer, Layer, mesh_bindings, pack_instances};
use crate::lighting::{ClusterGrid, ClusterStore, FEW_LIGHTS, LightBuffer, LightKind, LightLoop};
use crate::material::{
    FEATURE_CLEARCOAT, FEATURE_IRIDESCENCE, FEATURE_MATCAP, FEATURE_SHEEN, FEATURE_TRANSMISSION,
    MaterialWorld,
};
use crate::mesh_arena::pulled_pipeline;
use crate::recipe::{Recipe, TextureRef, next_recipe_id};
use crate::renderer::Renderer;
use crate::report::PassName;
use crate::shaders::{Permutation, Sampling, ShaderKey};
use crate::shadows::ShadowMaps;
use crate::texture_pool::ViewSpec;

const ACCUMULATION: wgpu::TextureFormat = wgpu::TextureFormat::Rgba16Float;
// Rgba16Float, not R16Float (only red is read): the targets are cleared by
// a compute pass, and half-float storage is only core in four channels.
const REVEALAGE: wgpu::TextureFormat = wgpu::TextureFormat::Rgba16Float;

/// Counted when there was nothing transparent to draw and the node only copied.
pub const SKIPPED: &str = "transparency skipped (nothing transparent)";
/// Transparent instances drawn.
pub const DRAWN: &str = "transparent instances drawn";
/// Light passes drawn: one per layer (and culling variant) and light buffer.
pub const LIGHT_PASSES: &str = "transparency light passes";
/// Light buffers whose lights were assigned to froxels for the forward loop.
pub const ASSIGNED: &str = "transparency clustered light buffers";
/// Layers drawn with refracted transmission (TRANSMISSION).
pub const REFRACTING: &str = "transparency refracting layers";

#[derive(Clone, Copy, Debug, PartialEq)]
pub struct TransparencySettings {
    pub ambient: Vec3,
    /// Towards the built-in key light, in world space (only without light buffers).
    pub light_direction: Vec3,
    /// The built-in key light; off (black) whenever light buffers are connected.
    pub light_color: Vec3,
    /// Roughness and metallic of surfaces whose material world has no
    /// CookTorrance feature (or that have no world).
    pub roughness: f32,
    pub metallic: f32,
    /// The multiple-scattering term on the light passes' specular, as CookTorrance's.
    pub energy_compensation: bool,
    /// How light passes find their lights (CookTorrance's choice).
    pub light_loop: LightLoop,
    /// Whether the lights are shaded by drawing the layers again or in compute.
    pub shading: TransparencyShading,
    /// Refraction for layers without a Transmission material, and the
    /// sampling quality of every refracting layer.
    pub transmission: TransmissionSettings,
}

impl Default for TransparencySettings {
    fn default() -> Self {
        TransparencySettings {
            ambient: Vec3::splat(0.3),
            light_direction: Vec3::new(0.3, 1.0, 0.5),
            light_color: Vec3::splat(1.0),
            roughness: 0.5,
            metallic: 0.0,
            energy_compensation: true,
            light_loop: LightLoop::Auto,
            shading: TransparencyShading::Auto,
            transmission: TransmissionSettings::default(),
        }
    }
}

/// A light buffer that lights the transparent layers, with the shadow maps
/// its lights' slices index (a ShadowMap of the same light type).
#[derive(Clone, Debug)]
pub struct TransparentLights {
    pub lights: Arc<LightBuffer>,
    pub shadows: Option<Arc<ShadowMaps>>,
}

/// What lights the layers besides the settings' ambient and key light.
#[derive(Clone, Debug, Default)]
pub struct LitBy {
    /// Each buffer is a light pass; with any, the settings' key light is off.
    pub lights: Vec<TransparentLights>,
    /// The world of layers that bring none of their own.
    pub materials: Option<Arc<MaterialWorld>>,
    /// Image-based light (irradiance and prefiltered reflection) in the base pass.
    pub environment: Option<Arc<Environment>>,
}

/// One light buffer as a light pass uses it.
struct LightSet {
    lights: Arc<LightBuffer>,
    shadows: Option<Arc<ShadowMaps>>,
    /// The froxel lists, when the walk is clustered.
    clusters: Option<SetClusters>,
}

struct SetClusters {
    store: Arc<ClusterStore>,
    grid: wgpu::Buffer,
}

/// Per node: each light buffer's froxel buffers and grid uniform, and the
/// froxel marks, kept across the node's recipes (a new one each frame the
/// camera moves), as CookTorrance keeps its `ClusterStore`.
#[derive(Default)]
struct ForwardClusters {
    sets: Mutex<Vec<(Arc<ClusterStore>, wgpu::Buffer)>>,
    marks: Arc<FroxelMarks>,
}

/// The word per froxel that the base pass sets where a transparent fragment
/// lies (transparency.wgsl's `mark_froxels`): one for all light buffers,
/// which share the grid. Grown when the grid outgrows it.
#[derive(Default)]
struct FroxelMarks(Mutex<Option<(u32, wgpu::Buffer)>>);

impl FroxelMarks {
    fn get(&self, gpu: &crate::context::GpuContext, clusters: u32) -> wgpu::Buffer {
        let mut kept = self.0.lock().unwrap_or_else(|e| e.into_inner());
        match kept.as_ref() {
            Some((size, buffer)) if *size >= clusters => buffer.clone(),
            _ => {
                let buffer = gpu.device.create_buffer(&wgpu::BufferDescriptor {
                    label: Some("transparency froxel marks"),
                    size: u64::from(clusters.max(1)) * 4,
                    usage: wgpu::BufferUsages::STORAGE | wgpu::BufferUsages::COPY_DST,
                    mapped_at_creation: false,
                });
                *kept = Some((clusters, buffer.clone()));
                buffer
            }
        }
    }
}

impl ForwardClusters {
    fn set(&self, renderer: &Renderer, index: usize) -> (Arc<ClusterStore>, wgpu::Buffer) {
        let mut sets = self.sets.lock().unwrap_or_else(|e| e.into_inner());
        while sets.len() <= index {
            let grid = renderer.gpu.device.create_buffer(&wgpu::BufferDescriptor {
                label: Some("transparency cluster grid"),
                size: crate::lighting::GRID_BYTES,
                usage: wgpu::BufferUsages::UNIFORM | wgpu::BufferUsages::COPY_DST,
                mapped_at_creation: false,
            });
            sets.push((Arc::default(), grid));
        }
        sets[index].clone()
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
    lights: Vec<LightSet>,
    /// The froxels transparent fragments lie in, when a light pass is clustered.
    marks: Arc<FroxelMarks>,
    /// The world of layers that bring none.
    materials: Option<Arc<MaterialWorld>>,
    environment: Option<Arc<Environment>>,
    /// The settings' transmission is on: every layer refracts.
    transmission: bool,
    /// How refracting layers blur (resolved: Taps or Mips).
    blur: RefractionBlur,
    /// The opaque image's mip chain (kept per node), built when some layer
    /// refracts with [`RefractionBlur::Mips`].
    mips: Arc<RefractionMips>,
    /// Orders the chain's build before the accumulation (it lives outside the graph).
    mips_token: String,
    /// The lights are shaded in compute over recorded fragments (some light
    /// buffer is connected and the settings' shading says so).
    compute: bool,
    /// Clustered light buffers are shaded with the tiles sharing their lights.
    tiled: bool,
    /// The fragment lists of compute shading, kept per node.
    lists: Arc<FragmentLists>,
    accumulation: String,
    revealage: String,
    pub output: String,
}

/// A finite colour in 0..HALF_MAX (black for NaN or infinity).
fn clean(v: Vec3) -> Vec3 {
    if v.is_finite() {
        v.clamp(Vec3::ZERO, Vec3::splat(super::HALF_MAX))
    } else {
        Vec3::ZERO
    }
}

/// 0..1, `fallback` for NaN or infinity.
fn unit(v: f32, fallback: f32) -> f32 {
    if v.is_finite() {
        v.clamp(0.0, 1.0)
    } else {
        fallback
    }
}

impl Transparency {
    /// Unlit but for the settings' ambient and key light (no light buffers).
    pub fn new(
        renderer: &Renderer,
        owner: Option<u32>,
        source: TextureRef,
        gbuffer: Arc<GBuffer>,
        layers: Vec<Arc<Layer>>,
        settings: TransparencySettings,
    ) -> Arc<Self> {
        Self::lit(
            renderer,
            owner,
            source,
            gbuffer,
            layers,
            settings,
            LitBy::default(),
        )
    }

    /// Lit by `by`'s light buffers and environment as well, surfaces read
    /// from its material world where a layer brings none of its own.
    pub fn lit(
        renderer: &Renderer,
        owner: Option<u32>,
        source: TextureRef,
        gbuffer: Arc<GBuffer>,
        layers: Vec<Arc<Layer>>,
        settings: TransparencySettings,
        by: LitBy,
    ) -> Arc<Self> {
        let LitBy {
            lights,
            materials,
            environment,
        } = by;
        let id = next_recipe_id();
        let (gpu_instances, draws, layer_ranges) = pack_instances(&layers);
        let instance_count = gpu_instances.len() as u32;
        let instances = renderer.kept_storage(owner, "transparent instances", &gpu_instances);
        // Buffers without lights light nothing: no pass for them.
        let lights: Vec<TransparentLights> = lights
            .into_iter()
            .filter(|l| l.lights.count() > 0)
            .collect();
        let direction = settings.light_direction.normalize_or(Vec3::Y);
        let a = clean(settings.ambient);
        let l = if lights.is_empty() {
            clean(settings.light_color)
        } else {
            Vec3::ZERO
        };
        let t = settings.transmission.words();
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
                unit(settings.roughness, 0.5),
                unit(settings.metallic, 0.0),
                if settings.energy_compensation {
                    1.0
                } else {
                    0.0
                },
                environment
                    .as_ref()
                    .map_or(0.0, |e| e.quality.levels() as f32),
                t[0],
                t[1],
                t[2],
                t[3],
                t[4],
                t[5],
                t[6],
                t[7],
            ]),
        );
        // Auto draws forward where not one record a pixel of the output fits
        // the device's storage limits; Compute and Tiled asked by name say so
        // at run time (`fragment_lists`).
        let fits = || {
            let (w, h) = renderer.output_size();
            compute::slots_on(&renderer.gpu, u64::from(w) * u64::from(h)) > 0
        };
        // Sheen and anisotropic layers shade in compute too: their records
        // keep the lobes' inputs (compute::RecordedLobes). A layer with a
        // thin film shades forward under Auto: the records keep no film
        // (Compute and Tiled asked by name draw such a layer without it).
        let filmed = layers.iter().any(|l| {
            l.map_world()
                .or(l.materials.as_ref())
                .or(materials.as_ref())
                .is_some_and(|w| w.any_has(FEATURE_IRIDESCENCE))
        });
        let compute = !lights.is_empty()
            && settings.shading.computes(renderer.gpu.adapter_class())
            && (settings.shading != TransparencyShading::Auto || (fits() && !filmed));
        let lists = owner
            .map(|node| renderer.state::<FragmentLists>(u64::from(node)))
            .unwrap_or_default();
        let kept = owner.map(|node| renderer.state::<ForwardClusters>(u64::from(node)));
        let marks = kept.as_ref().map(|k| k.marks.clone()).unwrap_or_default();
        let lights = lights
            .into_iter()
            .enumerate()
            .map(|(i, l)| {
                let clustered = clustered(settings.light_loop, &l.lights);
                let clusters = clustered.then(|| {
                    let (store, grid) = match &kept {
                        Some(kept) => kept.set(renderer, i),
                        None => ForwardClusters::default().set(renderer, 0),
                    };
                    SetClusters { store, grid }
                });
                LightSet {
                    lights: l.lights,
                    shadows: l.shadows,
                    clusters,
                }
            })
            .collect();
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
            lights,
            marks,
            materials,
            environment,
            transmission: settings.transmission.on(),
            blur: settings.transmission.blur.resolved(),
            mips: owner
                .map(|node| renderer.state::<RefractionMips>(u64::from(node)))
                .unwrap_or_default(),
            mips_token: format!("transparency{id}/refraction mips"),
            compute,
            tiled: settings.shading == TransparencyShading::Tiled,
            lists,
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

    /// The permutations this recipe draws with: each layer's base pass and
    /// one light pass per light buffer (what `stats` counts as compiled).
    pub fn keys(&self) -> Vec<TransparencyKey> {
        let mut keys = Vec::new();
        for (layer, range) in self.layers.iter().zip(&self.layer_ranges) {
            if range.0 == range.1 {
                continue;
            }
            let (surface, world) = self.surface(layer);
            for pass in self.passes(Self::matcap(world), self.transmits(world)) {
                let key = TransparencyKey {
                    surface,
                    pass,
                    coat: Self::coat(world, pass),
                    anisotropy: Self::anisotropy(surface, world, pass),
                    sheen: Self::sheen(world, pass),
                };
                if !keys.contains(&key) {
                    keys.push(key);
                }
            }
        }
        if self.compute && !keys.is_empty() {
            for light in self.light_keys() {
                let lobes = self.recorded_lobes();
                let key = TransparencyKey {
                    surface: TransparencyKey::COMPOSITE.surface,
                    pass: self.shade_pass(light),
                    coat: lobes.coat,
                    anisotropy: lobes.anisotropy,
                    sheen: lobes.sheen,
                };
                if !keys.contains(&key) {
                    keys.push(key);
                }
            }
            keys.push(TransparencyKey::SHADED_RESOLVE);
        }
        keys
    }

    /// Each light buffer's light permutation (drawn forward or shaded in compute).
    fn light_keys(&self) -> impl Iterator<Item = LightKey> + '_ {
        self.lights.iter().map(|set| LightKey {
            kind: set.lights.kind,
            clustered: set.clusters.is_some(),
            shadows: ShadowKey::of(set.shadows.as_ref().map(|s| s.filter())),
            spot_texture: set.lights.textures().is_some(),
        })
    }

    /// The compute pass that shades a light buffer of permutation `light`:
    /// tiled only where there are froxel lists to share.
    fn shade_pass(&self, light: LightKey) -> TransparencyPass {
        if self.tiled && light.clustered {
            TransparencyPass::ShadeTiled(light)
        } else {
            TransparencyPass::Shade(light)
        }
    }

    /// Whether the lights are shaded in compute over recorded fragments.
    pub fn shades_in_compute(&self) -> bool {
        self.compute
    }

    /// How many fragments of the last compute-shaded frame of this node
    /// found their pixel's slots full (read back from the GPU: tests and
    /// diagnostics, not a frame's work). 0 when nothing was recorded yet.
    pub fn missed_fragments(&self, renderer: &Renderer) -> Result<u32, RenderError> {
        self.lists.missed(renderer)
    }

    /// A layer's base pass (with its `matcap` and `transmission`), then a
    /// light pass per light buffer, unless the lights are shaded in compute.
    fn passes(
        &self,
        matcap: MatCapKey,
        transmission: bool,
    ) -> impl Iterator<Item = TransparencyPass> + '_ {
        let environment = self.environment.is_some();
        let base = TransparencyPass::Base {
            environment,
            matcap,
            marks: self.clustered(),
            transmission: match (transmission, self.blur) {
                (false, _) => RefractionKey::Off,
                (true, RefractionBlur::Taps) => RefractionKey::Taps,
                (true, _) => RefractionKey::Mips,
            },
            records: self.compute,
        };
        let forward = (!self.compute).then(|| self.light_keys().map(TransparencyPass::Light));
        std::iter::once(base).chain(forward.into_iter().flatten())
    }

    /// Whether a pass of a layer reading `world` compiles the coat
    /// ([`TransparencyKey::coat`]): its world has a Clearcoat material, and
    /// the pass is a light pass or a base pass that records fragments or
    /// reads the environment (the coat reflects it).
    fn coat(world: Option<&Arc<MaterialWorld>>, pass: TransparencyPass) -> bool {
        let coated = world.is_some_and(|w| w.union_flags() & (1 << FEATURE_CLEARCOAT) != 0);
        coated
            && match pass {
                TransparencyPass::Base {
                    records,
                    environment,
                    ..
                } => records || environment,
                _ => true,
            }
    }

    /// Whether a pass of a layer with `surface` reading `world` compiles
    /// the anisotropic lobe ([`TransparencyKey::anisotropy`]): a light pass
    /// or a recording base pass over surface maps whose world has an
    /// Anisotropy material.
    fn anisotropy(
        surface: SurfaceKey,
        world: Option<&Arc<MaterialWorld>>,
        pass: TransparencyPass,
    ) -> bool {
        surface.maps.is_surface()
            && world.is_some_and(|w| w.has_anisotropy())
            && Self::lights_or_records(pass)
    }

    /// Whether a pass of a layer reading `world` compiles the sheen and the
    /// thin film ([`TransparencyKey::sheen`]): a light pass of a world with
    /// a Sheen or an Iridescence material, or a recording base pass of a
    /// world with a Sheen material (the compute records keep the sheen, not
    /// the film). One switch for both lobes (the shader branches per
    /// material): a switch of its own for the film would add 3,080
    /// permutations for a few dozen lines of code.
    fn sheen(world: Option<&Arc<MaterialWorld>>, pass: TransparencyPass) -> bool {
        (matches!(pass, TransparencyPass::Light(_))
            && world.is_some_and(|w| w.any_has(FEATURE_IRIDESCENCE)))
            || (Self::lights_or_records(pass) && world.is_some_and(|w| w.any_has(FEATURE_SHEEN)))
    }

    /// A forward light pass, or a base pass that records its fragments for
    /// the compute shading: the passes a lobe's inputs are read in.
    fn lights_or_records(pass: TransparencyPass) -> bool {
        matches!(
            pass,
            TransparencyPass::Light(_) | TransparencyPass::Base { records: true, .. }
        )
    }

    /// The lobes some drawn layer of the node has: the compute shading
    /// reads their records (which are then made and cleared each frame) and
    /// compiles their code.
    fn recorded_lobes(&self) -> compute::RecordedLobes {
        let mut lobes = compute::RecordedLobes::default();
        for (layer, range) in self.layers.iter().zip(&self.layer_ranges) {
            if range.0 == range.1 {
                continue;
            }
            let (surface, world) = self.surface(layer);
            let Some(world) = world else {
                continue;
            };
            lobes.coat |= world.union_flags() & (1 << FEATURE_CLEARCOAT) != 0;
            lobes.sheen |= world.any_has(FEATURE_SHEEN);
            lobes.anisotropy |= surface.maps.is_surface() && world.has_anisotropy();
        }
        lobes
    }

    /// Whether some light pass walks froxel lists (which the base pass marks).
    fn clustered(&self) -> bool {
        self.lights.iter().any(|set| set.clusters.is_some())
    }

    /// The matcap a layer's base pass compiles in: its world has a MatCap
    /// material (images when one names a layer of the world's texture array).
    fn matcap(world: Option<&Arc<MaterialWorld>>) -> MatCapKey {
        match world {
            Some(w) if w.union_flags() & (1 << FEATURE_MATCAP) != 0 => {
                if w.textured(1 << FEATURE_MATCAP) && w.textures().is_some() {
                    MatCapKey::Images
                } else {
                    MatCapKey::BuiltIn
                }
            }
            _ => MatCapKey::Off,
        }
    }

    /// Whether a layer of material world `world` refracts: the settings'
    /// transmission is on, or the world has a Transmission material.
    fn transmits(&self, world: Option<&Arc<MaterialWorld>>) -> bool {
        self.transmission
            || world.is_some_and(|w| w.union_flags() & (1 << FEATURE_TRANSMISSION) != 0)
    }

    /// A layer's surface permutation and the material world it reads.
    fn surface<'a>(&'a self, layer: &'a Layer) -> (SurfaceKey, Option<&'a Arc<MaterialWorld>>) {
        let map_world = layer.map_world();
        let world = map_world
            .or(layer.materials.as_ref())
            .or(self.materials.as_ref());
        let color = layer.color_map.is_some();
        let normal = layer.features.normal_map && layer.normal_map.is_some();
        let maps = if let Some(w) = map_world {
            LayerMaps::Surface {
                extensions: w.has_extension_maps(),
            }
        } else if color || normal {
            // A normal map without either switch reads the mesh's own UVs, as the resolve does.
            let uv = if layer.features.triplanar && !layer.features.texcoords {
                LayerUv::Triplanar
            } else {
                LayerUv::Texcoords
            };
            LayerMaps::Layer { uv, color, normal }
        } else {
            LayerMaps::None
        };
        let key = SurfaceKey {
            maps,
            vertex_extras: layer.vertex_extras(),
            materials: world.is_some(),
        };
        (key, world)
    }

    /// A layer's accumulation draws (its instances `range`), as
    /// [`Self::accumulate`] records them and the pass announces their
    /// pipelines: per culling variant its draws use (glTF materials, surface
    /// maps, cull back faces unless double-sided, as other viewers draw
    /// them; patch-built layers show both faces: a glass shell's back
    /// through its front), each pass (the base pass, then a light pass per
    /// light buffer `set`) with its permutation.
    fn layer_passes(&self, layer: &Layer, range: (u32, u32)) -> SmallVec<[LayerPass; 8]> {
        let mut passes = SmallVec::new();
        if range.0 == range.1 {
            return passes;
        }
        let (surface, world) = self.surface(layer);
        let surface_maps = surface.maps.is_surface();
        let transmits = self.transmits(world);
        for culled in [true, false] {
            let in_layer = |d: &&Draw| (range.0..range.1).contains(&d.first_instance);
            let culls = |d: &Draw| surface_maps && !d.two_sided;
            if !self
                .draws
                .iter()
                .filter(in_layer)
                .any(|d| culls(d) == culled)
            {
                continue;
            }
            for (pass, set) in self
                .passes(Self::matcap(world), transmits)
                .zip(std::iter::once(None).chain((0..self.lights.len()).map(Some)))
            {
                let key = TransparencyKey {
                    surface,
                    pass,
                    coat: Self::coat(world, pass),
                    anisotropy: Self::anisotropy(surface, world, pass),
                    sheen: Self::sheen(world, pass),
                }
                .key();
                passes.push((culled, pass, set, key));
            }
        }
        passes
    }

    /// Announce the accumulation's pipelines (frame_graph/gather.rs): the
    /// layers' render pipelines, the clear and, shaded in compute, each
    /// light buffer's shade, as the pass will look them up.
    fn announce_accumulation(
        &self,
        pass: &mut crate::frame_graph::PassBuilder<'_, '_>,
        class: crate::adapter_class::AdapterClass,
    ) {
        pass.will_dispatch(&TransparencyKey::COMPOSITE.key(), "clear");
        for (layer, range) in self.layers.iter().zip(&self.layer_ranges) {
            for (culled, kind, _, key) in self.layer_passes(layer, *range) {
                let (variant, build) = accumulate_build(culled, kind);
                pass.will_render(&key, variant, Arc::new(build));
            }
        }
        // The froxel lists of clustered light buffers, where the base pass marked.
        for set in self.lights.iter().filter(|set| set.clusters.is_some()) {
            crate::lighting::announce_assignment(pass, true, false, set.lights.count(), class);
        }
        if self.compute {
            let lobes = self.recorded_lobes();
            for light in self.light_keys() {
                let kind = self.shade_pass(light);
                let key = TransparencyKey {
                    surface: TransparencyKey::COMPOSITE.surface,
                    pass: kind,
                    coat: lobes.coat,
                    anisotropy: lobes.anisotropy,
                    sheen: lobes.sheen,
                };
                pass.will_dispatch(&key.key(), shade_entry(kind));
            }
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
        let grid = io.grid;
        let clusters = grid.clusters();
        // The froxel marks the base pass writes and the assignment reads.
        let marks = self.clustered().then(|| self.marks.get(cx.gpu, clusters));
        // The grid uniform the base pass marks by (any clustered buffer's:
        // they differ only in the light count, which it does not read).
        let marks_grid = self
            .lights
            .iter()
            .find_map(|s| s.clusters.as_ref())
            .map(|c| &c.grid);
        // The froxel lists, held while the bind groups are made, at the
        // grid's size: the assignment between the base and light passes
        // finds them big enough and fills these same buffers.
        let guards: Vec<_> = self
            .lights
            .iter()
            .map(|set| {
                set.clusters
                    .as_ref()
                    .map(|c| (c.store.get(cx.gpu, clusters, set.lights.count()), &c.grid))
            })
            .collect();
        // The mip chain its refracting layers read, built by the pass before.
        let mips = match (io.lit, io.mips) {
            (Some(lit), Some(_)) => Some(self.mips.get(cx.gpu, cx.size_of(lit)?)),
            _ => None,
        };
        // Compute shading's fragment lists, at the accumulation's size.
        let lists = match self.compute {
            true => Some(self.fragment_lists(cx, io.accumulation)?),
            false => None,
        };
        // Per layer, culling variant and pass: its pipeline and bind groups
        // (0; 1 and 3 with a material world and maps; 2 with layer maps).
        let mut work: Vec<Work> = Vec::new();
        let mut refracting = 0;
        for ((layer, range), maps) in self
            .layers
            .iter()
            .zip(&self.layer_ranges)
            .zip(&io.layer_maps)
        {
            if range.0 == range.1 {
                continue;
            }
            let (surface, world) = self.surface(layer);
            let surface_maps = surface.maps.is_surface();
            let transmits = self.transmits(world);
            refracting += u64::from(transmits);
            for (culled, pass, set, key) in self.layer_passes(layer, *range) {
                let pipeline = accumulate_pipeline(cx, key.clone(), culled, pass)?;
                let mut b = mesh_bindings(&vertices, &indices, &self.instances)
                    .buffer("camera", self.gbuffer.camera_buffer())
                    .texture("opaque_depth", io.depth)
                    .buffer("params", &self.params)
                    .buffer_opt("extras", surface.vertex_extras.then_some(&extras));
                if let Some(world) = world {
                    b = b.extend(world.bindings(None));
                    if surface_maps && let Some(maps) = world.maps_bindings() {
                        b = b.extend(maps);
                    }
                }
                if let Some(normal) = maps.normal {
                    b = b
                        .texture("normal_map", normal)
                        .sampler("normal_sampler", Sampling::LinearRepeat);
                }
                if let Some(color) = maps.color {
                    b = b
                        .texture("color_map", color)
                        .sampler("color_sampler", Sampling::LinearRepeat);
                }
                if let (None, Some(images)) = (set, maps.matcap) {
                    // Clamped: the rim of a matcap must not wrap to the far side.
                    b = b
                        .array("matcap_images", images)
                        .sampler("matcap_sampler", Sampling::LinearClamp);
                }
                if let (None, Some(marks), Some(grid)) = (set, &marks, marks_grid) {
                    b = b.buffer("grid", grid).buffer("froxel_marks", marks);
                }
                if let (None, Some(lists)) = (set, &lists) {
                    b = b
                        .buffer("fragment_counts", &lists.counts)
                        .buffer("fragment_records", &lists.records)
                        .buffer_opt("coat_records", lists.coat.as_ref())
                        .buffer_opt("sheen_records", lists.sheen.as_ref())
                        .buffer_opt("anisotropy_records", lists.anisotropy.as_ref());
                }
                match (set, transmits, io.lit, &mips) {
                    // The chain's levels, read trilinearly (RefractionKey::Mips).
                    (None, true, _, Some((chain, sampler))) => {
                        b = b
                            .view("refraction_mips", cx.view_of(chain, ViewSpec::default()))
                            .sampler_object("refraction_sampler", sampler.clone());
                    }
                    // Sampled by hand and clamped (RefractionKey::Taps).
                    (None, true, Some(lit), None) => b = b.texture("lit_opaque", lit),
                    _ => {}
                }
                if let (None, Some(environment)) = (set, &self.environment) {
                    let maps = environment.maps_for("transparency")?;
                    b = b
                        .view(
                            "prefiltered",
                            cx.view_of(&maps.prefiltered, ViewSpec::cube()),
                        )
                        .view("irradiance", cx.view_of(&maps.irradiance, ViewSpec::cube()))
                        .view("lut", cx.view_of(&maps.lut, ViewSpec::default()))
                        .sampler_object("cube_sampler", maps.sampler.clone());
                }
                if let Some(set) = set {
                    b = b.extend(self.light_bindings(cx, set, io.spot_textures[set])?);
                    if let Some((guard, grid)) = &guards[set] {
                        let Some(lists) = guard.as_ref() else {
                            continue;
                        };
                        b = b
                            .buffer("grid", grid)
                            .buffer("light_counts", &lists.counts)
                            .buffer("light_offsets", &lists.offsets)
                            .buffer("light_indices", &lists.indices);
                    }
                }
                // Through the cache: the camera, meshes, kept instances,
                // parameters and lights are the same buffers from frame to frame.
                let groups = cx.render_bind_groups(&key, &["vs", "fs"], &pipeline, b)?;
                work.push((
                    *range,
                    culled,
                    surface_maps,
                    set.is_some(),
                    pipeline,
                    groups,
                ));
            }
        }
        drop(guards);
        // Cleared in compute, then loaded: a render pass's clear goes through
        // the raster output, which on the H100 took 0.28 of this pass's
        // 0.41 ms at 1080p (docs/benchmarks.md, session 10); compute writes
        // the same bytes about a hundred times faster.
        let size = cx.size_of(io.accumulation)?;
        let composite = TransparencyKey::COMPOSITE.key();
        cx.dispatch_shader(
            "transparency clear",
            &composite,
            "clear",
            Bindings::new()
                .texture("clear_accumulation", io.accumulation)
                .texture("clear_revealage", io.revealage),
            super::per_pixel(size),
        )?;
        if let Some(marks) = &marks {
            cx.encoder().clear_buffer(marks, 0, None);
        }
        if let Some(lists) = &lists {
            // The records need no clearing: a pixel reads only as many as it counted.
            cx.encoder().clear_buffer(&lists.counts, 0, None);
            cx.encoder().clear_buffer(&lists.light, 0, None);
            // Cleared: a fragment of a layer without a lobe writes no record
            // of it, and reads none (no coat, no sheen, the isotropic lobe).
            for records in lists.lobe_buffers() {
                cx.encoder().clear_buffer(records, 0, None);
            }
            cx.count(compute::FRAGMENT_SLOTS, u64::from(lists.slots));
        }
        // The base passes first: they mark the froxels their fragments lie
        // in. Then the lights are listed in those froxels alone, and the
        // light passes walk the lists. The sums are order-independent, so
        // drawing every base pass before any light pass changes nothing.
        let (base, lit): (Vec<_>, Vec<_>) = work.iter().partition(|w| !w.3);
        let mut draws = self.draw(cx, io, &base)?;
        for set in &self.lights {
            let Some(c) = &set.clusters else {
                continue;
            };
            cx.count(ASSIGNED, 1);
            crate::lighting::assign_lights(
                cx,
                &c.store,
                grid,
                &c.grid,
                self.gbuffer.camera_buffer(),
                &set.lights,
                marks.as_ref(),
            )?;
        }
        if !lit.is_empty() {
            draws += self.draw(cx, io, &lit)?;
        }
        if let Some(lists) = &lists {
            for set in 0..self.lights.len() {
                self.shade(cx, io, set, lists)?;
            }
        }
        cx.draws += draws;
        cx.count(DRAWN, u64::from(self.instance_count));
        cx.count(LIGHT_PASSES, lit.len() as u64);
        cx.count(REFRACTING, refracting);
        Ok(())
    }

    /// Compute shading's fragment lists for the accumulation `target`'s
    /// pixels, with as many slots as the device's limits allow.
    fn fragment_lists(
        &self,
        cx: &PassContext<'_>,
        target: Tex,
    ) -> Result<Arc<ListBuffers>, RenderError> {
        let (w, h) = cx.size_of(target)?;
        let slots = compute::slots_on(cx.gpu, u64::from(w) * u64::from(h));
        if slots == 0 {
            return Err(RenderError::Pass {
                pass: "transparency".to_owned(),
                message: format!(
                    "a {w}x{h} image's fragment records do not fit the device's storage \
                     buffer limit: shade this Transparency forward (Shading: Forward)"
                ),
            });
        }
        Ok(self
            .lists
            .get(cx.gpu, (w * h).max(1), slots, self.recorded_lobes()))
    }

    /// Light buffer `set`'s light on every recorded fragment, added to the
    /// lists' light sums (one compute pass; transparency.wgsl's `shade`).
    fn shade(
        &self,
        cx: &mut PassContext<'_>,
        io: &AccumulateIo,
        set: usize,
        lists: &ListBuffers,
    ) -> Result<(), RenderError> {
        let light = self
            .light_keys()
            .nth(set)
            .ok_or_else(|| RenderError::Pass {
                pass: "transparency".to_owned(),
                message: format!("no light buffer {set} to shade"),
            })?;
        let pass = self.shade_pass(light);
        let entry = shade_entry(pass);
        let lobes = lists.lobes();
        let key = TransparencyKey {
            surface: TransparencyKey::COMPOSITE.surface,
            pass,
            coat: lobes.coat,
            anisotropy: lobes.anisotropy,
            sheen: lobes.sheen,
        }
        .key();
        let size = cx.size_of(io.accumulation)?;
        let mut b = Bindings::new()
            .buffer("camera", self.gbuffer.camera_buffer())
            .buffer("params", &self.params)
            .buffer("fragment_counts", &lists.counts)
            .buffer("fragment_records", &lists.records)
            .buffer_opt("coat_records", lists.coat.as_ref())
            .buffer_opt("sheen_records", lists.sheen.as_ref())
            .buffer_opt("anisotropy_records", lists.anisotropy.as_ref())
            .buffer("shaded_light", &lists.light)
            .texture("shade_accumulation", io.accumulation)
            .extend(self.light_bindings(cx, set, io.spot_textures[set])?);
        let light_set = &self.lights[set];
        // Held while the dispatch binds them: the lists the assignment just filled.
        let guard = light_set.clusters.as_ref().map(|c| {
            (
                c.store
                    .get(cx.gpu, io.grid.clusters(), light_set.lights.count()),
                &c.grid,
            )
        });
        if let Some((guard, grid)) = &guard {
            let Some(lists) = guard.as_ref() else {
                return Ok(());
            };
            b = b
                .buffer("grid", grid)
                .buffer("light_counts", &lists.counts)
                .buffer("light_offsets", &lists.offsets)
                .buffer("light_indices", &lists.indices);
        }
        cx.count(compute::SHADED, 1);
        cx.dispatch_shader("transparency shade", &key, entry, b, super::per_pixel(size))
    }

    /// One render pass over the two targets drawing `work`'s items: their
    /// layers' draws with their pipelines and groups. Returns the draws.
    fn draw(
        &self,
        cx: &mut PassContext<'_>,
        io: &AccumulateIo,
        work: &[&Work],
    ) -> Result<u64, RenderError> {
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
        for ((first, end), culled, maps, _, pipeline, groups) in work.iter().copied() {
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
        Ok(draws)
    }

    /// Light buffer `set`'s bindings: its lights, spots' projections and
    /// texture array, and shadow maps.
    fn light_bindings(
        &self,
        cx: &PassContext<'_>,
        set: usize,
        spot_textures: Option<Tex>,
    ) -> Result<Bindings<'_>, RenderError> {
        let light_set = &self.lights[set];
        let b = Bindings::new().buffer("lights", light_set.lights.buffer());
        crate::lighting::bind_light_buffer(
            b,
            cx,
            &light_set.lights,
            light_set.shadows.as_deref(),
            spot_textures,
            "transparency",
        )
    }

    /// The opaque image's mip chain, at the image's size.
    fn build_mips(&self, cx: &mut PassContext<'_>, source: Tex) -> Result<(), RenderError> {
        let (chain, _) = self.mips.get(cx.gpu, cx.size_of(source)?);
        refraction_mips::build(cx, source, &chain)
    }

    fn resolve(&self, cx: &mut PassContext<'_>, io: &ResolveIo) -> Result<(), RenderError> {
        let size = cx.size_of(io.output)?;
        let b = Bindings::new()
            .texture("opaque", io.opaque)
            .texture("accumulation", io.accumulation)
            .texture("revealage", io.revealage)
            .texture("output", io.output);
        if !self.compute {
            return cx.dispatch_shader(
                "transparency resolve",
                &TransparencyKey::COMPOSITE.key(),
                "resolve",
                b,
                super::per_pixel(size),
            );
        }
        // The accumulation pass made them this frame.
        let lists = self.lists.current().ok_or_else(|| RenderError::Pass {
            pass: "transparency".to_owned(),
            message: "the compute-shaded light sums were not made this frame".to_owned(),
        })?;
        cx.dispatch_shader(
            "transparency resolve",
            &TransparencyKey::SHADED_RESOLVE.key(),
            "resolve",
            b.buffer("shaded_light", &lists.light),
            super::per_pixel(size),
        )
    }
}

/// Whether a light pass walks froxel lists: as CookTorrance decides it
/// (suns have no range to cluster by; Auto clusters past [`FEW_LIGHTS`]).
fn clustered(mode: LightLoop, lights: &LightBuffer) -> bool {
    match mode {
        _ if lights.kind == LightKind::Sun => false,
        LightLoop::Auto => lights.count() > FEW_LIGHTS,
        // Its forward walk has one froxel loop; every froxel walk lists the same lights.
        LightLoop::Clustered | LightLoop::Tiled | LightLoop::PerPixel => true,
        LightLoop::Naive => false,
    }
}

/// One pipeline's share of the accumulation: its layer's instance range,
/// whether back faces are culled, whether the layer has surface maps,
/// whether it is a light pass; the pipeline and its bind groups.
type Work = (
    (u32, u32),
    bool,
    bool,
    bool,
    wgpu::RenderPipeline,
    crate::frame_graph::BindGroups,
);

/// A layer's own maps as the accumulation pass read them.
#[derive(Clone, Copy, Default)]
struct LayerMapReads {
    normal: Option<Tex>,
    color: Option<Tex>,
    /// The world's texture array, when its MatCap materials name images.
    matcap: Option<Tex>,
}

/// What the accumulation pass declared: the depth it tests against, the
/// two targets it clears and draws into, and the textures layers and
/// lights sample.
struct AccumulateIo {
    depth: Tex,
    accumulation: Tex,
    revealage: Tex,
    /// Per layer.
    layer_maps: Vec<LayerMapReads>,
    /// Per light buffer: its spots' texture array.
    spot_textures: Vec<Option<Tex>>,
    /// The forward grid the clustered light passes' lists are made in.
    grid: ClusterGrid,
    /// The opaque lit image, when some layer refracts it.
    lit: Option<Tex>,
    /// The mip chain's token, when refracting layers blur by it.
    mips: Option<Tex>,
}

/// What the resolve pass declared.
struct ResolveIo {
    opaque: Tex,
    accumulation: Tex,
    revealage: Tex,
    output: Tex,
}

/// A layer's accumulation draw: culled or not, its pass, the light buffer
/// of a light pass, and its permutation ([`Transparency::layer_passes`]).
type LayerPass = (bool, TransparencyPass, Option<usize>, ShaderKey);

/// The compute shading's entry point for a shade `pass`.
fn shade_entry(pass: TransparencyPass) -> &'static str {
    match pass {
        TransparencyPass::ShadeTiled(_) => "shade_tiled",
        _ => "shade",
    }
}

/// The accumulation pipeline of one permutation, back faces culled when
/// `culled`.
fn accumulate_pipeline(
    cx: &mut PassContext<'_>,
    key: ShaderKey,
    culled: bool,
    pass: TransparencyPass,
) -> Result<wgpu::RenderPipeline, RenderError> {
    let device = cx.gpu.device.clone();
    let (variant, build) = accumulate_build(culled, pass);
    cx.shaders
        .render_pipeline(&device, &key, variant, |module, cache| {
            build(&device, module, cache)
        })
}

/// The accumulation pipeline's variant name and how it is built (by the
/// pass, or on a thread where the pass announced it): back faces culled
/// when `culled`. The base pass adds (premultiplied colour, alpha) and
/// multiplies the revealage; a light pass adds to the colour alone.
fn accumulate_build(
    culled: bool,
    pass: TransparencyPass,
) -> (
    &'static str,
    impl Fn(&wgpu::Device, &wgpu::ShaderModule, Option<&wgpu::PipelineCache>) -> wgpu::RenderPipeline
    + Send
    + Sync
    + 'static,
) {
    let lit = matches!(pass, TransparencyPass::Light(_));
    let variant = match (culled, lit) {
        (true, false) => "wboit, culled",
        (false, false) => "wboit",
        (true, true) => "wboit light, culled",
        (false, true) => "wboit light",
    };
    let build = move |device: &wgpu::Device,
                      module: &wgpu::ShaderModule,
                      cache: Option<&wgpu::PipelineCache>| {
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
        pulled_pipeline(
            device,
            module,
            cache,
            "transparency accumulate",
            wgpu::PrimitiveState {
                topology: wgpu::PrimitiveTopology::TriangleList,
                front_face: wgpu::FrontFace::Ccw,
                cull_mode: culled.then_some(wgpu::Face::Back),
                ..Default::default()
            },
            None,
            &[
                Some(wgpu::ColorTargetState {
                    format: ACCUMULATION,
                    blend: Some(wgpu::BlendState {
                        color: additive,
                        alpha: additive,
                    }),
                    // A light pass adds colour; the weight sum (alpha) is the base pass's.
                    write_mask: if lit {
                        wgpu::ColorWrites::COLOR
                    } else {
                        wgpu::ColorWrites::ALL
                    },
                }),
                Some(wgpu::ColorTargetState {
                    format: REVEALAGE,
                    blend: Some(wgpu::BlendState {
                        color: reveal,
                        alpha: reveal,
                    }),
                    // Only red is read, and only the base pass covers.
                    write_mask: if lit {
                        wgpu::ColorWrites::empty()
                    } else {
                        wgpu::ColorWrites::RED
                    },
                }),
            ],
        )
    };
    (variant, build)
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
        if let Some(environment) = &self.environment {
            environment.declare(renderer, fg);
        }
        for set in &self.lights {
            if let Some(textures) = set.lights.textures() {
                textures.recipe.declare(renderer, fg);
            }
            if let Some(shadows) = &set.shadows {
                shadows.declare(renderer, fg);
            }
        }
        // The forward grid of the G-buffer's camera, where the transparent
        // fragments are drawn too: finer tiles and thinner slices than
        // CookTorrance's (a fragment walks its froxel's whole list), lists
        // only where the base pass marked a fragment. The assignment runs
        // inside the accumulation, between the base and light passes.
        let size = self.gbuffer.pixel_size(fg.output_size());
        let (near, far) =
            crate::lighting::near_far(self.gbuffer.camera.projection).unwrap_or((0.1, 1000.0));
        let grid = ClusterGrid::forward(size, near, far);
        for set in &self.lights {
            if let Some(clusters) = &set.clusters {
                renderer.gpu.queue.write_buffer(
                    &clusters.grid,
                    0,
                    bytemuck::cast_slice(&grid.uniform(set.lights.count())),
                );
            }
        }
        // Rough refraction's mip chain, a pass before the accumulation, only
        // when some layer refracts and blurs by it.
        let refracts = self
            .layers
            .iter()
            .zip(&self.layer_ranges)
            .any(|(layer, range)| range.0 != range.1 && self.transmits(self.surface(layer).1));
        let mips_built = refracts && self.blur == RefractionBlur::Mips;
        if mips_built {
            let mut pass = fg.pass(name("refraction mips"), self.owner);
            let source = pass.read(&self.source.name);
            pass.write(&self.mips_token, TextureDesc::token());
            pass.run(move |cx| self.build_mips(cx, source));
        }
        // Drawn into, and cleared by a compute pass first.
        let target = |format| {
            let mut desc = TextureDesc::attachment(format).size(self.gbuffer.size);
            desc.usage |= wgpu::TextureUsages::STORAGE_BINDING;
            desc
        };
        let mut pass = fg.pass(name("accumulate"), self.owner);
        // Ordering tokens: the environment's maps and the shadow maps live
        // outside the graph.
        if let Some(environment) = &self.environment {
            pass.read(environment.token());
        }
        for set in &self.lights {
            if let Some(shadows) = &set.shadows {
                pass.read(shadows.token());
            }
        }
        let layer_maps = self
            .layers
            .iter()
            .map(|layer| {
                let (surface, world) = self.surface(layer);
                let matcap = match Self::matcap(world) {
                    MatCapKey::Images => {
                        world.and_then(|w| w.textures()).map(|t| pass.read(&t.name))
                    }
                    _ => None,
                };
                match surface.maps {
                    LayerMaps::Layer { color, normal, .. } => LayerMapReads {
                        normal: layer
                            .normal_map
                            .as_ref()
                            .filter(|_| normal)
                            .map(|m| pass.read(&m.name)),
                        color: layer
                            .color_map
                            .as_ref()
                            .filter(|_| color)
                            .map(|m| pass.read(&m.name)),
                        matcap,
                    },
                    _ => LayerMapReads {
                        matcap,
                        ..Default::default()
                    },
                }
            })
            .collect();
        let spot_textures = self
            .lights
            .iter()
            .map(|set| set.lights.textures().map(|t| pass.read(&t.name)))
            .collect();
        let io = AccumulateIo {
            lit: refracts.then(|| pass.read(&self.source.name)),
            mips: mips_built.then(|| pass.read(&self.mips_token)),
            depth: pass.read(&self.gbuffer.targets.depth),
            accumulation: pass.write(&self.accumulation, target(ACCUMULATION)),
            revealage: pass.write(&self.revealage, target(REVEALAGE)),
            layer_maps,
            spot_textures,
            grid,
        };
        // The pipelines of the draws, the clear and the compute shading,
        // made on threads on a first frame (frame_graph/gather.rs).
        if pass.graph().gathers_pipelines() {
            self.announce_accumulation(&mut pass, renderer.gpu.adapter_class());
        }
        pass.run(move |cx| self.accumulate(renderer, cx, &io));
        let mut pass = fg.pass(name("resolve"), self.owner);
        if pass.graph().gathers_pipelines() {
            let resolve_key = match self.compute {
                true => TransparencyKey::SHADED_RESOLVE,
                false => TransparencyKey::COMPOSITE,
            };
            pass.will_dispatch(&resolve_key.key(), "resolve");
        }
        let io = ResolveIo {
            opaque: pass.read(&self.source.name),
            accumulation: pass.read(&self.accumulation),
            revealage: pass.read(&self.revealage),
            output: pass.write(&self.output, output),
        };
        pass.run(move |cx| self.resolve(cx, &io));
    }
}
