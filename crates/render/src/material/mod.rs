//! Emeshe's flags-driven material system. A [`Material`] is a set of
//! features, each a bit of a `u32` flag word with its vec4 parameters. A
//! [`MaterialWorld`] is an ordered list of materials (material id = index,
//! what the G-buffer stores per pixel) packed into three storage buffers,
//! read by `shaders/lib/material.wgsl`:
//!
//! - MaterialMeta, one per material: flags, address (index of its first
//!   FeatureOffset entry), size (its number of features), pad.
//! - FeatureOffset, one per feature of each material, in ascending feature id:
//!   feature id, offset into MaterialData (in vec4s), count (vec4s), pad.
//! - MaterialData: every parameter vec4 of every material, back to back.
//!
//! Because a material's entries are sorted by id, the shader finds feature
//! `f` at `address + countOneBits(flags & ((1 << f) - 1))` without a loop.
//! [`MaterialWorld::union_flags`] is what a shading pass builds its
//! permutation from: a feature no material has costs nothing. Worlds are not
//! singletons; each owns its buffers.
//!
//! glTF materials are materials of the same world: their maps are the
//! SurfaceMaps feature ([`maps`]), whose textures the world uploads in size
//! classes ([`map_textures`]). The G-buffer resolve samples them and writes
//! each pixel's roughness, metallic, occlusion and emission to the
//! G-buffer's `surface` target (as it does for a shader node material's
//! `surface` function), which lighting reads wherever it was written
//! (`shaders/lib/surface_target.wgsl`; `feature_param_at` too): every
//! shading pass sees mapped values without knowing glTF. The extensions'
//! maps (clearcoat, specular) add the coat and the reflectance to it, for
//! the materials that have one (`clearcoat_at`); lit transparency samples
//! them, and the thickness map, per fragment.

mod feature;
pub mod library;
pub mod map_textures;
pub mod maps;

use std::collections::BTreeMap;
use std::sync::Arc;

use thiserror::Error;
use wgpu::util::DeviceExt;

pub use feature::{
    FEATURE_AMBIENT_OCCLUSION, FEATURE_ANISOTROPY, FEATURE_CLEARCOAT, FEATURE_COOK_TORRANCE,
    FEATURE_EMISSION, FEATURE_FAKE_SSS, FEATURE_IRIDESCENCE, FEATURE_MATCAP, FEATURE_REFLECTION,
    FEATURE_SHEEN, FEATURE_SURFACE_MAPS, FEATURE_TRANSMISSION, FEATURE_UNLIT, FIRST_CUSTOM_FEATURE,
    Feature, MAX_ABSORPTION, MAX_FEATURES, MatCapMapping, MatCapMode, ParamLayout, Range,
    matcap_params, transmission_params,
};
use map_textures::MapLayout;
pub use map_textures::{MapFiltering, WorldMaps};
use maps::{MapSlot, SurfaceMaps};

use crate::frame_graph::Bindings;
use crate::recipe::TextureRef;
use crate::renderer::Renderer;

/// Why a feature's setting was refused. Names the feature; [`MaterialError`] adds the material.
#[derive(Clone, Debug, Error, PartialEq)]
pub enum FeatureError {
    #[error("feature {feature}: parameter {index} component {component} is NaN or infinite")]
    NonFinite {
        feature: String,
        index: usize,
        component: usize,
    },
    #[error("feature {feature} takes {expected} parameter vec4(s), got {got}")]
    ParamCount {
        feature: String,
        expected: usize,
        got: usize,
    },
    #[error(
        "feature id {id} does not exist: built-in features are 0..=5, 7 and 8 (6 is SurfaceMaps, 9..=15 are reserved), custom ones 16..=31"
    )]
    UnknownFeature { id: i64 },
}

/// The G-buffer's sheen and film target's format: four pairs of unorm16
/// values and a written flag (shaders/lib/sheen_film.wgsl). Here, beside
/// the 1x1 stand-in bound where the G-buffer has no such target; the
/// G-buffer re-exports it.
pub const SHEEN_FILM_FORMAT: wgpu::TextureFormat = wgpu::TextureFormat::Rgba32Uint;

/// A [`FeatureError`] on material `material` (its id: index in the world, slice on a node).
#[derive(Clone, Debug, Error, PartialEq)]
#[error("material {material}: {source}")]
pub struct MaterialError {
    pub material: usize,
    #[source]
    pub source: FeatureError,
}

