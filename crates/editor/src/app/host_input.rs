//! What the patch's `Mouse (Window)`, `Keyboard (Window)`, `KeyMatch
//! (Keyboard)` and `WindowSize (Window)` nodes read: the first viewport is the
//! patch's window (in the show window, the whole window), so its pixel size is
//! the window size, the pointer is measured across it, and keys reach the
//! patch while the pointer is over it and no text field has the keyboard (in
//! the show window, always). Written into the worker's `HostInput` each frame.

use glam::Vec2;
use spreadlight_nodes::input::{HOST_INPUT_NODES, InputSnapshot};

use super::*;

/// Points of smooth scrolling per wheel notch (egui's line scroll speed on native).
const POINTS_PER_NOTCH: f32 = 40.0;

impl EditorApp {
    /// Read this frame's pointer, keys and window size; whether they changed
    /// for a patch that reads them (it is then evaluated again, even paused).
    pub(super) fn feed_host_input(&mut self, ctx: &egui::Context) -> bool {
        let Some(area) = self.view_area else {
            return false;
        };
        let (w, h) = self.viewports[0].size;
        let show = self.show_mode;
        let typing = ctx.egui_wants_keyboard_input();
        let mut wheel = self.wheel;
        let snapshot = ctx.input(|i| {
            let pointer = i.pointer.latest_pos().filter(|p| area.contains(*p));
            let inside = pointer.is_some();
            if inside {
                for e in &i.raw.events {
                    if let egui::Event::MouseWheel { unit, delta, .. } = e {
                        wheel += match unit {
                            egui::MouseWheelUnit::Point => delta.y / POINTS_PER_NOTCH,
                            egui::MouseWheelUnit::Line | egui::MouseWheelUnit::Page => delta.y,
                        };
                    }
                }
            }
            let keys = (show || inside) && !typing;
            InputSnapshot {
                mouse_position: pointer.map(|p| {
                    InputSnapshot::normalized_position(
                        Vec2::new(p.x - area.min.x, p.y - area.min.y),
                        Vec2::new(area.width(), area.height()),
                    )
                }),
                mouse_buttons: if inside {
                    [
                        i.pointer.primary_down(),
                        i.pointer.middle_down(),
                        i.pointer.secondary_down(),
                    ]
                } else {
                    [false; 3]
                },
                mouse_wheel: wheel,
                keys_down: if keys {
                    i.keys_down.iter().map(|k| k.name().to_owned()).collect()
                } else {
                    Default::default()
                },
                window_size: Some((w, h)),
            }
        });
        self.wheel = wheel;
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
