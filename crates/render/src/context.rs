//! The one wgpu device shared by everything that renders.
//!
//! Headless by default. The adapter follows wgpu's environment variables
//! (`WGPU_BACKEND`, `WGPU_ADAPTER_NAME`, `WGPU_POWER_PREF`). Features and
//! limits the renderer needs are checked up front, so a missing one is an
//! error naming it rather than a panic deep inside a pass. The editor builds a
//! context from the device egui-wgpu already opened ([`GpuContext::from_parts`]).
//! Every context records the device errors no error scope catches instead of
//! letting wgpu's default handler panic (`uncaptured.rs`).

use std::sync::Arc;

use crate::adapter_class::AdapterClass;
use crate::error::RenderError;
use crate::frame_queue::FrameQueue;
use crate::pipeline_cache::DiskPipelineCache;
use crate::submission_gate::SubmissionGate;
use crate::uncaptured::{UncapturedErrors, error_text};

/// Features the renderer cannot work without (none yet beyond WebGPU's baseline).
pub const REQUIRED_FEATURES: wgpu::Features = wgpu::Features::empty();
/// Features used when the adapter has them: timestamps for GPU times (inside
/// passes too, so that timed passes can share a compute pass), and
/// 64-bit atomics for the compute rasterizer (the G-buffer falls back to the
/// raster hardware without them), and a pipeline cache kept on disk
/// (pipeline_cache.rs).
pub const OPTIONAL_FEATURES: wgpu::Features = wgpu::Features::TIMESTAMP_QUERY
    .union(wgpu::Features::TIMESTAMP_QUERY_INSIDE_PASSES)
    .union(wgpu::Features::SHADER_INT64)
    .union(wgpu::Features::SHADER_INT64_ATOMIC_MIN_MAX)
    .union(wgpu::Features::PIPELINE_CACHE);

/// A shared device and queue, with what the adapter told us about itself.
#[derive(Clone)]
pub struct GpuContext {
    pub device: wgpu::Device,
    /// The queue, which waits for a frame submission a submission thread
    /// still owes before it is used (frame_queue.rs).
    pub queue: FrameQueue,
    pub adapter_info: Arc<wgpu::AdapterInfo>,
    /// GPU or CPU: the paths the adapter-dependent choices take (from
    /// `adapter_info` unless [`GpuContext::with_adapter_class`] says otherwise).
    class: AdapterClass,
    /// What every submission the renderer makes passes ([`GpuContext::submit`]);
    /// open unless a host that configures window surfaces closes it.
    gate: SubmissionGate,
    /// Device errors no error scope caught, until a host takes them.
    uncaptured: Arc<UncapturedErrors>,
    /// Compiled pipelines kept between runs, where the device offers it;
    /// saved when the last clone of the context is dropped.
    pipeline_cache: Option<Arc<DiskPipelineCache>>,
    /// Where opening it went (zero for a device opened elsewhere).
    pub open_times: OpenTimes,
}

/// Where opening a headless context went, by step (`cold_start` of the
/// CLI's `--json`): what of "open GPU" is the driver and what is ours.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct OpenTimes {
    /// The instance and the adapter (the driver loads and enumerates).
    pub adapter: std::time::Duration,
    /// The device and its queue.
    pub device: std::time::Duration,
    /// The pipeline cache: its file read, the driver's cache made from it.
    pub pipeline_cache: std::time::Duration,
}

impl std::fmt::Debug for GpuContext {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(f, "GpuContext({})", self.adapter_name())
    }
}

impl GpuContext {
    /// Open the default (or environment-chosen) adapter without a window.
    pub fn headless() -> Result<Self, RenderError> {
        pollster::block_on(Self::headless_async())
    }

