//! Shaders: the WGSL sources (embedded in the binary), their feature
//! switches, and the permutation cache, which is the only place that compiles
//! shaders and pipelines.
//!
//! Feature switches work like Emeshe's `#define` switches: a shader marks
//! optional code with `#ifdef FEATURE` (naga_oil's preprocessor), a pass asks
//! for a set of features, and the cache composes, validates and compiles that
//! permutation once. A combination no pass asks for is never compiled.
//! Shared libraries are imported by name (`#import spreadlight::packing`).

use std::collections::BTreeSet;

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
            source: include_str!(concat!("../../../../shaders/", $path)),
            features: &[],
            library: true,
            rules: &[],
        }
    };
    ($path:literal, [$($feature:literal),*] $(, $rule:expr)*) => {
        ShaderFile {
            path: $path,
            source: include_str!(concat!("../../../../shaders/", $path)),
            features: &[$($feature),*],
            library: false,
            rules: &[$($rule),*],
        }
    };
    ($path:literal, one_of [$($feature:literal),*]) => {
        ShaderFile {
            path: $path,
            source: include_str!(concat!("../../../../shaders/", $path)),
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
    shader!("lib/ao_history.wgsl", library),
    shader!("lib/sky.wgsl", library),
    shader!("lib/fog.wgsl", library),
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
    shader!("gbuffer/raster.wgsl", ["TWO_SIDED", "MESHES_ONLY"]),
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
    shader!("occlusion/linear_depth.wgsl", ["DOWNSAMPLE"]),
    shader!(
        "occlusion/ao.wgsl",
        ["SAO", "HBAO", "HALF", "TEMPORAL"],
        Rule::AtMostOne(&["SAO", "HBAO"]),
        // Half resolution blends after the upsample (occlusion/temporal.wgsl).
        Rule::AtMostOne(&["HALF", "TEMPORAL"])
    ),
    shader!("occlusion/temporal.wgsl", []),
    shader!(
        "occlusion/blur.wgsl",
        ["VERTICAL", "COMBINE"],
        Rule::Requires("COMBINE", "VERTICAL")
    ),
    shader!("environment/sky.wgsl", ["ENVIRONMENT", "FOG"]),
    shader!("environment/prefilter.wgsl", []),
    shader!(
        "environment/reflection.wgsl",
        ["MATERIAL_TEXTURES", "SURFACE_TARGET"]
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
    shader!(
        "post/dof.wgsl",
        ["AUTOFOCUS", "BOKEH", "HALF", "INLINE_COC"],
        // At half resolution the upsample reads the CoC target: a pass makes it.
        Rule::AtMostOne(&["HALF", "INLINE_COC"])
    ),
    shader!("post/autofocus.wgsl", []),
    shader!("post/motion_blur.wgsl", []),
    shader!("post/glare.wgsl", ["FILTERED_SOURCE"]),
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

mod cache;
mod composer;
pub mod layout;
mod reflection;

pub use cache::{PipelineRef, Sampling, ShaderCache};
pub use composer::{ShaderComposer, Splice};
pub use reflection::{Reflection, ShaderVar};

#[cfg(test)]
mod tests;
