//! Spreadlight's renderer: one wgpu device shared by everything that renders,
//! the frame graph that culls and runs passes, the shader permutation cache,
//! meshes (primitives and glTF), and the deferred passes. No UI: the editor
//! and the CLI only host it.

pub mod accumulate;
pub mod adapter_class;
pub mod allocation_count;
pub mod bench;
pub mod camera;
pub mod context;
pub mod environment;
pub mod error;
pub mod finite;
pub mod frame_graph;
pub mod frame_queue;
pub mod gbuffer;
pub mod geometry;
pub mod image_io;
pub mod light_kind;
pub mod lighting;
pub mod material;
pub mod mesh;
pub mod mesh_arena;
pub mod mip_chain;
pub mod packed_surface;
pub mod particles;
pub mod permutations;
pub mod pipeline_cache;
pub use shaders::pipelines_ahead;
pub mod post;
pub mod precompose;
pub mod readback;
pub mod recipe;
pub mod renderer;
pub mod report;
pub mod resolution;
pub(crate) mod resolution_key;
pub mod scenes;
pub mod setting;
pub mod shader_nodes;
pub mod shaders;
pub mod shadows;
pub mod ssao;
pub mod static_texture;
pub mod submission_gate;
pub mod temporal;
pub mod texture;
pub mod texture_pool;
pub mod uncaptured;

pub use context::GpuContext;
pub use error::RenderError;
pub use frame_graph::{FrameGraph, FrameReport, Lifetime, SizeRule, TextureDesc};
pub use recipe::{Recipe, TextureRef};
pub use renderer::Renderer;
pub use submission_gate::{GateCounts, SubmissionGate};
