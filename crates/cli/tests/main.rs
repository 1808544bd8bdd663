//! The cli crate's integration tests, one binary: linking a binary per
//! file cost CI minutes (each links wgpu, naga, egui and the editor), docs/testing.md. Every
//! file beside this one is a module here, so its tests are named
//! `file::test` (`cargo test --workspace --test cli -- accuracy::` runs
//! one file's); a new test file needs its `mod` line below, which
//! `tests/test_files.rs` checks.

// Shared by several files.
mod support;
mod xwindow;

// The test files.
mod accuracy;
mod cli;
mod editor_window;
mod farm;
mod half_resolution;
mod sequence;
mod sequence_quality;
mod show_window;
mod view;
