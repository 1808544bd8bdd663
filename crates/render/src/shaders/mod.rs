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
    shader!("gbuffer/visibility.wgsl", keyed crate::gbuffer::visibility_key::VisibilityKey),
    shader!("geometry/spherize.wgsl", keyed crate::geometry::spherize_key::SpherizeKey),
    shader!("geometry/extrude.wgsl", keyed crate::geometry::extrude_key::ExtrudeKey),
    shader!("geometry/pn_triangles.wgsl", keyed crate::geometry::pn_triangles_key::PnTrianglesKey),
    shader!("geometry/spline.wgsl", keyed crate::geometry::spline_key::SplineKey),
    shader!("geometry/tessellate.wgsl", keyed crate::geometry::tessellate_key::TessellateKey),
    shader!("geometry/displace.wgsl", keyed crate::geometry::displace_key::DisplaceKey),
    shader!("geometry/skinning.wgsl", keyed crate::geometry::skinning_key::SkinningKey),
    shader!("particles/simulate.wgsl", keyed crate::particles::simulate_key::SimulateKey),
    shader!("particles/expand.wgsl", keyed crate::particles::expand_key::ExpandKey),
    shader!("gbuffer/raster.wgsl", keyed crate::gbuffer::compute_raster_key::RasterKey),
    shader!("gbuffer/published_depth.wgsl", keyed crate::gbuffer::published_depth_key::PublishedDepthKey),
    shader!("gbuffer/resolve.wgsl", keyed crate::gbuffer::resolve_key::ResolveKey),
    shader!("lighting/clusters.wgsl", keyed crate::lighting::clusters_key::ClustersKey),
    shader!("lighting/cook_torrance.wgsl", keyed crate::lighting::cook_torrance_key::CookTorranceKey),
    shader!("lighting/composite.wgsl", keyed crate::lighting::composite::key::CompositeKey),
    shader!("lighting/ssgi.wgsl", keyed crate::lighting::ssgi_key::SsgiKey),
    shader!("lighting/ssgi_blur_tiled.wgsl", keyed crate::lighting::ssgi_key::SsgiTiledBlurKey),
    shader!("lighting/ssss.wgsl", keyed crate::lighting::ssss_key::SsssKey),
    shader!("shadows/depth.wgsl", keyed crate::shadows::raster_key::ShadowDepthKey),
    shader!("shadows/moments.wgsl", keyed crate::shadows::raster_key::MomentsKey),
    shader!("shadows/resolve.wgsl", keyed crate::shadows::raster_key::ShadowResolveKey),
    shader!("ssao/linear_depth.wgsl", keyed crate::ssao::key::DepthKey),
    shader!("ssao/ao.wgsl", keyed crate::ssao::key::AoKey),
    shader!("ssao/temporal.wgsl", keyed crate::ssao::key::TemporalKey),
    shader!("ssao/blur.wgsl", keyed crate::ssao::key::BlurKey),
    shader!("ssao/blur_tiled.wgsl", keyed crate::ssao::key::TiledBlurKey),
    shader!("environment/sky.wgsl", keyed crate::environment::sky_key::SkyKey),
    shader!("environment/prefilter.wgsl", keyed crate::environment::prefilter_key::PrefilterKey),
    shader!("environment/environment_probe.wgsl", keyed crate::environment::probe::key::ProbeFacesKey),
    shader!("environment/reflection.wgsl", keyed crate::environment::reflection_key::ReflectionKey),
    shader!("environment/ssr.wgsl", keyed crate::environment::ssr::key::SsrKey),
    shader!("environment/fog.wgsl", keyed crate::environment::fog_key::FogKey),
    shader!("post/tonemap.wgsl", keyed crate::post::tonemap_key::TonemapKey),
    shader!("post/eye_adaptation.wgsl", keyed crate::post::eye_adaptation_key::EyeAdaptationKey),
    shader!("post/fxaa.wgsl", keyed crate::post::fxaa_key::FxaaKey),
    shader!("post/copy.wgsl", keyed crate::post::copy_key::CopyKey),
    shader!("bench/pass_chain.wgsl", keyed crate::bench::pass_chain_key::PassChainKey),
    shader!("accumulate/add.wgsl", keyed crate::accumulate::key::AccumulateKey),
    shader!("post/dof.wgsl", keyed crate::post::dof_key::DofKey),
    shader!("post/autofocus.wgsl", keyed crate::post::autofocus_key::AutofocusKey),
    shader!("post/motion_blur.wgsl", keyed crate::post::motion_blur_key::MotionBlurKey),
    shader!("post/glare.wgsl", keyed crate::post::glare_key::GlareKey),
    shader!("post/transparency.wgsl", keyed crate::post::transparency::key::TransparencyKey),
    shader!("post/taa.wgsl", keyed crate::post::taa_key::TaaQuality),
    // The shader-node example blur, run as a built-in pass (the baseline its node is benchmarked against).
    shader!("nodes/blur.wgsl", keyed crate::shader_nodes::builtin_blur_key::BuiltinBlurKey),
    shader!("resolution/upsample.wgsl", keyed crate::resolution_key::UpsampleKey),
    shader!("gbuffer/view.wgsl", keyed crate::gbuffer::view_key::Channel),
];

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
mod flags;
pub mod layout;
pub mod permutation;
mod reflection;
mod uniform;

pub use cache::{CompileTimes, PipelineRef, Sampling, ShaderCache};
pub use composer::{ShaderComposer, Splice};
pub use permutation::{Permutation, Rule, ShaderFile, ShaderKey};
pub use reflection::{Reflection, ShaderVar};
pub use uniform::Uniform;

#[cfg(test)]
mod tests;
