//! Sequences: `spreadlight render PATCH --frames 0-239 -o out/shot_####.exr`.
//! A frame range at a fixed frame rate, one sequence per `Output` node,
//! resumable (complete frames are skipped) and deterministic in chunks (a
//! chunk first evaluates the preroll `--preroll` asks or its patch declares,
//! else from frame 0 when its nodes keep state), each file written atomically, a failing frame reported while the
//! rest go on. Optional sub-frame accumulation (`--samples`) and video
//! through ffmpeg. The farm (tools/farm) hands chunks of this command out.

pub mod accumulate;
mod evaluate;
mod exr_pixels;
mod exr_zip;
mod fault;
mod files;
pub mod frames;
mod names;
mod outputs;
mod pipeline;
mod progress;
mod render;
mod stages;
mod video;
mod whole;

pub use render::{Args, run};

/// Input the run cannot start with (a malformed patch, a bad range or
/// name, a missing tool): exit code 2, where failed frames give 1.
#[derive(Debug, thiserror::Error)]
#[error("{0}")]
pub struct BadInput(pub String);
