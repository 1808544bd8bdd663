//! The editor application: menus, canvas, inspector, viewports, autosave.

use std::path::{Path, PathBuf};
use std::sync::Arc;
use std::time::Instant;

use egui::{Id, Key, KeyboardShortcut, LayerId, Modifiers, Pos2, Ui, ViewportCommand};
use egui_snarl::ui::SnarlWidget;
use spreadlight_graph::registry::Name;
use spreadlight_graph::{
    FrameClock, NodeId, PinRef, PinType, Registry, ResourceKind, RuntimeSnapshot, Spread, format,
};
use spreadlight_render::{GpuContext, Renderer, SubmissionGate};

mod automation;
mod autosave;
mod canvas_state;
mod canvas_view;
mod dialogs;
mod document;
mod help;
mod host_input;
mod inspector;
mod menus;
mod organise;
mod output_index;
mod previews;
mod queries;
mod recording;
mod running;
mod search_field;
mod show;
mod show_window;
mod subpatches;
mod transport;
mod viewports;
mod watches;

use self::autosave::{Autosave, Autosaved};
use self::canvas_state::CanvasState;
use self::show_window::ShowWindowState;
use self::transport::Transport;
use self::viewports::{Source, Viewport, Viewports};
use crate::browser;
use crate::canvas::{self, Canvas, Refusal, SCALE};
use crate::files;
use crate::gpu::WorkerGpu;
use crate::model::EditorDoc;
use crate::model::edits::Clip;
use crate::values;
use crate::viewport::{Blitter, ViewportError};
use crate::worker::{Frame, FrameWait, Request, ViewRequest, Worker};
pub use help::{HelpLaunch, READ_ONLY_BANNER};
pub use show_window::ShowWindowOptions;

/// How the editor starts.
#[derive(Clone, Debug)]
pub struct EditorOptions {
    pub path: Option<PathBuf>,
    pub config_dir: PathBuf,
    /// Seconds between autosaves while there are unsaved changes: an edit is
    /// in the recovery file at most this long after it is made.
    pub autosave_secs: f64,
    pub automation: Option<Automation>,
    /// How long a UI frame waits for the patch frame it asked for (the patch
    /// runs on its own thread, `worker.rs`).
    pub frame_wait: FrameWait,
    /// A help patch: every edit is undone at once (`help.rs`).
    pub read_only: bool,
    /// The smallest zoom fitting the view goes to (`zoom::READABLE_ZOOM`;
    /// lower brings a bigger patch wholly on screen: `edit --min-zoom`).
    pub min_zoom: f32,
    /// Open with time stopped (`edit --paused`): the patch evaluates on
    /// edits and Step only, so a measurement sees the UI's own cost.
    pub paused: bool,
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
    /// The worker's seconds per finished patch frame, one entry per new frame.
    patch: Vec<f64>,
    last_evaluations: u64,
    /// The first patch frame counted and the worker's counts then (automation.rs).
    counted_from: Option<(u64, crate::worker::WorkerCounts)>,
    screenshot_sent: bool,
    /// When the frames were done and the screenshot began waiting for the patch.
    wait_started: Option<Instant>,
}

fn median_and_p95(v: &[f64]) -> (f64, f64) {
    let mut s = v.to_vec();
    s.sort_by(f64::total_cmp);
    if s.is_empty() {
        return (0.0, 0.0);
    }
    (s[s.len() / 2], s[(s.len() * 95 / 100).min(s.len() - 1)])
}

/// At most this long after an edit, the recovery file holds it.
pub const AUTOSAVE_SECS: f64 = 1.0;