    async fn headless_async() -> Result<Self, RenderError> {
        let started = std::time::Instant::now();
        let instance =
            wgpu::Instance::new(wgpu::InstanceDescriptor::new_without_display_handle_from_env());
        let adapter = match std::env::var("WGPU_ADAPTER_NAME") {
            Ok(wanted) => {
                // wgpu's own helper panics when the name matches nothing; this one says so.
                let wanted_lower = wanted.to_lowercase();
                let adapters = instance.enumerate_adapters(wgpu::Backends::all()).await;
                let names: Vec<String> = adapters.iter().map(|a| a.get_info().name).collect();
                adapters
                    .into_iter()
                    .find(|a| a.get_info().name.to_lowercase().contains(&wanted_lower))
                    .ok_or_else(|| RenderError::NoAdapter {
                        filter: format!(
                            " matching WGPU_ADAPTER_NAME=`{wanted}` (adapters: {})",
                            names.join(", ")
                        ),
                    })?
            }
            Err(_) => instance
                .request_adapter(&wgpu::RequestAdapterOptions {
                    power_preference: wgpu::PowerPreference::from_env()
                        .unwrap_or(wgpu::PowerPreference::HighPerformance),
                    ..Default::default()
                })
                .await
                .map_err(|_| RenderError::NoAdapter {
                    filter: String::new(),
                })?,
        };
        let info = adapter.get_info();
        let missing = REQUIRED_FEATURES - adapter.features();
        if !missing.is_empty() {
            return Err(RenderError::MissingFeatures {
                adapter: info.name,
                missing: format!("{missing:?}"),
            });
        }
        let limits = required_limits(&adapter.limits(), &info.name)?;
        let adapter_time = started.elapsed();
        let started = std::time::Instant::now();
        let (device, queue) = adapter
            .request_device(&wgpu::DeviceDescriptor {
                label: Some("spreadlight"),
                required_features: REQUIRED_FEATURES | (OPTIONAL_FEATURES & adapter.features()),
                required_limits: limits,
                ..Default::default()
            })
            .await
            .map_err(|e| RenderError::Device {
                adapter: info.name.clone(),
                message: e.to_string(),
            })?;
        let device_time = started.elapsed();
        let mut context = Self::from_parts(device, queue, info);
        context.open_times.adapter = adapter_time;
        context.open_times.device = device_time;
        Ok(context)
    }

    /// Wrap a device opened elsewhere (the editor's egui-wgpu device).
    pub fn from_parts(
        device: wgpu::Device,
        queue: wgpu::Queue,
        adapter_info: wgpu::AdapterInfo,
    ) -> Self {
        let uncaptured = Arc::new(UncapturedErrors::default());
        let recorder = uncaptured.clone();
        device.on_uncaptured_error(Arc::new(move |error: wgpu::Error| recorder.record(&error)));
        let started = std::time::Instant::now();
        let pipeline_cache = DiskPipelineCache::open(&device, &adapter_info);
        GpuContext {
            open_times: OpenTimes {
                pipeline_cache: started.elapsed(),
                ..OpenTimes::default()
            },
            pipeline_cache,
            device,
            queue: FrameQueue::new(queue),
            class: AdapterClass::of(&adapter_info),
            adapter_info: Arc::new(adapter_info),
            gate: SubmissionGate::default(),
            uncaptured,
        }
    }

    /// The pipeline cache every pipeline of this device is compiled through
    /// (None where the device has none: pipeline_cache.rs).
    pub fn pipeline_cache(&self) -> Option<&wgpu::PipelineCache> {
        self.pipeline_cache.as_deref().map(DiskPipelineCache::cache)
    }

    /// The disk-kept pipeline cache (its file, the bytes it started from), if any.
    pub fn disk_pipeline_cache(&self) -> Option<&DiskPipelineCache> {
        self.pipeline_cache.as_deref()
    }

    /// The device errors no error scope caught since the last call
    /// (`uncaptured.rs`): a host reports them against what it was doing.
    pub fn take_uncaptured_errors(&self) -> Vec<String> {
        self.uncaptured.take()
    }

    /// Print the device errors no host took (what dropping the last clone
    /// of the context does), for a host that ends without dropping it.
    pub fn print_unreported_errors(&self) {
        self.uncaptured.print_unreported();
    }

    /// Run `work` inside a validation and an out-of-memory error scope: an
    /// error it causes comes back as `Err` with wgpu's message, for the
    /// caller to say what it was doing, instead of reaching the device's
    /// uncaptured-error handler.
    pub fn scoped<T>(&self, work: impl FnOnce() -> T) -> Result<T, String> {
        let memory = self.device.push_error_scope(wgpu::ErrorFilter::OutOfMemory);
        let validation = self.device.push_error_scope(wgpu::ErrorFilter::Validation);
        let value = work();
        let invalid = pollster::block_on(validation.pop());
        let out_of_memory = pollster::block_on(memory.pop());
        match invalid.or(out_of_memory) {
            Some(error) => Err(error_text(&error)),
            None => Ok(value),
        }
    }

    /// Submit `commands` to the queue once the [`SubmissionGate`] lets them
    /// through (at once, unless a host closed it). Every submission of the
    /// renderer's, and of whatever renders beside it on another thread, goes
    /// through here; a host's own submissions on its own thread do not.
    pub fn submit<I: IntoIterator<Item = wgpu::CommandBuffer>>(
        &self,
        commands: I,
    ) -> wgpu::SubmissionIndex {
        // After the frame a submission thread owes (frame_queue.rs).
        self.queue.owed().wait();
        self.submit_unordered(commands)
    }

