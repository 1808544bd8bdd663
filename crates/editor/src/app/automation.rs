//! Scripted runs for the CLI's measurements and screenshots (`--measure-frames`, `--screenshot`).

use super::*;

/// How long a scripted screenshot waits for the patch's first finished frame.
const SCREENSHOT_WAIT_SECS: f64 = 300.0;

impl EditorApp {
    /// The scripted run: count frames, then screenshot, report and quit.
    pub(super) fn automate(
        &mut self,
        ctx: &egui::Context,
        frame: Option<&eframe::Frame>,
        started: Instant,
    ) {
        let Some(auto) = self.options.automation.clone() else {
            return;
        };
        ctx.request_repaint();
        let nodes = self.doc.patch().nodes.len();
        let canvas_zoom = self.canvas_zoom(ctx).unwrap_or(0.0);
        let recovery_offered = self.recovery_offered();
        let recovery_modules = self.recovery_offered_modules().len();
        let canvas_text_px = self.canvas_text_points(ctx).unwrap_or(0.0) * ctx.pixels_per_point();
        let viewport_error = self.viewport_error(0).unwrap_or_default();
        let patch_frame = (self.frame.evaluations, self.frame.seconds);
        // The patch has been drawn as the window shows it: a finished frame,
        // its first viewport (if it has one) rendered for the viewport's
        // size. Not "at" it: an image file's texture keeps its own size, and
        // waiting for it to match made the screenshot wait its whole timeout.
        let drawn = patch_frame.0 > 0
            && self.frame.views.first().is_none_or(|v| {
                v.target.is_none() || v.for_size == Some(self.viewports.views[0].size)
            });
        let counts = self.frame.counts;
        let a = &mut self.auto;
        // Each new patch frame once: how long the worker took for it.
        if patch_frame.0 != a.last_evaluations {
            a.last_evaluations = patch_frame.0;
            a.patch.push(patch_frame.1);
            a.counted_from.get_or_insert((patch_frame.0, counts));
        }
        if let Some(last) = a.last_start {
            a.intervals.push(started.duration_since(last).as_secs_f64());
        }
        a.last_start = Some(started);
        a.ui.push(started.elapsed().as_secs_f64());
        if let Some(cpu) = frame.and_then(|f| f.info().cpu_usage) {
            a.cpu.push(f64::from(cpu));
        }
        a.frames += 1;
        let shot = ctx.input(|i| {
            i.events.iter().find_map(|e| match e {
                egui::Event::Screenshot { image, .. } => Some(image.clone()),
                _ => None,
            })
        });
        let mut done = auto.screenshot.is_none() && a.frames >= auto.frames;
        if let (Some(image), Some(path)) = (shot, &auto.screenshot) {
            let [w, h] = image.size;
            let bytes: Vec<u8> = image.pixels.iter().flat_map(|c| c.to_array()).collect();
            match image::RgbaImage::from_raw(w as u32, h as u32, bytes).map(|img| img.save(path)) {
                Some(Ok(())) => {}
                Some(Err(e)) => eprintln!("error: cannot write {}: {e}", path.display()),
                None => eprintln!("error: the screenshot has the wrong size"),
            }
            done = true;
        } else if auto.screenshot.is_some()
            && a.frames >= auto.frames
            && !a.screenshot_sent
            // A screenshot shows the patch: wait for its first finished frame
            // (the worker may still be compiling pipelines), within reason.
            && (drawn
                || a.wait_started.get_or_insert(started).elapsed().as_secs_f64()
                    > SCREENSHOT_WAIT_SECS)
        {
            a.screenshot_sent = true;
            ctx.send_viewport_cmd(ViewportCommand::Screenshot(egui::UserData::default()));
        }
        if done {
            // A recording ends with the run, its file closed before the report.
            let recorded = self.stop_recording();
            let a = &mut self.auto;
            let (ui_med, ui_p95) = median_and_p95(&a.ui);
            let (frame_med, frame_p95) = median_and_p95(&a.intervals);
            let (cpu_med, _) = median_and_p95(&a.cpu);
            let (patch_med, _) = median_and_p95(&a.patch);
            let per_frame = per_patch_frame(a.counted_from, (a.last_evaluations, counts));
            let ppp = ctx.pixels_per_point();
            let rect = self.viewports.rects[0]
                .map(|r| [r.min.x * ppp, r.min.y * ppp, r.max.x * ppp, r.max.y * ppp]);
            println!(
                "{{\"frames\": {}, \"nodes\": {}, \"ui_ms_median\": {:.3}, \"ui_ms_p95\": {:.3}, \"frame_ms_median\": {:.3}, \"frame_ms_p95\": {:.3}, \"eframe_cpu_ms_median\": {:.3}, \"patch_frames\": {}, \"patch_ms_median\": {:.3}, \"viewport_px\": {}, \"viewport_error\": {:?}, \"canvas_zoom\": {:.3}, \"canvas_text_px\": {:.2}, \"recovery_offered\": {}, \"recovery_module_files\": {}, \"nodes_laid_out\": {}, \"thumbnails\": {}, \"recorded_frames\": {}, \"recording_first_frame\": {}, \"recording_dropped\": {}, \"recording_error\": {:?}, \"thumbnail_ms\": {}, \"patch_alone_ms\": {}, \"thumbnails_low_rate\": {}, {}}}",
                a.frames,
                nodes,
                ui_med * 1e3,
                ui_p95 * 1e3,
                frame_med * 1e3,
                frame_p95 * 1e3,
                cpu_med * 1e3,
                a.patch.len(),
                patch_med * 1e3,
                rect.map_or_else(
                    || "null".to_owned(),
                    |r| format!("[{}, {}, {}, {}]", r[0], r[1], r[2], r[3])
                ),
                viewport_error,
                canvas_zoom,
                canvas_text_px,
                recovery_offered,
                recovery_modules,
                self.canvas.culling.laid_out,
                // Thumbnails drawn on screen (each asks for its preview).
                self.previews.sent.iter().filter(|r| !r.key.large).count(),
                recorded.as_ref().map_or(0, |r| r.frames),
                recorded
                    .as_ref()
                    .and_then(|r| r.first_frame)
                    .map_or_else(|| "null".to_owned(), |f| f.to_string()),
                recorded.as_ref().map_or(0, |r| r.dropped),
                recorded
                    .as_ref()
                    .and_then(|r| r.error.clone())
                    .unwrap_or_default(),
                // The thumbnails' schedule, as the worker measured it (previews/schedule.rs).
                json_ms(self.frame.thumbnail_cost.thumb_ms),
                json_ms(self.frame.thumbnail_cost.base_ms),
                // Thumbnails whose texture the patch's frame does not make
                // (merged away), refreshed at a low rate (previews/engine.rs).
                self.previews
                    .outputs
                    .iter()
                    .filter(|(k, o)| !k.large && o.note.is_some())
                    .count(),
                per_frame,
            );
            self.allow_close = true;
            ctx.send_viewport_cmd(ViewportCommand::Close);
        }
    }
}

