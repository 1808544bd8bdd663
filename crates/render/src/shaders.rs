//! Shaders: the WGSL sources (embedded in the binary), their feature
//! switches, and the permutation cache, which is the only place that compiles
//! shaders and pipelines.
//!
//! Feature switches work like Emeshe's `#define` switches: a shader marks
//! optional code with `#ifdef FEATURE` (naga_oil's preprocessor), a pass asks
//! for a set of features, and the cache composes, validates and compiles that
//! permutation once. A combination no pass asks for is never compiled.
//! Shared libraries are imported by name (`#import spreadlight::packing`).

use std::borrow::Cow;
use std::collections::{BTreeSet, HashMap};
use std::path::Path;

use naga_oil::compose::{
    ComposableModuleDescriptor, Composer, NagaModuleDescriptor, ShaderDefValue, ShaderLanguage,
    ShaderType,
};

use crate::error::RenderError;

/// One WGSL file of `shaders/`.
pub struct ShaderFile {
    /// Path below `shaders/`, e.g. `gbuffer/visibility.wgsl`.
    pub path: &'static str,
    pub source: &'static str,
    /// The feature switches the file reacts to; every subset is a valid permutation.
    pub features: &'static [&'static str],
    /// Libraries are imported by other shaders; they have no entry points.
    pub library: bool,
    /// Which subsets make sense: a permutation that breaks a rule is refused
    /// and never compiled, and the permutation test skips it.
    pub rules: &'static [Rule],
}

/// A constraint between the features of one shader.
#[derive(Clone, Copy, Debug)]
pub enum Rule {
    /// The first feature only with the second (a third light pair only with a second).
    Requires(&'static str, &'static str),
    /// At most one of these (a choice, such as GBufferView's channel).
    AtMostOne(&'static [&'static str]),
}

impl Rule {
    fn check(&self, features: &BTreeSet<&'static str>) -> Result<(), String> {
        match *self {
            Rule::Requires(a, b) if features.contains(a) && !features.contains(b) => {
                Err(format!("`{a}` needs `{b}`"))
            }
            Rule::AtMostOne(set) if set.iter().filter(|f| features.contains(*f)).count() > 1 => {
                Err(format!(
                    "these features are a choice, set at most one: {}",
                    set.join(", ")
                ))
            }
            _ => Ok(()),
        }
    }
}

impl ShaderFile {
    /// Whether `features` is a permutation this file allows (every rule holds).
    pub fn check(&self, features: &BTreeSet<&'static str>) -> Result<(), String> {
        self.rules.iter().try_for_each(|r| r.check(features))
    }
}

macro_rules! shader {
    ($path:literal, library) => {
        ShaderFile {
            path: $path,
            source: include_str!(concat!("../../../shaders/", $path)),
            features: &[],
            library: true,
            rules: &[],
        }
    };
    ($path:literal, [$($feature:literal),*] $(, $rule:expr)*) => {
        ShaderFile {
            path: $path,
            source: include_str!(concat!("../../../shaders/", $path)),
            features: &[$($feature),*],
            library: false,
            rules: &[$($rule),*],
        }
    };
    ($path:literal, one_of [$($feature:literal),*]) => {
        ShaderFile {
            path: $path,
            source: include_str!(concat!("../../../shaders/", $path)),
            features: &[$($feature),*],
            library: false,
            rules: &[Rule::AtMostOne(&[$($feature),*])],
        }
    };
}