    /// [`GpuContext::submit`] without waiting for an owed frame submission:
    /// the submission thread's, which pays it (frame_graph/submitter.rs).
    pub(crate) fn submit_unordered<I: IntoIterator<Item = wgpu::CommandBuffer>>(
        &self,
        commands: I,
    ) -> wgpu::SubmissionIndex {
        self.gate.pass(|| self.queue.unordered().submit(commands))
    }

    /// The gate [`GpuContext::submit`] passes, for a host that configures
    /// window surfaces on this device (see [`SubmissionGate`] for why).
    pub fn submission_gate(&self) -> &SubmissionGate {
        &self.gate
    }

    /// The adapter's name and backend, as every figure must be labelled.
    pub fn adapter_name(&self) -> String {
        format!(
            "{} ({:?})",
            self.adapter_info.name, self.adapter_info.backend
        )
    }

    /// A GPU or a CPU adapter: what the adapter-dependent `Auto` choices
    /// follow (adapter_class.rs).
    pub fn adapter_class(&self) -> AdapterClass {
        self.class
    }

    /// Take `class`'s paths whatever the adapter is: a test renders a GPU's
    /// and a CPU adapter's paths on one adapter to show they draw the same.
    pub fn with_adapter_class(mut self, class: AdapterClass) -> Self {
        self.class = class;
        self
    }

    /// Whether the G-buffer can be rasterized in compute (64-bit atomicMax).
    pub fn has_compute_raster(&self) -> bool {
        self.device
            .features()
            .contains(wgpu::Features::SHADER_INT64 | wgpu::Features::SHADER_INT64_ATOMIC_MIN_MAX)
    }

    pub fn has_timestamps(&self) -> bool {
        self.device
            .features()
            .contains(wgpu::Features::TIMESTAMP_QUERY)
    }
}

/// The limits we ask for: the adapter's own where they exceed WebGPU's
/// defaults for what we use (storage buffers grow with light and instance
/// counts; textures with the output size, which the CLI takes up to 16384:
/// WebGPU's default 8192 would refuse sizes the adapter can render).
fn required_limits(adapter: &wgpu::Limits, name: &str) -> Result<wgpu::Limits, RenderError> {
    let needed_storage: u64 = 128 << 20;
    if adapter.max_storage_buffer_binding_size < needed_storage {
        return Err(RenderError::Limit {
            adapter: name.to_owned(),
            limit: "max_storage_buffer_binding_size",
            needed: needed_storage,
            has: adapter.max_storage_buffer_binding_size,
        });
    }
    Ok(wgpu::Limits {
        max_storage_buffer_binding_size: adapter.max_storage_buffer_binding_size,
        max_buffer_size: adapter.max_buffer_size,
        max_texture_dimension_2d: adapter.max_texture_dimension_2d,
        max_storage_buffers_per_shader_stage: adapter.max_storage_buffers_per_shader_stage.min(16),
        max_storage_textures_per_shader_stage: adapter.max_storage_textures_per_shader_stage.min(8),
        // Lit transparency's refracting base pass over glTF maps with an
        // environment samples 17 textures (WebGPU's default is 16).
        max_sampled_textures_per_shader_stage: adapter
            .max_sampled_textures_per_shader_stage
            .min(32),
        ..wgpu::Limits::default()
    })
}

/// Copy a mappable buffer's first `size` bytes to the CPU, waiting for the GPU.
pub(crate) fn read_buffer(
    gpu: &GpuContext,
    buffer: &wgpu::Buffer,
    size: u64,
) -> Result<Vec<u8>, RenderError> {
    let slice = buffer.slice(0..size);
    let (tx, rx) = std::sync::mpsc::channel();
    slice.map_async(wgpu::MapMode::Read, move |r| {
        let _ = tx.send(r);
    });
    gpu.device
        .poll(wgpu::PollType::wait_indefinitely())
        .map_err(|e| RenderError::Readback(e.to_string()))?;
    rx.recv()
        .map_err(|e| RenderError::Readback(e.to_string()))?
        .map_err(|e| RenderError::Readback(e.to_string()))?;
    let data = slice
        .get_mapped_range()
        .map_err(|e| RenderError::Readback(e.to_string()))?
        .to_vec();
    buffer.unmap();
    Ok(data)
}
