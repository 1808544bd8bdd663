//! Help patches: F1 on a node (the one under the pointer, else the selected
//! one) opens the help patch of its family (`spreadlight_nodes::help`) in a
//! second editor window, read-only, beside this one; the patch runs there,
//! showing the node working. A read-only editor undoes every edit at once
//! and says so (a banner over the canvas, the status bar).

use super::*;

/// How F1 opens a help patch.
#[derive(Clone, Debug, Default, PartialEq, Eq)]
pub enum HelpLaunch {
    /// A second `spreadlight edit --read-only PATCH` process (this binary):
    /// its own window, its own patch worker.
    #[default]
    Process,
    /// Only record what would open (`EditorApp::help_opened`): tests.
    Record,
}

/// The banner a read-only editor shows over its canvas.
pub const READ_ONLY_BANNER: &str = "Help patch, read-only: edits are undone at once. Save as… writes a copy you can open and edit.";

impl EditorApp {
    /// How F1 opens help patches (a second process unless a test says otherwise).
    pub fn set_help_launch(&mut self, launch: HelpLaunch) {
        self.help_launch = launch;
    }

    /// The help patches F1 opened, in order.
    pub fn help_opened(&self) -> &[PathBuf] {
        &self.help_opened
    }

    /// How many edits a read-only editor undid.
    pub fn refused_edits(&self) -> u32 {
        self.refused_edits
    }

    /// F1: the help patch of the node under the pointer, else of the selected one.
    pub(super) fn help_key(&mut self, ctx: &egui::Context) {
        if self.dialog.is_some() || !ctx.input(|i| i.key_pressed(Key::F1)) {
            return;
        }
        let pointer = ctx.input(|i| i.pointer.hover_pos());
        let under = pointer.and_then(|p| {
            self.canvas
                .node_rects
                .iter()
                .rev()
                .find(|(_, r)| r.contains(p))
                .map(|(id, _)| *id)
        });
        let Some(id) = under.or_else(|| self.focus_node()) else {
            self.status = "F1: point at a node or select one for its help patch".to_owned();
            return;
        };
        let Some(type_name) = self.doc.node(id).map(|n| n.type_name.clone()) else {
            return;
        };
        self.open_help(&type_name);
    }

    /// Open the help patch for node type `type_name` beside this editor.
    pub fn open_help(&mut self, type_name: &str) {
        let Some(help) = spreadlight_nodes::help::for_type(type_name) else {
            self.status = format!("{type_name} has no help patch yet");
            return;
        };
        // The checkout's own file when there is one (its `../assets` resolve);
        // else the copy built into the binary, written out to open.
        let path = match help.source_file() {
            Some(path) => path,
            None => {
                let dir = self.options.config_dir.join("help");
                let path = dir.join(help.file);
                if let Err(e) =
                    std::fs::create_dir_all(&dir).and_then(|()| std::fs::write(&path, help.text))
                {
                    self.status = format!("cannot write {}: {e}", path.display());
                    return;
                }
                path
            }
        };
        if self.help_launch == HelpLaunch::Process {
            let spawned = std::env::current_exe().and_then(|exe| {
                std::process::Command::new(exe)
                    .arg("edit")
                    .arg("--read-only")
                    .arg(&path)
                    .spawn()
            });
            match spawned {
                // Reaped when it closes, whenever that is.
                Ok(mut child) => {
                    std::thread::spawn(move || child.wait());
                }
                Err(e) => {
                    self.status = format!("cannot open the help patch {}: {e}", path.display());
                    return;
                }
            }
        }
        self.status = format!(
            "help for {type_name}: {} (read-only, in its own window)",
            help.path()
        );
        self.help_opened.push(path);
    }

    /// A read-only editor takes every edit back as soon as it is made.
    pub(super) fn refuse_edits(&mut self) {
        if !self.options.read_only || !self.doc.can_undo() {
            return;
        }
        while self.doc.undo() {}
        self.refused_edits += 1;
        self.status = "read-only help patch: the edit was undone".to_owned();
    }

    /// The banner over a read-only editor's canvas.
    pub(super) fn read_only_banner(&mut self, ui: &mut Ui) {
        if self.options.read_only {
            egui::Panel::top("read-only").show(ui, |ui| {
                ui.colored_label(egui::Color32::from_rgb(255, 200, 90), READ_ONLY_BANNER);
            });
        }
    }
}