impl FeatureError {
    pub fn in_material(self, material: usize) -> MaterialError {
        MaterialError {
            material,
            source: self,
        }
    }
}

/// The G-buffer targets material lookups read at a pixel, by name: the UV
/// (zw of the velocity/UV target) that texture layers are mapped by. The
/// G-buffer hands them out (`GBufferTargets::surface_targets`), so materials
/// need not know it. (Its surface target is bound by the lighting passes
/// themselves, group 0 under SURFACE_TARGET, with or without a material
/// world: `GBufferTargets::surface_feature`.)
#[derive(Clone, Copy, Debug)]
pub struct SurfaceTargets<'a> {
    pub uv: &'a str,
}

/// A material in patch space: features and their (checked, clamped) parameters.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Material {
    /// By feature id, so packing walks them in ascending order.
    features: BTreeMap<u32, (Feature, Vec<[f32; 4]>)>,
    /// Per feature id: the layer of the world's texture array that scales
    /// its first parameter vec4, channel by channel, at each pixel's G-buffer UV.
    textures: BTreeMap<u32, u32>,
    /// Per (feature id, parameter index in [`Feature::parameters`]): the
    /// layer that scales that parameter alone (a number by the layer's red
    /// channel, a colour by its rgb), in place of `textures`' channel.
    param_textures: BTreeMap<(u32, usize), u32>,
    /// A glTF material's maps (the SurfaceMaps feature), shared, not copied.
    maps: Option<Arc<SurfaceMaps>>,
}

impl Material {
    /// A material without features.
    pub fn new() -> Self {
        Self::default()
    }

    /// What material id 0 is when nothing is given: CookTorrance, roughness 0.5, metallic 0.
    pub fn default_material() -> Self {
        let mut m = Material::new();
        let params = Feature::CookTorrance.layout().map(|l| l.default);
        m.features.insert(
            FEATURE_COOK_TORRANCE,
            (Feature::CookTorrance, params.into_iter().collect()),
        );
        m
    }

    /// Set `feature`, replacing an earlier setting of it. Non-finite
    /// parameters are refused; the rest is clamped to physical ranges.
    pub fn set(&mut self, feature: Feature, params: &[[f32; 4]]) -> Result<(), FeatureError> {
        let params = feature.sanitize(params)?;
        self.features.insert(feature.id(), (feature, params));
        Ok(())
    }

    /// `self` with `feature` set, for chaining.
    pub fn with(mut self, feature: Feature, params: &[[f32; 4]]) -> Result<Self, FeatureError> {
        self.set(feature, params)?;
        Ok(self)
    }

    pub fn remove(&mut self, feature: Feature) {
        self.features.remove(&feature.id());
        self.textures.remove(&feature.id());
        self.param_textures.retain(|(id, _), _| *id != feature.id());
    }

    /// Let layer `layer` scale parameter `param` of `feature` alone (its
    /// index in [`Feature::parameters`]: CookTorrance's Metallic is 1,
    /// Emission's Strength 1), at each pixel's UV: a number by the layer's
    /// red channel (a grayscale map), a colour by its rgb. It takes the
    /// place of the feature's Texture ID for that parameter; None: none.
    /// Shading reads it for CookTorrance, Emission and FakeSSS (what
    /// `feature_param_at` serves), and only while the material has the feature.
    pub fn set_param_texture(&mut self, feature: Feature, param: usize, layer: Option<u32>) {
        match layer {
            Some(layer) => self.param_textures.insert((feature.id(), param), layer),
            None => self.param_textures.remove(&(feature.id(), param)),
        };
    }

    pub fn param_texture(&self, feature: Feature, param: usize) -> Option<u32> {
        self.features
            .contains_key(&feature.id())
            .then(|| self.param_textures.get(&(feature.id(), param)).copied())
            .flatten()
    }

