//! Keyboard shortcuts, the menu bar and the status bar.

use super::*;

impl EditorApp {
    pub(super) fn shortcuts(&mut self, ctx: &egui::Context) {
        if self.dialog.is_some() {
            // The file dialog has the keyboard (Esc, Enter, arrows are its own).
            return;
        }
        let typing = ctx.egui_wants_keyboard_input();
        let cmd = |key| KeyboardShortcut::new(Modifiers::COMMAND, key);
        let cmd_shift = |key| KeyboardShortcut::new(Modifiers::COMMAND | Modifiers::SHIFT, key);
        let consume = |s: KeyboardShortcut| ctx.input_mut(|i| i.consume_shortcut(&s));
        if consume(cmd_shift(Key::S)) {
            self.open_dialog(DialogMode::SaveAs);
        }
        if consume(cmd(Key::S)) && !self.save() {
            self.open_dialog(DialogMode::SaveAs);
        }
        if consume(cmd(Key::O)) {
            self.open_dialog(DialogMode::Open);
        }
        if consume(cmd(Key::N)) {
            if self.doc.is_dirty() {
                self.pending = Some(Pending::New);
            } else {
                self.replace_document(EditorDoc::default(), None);
            }
        }
        if typing {
            return;
        }
        if consume(cmd_shift(Key::Z)) || consume(cmd(Key::Y)) {
            self.doc.redo();
        }
        if consume(cmd(Key::Z)) {
            self.doc.undo();
        }
        if consume(KeyboardShortcut::new(Modifiers::NONE, Key::F11)) {
            self.toggle_show_window();
        }
        if consume(cmd(Key::D)) {
            self.duplicate_selected();
        }
        if consume(cmd_shift(Key::G)) {
            self.unmake_selected_subpatches();
        }
        if consume(cmd(Key::G)) {
            self.make_subpatch_of_selection();
        }
        let (copy, paste, pasted_text) = ctx.input(|i| {
            let copy = i.events.iter().any(|e| matches!(e, egui::Event::Copy))
                || i.events.iter().any(|e| {
                    matches!(e, egui::Event::Key { key: Key::C, pressed: true, modifiers, .. } if modifiers.command)
                });
            let pasted_text = i.events.iter().find_map(|e| match e {
                egui::Event::Paste(text) => Some(text.clone()),
                _ => None,
            });
            let paste = pasted_text.is_some()
                || i.events.iter().any(|e| {
                    matches!(e, egui::Event::Key { key: Key::V, pressed: true, modifiers, .. } if modifiers.command)
                });
            (copy, paste, pasted_text)
        });
        if copy {
            self.copy_selected(Some(ctx));
        }
        if let Some(text) = pasted_text {
            self.take_pasted_text(&text);
        }
        if paste {
            self.paste();
        }
        if ctx.input_mut(|i| i.consume_key(Modifiers::NONE, Key::Delete)) {
            self.delete_selected();
        }
        if ctx.input_mut(|i| i.consume_key(Modifiers::NONE, Key::Escape)) {
            if self.show_window.open.is_some() && ctx.embed_viewports() {
                // The show window is drawn inside the editor (no native
                // windows), so it shares the editor's keyboard: Esc closes it.
                self.close_show_window();
            } else {
                self.canvas.selected.clear();
            }
        }
        self.organise_shortcuts(ctx);
        if ctx.input_mut(|i| i.consume_key(Modifiers::NONE, Key::F)) {
            self.canvas.fit = FIT_FROM_SCRATCH;
        }
        self.preview_shortcuts(ctx);
    }

