//! Modal dialogs: unsaved changes, recovery, and the file dialog
//! (egui-file-dialog: folders, places, filters, a typed path, overwrite check).

use super::*;

impl EditorApp {
    pub(super) fn dialogs(&mut self, ctx: &egui::Context) {
        if let Some(recovery) = self.autosave.offer.clone() {
            egui::Modal::new(Id::new("recovery")).show(ctx, |ui| {
                ui.heading("Restore unsaved changes?");
                ui.label(format!(
                    "An autosave from a session that did not end normally exists:\n{}",
                    recovery.display()
                ));
                if !self.autosave.offer_modules.is_empty() {
                    let list: Vec<String> = self
                        .autosave.offer_modules
                        .iter()
                        .map(|p| p.display().to_string())
                        .collect();
                    ui.label(format!(
                        "with unsaved edits of subpatch files (written to them only when you save):\n{}",
                        list.join("\n")
                    ));
                }
                ui.horizontal(|ui| {
                    if ui.button("Restore").clicked() {
                        self.autosave.offer = None;
                        self.restore_recovery(&recovery);
                    }
                    if ui.button("Discard").clicked() {
                        self.autosave.offer = None;
                        files::remove_recovery(&recovery);
                    }
                });
            });
        }
        // While the Save-as dialog answers "Save", the question waits behind it.
        if let Some(pending) = self.pending.clone().filter(|_| self.dialog.is_none()) {
            let mut answer = None;
            egui::Modal::new(Id::new("unsaved")).show(ctx, |ui| {
                ui.heading("Unsaved changes");
                ui.label(format!(
                    "Save the changes to {}?",
                    self.title().trim_start_matches('*')
                ));
                ui.horizontal(|ui| {
                    if ui.button("Save").clicked() {
                        answer = Some(1);
                    }
                    if ui.button("Don't save").clicked() {
                        answer = Some(2);
                    }
                    if ui.button("Cancel").clicked() {
                        answer = Some(0);
                    }
                });
            });
            match answer {
                Some(1) => {
                    if self.save() {
                        self.pending = None;
                        self.perform(pending, ctx);
                    } else {
                        self.open_dialog(DialogMode::SaveAs);
                    }
                }
                Some(2) => {
                    self.pending = None;
                    // The user chose to drop the changes: their autosave goes too.
                    files::remove_recovery(&self.recovery_file());
                    self.autosave.recovery_written = false;
                    self.doc.mark_saved();
                    self.perform(pending, ctx);
                }
                Some(_) => self.pending = None,
                None => {}
            }
        }
        self.file_dialog(ctx);
    }

    /// Open the file dialog for `mode`: patches filter to `.ron`, file pins
    /// to what their node reads (glTF scenes, images), always with "All Files".
    pub(super) fn open_dialog(&mut self, mode: DialogMode) {
        let dir = self
            .path
            .as_ref()
            .and_then(|p| p.parent().map(Path::to_path_buf))
            .filter(|p| !p.as_os_str().is_empty())
            .or_else(|| std::env::current_dir().ok())
            .unwrap_or_default();
        let (title, ok) = match &mode {
            DialogMode::Open => ("Open patch", "Open"),
            DialogMode::SaveAs => ("Save patch as", "Save"),
            DialogMode::PickValue { .. } => ("Choose a file", "Choose"),
        };
        let mut dialog = egui_file_dialog::FileDialog::new()
            .title(title)
            .id(Id::new("file-dialog"))
            // Where the patch is, each time (the last picked folder is often a module or texture folder).
            .opening_mode(egui_file_dialog::OpeningMode::AlwaysInitialDir)
            .initial_directory(dir);
        {
            let labels = dialog.labels_mut();
            labels.open_button = ok.to_owned();
            labels.save_button = ok.to_owned();
            labels.cancel_button = "Cancel".to_owned();
        }
        match &mode {
            DialogMode::Open | DialogMode::SaveAs => {
                dialog = dialog
                    .add_file_filter_extensions(PATCHES, vec!["ron"])
                    .default_file_filter(PATCHES)
                    .add_save_extension(PATCHES, "ron")
                    .default_save_extension(PATCHES);
            }
            DialogMode::PickValue { node, .. } => {
                let reads_gltf = self
                    .doc
                    .node(*node)
                    .is_some_and(|n| n.type_name.to_lowercase().contains("gltf"));
                dialog = dialog
                    .add_file_filter_extensions(GLTF, vec!["gltf", "glb"])
                    .add_file_filter_extensions(IMAGES, IMAGE_EXTENSIONS.to_vec())
                    .default_file_filter(if reads_gltf { GLTF } else { IMAGES });
            }
        }
        match &mode {
            DialogMode::SaveAs => {
                let name = self.path.as_ref().and_then(|p| p.file_name()).map_or_else(
                    || "untitled.ron".to_owned(),
                    |n| n.to_string_lossy().into_owned(),
                );
                dialog = dialog.default_file_name(&name);
                dialog.save_file();
            }
            // An `Output`'s Filename is where it writes: a name to save to.
            DialogMode::PickValue { node, .. }
                if self
                    .doc
                    .node(*node)
                    .is_some_and(|n| n.type_name == "Output") =>
            {
                dialog.save_file();
            }
            _ => dialog.pick_file(),
        }
        self.dialog = Some(FilePicker { mode, dialog });
    }

    /// Show the file dialog while it is open and act on what it picked.
    pub(super) fn file_dialog(&mut self, ctx: &egui::Context) {
        let Some(picker) = &mut self.dialog else {
            return;
        };
        picker.dialog.update(ctx);
        let path = match picker.dialog.state() {
            egui_file_dialog::DialogState::Open => return,
            egui_file_dialog::DialogState::Picked(path) => Some(path.clone()),
            _ => None,
        };
        let mode = picker.mode.clone();
        self.dialog = None;
        let Some(mut path) = path else {
            return;
        };
        if mode == DialogMode::SaveAs && path.extension().is_none() {
            // A name typed without one gets the patch extension, as the filter says.
            path.set_extension("ron");
        }
        match mode {
            DialogMode::Open => self.request_open(path),
            DialogMode::SaveAs => {
                if self.save_as(&path)
                    && let Some(p) = self.pending.take()
                {
                    self.perform(p, ctx);
                }
            }
            DialogMode::PickValue { node, pin, slice } => {
                if let Some(Spread::String(mut v)) =
                    self.doc.input_value(&self.registry, node, &pin)
                {
                    if slice < v.len() {
                        v[slice] = path.display().to_string();
                    }
                    self.doc
                        .set_value(node, &pin, Some(Spread::String(v)), false);
                }
            }
        }
    }
}

const PATCHES: &str = "Patches (.ron)";
const GLTF: &str = "glTF scenes (.gltf, .glb)";
const IMAGES: &str = "Images";
/// What the image loaders read: the `image` crate's formats this workspace enables.
const IMAGE_EXTENSIONS: [&str; 3] = ["png", "hdr", "exr"];
