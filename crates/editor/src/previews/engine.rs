//! The worker's side of the previews: which pins the runtime evaluates for
//! them, which textures the first viewport's frame graph also makes, and
//! the scaled images and probed texels it makes of them.
//!
//! A thumbnail watches its texture in the viewport's frame graph
//! ([`spreadlight_render::FrameGraph::watch`]): the patch's frame is the
//! same with thumbnails as without (no pass kept from being culled or
//! merged, no texture's usage or memory changed but that it is kept to the
//! end of the frame), and the thumbnail is scaled from what the frame made.
//! A texture the frame does not make (merged into the next pass, as Fog's
//! into Sky's; an output no pass reads) is requested instead, every
//! [`MERGED_EVERY`]th frame of a playing patch, and labelled so. A texture
//! that feeds no sink is made for its preview alone, as a request. The
//! hovered preview and a thumbnail under the pointer (whose texel is read
//! back) are requested every frame.

use std::collections::HashMap;
use std::sync::Arc;
use std::time::Instant;

use spreadlight_graph::{NodeId, ResourceKind, Runtime, Spread};
use spreadlight_render::gbuffer::{Channel, GBuffer, GBufferView};
use spreadlight_render::mesh_arena::GpuMesh;
use spreadlight_render::recipe::Recipe;
use spreadlight_render::{FrameReport, Renderer, TextureRef};

use super::schedule::{Candidate, Measured, Scheduler};
use super::{
    ChannelName, LARGE_PIXELS, MeshCounts, PreviewKey, PreviewOut, PreviewOuts, PreviewRequest,
    THUMB_PIXELS,
};
use crate::gpu::WorkerGpu;
use crate::viewport::{self, Blitter, ViewTarget};

/// Runs of the worker a preview no longer asked for keeps its texture, so
/// a frame the UI still draws never loses it; then it is freed.
const KEEP_RUNS: u32 = 120;

/// A thumbnail whose texture the patch's frame does not make is requested
/// (changing that frame: the pass that writes it no longer merges into the
/// next) once in this many frames of a playing patch.
pub const MERGED_EVERY: u64 = 30;

/// What a thumbnail of a texture the patch's frame does not make says.
pub const MERGED_NOTE: &str =
    "not made by the patch's frame (merged into the next pass): refreshed every 30th frame";

/// A preview this frame refreshes: what it shows, its source, and how it
/// gets its texture.
type Refreshed = (PreviewRequest, Result<Shown, String>, Option<Source>, Via);

/// How a refreshed preview gets its texture from the frame graph.
#[derive(Clone, Copy, PartialEq, Eq)]
enum Via {
    /// Watched: shown if the patch's frame makes it, which it leaves as it is.
    Watch,
    /// Requested: the hovered preview, a probed thumbnail, or a thumbnail the
    /// frame does not make (at its low rate).
    Request,
}

/// What a preview shows, found in the runtime.
enum Found {
    Texture(TextureRef),
    /// A G-buffer and the channel to show (its view is made only when refreshed).
    GBuffer(Arc<GBuffer>, ChannelName),
    /// A mesh's counts and, for the large preview, the mesh to turn.
    Mesh(MeshCounts, Option<Arc<GpuMesh>>),
}

/// What a preview shows, made ready for the frame graph.
enum Shown {
    Texture(TextureRef),
    /// A mesh's counts and its turntable (the first mesh's normals).
    Mesh(MeshCounts, Option<TextureRef>),
}

/// The image a preview shows, as far as telling an unchanged one goes: the
/// recipe that makes it (held, so no other can take its address) at the
/// frame's size. A node the runtime did not evaluate again keeps its
/// recipe, and a recipe makes the same image from the same inputs.
#[derive(Clone)]
pub enum Source {
    Texture(Arc<dyn Recipe>, String, (u32, u32)),
    GBuffer(Arc<GBuffer>, ChannelName, (u32, u32)),
}

impl PartialEq for Source {
    fn eq(&self, other: &Self) -> bool {
        match (self, other) {
            (Source::Texture(a, n, s), Source::Texture(b, m, t)) => {
                Arc::ptr_eq(a, b) && n == m && s == t
            }
            (Source::GBuffer(a, c, s), Source::GBuffer(b, d, t)) => {
                Arc::ptr_eq(a, b) && c == d && s == t
            }
            _ => false,
        }
    }
}