/// Every shader, in dependency order (libraries first).
pub const SHADERS: &[ShaderFile] = &[
    shader!("lib/packing.wgsl", library),
    shader!("lib/camera.wgsl", library),
    shader!("lib/mesh.wgsl", library),
    shader!("lib/geometry.wgsl", library),
    shader!("lib/particle.wgsl", library),
    shader!("lib/mesh_fetch.wgsl", library),
    shader!("lib/vertex_extras.wgsl", library),
    shader!("lib/brdf.wgsl", library),
    shader!("lib/lights.wgsl", library),
    shader!("lib/tonemap.wgsl", library),
    shader!("lib/surface_target.wgsl", library),
    shader!("lib/material.wgsl", library),
    shader!("lib/material_maps.wgsl", library),
    shader!("lib/matcap.wgsl", library),
    shader!("lib/screen.wgsl", library),
    shader!("lib/sky.wgsl", library),
    shader!("lib/ibl.wgsl", library),
    shader!("lib/post.wgsl", library),
    shader!("lighting/shadow_sampling.wgsl", library),
    shader!("lib/surface.wgsl", library),
    shader!("lib/custom_surface.wgsl", library),
    shader!("gbuffer/visibility.wgsl", ["ALPHA_MASK"]),
    shader!("geometry/spherize.wgsl", []),
    shader!("geometry/extrude.wgsl", ["TEXTURE"]),
    shader!("geometry/pn_triangles.wgsl", ["FLAT"]),
    shader!("geometry/spline.wgsl", ["RIBBON", "BEZIER"]),
    shader!("geometry/tessellate.wgsl", one_of["COUNT", "SUMS"]),
    shader!("geometry/displace.wgsl", one_of["ACCUMULATE", "NORMALS"]),
    shader!("geometry/skinning.wgsl", []),
    shader!(
        "particles/simulate.wgsl",
        ["FIELD_TEXTURE", "MESH_EMITTER", "DEPTH_COLLISION"]
    ),
    shader!("particles/expand.wgsl", []),
    shader!("gbuffer/raster.wgsl", ["TWO_SIDED"]),
    shader!("gbuffer/published_depth.wgsl", ["COMPUTE_RASTER"]),
    shader!(
        "gbuffer/resolve.wgsl",
        [
            "COMPUTE_RASTER",
            "MOTION",
            "TEXCOORDS",
            "NORMAL_MAP",
            "TRIPLANAR",
            "VELOCITY_FROM_GEOMETRY",
            "COLOR_MAP",
            "SURFACE_OUT",
            "MATERIAL_MAPS",
            "CUSTOM_SURFACE",
            "VERTEX_EXTRAS"
        ],
        // The colour map is the surface pass's; it reads UVs.
        Rule::AtMostOne(&["COLOR_MAP", "MOTION"]),
        Rule::AtMostOne(&["TEXCOORDS", "TRIPLANAR"]),
        // Surface maps are the surface pass's, and write the surface target.
        Rule::AtMostOne(&["SURFACE_OUT", "MOTION"]),
        Rule::Requires("MATERIAL_MAPS", "SURFACE_OUT"),
        // A shader node material writes the surface target and binds group 1,
        // where surface maps would put the material world.
        Rule::Requires("CUSTOM_SURFACE", "SURFACE_OUT"),
        Rule::AtMostOne(&["CUSTOM_SURFACE", "MATERIAL_MAPS"]),
        // Vertex colours and the second UV set are the surface pass's.
        Rule::AtMostOne(&["VERTEX_EXTRAS", "MOTION"])
    ),
    shader!("lighting/clusters.wgsl", []),
    shader!(
        "lighting/cook_torrance.wgsl",
        [
            "CLUSTERED",
            "ENERGY_COMPENSATION",
            "LIGHT_SPOT",
            "LIGHT_SUN",
            "MATERIALS",
            "FAKE_SSS",
            "SPOT_TEXTURE",
            "MATERIAL_TEXTURES",
            "SHADOWS",
            "SHADOW_PCF",
            "SHADOW_PCSS",
            "SHADOW_VSM",
            "SURFACE_TARGET"
        ],
        Rule::AtMostOne(&["LIGHT_SPOT", "LIGHT_SUN"]),
        // SHADOWS alone samples raw; the others choose a filter.
        Rule::AtMostOne(&["SHADOW_PCF", "SHADOW_PCSS", "SHADOW_VSM"]),
        Rule::Requires("SHADOW_PCF", "SHADOWS"),
        Rule::Requires("SHADOW_PCSS", "SHADOWS"),
        Rule::Requires("SHADOW_VSM", "SHADOWS"),
        Rule::Requires("FAKE_SSS", "MATERIALS"),
        // Suns have no range to cluster by.
        Rule::AtMostOne(&["LIGHT_SUN", "CLUSTERED"]),
        Rule::Requires("SPOT_TEXTURE", "LIGHT_SPOT"),
        Rule::Requires("MATERIAL_TEXTURES", "MATERIALS")
    ),
    shader!(
        "lighting/composite.wgsl",
        [
            "LIGHTS_2",
            "LIGHTS_3",
            "LIGHTS_4",
            "EMISSION",
            "SSS_1",
            "SSS_2",
            "SSS_3",
            "SSS_4",
            "AO",
            "AO_PER_MATERIAL",
            "MATERIAL_TEXTURES",
            "MATERIALS",
            "GI",
            "REFLECTION",
            "MATCAP",
            "MATCAP_TEXTURE",
            "SURFACE_TARGET"
        ],
        // Light pairs are cumulative, a subsurface term comes with its pair,
        // and per-material AO weights only AO.
        Rule::Requires("LIGHTS_3", "LIGHTS_2"),
        Rule::Requires("LIGHTS_4", "LIGHTS_3"),
        Rule::Requires("SSS_2", "LIGHTS_2"),
        Rule::Requires("SSS_3", "LIGHTS_3"),
        Rule::Requires("SSS_4", "LIGHTS_4"),
        Rule::Requires("AO_PER_MATERIAL", "AO"),
        // Textured emission (surface maps' occlusion and emission come
        // through SURFACE_TARGET, with or without materials).
        Rule::Requires("MATERIAL_TEXTURES", "EMISSION"),
        Rule::Requires("MATERIAL_TEXTURES", "MATERIALS"),
        // What reads the material library binds it.
        Rule::Requires("EMISSION", "MATERIALS"),
        Rule::Requires("AO_PER_MATERIAL", "MATERIALS"),
        Rule::Requires("REFLECTION", "MATERIALS"),
        Rule::Requires("MATCAP", "MATERIALS"),
        Rule::Requires("MATCAP_TEXTURE", "MATCAP")
    ),
    shader!(
        "lighting/ssgi.wgsl",
        ["TEMPORAL", "BLUR", "AMBIENT", "HALF"],
        Rule::AtMostOne(&["TEMPORAL", "BLUR"]),
        Rule::Requires("AMBIENT", "BLUR"),
        // Only the gather runs at half resolution.
        Rule::AtMostOne(&["HALF", "TEMPORAL"]),
        Rule::AtMostOne(&["HALF", "BLUR"])
    ),
    shader!("lighting/ssss.wgsl", ["VERTICAL"]),
    shader!("shadows/depth.wgsl", []),
    shader!("shadows/moments.wgsl", []),
    shader!("shadows/resolve.wgsl", []),
    shader!("occlusion/linear_depth.wgsl", ["DOWNSAMPLE"]),
    shader!(
        "occlusion/ao.wgsl",
        ["SAO", "HBAO", "HALF"],
        Rule::AtMostOne(&["SAO", "HBAO"])
    ),
    shader!("occlusion/temporal.wgsl", []),
    shader!(
        "occlusion/blur.wgsl",
        ["VERTICAL", "COMBINE"],
        Rule::Requires("COMBINE", "VERTICAL")
    ),
    shader!("environment/sky.wgsl", ["ENVIRONMENT"]),
    shader!("environment/prefilter.wgsl", []),
    shader!(
        "environment/reflection.wgsl",
        ["MATERIAL_TEXTURES", "SURFACE_TARGET"]
    ),
    shader!(
        "environment/ssr.wgsl",
        ["MATERIAL_TEXTURES", "HALF", "SURFACE_TARGET"]
    ),
    shader!("environment/fog.wgsl", []),
    shader!("post/tonemap.wgsl", ["EYE_ADAPTATION"]),
    shader!("post/eye_adaptation.wgsl", []),
    shader!("post/fxaa.wgsl", []),
    shader!("post/copy.wgsl", []),
    shader!("post/dof.wgsl", ["AUTOFOCUS", "BOKEH", "HALF"]),
    shader!("post/autofocus.wgsl", []),
    shader!("post/motion_blur.wgsl", []),
    shader!("post/glare.wgsl", []),
    shader!("post/transparency.wgsl", ["MATERIAL_MAPS", "VERTEX_EXTRAS"]),
    shader!(
        "post/taa.wgsl",
        ["VARIANCE_CLIP", "CATMULL_ROM"],
        Rule::Requires("CATMULL_ROM", "VARIANCE_CLIP")
    ),
    // The shader-node example blur, run as a built-in pass (the baseline its node is benchmarked against).
    shader!("nodes/blur.wgsl", []),
    shader!(
        "resolution/upsample.wgsl",
        ["R32", "DETAIL"],
        Rule::AtMostOne(&["R32", "DETAIL"])
    ),
    shader!("gbuffer/view.wgsl", one_of ["ALBEDO", "NORMALS", "VELOCITY", "UV", "DEPTH", "MATERIAL_ID", "OBJECT_ID"]),
];

