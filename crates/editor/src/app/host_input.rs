//! What the patch's `Mouse (Window)`, `Keyboard (Window)`, `KeyMatch
//! (Keyboard)` and `WindowSize (Window)` nodes read: the first viewport is the
//! patch's window (in the show window, the whole window), so its pixel size is
//! the window size, the pointer is measured across it, and keys reach the
//! patch while the pointer is over it and no text field has the keyboard (in
//! the show window, always). While the editor's show window is open, it is
//! the patch's window (`show_window.rs`). Written into the worker's
//! `HostInput` each frame.

use spreadlight_nodes::input::HOST_INPUT_NODES;

use super::*;

/// Points of smooth scrolling per wheel notch (egui's line scroll speed on native).
pub(super) const POINTS_PER_NOTCH: f32 = 40.0;

impl EditorApp {
    /// Read this frame's pointer, keys and window size; whether they changed
    /// for a patch that reads them (it is then evaluated again, even paused).
    pub(super) fn feed_host_input(&mut self, ctx: &egui::Context) -> bool {
        let Some(area) = self.viewports.area else {
            return false;
        };
        let snapshot = match &self.show_window.input {
            // The show window is open: the patch's window is that one.
            Some(s) => s.clone(),
            None => {
                let mut wheel = self.viewports.wheel;
                let s = show_window::read_input(
                    ctx,
                    area,
                    self.viewports.views[0].size,
                    self.show_mode,
                    &mut wheel,
                );
                self.viewports.wheel = wheel;
                s
            }
        };
        let host = self.worker.host_input();
        if host.snapshot() == snapshot {
            return false;
        }
        host.set(snapshot);
        self.frame
            .runtime
            .network()
            .nodes()
            .iter()
            .any(|n| HOST_INPUT_NODES.contains(&&*n.type_name))
    }
}