impl Found {
    fn source(&self, size: (u32, u32)) -> Option<Source> {
        match self {
            Found::Texture(t) => Some(Source::Texture(t.recipe.clone(), t.name.clone(), size)),
            Found::GBuffer(g, c) => Some(Source::GBuffer(g.clone(), *c, size)),
            Found::Mesh(..) => None,
        }
    }
}

/// A preview asked for this frame: what it shows and whether it is refreshed.
struct Resolved {
    request: PreviewRequest,
    found: Result<Found, String>,
    source: Option<Source>,
    refresh: bool,
}

struct Slot {
    out: PreviewOut,
    /// Worker runs since it was last asked for.
    idle: u32,
    /// The patch's frame did not make its texture when last watched.
    merged: bool,
    /// The frame ([`PreviewEngine::frames`]) it was last requested in as merged.
    forced_at: u64,
}

/// The previews the worker keeps.
#[derive(Default)]
pub struct PreviewEngine {
    requests: Vec<PreviewRequest>,
    slots: HashMap<PreviewKey, Slot>,
    /// The requests changed since they were last rendered.
    due: bool,
    /// Only the texels to probe changed: read them from the last frame's textures.
    reprobe: bool,
    /// The textures the last frame's previews showed, by key: valid until
    /// the next frame takes its pooled textures back.
    sources: HashMap<PreviewKey, wgpu::Texture>,
    /// Which thumbnails a frame refreshes (schedule.rs).
    schedule: Scheduler<Source>,
    /// The frame being worked on advances a playing patch: the thumbnails
    /// keep to their budget of its frame time.
    budgeted: bool,
    /// Frames rendered, for the merged thumbnails' low rate.
    frames: u64,
    /// Thumbnails (not live) scaled in the last frame rendered.
    scaled: usize,
}

impl PreviewEngine {
    /// Take the canvas's new wishes.
    pub fn set_requests(&mut self, requests: Vec<PreviewRequest>) {
        let same_previews = requests.len() == self.requests.len()
            && requests
                .iter()
                .zip(&self.requests)
                .all(|(a, b)| a.key == b.key);
        // A texel asked of a preview this frame did not render (skipped as
        // unchanged): its texture is gone to the pool, so it renders again.
        let unsourced = requests
            .iter()
            .any(|r| r.probe.is_some() && !self.sources.contains_key(&r.key));
        self.requests = requests;
        if same_previews && !self.due && !unsourced {
            // The pointer moved over a thumbnail: no frame to render for that.
            self.reprobe = true;
        } else {
            self.due = true;
        }
    }

    /// Read the texels under the pointer again from the last frame's
    /// textures, when only they changed (and no frame was rendered since).
    pub fn probe_again(&mut self, renderer: &Renderer, blitter: &Blitter) {
        if !std::mem::take(&mut self.reprobe) {
            return;
        }
        for r in &self.requests {
            let (Some(slot), Some(src)) = (self.slots.get_mut(&r.key), self.sources.get(&r.key))
            else {
                continue;
            };
            slot.out.value = r.probe.and_then(|uv| probe(renderer, blitter, src, uv));
        }
    }

    /// The output pins the previews look at (node path, pin), sorted, once each.
    pub fn pins(&self) -> Vec<(Vec<NodeId>, String)> {
        let mut pins: Vec<(Vec<NodeId>, String)> = self
            .requests
            .iter()
            .map(|r| (r.key.path.clone(), r.key.pin.clone()))
            .collect();
        pins.sort();
        pins.dedup();
        pins
    }

    /// Whether there are previews to render though the viewport has not
    /// changed: new wishes, or changed thumbnails a budgeted frame left.
    pub fn is_due(&self) -> bool {
        self.due || self.schedule.pending() > 0
    }

    /// Whether a budgeted frame left changed thumbnails for later: a patch
    /// paused meanwhile gets them in a frame of their own.
    pub fn has_pending(&self) -> bool {
        self.schedule.pending() > 0
    }

    /// Whether the next frame advances a playing patch (so the thumbnails keep
    /// to their budget) or not (all changed thumbnails are refreshed).
    pub fn set_budgeted(&mut self, budgeted: bool) {
        self.budgeted = budgeted;
    }

    /// The patch's frame time alone and one thumbnail's cost, as measured.
    pub fn measurements(&self) -> Measured {
        self.schedule.measurements()
    }

    pub fn is_empty(&self) -> bool {
        self.requests.is_empty()
    }