    /// Per component of `feature`'s first vec4, what scales it: 0 for
    /// nothing, else the layer + 1 (low 24 bits) and the channel of that
    /// layer (bits 24..26), as `feature_param_at` reads them. The feature's
    /// Texture ID gives component k channel k; a parameter's own layer
    /// replaces it for that parameter's components.
    pub fn component_maps(&self, feature: Feature) -> [u32; 4] {
        let mut maps = [0u32; 4];
        if !self.features.contains_key(&feature.id()) {
            return maps;
        }
        let entry =
            |layer: u32, channel: usize| (layer.min(0xFF_FFFE) + 1) | ((channel as u32) << 24);
        // MatCap's Texture ID is its image, not a scale.
        if let Some(layer) = self.texture(feature).filter(|_| feature != Feature::MatCap) {
            for (k, m) in maps.iter_mut().enumerate() {
                *m = entry(layer, k);
            }
        }
        for (param, (_, components)) in feature.parameters().iter().enumerate() {
            if let Some(layer) = self.param_texture(feature, param) {
                let colour = components.len() > 1;
                for (j, k) in components.clone().enumerate() {
                    maps[k] = entry(layer, if colour { j } else { 0 });
                }
            }
        }
        maps
    }

    /// Let layer `layer` of the world's texture array scale `feature`'s first
    /// parameter, component by component, at each pixel's UV (None: no texture).
    /// MatCap is the exception: its layer is the matcap image, looked up by
    /// the pixel's normal. It takes effect only while the material has the feature.
    pub fn set_texture(&mut self, feature: Feature, layer: Option<u32>) {
        match layer {
            Some(layer) => self.textures.insert(feature.id(), layer),
            None => self.textures.remove(&feature.id()),
        };
    }

    pub fn texture(&self, feature: Feature) -> Option<u32> {
        self.features
            .contains_key(&feature.id())
            .then(|| self.textures.get(&feature.id()).copied())
            .flatten()
    }

    /// Whether some feature of this material reads a texture.
    pub fn has_textures(&self) -> bool {
        self.textured_ids().next().is_some()
    }

    /// The ids of features this material has that name a texture layer
    /// (theirs or one of their parameters').
    fn textured_ids(&self) -> impl Iterator<Item = u32> + '_ {
        (self.textures.keys().copied())
            .chain(self.param_textures.keys().map(|(id, _)| *id))
            .filter(|id| self.features.contains_key(id))
    }

    /// The OR of the features' flags (SurfaceMaps' included).
    pub fn flags(&self) -> u32 {
        let maps = if self.maps.is_some() {
            1 << FEATURE_SURFACE_MAPS
        } else {
            0
        };
        self.features.keys().fold(maps, |acc, id| acc | 1 << id)
    }

    /// Give the material surface maps (the SurfaceMaps feature), or take them away.
    pub fn set_maps(&mut self, maps: Option<Arc<SurfaceMaps>>) {
        self.maps = maps;
    }

    pub fn maps(&self) -> Option<&Arc<SurfaceMaps>> {
        self.maps.as_ref()
    }

    /// Every feature entry as packed, in ascending id: (id, parameters,
    /// texture layer + 1, per-component maps).
    fn entries(&self, layout: Option<&MapLayout>) -> Vec<Entry> {
        let mut entries: Vec<_> = self
            .features()
            .map(|(f, p)| {
                let texture = self.texture(f).map_or(0, |layer| layer + 1);
                (f.id(), p.to_vec(), texture, self.component_maps(f))
            })
            .collect();
        if let Some(maps) = &self.maps {
            let params = maps.pack(&|m, slot| layout?.location(m, slot));
            entries.push((FEATURE_SURFACE_MAPS, params, 0, [0; 4]));
            entries.sort_by_key(|e| e.0);
        }
        entries
    }

    pub fn params(&self, feature: Feature) -> Option<&[[f32; 4]]> {
        self.features.get(&feature.id()).map(|(_, p)| p.as_slice())
    }

    /// The features in ascending id, with their parameters.
    pub fn features(&self) -> impl Iterator<Item = (Feature, &[[f32; 4]])> {
        self.features.values().map(|(f, p)| (*f, p.as_slice()))
    }
}

/// One packed feature: its id, parameter vec4s, Texture ID + 1 and per-component maps.
type Entry = (u32, Vec<[f32; 4]>, u32, [u32; 4]);

/// Matches `MaterialMeta` in shaders/lib/material.wgsl.
#[repr(C)]
#[derive(Clone, Copy, Debug, PartialEq, Eq, bytemuck::Pod, bytemuck::Zeroable)]
pub struct GpuMaterialMeta {
    pub flags: u32,
    pub address: u32,
    pub size: u32,
    pub pad: u32,
}

