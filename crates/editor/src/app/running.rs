//! Running the patch: the UI's side of the worker (`worker.rs`). Each frame
//! sends what changed (the document, the clock, the viewports' wishes) and
//! takes the latest finished frame, waiting for it at most `frame_wait`.

use super::*;

impl EditorApp {
    /// Pick up saved shader files: their node types are replaced and the
    /// patch recompiled, keeping links and values; errors go to the status bar
    /// (and, in the show window, which has none, to standard error). The editor
    /// and `spreadlight play` both call it once a frame.
    pub(super) fn poll_shaders(&mut self, ctx: &egui::Context) {
        let now = ctx.input(|i| i.time);
        if let Some(changes) = self.shaders.poll(now, &mut self.registry) {
            self.worker.submit(Request {
                registry: Some(self.registry.clone()),
                ..Default::default()
            });
            self.sent_generation = None;
            self.synced_generation = None;
            self.status = self.shaders.describe(&changes);
            if self.show_mode {
                eprintln!("{}", self.status);
            }
        }
        // A paused patch repaints only on input: wake up for the next look.
        if self.shaders.is_watching() {
            ctx.request_repaint_after(std::time::Duration::from_secs_f64(
                crate::shader_watch::POLL_SECS,
            ));
        }
    }

    /// Send the worker what changed; with `dt`, also advance time when
    /// playing or stepping. With `wait`, wait for the result as `frame_wait`
    /// allows (always, in `FrameWait::Always`); then take the latest frame.
    pub(super) fn evaluate_if_needed(&mut self, ctx: &egui::Context, dt: Option<f64>, wait: bool) {
        if !self.wake_set && !matches!(self.options.frame_wait, FrameWait::Always) {
            // An idle UI (paused patch, no input) repaints when a frame is finished.
            let ctx = ctx.clone();
            self.worker
                .set_wake(Box::new(move || ctx.request_repaint()));
            self.wake_set = true;
        }
        if std::mem::take(&mut self.record_on_start) {
            self.toggle_recording();
        }
        let mut request = Request::default();
        let generation = self.doc.generation();
        if self.sent_generation != Some(generation) {
            request.patch = Some((generation, Arc::new(self.doc.runtime_patch())));
            self.sent_generation = Some(generation);
        }
        if dt.is_some() && self.feed_host_input(ctx) && !self.transport.playing {
            // The patch reads the pointer or keys: a paused patch follows them too.
            request.clock = Some(self.transport.clock);
        }
        if let Some(clock) = dt.and_then(|dt| self.transport.advance(dt)) {
            request.clock = Some(clock);
        }
        let views: Vec<ViewRequest> = self
            .viewports
            .views
            .iter()
            .map(|v| ViewRequest {
                texture: self.texture_of(&v.source),
                size: v.size,
            })
            .collect();
        if views != self.sent_views {
            request.views = Some(views.clone());
            self.sent_views = views;
        }
        request.previews = self.previews.take_request();
        if !request.is_empty() {
            let seq = self.worker.submit(request);
            let wait = match self.options.frame_wait {
                FrameWait::Always => FrameWait::Always,
                _ if !wait => FrameWait::AtMost(std::time::Duration::ZERO),
                w => w,
            };
            self.worker.wait(seq, wait);
        }
        if let Some(frame) = self.worker.latest()
            && !Arc::ptr_eq(&frame, &self.frame)
        {
            if let Some(failure) = &frame.failure {
                self.status = failure.clone();
            }
            // The worker frees the old one (every node's outputs), not this thread.
            let old = std::mem::replace(&mut self.frame, frame);
            self.worker.retire(old);
        }
    }

    /// The output pin a viewport's source points at (the worker checks that it was evaluated).
    pub(super) fn texture_of(&self, source: &Source) -> Result<(NodeId, String), ViewportError> {
        match source {
            Source::None => Err(ViewportError::NoTexture),
            Source::Pin(node, pin) => Ok((*node, pin.clone())),
            // Viewports show the top patch, whichever document is open; its
            // Outputs are indexed once per edit (`output_index.rs`).
            Source::Output => self
                .outputs
                .source(
                    self.doc.generation(),
                    self.doc.top(),
                    self.canvas.selected.iter(),
                )
                .flatten()
                .ok_or(ViewportError::NoTexture),
        }
    }
}
