//! The renderer: the shared GPU context plus what lives across frames: the
//! shader permutation cache, the texture pool, persistent textures, the mesh
//! arena, the timestamp queries, and the last frame's report.
//!
//! Nodes hold it behind an `Arc` and call it from their evaluation; its
//! interior state is behind mutexes so it is shared, not cloned.

use rustc_hash::FxHashMap;
use std::sync::{Arc, Mutex};

use crate::context::GpuContext;
use crate::error::RenderError;
use crate::mesh_arena::MeshArena;
use crate::report::FrameReport;
use crate::shaders::{ShaderCache, ShaderComposer};
use crate::texture_pool::TexturePool;

pub(crate) const MAX_QUERIES: u32 = 512;

/// A kept buffer's name: the node that owns it, what it is, and which one
/// of several of the same kind (a G-buffer's layers, a rasterizer's batches).
type KeptKey = (u32, &'static str, u32);

struct KeptBuffer {
    buffer: wgpu::Buffer,
    /// What `Renderer::kept_init` last wrote (empty for scratch buffers).
    contents: Vec<u8>,
}

/// The buffer kept under `key` if it `fits`, else `make()` kept in its
/// place; true when it was made now.
fn kept_entry(
    kept: &mut FxHashMap<KeptKey, KeptBuffer>,
    key: KeptKey,
    fits: impl Fn(&KeptBuffer) -> bool,
    make: impl FnOnce() -> wgpu::Buffer,
) -> (&mut KeptBuffer, bool) {
    use std::collections::hash_map::Entry;
    match kept.entry(key) {
        Entry::Occupied(o) if fits(o.get()) => (o.into_mut(), false),
        Entry::Occupied(mut o) => {
            o.insert(KeptBuffer {
                buffer: make(),
                contents: Vec::new(),
            });
            (o.into_mut(), true)
        }
        Entry::Vacant(v) => (
            v.insert(KeptBuffer {
                buffer: make(),
                contents: Vec::new(),
            }),
            true,
        ),
    }
}

/// The range of `new` that differs from `old` (of the same length), widened
/// to 4-byte boundaries as buffer writes must be; None if nothing differs.
fn changed_span(old: &[u8], new: &[u8]) -> Option<(usize, usize)> {
    // Chunks compare as slices (memcmp), then bytes within the chunk found.
    const CHUNK: usize = 256;
    let chunk = old
        .chunks(CHUNK)
        .zip(new.chunks(CHUNK))
        .position(|(a, b)| a != b)?;
    let from = chunk * CHUNK;
    let first = from
        + old[from..]
            .iter()
            .zip(&new[from..])
            .position(|(a, b)| a != b)?;
    let chunk = old
        .rchunks(CHUNK)
        .zip(new.rchunks(CHUNK))
        .position(|(a, b)| a != b)?;
    let to = old.len() - chunk * CHUNK;
    let last = old[..to]
        .iter()
        .zip(&new[..to])
        .rposition(|(a, b)| a != b)?;
    let align = wgpu::COPY_BUFFER_ALIGNMENT as usize;
    let start = first / align * align;
    let end = (last + 1).div_ceil(align) * align;
    // A length off the alignment (not made here) is written whole, as before.
    if end > new.len() {
        return Some((0, new.len()));
    }
    Some((start, end))
}

/// Kept-buffer writes since the last frame graph ran (the frame report's counters).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub(crate) struct Uploads {
    /// Writes made ("uniform uploads").
    pub made: u64,
    /// Writes skipped: nothing had changed ("uniform uploads skipped").
    pub skipped: u64,
    /// Bytes written ("uniform bytes uploaded").
    pub bytes: u64,
    /// Bytes compared with what was written before ("kept bytes compared").
    pub compared: u64,
}

pub(crate) struct Timestamps {
    pub set: wgpu::QuerySet,
    pub resolve: wgpu::Buffer,
    pub readback: wgpu::Buffer,
}

/// How frames are timed (`FrameGraph::execute`).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum Timing {
    /// Timestamps around every pass, read back after each frame: the
    /// per-pass figures of `stats` and `bench`. The CPU waits for the GPU.
    #[default]
    PerPass,
    /// Timestamps at the first and the last pass only: the frame's GPU span.
    Frame,
    /// No timestamps and no waiting: frames overlap (recorded while the GPU
    /// works on the last), as an interactive host runs them.
    Off,
}

/// How passes are recorded (`FrameGraph::execute`).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum Recording {
    /// Each pass in its own command encoder and error scope: an error names its pass.
    #[default]
    Isolated,
    /// The whole frame in one command encoder; an error drops the frame and
    /// switches to `Isolated`.
    Batched,
}

