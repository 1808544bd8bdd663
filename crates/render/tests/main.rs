//! The render crate's integration tests, one binary: linking a binary per
//! file cost CI minutes (each links wgpu, naga), docs/testing.md. Every
//! file beside this one is a module here, so its tests are named
//! `file::test` (`cargo test --workspace --test render -- compute_passes::` runs
//! one file's); a new test file needs its `mod` line below, which
//! `tests/test_files.rs` checks.

// Shared by several files.
mod common;
mod floor_view;
mod occlusion_scene;
mod post_common;
mod reflection_scene;

// The test files.
mod compute_passes;
mod depth_aware_blur;
mod dof;
mod environment;
mod eye_adaptation;
mod frame_chunks;
mod frame_cpu;
mod frame_graph;
mod fxaa;
mod gbuffer;
mod geometry;
mod geometry_adaptive;
mod glare;
mod gltf_sides;
mod half_resolution;
mod light_loop_reference;
mod lighting;
mod matcap;
mod material;
mod motion_blur;
mod occlusion;
mod particle_drawing;
mod particles;
mod post_stability;
mod reflection;
mod shader_reference;
mod shadow_layers;
mod shadows;
mod ssr;
mod ssr_hi_z;
mod submission_thread;
mod surface_lighting;
mod taa;
mod tonemap;
mod transparency;