    pub(super) fn menu_bar(&mut self, ui: &mut Ui) {
        // Wrapped: a window narrower than the toolbar shows its last
        // buttons (Timings, Thumbnails, Show window) on a second row
        // instead of clipping them.
        egui::MenuBar::new().ui(ui, |ui| {
            ui.horizontal_wrapped(|ui| {
                ui.menu_button("File", |ui| {
                    if ui.button("New").clicked() {
                        if self.doc.is_dirty() {
                            self.pending = Some(Pending::New);
                        } else {
                            self.replace_document(EditorDoc::default(), None);
                        }
                    }
                    if ui.button("Open…").clicked() {
                        self.open_dialog(DialogMode::Open);
                    }
                    ui.menu_button("Open recent", |ui| {
                        if self.recent.is_empty() {
                            ui.weak("nothing yet");
                        }
                        for p in self.recent.clone() {
                            if ui.button(p.display().to_string()).clicked() {
                                self.request_open(p);
                            }
                        }
                    });
                    if ui.button("Save").clicked() && !self.save() {
                        self.open_dialog(DialogMode::SaveAs);
                    }
                    if ui.button("Save as…").clicked() {
                        self.open_dialog(DialogMode::SaveAs);
                    }
                    ui.separator();
                    if ui.button("Quit").clicked() {
                        ui.ctx().send_viewport_cmd(ViewportCommand::Close);
                    }
                });
                ui.menu_button("Edit", |ui| {
                    let undo = self.doc.undo_label().map(|l| format!("Undo {l}"));
                    if ui
                        .add_enabled(
                            undo.is_some(),
                            egui::Button::new(undo.unwrap_or_else(|| "Undo".into())),
                        )
                        .clicked()
                    {
                        self.doc.undo();
                    }
                    let redo = self.doc.redo_label().map(|l| format!("Redo {l}"));
                    if ui
                        .add_enabled(
                            redo.is_some(),
                            egui::Button::new(redo.unwrap_or_else(|| "Redo".into())),
                        )
                        .clicked()
                    {
                        self.doc.redo();
                    }
                    ui.separator();
                    if ui.button("Copy").clicked() {
                        self.copy_selected(Some(ui.ctx()));
                    }
                    if ui.button("Paste").clicked() {
                        self.paste();
                    }
                    if ui.button("Duplicate").clicked() {
                        self.duplicate_selected();
                    }
                    if ui.button("Delete").clicked() {
                        self.delete_selected();
                    }
                    ui.separator();
                    if ui.button("Make subpatch").on_hover_text("Ctrl+G").clicked() {
                        self.make_subpatch_of_selection();
                    }
                    if ui
                        .button("Unmake subpatch")
                        .on_hover_text("Ctrl+Shift+G")
                        .clicked()
                    {
                        self.unmake_selected_subpatches();
                    }
                });
                self.organise_menu(ui);
                ui.separator();
                let play = if self.transport.playing {
                    "⏸ Pause"
                } else {
                    "▶ Play"
                };
                if ui.button(play).clicked() {
                    self.transport.playing = !self.transport.playing;
                }
                if ui.button("⏭ Step").clicked() {
                    self.transport.playing = false;
                    self.transport.step = true;
                }
                ui.label(format!(
                    "frame {} · {:.2} s",
                    self.transport.clock.frame, self.transport.clock.time
                ));
                self.recording_button(ui);
                ui.separator();
                if ui
                    .button("⛶ Fit")
                    .on_hover_text("show the whole patch (F)")
                    .clicked()
                {
                    self.canvas.fit = FIT_FROM_SCRATCH;
                }
                ui.toggle_value(&mut self.show_timings, "⏱ Timings")
                    .on_hover_text("CPU time per node, GPU time per render node");
                self.previews_toolbar(ui);
                ui.separator();
                let open = self.show_window.open.is_some();
                if ui
                    .selectable_label(open, "🖵 Show window")
                    .on_hover_text(
                        "the Output in its own borderless window (F11); Esc in it closes it",
                    )
                    .clicked()
                {
                    self.toggle_show_window();
                }
                ui.add_enabled_ui(!open, |ui| {
                    ui.checkbox(&mut self.show_window.choice.fullscreen, "Fullscreen")
                        .on_hover_text("on the monitor the Output's Monitor pin names");
                    ui.checkbox(&mut self.show_window.choice.native, "Native size")
                        .on_hover_text("the window takes the texture's pixel size, 1:1");
                });
            });
        });
    }

    pub(super) fn status_bar(&mut self, ui: &mut Ui) {
        ui.horizontal(|ui| {
            let stats = self.frame.runtime.stats();
            ui.label(format!(
                "{} nodes · evaluated {} · reused {} · failed {} · cpu {:.3} ms",
                self.doc.patch().nodes.len(),
                stats.evaluated,
                stats.reused,
                stats.failed,
                stats.cpu_ns as f64 / 1e6
            ));
            if let Some(recording) = self.frame.recording.as_ref().filter(|r| r.recording) {
                ui.separator();
                ui.label(recording.describe());
            }
            if let Some(ui_s) = self.median_ui_seconds() {
                ui.separator();
                ui.label(format!("ui {:.1} ms", ui_s * 1e3));
            }
            ui.separator();
            ui.label(&self.status);
        });
    }
}
