//! The renderer's errors. Each names what failed and, where a user can fix
//! it, how.

use thiserror::Error;

#[derive(Debug, Error)]
pub enum RenderError {
    #[error(
        "no GPU adapter found{filter}. On a machine without a GPU install Mesa's software Vulkan driver \
         (Debian/Ubuntu: `apt-get install mesa-vulkan-drivers`); wgpu's WGPU_BACKEND and WGPU_ADAPTER_NAME \
         environment variables choose among several"
    )]
    NoAdapter { filter: String },
    #[error("the GPU adapter `{adapter}` lacks required feature(s) {missing}")]
    MissingFeatures { adapter: String, missing: String },
    #[error(
        "the GPU adapter `{adapter}` cannot provide the limit {limit} (needs {needed}, has {has})"
    )]
    Limit {
        adapter: String,
        limit: &'static str,
        needed: u64,
        has: u64,
    },
    #[error("cannot open the GPU device on `{adapter}`: {message}")]
    Device { adapter: String, message: String },
    #[error("shader `{shader}`{defs}: {message}")]
    Shader {
        shader: String,
        defs: String,
        message: String,
    },
    #[error("pass `{pass}`: {message}")]
    Pass { pass: String, message: String },
    #[error("GPU validation error in pass `{pass}`: {message}")]
    Validation { pass: String, message: String },
    /// Something the adapter cannot hold: caught before it is made, since
    /// wgpu would refuse it with an error outside any pass.
    #[error("{what} is past the adapter's limit {limit} ({max})")]
    TooLarge {
        what: String,
        limit: &'static str,
        max: u64,
    },
    #[error("frame graph: {0}")]
    Graph(String),
    #[error("reading back from the GPU failed: {0}")]
    Readback(String),
    #[error("{path}: cannot write the image: {message}")]
    ImageWrite { path: String, message: String },
}
