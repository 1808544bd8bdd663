//! The app's side of the previews (`crate::previews`): the toggles (all
//! thumbnails, Ctrl+T; the selected nodes', Shift+T; one in the inspector),
//! kept in the config directory, and what tests read of them.

use super::*;
use crate::previews::{PreviewKey, PreviewOut, PreviewRequest};

impl EditorApp {
    /// The node at `id` of the open document, as a path from the top patch.
    fn preview_path(&self, id: NodeId) -> Vec<NodeId> {
        let mut path = self.instance.clone();
        path.push(id);
        path
    }

    fn save_preview_settings(&mut self) {
        if let Err(e) = self.previews.settings.save(&self.options.config_dir) {
            self.status = e;
        }
    }

    /// Thumbnails on nodes on or off, for every node.
    pub fn set_thumbnails(&mut self, on: bool) {
        self.previews.settings.thumbnails = on;
        self.save_preview_settings();
    }

    pub fn thumbnails(&self) -> bool {
        self.previews.settings.thumbnails
    }

    /// Hide (or show again) the thumbnails of the selected nodes: all of them
    /// hidden when any shows, else all shown.
    pub fn toggle_selected_thumbnails(&mut self) {
        let paths: Vec<Vec<NodeId>> = self
            .selected()
            .into_iter()
            .map(|id| self.preview_path(id))
            .collect();
        if paths.is_empty() {
            return;
        }
        let file = self.path.clone();
        let settings = &mut self.previews.settings;
        let hide = paths
            .iter()
            .any(|p| !settings.is_hidden(file.as_deref(), p));
        for p in &paths {
            settings.set_hidden(file.as_deref(), p, hide);
        }
        self.save_preview_settings();
    }

    /// Ctrl+T and Shift+T (called from `shortcuts`, while nothing has the keyboard).
    pub(super) fn preview_shortcuts(&mut self, ctx: &egui::Context) {
        if ctx.input_mut(|i| i.consume_key(Modifiers::COMMAND, Key::T)) {
            self.set_thumbnails(!self.thumbnails());
        }
        if ctx.input_mut(|i| i.consume_key(Modifiers::SHIFT, Key::T)) {
            self.toggle_selected_thumbnails();
        }
    }

    /// The toolbar's toggle for every thumbnail.
    pub(super) fn previews_toolbar(&mut self, ui: &mut Ui) {
        let mut on = self.thumbnails();
        if ui
            .toggle_value(&mut on, "🖼 Thumbnails")
            .on_hover_text(
                "a live thumbnail on every texture output (Ctrl+T); Shift+T hides or shows the \
                 selected nodes' own",
            )
            .changed()
        {
            self.set_thumbnails(on);
        }
    }

    /// The inspector's toggle for the focused node's thumbnail.
    pub(super) fn inspector_thumbnail(
        &mut self,
        ui: &mut Ui,
        id: NodeId,
        def: &spreadlight_graph::NodeDef,
    ) {
        if !def
            .outputs
            .iter()
            .any(|p| crate::previews::has_thumbnail(p.ty))
        {
            return;
        }
        let path = self.preview_path(id);
        let file = self.path.clone();
        let mut shown = !self.previews.settings.is_hidden(file.as_deref(), &path);
        if ui
            .checkbox(&mut shown, "Thumbnail")
            .on_hover_text("this node's thumbnail (Shift+T); Ctrl+T switches all of them")
            .changed()
        {
            self.previews
                .settings
                .set_hidden(file.as_deref(), &path, !shown);
            self.save_preview_settings();
        }
    }

    /// The previews the canvas asked the worker for last.
    pub fn preview_requests(&self) -> &[PreviewRequest] {
        &self.previews.sent
    }

    /// Where the last frame drew a thumbnail (or, for a `large` key, the
    /// hover preview), in screen points.
    pub fn thumbnail_rect(&self, key: &PreviewKey) -> Option<egui::Rect> {
        self.previews
            .drawn
            .iter()
            .find(|(k, _)| k == key)
            .map(|(_, r)| *r)
    }

    /// A preview as the latest finished frame has it.
    pub fn preview(&self, key: &PreviewKey) -> Option<&PreviewOut> {
        self.frame.previews.get(key)
    }
}
