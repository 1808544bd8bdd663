//! The editor crate's integration tests, one binary: linking a binary per
//! file cost CI minutes (each links wgpu, naga, egui and the editor), docs/testing.md. Every
//! file beside this one is a module here, so its tests are named
//! `file::test` (`cargo test --workspace --test editor -- editor::` runs
//! one file's); a new test file needs its `mod` line below, which
//! `tests/test_files.rs` checks.

// Shared by several files.
mod common;

// The test files.
mod editor;
mod host_input;
mod iobox;
mod readability;
mod scene;
mod show_window;
mod subpatch;
mod viewport;
