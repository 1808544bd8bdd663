//! Every entry shader of the renderer, by its effect's typed key: the one
//! place that names them all. It stands above the effects (it imports their
//! key files, and nothing of the renderer imports it), so the shader layer
//! below them keeps no table of entry shaders: a key carries its own file.
//! The exhaustive tests walk this list (every permutation composes and
//! validates; the composite's 6,720 keys), and a test holds it against the
//! `shaders/` folder, so a new effect's shader cannot be left out.

use crate::shaders::{Generator, Permutation, ShaderFile, ShaderKey};

/// Every entry shader, as its typed key declares it (the libraries are
/// `shaders::LIBRARIES`).
pub const ENTRY_SHADERS: &[&ShaderFile] = &[
    <crate::gbuffer::visibility_key::VisibilityKey as Permutation>::FILE,
    <crate::geometry::spherize_key::SpherizeKey as Permutation>::FILE,
    <crate::geometry::extrude_key::ExtrudeKey as Permutation>::FILE,
    <crate::geometry::pn_triangles_key::PnTrianglesKey as Permutation>::FILE,
    <crate::geometry::spline_key::SplineKey as Permutation>::FILE,
    <crate::geometry::tessellate_key::TessellateKey as Permutation>::FILE,
    <crate::geometry::displace_key::DisplaceKey as Permutation>::FILE,
    <crate::geometry::skinning_key::SkinningKey as Permutation>::FILE,
    <crate::particles::simulate_key::SimulateKey as Permutation>::FILE,
    <crate::particles::expand_key::ExpandKey as Permutation>::FILE,
    <crate::gbuffer::compute_raster_key::RasterKey as Permutation>::FILE,
    <crate::gbuffer::published_depth_key::PublishedDepthKey as Permutation>::FILE,
    <crate::gbuffer::resolve_key::ResolveKey as Permutation>::FILE,
    <crate::lighting::clusters_key::ClustersKey as Permutation>::FILE,
    <crate::lighting::cook_torrance_key::CookTorranceKey as Permutation>::FILE,
    <crate::lighting::composite::key::CompositeKey as Permutation>::FILE,
    <crate::lighting::ssgi_key::SsgiKey as Permutation>::FILE,
    <crate::lighting::ssss_key::SsssKey as Permutation>::FILE,
    <crate::shadows::raster_key::ShadowDepthKey as Permutation>::FILE,
    <crate::shadows::raster_key::MomentsKey as Permutation>::FILE,
    <crate::shadows::raster_key::ShadowResolveKey as Permutation>::FILE,
    <crate::shadows::scroll_key::ShadowScrollKey as Permutation>::FILE,
    <crate::ssao::key::DepthKey as Permutation>::FILE,
    <crate::ssao::key::AoKey as Permutation>::FILE,
    <crate::ssao::key::BlurKey as Permutation>::FILE,
    <crate::packed_surface::key::PackKey as Permutation>::FILE,
    <crate::environment::sky_key::SkyKey as Permutation>::FILE,
    <crate::environment::prefilter_key::PrefilterKey as Permutation>::FILE,
    <crate::environment::probe::key::ProbeFacesKey as Permutation>::FILE,
    <crate::environment::reflection_key::ReflectionKey as Permutation>::FILE,
    <crate::environment::ssr::key::SsrKey as Permutation>::FILE,
    <crate::environment::fog_key::FogKey as Permutation>::FILE,
    <crate::post::tonemap_key::TonemapKey as Permutation>::FILE,
    <crate::post::eye_adaptation_key::EyeAdaptationKey as Permutation>::FILE,
    <crate::post::fxaa_key::FxaaKey as Permutation>::FILE,
    <crate::post::copy_key::CopyKey as Permutation>::FILE,
    <crate::bench::pass_chain_key::PassChainKey as Permutation>::FILE,
    <crate::accumulate::key::AccumulateKey as Permutation>::FILE,
    <crate::post::dof_key::DofKey as Permutation>::FILE,
    <crate::post::autofocus_key::AutofocusKey as Permutation>::FILE,
    <crate::post::motion_blur_key::MotionBlurKey as Permutation>::FILE,
    <crate::post::glare_key::GlareKey as Permutation>::FILE,
    <crate::post::transparency::key::TransparencyKey as Permutation>::FILE,
    <crate::post::taa_key::TaaQuality as Permutation>::FILE,
    <crate::shader_nodes::builtin_blur_key::BuiltinBlurKey as Permutation>::FILE,
    <crate::resolution_key::UpsampleKey as Permutation>::FILE,
    <crate::gbuffer::view_key::Channel as Permutation>::FILE,
];

/// Every generator of shaders made from the sources' text
/// (`shaders/generated.rs`): what a permutation list's `generated` lines
/// are read by (`crate::precompose`).
pub static GENERATORS: &[&Generator] = &[&crate::lighting::light_sets::GENERATOR];

/// Every permutation the shader set allows: each entry shader with each of
/// its typed key's values.
pub fn all_permutations() -> Vec<ShaderKey> {
    ENTRY_SHADERS
        .iter()
        .filter_map(|file| file.keys)
        .flat_map(|keys| keys())
        .collect()
}

#[cfg(test)]
mod tests;
