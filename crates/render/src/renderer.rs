//! The renderer: the shared GPU context plus what lives across frames: the
//! shader permutation cache, the texture pool, persistent textures, the mesh
//! arena, the timestamp queries, and the last frame's report.
//!
//! Nodes hold it behind an `Arc` and call it from their evaluation; its
//! interior state is behind mutexes so it is shared, not cloned.

use std::collections::{HashMap, HashSet};
use std::sync::{Arc, Mutex};

use crate::context::GpuContext;
use crate::error::RenderError;
use crate::frame_graph::{self, FrameGraph, FrameReport, Lifetime, PassReport, TextureKey};
use crate::mesh_arena::MeshArena;
use crate::shaders::{ShaderCache, ShaderComposer};

const MAX_QUERIES: u32 = 512;

struct Timestamps {
    set: wgpu::QuerySet,
    resolve: wgpu::Buffer,
    readback: wgpu::Buffer,
}

#[derive(Default)]
struct Textures {
    pool: HashMap<TextureKey, Vec<wgpu::Texture>>,
    persistent: HashMap<String, (TextureKey, wgpu::Texture)>,
    /// Per persistent texture: frame graphs run since a pass last wrote it.
    idle: HashMap<String, u32>,
    /// Last frame's requested outputs: handed to the caller, back to the pool next frame.
    lent: Vec<(TextureKey, wgpu::Texture)>,
}

/// Frame graphs a persistent texture may go unwritten before it is dropped:
/// about a second at 60 frames a second, so a node briefly culled (an editor
/// viewport looking elsewhere) keeps its history.
pub const PERSISTENT_IDLE_GRAPHS: u32 = 60;

pub struct Renderer {
    pub gpu: GpuContext,
    shaders: Mutex<ShaderCache>,
    textures: Mutex<Textures>,
    pub meshes: MeshArena,
    timestamps: Option<Timestamps>,
    last_report: Mutex<FrameReport>,
    output_size: Mutex<(u32, u32)>,
    /// What recipes keep between frames (shadow maps), by type and key.
    states: Mutex<HashMap<(std::any::TypeId, u64), Arc<dyn std::any::Any + Send + Sync>>>,
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
            textures: Mutex::new(Textures::default()),
            meshes,
            timestamps,
            last_report: Mutex::new(FrameReport::default()),
            output_size: Mutex::new(DEFAULT_OUTPUT_SIZE),
            states: Mutex::new(HashMap::new()),
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

    /// The report of the last executed frame graph.
    pub fn last_report(&self) -> FrameReport {
        self.last_report
            .lock()
            .unwrap_or_else(|e| e.into_inner())
            .clone()
    }

    fn create_texture(&self, key: &TextureKey, label: &str) -> wgpu::Texture {
        self.gpu.device.create_texture(&wgpu::TextureDescriptor {
            label: Some(label),
            size: wgpu::Extent3d {
                width: key.width,
                height: key.height,
                depth_or_array_layers: 1,
            },
            mip_level_count: 1,
            sample_count: 1,
            dimension: wgpu::TextureDimension::D2,
            format: key.format,
            usage: key.usage,
            view_formats: &[],
        })
    }

