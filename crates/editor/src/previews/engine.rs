//! The worker's side of the previews: which pins the runtime evaluates for
//! them, which textures the first viewport's frame graph also requests, and
//! the scaled images and probed texels it makes of them.

use std::collections::HashMap;
use std::sync::Arc;

use spreadlight_graph::{NodeId, ResourceKind, Runtime, Spread};
use spreadlight_render::gbuffer::{Channel, GBuffer, GBufferView};
use spreadlight_render::mesh_arena::GpuMesh;
use spreadlight_render::{Renderer, TextureRef};

use super::{
    LARGE_PIXELS, MeshCounts, PreviewKey, PreviewOut, PreviewOuts, PreviewRequest, THUMB_PIXELS,
};
use crate::viewport::{self, Blitter, RenderedFrame};

/// Runs of the worker a preview no longer asked for keeps its texture, so
/// a frame the UI still draws never loses it; then it is freed.
const KEEP_RUNS: u32 = 120;

/// What a preview shows, found in the runtime.
enum Shown {
    Texture(TextureRef),
    /// A mesh's counts and its turntable (the first mesh's normals).
    Mesh(MeshCounts, Option<TextureRef>),
}

struct Slot {
    out: PreviewOut,
    /// Worker runs since it was last asked for.
    idle: u32,
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
}

impl PreviewEngine {
    /// Take the canvas's new wishes.
    pub fn set_requests(&mut self, requests: Vec<PreviewRequest>) {
        let same_previews = requests.len() == self.requests.len()
            && requests
                .iter()
                .zip(&self.requests)
                .all(|(a, b)| a.key == b.key);
        self.requests = requests;
        if same_previews && !self.due {
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

    /// Whether there are previews to render though the viewport has not changed.
    pub fn is_due(&self) -> bool {
        self.due
    }

    pub fn is_empty(&self) -> bool {
        self.requests.is_empty()
    }

    /// The textures this frame's previews show, to request in the viewport's
    /// frame graph, and what the rest (meshes, failures) are.
    fn resolve(
        &self,
        runtime: &Runtime,
        renderer: &Renderer,
        time: f64,
    ) -> Vec<(PreviewRequest, Result<Shown, String>)> {
        // One G-buffer view per (G-buffer, channel): the large and the small
        // preview of a channel share its pass.
        let mut views: HashMap<(usize, usize), TextureRef> = HashMap::new();
        self.requests
            .iter()
            .map(|r| {
                let shown = shown(runtime, renderer, &r.key, &mut views, time);
                (r.clone(), shown)
            })
            .collect()
    }

    /// Render the first viewport's `main` texture with every preview's in one
    /// frame graph at `size`, then scale each preview into its texture.
    /// `time` (seconds) turns mesh turntables.
    /// Returns the frame (for the viewport to show `main` from) or the
    /// error of `main`'s frame. A preview that breaks the joint frame does
    /// not take the viewport with it: `main` is rendered again alone.
    pub fn render(
        &mut self,
        runtime: &Runtime,
        gpu: &crate::worker::WorkerGpu,
        main: Option<&TextureRef>,
        size: (u32, u32),
        time: f64,
    ) -> Option<Result<RenderedFrame, viewport::ViewportError>> {
        let (render_state, renderer, blitter) = (&gpu.state, &gpu.renderer, &gpu.blitter);
        self.due = false;
        self.reprobe = false;
        self.sources.clear();
        let resolved = self.resolve(runtime, renderer, time);
        let mut textures: Vec<&TextureRef> = main.into_iter().collect();
        for (_, shown) in &resolved {
            if let Ok(Shown::Texture(t) | Shown::Mesh(_, Some(t))) = shown
                && !textures.iter().any(|u| u.name == t.name)
            {
                textures.push(t);
            }
        }
        let frame = if textures.is_empty() {
            None
        } else {
            match viewport::render_frame(renderer, &textures, size) {
                Ok(frame) => Some(Ok(frame)),
                Err(e) if textures.len() > 1 => {
                    // The previews' error; the viewport renders on its own.
                    let alone = main.map(|m| viewport::render_frame(renderer, &[m], size));
                    for (request, _) in &resolved {
                        slot(&mut self.slots, &request.key).out.error = Some(e.to_string());
                    }
                    self.age();
                    return alone;
                }
                Err(e) => Some(Err(e)),
            }
        };
        let outputs = frame.as_ref().and_then(|f| f.as_ref().ok()).map(|f| &f.1);
        // Every thumbnail's blit in one submission (each may wait at the gate).
        let mut batch = Vec::new();
        let mut probes = Vec::new();
        for (request, shown) in resolved {
            let slot = slot(&mut self.slots, &request.key);
            slot.out.mesh = None;
            slot.out.error = None;
            slot.out.value = None;
            if let Ok(Shown::Mesh(counts, _)) = &shown {
                slot.out.mesh = Some(*counts);
            }
            match shown {
                Err(e) => slot.out.error = Some(e),
                Ok(Shown::Mesh(_, None)) => {}
                Ok(Shown::Mesh(_, Some(t)) | Shown::Texture(t)) => {
                    let Some(src) = outputs.and_then(|o| o.get(&t.name)) else {
                        slot.out.error = Some(format!("the frame produced no `{}`", t.name));
                        continue;
                    };
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
                        &mut batch,
                    ) {
                        slot.out.error = Some(e.to_string());
                        continue;
                    }
                    if let Some(uv) = request.probe {
                        probes.push((request.key.clone(), uv));
                    }
                    self.sources.insert(request.key.clone(), src.clone());
                }
            }
        }
        renderer.gpu.submit(batch);
        // The texels under the pointer, after the thumbnails (each waits for the GPU).
        for (key, uv) in probes {
            if let (Some(src), Some(slot)) = (self.sources.get(&key), self.slots.get_mut(&key)) {
                slot.out.value = probe(renderer, blitter, src, uv);
            }
        }
        self.age();
        frame
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

/// What the pin of `key` holds, as a preview shows it.
fn shown(
    runtime: &Runtime,
    renderer: &Renderer,
    key: &PreviewKey,
    views: &mut HashMap<(usize, usize), TextureRef>,
    time: f64,
) -> Result<Shown, String> {
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
            .map(|t| Shown::Texture((*t).clone()))
            .ok_or_else(|| "holds something other than a texture".to_owned()),
        ResourceKind::GBuffer => {
            let gbuffer = handles
                .first()
                .ok_or_else(empty)?
                .downcast_arc::<GBuffer>()
                .ok_or_else(|| "holds something other than a G-buffer".to_owned())?;
            let channel = key.channel.unwrap_or_default();
            let view = views
                .entry((Arc::as_ptr(&gbuffer) as usize, channel.0))
                .or_insert_with(|| {
                    GBufferView::new(renderer, None, gbuffer, channel.channel(), 20.0).texture()
                });
            Ok(Shown::Texture(view.clone()))
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
            let turntable = first
                .filter(|_| key.large)
                .map(|mesh| turntable(renderer, mesh, time));
            Ok(Shown::Mesh(counts, turntable))
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