    /// What each preview shows, and which of them this frame refreshes
    /// (the schedule's pick; failures always, they cost nothing).
    fn resolve(&mut self, runtime: &Runtime, size: (u32, u32)) -> Vec<Resolved> {
        self.frames += 1;
        let found: Vec<(PreviewRequest, Result<Found, String>)> = self
            .requests
            .iter()
            .map(|r| (r.clone(), found(runtime, &r.key)))
            .collect();
        // A thumbnail the patch's frame does not make waits for its low rate
        // while the patch plays: no candidate until then.
        let waiting: Vec<bool> = found
            .iter()
            .map(|(r, _)| {
                self.budgeted
                    && !(r.key.large || r.probe.is_some())
                    && self.slots.get(&r.key).is_some_and(|s| {
                        s.merged && self.frames.saturating_sub(s.forced_at) < MERGED_EVERY
                    })
            })
            .collect();
        let candidates: Vec<Candidate<Source>> = found
            .iter()
            .zip(&waiting)
            .filter(|(_, waits)| !**waits)
            .filter_map(|((r, f), _)| {
                Some(Candidate {
                    key: r.key.clone(),
                    source: f.as_ref().ok()?.source(size),
                    live: r.key.large || r.probe.is_some(),
                })
            })
            .collect();
        let mut picked = self.schedule.pick(&candidates, self.budgeted).into_iter();
        found
            .into_iter()
            .zip(waiting)
            .map(|((r, f), waits)| {
                let source = f.as_ref().ok().and_then(|f| f.source(size));
                let refresh = !waits && (f.is_err() || picked.next().unwrap_or(true));
                Resolved {
                    request: r,
                    found: f,
                    source,
                    refresh,
                }
            })
            .collect()
    }

    /// Render the first viewport's `main` texture with every preview's in one
    /// frame graph at `size`, and scale each preview into its texture and
    /// `main` into `main_target`, all in the frame's own submission (each
    /// submission of the worker's may wait at the gate for a UI frame, and
    /// that wait is the patch's: one a frame, as without thumbnails).
    /// `time` (seconds) turns mesh turntables.
    /// Returns the frame's report, or the error of `main`'s frame or blit
    /// (None when there was nothing to render). A preview that breaks the
    /// joint frame does not take the viewport with it: `main` is rendered
    /// again alone.
    pub fn render(
        &mut self,
        runtime: &Runtime,
        gpu: &WorkerGpu,
        (main, main_target): (Option<&TextureRef>, &mut Option<ViewTarget>),
        size: (u32, u32),
        time: f64,
    ) -> Option<Result<FrameReport, viewport::ViewportError>> {
        let (render_state, renderer, blitter) = (&gpu.state, &gpu.renderer, &gpu.blitter);
        let started = Instant::now();
        self.due = false;
        self.reprobe = false;
        self.sources.clear();
        self.scaled = 0;
        let resolved = self.resolve(runtime, size);
        // One G-buffer view per (G-buffer, channel): the large and the small
        // preview of a channel share its pass.
        let mut views: HashMap<(usize, usize), TextureRef> = HashMap::new();
        let resolved: Vec<Refreshed> = resolved
            .into_iter()
            .filter(|r| r.refresh)
            .map(
                |Resolved {
                     request,
                     found,
                     source,
                     ..
                 }| {
                    let shown = found.map(|f| made(renderer, f, &mut views, time));
                    let live = request.key.large || request.probe.is_some();
                    let merged = self.slots.get(&request.key).is_some_and(|s| s.merged);
                    let via = if live || merged {
                        Via::Request
                    } else {
                        Via::Watch
                    };
                    (request, shown, source, via)
                },
            )
            .collect();
        let mut textures: Vec<&TextureRef> = main.into_iter().collect();
        let mut watched: Vec<&TextureRef> = Vec::new();
        for (_, shown, _, via) in &resolved {
            if let Ok(Shown::Texture(t) | Shown::Mesh(_, Some(t))) = shown {
                let list = match via {
                    Via::Request => &mut textures,
                    Via::Watch => &mut watched,
                };
                if !list.iter().any(|u| u.name == t.name) {
                    list.push(t);
                }
            }
        }
        if textures.is_empty() && watched.is_empty() {
            // Nothing to render; what failed to resolve still says why.
            self.scale(&resolved, None, gpu, &mut Vec::new());
            self.age();
            return None;
        }
        let mut main_shown = None;
        let mut probes = Vec::new();
        let frame = viewport::render_frame_then(renderer, &textures, &watched, size, |outputs| {
            let mut batch = Vec::new();
            probes = self.scale(&resolved, Some(outputs), gpu, &mut batch);
            main_shown = main.map(|m| match outputs.get(&m.name) {
                Some(src) => viewport::show_in_batch(
                    render_state,
                    renderer,
                    blitter,
                    src,
                    (src.width(), src.height()),
                    main_target,
                    &mut batch,
                ),
                None => Err(viewport::ViewportError::Missing(m.name.clone())),
            });
            batch
        });
        let report = match frame {
            Ok((report, _)) => report,
            Err(e) if textures.len() > 1 || !watched.is_empty() => {
                // The previews' error; the viewport renders on its own.
                let alone = main.map(|m| {
                    viewport::render_into(render_state, renderer, blitter, m, size, main_target)
                });
                for (request, _, _, _) in &resolved {
                    slot(&mut self.slots, &request.key).out.error = Some(e.to_string());
                    // Tried again in the next frame, not taken as shown.
                    self.schedule.refreshed(&request.key, None);
                    self.sources.remove(&request.key);
                }
                self.scaled = 0;
                self.age();
                return alone;
            }
            Err(e) => {
                // `main`'s own frame failed: the previews say so too.
                self.scale(&resolved, None, gpu, &mut Vec::new());
                self.age();
                return Some(Err(e));
            }
        };
        // A frame that read its timestamps back has waited for its passes
        // and these blits (one submission). One that did not is waited for
        // here, so the scaling is timed with the frame it belongs to, not the
        // next (a failed wait only shifts a sample to the next frame). Not
        // both: a second wait for the whole queue also waited for the UI's
        // paint submitted meanwhile, and only when thumbnails were scaled.
        if self.budgeted && self.scaled > 0 && report.gpu_frame_ms.is_none() {
            let _ = renderer
                .gpu
                .device
                .poll(wgpu::PollType::wait_indefinitely());
        }
        // The texels under the pointer, after the thumbnails (each waits for the GPU).
        for (key, uv) in probes {
            if let (Some(src), Some(slot)) = (self.sources.get(&key), self.slots.get_mut(&key)) {
                slot.out.value = probe(renderer, blitter, src, uv);
            }
        }
        if self.budgeted {
            self.schedule
                .measured(started.elapsed().as_secs_f64() * 1e3, self.scaled);
        }
        self.age();
        Some(match main_shown {
            Some(Err(e)) => Err(e),
            _ => Ok(report),
        })
    }