/// Frame graphs a persistent texture may go unwritten before it is dropped:
/// about a second at 60 frames a second, so a node briefly culled (an editor
/// viewport looking elsewhere) keeps its history.
pub const PERSISTENT_IDLE_GRAPHS: u32 = 60;

pub struct Renderer {
    pub gpu: GpuContext,
    shaders: Mutex<ShaderCache>,
    textures: Mutex<TexturePool>,
    pub meshes: MeshArena,
    timestamps: Option<Timestamps>,
    settings: Mutex<(Timing, Recording)>,
    /// Submissions not yet known to be done, oldest first (`Timing::Off`).
    in_flight: Mutex<std::collections::VecDeque<wgpu::SubmissionIndex>>,
    last_report: Mutex<FrameReport>,
    output_size: Mutex<(u32, u32)>,
    /// Buffers recipes keep across their re-creation, by owner node and label
    /// (`Renderer::uniform`, `Renderer::kept_buffer`), with a uniform's last contents.
    kept: Mutex<FxHashMap<KeptKey, KeptBuffer>>,
    /// Kept-buffer writes made and skipped since the last frame graph ran.
    uploads: Mutex<Uploads>,
    /// What recipes keep between frames (shadow maps), by type and key.
    states: Mutex<FxHashMap<(std::any::TypeId, u64), Arc<dyn std::any::Any + Send + Sync>>>,
}

/// The output size until a host sets one.
pub const DEFAULT_OUTPUT_SIZE: (u32, u32) = (640, 360);

impl Renderer {
    pub fn new(gpu: GpuContext) -> Result<Self, RenderError> {
        let shaders = ShaderCache::new(ShaderComposer::new()?);
        let timestamps = gpu.has_timestamps().then(|| Timestamps {
            set: gpu.device.create_query_set(&wgpu::QuerySetDescriptor {
                label: Some("pass timestamps"),
                ty: wgpu::QueryType::Timestamp,
                count: MAX_QUERIES,
            }),
            resolve: gpu.device.create_buffer(&wgpu::BufferDescriptor {
                label: Some("timestamp resolve"),
                size: u64::from(MAX_QUERIES) * 8,
                usage: wgpu::BufferUsages::QUERY_RESOLVE | wgpu::BufferUsages::COPY_SRC,
                mapped_at_creation: false,
            }),
            readback: gpu.device.create_buffer(&wgpu::BufferDescriptor {
                label: Some("timestamp readback"),
                size: u64::from(MAX_QUERIES) * 8,
                usage: wgpu::BufferUsages::MAP_READ | wgpu::BufferUsages::COPY_DST,
                mapped_at_creation: false,
            }),
        });
        let meshes = MeshArena::new(&gpu);
        Ok(Renderer {
            gpu,
            shaders: Mutex::new(shaders),
            textures: Mutex::new(TexturePool::default()),
            meshes,
            timestamps,
            settings: Mutex::new((Timing::default(), Recording::default())),
            in_flight: Mutex::new(std::collections::VecDeque::new()),
            last_report: Mutex::new(FrameReport::default()),
            output_size: Mutex::new(DEFAULT_OUTPUT_SIZE),
            states: Mutex::new(FxHashMap::default()),
            kept: Mutex::new(FxHashMap::default()),
            uploads: Mutex::new(Uploads::default()),
        })
    }

    /// A renderer on a headless device (the CLI and tests).
    pub fn headless() -> Result<Self, RenderError> {
        Self::new(GpuContext::headless()?)
    }

