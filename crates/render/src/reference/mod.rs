//! The CPU reference of the renderer's pure maths: BRDF terms
//! ([`brdf`]), light falloff ([`lights`]) and tone operators ([`tonemap`]),
//! the matcap lookup ([`matcap`]), glTF materials point-sampled
//! ([`material`]), ray-cast soft shadows ([`shadows`]) to measure the shadow filters by,
//! and the shipped light shader nodes' models ([`toon`], [`ashikhmin_shirley`]).
//!
//! Each function is written twice, here in Rust and in a WGSL library under
//! `shaders/lib/` with the same name and signature (`spreadlight::brdf`,
//! `spreadlight::lights`, `spreadlight::tonemap`), so that a test can tell
//! what a shader should have computed. The tests beside each module check the
//! maths itself (energy conservation, boundaries, monotonicity);
//! `tests/shader_reference.rs` composes the WGSL libraries and runs them on
//! the GPU against these functions. Pure: no wgpu here.

pub mod ashikhmin_shirley;
pub mod brdf;
pub mod lights;
pub mod matcap;
pub mod material;
pub mod reflection;
pub mod shadows;
pub mod ssao;
pub mod tonemap;
pub mod toon;
