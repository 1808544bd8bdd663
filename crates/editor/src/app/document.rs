//! The document's life: opening, replacing, saving, autosave and recovery.

use super::*;

impl EditorApp {
    pub(super) fn open_now(&mut self, path: &Path) {
        match format::load(path) {
            Ok(patch) => self.replace_document(EditorDoc::new(patch), Some(path.to_owned())),
            Err(e) => self.status = e.to_string(),
        }
    }

    pub(super) fn replace_document(&mut self, doc: EditorDoc, path: Option<PathBuf>) {
        // A help patch (read-only) is not a patch of the user's.
        if let Some(p) = path.as_ref().filter(|_| !self.options.read_only) {
            files::remember_recent(&self.options.config_dir, &mut self.recent, p);
        }
        self.doc = doc;
        self.path = path;
        self.instance.clear();
        self.canvas.forget_document();
        self.synced_generation = None;
        self.autosave.forget();
        self.transport.clock = FrameClock::default();
        // The patch's own shader folder: its node types join the registry.
        self.shaders = crate::shader_watch::ShaderWatch::new(self.path.as_deref());
        self.shaders.poll_now(&mut self.registry);
        self.worker.submit(Request {
            reset: Some(self.registry.clone()),
            ..Default::default()
        });
        self.provide_patch_dir();
        self.sent_generation = None;
        self.sent_views.clear();
        self.status = match &self.path {
            Some(p) => format!("opened {}", p.display()),
            None => "new patch".to_owned(),
        };
    }

    /// Relative file names on pins (textures, models) resolve beside the
    /// patch, as the CLI resolves them; an untitled patch has none.
    pub(super) fn provide_patch_dir(&mut self) {
        if let Some(dir) = self.path.as_deref().and_then(Path::parent) {
            self.worker.submit(Request {
                patch_dir: Some(dir.to_path_buf()),
                ..Default::default()
            });
        }
    }

    pub(super) fn recovery_file(&self) -> PathBuf {
        files::recovery_path(self.path.as_deref(), &self.options.config_dir)
    }

    /// Save to the current path; `false` when there is none (ask for one).
    pub fn save(&mut self) -> bool {
        let Some(path) = self.path.clone() else {
            return false;
        };
        self.save_as(&path)
    }

    /// Save the patch to `path`, and every subpatch file edited in place to its own file.
    pub fn save_as(&mut self, path: &Path) -> bool {
        let modules = match self.doc.save_module_files() {
            Ok(written) => written,
            Err(e) => {
                self.status = e.to_string();
                return false;
            }
        };
        match format::save(self.doc.top(), path) {
            Ok(()) => {
                let old_recovery = self.recovery_file();
                self.path = Some(path.to_owned());
                self.provide_patch_dir();
                self.doc.mark_saved();
                files::remove_recovery(&old_recovery);
                files::remove_recovery(&self.recovery_file());
                self.autosave.recovery_written = false;
                files::remember_recent(&self.options.config_dir, &mut self.recent, path);
                self.status = match modules.len() {
                    0 => format!("saved {}", path.display()),
                    n => format!("saved {} and {n} subpatch file(s)", path.display()),
                };
                true
            }
            Err(e) => {
                self.status = e.to_string();
                false
            }
        }
    }

    /// Open `path`, asking first when there are unsaved changes.
    pub fn request_open(&mut self, path: PathBuf) {
        if self.doc.is_dirty() {
            self.pending = Some(Pending::Open(path));
        } else {
            self.open_now(&path);
        }
    }

    pub(super) fn perform(&mut self, pending: Pending, ctx: &egui::Context) {
        match pending {
            Pending::Open(path) => self.open_now(&path),
            Pending::New => self.replace_document(EditorDoc::default(), None),
            Pending::Quit => {
                self.allow_close = true;
                ctx.send_viewport_cmd(ViewportCommand::Close);
            }
        }
    }

    /// Write the recovery file when the document changed and the last write
    /// is `autosave_secs` old; otherwise ask for a frame when it will be, so an
    /// idle editor (nothing repaints it) still saves the edit in time.
    pub(super) fn autosave(&mut self, now: f64, ctx: &egui::Context) {
        let recovery = self.recovery_file();
        match self
            .autosave
            .tick(&self.doc, &recovery, self.options.autosave_secs, now)
        {
            Autosaved::In(wait) => {
                ctx.request_repaint_after(std::time::Duration::from_secs_f64(wait));
            }
            Autosaved::Failed(e) => self.status = e,
            Autosaved::Nothing | Autosaved::Written => {}
        }
    }

    /// Restore the patch's autosave and its subpatch files' edits, all
    /// unsaved: nothing on disk changes until the user saves.
    pub(super) fn restore_recovery(&mut self, recovery: &Path) {
        let patch = match format::load(recovery) {
            Ok(patch) => patch,
            Err(e) => {
                self.status = format!("cannot restore the autosave: {e}");
                return;
            }
        };
        let modules = files::load_module_recovery(recovery);
        let path = self.path.clone();
        self.replace_document(EditorDoc::recovered(patch), path);
        let mut status = "restored unsaved changes from the autosave".to_owned();
        match modules {
            Ok(modules) => {
                if !modules.edits.is_empty() {
                    let names: Vec<&str> = modules.edits.iter().map(|e| e.name.as_str()).collect();
                    status += &format!(" and of subpatch files {}", names.join(", "));
                }
                for stale in &modules.stale {
                    status += &format!(
                        "; not restored: {} was saved after the autosave",
                        stale.display()
                    );
                }
                for (file, why) in self.doc.restore_module_files(modules.edits) {
                    status += &format!("; {why} (saving writes {} again)", file.display());
                }
            }
            Err(e) => status += &format!("; the subpatch files' edits cannot be restored: {e}"),
        }
        self.status = status;
    }
}