    pub fn shaders(&self) -> std::sync::MutexGuard<'_, ShaderCache> {
        self.shaders.lock().unwrap_or_else(|e| e.into_inner())
    }

    /// The size sinks render at (`--size`, or the editor's viewport).
    pub fn output_size(&self) -> (u32, u32) {
        *self.output_size.lock().unwrap_or_else(|e| e.into_inner())
    }

    pub fn set_output_size(&self, size: (u32, u32)) {
        *self.output_size.lock().unwrap_or_else(|e| e.into_inner()) =
            (size.0.max(1), size.1.max(1));
    }

    /// State a recipe keeps across frames and across its own re-creation
    /// (a node re-evaluated makes a new recipe), under `key` (usually the
    /// node id): made with `T::default()` the first time.
    pub fn state<T: Default + Send + Sync + 'static>(&self, key: u64) -> Arc<T> {
        let mut states = self.states.lock().unwrap_or_else(|e| e.into_inner());
        let entry = states
            .entry((std::any::TypeId::of::<T>(), key))
            .or_insert_with(|| Arc::new(T::default()));
        match entry.clone().downcast::<T>() {
            Ok(state) => state,
            // Keyed by the type's id: another type cannot be under it.
            Err(_) => unreachable!("state keyed by its TypeId"),
        }
    }

    /// A uniform buffer holding `bytes` for node `owner`'s `label`: the same
    /// buffer each time the node's recipe is made again, written only when
    /// the bytes changed (counted: "uniform uploads", "uniform uploads
    /// skipped"), so bind groups over it are reused from frame to frame.
    /// One (owner, label) must name one buffer per frame: a node making
    /// several recipes gives each its own label. Without an owner, a new buffer.
    pub fn uniform(&self, owner: Option<u32>, label: &'static str, bytes: &[u8]) -> wgpu::Buffer {
        self.kept_init(
            owner,
            label,
            bytes,
            wgpu::BufferUsages::UNIFORM | wgpu::BufferUsages::COPY_DST,
        )
    }

    /// [`Renderer::uniform`] for any usage (COPY_DST is added): storage
    /// buffers such as a G-buffer's instances, kept and written on change.
    pub fn kept_init(
        &self,
        owner: Option<u32>,
        label: &'static str,
        bytes: &[u8],
        usage: wgpu::BufferUsages,
    ) -> wgpu::Buffer {
        self.kept_init_at(owner, label, 0, bytes, usage)
    }

    /// A temporal pass's "history was reset" flag as two kept uniforms
    /// (`vec4<u32>` with x = 0, then x = 1), so a pass binds
    /// `flags[usize::from(fresh)]` and its bind groups stay the same
    /// buffers from frame to frame whichever it is.
    pub fn kept_flags(&self, owner: Option<u32>, label: &'static str) -> [wgpu::Buffer; 2] {
        [0u32, 1].map(|flag| {
            self.kept_init_at(
                owner,
                label,
                flag,
                bytemuck::cast_slice(&[flag, 0, 0, 0]),
                wgpu::BufferUsages::UNIFORM,
            )
        })
    }

    /// [`Renderer::kept_init`] for the `index`th of several buffers of one
    /// kind that one recipe keeps (a G-buffer's layer records, a rasterizer's
    /// batches): each keeps its own buffer, so none overwrites another.
    pub fn kept_init_at(
        &self,
        owner: Option<u32>,
        label: &'static str,
        index: u32,
        bytes: &[u8],
        usage: wgpu::BufferUsages,
    ) -> wgpu::Buffer {
        let usage = usage | wgpu::BufferUsages::COPY_DST;
        let fresh = || {
            wgpu::util::DeviceExt::create_buffer_init(
                &self.gpu.device,
                &wgpu::util::BufferInitDescriptor {
                    label: Some(label),
                    contents: bytes,
                    usage,
                },
            )
        };
        let Some(owner) = owner else {
            return fresh();
        };
        let mut kept = self.kept.lock().unwrap_or_else(|e| e.into_inner());
        let (k, made) = kept_entry(
            &mut kept,
            (owner, label, index),
            |k| k.buffer.usage() == usage && k.contents.len() == bytes.len(),
            fresh,
        );
        let mut uploads = self.uploads.lock().unwrap_or_else(|e| e.into_inner());
        if made {
            k.contents = bytes.to_vec();
            uploads.made += 1;
            uploads.bytes += bytes.len() as u64;
        } else if let Some((start, end)) = {
            uploads.compared += bytes.len() as u64;
            changed_span(&k.contents, bytes)
        } {
            // Only the bytes that changed: one moving instance among a
            // thousand still ones writes its 224 bytes, not the buffer.
            self.gpu
                .queue
                .write_buffer(&k.buffer, start as u64, &bytes[start..end]);
            k.contents[start..end].copy_from_slice(&bytes[start..end]);
            uploads.made += 1;
            uploads.bytes += (end - start) as u64;
        } else {
            uploads.skipped += 1;
        }
        k.buffer.clone()
    }

    /// [`Renderer::kept_init`] for contents laid out as `parts` one after
    /// another (a G-buffer's layers), where `unchanged[i]` says that part `i`
    /// holds the bytes this wrote at the same offset last time: those are
    /// neither compared nor written, so one moving layer among a thousand
    /// still instances compares its own bytes, not ~230 KB. A buffer made
    /// now (new, or another length) is written whole.
    pub fn kept_init_parts(
        &self,
        owner: Option<u32>,
        label: &'static str,
        parts: &[&[u8]],
        unchanged: &[bool],
        usage: wgpu::BufferUsages,
    ) -> wgpu::Buffer {
        let len = parts.iter().map(|p| p.len()).sum::<usize>();
        let usage = usage | wgpu::BufferUsages::COPY_DST;
        let mut kept = self.kept.lock().unwrap_or_else(|e| e.into_inner());
        let Some(k) = owner
            .and_then(|owner| kept.get_mut(&(owner, label, 0)))
            .filter(|k| k.buffer.usage() == usage && k.contents.len() == len)
        else {
            drop(kept);
            return self.kept_init(owner, label, &parts.concat(), usage);
        };
        let mut uploads = self.uploads.lock().unwrap_or_else(|e| e.into_inner());
        let align = wgpu::COPY_BUFFER_ALIGNMENT as usize;
        let (mut offset, mut wrote) = (0, false);
        for (i, part) in parts.iter().enumerate() {
            let at = offset;
            offset += part.len();
            if unchanged.get(i).copied().unwrap_or(false) {
                continue;
            }
            uploads.compared += part.len() as u64;
            let Some((start, end)) = changed_span(&k.contents[at..offset], part) else {
                continue;
            };
            wrote = true;
            uploads.made += 1;
            if at % align != 0 || end % align != 0 {
                // Parts off the 4-byte grid (not made here): all of it, once.
                let all = parts.concat();
                self.gpu.queue.write_buffer(&k.buffer, 0, &all);
                uploads.bytes += all.len() as u64;
                k.contents = all;
                break;
            }
            let bytes = &part[start..end];
            self.gpu
                .queue
                .write_buffer(&k.buffer, (at + start) as u64, bytes);
            k.contents[at + start..at + end].copy_from_slice(bytes);
            uploads.bytes += bytes.len() as u64;
        }
        if !wrote {
            uploads.skipped += 1;
        }
        k.buffer.clone()
    }

    /// A buffer of `size` bytes and `usage` that node `owner`'s recipes keep
    /// under `label` across their re-creation (scratch a pass fills each
    /// frame, such as the compute rasterizer's 64-bit visibility buffer).
    /// Its contents are whatever the last frame left. Without an owner, a new one.
    pub fn kept_buffer(
        &self,
        owner: Option<u32>,
        label: &'static str,
        size: u64,
        usage: wgpu::BufferUsages,
    ) -> wgpu::Buffer {
        let fresh = || {
            self.gpu.device.create_buffer(&wgpu::BufferDescriptor {
                label: Some(label),
                size,
                usage,
                mapped_at_creation: false,
            })
        };
        let Some(owner) = owner else {
            return fresh();
        };
        let mut kept = self.kept.lock().unwrap_or_else(|e| e.into_inner());
        let fits = |k: &KeptBuffer| k.buffer.usage() == usage && k.buffer.size() == size;
        kept_entry(&mut kept, (owner, label, 0), fits, fresh)
            .0
            .buffer
            .clone()
    }

    /// Write `bytes` at the start of the buffer kept under node `owner`'s
    /// `label` ([`Renderer::kept_buffer`]), only the bytes that differ from
    /// what this last wrote there (counted as [`Renderer::uniform`]'s
    /// uploads): a recipe that fills its kept buffer as it declares, such as
    /// the G-buffer's camera, skips the write when nothing moved. A buffer
    /// that is not the one kept there (no owner, or replaced) is written whole.
    pub fn write_kept(
        &self,
        owner: Option<u32>,
        label: &'static str,
        buffer: &wgpu::Buffer,
        bytes: &[u8],
    ) {
        let mut uploads = self.uploads.lock().unwrap_or_else(|e| e.into_inner());
        let mut kept = self.kept.lock().unwrap_or_else(|e| e.into_inner());
        let entry = owner
            .and_then(|owner| kept.get_mut(&(owner, label, 0)))
            .filter(|k| k.buffer == *buffer);
        let span = match entry {
            Some(k) if k.contents.len() == bytes.len() => {
                uploads.compared += bytes.len() as u64;
                let span = changed_span(&k.contents, bytes);
                if let Some((start, end)) = span {
                    k.contents[start..end].copy_from_slice(&bytes[start..end]);
                }
                span
            }
            Some(k) => {
                k.contents = bytes.to_vec();
                Some((0, bytes.len()))
            }
            None => Some((0, bytes.len())),
        };
        match span {
            Some((start, end)) => {
                self.gpu
                    .queue
                    .write_buffer(buffer, start as u64, &bytes[start..end]);
                uploads.made += 1;
                uploads.bytes += (end - start) as u64;
            }
            None => uploads.skipped += 1,
        }
    }

    /// Kept-buffer writes made and skipped, the bytes written and compared,
    /// since the last call (the frame report's counters).
    pub(crate) fn take_uploads(&self) -> Uploads {
        std::mem::take(&mut *self.uploads.lock().unwrap_or_else(|e| e.into_inner()))
    }

    /// How frames are timed and recorded.
    pub fn settings(&self) -> (Timing, Recording) {
        *self.settings.lock().unwrap_or_else(|e| e.into_inner())
    }

    pub fn set_timing(&self, timing: Timing) {
        self.settings.lock().unwrap_or_else(|e| e.into_inner()).0 = timing;
    }

    pub fn set_recording(&self, recording: Recording) {
        self.settings.lock().unwrap_or_else(|e| e.into_inner()).1 = recording;
    }

    pub(crate) fn texture_pool(&self) -> std::sync::MutexGuard<'_, TexturePool> {
        self.textures.lock().unwrap_or_else(|e| e.into_inner())
    }

    pub(crate) fn timestamps(&self) -> Option<&Timestamps> {
        self.timestamps.as_ref()
    }

    pub(crate) fn set_last_report(&self, report: FrameReport) {
        *self.last_report.lock().unwrap_or_else(|e| e.into_inner()) = report;
    }

    /// Remember `submission`; wait until no more than `frames` are unfinished.
    pub(crate) fn throttle(
        &self,
        submission: wgpu::SubmissionIndex,
        frames: usize,
    ) -> Result<(), RenderError> {
        let mut in_flight = self.in_flight.lock().unwrap_or_else(|e| e.into_inner());
        in_flight.push_back(submission);
        while in_flight.len() > frames {
            if let Some(oldest) = in_flight.pop_front() {
                self.gpu
                    .device
                    .poll(wgpu::PollType::Wait {
                        submission_index: Some(oldest),
                        timeout: None,
                    })
                    .map_err(|e| RenderError::Readback(e.to_string()))?;
            }
        }
        Ok(())
    }

    /// Wait for every submission so far (frames in flight drained).
    pub fn wait_idle(&self) -> Result<(), RenderError> {
        self.in_flight
            .lock()
            .unwrap_or_else(|e| e.into_inner())
            .clear();
        self.gpu
            .device
            .poll(wgpu::PollType::wait_indefinitely())
            .map(|_| ())
            .map_err(|e| RenderError::Readback(e.to_string()))
    }

    /// The report of the last executed frame graph.
    pub fn last_report(&self) -> FrameReport {
        self.last_report
            .lock()
            .unwrap_or_else(|e| e.into_inner())
            .clone()
    }

    /// The errors of the last executed frame graph, by owner: what a host
    /// checks every frame, without copying the whole report (every pass's
    /// name and the counters) as [`Renderer::last_report`] does.
    pub fn last_errors(&self) -> Vec<(Option<u32>, String)> {
        self.last_report
            .lock()
            .unwrap_or_else(|e| e.into_inner())
            .errors
            .clone()
    }

    /// A persistent texture by its name (temporal history), if a frame made it:
    /// for tests and tools that inspect or seed history.
    pub fn persistent_texture(&self, name: &str) -> Option<wgpu::Texture> {
        self.textures
            .lock()
            .unwrap_or_else(|e| e.into_inner())
            .persistent
            .get(name)
            .map(|(_, t)| t.clone())
    }

    /// Forget persistent textures (a camera cut or a resize resets history).
    pub fn reset_history(&self) {
        self.textures
            .lock()
            .unwrap_or_else(|e| e.into_inner())
            .persistent
            .clear();
    }
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

/// The one way tests get a GPU: a headless renderer, or a panic that says how
/// to get one (never a silent skip).
pub fn test_renderer() -> std::sync::Arc<Renderer> {
    match Renderer::headless() {
        Ok(r) => std::sync::Arc::new(r),
        Err(e) => panic!("GPU tests need a GPU adapter: {e}"),
    }
}

#[cfg(test)]
mod tests {
    use super::changed_span;

    #[test]
    fn only_the_changed_bytes_are_written_on_4_byte_boundaries() {
        let old = vec![0u8; 1000];
        let mut new = old.clone();
        assert_eq!(changed_span(&old, &new), None);
        new[517] = 1;
        new[600] = 2;
        assert_eq!(changed_span(&old, &new), Some((516, 604)));
        new[0] = 3;
        new[999] = 4;
        assert_eq!(changed_span(&old, &new), Some((0, 1000)));
        // A length off the alignment is written whole.
        assert_eq!(changed_span(&[0; 6], &[0, 0, 0, 0, 0, 1]), Some((0, 6)));
    }
}
