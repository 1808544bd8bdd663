//! What tests and the CLI read of the editor: the document, the latest
//! patch frame, where things were drawn, the viewports and the timings.

use super::*;

impl EditorApp {
    pub fn doc(&self) -> &EditorDoc {
        &self.doc
    }

    pub fn doc_mut(&mut self) -> &mut EditorDoc {
        &mut self.doc
    }

    pub fn path(&self) -> Option<&Path> {
        self.path.as_deref()
    }

    /// The runtime as of the latest finished patch frame (the runtime itself
    /// lives on the worker thread).
    pub fn runtime(&self) -> &RuntimeSnapshot {
        &self.frame.runtime
    }

    pub fn registry(&self) -> &Registry {
        &self.registry
    }

    pub fn status(&self) -> &str {
        &self.status
    }

    pub fn title(&self) -> String {
        let name = self.path.as_ref().and_then(|p| p.file_name()).map_or_else(
            || "untitled".to_owned(),
            |n| n.to_string_lossy().into_owned(),
        );
        let mark = if self.doc.is_dirty() { "*" } else { "" };
        let help = if self.options.read_only {
            " (read-only help)"
        } else {
            ""
        };
        format!("{mark}{name}{help} — Spreadlight")
    }

    /// Where a pin was drawn last frame, in screen points.
    pub fn pin_pos(&self, node: NodeId, pin: &str, input: bool) -> Option<Pos2> {
        self.canvas
            .pins
            .borrow()
            .get(&(node, pin.to_owned(), input))
            .copied()
    }

    /// Where a point of the canvas (as its widgets report their rects) is on screen.
    pub fn canvas_to_screen(&self, ctx: &egui::Context, p: Pos2) -> Pos2 {
        self.canvas
            .layer
            .and_then(|l| ctx.layer_transform_to_global(l))
            .map_or(p, |t| t * p)
    }

    /// How many nodes the canvas laid out (title, pins, values) in the last
    /// frame: those near the view, not the whole patch (`canvas/cull.rs`).
    pub fn nodes_laid_out(&self) -> usize {
        self.canvas.culling.laid_out
    }

    pub fn canvas_rect(&self) -> Option<egui::Rect> {
        self.canvas.rect
    }

    pub fn selected(&self) -> Vec<NodeId> {
        self.canvas.selected.iter().copied().collect()
    }

    pub fn select(&mut self, ids: &[NodeId]) {
        self.canvas.selected = ids.iter().copied().collect();
    }

    pub fn refusal(&self) -> Option<&str> {
        self.refusal.as_ref().map(|r| r.message.as_str())
    }

    pub fn recovery_offered(&self) -> bool {
        self.autosave.offer.is_some()
    }

    /// The subpatch files whose unsaved edits the recovery offer restores too.
    pub fn recovery_offered_modules(&self) -> &[PathBuf] {
        if self.autosave.offer.is_some() {
            &self.autosave.offer_modules
        } else {
            &[]
        }
    }

    pub fn is_playing(&self) -> bool {
        self.transport.playing
    }

    pub fn set_playing(&mut self, playing: bool) {
        self.transport.playing = playing;
    }

    /// The frame the patch clock is at: it advances while playing and on Step.
    pub fn frame(&self) -> u64 {
        self.transport.clock.frame
    }

    /// How many times the patch was evaluated: it runs only on change or while playing.
    pub fn evaluations(&self) -> u64 {
        self.frame.evaluations
    }

    /// What the worker's frames cost the UI so far, as of the frame shown
    /// (submissions and waits at the gate, frames published, thumbnails
    /// scaled): compare two readings.
    pub fn worker_counts(&self) -> crate::worker::WorkerCounts {
        self.frame.counts
    }

    /// The egui texture a viewport shows, once something was rendered into it.
    pub fn viewport_texture(&self, index: usize) -> Option<&wgpu::Texture> {
        self.frame
            .views
            .get(index)?
            .target
            .as_ref()
            .map(|t| &t.texture)
    }

    /// Where a viewport's image was drawn last frame, in points.
    pub fn viewport_rect(&self, index: usize) -> Option<egui::Rect> {
        self.viewports.rects.get(index).copied().flatten()
    }

    /// The area the patch's Mouse and WindowSize nodes measure: the first
    /// viewport's (the whole window in the show window), in points.
    pub fn patch_window_rect(&self) -> Option<egui::Rect> {
        self.viewports.area
    }

    /// The pixel size a viewport renders at (the first one's is the patch's window size).
    pub fn viewport_pixels(&self, index: usize) -> Option<(u32, u32)> {
        self.viewports.views.get(index).map(|v| v.size)
    }

    pub fn viewport_error(&self, index: usize) -> Option<String> {
        self.frame
            .views
            .get(index)?
            .error
            .as_ref()
            .map(ToString::to_string)
    }

    pub fn gpu_error(&self) -> Option<&str> {
        self.gpu_error.as_deref()
    }

    /// Median seconds the editor's `ui` took over the recent frames.
    pub fn median_ui_seconds(&self) -> Option<f64> {
        let mut v: Vec<f64> = self.ui_times.iter().copied().collect();
        if v.is_empty() {
            return None;
        }
        v.sort_by(f64::total_cmp);
        Some(v[v.len() / 2])
    }
}