impl EditorOptions {
    pub fn new(path: Option<PathBuf>) -> Self {
        EditorOptions {
            path,
            config_dir: files::config_dir(),
            autosave_secs: AUTOSAVE_SECS,
            automation: None,
            frame_wait: FrameWait::default(),
            read_only: false,
            min_zoom: crate::zoom::READABLE_ZOOM,
            paused: false,
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
    /// A dropped wire or a double-clicked link the new node is linked into.
    link: Option<crate::organise::gestures::BrowserLink>,
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

/// The file dialog (egui-file-dialog) and what its answer is for.
struct FilePicker {
    mode: DialogMode,
    dialog: egui_file_dialog::FileDialog,
}

/// What to do once the unsaved-changes question is answered.
#[derive(Clone, Debug, PartialEq)]
enum Pending {
    Open(PathBuf),
    New,
    Quit,
}

pub struct EditorApp {
    registry: Registry,
    /// The canvas: snarl, the selection, the view (`canvas_state.rs`).
    canvas: CanvasState,
    /// The viewports' wishes and where they were drawn (`viewports.rs`).
    viewports: Viewports,
    /// The recovery file and the offer to restore one (`autosave.rs`).
    autosave: Autosave,
    /// The show window from inside the editor (`show_window.rs`).
    show_window: ShowWindowState,
    /// The patch's clock, playing or paused (`transport.rs`).
    transport: Transport,
    doc: EditorDoc,
    path: Option<PathBuf>,
    options: EditorOptions,
    recent: Vec<PathBuf>,
    /// Evaluates the patch and renders the viewports on its own thread.
    worker: Worker,
    /// The latest finished patch frame: live values, errors, the viewports' images.
    frame: Arc<Frame>,
    /// The document generation last sent to the worker.
    sent_generation: Option<u64>,
    /// The viewports' wishes last sent.
    sent_views: Vec<ViewRequest>,
    /// Whether the worker's repaint call is installed (on the first frame, when there is a context).
    wake_set: bool,
    gpu_error: Option<String>,
    /// The renderer's submissions (the worker's): closed except while this
    /// app's own frame runs, minus the show window's drawing, because eframe
    /// may configure a window's surface anywhere else and wgpu refuses that
    /// while another thread submits (`SubmissionGate`, docs/editor.md).
    submission_gate: Option<SubmissionGate>,
    /// Whether the gate asks for a repaint when the worker waits at it.
    gate_waker_set: bool,
    /// The top patch's Outputs, for the first viewport.
    outputs: output_index::OutputIndex,
    browser: Option<BrowserState>,
    refusal: Option<Refusal>,
    clipboard: Clip,
    pastes: u32,
    show_timings: bool,
    status: String,
    pending: Option<Pending>,
    allow_close: bool,
    dialog: Option<FilePicker>,
    synced_generation: Option<u64>,
    title: String,
    ui_times: std::collections::VecDeque<f64>,
    auto: AutoRun,
    /// The shader files beside the patch and in the user library, polled for saves.
    shaders: crate::shader_watch::ShaderWatch,
    /// Subpatch types this editor put in `registry` (see `subpatches.rs`).
    subpatch_types: Vec<String>,
    /// The subpatch instance the open document is shown for.
    instance: Vec<NodeId>,
    /// Running as the show window (`show.rs`).
    show_mode: bool,
    /// Outputs pinned as watched values (`watches.rs`).
    watches: Vec<watches::Watch>,
    /// Where the show window goes, until its first frame placed it (`show.rs`).
    placement: Option<show::Placement>,
    /// `play --native`: the window takes the texture's size (`show.rs`).
    play_native: bool,
    /// How F1 opens help patches, and what it opened (`help.rs`).
    help_launch: HelpLaunch,
    help_opened: Vec<PathBuf>,
    refused_edits: u32,
    /// Thumbnails and hover previews: their settings and this frame's wishes (`previews.rs`).
    previews: crate::previews::CanvasPreviews,
    /// Comments, frames, find, the legend and the gestures (`organise.rs`).
    organise: organise::OrganiseUi,
    /// The file being recorded to (`app/recording.rs`).
    recording: Option<PathBuf>,
    /// Where the next recording goes (`play --record`); it starts on the first frame.
    record_to: Option<PathBuf>,
    record_on_start: bool,
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
        let mut submission_gate = None;
        let (gpu, gpu_error) = match render_state {
            Some(state) => {
                // A device error no scope catches (say a window's surface
                // that cannot be configured) is reported, not a panic that
                // takes the editor and the patch down.
                state.device.on_uncaptured_error(Arc::new(|e: wgpu::Error| {
                    eprintln!("warning: GPU: {e}");
                }));
                let context = GpuContext::from_parts(
                    state.device.clone(),
                    state.queue.clone(),
                    state.adapter.get_info(),
                );
                submission_gate = Some(context.submission_gate().clone());
                match Renderer::new(context) {
                    Ok(renderer) => {
                        // A few command encoders a frame, finished beside the
                        // recording (docs/benchmarks.md, "Session 11: CPU"); a
                        // failing frame falls back to a pass at a time.
                        renderer.set_recording(spreadlight_render::renderer::Recording::Batched);
                        let renderer = Arc::new(renderer);
                        let blitter = Blitter::new(&state.device);
                        (
                            Some(WorkerGpu {
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
        // Closed from before eframe's first event (a window's first
        // `Resized` configures its surface); only `show_frame` opens it.
        if let Some(gate) = &submission_gate {
            gate.close();
        }
        let worker = Worker::new(registry.clone(), gpu);
        let mut app = EditorApp {
            registry,
            canvas: CanvasState::new(),
            viewports: Viewports::new(),
            autosave: Autosave::default(),
            show_window: ShowWindowState::new(),
            transport: Transport::new(!options.paused),
            doc: EditorDoc::default(),
            path: None,
            options: options.clone(),
            recent,
            worker,
            frame: Arc::default(),
            sent_generation: None,
            sent_views: Vec::new(),
            wake_set: false,
            gpu_error,
            submission_gate,
            gate_waker_set: false,
            outputs: Default::default(),
            browser: None,
            refusal: None,
            clipboard: Clip::default(),
            pastes: 0,
            show_timings: false,
            status: String::new(),
            pending: None,
            allow_close: false,
            dialog: None,
            synced_generation: None,
            title: String::new(),
            ui_times: std::collections::VecDeque::new(),
            auto: AutoRun::default(),
            shaders: crate::shader_watch::ShaderWatch::new(None),
            subpatch_types: Vec::new(),
            instance: Vec::new(),
            show_mode: false,
            watches: Vec::new(),
            placement: None,
            play_native: false,
            help_launch: HelpLaunch::default(),
            help_opened: Vec::new(),
            refused_edits: 0,
            previews: crate::previews::CanvasPreviews::new(crate::previews::PreviewSettings::load(
                &options.config_dir,
            )),
            organise: Default::default(),
            recording: None,
            record_to: None,
            record_on_start: false,
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
        let path = app.path.clone();
        app.autosave
            .find_offer(path.as_deref(), &app.options.config_dir);
        app
    }

    // ----- edits -----

    /// The node the inspector shows: the last one clicked, while it is selected.
    fn focus_node(&self) -> Option<NodeId> {
        self.canvas.focus_node()
    }

    pub fn delete_selected(&mut self) {
        let ids = self.selected();
        self.doc.delete_nodes(&ids);
        self.canvas.selected.clear();
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
            self.canvas.selected = ids.into_iter().collect();
        }
    }

    pub fn duplicate_selected(&mut self) {
        let ids = self.selected();
        let new = self.doc.duplicate(&ids, (20.0, 20.0));
        if !new.is_empty() {
            self.canvas.selected = new.into_iter().collect();
        }
    }

    // ----- the frame -----

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
        // The worker submits while this frame runs: eframe configures no
        // surface inside an app's update but in the immediate viewports it
        // draws there (closed again around them, `show_window.rs`).
        let gate = self.submission_gate.clone();
        let _open = gate.as_ref().map(|gate| {
            if !self.gate_waker_set {
                // A submit that waits asks for this frame soon.
                let ctx = ui.ctx().clone();
                gate.set_waker(move || ctx.request_repaint());
                self.gate_waker_set = true;
            }
            gate.open_scope()
        });
        self.draw_frame(ui, frame);
    }

    fn draw_frame(&mut self, ui: &mut Ui, frame: Option<&eframe::Frame>) {
        let started = Instant::now();
        if self.show_mode {
            self.show_only(ui, frame, started);
            return;
        }
        let ctx = ui.ctx().clone();
        self.handle_close(&ctx);
        let (now, dt) = ctx.input(|i| (i.time, f64::from(i.stable_dt)));
        self.poll_shaders(&ctx);
        self.shortcuts(&ctx);
        self.help_key(&ctx);
        self.recording_shortcut(&ctx);
        self.evaluate_if_needed(&ctx, Some(dt), true);

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
                self.watches_ui(ui);
            });
        self.read_only_banner(ui);
        egui::CentralPanel::default().show(ui, |ui| self.canvas(ui));
        self.node_browser(&ctx);
        self.organise_windows(&ctx);
        self.dialogs(&ctx);
        self.show_window_ui(&ctx);
        self.refuse_edits();

        // Edits made while drawing are evaluated at once, so the viewport never shows a stale frame.
        self.evaluate_if_needed(&ctx, None, false);
        self.autosave(now, &ctx);

        let title = self.title();
        if title != self.title {
            ctx.send_viewport_cmd(ViewportCommand::Title(title.clone()));
            self.title = title;
        }
        // Playing, the worker wakes the UI when it finishes a frame (the wake
        // `evaluate_if_needed` sets), so the canvas is drawn as often as the
        // patch makes frames, and input repaints at once. Asking for a
        // repaint on every UI frame as well drew the canvas several times
        // per patch frame on a slow adapter, and on lavapipe those drawings
        // took the CPU the patch needed (docs/editor.md, "Previews' cost").
        // Without a wake (FrameWait::Always, the tests) the UI keeps asking.
        if self.transport.playing && !self.wake_set {
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
