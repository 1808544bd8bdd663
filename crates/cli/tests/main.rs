//! The cli crate's integration tests, one binary: linking a binary per
//! file cost CI minutes (each links wgpu, naga, egui and the editor), docs/testing.md. Every
//! file beside this one is a module here, so its tests are named
//! `file::test` (`cargo test --workspace --test cli -- accuracy::` runs
//! one file's); a new test file needs its `mod` line below, which
//! `tests/test_files.rs` checks. The window tests (`editor_window.rs`,
//! `show_window.rs`, with `xwindow/`) are binaries of their own: Cargo.toml
//! says why.

// Shared by several files.
mod support;

// The test files.
mod accuracy;
mod cli;
mod farm;
mod half_resolution;
mod sequence;
mod sequence_quality;
mod submission_thread;
mod view;
