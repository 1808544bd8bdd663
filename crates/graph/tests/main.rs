//! The graph crate's integration tests, one binary: linking a binary per
//! file cost CI minutes, docs/testing.md. Every
//! file beside this one is a module here, so its tests are named
//! `file::test` (`cargo test --workspace --test graph -- runtime::` runs
//! one file's); a new test file needs its `mod` line below, which
//! `tests/test_files.rs` checks.

// Shared by several files.

// The test files.
mod runtime;
mod subpatch;
