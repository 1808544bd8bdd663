//! Modal dialogs: unsaved changes, recovery, and the file dialog.

use super::*;

impl EditorApp {
    pub(super) fn dialogs(&mut self, ctx: &egui::Context) {
        if let Some(recovery) = self.recovery_offer.clone() {
            egui::Modal::new(Id::new("recovery")).show(ctx, |ui| {
                ui.heading("Restore unsaved changes?");
                ui.label(format!(
                    "An autosave from a session that did not end normally exists:\n{}",
                    recovery.display()
                ));
                ui.horizontal(|ui| {
                    if ui.button("Restore").clicked() {
                        self.recovery_offer = None;
                        self.restore_recovery(&recovery);
                    }
                    if ui.button("Discard").clicked() {
                        self.recovery_offer = None;
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
                    self.recovery_written = false;
                    self.doc.mark_saved();
                    self.perform(pending, ctx);
                }
                Some(_) => self.pending = None,
                None => {}
            }
        }
        self.file_dialog(ctx);
    }

    pub(super) fn file_dialog(&mut self, ctx: &egui::Context) {
        let Some(d) = &mut self.dialog else {
            return;
        };
        let title = match d.mode {
            DialogMode::Open => "Open patch",
            DialogMode::SaveAs => "Save patch as",
            DialogMode::PickValue { .. } => "Pick a file",
        };
        let mut chosen: Option<PathBuf> = None;
        let mut close = false;
        egui::Window::new(title).collapsible(false).show(ctx, |ui| {
            ui.horizontal(|ui| {
                if ui
                    .small_button("⬆")
                    .on_hover_text("parent folder")
                    .clicked()
                    && let Some(parent) = d.dir.parent()
                {
                    d.dir = parent.to_owned();
                }
                ui.label(d.dir.display().to_string());
            });
            let mut entries: Vec<(bool, PathBuf)> = std::fs::read_dir(&d.dir)
                .map(|rd| {
                    rd.filter_map(Result::ok)
                        .map(|e| (e.path().is_dir(), e.path()))
                        .filter(|(dir, p)| {
                            let hidden = p
                                .file_name()
                                .is_some_and(|n| n.to_string_lossy().starts_with('.'));
                            !hidden
                                && (*dir
                                    || !matches!(d.mode, DialogMode::Open)
                                    || p.extension().is_some_and(|e| e == "ron"))
                        })
                        .collect()
                })
                .unwrap_or_default();
            entries.sort_by(|a, b| b.0.cmp(&a.0).then(a.1.cmp(&b.1)));
            egui::ScrollArea::vertical()
                .max_height(240.0)
                .show(ui, |ui| {
                    for (is_dir, p) in entries {
                        let name = p
                            .file_name()
                            .map(|n| n.to_string_lossy().into_owned())
                            .unwrap_or_default();
                        let label = if is_dir {
                            format!("📁 {name}")
                        } else {
                            name.clone()
                        };
                        if ui.selectable_label(d.name == name, label).clicked() {
                            if is_dir {
                                d.dir = p;
                            } else {
                                d.name = name;
                            }
                        }
                    }
                });
            ui.horizontal(|ui| {
                let label = ui.label("File:").id;
                let edit = ui
                    .add(egui::TextEdit::singleline(&mut d.name).id(Id::new("file-dialog-name")))
                    .labelled_by(label);
                let enter = edit.lost_focus() && ui.input(|i| i.key_pressed(Key::Enter));
                let ok = match d.mode {
                    DialogMode::Open => "Open",
                    DialogMode::SaveAs => "Save",
                    DialogMode::PickValue { .. } => "Pick",
                };
                if (ui.button(ok).clicked() || enter) && !d.name.is_empty() {
                    chosen = Some(d.dir.join(&d.name));
                }
                if ui.button("Cancel").clicked() {
                    close = true;
                }
            });
        });
        if let Some(path) = chosen {
            let mode = d.mode.clone();
            self.dialog = None;
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
        } else if close {
            self.dialog = None;
        }
    }
}