/// Matches `FeatureOffset` in shaders/lib/material.wgsl.
#[repr(C)]
#[derive(Clone, Copy, Debug, PartialEq, Eq, bytemuck::Pod, bytemuck::Zeroable)]
pub struct GpuFeatureOffset {
    pub feature: u32,
    pub offset: u32,
    pub count: u32,
    /// The feature's Texture ID: its layer + 1; 0: none.
    pub texture: u32,
    /// What scales each component of the first parameter vec4
    /// ([`Material::component_maps`]); 0: nothing.
    pub maps: [u32; 4],
}

/// The three buffers' contents, before upload (also what tests check without a GPU).
#[derive(Clone, Debug, Default, PartialEq)]
pub struct PackedMaterials {
    pub meta: Vec<GpuMaterialMeta>,
    pub offsets: Vec<GpuFeatureOffset>,
    pub data: Vec<[f32; 4]>,
}

impl PackedMaterials {
    /// Pack without map textures: maps read as absent.
    pub fn pack(materials: &[Material]) -> Self {
        Self::pack_with(materials, None)
    }

    /// Pack with the maps' places in `layout`.
    pub fn pack_with(materials: &[Material], layout: Option<&MapLayout>) -> Self {
        let mut packed = PackedMaterials::default();
        for material in materials {
            let entries = material.entries(layout);
            packed.meta.push(GpuMaterialMeta {
                flags: material.flags(),
                address: packed.offsets.len() as u32,
                size: entries.len() as u32,
                pad: 0,
            });
            for (feature, params, texture, maps) in entries {
                packed.offsets.push(GpuFeatureOffset {
                    feature,
                    offset: packed.data.len() as u32,
                    count: params.len() as u32,
                    texture,
                    maps,
                });
                packed.data.extend_from_slice(&params);
            }
        }
        packed
    }
}

/// Stand-ins bound where a permutation declares a texture the world lacks.
struct Dummies {
    array: wgpu::TextureView,
    uv: wgpu::TextureView,
    /// A 1x1 sheen and film target of one unwritten texel
    /// (`spreadlight::sheen_film`): lighting reads the factors through it.
    sheen_film: wgpu::TextureView,
}

/// A material world on the GPU: what a `MaterialBuffer` node outputs,
/// uploaded once when its inputs change.
pub struct MaterialWorld {
    materials: Vec<Material>,
    union_flags: u32,
    /// Some material's FakeSSS has a colour and a strength above zero
    /// ([`MaterialWorld::scatters_subsurface`]), found once when built.
    scatters: bool,
    /// The array material textures index; only when some material reads it.
    textures: Option<TextureRef>,
    /// Bit n: some material's feature n reads a texture.
    textured_flags: u32,
    /// The SurfaceMaps' textures, when some material has maps.
    maps: Option<WorldMaps>,
    /// Some material has a map of a material extension (clearcoat,
    /// specular, thickness): the passes that read them compile their code
    /// (EXTENSION_MAPS) only then.
    extension_maps: bool,
    /// Some material has a sheen or iridescence map: the G-buffer's sheen
    /// and film target holds what they make per pixel.
    sheen_film_maps: bool,
    dummies: Dummies,
    meta: wgpu::Buffer,
    offsets: wgpu::Buffer,
    data: wgpu::Buffer,
}

impl std::fmt::Debug for MaterialWorld {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(
            f,
            "MaterialWorld({} materials, flags {:#x})",
            self.materials.len(),
            self.union_flags
        )
    }
}

impl MaterialWorld {
    /// Upload `materials` (material id = index). An empty list gives the
    /// default material as id 0, so every world has one: shaders map ids out
    /// of range to 0.
    pub fn new(renderer: &Renderer, materials: Vec<Material>) -> Arc<Self> {
        Self::with_textures(renderer, materials, None)
    }

    /// A world whose materials' texture layers index `textures` (a 2D texture
    /// or texture array); layers past its end wrap. Without it, or when no
    /// material reads a texture, shading compiles no texture code.
    pub fn with_textures(
        renderer: &Renderer,
        materials: Vec<Material>,
        textures: Option<TextureRef>,
    ) -> Arc<Self> {
        Self::build(renderer, materials, textures, MapFiltering::default())
    }

