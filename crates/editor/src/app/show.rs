//! The show window (`spreadlight play PATCH`): the patch's `Output` alone,
//! filling a borderless window at the window's own pixel size, playing; no
//! menus, canvas or inspector. Esc closes it. On its first frame it moves to
//! its monitor: `--monitor N`, else the `Monitor` pin of the patch's first
//! `Output` (-1 leaves the window where the window system put it). With
//! `--native` the window takes the texture's pixel size (`show_window.rs`).
//! Saved shader files reload here too, as in the editor (`shader_watch.rs`).

use std::sync::Mutex;

use super::*;
use crate::ShowWindow;
use crate::monitors::{self, Found};

/// What the show window was asked for, until it has been placed.
pub(super) struct Placement {
    window: ShowWindow,
    found: Found,
    failure: Arc<Mutex<Option<String>>>,
}

impl EditorApp {
    /// Run as the show window instead of the editor.
    pub fn set_show_mode(&mut self, on: bool) {
        self.show_mode = on;
        self.transport.playing = on || self.transport.playing;
    }

    /// How the show window is placed; a monitor that does not exist ends it
    /// with that error in `failure`.
    pub fn set_show_window(
        &mut self,
        window: ShowWindow,
        found: Found,
        failure: Arc<Mutex<Option<String>>>,
    ) {
        self.play_native = window.native;
        if let Some(fps) = window.fps.filter(|f| f.is_finite() && *f > 0.0) {
            self.transport.fixed_step = Some(1.0 / fps);
            self.worker.submit(Request {
                playback: Some(spreadlight_nodes::media::Playback::Exact),
                ..Default::default()
            });
        }
        self.record_on_start = window.record.is_some();
        self.record_to = window.record.clone();
        self.placement = Some(Placement {
            window,
            found,
            failure,
        });
    }

    /// The monitor the patch's first `Output` asks for with its `Monitor` pin.
    pub(super) fn output_monitor(&self) -> Option<usize> {
        let output = self
            .doc
            .top()
            .nodes
            .iter()
            .find(|n| n.type_name == "Output")?;
        match self.doc.input_value(&self.registry, output.id, "Monitor")? {
            Spread::Int(v) => v.first().and_then(|&m| usize::try_from(m).ok()),
            _ => None,
        }
    }

    fn place_window(&mut self, ctx: &egui::Context) {
        let Some(p) = self.placement.take() else {
            return;
        };
        let Some(index) = p.window.monitor.or_else(|| self.output_monitor()) else {
            return;
        };
        let monitors = p.found.lock().unwrap_or_else(|e| e.into_inner()).clone();
        let Some(monitors) = monitors else {
            // The loop has not listed them yet (it does before the first frame).
            self.placement = Some(p);
            return;
        };
        match monitors::pick(&monitors, index) {
            Ok(m) => {
                let ppp = ctx.pixels_per_point();
                let origin = egui::pos2(m.position.0 as f32, m.position.1 as f32) / ppp;
                let (w, h) = match (p.window.fullscreen, p.window.size) {
                    (false, Some(size)) => size,
                    (false, None) => (1280, 720),
                    (true, _) => m.size,
                };
                let size = egui::vec2(w as f32, h as f32) / ppp;
                // Centred on the monitor; fullscreen, it covers it.
                let monitor_size = egui::vec2(m.size.0 as f32, m.size.1 as f32) / ppp;
                let at = origin + ((monitor_size - size) / 2.0).max(egui::Vec2::ZERO);
                ctx.send_viewport_cmd(ViewportCommand::OuterPosition(at));
                ctx.send_viewport_cmd(ViewportCommand::InnerSize(size));
                if p.window.fullscreen {
                    ctx.send_viewport_cmd(ViewportCommand::Fullscreen(true));
                }
                self.status = format!("showing on monitor {index}: {}", m.name);
            }
            Err(message) => {
                eprintln!("error: {message}");
                *p.failure.lock().unwrap_or_else(|e| e.into_inner()) = Some(message);
                self.allow_close = true;
                ctx.send_viewport_cmd(ViewportCommand::Close);
            }
        }
    }

    pub(super) fn show_only(
        &mut self,
        ui: &mut Ui,
        frame: Option<&eframe::Frame>,
        started: Instant,
    ) {
        let ctx = ui.ctx().clone();
        self.place_window(&ctx);
        if ctx.input_mut(|i| i.consume_key(Modifiers::NONE, Key::Escape)) {
            ctx.send_viewport_cmd(ViewportCommand::Close);
        }
        // A show is tuned while it runs: saved shader files reload as in the editor.
        self.poll_shaders(&ctx);
        self.recording_shortcut(&ctx);
        let dt = ctx.input(|i| f64::from(i.stable_dt));
        self.evaluate_if_needed(&ctx, Some(dt), true);
        egui::CentralPanel::default()
            .frame(egui::Frame::NONE)
            .show(ui, |ui| {
                if self.play_native {
                    let area = ui.available_rect_before_wrap();
                    self.viewports.area = Some(area);
                    self.show_window_image(ui, 0, area, true);
                } else {
                    self.viewport_ui(ui, 0, None);
                }
            });
        self.evaluate_if_needed(&ctx, None, false);
        if self.transport.playing {
            ctx.request_repaint();
        }
        self.ui_times.push_back(started.elapsed().as_secs_f64());
        if self.ui_times.len() > 120 {
            self.ui_times.pop_front();
        }
        self.automate(&ctx, frame, started);
    }
}
