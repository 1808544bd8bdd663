//! Shaders: the WGSL sources (embedded in the binary), their feature
//! switches, and the permutation cache, which is the only place that compiles
//! shaders and pipelines.
//!
//! Feature switches work like Emeshe's `#define` switches: a shader marks
//! optional code with `#ifdef FEATURE` (naga_oil's preprocessor), a pass asks
//! for a set of features, and the cache composes, validates and compiles that
//! permutation once. A combination no pass asks for is never compiled.
//! Shared libraries are imported by name (`#import spreadlight::packing`).

use std::collections::{BTreeSet, HashMap, HashSet};
use std::sync::OnceLock;

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
    /// For a shader with a typed key ([`Permutation`]): its permutations,
    /// which replace the rules (every other subset is refused).
    pub keyed: Option<fn() -> Vec<ShaderKey>>,
}

/// A shader's permutations as a Rust type, beside the effect that runs it
/// (SSAO's `AoKey` in `ssao/key.rs`): each value is one permutation, and a
/// combination the shader does not support cannot be written, so the
/// effect's code says `AoKey { estimator, target }`, not a list of strings.
pub trait Permutation: Copy + 'static {
    /// The shader, below `shaders/`.
    const PATH: &'static str;
    /// Every feature switch the shader reacts to.
    const FEATURES: &'static [&'static str];
    /// The switches this permutation turns on.
    fn features(self) -> impl Iterator<Item = &'static str>;
    /// Every permutation the shader supports.
    fn all() -> Vec<Self>;

    fn key(self) -> ShaderKey {
        ShaderKey::new(Self::PATH, self.features())
    }

    /// The keys of [`Permutation::all`], for `SHADERS`.
    fn all_keys() -> Vec<ShaderKey> {
        Self::all().into_iter().map(Self::key).collect()
    }
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
    /// Whether `features` is a permutation this file allows (every rule
    /// holds; for a keyed file, one of its typed key's values).
    pub fn check(&self, features: &BTreeSet<&'static str>) -> Result<(), String> {
        if self.keyed.is_some() {
            return match keyed_features(self.path).is_some_and(|set| set.contains(features)) {
                true => Ok(()),
                false => Err(format!(
                    "no value of its typed key switches on exactly {}",
                    features.iter().copied().collect::<Vec<_>>().join(", ")
                )),
            };
        }
        self.rules.iter().try_for_each(|r| r.check(features))
    }
}

