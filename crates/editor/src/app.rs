//! The editor application: menus, canvas, inspector, viewports, autosave.

use std::collections::{BTreeSet, HashMap};
use std::path::{Path, PathBuf};
use std::sync::Arc;
use std::time::Instant;

use egui::{Id, Key, KeyboardShortcut, LayerId, Modifiers, Pos2, Ui, ViewportCommand};
use egui_snarl::Snarl;
use egui_snarl::ui::SnarlWidget;
use spreadlight_graph::{
    FrameClock, NodeId, PinRef, PinType, Registry, ResourceKind, Runtime, Spread, format,
};
use spreadlight_render::{GpuContext, Renderer, TextureRef};

use crate::browser;
use crate::canvas::{self, Canvas, CanvasNode, PinPositions, Refusal, SCALE};
use crate::files;
use crate::model::{Clip, EditorDoc};
use crate::values;
use crate::viewport::{self, Blitter, ViewTarget, ViewportError};

/// How the editor starts.
#[derive(Clone, Debug)]
pub struct EditorOptions {
    pub path: Option<PathBuf>,
    pub config_dir: PathBuf,
    /// Seconds between autosaves while there are unsaved changes.
    pub autosave_secs: f64,
    pub automation: Option<Automation>,
}

/// A scripted run of the real window: repaint for `frames` frames, then
/// optionally take a screenshot, print the frame times as JSON, and quit.
#[derive(Clone, Debug)]
pub struct Automation {
    pub frames: u32,
    pub screenshot: Option<PathBuf>,
}

#[derive(Default)]
struct AutoRun {
    frames: u32,
    last_start: Option<Instant>,
    intervals: Vec<f64>,
    ui: Vec<f64>,
    cpu: Vec<f64>,
    screenshot_sent: bool,
}

fn median_and_p95(v: &[f64]) -> (f64, f64) {
    let mut s = v.to_vec();
    s.sort_by(f64::total_cmp);
    if s.is_empty() {
        return (0.0, 0.0);
    }
    (s[s.len() / 2], s[(s.len() * 95 / 100).min(s.len() - 1)])
}

impl EditorOptions {
    pub fn new(path: Option<PathBuf>) -> Self {
        EditorOptions {
            path,
            config_dir: files::config_dir(),
            autosave_secs: 2.0,
            automation: None,
        }
    }
}

const CANVAS_ID: &str = "spreadlight-canvas";

/// Measure, fit, measure, fit (see `EditorApp::fit`).
const FIT_FROM_SCRATCH: u8 = 4;

struct BrowserState {
    /// Where the node goes, in patch units.
    at: (f32, f32),
    screen: Pos2,
    query: String,
    highlighted: usize,
    focus: bool,
}

#[derive(Clone, Debug, PartialEq)]
enum DialogMode {
    Open,
    SaveAs,
    PickValue {
        node: NodeId,
        pin: String,
        slice: usize,
    },
}

struct FileDialog {
    mode: DialogMode,
    dir: PathBuf,
    name: String,
}

/// What to do once the unsaved-changes question is answered.
#[derive(Clone, Debug, PartialEq)]
enum Pending {
    Open(PathBuf),
    New,
    Quit,
}

/// Which texture a viewport shows.
#[derive(Clone, Debug, PartialEq)]
enum Source {
    /// Nothing until a pin is picked (rendering the Output twice would cost for nothing).
    None,
    /// The selected Output node, or the first one.
    Output,
    Pin(NodeId, String),
}

struct Viewport {
    source: Source,
    target: Option<ViewTarget>,
    size: (u32, u32),
    error: Option<ViewportError>,
    rendered_size: (u32, u32),
}

impl Viewport {
    fn new(source: Source) -> Self {
        Viewport {
            source,
            target: None,
            size: (1, 1),
            error: None,
            rendered_size: (0, 0),
        }
    }
}

struct Gpu {
    state: egui_wgpu::RenderState,
    renderer: Arc<Renderer>,
    blitter: Blitter,
}

pub struct EditorApp {
    registry: Registry,
    doc: EditorDoc,
    path: Option<PathBuf>,
    options: EditorOptions,
    recent: Vec<PathBuf>,
    runtime: Runtime,
    loaded_generation: Option<u64>,
    gpu: Option<Gpu>,
    gpu_error: Option<String>,
    viewports: [Viewport; 2],
    viewport_rects: [Option<egui::Rect>; 2],
    gpu_ms: HashMap<u32, f64>,
    /// Errors of the viewport's passes, by the node that declared them.
    gpu_errors: HashMap<u32, String>,
    snarl: Snarl<CanvasNode>,
    snarl_ids: HashMap<NodeId, egui_snarl::NodeId>,
    selected: BTreeSet<NodeId>,
    focused: Option<NodeId>,
    /// Where a Shift-drag selection rectangle started, while it is being drawn.
    rect_select: Option<Pos2>,
    /// Fitting the view to the patch alternates measuring the nodes (even)
    /// and fitting them (odd) down to 0, twice: node sizes change with zoom
    /// (editors are left out when small), so one pass may not settle.
    fit: u8,
    node_rects: Vec<(NodeId, egui::Rect)>,
    canvas_rect: Option<egui::Rect>,
    browser: Option<BrowserState>,
    refusal: Option<Refusal>,
    clipboard: Clip,
    pastes: u32,
    clock: FrameClock,
    playing: bool,
    step: bool,
    show_timings: bool,
    status: String,
    autosaved_generation: Option<u64>,
    last_autosave: f64,
    recovery_written: bool,
    recovery_offer: Option<PathBuf>,
    pending: Option<Pending>,
    allow_close: bool,
    dialog: Option<FileDialog>,
    pins: PinPositions,
    canvas_layer: Option<LayerId>,
    synced_generation: Option<u64>,
    last_pointer: Pos2,
    title: String,
    ui_times: std::collections::VecDeque<f64>,
    evaluations: u64,
    auto: AutoRun,
}