/// What each patch frame cost the UI, from the worker's counts at the first
/// and the last patch frame of the run (worker.rs, `WorkerCounts`): the
/// report's `submissions_per_patch_frame` (through the renderer's gate),
/// `gate_waits_per_patch_frame` (submits that found the gate closed and
/// asked for a UI frame), `published_per_patch_frame` (frames the worker
/// published, each a wake of the UI) and `thumbnails_scaled_per_patch_frame`;
/// `null` with fewer than two patch frames.
fn per_patch_frame(
    first: Option<(u64, crate::worker::WorkerCounts)>,
    (last_evaluations, last): (u64, crate::worker::WorkerCounts),
) -> String {
    let ratios = first.and_then(|(from, c)| {
        let frames = last_evaluations.checked_sub(from).filter(|n| *n > 0)? as f64;
        let ratio = |now: u64, then: u64| now.saturating_sub(then) as f64 / frames;
        Some([
            ratio(last.gate.submissions, c.gate.submissions),
            ratio(last.gate.waits, c.gate.waits),
            ratio(last.published, c.published),
            ratio(last.thumbnails_scaled, c.thumbnails_scaled),
        ])
    });
    let names = [
        "submissions_per_patch_frame",
        "gate_waits_per_patch_frame",
        "published_per_patch_frame",
        "thumbnails_scaled_per_patch_frame",
    ];
    names
        .iter()
        .enumerate()
        .map(|(k, name)| {
            let value = ratios.map_or_else(|| "null".to_owned(), |r| format!("{:.3}", r[k]));
            format!("\"{name}\": {value}")
        })
        .collect::<Vec<_>>()
        .join(", ")
}

/// Milliseconds for the report, `null` when not measured.
fn json_ms(ms: Option<f64>) -> String {
    ms.map_or_else(|| "null".to_owned(), |ms| format!("{ms:.3}"))
}