    pub(crate) fn execute_graph(
        &self,
        graph: FrameGraph<'_>,
    ) -> Result<(FrameReport, HashMap<String, wgpu::Texture>), RenderError> {
        let started = std::time::Instant::now();
        let output_size = graph.output_size();
        let mut textures = self.textures.lock().unwrap_or_else(|e| e.into_inner());
        let lent = std::mem::take(&mut textures.lent);
        for (key, texture) in lent {
            textures.pool.entry(key).or_default().push(texture);
        }
        let persistent_names: HashSet<String> = textures.persistent.keys().cloned().collect();
        let mut parts = graph.into_parts(&persistent_names)?;

        // Where each texture is last read, so temporaries go back to the pool after it.
        let mut last_use: HashMap<&str, usize> = HashMap::new();
        for (step, &p) in parts.order.iter().enumerate() {
            for name in parts.reads[p]
                .iter()
                .chain(parts.writes[p].iter().map(|(n, _)| n))
            {
                last_use.insert(name.as_str(), step);
            }
        }
        let requested: HashSet<&str> = parts.requested.iter().map(String::as_str).collect();

        let mut live: HashMap<String, wgpu::Texture> = parts.imports.clone();
        for (name, (_, texture)) in &textures.persistent {
            live.insert(name.clone(), texture.clone());
        }
        let mut fresh = HashSet::new();
        let mut report = FrameReport {
            adapter: self.gpu.adapter_name(),
            ..Default::default()
        };
        for (name, n) in std::mem::take(&mut parts.counters) {
            *report.counters.entry(name.to_owned()).or_default() += n;
        }
        let mut owned: Vec<(String, TextureKey, Lifetime)> = Vec::new();
        let mut commands = Vec::new();
        let mut pass_queries: Vec<(usize, Vec<(u32, u32)>)> = Vec::new();
        let mut next_query = 0u32;
        let mut shaders = self.shaders();
        let compiled_before = shaders.pipelines_compiled;

        for (step, &p) in parts.order.clone().iter().enumerate() {
            for ((name, desc), key) in parts.writes[p].iter().zip(&parts.keys[p]) {
                let texture = match desc.lifetime {
                    Lifetime::Persistent => match textures.persistent.get(name) {
                        Some((k, t)) if k == key => t.clone(),
                        _ => {
                            let t = self.create_texture(key, name);
                            report.textures_created += 1;
                            textures.persistent.insert(name.clone(), (*key, t.clone()));
                            fresh.insert(name.clone());
                            t
                        }
                    },
                    Lifetime::Temporary | Lifetime::Permanent => {
                        match textures.pool.get_mut(key).and_then(Vec::pop) {
                            Some(t) => t,
                            None => {
                                report.textures_created += 1;
                                self.create_texture(key, name)
                            }
                        }
                    }
                };
                if desc.lifetime == Lifetime::Persistent {
                    textures.idle.insert(name.clone(), 0);
                } else {
                    owned.push((name.clone(), *key, desc.lifetime));
                }
                live.insert(name.clone(), texture);
            }

            let encoder = self
                .gpu
                .device
                .create_command_encoder(&wgpu::CommandEncoderDescriptor {
                    label: Some(&parts.names[p]),
                });
            let scope = self
                .gpu
                .device
                .push_error_scope(wgpu::ErrorFilter::Validation);
            let capacity = if self.timestamps.is_some() {
                MAX_QUERIES
            } else {
                0
            };
            let mut cx = frame_graph::PassContext {
                gpu: &self.gpu,
                encoder,
                shaders: &mut shaders,
                textures: &live,
                fresh: &fresh,
                timestamps: self.timestamps.as_ref().map(|t| &t.set),
                queries: Vec::new(),
                next_query: &mut next_query,
                query_capacity: capacity,
                draws: 0,
                output_size,
                counters: Default::default(),
            };
            let run = parts.runs[p].take();
            let result = match run {
                Some(run) => run(&mut cx),
                None => Ok(()),
            };
            let frame_graph::Recorded {
                commands: buffer,
                queries,
                draws,
                counters,
            } = cx.finish();
            for (name, n) in counters {
                *report.counters.entry(name.to_owned()).or_default() += n;
            }
            let validation = pollster::block_on(scope.pop());
            let error = match (result, validation) {
                (Err(e), _) => Some(e.to_string()),
                (Ok(()), Some(e)) => Some(
                    RenderError::Validation {
                        pass: parts.names[p].clone(),
                        message: e.to_string(),
                    }
                    .to_string(),
                ),
                (Ok(()), None) => None,
            };
            match error {
                Some(message) => report.errors.push((
                    parts.owners[p],
                    format!("pass `{}`: {message}", parts.names[p]),
                )),
                None => {
                    commands.push(buffer);
                    pass_queries.push((report.passes.len(), queries));
                }
            }
            report.draws += draws;
            report.passes.push(PassReport {
                name: parts.names[p].clone(),
                owner: parts.owners[p],
                gpu_ms: None,
                draws,
            });

            // Temporaries whose last reader has recorded go back to the pool.
            owned.retain(|(name, key, lifetime)| {
                let done = *lifetime == Lifetime::Temporary
                    && last_use.get(name.as_str()).is_some_and(|&s| s <= step)
                    && !requested.contains(name.as_str());
                if done && let Some(t) = live.get(name) {
                    textures.pool.entry(*key).or_default().push(t.clone());
                }
                !done
            });
        }
        report.culled = parts
            .culled
            .iter()
            .map(|&p| parts.names[p].clone())
            .collect();
        report.pipelines_compiled = shaders.pipelines_compiled - compiled_before;
        drop(shaders);

        if let (Some(ts), true) = (&self.timestamps, next_query > 0) {
            let mut encoder = self.gpu.device.create_command_encoder(&Default::default());
            encoder.resolve_query_set(&ts.set, 0..next_query, &ts.resolve, 0);
            encoder.copy_buffer_to_buffer(
                &ts.resolve,
                0,
                &ts.readback,
                0,
                u64::from(next_query) * 8,
            );
            commands.push(encoder.finish());
        }
        self.gpu.queue.submit(commands);
        report.record_ms = started.elapsed().as_secs_f64() * 1e3;

        if let (Some(ts), true) = (&self.timestamps, next_query > 0) {
            let ticks = read_buffer(&self.gpu, &ts.readback, u64::from(next_query) * 8)?;
            let ticks: Vec<u64> = ticks
                .chunks_exact(8)
                .map(|c| u64::from_le_bytes(c.try_into().unwrap_or([0; 8])))
                .collect();
            let period_ns = f64::from(self.gpu.queue.get_timestamp_period());
            let written: Vec<u64> = pass_queries
                .iter()
                .flat_map(|(_, q)| {
                    q.iter()
                        .flat_map(|&(b, e)| [ticks[b as usize], ticks[e as usize]])
                })
                .collect();
            if let (Some(first), Some(last)) = (written.iter().min(), written.iter().max()) {
                report.gpu_frame_ms = Some(last.saturating_sub(*first) as f64 * period_ns / 1e6);
            }
            let mut total = 0.0;
            for (index, queries) in pass_queries {
                let ms: f64 = queries
                    .iter()
                    .map(|&(b, e)| {
                        ticks[e as usize].saturating_sub(ticks[b as usize]) as f64 * period_ns / 1e6
                    })
                    .sum();
                report.passes[index].gpu_ms = Some(ms);
                total += ms;
            }
            report.gpu_ms = Some(total);
        }

        // History exists only for effects that run: a persistent texture no pass
        // has written for a while (its node deleted, culled, or switched to
        // another mode) is dropped.
        let textures = &mut *textures;
        let mut dropped = 0;
        for name in textures.persistent.keys().cloned().collect::<Vec<_>>() {
            let idle = textures.idle.entry(name.clone()).or_insert(0);
            if parts
                .order
                .iter()
                .any(|&p| parts.writes[p].iter().any(|(n, _)| *n == name))
            {
                continue;
            }
            *idle += 1;
            if *idle > PERSISTENT_IDLE_GRAPHS {
                textures.persistent.remove(&name);
                textures.idle.remove(&name);
                dropped += 1;
            }
        }
        if dropped > 0 {
            *report
                .counters
                .entry("histories dropped".to_owned())
                .or_default() += dropped;
        }

        // Requested outputs go to the caller and come back to the pool next frame;
        // other permanent textures return now.
        let mut outputs = HashMap::new();
        for (name, key, _) in owned {
            if let Some(texture) = live.get(&name) {
                if requested.contains(name.as_str()) {
                    textures.lent.push((key, texture.clone()));
                } else {
                    textures.pool.entry(key).or_default().push(texture.clone());
                }
            }
        }
        for name in &parts.requested {
            if let Some(t) = live.get(name) {
                outputs.insert(name.clone(), t.clone());
            }
        }
        report.wait_ms = (started.elapsed().as_secs_f64() * 1e3 - report.record_ms).max(0.0);
        *self.last_report.lock().unwrap_or_else(|e| e.into_inner()) = report.clone();
        Ok((report, outputs))
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
