//! The CPU reference of the renderer's pure maths: BRDF terms
//! ([`brdf`], the anisotropic lobe in [`anisotropy`]), light falloff ([`lights`]) and tone operators ([`tonemap`]),
//! the matcap lookup ([`matcap`]), a material shaded under the sun
//! ([`material`]), ray-cast soft shadows ([`shadows`]) and ambient
//! occlusion ([`ssao`]) to measure the filters by, reflections ray-traced
//! ([`reflection`]), refraction through a slab ([`refraction`]), thin-film
//! iridescence ([`iridescence`]), the sheen lobe ([`sheen`]), and the shipped light shader nodes' models ([`toon`],
//! [`ashikhmin_shirley`]); glTF materials point-sampled are
//! `spreadlight_gltf::reference`, beside the importer.
//!
//! Each function is written twice, here in Rust and in a WGSL library under
//! `shaders/lib/` with the same name and signature (`spreadlight::brdf`,
//! `spreadlight::lights`, `spreadlight::tonemap`), so that a test can tell
//! what a shader should have computed. The tests beside each module check the
//! maths itself (energy conservation, boundaries, monotonicity);
//! `crates/render/tests/shader_reference.rs` composes the WGSL libraries and runs them on
//! the GPU against these functions. Pure: no wgpu here, and nothing of the
//! renderer, which depends on this crate and not the other way round: a
//! change in an effect does not rebuild the references.

pub mod anisotropy;
pub mod ashikhmin_shirley;
pub mod brdf;
pub mod iridescence;
pub mod lights;
pub mod matcap;
pub mod material;
pub mod reflection;
pub mod refraction;
pub mod shadows;
pub mod sheen;
pub mod ssao;
pub mod tonemap;
pub mod toon;
