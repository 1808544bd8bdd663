//! The show window (`spreadlight play PATCH`): the patch's `Output` alone,
//! filling a borderless window at the window's own pixel size, playing; no
//! menus, canvas or inspector. Esc closes it.

use super::*;

impl EditorApp {
    /// Run as the show window instead of the editor.
    pub fn set_show_mode(&mut self, on: bool) {
        self.show_mode = on;
        self.playing = on || self.playing;
    }

    pub(super) fn show_only(
        &mut self,
        ui: &mut Ui,
        frame: Option<&eframe::Frame>,
        started: Instant,
    ) {
        let ctx = ui.ctx().clone();
        if ctx.input_mut(|i| i.consume_key(Modifiers::NONE, Key::Escape)) {
            ctx.send_viewport_cmd(ViewportCommand::Close);
        }
        let dt = ctx.input(|i| f64::from(i.stable_dt));
        self.evaluate_if_needed(Some(dt));
        egui::CentralPanel::default()
            .frame(egui::Frame::NONE)
            .show(ui, |ui| self.viewport_ui(ui, 0, None));
        self.render_viewports();
        if self.playing {
            ctx.request_repaint();
        }
        self.ui_times.push_back(started.elapsed().as_secs_f64());
        if self.ui_times.len() > 120 {
            self.ui_times.pop_front();
        }
        self.automate(&ctx, frame, started);
    }
}