    /// Thumbnails (not live) scaled in the last frame rendered.
    pub fn scaled(&self) -> usize {
        self.scaled
    }

    /// Record each refreshed preview's blit from the frame's `outputs` into
    /// `batch` (None: no frame was rendered) and note what it shows; returns
    /// the texels to probe once the frame is done.
    fn scale(
        &mut self,
        resolved: &[Refreshed],
        outputs: Option<&HashMap<String, wgpu::Texture>>,
        gpu: &WorkerGpu,
        batch: &mut Vec<wgpu::CommandBuffer>,
    ) -> Vec<(PreviewKey, (f32, f32))> {
        let (render_state, renderer, blitter) = (&gpu.state, &gpu.renderer, &gpu.blitter);
        let mut probes = Vec::new();
        let frames = self.frames;
        for (request, shown, source, via) in resolved {
            let slot = slot(&mut self.slots, &request.key);
            slot.out.mesh = None;
            slot.out.error = None;
            slot.out.value = None;
            if let Ok(Shown::Mesh(counts, _)) = shown {
                slot.out.mesh = Some(*counts);
            }
            match shown {
                Err(e) => slot.out.error = Some(e.clone()),
                Ok(Shown::Mesh(_, None)) => {}
                Ok(Shown::Mesh(_, Some(t)) | Shown::Texture(t)) => {
                    let Some(src) = outputs.and_then(|o| o.get(&t.name)) else {
                        if *via == Via::Watch && outputs.is_some() {
                            // The patch's frame merged it away (or left it
                            // unwritten): requested at the low rate from now
                            // on, at once when the thumbnail shows nothing yet.
                            slot.merged = true;
                            slot.out.note = Some(MERGED_NOTE.to_owned());
                            if slot.out.target.is_none() {
                                slot.forced_at = frames.saturating_sub(MERGED_EVERY);
                            }
                        } else {
                            slot.out.error = Some(format!("the frame produced no `{}`", t.name));
                        }
                        continue;
                    };
                    let live = request.key.large || request.probe.is_some();
                    if slot.merged && !live {
                        // Requested at its low rate; watched again next time
                        // (the patch may have changed so that it is made).
                        slot.merged = false;
                        slot.forced_at = frames;
                    } else if *via == Via::Watch {
                        slot.out.note = None;
                    }
                    let src_size = (src.width().max(1), src.height().max(1));
                    slot.out.source = Some((src_size, src.format()));
                    let width = if request.key.large {
                        LARGE_PIXELS
                    } else {
                        THUMB_PIXELS
                    };
                    let size = preview_pixels(src_size, width);
                    if let Err(e) = viewport::show_in_batch(
                        render_state,
                        renderer,
                        blitter,
                        src,
                        size,
                        &mut slot.out.target,
                        batch,
                    ) {
                        slot.out.error = Some(e.to_string());
                        continue;
                    }
                    if let Some(uv) = request.probe {
                        probes.push((request.key.clone(), uv));
                    }
                    self.scaled += usize::from(!live);
                    self.sources.insert(request.key.clone(), src.clone());
                    // Shown: skipped from now on while its source stays the same.
                    self.schedule.refreshed(&request.key, source.clone());
                }
            }
        }
        probes
    }