/// Which permutation of which shader: its path and the set of switched-on features.
#[derive(Clone, Debug, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub struct ShaderKey {
    pub path: &'static str,
    pub features: BTreeSet<&'static str>,
}

impl ShaderKey {
    pub fn new(path: &'static str, features: impl IntoIterator<Item = &'static str>) -> Self {
        ShaderKey {
            path,
            features: features.into_iter().collect(),
        }
    }

    fn describe_defs(&self) -> String {
        if self.features.is_empty() {
            String::new()
        } else {
            format!(
                " [{}]",
                self.features.iter().copied().collect::<Vec<_>>().join(", ")
            )
        }
    }
}

/// Composes shader permutations into validated naga modules. No GPU needed,
/// so tests can validate every permutation anywhere.
pub struct ShaderComposer {
    composer: Composer,
    sources: HashMap<&'static str, Cow<'static, str>>,
    /// Over the embedded sources, with no library replaced: what it composes
    /// is the same in every composer of the process (see [`embedded_modules`]).
    embedded: bool,
    /// A library is replaced ([`ShaderComposer::replace_library`]).
    replaced: bool,
}

/// Permutations of the embedded sources composed so far in this process.
/// Composing (naga_oil's preprocessing, naga's parse and validation) is
/// most of what opening a renderer costs the CPU, and every renderer of a
/// process (each test, each CLI run's renderers) composes the same
/// permutations from the same compiled-in text: they are made once.
fn embedded_modules() -> &'static std::sync::Mutex<HashMap<ShaderKey, naga::Module>> {
    static MODULES: std::sync::OnceLock<std::sync::Mutex<HashMap<ShaderKey, naga::Module>>> =
        std::sync::OnceLock::new();
    MODULES.get_or_init(Default::default)
}

impl ShaderComposer {
    /// A composer over the embedded sources.
    pub fn new() -> Result<Self, RenderError> {
        let sources = SHADERS
            .iter()
            .map(|s| (s.path, Cow::Borrowed(s.source)))
            .collect();
        let mut composer = Self::with_sources(sources)?;
        composer.embedded = true;
        Ok(composer)
    }