macro_rules! shader {
    ($path:literal, library) => {
        ShaderFile {
            path: $path,
            source: include_str!(concat!("../../../../shaders/", $path)),
            features: &[],
            library: true,
            rules: &[],
            keyed: None,
        }
    };
    ($path:literal, keyed $key:ty) => {
        ShaderFile {
            path: $path,
            source: include_str!(concat!("../../../../shaders/", $path)),
            features: <$key as Permutation>::FEATURES,
            library: false,
            rules: &[],
            keyed: Some(<$key as Permutation>::all_keys),
        }
    };
    ($path:literal, [$($feature:literal),*] $(, $rule:expr)*) => {
        ShaderFile {
            path: $path,
            source: include_str!(concat!("../../../../shaders/", $path)),
            features: &[$($feature),*],
            library: false,
            rules: &[$($rule),*],
            keyed: None,
        }
    };
    ($path:literal, one_of [$($feature:literal),*]) => {
        ShaderFile {
            path: $path,
            source: include_str!(concat!("../../../../shaders/", $path)),
            features: &[$($feature),*],
            library: false,
            rules: &[Rule::AtMostOne(&[$($feature),*])],
            keyed: None,
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
    shader!("lib/spot.wgsl", library),
    shader!("lib/tonemap.wgsl", library),
    shader!("lib/surface_target.wgsl", library),
    shader!("lib/material.wgsl", library),
    shader!("lib/materials.wgsl", library),
    shader!("lib/material_maps.wgsl", library),
    shader!("lib/matcap.wgsl", library),
    shader!("lib/screen.wgsl", library),
    shader!("lib/ao_history.wgsl", library),
    shader!("lib/sky.wgsl", library),
    shader!("lib/fog.wgsl", library),
    shader!("lib/ibl.wgsl", library),
    shader!("lib/post.wgsl", library),
    shader!("lighting/shadow_sampling.wgsl", library),
    shader!("lib/surface.wgsl", library),
    shader!("lib/custom_surface.wgsl", library),
    shader!("lib/light_shader.wgsl", library),
    shader!("lib/custom_light.wgsl", library),
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
    shader!(
        "gbuffer/raster.wgsl",
        ["TWO_SIDED", "MESHES_ONLY", "DEPTH_ONLY"]
    ),
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
            "VERTEX_EXTRAS",
            "VELOCITY_OUT"
        ],
        // The colour map is the surface pass's; it reads UVs.
        Rule::AtMostOne(&["COLOR_MAP", "MOTION"]),
        // The surface pass writing what the motion pass writes, too.
        Rule::AtMostOne(&["VELOCITY_OUT", "MOTION"]),
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
            "SURFACE_TARGET",
            "CLEARCOAT",
            "CUSTOM_LIGHT"
        ],
        Rule::AtMostOne(&["LIGHT_SPOT", "LIGHT_SUN"]),
        // A light shader node's function replaces the BRDF and its extras.
        Rule::AtMostOne(&["CUSTOM_LIGHT", "ENERGY_COMPENSATION"]),
        Rule::AtMostOne(&["CUSTOM_LIGHT", "FAKE_SSS"]),
        Rule::AtMostOne(&["CUSTOM_LIGHT", "CLEARCOAT"]),
        // SHADOWS alone samples raw; the others choose a filter.
        Rule::AtMostOne(&["SHADOW_PCF", "SHADOW_PCSS", "SHADOW_VSM"]),
        Rule::Requires("SHADOW_PCF", "SHADOWS"),
        Rule::Requires("SHADOW_PCSS", "SHADOWS"),
        Rule::Requires("SHADOW_VSM", "SHADOWS"),
        Rule::Requires("FAKE_SSS", "MATERIALS"),
        Rule::Requires("CLEARCOAT", "MATERIALS"),
        // Suns have no range to cluster by.
        Rule::AtMostOne(&["LIGHT_SUN", "CLUSTERED"]),
        Rule::Requires("SPOT_TEXTURE", "LIGHT_SPOT"),
        Rule::Requires("MATERIAL_TEXTURES", "MATERIALS")
    ),
    shader!("lighting/composite.wgsl", keyed crate::lighting::CompositeKey),
    shader!(
        "lighting/ssgi.wgsl",
        ["TEMPORAL", "GATHER", "BLUR", "AMBIENT", "HALF"],
        Rule::AtMostOne(&["TEMPORAL", "BLUR"]),
        Rule::Requires("AMBIENT", "BLUR"),
        // The gather fused into the temporal pass (full resolution only).
        Rule::Requires("GATHER", "TEMPORAL"),
        // Only the gather runs at half resolution.
        Rule::AtMostOne(&["HALF", "TEMPORAL"]),
        Rule::AtMostOne(&["HALF", "BLUR"])
    ),
    shader!("lighting/ssss.wgsl", ["VERTICAL", "SOURCES_2", "SOURCES_3"]),
    shader!("shadows/depth.wgsl", []),
    shader!("shadows/moments.wgsl", []),
    shader!("shadows/resolve.wgsl", ["OVER_STILL"]),
    shader!("ssao/linear_depth.wgsl", keyed crate::ssao::DepthKey),
    shader!("ssao/ao.wgsl", keyed crate::ssao::AoKey),
    shader!("ssao/temporal.wgsl", keyed crate::ssao::TemporalKey),
    shader!("ssao/blur.wgsl", keyed crate::ssao::BlurKey),
    shader!("environment/sky.wgsl", ["ENVIRONMENT", "FOG"]),
    shader!("environment/prefilter.wgsl", []),
    shader!(
        "environment/environment_probe.wgsl",
        ["COLOR_MAP", "TEXCOORDS", "TRIPLANAR"],
        // The Color Texture by the mesh's UVs or by three planar projections.
        Rule::AtMostOne(&["TEXCOORDS", "TRIPLANAR"]),
        Rule::Requires("TEXCOORDS", "COLOR_MAP"),
        Rule::Requires("TRIPLANAR", "COLOR_MAP")
    ),
    shader!(
        "environment/reflection.wgsl",
        ["MATERIAL_TEXTURES", "SURFACE_TARGET", "PARALLAX"]
    ),
    shader!(
        "environment/ssr.wgsl",
        ["MATERIAL_TEXTURES", "HALF", "SURFACE_TARGET", "TEMPORAL"],
        // The trace blends the history in its own pass at full resolution only.
        Rule::AtMostOne(&["HALF", "TEMPORAL"])
    ),
    shader!("environment/fog.wgsl", []),
    shader!("post/tonemap.wgsl", ["EYE_ADAPTATION"]),
    shader!("post/eye_adaptation.wgsl", []),
    shader!("post/fxaa.wgsl", []),
    shader!("post/copy.wgsl", []),
    shader!("bench/pass_chain.wgsl", []),
    shader!(
        "post/dof.wgsl",
        ["AUTOFOCUS", "BOKEH", "HALF", "INLINE_COC"],
        // At half resolution the upsample reads the CoC target: a pass makes it.
        Rule::AtMostOne(&["HALF", "INLINE_COC"])
    ),
    shader!("post/autofocus.wgsl", []),
    shader!("post/motion_blur.wgsl", []),
    shader!("post/glare.wgsl", ["FILTERED_SOURCE"]),
    shader!("post/transparency.wgsl", keyed crate::post::TransparencyKey),
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

/// The feature sets of each keyed file's typed key, made once: checking
/// is a look-up (the exhaustive test checks the composite's 6,720 keys).
fn keyed_features(path: &str) -> Option<&'static HashSet<BTreeSet<&'static str>>> {
    static SETS: OnceLock<HashMap<&'static str, HashSet<BTreeSet<&'static str>>>> = OnceLock::new();
    SETS.get_or_init(|| {
        SHADERS
            .iter()
            .filter_map(|f| Some((f.path, f.keyed?().into_iter().map(|k| k.features).collect())))
            .collect()
    })
    .get(path)
}

/// Every permutation the shader set allows: each entry shader with every
/// subset of its features that keeps its rules.
pub fn all_permutations() -> Vec<ShaderKey> {
    let mut keys = Vec::new();
    for file in SHADERS.iter().filter(|f| !f.library) {
        if let Some(keyed) = file.keyed {
            keys.extend(keyed());
            continue;
        }
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

mod cache;
mod composer;
pub mod layout;
mod reflection;

pub use cache::{CompileTimes, PipelineRef, Sampling, ShaderCache};
pub use composer::{ShaderComposer, Splice};
pub use reflection::{Reflection, ShaderVar};

#[cfg(test)]
mod tests;
