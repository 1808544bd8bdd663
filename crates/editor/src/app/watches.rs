//! Watched values: outputs pinned from the inspector (`👁`), listed under it
//! with their live spreads wherever the canvas is, inside subpatches too.

use super::*;

/// A watched output: the node's path from the top (subpatch nodes, then its id) and the pin.
pub type Watch = (Vec<NodeId>, String);

impl EditorApp {
    /// The watched outputs, in the order they were pinned.
    pub fn watches(&self) -> &[Watch] {
        &self.watches
    }

    /// Pin or unpin an output of the node at `path`.
    pub fn toggle_watch(&mut self, path: Vec<NodeId>, pin: &str) {
        let watch = (path, pin.to_owned());
        match self.watches.iter().position(|w| *w == watch) {
            Some(k) => {
                self.watches.remove(k);
            }
            None => self.watches.push(watch),
        }
    }

    /// The list under the inspector: each watch's place and its live value.
    pub(super) fn watches_ui(&mut self, ui: &mut Ui) {
        if self.watches.is_empty() {
            return;
        }
        ui.separator();
        ui.heading("Watches");
        let mut unpin = None;
        for (k, (path, pin)) in self.watches.iter().enumerate() {
            let value = self
                .frame
                .runtime
                .output_at(path, pin)
                .map_or_else(|| "not evaluated".to_owned(), |s| canvas::preview(s));
            let place: Vec<String> = path.iter().map(|id| id.to_string()).collect();
            ui.horizontal(|ui| {
                if ui
                    .small_button("✕")
                    .on_hover_text("stop watching")
                    .clicked()
                {
                    unpin = Some(k);
                }
                ui.label(format!("{}.{pin}", place.join(" > ")));
            });
            ui.monospace(value);
        }
        if let Some(k) = unpin {
            self.watches.remove(k);
        }
    }
}
