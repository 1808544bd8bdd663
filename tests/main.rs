//! The workspace's tests, one binary: linking a binary per file cost CI
//! minutes (each links wgpu, naga and the node library), docs/testing.md.
//! Every test file here is a module, so its tests are named `file::test`
//! (`cargo test --workspace --test workspace -- reference_images::` runs one
//! file's); a new test file needs its `mod` line below, which
//! `test_files.rs` checks. `frame_allocations.rs` is a binary of its own
//! (Cargo.toml says why).

mod bad_patches;
mod docs;
mod patches;
mod reference_images;
mod test_files;