    /// A composer over the sources in a `shaders/` folder on disk (for live
    /// editing); files missing there fall back to the embedded ones.
    pub fn from_dir(dir: &Path) -> Result<Self, RenderError> {
        let mut sources = HashMap::new();
        for file in SHADERS {
            let text = std::fs::read_to_string(dir.join(file.path))
                .map(Cow::Owned)
                .unwrap_or(Cow::Borrowed(file.source));
            sources.insert(file.path, text);
        }
        Self::with_sources(sources)
    }

    fn with_sources(
        sources: HashMap<&'static str, Cow<'static, str>>,
    ) -> Result<Self, RenderError> {
        // Validate with what the compute rasterizer needs; devices without it never compile that shader.
        let mut composer = Composer::default().with_capabilities(
            naga::valid::Capabilities::SHADER_INT64
                | naga::valid::Capabilities::SHADER_INT64_ATOMIC_MIN_MAX,
        );
        for file in SHADERS.iter().filter(|f| f.library) {
            let source = &sources[file.path];
            let result = composer
                .add_composable_module(ComposableModuleDescriptor {
                    source,
                    file_path: file.path,
                    language: ShaderLanguage::Wgsl,
                    ..Default::default()
                })
                .map(|_| ())
                .map_err(|e| e.emit_to_string(&composer));
            result.map_err(|message| RenderError::Shader {
                shader: file.path.to_owned(),
                defs: String::new(),
                message,
            })?;
        }
        Ok(ShaderComposer {
            composer,
            sources,
            embedded: false,
            replaced: false,
        })
    }

    /// Compose and validate one permutation.
    pub fn compose(&mut self, key: &ShaderKey) -> Result<naga::Module, RenderError> {
        let file =
            SHADERS
                .iter()
                .find(|f| f.path == key.path)
                .ok_or_else(|| RenderError::Shader {
                    shader: key.path.to_owned(),
                    defs: String::new(),
                    message: "no such shader".to_owned(),
                })?;
        if let Err(message) = file.check(&key.features) {
            return Err(RenderError::Shader {
                shader: key.path.to_owned(),
                defs: key.describe_defs(),
                message,
            });
        }
        if let Some(unknown) = key.features.iter().find(|f| !file.features.contains(f)) {
            return Err(RenderError::Shader {
                shader: key.path.to_owned(),
                defs: key.describe_defs(),
                message: format!(
                    "`{unknown}` is not a feature of this shader (features: {})",
                    file.features.join(", ")
                ),
            });
        }
        let shared = self.embedded && !self.replaced;
        if shared
            && let Some(module) = embedded_modules()
                .lock()
                .unwrap_or_else(|e| e.into_inner())
                .get(key)
        {
            return Ok(module.clone());
        }
        let shader_defs = key
            .features
            .iter()
            .map(|f| ((*f).to_owned(), ShaderDefValue::Bool(true)))
            .collect();
        let result = self.composer.make_naga_module(NagaModuleDescriptor {
            source: &self.sources[key.path],
            file_path: key.path,
            shader_type: ShaderType::Wgsl,
            shader_defs,
            additional_imports: &[],
        });
        let module = result.map_err(|e| RenderError::Shader {
            shader: key.path.to_owned(),
            defs: key.describe_defs(),
            message: e.emit_to_string(&self.composer),
        })?;
        if shared {
            embedded_modules()
                .lock()
                .unwrap_or_else(|e| e.into_inner())
                .insert(key.clone(), module.clone());
        }
        Ok(module)
    }
}

impl ShaderComposer {
    /// Compose a WGSL file that is not one of [`SHADERS`] (a shader node's)
    /// as a top-level module: it may `#import` every library. Its own
    /// `#ifdef`s must already be resolved. The error is naga_oil's, for the
    /// caller to place in the file ([`ShaderComposer::composer`] undecorates it).
    pub fn compose_external(
        &mut self,
        file_path: &str,
        source: &str,
    ) -> Result<naga::Module, Box<naga_oil::compose::ComposerError>> {
        self.composer
            .make_naga_module(NagaModuleDescriptor {
                source,
                file_path,
                shader_type: ShaderType::Wgsl,
                ..Default::default()
            })
            .map_err(Box::new)
    }

    /// The naga_oil composer (to format and undecorate its errors).
    pub fn composer(&self) -> &Composer {
        &self.composer
    }

    /// Put `source` (a shader node material's file, named `file_path`) in
    /// the place of library `module` (an import path such as
    /// `spreadlight::custom_surface`) until [`ShaderComposer::restore_library`].
    pub fn replace_library(
        &mut self,
        module: &str,
        file_path: &str,
        source: &str,
    ) -> Result<(), Box<naga_oil::compose::ComposerError>> {
        // Even a failed replacement may leave the library half-replaced.
        self.replaced = true;
        self.composer
            .add_composable_module(ComposableModuleDescriptor {
                source,
                file_path,
                language: ShaderLanguage::Wgsl,
                as_name: Some(module.to_owned()),
                ..Default::default()
            })
            .map(|_| ())
            .map_err(Box::new)
    }

