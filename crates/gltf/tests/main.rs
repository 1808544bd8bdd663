//! The gltf crate's integration tests, one binary: linking a binary per
//! file cost CI minutes (each links wgpu, naga), docs/testing.md. Every
//! file beside this one is a module here, so its tests are named
//! `file::test` (`cargo test --workspace --test gltf -- gltf_blend::` runs
//! one file's); a new test file needs its `mod` line below, which
//! `tests/test_files.rs` checks.

// Shared by several files.
mod common;
#[path = "../../render/tests/post_common/mod.rs"]
mod post_common;

// The test files.
mod gltf_blend;
mod gltf_extension_maps;
mod gltf_vertex_streams;
mod skinning;