impl EditorApp {
    /// Build the editor on eframe's context; uses eframe's wgpu device for the renderer when there is one.
    pub fn new(cc: &eframe::CreationContext<'_>, options: EditorOptions) -> Self {
        let render_state = cc.wgpu_render_state.clone();
        Self::with_render_state(render_state, options)
    }

    pub fn with_render_state(
        render_state: Option<egui_wgpu::RenderState>,
        options: EditorOptions,
    ) -> Self {
        let registry = crate::nodes::registry();
        let mut runtime = Runtime::new(registry.clone());
        let (gpu, gpu_error) = match render_state {
            Some(state) => {
                let context = GpuContext::from_parts(
                    state.device.clone(),
                    state.queue.clone(),
                    state.adapter.get_info(),
                );
                match Renderer::new(context) {
                    Ok(renderer) => {
                        // One command encoder a frame (docs/benchmarks.md); a
                        // failing frame falls back to a pass at a time.
                        renderer.set_recording(spreadlight_render::renderer::Recording::Batched);
                        let renderer = Arc::new(renderer);
                        runtime.provide(renderer.clone());
                        let blitter = Blitter::new(&state.device);
                        (
                            Some(Gpu {
                                state,
                                renderer,
                                blitter,
                            }),
                            None,
                        )
                    }
                    Err(e) => (None, Some(e.to_string())),
                }
            }
            None => (
                None,
                Some("no wgpu device: the editor runs without viewports".to_owned()),
            ),
        };
        let recent = files::load_recent(&options.config_dir);
        let mut app = EditorApp {
            registry,
            doc: EditorDoc::default(),
            path: None,
            options: options.clone(),
            recent,
            runtime,
            loaded_generation: None,
            gpu,
            gpu_error,
            viewports: [Viewport::new(Source::Output), Viewport::new(Source::None)],
            viewport_rects: [None; 2],
            gpu_ms: HashMap::new(),
            gpu_errors: HashMap::new(),
            snarl: Snarl::new(),
            snarl_ids: HashMap::new(),
            selected: BTreeSet::new(),
            focused: None,
            rect_select: None,
            fit: FIT_FROM_SCRATCH,
            node_rects: Vec::new(),
            canvas_rect: None,
            browser: None,
            refusal: None,
            clipboard: Clip::default(),
            pastes: 0,
            clock: FrameClock::default(),
            playing: true,
            step: false,
            show_timings: false,
            status: String::new(),
            autosaved_generation: None,
            last_autosave: 0.0,
            recovery_written: false,
            recovery_offer: None,
            pending: None,
            allow_close: false,
            dialog: None,
            pins: PinPositions::default(),
            canvas_layer: None,
            synced_generation: None,
            last_pointer: Pos2::ZERO,
            title: String::new(),
            ui_times: std::collections::VecDeque::new(),
            evaluations: 0,
            auto: AutoRun::default(),
        };
        match options.path {
            // `spreadlight edit new.ron` starts that patch, as text editors do.
            Some(path) if !path.exists() => {
                app.path = Some(path.clone());
                app.status = format!("new patch {}", path.display());
            }
            Some(path) => app.open_now(&path),
            None => {}
        }
        app.recovery_offer = files::pending_recovery(app.path.as_deref(), &app.options.config_dir);
        app
    }

    // ----- what tests and the CLI read -----

    pub fn doc(&self) -> &EditorDoc {
        &self.doc
    }

    pub fn doc_mut(&mut self) -> &mut EditorDoc {
        &mut self.doc
    }

    pub fn path(&self) -> Option<&Path> {
        self.path.as_deref()
    }

    pub fn runtime(&self) -> &Runtime {
        &self.runtime
    }

    pub fn registry(&self) -> &Registry {
        &self.registry
    }

    pub fn status(&self) -> &str {
        &self.status
    }

    pub fn title(&self) -> String {
        let name = self.path.as_ref().and_then(|p| p.file_name()).map_or_else(
            || "untitled".to_owned(),
            |n| n.to_string_lossy().into_owned(),
        );
        let mark = if self.doc.is_dirty() { "*" } else { "" };
        format!("{mark}{name} — Spreadlight")
    }

    /// Where a pin was drawn last frame, in screen points.
    pub fn pin_pos(&self, node: NodeId, pin: &str, input: bool) -> Option<Pos2> {
        self.pins
            .borrow()
            .get(&(node, pin.to_owned(), input))
            .copied()
    }

    /// Where a point of the canvas (as its widgets report their rects) is on screen.
    pub fn canvas_to_screen(&self, ctx: &egui::Context, p: Pos2) -> Pos2 {
        self.canvas_layer
            .and_then(|l| ctx.layer_transform_to_global(l))
            .map_or(p, |t| t * p)
    }

    /// Each node's rectangle on screen last frame, and the canvas's.
    pub fn node_screen_rects(&self) -> &[(NodeId, egui::Rect)] {
        &self.node_rects
    }

    pub fn canvas_rect(&self) -> Option<egui::Rect> {
        self.canvas_rect
    }

    pub fn selected(&self) -> Vec<NodeId> {
        self.selected.iter().copied().collect()
    }

    pub fn select(&mut self, ids: &[NodeId]) {
        self.selected = ids.iter().copied().collect();
    }

    pub fn refusal(&self) -> Option<&str> {
        self.refusal.as_ref().map(|r| r.message.as_str())
    }

    pub fn recovery_offered(&self) -> bool {
        self.recovery_offer.is_some()
    }