    /// Put library `module` back as [`SHADERS`] has it.
    pub fn restore_library(&mut self, module: &str) -> Result<(), RenderError> {
        let library = SHADERS
            .iter()
            .find(|f| f.library && f.source.contains(&format!("#define_import_path {module}")))
            .ok_or_else(|| RenderError::Shader {
                shader: module.to_owned(),
                defs: String::new(),
                message: "no such library".to_owned(),
            })?;
        let restored = self
            .composer
            .add_composable_module(ComposableModuleDescriptor {
                source: &self.sources[library.path],
                file_path: library.path,
                language: ShaderLanguage::Wgsl,
                ..Default::default()
            })
            .map(|_| ())
            .map_err(|e| e.emit_to_string(&self.composer));
        restored.map_err(|message| RenderError::Shader {
            shader: library.path.to_owned(),
            defs: String::new(),
            message,
        })?;
        self.replaced = false;
        Ok(())
    }

    /// Compose permutation `key` with library `module` replaced, for this
    /// composition only, by a shader node material's `source`.
    pub fn compose_with_module(
        &mut self,
        key: &ShaderKey,
        module: &str,
        file_path: &str,
        source: &str,
    ) -> Result<naga::Module, RenderError> {
        let replaced = self
            .replace_library(module, file_path, source)
            .map_err(|e| e.emit_to_string(&self.composer));
        let composed = match replaced {
            Ok(()) => self.compose(key),
            Err(message) => Err(RenderError::Shader {
                shader: file_path.to_owned(),
                defs: String::new(),
                message,
            }),
        };
        // Put the library back, so built-in permutations compose as before.
        self.restore_library(module)?;
        composed
    }
}

/// A shader node material's file, composed into a permutation in place of a library.
#[derive(Clone, Copy, Debug)]
pub struct Splice<'a> {
    /// Changes with the source (pipelines are cached under it).
    pub key: u64,
    /// The library it replaces, e.g. `spreadlight::custom_surface`.
    pub module: &'a str,
    pub file_path: &'a str,
    /// Its text, `#ifdef`s resolved.
    pub source: &'a str,
}

/// The (group, binding)s entry point `entry` of `module` uses (naga's reflection).
fn used_bindings_of(module: &naga::Module, entry: &str) -> Result<Vec<(u32, u32)>, String> {
    let info = naga::valid::Validator::new(
        naga::valid::ValidationFlags::all(),
        naga::valid::Capabilities::all(),
    )
    .validate(module)
    .map_err(|e| e.to_string())?;
    let index = module
        .entry_points
        .iter()
        .position(|e| e.name == entry)
        .ok_or_else(|| format!("no entry point `{entry}`"))?;
    let function = info.get_entry_point(index);
    Ok(module
        .global_variables
        .iter()
        .filter(|(handle, _)| !function[*handle].is_empty())
        .filter_map(|(_, var)| var.binding.as_ref().map(|b| (b.group, b.binding)))
        .collect())
}

/// Every permutation the shader set allows: each entry shader with every
/// subset of its features that keeps its rules.
pub fn all_permutations() -> Vec<ShaderKey> {
    let mut keys = Vec::new();
    for file in SHADERS.iter().filter(|f| !f.library) {
        let n = file.features.len();
        for mask in 0u32..(1 << n) {
            let features = (0..n)
                .filter(|i| mask & (1 << i) != 0)
                .map(|i| file.features[i]);
            let key = ShaderKey::new(file.path, features);
            if file.check(&key.features).is_ok() {
                keys.push(key);
            }
        }
    }
    keys
}

/// A compute pipeline of `entry` in `module`, its bind group layouts derived from the shader.
fn compute_pipeline_of(
    device: &wgpu::Device,
    module: &wgpu::ShaderModule,
    label: &str,
    entry: &str,
) -> wgpu::ComputePipeline {
    device.create_compute_pipeline(&wgpu::ComputePipelineDescriptor {
        label: Some(label),
        layout: None,
        module,
        entry_point: Some(entry),
        compilation_options: Default::default(),
        cache: None,
    })
}

/// How a pass samples a texture.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum Sampling {
    /// Bilinear, tiling past 0..1 (surface textures mapped by UV).
    LinearRepeat,
    /// Bilinear, held at the edges (projected textures).
    LinearClamp,
}