    /// A world whose surface maps are filtered as `filtering` says, not
    /// trilinear + anisotropic (the accuracy command's comparison).
    pub fn with_map_filtering(
        renderer: &Renderer,
        materials: Vec<Material>,
        filtering: MapFiltering,
    ) -> Arc<Self> {
        Self::build(renderer, materials, None, filtering)
    }

    fn build(
        renderer: &Renderer,
        mut materials: Vec<Material>,
        textures: Option<TextureRef>,
        filtering: MapFiltering,
    ) -> Arc<Self> {
        if materials.is_empty() {
            materials.push(Material::default_material());
        }
        let device = &renderer.gpu.device;
        let max_layers = device.limits().max_texture_array_layers;
        let mut layout = MapLayout::new();
        for maps in materials.iter().filter_map(|m| m.maps.as_ref()) {
            for slot in MapSlot::ALL {
                if let Some(map) = maps.map(slot) {
                    layout.place(map, slot, max_layers);
                }
            }
        }
        let packed = PackedMaterials::pack_with(&materials, Some(&layout));
        let upload = |label: &str, bytes: &[u8]| {
            // A storage binding cannot be empty (materials without features
            // have no offsets or data); the flags say nothing is there. One
            // element of the largest struct bound (a GpuFeatureOffset, 32
            // bytes): a shader's minimum binding size is one element.
            const PLACEHOLDER: [u8; std::mem::size_of::<GpuFeatureOffset>()] =
                [0; std::mem::size_of::<GpuFeatureOffset>()];
            let contents = if bytes.is_empty() {
                &PLACEHOLDER[..]
            } else {
                bytes
            };
            device.create_buffer_init(&wgpu::util::BufferInitDescriptor {
                label: Some(label),
                contents,
                usage: wgpu::BufferUsages::STORAGE,
            })
        };
        let meta = upload("material meta", bytemuck::cast_slice(&packed.meta));
        let offsets = upload("feature offsets", bytemuck::cast_slice(&packed.offsets));
        let data = upload("material data", bytemuck::cast_slice(&packed.data));
        let union_flags = materials.iter().fold(0, |acc, m| acc | m.flags());
        let scatters = materials.iter().any(|m| {
            m.params(Feature::FakeSss)
                .and_then(|p| p.first())
                .is_some_and(|p| p[3] > 0.0 && p[0].max(p[1]).max(p[2]) > 0.0)
        });
        let textured_flags = match &textures {
            Some(_) => materials.iter().fold(0, |acc, m| {
                m.textured_ids().fold(acc, |acc, id| acc | 1 << id)
            }),
            None => 0,
        };
        let textures = textures.filter(|_| textured_flags != 0);
        // Mapped roughness, metallic, emission and occlusion reach shading
        // through the G-buffer's surface target (SURFACE_TARGET), not
        // through MATERIAL_TEXTURES: maps alone compile no texture code.
        let has_maps = union_flags & (1 << FEATURE_SURFACE_MAPS) != 0;
        let maps = has_maps.then(|| WorldMaps::new(renderer, &layout, filtering));
        let extension_maps = materials
            .iter()
            .filter_map(|m| m.maps.as_ref())
            .any(|m| m.has_extension_maps());
        let sheen_film_maps = materials
            .iter()
            .filter_map(|m| m.maps.as_ref())
            .any(|m| m.has_sheen_film_maps());
        Arc::new(MaterialWorld {
            materials,
            union_flags,
            scatters,
            textures,
            textured_flags,
            maps,
            extension_maps,
            sheen_film_maps,
            dummies: Dummies::new(&renderer.gpu),
            meta,
            offsets,
            data,
        })
    }

    pub fn materials(&self) -> &[Material] {
        &self.materials
    }

    pub fn len(&self) -> usize {
        self.materials.len()
    }

    /// Never true: a world always has material 0.
    pub fn is_empty(&self) -> bool {
        self.materials.is_empty()
    }

    /// The OR of every material's flags: the features a shading permutation must include.
    pub fn union_flags(&self) -> u32 {
        self.union_flags
    }

    /// Whether some material has `feature` (a `FEATURE_*` index).
    pub fn has(&self, feature: u32) -> bool {
        self.union_flags & (1 << feature) != 0
    }

    /// Whether some material scatters light under its surface: has FakeSSS
    /// with a colour and a strength above zero. A FakeSSS of strength 0 makes
    /// no subsurface term (CookTorrance multiplies by both), so it asks for
    /// no SSSS passes; maps only scale the strength, they cannot raise a zero.
    /// Recipes made again each frame ask it, so it is found when the world is built.
    pub fn scatters_subsurface(&self) -> bool {
        self.scatters
    }