    pub fn is_playing(&self) -> bool {
        self.playing
    }

    pub fn set_playing(&mut self, playing: bool) {
        self.playing = playing;
    }

    /// The frame the patch clock is at: it advances while playing and on Step.
    pub fn frame(&self) -> u64 {
        self.clock.frame
    }

    /// How many times the patch was evaluated: it runs only on change or while playing.
    pub fn evaluations(&self) -> u64 {
        self.evaluations
    }

    /// The egui texture a viewport shows, once something was rendered into it.
    pub fn viewport_texture(&self, index: usize) -> Option<&wgpu::Texture> {
        self.viewports
            .get(index)?
            .target
            .as_ref()
            .map(|t| &t.texture)
    }

    /// Where a viewport's image was drawn last frame, in points.
    pub fn viewport_rect(&self, index: usize) -> Option<egui::Rect> {
        self.viewport_rects.get(index).copied().flatten()
    }

    pub fn viewport_error(&self, index: usize) -> Option<String> {
        self.viewports
            .get(index)?
            .error
            .as_ref()
            .map(ToString::to_string)
    }

    pub fn gpu_error(&self) -> Option<&str> {
        self.gpu_error.as_deref()
    }

    /// Median seconds the editor's `ui` took over the recent frames.
    pub fn median_ui_seconds(&self) -> Option<f64> {
        let mut v: Vec<f64> = self.ui_times.iter().copied().collect();
        if v.is_empty() {
            return None;
        }
        v.sort_by(f64::total_cmp);
        Some(v[v.len() / 2])
    }

    // ----- files -----

    fn open_now(&mut self, path: &Path) {
        match format::load(path) {
            Ok(patch) => self.replace_document(EditorDoc::new(patch), Some(path.to_owned())),
            Err(e) => self.status = e.to_string(),
        }
    }

    fn replace_document(&mut self, doc: EditorDoc, path: Option<PathBuf>) {
        if let Some(p) = &path {
            files::remember_recent(&self.options.config_dir, &mut self.recent, p);
        }
        self.doc = doc;
        self.path = path;
        self.selected.clear();
        self.snarl = Snarl::new();
        self.snarl_ids.clear();
        self.synced_generation = None;
        self.fit = FIT_FROM_SCRATCH;
        self.autosaved_generation = None;
        self.recovery_written = false;
        self.clock = FrameClock::default();
        self.runtime = Runtime::new(self.registry.clone());
        if let Some(gpu) = &self.gpu {
            self.runtime.provide(gpu.renderer.clone());
            gpu.renderer.reset_history();
        }
        self.provide_patch_dir();
        self.loaded_generation = None;
        self.status = match &self.path {
            Some(p) => format!("opened {}", p.display()),
            None => "new patch".to_owned(),
        };
    }

    /// Relative file names on pins (textures, models) resolve beside the
    /// patch, as the CLI resolves them; an untitled patch has none.
    fn provide_patch_dir(&mut self) {
        if let Some(dir) = self.path.as_deref().and_then(Path::parent) {
            self.runtime
                .provide(Arc::new(spreadlight_graph::PatchDir(dir.to_path_buf())));
        }
    }

    fn recovery_file(&self) -> PathBuf {
        files::recovery_path(self.path.as_deref(), &self.options.config_dir)
    }

    /// Save to the current path; `false` when there is none (ask for one).
    pub fn save(&mut self) -> bool {
        let Some(path) = self.path.clone() else {
            return false;
        };
        self.save_as(&path)
    }