/// Compiled shader modules and pipelines, keyed by permutation. Counts what it
/// compiles, so the frame statistics show when a frame had to compile.
pub struct ShaderCache {
    composer: ShaderComposer,
    modules: HashMap<ShaderKey, wgpu::ShaderModule>,
    /// Per permutation and entry point: the (group, binding)s it uses.
    used: HashMap<(ShaderKey, String), Vec<(u32, u32)>>,
    compute: HashMap<(ShaderKey, &'static str), wgpu::ComputePipeline>,
    render: HashMap<(ShaderKey, String), wgpu::RenderPipeline>,
    samplers: HashMap<Sampling, wgpu::Sampler>,
    /// Pipelines of shaders not in [`SHADERS`] (shader node files), by the caller's key and entry.
    external: HashMap<(u64, String), wgpu::ComputePipeline>,
    /// Resolve permutations composed with a shader node material, by its source key.
    surfaces: HashMap<(ShaderKey, u64), SplicedPipeline>,
    /// Bind groups by pipeline, group and what they bind (by identity), with
    /// the frame they were last used in: a pass that binds what it bound
    /// last frame reuses its group instead of making one.
    bind_groups: HashMap<BindGroupKey, (wgpu::BindGroup, u64)>,
    frame: u64,
    /// Pipelines compiled since the cache was made.
    pub pipelines_compiled: u64,
    /// Bind groups made and reused since the cache was made.
    pub bind_groups_created: u64,
    pub bind_groups_reused: u64,
}

/// A pipeline composed with a shader node material, and the (group, binding)s it uses.
type SplicedPipeline = (wgpu::ComputePipeline, Vec<(u32, u32)>);

/// A resource a bind group binds, by identity (wgpu handles compare by the object).
#[derive(Clone, PartialEq, Eq, Hash)]
enum Bound {
    Buffer(wgpu::Buffer, u64, Option<wgpu::BufferSize>),
    View(wgpu::TextureView),
    Sampler(wgpu::Sampler),
}

impl Bound {
    /// None for resources the cache does not key (arrays of them).
    fn of(resource: &wgpu::BindingResource<'_>) -> Option<Bound> {
        match resource {
            wgpu::BindingResource::Buffer(b) => {
                Some(Bound::Buffer(b.buffer.clone(), b.offset, b.size))
            }
            wgpu::BindingResource::TextureView(v) => Some(Bound::View((*v).clone())),
            wgpu::BindingResource::Sampler(s) => Some(Bound::Sampler((*s).clone())),
            _ => None,
        }
    }
}

type BindGroupKey = (wgpu::ComputePipeline, u32, Vec<(u32, Bound)>);

/// Frames a cached bind group may go unused before it is dropped (with the
/// buffers and views it keeps alive): recipes re-made each frame make new
/// buffers, whose groups are never hit again.
const BIND_GROUP_IDLE_FRAMES: u64 = 2;

impl ShaderCache {
    pub fn new(composer: ShaderComposer) -> Self {
        ShaderCache {
            composer,
            modules: HashMap::new(),
            used: HashMap::new(),
            compute: HashMap::new(),
            render: HashMap::new(),
            samplers: HashMap::new(),
            external: HashMap::new(),
            surfaces: HashMap::new(),
            bind_groups: HashMap::new(),
            frame: 0,
            pipelines_compiled: 0,
            bind_groups_created: 0,
            bind_groups_reused: 0,
        }
    }

    /// A new frame begins: bind groups unused for a while are dropped.
    pub(crate) fn begin_frame(&mut self) {
        self.frame += 1;
        let frame = self.frame;
        self.bind_groups
            .retain(|_, (_, last)| frame - *last <= BIND_GROUP_IDLE_FRAMES);
    }

    /// Swap in new sources (live shader editing); everything compiled is dropped.
    pub fn replace_sources(&mut self, composer: ShaderComposer) {
        *self = ShaderCache {
            pipelines_compiled: self.pipelines_compiled,
            ..ShaderCache::new(composer)
        };
    }

    pub fn module(
        &mut self,
        device: &wgpu::Device,
        key: &ShaderKey,
    ) -> Result<wgpu::ShaderModule, RenderError> {
        if let Some(m) = self.modules.get(key) {
            return Ok(m.clone());
        }
        let module = self.composer.compose(key)?;
        let label = format!("{}{}", key.path, key.describe_defs());
        let m = device.create_shader_module(wgpu::ShaderModuleDescriptor {
            label: Some(&label),
            source: wgpu::ShaderSource::Naga(Cow::Owned(module)),
        });
        self.modules.insert(key.clone(), m.clone());
        Ok(m)
    }

    /// The bindings `entry` of a permutation uses (naga's reflection): a
    /// derived bind group layout has exactly these, so a bind group must too.
    pub fn used_bindings(
        &mut self,
        key: &ShaderKey,
        entry: &str,
    ) -> Result<Vec<(u32, u32)>, RenderError> {
        let cache_key = (key.clone(), entry.to_owned());
        if let Some(used) = self.used.get(&cache_key) {
            return Ok(used.clone());
        }
        let module = self.composer.compose(key)?;
        let used = used_bindings_of(&module, entry).map_err(|message| RenderError::Shader {
            shader: key.path.to_owned(),
            defs: key.describe_defs(),
            message,
        })?;
        self.used.insert(cache_key, used.clone());
        Ok(used)
    }