    /// Count a run for every preview not asked for.
    fn age(&mut self) {
        let asked: Vec<&PreviewKey> = self.requests.iter().map(|r| &r.key).collect();
        for (key, slot) in &mut self.slots {
            if !asked.contains(&key) {
                slot.idle += 1;
            }
        }
    }

    /// Free the egui textures of previews unused for [`KEEP_RUNS`] runs.
    pub fn free_stale(&mut self, render_state: &egui_wgpu::RenderState) {
        let stale: Vec<PreviewKey> = self
            .slots
            .iter()
            .filter(|(_, s)| s.idle > KEEP_RUNS)
            .map(|(k, _)| k.clone())
            .collect();
        for key in stale {
            self.schedule.forget(&key);
            if let Some(slot) = self.slots.remove(&key)
                && let Some(target) = slot.out.target
            {
                render_state.renderer.write().free_texture(&target.id);
            }
        }
    }

    /// The previews asked for, as the UI reads them.
    pub fn outputs(&self) -> PreviewOuts {
        Arc::new(
            self.requests
                .iter()
                .filter_map(|r| Some((r.key.clone(), self.slots.get(&r.key)?.out.clone())))
                .collect(),
        )
    }
}

/// The preview of `key`, kept or new, marked as asked for.
fn slot<'s>(slots: &'s mut HashMap<PreviewKey, Slot>, key: &PreviewKey) -> &'s mut Slot {
    let slot = slots.entry(key.clone()).or_insert_with(|| Slot {
        out: PreviewOut::default(),
        idle: 0,
        merged: false,
        forced_at: 0,
    });
    slot.idle = 0;
    slot
}

/// The texel of `src` at `uv` (0..1 from the top left) and its value.
fn probe(
    renderer: &Renderer,
    blitter: &Blitter,
    src: &wgpu::Texture,
    (u, v): (f32, f32),
) -> Option<((u32, u32), [f32; 4])> {
    let (w, h) = (src.width().max(1), src.height().max(1));
    let texel = (
        ((u.clamp(0.0, 1.0) * w as f32) as u32).min(w - 1),
        ((v.clamp(0.0, 1.0) * h as f32) as u32).min(h - 1),
    );
    blitter
        .probe(&renderer.gpu, src, texel)
        .ok()
        .map(|value| (texel, value))
}

/// A preview's pixel size: `width` wide (never wider than the source), the
/// source's aspect.
pub fn preview_pixels(source: (u32, u32), width: u32) -> (u32, u32) {
    let w = width.min(source.0).max(1);
    let h = (u64::from(w) * u64::from(source.1) / u64::from(source.0.max(1)))
        .clamp(1, u64::from(width)) as u32;
    (w, h)
}

/// A found preview made ready for the frame graph: a G-buffer's channel
/// view, a mesh's turntable.
fn made(
    renderer: &Renderer,
    found: Found,
    views: &mut HashMap<(usize, usize), TextureRef>,
    time: f64,
) -> Shown {
    match found {
        Found::Texture(t) => Shown::Texture(t),
        Found::GBuffer(gbuffer, channel) => {
            let view = views
                .entry((Arc::as_ptr(&gbuffer) as usize, channel.0))
                .or_insert_with(|| {
                    GBufferView::new(renderer, None, gbuffer, channel.channel(), 20.0).texture()
                });
            Shown::Texture(view.clone())
        }
        Found::Mesh(counts, mesh) => {
            Shown::Mesh(counts, mesh.map(|mesh| turntable(renderer, mesh, time)))
        }
    }
}