    pub fn save_as(&mut self, path: &Path) -> bool {
        match format::save(self.doc.patch(), path) {
            Ok(()) => {
                let old_recovery = self.recovery_file();
                self.path = Some(path.to_owned());
                self.provide_patch_dir();
                self.doc.mark_saved();
                files::remove_recovery(&old_recovery);
                files::remove_recovery(&self.recovery_file());
                self.recovery_written = false;
                files::remember_recent(&self.options.config_dir, &mut self.recent, path);
                self.status = format!("saved {}", path.display());
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

    fn perform(&mut self, pending: Pending, ctx: &egui::Context) {
        match pending {
            Pending::Open(path) => self.open_now(&path),
            Pending::New => self.replace_document(EditorDoc::default(), None),
            Pending::Quit => {
                self.allow_close = true;
                ctx.send_viewport_cmd(ViewportCommand::Close);
            }
        }
    }

    fn autosave(&mut self, now: f64) {
        if !self.doc.is_dirty() {
            if self.recovery_written {
                files::remove_recovery(&self.recovery_file());
                self.recovery_written = false;
            }
            return;
        }
        if self.autosaved_generation == Some(self.doc.generation())
            || now - self.last_autosave < self.options.autosave_secs
        {
            return;
        }
        self.last_autosave = now;
        match files::write_recovery(self.doc.patch(), &self.recovery_file()) {
            Ok(()) => {
                self.autosaved_generation = Some(self.doc.generation());
                self.recovery_written = true;
            }
            Err(e) => self.status = format!("autosave failed: {e}"),
        }
    }

    fn restore_recovery(&mut self, recovery: &Path) {
        match format::load(recovery) {
            Ok(patch) => {
                let path = self.path.clone();
                self.replace_document(EditorDoc::recovered(patch), path);
                self.status = "restored unsaved changes from the autosave".to_owned();
            }
            Err(e) => self.status = format!("cannot restore the autosave: {e}"),
        }
    }

    // ----- edits -----

    /// The node the inspector shows: the last one clicked, while it is selected.
    fn focus_node(&self) -> Option<NodeId> {
        self.focused
            .filter(|id| self.selected.contains(id))
            .or_else(|| self.selected.last().copied())
    }

    pub fn delete_selected(&mut self) {
        let ids = self.selected();
        self.doc.delete_nodes(&ids);
        self.selected.clear();
    }

    /// Copy the selection; with a context, also onto the system clipboard as
    /// patch text, so another editor window (or a text editor) can take it.
    pub fn copy_selected(&mut self, ctx: Option<&egui::Context>) {
        let ids = self.selected();
        if !ids.is_empty() {
            self.clipboard = self.doc.copy(&ids);
            self.pastes = 0;
            self.status = format!("copied {} nodes", ids.len());
            let as_patch = spreadlight_graph::Patch {
                nodes: self.clipboard.nodes.clone(),
                links: self.clipboard.links.clone(),
                ..Default::default()
            };
            if let (Some(ctx), Ok(text)) = (ctx, format::to_string(&as_patch)) {
                ctx.copy_text(text);
            }
        }
    }

    /// Take nodes pasted from the system clipboard when the text is a patch.
    fn take_pasted_text(&mut self, text: &str) {
        if let Ok(patch) = format::from_str(text, Path::new("clipboard")) {
            let clip = Clip {
                nodes: patch.nodes,
                links: patch.links,
            };
            if clip != self.clipboard {
                self.clipboard = clip;
                self.pastes = 0;
            }
        }
    }

    pub fn paste(&mut self) {
        self.pastes += 1;
        let d = 20.0 * self.pastes as f32;
        let ids = self.doc.paste(&self.clipboard.clone(), (d, d));
        if !ids.is_empty() {
            self.selected = ids.into_iter().collect();
        }
    }

    pub fn duplicate_selected(&mut self) {
        let ids = self.selected();
        let new = self.doc.duplicate(&ids, (20.0, 20.0));
        if !new.is_empty() {
            self.selected = new.into_iter().collect();
        }
    }

    // ----- runtime and viewports -----

    /// Reload on change; with `dt`, also advance time when playing or stepping.
    fn evaluate_if_needed(&mut self, dt: Option<f64>) {
        let mut run = false;
        if self.loaded_generation != Some(self.doc.generation()) {
            self.runtime.load(self.doc.patch());
            self.loaded_generation = Some(self.doc.generation());
            run = true;
        }
        if let Some(dt) = dt {
            if self.playing {
                self.clock.advance(dt);
                run = true;
            } else if self.step {
                self.clock.advance(1.0 / 60.0);
                run = true;
            }
            self.step = false;
        }
        if run {
            self.runtime.evaluate(self.clock);
            self.evaluations += 1;
            for v in &mut self.viewports {
                v.rendered_size = (0, 0);
            }
        }
    }

    /// The texture a viewport's source points at, if the runtime has one.
    fn texture_of(&self, source: &Source) -> Result<TextureRef, ViewportError> {
        let (node, pin) = match source {
            Source::None => return Err(ViewportError::NoTexture),
            Source::Pin(node, pin) => (*node, pin.clone()),
            Source::Output => {
                let patch = self.doc.patch();
                let is_output =
                    |id: &NodeId| patch.node(*id).is_some_and(|n| n.type_name == "Output");
                let chosen = self
                    .selected()
                    .into_iter()
                    .rev()
                    .find(is_output)
                    .or_else(|| patch.nodes.iter().map(|n| n.id).find(is_output))
                    .ok_or(ViewportError::NoTexture)?;
                let link = self
                    .doc
                    .link_into(&PinRef(chosen, "Texture".to_owned()))
                    .ok_or(ViewportError::NoTexture)?;
                (link.from.node(), link.from.pin().to_owned())
            }
        };
        let needed = self
            .runtime
            .network()
            .index_of(node)
            .is_some_and(|i| self.runtime.network().is_needed(i));
        if !needed {
            return Err(ViewportError::NotEvaluated(format!("{node}.{pin}")));
        }
        match self.runtime.output(node, &pin).map(|s| &**s) {
            Some(Spread::Resource(ResourceKind::Texture, handles)) => handles
                .first()
                .and_then(|h| h.downcast_arc::<TextureRef>())
                .map(|t| (*t).clone())
                .ok_or(ViewportError::NoTexture),
            _ => Err(ViewportError::NoTexture),
        }
    }

    fn render_viewports(&mut self) {
        let Some(gpu) = &self.gpu else {
            return;
        };
        for k in 0..self.viewports.len() {
            let size = self.viewports[k].size;
            if self.viewports[k].rendered_size == size {
                continue;
            }
            let texture = self.texture_of(&self.viewports[k].source);
            let v = &mut self.viewports[k];
            v.rendered_size = size;
            let result = texture.and_then(|t| {
                viewport::render_into(
                    &gpu.state,
                    &gpu.renderer,
                    &gpu.blitter,
                    &t,
                    size,
                    &mut v.target,
                )
            });
            match result {
                Ok(report) => {
                    v.error = None;
                    if k == 0 {
                        self.gpu_ms.clear();
                        for pass in report.passes {
                            if let (Some(owner), Some(ms)) = (pass.owner, pass.gpu_ms) {
                                *self.gpu_ms.entry(owner).or_default() += ms;
                            }
                        }
                        self.gpu_errors.clear();
                        for (owner, message) in report.errors {
                            if let Some(owner) = owner {
                                self.gpu_errors.insert(owner, message);
                            }
                        }
                    }
                }
                Err(e) => v.error = Some(e),
            }
        }
    }

    // ----- the frame -----

    fn shortcuts(&mut self, ctx: &egui::Context) {
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
        if consume(cmd(Key::D)) {
            self.duplicate_selected();
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
            self.selected.clear();
        }
        if ctx.input_mut(|i| i.consume_key(Modifiers::NONE, Key::F)) {
            self.fit = FIT_FROM_SCRATCH;
        }
    }

    fn open_dialog(&mut self, mode: DialogMode) {
        let dir = self
            .path
            .as_ref()
            .and_then(|p| p.parent().map(Path::to_path_buf))
            .filter(|p| !p.as_os_str().is_empty())
            .or_else(|| std::env::current_dir().ok())
            .unwrap_or_default();
        let name = match &mode {
            DialogMode::SaveAs => self.path.as_ref().and_then(|p| p.file_name()).map_or_else(
                || "untitled.ron".to_owned(),
                |n| n.to_string_lossy().into_owned(),
            ),
            _ => String::new(),
        };
        self.dialog = Some(FileDialog { mode, dir, name });
    }

    fn menu_bar(&mut self, ui: &mut Ui) {
        egui::MenuBar::new().ui(ui, |ui| {
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
            });
            ui.separator();
            let play = if self.playing {
                "⏸ Pause"
            } else {
                "▶ Play"
            };
            if ui.button(play).clicked() {
                self.playing = !self.playing;
            }
            if ui.button("⏭ Step").clicked() {
                self.playing = false;
                self.step = true;
            }
            ui.label(format!(
                "frame {} · {:.2} s",
                self.clock.frame, self.clock.time
            ));
            ui.separator();
            if ui
                .button("⛶ Fit")
                .on_hover_text("show the whole patch (F)")
                .clicked()
            {
                self.fit = FIT_FROM_SCRATCH;
            }
            ui.toggle_value(&mut self.show_timings, "⏱ Timings")
                .on_hover_text("CPU time per node, GPU time per render node");
        });
    }

    fn status_bar(&mut self, ui: &mut Ui) {
        ui.horizontal(|ui| {
            let stats = self.runtime.stats();
            ui.label(format!(
                "{} nodes · evaluated {} · reused {} · failed {} · cpu {:.3} ms",
                self.doc.patch().nodes.len(),
                stats.evaluated,
                stats.reused,
                stats.failed,
                stats.cpu_ns as f64 / 1e6
            ));
            if let Some(ui_s) = self.median_ui_seconds() {
                ui.separator();
                ui.label(format!("ui {:.1} ms", ui_s * 1e3));
            }
            ui.separator();
            ui.label(&self.status);
        });
    }

    fn inspector(&mut self, ui: &mut Ui) {
        ui.heading("Inspector");
        let Some(id) = self.focus_node() else {
            ui.weak("Click a node to inspect it.");
            return;
        };
        let Some(node) = self.doc.patch().node(id).cloned() else {
            return;
        };
        ui.label(egui::RichText::new(format!("{} {}", node.type_name, id)).strong());
        let Some(def) = self.registry.get(&node.type_name).cloned() else {
            ui.colored_label(
                egui::Color32::LIGHT_RED,
                "unknown node type: kept as it is, not run",
            );
            return;
        };
        ui.weak(def.help);
        if let Some(e) = self.runtime.node_error(id) {
            ui.colored_label(egui::Color32::LIGHT_RED, e.to_string());
        }
        ui.separator();
        egui::ScrollArea::vertical().show(ui, |ui| {
            for pin in &def.inputs {
                ui.push_id(pin.name, |ui| {
                    let label = ui
                        .horizontal(|ui| {
                            let label = ui.label(egui::RichText::new(pin.name).strong());
                            ui.weak(pin.ty.name());
                            label.id
                        })
                        .inner;
                    let target = PinRef(id, pin.name.to_owned());
                    if let Some(link) = self.doc.link_into(&target).cloned() {
                        ui.horizontal(|ui| {
                            ui.weak(format!("linked from {}", link.from));
                            if ui.small_button("unlink").clicked() {
                                self.doc.unlink(&link.from, &link.to);
                            }
                        });
                    } else if values::editable(pin.ty) {
                        let mut value = node
                            .values
                            .get(pin.name)
                            .cloned()
                            .unwrap_or_else(|| pin.default.clone());
                        let edited =
                            values::edit_spread(ui, pin.ty, &mut value, pin.name, Some(label));
                        if edited.changed {
                            self.doc
                                .set_value(id, pin.name, Some(value), edited.continuing);
                        }
                        if node.values.contains_key(pin.name)
                            && ui.small_button("reset to default").clicked()
                        {
                            self.doc.set_value(id, pin.name, None, false);
                        }
                    }
                    ui.add_space(4.0);
                });
            }
            ui.separator();
            for pin in &def.outputs {
                let value = self
                    .runtime
                    .output(id, pin.name)
                    .map_or_else(|| "not evaluated".to_owned(), |s| canvas::preview(s));
                ui.label(format!("{} → {value}", pin.name));
            }
        });
        let request: Option<(String, usize)> = ui
            .ctx()
            .data_mut(|d| d.remove_temp(Id::new("file-picker-request")));
        if let Some((pin, slice)) = request {
            self.open_dialog(DialogMode::PickValue {
                node: id,
                pin,
                slice,
            });
        }
    }

    fn texture_pins(&self) -> Vec<(NodeId, &'static str, String)> {
        let mut out = Vec::new();
        for n in &self.doc.patch().nodes {
            if let Some(def) = self.registry.get(&n.type_name) {
                for p in &def.outputs {
                    if p.ty == PinType::Resource(ResourceKind::Texture) {
                        out.push((n.id, p.name, format!("{} {}.{}", n.type_name, n.id, p.name)));
                    }
                }
            }
        }
        out
    }

    fn viewport_ui(&mut self, ui: &mut Ui, k: usize, label: Option<Id>) {
        if k == 1 {
            let pins = self.texture_pins();
            let current = match &self.viewports[1].source {
                Source::None => "none".to_owned(),
                Source::Output => "Output".to_owned(),
                Source::Pin(n, p) => format!("{n}.{p}"),
            };
            let combo = egui::ComboBox::from_id_salt("second-viewport")
                .selected_text(current)
                .show_ui(ui, |ui| {
                    if ui
                        .selectable_label(self.viewports[1].source == Source::Output, "Output")
                        .clicked()
                    {
                        self.viewports[1].source = Source::Output;
                        self.viewports[1].rendered_size = (0, 0);
                    }
                    for (node, pin, label) in pins {
                        let source = Source::Pin(node, pin.to_owned());
                        if ui
                            .selectable_label(self.viewports[1].source == source, label)
                            .clicked()
                        {
                            self.viewports[1].source = source;
                            self.viewports[1].rendered_size = (0, 0);
                        }
                    }
                });
            if let Some(label) = label {
                combo.response.labelled_by(label);
            }
        }
        let avail = ui.available_size();
        let ppp = ui.ctx().pixels_per_point();
        let size = (
            ((avail.x * ppp) as u32).clamp(16, 4096),
            ((avail.y * ppp) as u32).clamp(16, 4096),
        );
        self.viewports[k].size = size;
        let v = &self.viewports[k];
        match (&v.target, &v.error) {
            (_, Some(e)) => {
                ui.weak(e.to_string());
            }
            (Some(t), None) => {
                let tex_size =
                    egui::vec2(t.texture.width() as f32, t.texture.height() as f32) / ppp;
                let r = ui.add(egui::Image::new((t.id, tex_size)).fit_to_exact_size(avail));
                self.viewport_rects[k] = Some(r.rect);
            }
            (None, None) => {
                ui.weak(
                    self.gpu_error
                        .clone()
                        .unwrap_or_else(|| "nothing rendered yet".to_owned()),
                );
            }
        }
    }

    fn canvas(&mut self, ui: &mut Ui) {
        let dragging = ui.input(|i| i.pointer.any_down());
        let changed = self.synced_generation != Some(self.doc.generation());
        canvas::sync(
            &mut self.snarl,
            &mut self.snarl_ids,
            &self.doc,
            &self.registry,
            changed,
        );
        self.synced_generation = Some(self.doc.generation());
        let now = ui.input(|i| i.time);
        let layer = LayerId::new(ui.layer_id().order, Id::new(CANVAS_ID));
        self.canvas_layer = Some(layer);
        if let Some(p) = ui.input(|i| i.pointer.latest_pos()) {
            self.last_pointer = p;
        }
        // Labels that select text would take the drags that move nodes.
        ui.style_mut().interaction.selectable_labels = false;
        let canvas_rect = ui.max_rect().shrink(8.0);
        self.canvas_rect = Some(canvas_rect);
        let set_view = match ui.ctx().layer_transform_to_global(layer) {
            Some(view) if !self.fit.is_multiple_of(2) => {
                self.fit -= 1;
                ui.ctx().request_repaint();
                canvas::fit_view(view, &self.node_rects, canvas_rect)
            }
            _ => None,
        };
        let mut node_rects = Vec::new();
        let response = {
            let mut viewer = Canvas {
                doc: &mut self.doc,
                registry: &self.registry,
                runtime: &self.runtime,
                selected: &self.selected,
                node_rects: &mut node_rects,
                show_timings: self.show_timings,
                gpu_ms: &self.gpu_ms,
                gpu_errors: &self.gpu_errors,
                refusal: &mut self.refusal,
                pins: self.pins.clone(),
                pointer: self.last_pointer,
                set_view,
                now,
            };
            SnarlWidget::new()
                .id(Id::new(CANVAS_ID))
                .style(canvas::style())
                .show(&mut self.snarl, &mut viewer, ui)
        };
        if !dragging {
            let moves = canvas::moved_nodes(&self.snarl, &self.doc);
            self.doc.move_nodes(&moves);
        }
        let double = ui.input(|i| {
            i.pointer
                .button_double_clicked(egui::PointerButton::Primary)
        });
        if double
            && response.hovered()
            && let Some(screen) = ui.input(|i| i.pointer.interact_pos())
        {
            let from_global = ui
                .ctx()
                .layer_transform_from_global(layer)
                .unwrap_or_default();
            let g = from_global * screen;
            self.browser = Some(BrowserState {
                at: ((g.x / SCALE).round(), (g.y / SCALE).round()),
                screen,
                query: String::new(),
                highlighted: 0,
                focus: true,
            });
        } else if ui.input(|i| i.pointer.primary_clicked())
            && let Some(p) = ui.input(|i| i.pointer.interact_pos())
            && ui.max_rect().contains(p)
        {
            let add = ui.input(|i| i.modifiers.shift || i.modifiers.command);
            let hit = node_rects
                .iter()
                .rev()
                .find(|(_, r)| r.contains(p))
                .map(|(id, _)| *id);
            match hit {
                Some(id) if add && self.selected.contains(&id) => {
                    self.selected.remove(&id);
                }
                Some(id) => {
                    if !add {
                        self.selected.clear();
                    }
                    self.selected.insert(id);
                    self.focused = Some(id);
                }
                None if response.hovered() && !add => self.selected.clear(),
                None => {}
            }
        }
        self.rectangle_selection(ui, &response, &node_rects);
        if self.fit > 0 && self.fit.is_multiple_of(2) {
            // An empty patch has nothing to fit; its first node must not jump the view.
            self.fit = if node_rects.is_empty() {
                0
            } else {
                self.fit - 1
            };
            ui.ctx().request_repaint();
        }
        self.node_rects = node_rects.clone();
        // Hovering a wire shows what flows through it, as hovering its output pin does.
        if response.hovered()
            && let Some(p) = ui.input(|i| i.pointer.hover_pos())
            && !node_rects.iter().any(|(_, r)| r.contains(p))
            && let Some(link) = canvas::wire_under(&self.doc, &self.pins, p, 5.0)
        {
            let value = self
                .runtime
                .output(link.from.node(), link.from.pin())
                .map_or_else(|| "not evaluated".to_owned(), |s| canvas::preview(s));
            egui::Area::new(Id::new("wire-value"))
                .fixed_pos(p + egui::vec2(14.0, 14.0))
                .order(egui::Order::Tooltip)
                .interactable(false)
                .show(ui.ctx(), |ui| {
                    egui::Frame::popup(ui.style()).show(ui, |ui| {
                        ui.label(format!("{} → {}\n{value}", link.from, link.to));
                    });
                });
        }
        if let Some(r) = &self.refusal {
            if now - r.since > 4.0 {
                self.refusal = None;
            } else {
                egui::Area::new(Id::new("link-refused"))
                    .fixed_pos(r.at + egui::vec2(12.0, 12.0))
                    .order(egui::Order::Tooltip)
                    // It must not catch the next drop on the pins under it.
                    .interactable(false)
                    .show(ui.ctx(), |ui| {
                        egui::Frame::popup(ui.style()).show(ui, |ui| {
                            ui.colored_label(
                                egui::Color32::LIGHT_RED,
                                format!("Link refused: {}", r.message),
                            );
                        });
                    });
                ui.ctx().request_repaint();
            }
        }
    }

    /// Shift-drag on empty canvas selects every node the rectangle touches
    /// (Shift keeps the selection and adds to it, as Shift-click does).
    fn rectangle_selection(
        &mut self,
        ui: &Ui,
        canvas: &egui::Response,
        node_rects: &[(NodeId, egui::Rect)],
    ) {
        let (pressed, released, shift, pos) = ui.input(|i| {
            (
                i.pointer.primary_pressed(),
                i.pointer.primary_released(),
                i.modifiers.shift,
                i.pointer.latest_pos(),
            )
        });
        let Some(pos) = pos.map(|p| p.clamp(ui.max_rect().min, ui.max_rect().max)) else {
            return;
        };
        // `contains_pointer`, not `hovered`: with Shift held snarl puts its own
        // (hidden) selection layer over the canvas.
        let on_empty_canvas =
            canvas.contains_pointer() && !node_rects.iter().any(|(_, r)| r.contains(pos));
        if pressed && shift && on_empty_canvas {
            self.rect_select = Some(pos);
        }
        let Some(start) = self.rect_select else {
            return;
        };
        let area = egui::Rect::from_two_pos(start, pos);
        ui.ctx()
            .layer_painter(LayerId::new(
                egui::Order::Foreground,
                Id::new("rect-select"),
            ))
            .rect(
                area,
                0.0,
                egui::Color32::from_rgba_unmultiplied(90, 170, 255, 30),
                egui::Stroke::new(1.0, egui::Color32::from_rgb(90, 170, 255)),
                egui::StrokeKind::Inside,
            );
        if released {
            self.rect_select = None;
            for (id, r) in node_rects {
                if r.intersects(area) {
                    self.selected.insert(*id);
                }
            }
        }
    }

    fn node_browser(&mut self, ctx: &egui::Context) {
        let Some(b) = &mut self.browser else {
            return;
        };
        let hits = browser::filter(&self.registry, &b.query);
        let mut place = None;
        let mut close = false;
        let opened_now = b.focus;
        let area = egui::Area::new(Id::new("node-browser"))
            .fixed_pos(b.screen)
            .order(egui::Order::Foreground)
            .show(ctx, |ui| {
                egui::Frame::popup(ui.style()).show(ui, |ui| {
                    ui.set_width(260.0);
                    let (down, up, enter, escape) = ui.input(|i| {
                        (
                            i.key_pressed(Key::ArrowDown),
                            i.key_pressed(Key::ArrowUp),
                            i.key_pressed(Key::Enter),
                            // egui takes Esc to unfocus the text field; the raw input still has it.
                            i.raw.events.iter().any(|e| {
                                matches!(
                                    e,
                                    egui::Event::Key {
                                        key: Key::Escape,
                                        pressed: true,
                                        ..
                                    }
                                )
                            }),
                        )
                    });
                    let edit = ui.add(
                        egui::TextEdit::singleline(&mut b.query)
                            .hint_text("type a node name or category")
                            .id(Id::new("node-browser-query")),
                    );
                    if b.focus {
                        edit.request_focus();
                        b.focus = false;
                    }
                    if edit.changed() {
                        b.highlighted = 0;
                    }
                    if down {
                        b.highlighted = (b.highlighted + 1).min(hits.len().saturating_sub(1));
                    }
                    if up {
                        b.highlighted = b.highlighted.saturating_sub(1);
                    }
                    if enter {
                        place = hits.get(b.highlighted).copied();
                        close = true;
                    }
                    if escape {
                        close = true;
                    }
                    egui::ScrollArea::vertical()
                        .max_height(300.0)
                        .show(ui, |ui| {
                            for (i, name) in hits.iter().enumerate() {
                                let category = self.registry.get(name).map_or("", |d| d.category);
                                let r = ui
                                    .selectable_label(i == b.highlighted, *name)
                                    .on_hover_text(self.registry.get(name).map_or("", |d| d.help));
                                ui.weak(category);
                                if r.clicked() {
                                    place = Some(*name);
                                    close = true;
                                }
                            }
                        });
                });
            });
        // A click anywhere else closes it, as a popup menu does.
        if !opened_now && area.response.clicked_elsewhere() {
            close = true;
        }
        if let Some(name) = place {
            let at = b.at;
            let id = self.doc.add_node(name, at);
            self.selected = [id].into_iter().collect();
        }
        if close {
            self.browser = None;
        }
    }

    fn dialogs(&mut self, ctx: &egui::Context) {
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

    fn file_dialog(&mut self, ctx: &egui::Context) {
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

    /// The scripted run: count frames, then screenshot, report and quit.
    fn automate(&mut self, ctx: &egui::Context, frame: Option<&eframe::Frame>, started: Instant) {
        let Some(auto) = self.options.automation.clone() else {
            return;
        };
        ctx.request_repaint();
        let nodes = self.doc.patch().nodes.len();
        let viewport_error = self.viewport_error(0).unwrap_or_default();
        let a = &mut self.auto;
        if let Some(last) = a.last_start {
            a.intervals.push(started.duration_since(last).as_secs_f64());
        }
        a.last_start = Some(started);
        a.ui.push(started.elapsed().as_secs_f64());
        if let Some(cpu) = frame.and_then(|f| f.info().cpu_usage) {
            a.cpu.push(f64::from(cpu));
        }
        a.frames += 1;
        let shot = ctx.input(|i| {
            i.events.iter().find_map(|e| match e {
                egui::Event::Screenshot { image, .. } => Some(image.clone()),
                _ => None,
            })
        });
        let mut done = auto.screenshot.is_none() && a.frames >= auto.frames;
        if let (Some(image), Some(path)) = (shot, &auto.screenshot) {
            let [w, h] = image.size;
            let bytes: Vec<u8> = image.pixels.iter().flat_map(|c| c.to_array()).collect();
            match image::RgbaImage::from_raw(w as u32, h as u32, bytes).map(|img| img.save(path)) {
                Some(Ok(())) => {}
                Some(Err(e)) => eprintln!("error: cannot write {}: {e}", path.display()),
                None => eprintln!("error: the screenshot has the wrong size"),
            }
            done = true;
        } else if auto.screenshot.is_some() && a.frames >= auto.frames && !a.screenshot_sent {
            a.screenshot_sent = true;
            ctx.send_viewport_cmd(ViewportCommand::Screenshot(egui::UserData::default()));
        }
        if done {
            let (ui_med, ui_p95) = median_and_p95(&a.ui);
            let (frame_med, frame_p95) = median_and_p95(&a.intervals);
            let (cpu_med, _) = median_and_p95(&a.cpu);
            let ppp = ctx.pixels_per_point();
            let rect = self.viewport_rects[0]
                .map(|r| [r.min.x * ppp, r.min.y * ppp, r.max.x * ppp, r.max.y * ppp]);
            println!(
                "{{\"frames\": {}, \"nodes\": {}, \"ui_ms_median\": {:.3}, \"ui_ms_p95\": {:.3}, \"frame_ms_median\": {:.3}, \"frame_ms_p95\": {:.3}, \"eframe_cpu_ms_median\": {:.3}, \"viewport_px\": {}, \"viewport_error\": {:?}}}",
                a.frames,
                nodes,
                ui_med * 1e3,
                ui_p95 * 1e3,
                frame_med * 1e3,
                frame_p95 * 1e3,
                cpu_med * 1e3,
                rect.map_or_else(
                    || "null".to_owned(),
                    |r| format!("[{}, {}, {}, {}]", r[0], r[1], r[2], r[3])
                ),
                viewport_error,
            );
            self.allow_close = true;
            ctx.send_viewport_cmd(ViewportCommand::Close);
        }
    }

    fn handle_close(&mut self, ctx: &egui::Context) {
        if ctx.input(|i| i.viewport().close_requested()) && !self.allow_close && self.doc.is_dirty()
        {
            ctx.send_viewport_cmd(ViewportCommand::CancelClose);
            self.pending = Some(Pending::Quit);
        }
    }

    /// One editor frame, drawn into `ui` (eframe's root ui, or a test harness's).
    pub fn show(&mut self, ui: &mut Ui) {
        self.show_frame(ui, None);
    }

    fn show_frame(&mut self, ui: &mut Ui, frame: Option<&eframe::Frame>) {
        let started = Instant::now();
        let ctx = ui.ctx().clone();
        self.handle_close(&ctx);
        let (now, dt) = ctx.input(|i| (i.time, f64::from(i.stable_dt)));
        self.shortcuts(&ctx);
        self.evaluate_if_needed(Some(dt));

        egui::Panel::top("menu").show(ui, |ui| self.menu_bar(ui));
        egui::Panel::bottom("status").show(ui, |ui| self.status_bar(ui));
        egui::Panel::right("side")
            .default_size(360.0)
            .resizable(true)
            .show(ui, |ui| {
                let h = ui.available_height();
                ui.heading("Viewport");
                ui.allocate_ui(egui::vec2(ui.available_width(), h * 0.35), |ui| {
                    self.viewport_ui(ui, 0, None);
                });
                ui.separator();
                let label = ui.label("Texture pin").id;
                ui.allocate_ui(egui::vec2(ui.available_width(), h * 0.2), |ui| {
                    self.viewport_ui(ui, 1, Some(label));
                });
                ui.separator();
                self.inspector(ui);
            });
        egui::CentralPanel::default().show(ui, |ui| self.canvas(ui));
        self.node_browser(&ctx);
        self.dialogs(&ctx);

        // Edits made while drawing are evaluated at once, so the viewport never shows a stale frame.
        self.evaluate_if_needed(None);
        self.render_viewports();
        self.autosave(now);

        let title = self.title();
        if title != self.title {
            ctx.send_viewport_cmd(ViewportCommand::Title(title.clone()));
            self.title = title;
        }
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

impl eframe::App for EditorApp {
    fn ui(&mut self, ui: &mut Ui, frame: &mut eframe::Frame) {
        self.show_frame(ui, Some(frame));
    }
}