    /// A bind group for group `group` of a compute pipeline made from
    /// `key`/`entry`, given every resource a caller might bind: those the
    /// permutation compiled out are left out.
    pub fn bind_group(
        &mut self,
        device: &wgpu::Device,
        key: &ShaderKey,
        entry: &str,
        pipeline: &wgpu::ComputePipeline,
        group: u32,
        resources: &[(u32, wgpu::BindingResource<'_>)],
    ) -> Result<wgpu::BindGroup, RenderError> {
        let used = self.used_bindings(key, entry)?;
        let entries: Vec<wgpu::BindGroupEntry<'_>> = resources
            .iter()
            .filter(|(binding, _)| used.contains(&(group, *binding)))
            .map(|(binding, resource)| wgpu::BindGroupEntry {
                binding: *binding,
                resource: resource.clone(),
            })
            .collect();
        let bound: Option<Vec<(u32, Bound)>> = entries
            .iter()
            .map(|e| Bound::of(&e.resource).map(|b| (e.binding, b)))
            .collect();
        let cache_key = bound.map(|b| (pipeline.clone(), group, b));
        if let Some(k) = &cache_key
            && let Some((cached, last)) = self.bind_groups.get_mut(k)
        {
            *last = self.frame;
            self.bind_groups_reused += 1;
            return Ok(cached.clone());
        }
        let made = device.create_bind_group(&wgpu::BindGroupDescriptor {
            label: Some(key.path),
            layout: &pipeline.get_bind_group_layout(group),
            entries: &entries,
        });
        self.bind_groups_created += 1;
        if let Some(k) = cache_key {
            self.bind_groups.insert(k, (made.clone(), self.frame));
        }
        Ok(made)
    }

    /// A sampler, made once per device rather than once per pass or frame.
    pub fn sampler(&mut self, device: &wgpu::Device, sampling: Sampling) -> wgpu::Sampler {
        self.samplers
            .entry(sampling)
            .or_insert_with(|| {
                let address = match sampling {
                    Sampling::LinearRepeat => wgpu::AddressMode::Repeat,
                    Sampling::LinearClamp => wgpu::AddressMode::ClampToEdge,
                };
                device.create_sampler(&wgpu::SamplerDescriptor {
                    label: Some(match sampling {
                        Sampling::LinearRepeat => "linear repeat",
                        Sampling::LinearClamp => "linear clamp",
                    }),
                    address_mode_u: address,
                    address_mode_v: address,
                    mag_filter: wgpu::FilterMode::Linear,
                    min_filter: wgpu::FilterMode::Linear,
                    ..Default::default()
                })
            })
            .clone()
    }

    /// The permutations compiled so far (tests check a feature no scene uses never is).
    pub fn compiled_keys(&self) -> impl Iterator<Item = &ShaderKey> {
        self.modules.keys()
    }

    /// The compute pipeline of `entry` in a permutation (bind group layouts derived from the shader).
    pub fn compute_pipeline(
        &mut self,
        device: &wgpu::Device,
        key: &ShaderKey,
        entry: &'static str,
    ) -> Result<wgpu::ComputePipeline, RenderError> {
        if let Some(p) = self.compute.get(&(key.clone(), entry)) {
            return Ok(p.clone());
        }
        let module = self.module(device, key)?;
        let label = format!("{}{}::{entry}", key.path, key.describe_defs());
        let pipeline = compute_pipeline_of(device, &module, &label, entry);
        self.pipelines_compiled += 1;
        self.compute.insert((key.clone(), entry), pipeline.clone());
        Ok(pipeline)
    }

    /// The compute pipeline of `entry` in a module validated elsewhere (a
    /// shader node file), cached under `key`, which must change with the
    /// source: `module` is called only the first time.
    pub fn external_compute_pipeline(
        &mut self,
        device: &wgpu::Device,
        key: u64,
        label: &str,
        module: impl FnOnce() -> naga::Module,
        entry: &str,
    ) -> wgpu::ComputePipeline {
        let cache_key = (key, entry.to_owned());
        if let Some(p) = self.external.get(&cache_key) {
            return p.clone();
        }
        let module = device.create_shader_module(wgpu::ShaderModuleDescriptor {
            label: Some(label),
            source: wgpu::ShaderSource::Naga(Cow::Owned(module())),
        });
        let pipeline = compute_pipeline_of(device, &module, &format!("{label}::{entry}"), entry);
        self.pipelines_compiled += 1;
        self.external.insert(cache_key, pipeline.clone());
        pipeline
    }

    /// The compute pipeline of `entry` in permutation `key` composed with
    /// library `module` replaced by a shader node material's `source`
    /// (identified by `source_key`, which must change with it), and the
    /// (group, binding)s the entry point uses, to build its bind groups by.
    pub fn surface_pipeline(
        &mut self,
        device: &wgpu::Device,
        key: &ShaderKey,
        splice: &Splice<'_>,
        entry: &str,
    ) -> Result<SplicedPipeline, RenderError> {
        let Splice {
            key: source_key,
            module,
            file_path,
            source,
        } = *splice;
        let cache_key = (key.clone(), source_key);
        if let Some(found) = self.surfaces.get(&cache_key) {
            return Ok(found.clone());
        }
        let composed = self
            .composer
            .compose_with_module(key, module, file_path, source)?;
        let used = used_bindings_of(&composed, entry).map_err(|message| RenderError::Shader {
            shader: file_path.to_owned(),
            defs: key.describe_defs(),
            message,
        })?;
        let label = format!("{}{} + {file_path}", key.path, key.describe_defs());
        let shader = device.create_shader_module(wgpu::ShaderModuleDescriptor {
            label: Some(&label),
            source: wgpu::ShaderSource::Naga(Cow::Owned(composed)),
        });
        let pipeline = compute_pipeline_of(device, &shader, &format!("{label}::{entry}"), entry);
        self.pipelines_compiled += 1;
        self.surfaces
            .insert(cache_key, (pipeline.clone(), used.clone()));
        Ok((pipeline, used))
    }

    /// A render pipeline for a permutation; `variant` names what else the
    /// caller's descriptor depends on (target formats, blend), and `build` makes it.
    pub fn render_pipeline(
        &mut self,
        device: &wgpu::Device,
        key: &ShaderKey,
        variant: &str,
        build: impl FnOnce(&wgpu::ShaderModule) -> wgpu::RenderPipeline,
    ) -> Result<wgpu::RenderPipeline, RenderError> {
        let cache_key = (key.clone(), variant.to_owned());
        if let Some(p) = self.render.get(&cache_key) {
            return Ok(p.clone());
        }
        let module = self.module(device, key)?;
        let pipeline = build(&module);
        self.pipelines_compiled += 1;
        self.render.insert(cache_key, pipeline.clone());
        Ok(pipeline)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn every_permutation_composes_and_validates() {
        let keys = all_permutations();
        assert!(keys.len() >= 32, "resolve alone has 2^5 permutations");
        // Hundreds of permutations: a composer per thread, a share of the keys each.
        let threads = std::thread::available_parallelism().map_or(2, |n| n.get());
        let chunk = keys.len().div_ceil(threads);
        let failures: Vec<String> = std::thread::scope(|scope| {
            let workers: Vec<_> = keys
                .chunks(chunk)
                .map(|share| {
                    scope.spawn(move || {
                        let mut composer = ShaderComposer::new().expect("libraries compose");
                        share
                            .iter()
                            .filter_map(|k| composer.compose(k).err().map(|e| e.to_string()))
                            .collect::<Vec<_>>()
                    })
                })
                .collect();
            workers
                .into_iter()
                .flat_map(|w| w.join().expect("no panic"))
                .collect()
        });
        assert!(failures.is_empty(), "{}", failures.join("\n\n"));
    }

    #[test]
    fn shaders_reload_from_disk_and_report_errors_with_the_file() {
        let dir = tempfile::tempdir().expect("tempdir");
        // A folder with one edited shader: the rest fall back to the embedded sources.
        std::fs::create_dir_all(dir.path().join("gbuffer")).expect("mkdir");
        std::fs::write(dir.path().join("gbuffer/view.wgsl"), "fn broken( {").expect("write");
        let mut composer = ShaderComposer::from_dir(dir.path()).expect("libraries still compose");
        assert!(
            composer
                .compose(&ShaderKey::new("gbuffer/visibility.wgsl", []))
                .is_ok()
        );
        let err = composer
            .compose(&ShaderKey::new("gbuffer/view.wgsl", []))
            .expect_err("broken");
        assert!(
            err.to_string().starts_with("shader `gbuffer/view.wgsl`"),
            "{err}"
        );
    }

    #[test]
    fn an_exclusive_choice_takes_one_feature() {
        let mut composer = ShaderComposer::new().expect("libraries compose");
        let err = composer
            .compose(&ShaderKey::new("gbuffer/view.wgsl", ["DEPTH", "UV"]))
            .expect_err("refused");
        assert!(err.to_string().contains("set at most one"), "{err}");
    }

    #[test]
    fn a_feature_without_what_it_needs_is_refused_and_never_enumerated() {
        let mut composer = ShaderComposer::new().expect("libraries compose");
        let err = composer
            .compose(&ShaderKey::new("lighting/composite.wgsl", ["LIGHTS_3"]))
            .expect_err("refused");
        assert!(
            err.to_string().contains("`LIGHTS_3` needs `LIGHTS_2`"),
            "{err}"
        );
        let composite: Vec<_> = all_permutations()
            .into_iter()
            .filter(|k| k.path == "lighting/composite.wgsl")
            .collect();
        // Light pairs with the SSS terms they allow (2 + 4 + 8 + 16), times
        // GI (2), times the surface target (2), times the 56 ways of AO
        // (none, AO, per material), emission (none, plain, textured),
        // reflection (2), matcap (none, built-in, textured) and the material
        // library (forced on when one of them reads it, free otherwise:
        // 52 + 2 x 2): 6,720 of the 2^17 subsets.
        assert_eq!(composite.len(), 30 * 2 * 2 * 56);
    }

    #[test]
    fn an_unknown_feature_is_refused_by_name() {
        let mut composer = ShaderComposer::new().expect("libraries compose");
        let err = composer
            .compose(&ShaderKey::new("gbuffer/resolve.wgsl", ["SPARKLES"]))
            .expect_err("refused");
        assert!(
            err.to_string().contains("`SPARKLES` is not a feature"),
            "{err}"
        );
    }
}