/// What the pin of `key` holds, as a preview shows it.
fn found(runtime: &Runtime, key: &PreviewKey) -> Result<Found, String> {
    let network = runtime.network();
    let index = network
        .index_at(&key.path)
        .or_else(|| network.instance_output(&key.path, &key.pin))
        .ok_or_else(|| "not in the running patch".to_owned())?;
    if !runtime.is_demanded(index) {
        return Err("not evaluated".to_owned());
    }
    let spread = runtime
        .output_at(&key.path, &key.pin)
        .ok_or_else(|| "not evaluated".to_owned())?;
    let Spread::Resource(kind, handles) = &**spread else {
        return Err("not a texture, G-buffer or mesh".to_owned());
    };
    let empty = || "empty (the node made nothing this frame)".to_owned();
    match kind {
        ResourceKind::Texture => handles
            .first()
            .ok_or_else(empty)?
            .downcast_arc::<TextureRef>()
            .map(|t| Found::Texture((*t).clone()))
            .ok_or_else(|| "holds something other than a texture".to_owned()),
        ResourceKind::GBuffer => {
            let gbuffer = handles
                .first()
                .ok_or_else(empty)?
                .downcast_arc::<GBuffer>()
                .ok_or_else(|| "holds something other than a G-buffer".to_owned())?;
            Ok(Found::GBuffer(gbuffer, key.channel.unwrap_or_default()))
        }
        ResourceKind::Mesh => {
            let mut counts = MeshCounts {
                meshes: 0,
                vertices: 0,
                triangles: 0,
            };
            let mut first = None;
            for h in handles {
                let mesh = h
                    .downcast_arc::<GpuMesh>()
                    .ok_or_else(|| "holds something other than a mesh".to_owned())?;
                counts.meshes += 1;
                // A procedural mesh's vertices are made in the shaders: its records are not vertices.
                if !mesh.is_procedural() {
                    counts.vertices += u64::from(mesh.vertices.end - mesh.vertices.start);
                }
                counts.triangles += u64::from(mesh.index_count() / 3);
                first.get_or_insert(mesh);
            }
            // The large preview turns the first mesh; a thumbnail has none.
            Ok(Found::Mesh(counts, first.filter(|_| key.large)))
        }
        _ => Err("has no preview".to_owned()),
    }
}

/// Pixels of a mesh's turntable (square).
const TURNTABLE_PIXELS: u32 = 256;

/// `mesh` drawn by the renderer's own G-buffer from a camera circling it
/// once every 8 seconds of patch time, shown as its normals.
fn turntable(renderer: &Renderer, mesh: Arc<GpuMesh>, time: f64) -> TextureRef {
    use glam::{Mat4, Vec3};
    use spreadlight_render::camera::CameraInput;
    use spreadlight_render::frame_graph::SizeRule;
    use spreadlight_render::gbuffer::{DrawBatch, InstanceInput, Layer};
    let (min, max) = (mesh.bounds.min, mesh.bounds.max);
    let finite = min.is_finite() && max.is_finite() && min.cmple(max).all();
    let (centre, radius) = if finite {
        ((min + max) * 0.5, ((max - min).length() * 0.5).max(1e-3))
    } else {
        (Vec3::ZERO, 1.0)
    };
    let angle = (time / 8.0).fract() as f32 * std::f32::consts::TAU;
    let eye = centre + radius * 2.6 * Vec3::new(angle.sin(), 0.45, angle.cos());
    let camera = CameraInput {
        view: glam::camera::rh::view::look_at_mat4(eye, centre, Vec3::Y),
        projection: glam::camera::rh::proj::directx::perspective(
            std::f32::consts::FRAC_PI_4,
            1.0,
            radius * 0.05,
            radius * 10.0,
        ),
    };
    let layer = Layer::plain(vec![DrawBatch {
        mesh,
        instances: vec![InstanceInput {
            transform: Mat4::IDENTITY,
            previous_transform: Mat4::IDENTITY,
            color: [0.8, 0.8, 0.8, 1.0],
            material_id: 0,
            object_id: 0,
        }],
    }]);
    let size = SizeRule::Absolute {
        width: TURNTABLE_PIXELS,
        height: TURNTABLE_PIXELS,
    };
    let gbuffer = GBuffer::new(renderer, None, vec![Arc::new(layer)], camera, None, size);
    GBufferView::new(renderer, None, gbuffer, Channel::Normals, 1.0).texture()
}