    /// Whether some material has `feature` (a `FEATURE_*` id).
    pub fn any_has(&self, feature: u32) -> bool {
        feature < MAX_FEATURES && self.union_flags & (1 << feature) != 0
    }

    /// Material `id`'s flags; an id out of range reads material 0, as the shader does.
    pub fn flags(&self, material_id: u32) -> u32 {
        self.material(material_id).flags()
    }

    /// Material `id`'s parameters for `feature`, or `None` when it lacks it.
    pub fn params(&self, material_id: u32, feature: Feature) -> Option<&[[f32; 4]]> {
        self.material(material_id).params(feature)
    }

    fn material(&self, id: u32) -> &Material {
        self.materials
            .get(id as usize)
            .unwrap_or(&self.materials[0])
    }

    /// Whether material `id` is double-sided (its surface maps say so).
    pub fn double_sided(&self, material_id: u32) -> bool {
        self.material(material_id)
            .maps
            .as_ref()
            .is_some_and(|m| m.double_sided)
    }

    /// Whether material `id` is alpha-tested (a glTF MASK material).
    pub fn alpha_masked(&self, material_id: u32) -> bool {
        self.material(material_id)
            .maps
            .as_ref()
            .is_some_and(|m| matches!(m.alpha, maps::AlphaMode::Mask { .. }))
    }

    /// Whether some material has surface maps (a glTF material).
    pub fn has_maps(&self) -> bool {
        self.maps.is_some()
    }

    /// Whether some material has a map of a material extension
    /// (clearcoat, clearcoat roughness, specular, specular colour,
    /// thickness: `maps::MapSlot::EXTENSIONS`).
    pub fn has_extension_maps(&self) -> bool {
        self.extension_maps
    }

    /// Whether some material with surface maps (a glTF material) has the
    /// Anisotropy feature: the G-buffer then gets an anisotropy target,
    /// which the resolve fills from the mesh's tangents, and CookTorrance
    /// compiles the anisotropic lobe (`ANISOTROPY`). Materials without maps
    /// have no tangent frame the resolve reads, and shade isotropic.
    pub fn has_anisotropy(&self) -> bool {
        self.maps.is_some() && self.has(FEATURE_ANISOTROPY)
    }

    /// Whether some material with surface maps has a sheen or iridescence
    /// map (`KHR_materials_sheen`'s, `KHR_materials_iridescence`'s): the
    /// G-buffer then gets its sheen and film target, which the resolve
    /// fills (`SHEEN_FILM`) and CookTorrance's and Reflection's `SHEEN` and
    /// `IRIDESCENCE` read. Factors alone need no target.
    pub fn has_sheen_film_maps(&self) -> bool {
        self.maps.is_some() && self.sheen_film_maps
    }

    /// What lighting binds as `sheen_film_target` where the G-buffer has no
    /// sheen and film target: one texel that says "not written", so every
    /// pixel reads its material's factors.
    pub(crate) fn sheen_film_stand_in(&self) -> wgpu::TextureView {
        self.dummies.sheen_film.clone()
    }

    /// The surface maps' textures and samplers, when some material has maps.
    pub fn world_maps(&self) -> Option<&WorldMaps> {
        self.maps.as_ref()
    }

    /// The texture array, when some material reads it.
    pub fn textures(&self) -> Option<&TextureRef> {
        self.textures.as_ref()
    }

    /// Whether a pass reading `features` (a flag mask) needs MATERIAL_TEXTURES.
    pub fn textured(&self, features: u32) -> bool {
        self.textured_flags & features != 0
    }

    /// What a pass that imports `spreadlight::material` binds, by name: the
    /// three buffers and, with `textures` (a pass that reads the texture
    /// array), the array, its sampler and the G-buffer's UV target
    /// (stand-ins where the world has none).
    pub(crate) fn bindings(&self, textures: Option<MaterialTextures>) -> Bindings<'_> {
        let b = Bindings::new()
            .buffer("material_meta", &self.meta)
            .buffer("feature_offsets", &self.offsets)
            .buffer("material_data", &self.data);
        let Some(t) = textures else {
            return b;
        };
        // Repeat: UVs beyond 0..1 tile.
        let b = b.sampler("material_sampler", crate::shaders::Sampling::LinearRepeat);
        // Only a texture array is mapped by the G-buffer's UV: surface maps
        // alone leave the motion resolve to be culled.
        match t.0 {
            Some((array, uv)) => b
                .array("material_textures", array)
                .texture("material_uv", uv),
            None => b
                .view("material_textures", self.dummies.array.clone())
                .view("material_uv", self.dummies.uv.clone()),
        }
    }

    /// The recipe of the texture array, declared for a pass that reads it
    /// (`textured`), before the pass is: see [`MaterialWorld::read_textures`].
    pub(crate) fn declare_upstream<'a>(
        &'a self,
        renderer: &'a Renderer,
        fg: &mut crate::frame_graph::FrameGraph<'a>,
        textured: bool,
    ) {
        if let Some(t) = self.textures.as_ref().filter(|_| textured) {
            t.recipe.declare(renderer, fg);
        }
    }

    /// A pass's reads of the texture array and the UV target, when it reads
    /// the array (`textured`): what [`MaterialWorld::bindings`] binds.
    pub(crate) fn read_textures(
        &self,
        pass: &mut crate::frame_graph::PassBuilder<'_, '_>,
        textured: bool,
        targets: SurfaceTargets<'_>,
    ) -> Option<MaterialTextures> {
        if !textured {
            return None;
        }
        Some(MaterialTextures(
            self.textures
                .as_ref()
                .map(|t| (pass.read(&t.name), pass.read(targets.uv))),
        ))
    }

    /// The maps' arrays and samplers by name, when some material has maps.
    pub(crate) fn maps_bindings(&self) -> Option<Bindings<'static>> {
        Some(self.maps.as_ref()?.bindings())
    }

    pub fn buffers(&self) -> (&wgpu::Buffer, &wgpu::Buffer, &wgpu::Buffer) {
        (&self.meta, &self.offsets, &self.data)
    }
}

/// The texture array and the UV target a pass declared it reads; None
/// where the world has no array (stand-ins are bound).
#[derive(Clone, Copy, Debug)]
pub(crate) struct MaterialTextures(Option<(crate::frame_graph::Tex, crate::frame_graph::Tex)>);

#[cfg(test)]
mod tests;

impl Dummies {
    fn new(gpu: &crate::context::GpuContext) -> Self {
        let array = crate::texture::GpuTexture::upload_rgba8(
            gpu,
            (1, 1),
            &[vec![255; 4]],
            false,
            "no material textures",
        );
        let array = array.texture.create_view(&wgpu::TextureViewDescriptor {
            dimension: Some(wgpu::TextureViewDimension::D2Array),
            ..Default::default()
        });
        let uv = crate::texture::GpuTexture::from_rgba8(gpu, 1, 1, &[0; 4], false, "no UV target");
        // wgpu zeroes a new texture: w = 0 reads "not written".
        let sheen_film = gpu
            .device
            .create_texture(&wgpu::TextureDescriptor {
                label: Some("no sheen and film target"),
                size: wgpu::Extent3d {
                    width: 1,
                    height: 1,
                    depth_or_array_layers: 1,
                },
                mip_level_count: 1,
                sample_count: 1,
                dimension: wgpu::TextureDimension::D2,
                format: SHEEN_FILM_FORMAT,
                usage: wgpu::TextureUsages::TEXTURE_BINDING,
                view_formats: &[],
            })
            .create_view(&wgpu::TextureViewDescriptor::default());
        Dummies {
            array,
            uv: uv.view,
            sheen_film,
        }
    }
}

/// The layout the shader sees (shaders/layout.rs).
#[cfg(test)]
mod wgsl_layout {
    use super::*;

    #[test]
    fn gpu_material_meta_matches_materialmeta_in_the_shader() {
        crate::assert_wgsl_layout!(
            GpuMaterialMeta,
            "lib/material.wgsl",
            [],
            "MaterialMeta",
            [flags, address, size, pad]
        );
    }

    #[test]
    fn gpu_feature_offset_matches_featureoffset_in_the_shader() {
        crate::assert_wgsl_layout!(
            GpuFeatureOffset,
            "lib/material.wgsl",
            [],
            "FeatureOffset",
            [feature, offset, count, texture, maps]
        );
    }
}
