//! The show window from inside the editor: a second, borderless native
//! window (an egui viewport, independent of the editor's layout) showing the
//! latest finished frame of the Output the first viewport shows. Opened from
//! the toolbar or with F11; Esc in it, or closing it, closes it. Filled, the
//! texture renders at the window's pixel size; at native size the window
//! takes the texture's own pixel size and shows it 1:1. While it is open the
//! patch's Mouse, Keyboard and WindowSize nodes read it (`host_input.rs`).

use spreadlight_nodes::input::InputSnapshot;

use super::*;

/// The worker's view the show window shows (after the two side-panel viewports).
pub(super) const SHOW_VIEW: usize = 2;

/// How the show window opens when nothing else says (points).
const DEFAULT_SIZE: egui::Vec2 = egui::vec2(640.0, 360.0);

/// The open show window's choices.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ShowWindowOptions {
    /// Borderless fullscreen, on the Output's `Monitor` pin monitor when it names one.
    pub fullscreen: bool,
    /// The window takes the texture's pixel size and shows it 1:1 (else the texture fills the window).
    pub native: bool,
}

/// The show window's state: open or not and how, what the toolbar's
/// choices are, and what it read and drew last frame.
pub(super) struct ShowWindowState {
    /// The editor's show window, while it is open.
    pub(super) open: Option<ShowWindowOptions>,
    /// What the toolbar's show window choices are set to.
    pub(super) choice: ShowWindowOptions,
    /// The show window's pointer, keys and size, read while it is open.
    pub(super) input: Option<InputSnapshot>,
    /// Where it drew its image last frame, in its own points.
    pub(super) image_rect: Option<egui::Rect>,
}

impl ShowWindowState {
    pub(super) fn new() -> Self {
        ShowWindowState {
            open: None,
            choice: ShowWindowOptions {
                fullscreen: false,
                native: false,
            },
            input: None,
            image_rect: None,
        }
    }

    /// Closed: nothing of the window is kept but the toolbar's choices.
    fn close(&mut self) {
        self.open = None;
        self.input = None;
        self.image_rect = None;
    }
}

impl EditorApp {
    /// Open the show window for the Output the first viewport shows.
    pub fn open_show_window(&mut self, options: ShowWindowOptions) {
        self.show_window.open = Some(options);
        self.viewports.views[SHOW_VIEW].source = Source::Output;
        self.status = "show window open (Esc in it closes it)".to_owned();
    }

    pub fn close_show_window(&mut self) {
        self.show_window.close();
        self.viewports.views[SHOW_VIEW] = Viewport::new(Source::None);
    }

    /// The open show window's choices, if it is open.
    pub fn show_window(&self) -> Option<ShowWindowOptions> {
        self.show_window.open
    }

    /// Where the show window drew its image last frame, in its own points.
    pub fn show_window_image_rect(&self) -> Option<egui::Rect> {
        self.show_window.image_rect
    }

    /// The pixel size the show window's texture is rendered at.
    pub fn show_window_pixels(&self) -> Option<(u32, u32)> {
        self.show_window
            .open
            .map(|_| self.viewports.views[SHOW_VIEW].size)
    }

    pub(super) fn toggle_show_window(&mut self) {
        if self.show_window.open.is_some() {
            self.close_show_window();
        } else {
            let options = self.show_window.choice;
            self.open_show_window(options);
        }
    }

    /// Draw the show window while it is open (each editor frame).
    pub(super) fn show_window_ui(&mut self, ctx: &egui::Context) {
        let Some(options) = self.show_window.open else {
            return;
        };
        let mut builder = egui::ViewportBuilder::default()
            .with_title("Spreadlight show")
            .with_decorations(false)
            .with_inner_size(DEFAULT_SIZE)
            .with_fullscreen(options.fullscreen);
        if options.fullscreen
            && let Some(monitor) = self.output_monitor()
        {
            builder = builder.with_monitor(monitor);
        }
        let id = egui::ViewportId::from_hash_of("spreadlight-show-window");
        // eframe creates, resizes and paints the window inside this call,
        // configuring its surface (first frame, resize, viewport commands);
        // wgpu refuses that while the worker submits, and the next paint then
        // panics on the unconfigured surface. Closed while it runs.
        let gate = self.submission_gate.clone();
        let _closed = gate.as_ref().map(SubmissionGate::closed_scope);
        let close = ctx.show_viewport_immediate(id, builder, |ui, class| {
            let ctx = ui.ctx().clone();
            let close = ctx.input_mut(|i| i.consume_key(Modifiers::NONE, Key::Escape))
                || ctx.input(|i| i.viewport().close_requested());
            if class == egui::ViewportClass::EmbeddedWindow {
                // No native windows (a test harness): it draws as an egui
                // window of the default size in the editor's.
                let (area, _) = ui.allocate_exact_size(DEFAULT_SIZE, egui::Sense::hover());
                self.show_window_image(ui, SHOW_VIEW, area, options.native);
            } else {
                egui::CentralPanel::default()
                    .frame(egui::Frame::NONE.fill(egui::Color32::BLACK))
                    .show(ui, |ui| {
                        let area = ui.available_rect_before_wrap();
                        self.show_window_image(ui, SHOW_VIEW, area, options.native);
                    });
            }
            close
        });
        if close {
            self.close_show_window();
        }
    }

    /// Draw view `k`'s texture into `area` (the window's inside, in points):
    /// the editor's show window, or `play`'s window at native size.
    pub(super) fn show_window_image(
        &mut self,
        ui: &mut Ui,
        k: usize,
        area: egui::Rect,
        native: bool,
    ) {
        let avail = area.size();
        let ppp = ui.ctx().pixels_per_point();
        let size = (
            ((avail.x * ppp) as u32).clamp(16, 8192),
            ((avail.y * ppp) as u32).clamp(16, 8192),
        );
        self.viewports.views[k].size = size;
        if k == SHOW_VIEW {
            let mut wheel = self.viewports.wheel;
            self.show_window.input = Some(read_input(ui.ctx(), area, size, true, &mut wheel));
            self.viewports.wheel = wheel;
        }
        let shown = self.frame.views.get(k).cloned().unwrap_or_default();
        match (&shown.target, &shown.error) {
            (_, Some(e)) => {
                ui.put(area, egui::Label::new(e.to_string()));
            }
            (Some(t), None) => {
                let pixels = (t.texture.width(), t.texture.height());
                let painter = ui.painter_at(area);
                let tex_size = egui::vec2(pixels.0 as f32, pixels.1 as f32) / ppp;
                if native {
                    if pixels != size {
                        // The texture has its own size: the window takes it.
                        ui.ctx()
                            .send_viewport_cmd(ViewportCommand::InnerSize(tex_size));
                    }
                    // 1:1 pixels, centred until the window has its size.
                    let rect = egui::Rect::from_center_size(area.center(), tex_size);
                    paint(&painter, t.id, rect);
                    self.show_window.image_rect = Some(rect);
                    self.viewports.rects[k] = Some(rect);
                } else {
                    paint(&painter, t.id, area);
                    self.show_window.image_rect = Some(area);
                    self.viewports.rects[k] = Some(area);
                }
            }
            (None, None) => {
                ui.put(area, egui::Label::new("nothing rendered yet"));
            }
        }
    }
}

fn paint(painter: &egui::Painter, texture: egui::TextureId, rect: egui::Rect) {
    let uv = egui::Rect::from_min_max(egui::pos2(0.0, 0.0), egui::pos2(1.0, 1.0));
    painter.image(texture, rect, uv, egui::Color32::WHITE);
}

/// The pointer, keys and size of `area` (in points; `size` in pixels), as
/// the patch's input nodes read them; wheel notches are added to `wheel`.
/// With `always_keys`, keys count wherever the pointer is.
pub(super) fn read_input(
    ctx: &egui::Context,
    area: egui::Rect,
    size: (u32, u32),
    always_keys: bool,
    wheel: &mut f32,
) -> InputSnapshot {
    let typing = ctx.egui_wants_keyboard_input();
    ctx.input(|i| {
        let pointer = i.pointer.latest_pos().filter(|p| area.contains(*p));
        let inside = pointer.is_some();
        if inside {
            for e in &i.raw.events {
                if let egui::Event::MouseWheel { unit, delta, .. } = e {
                    *wheel += match unit {
                        egui::MouseWheelUnit::Point => delta.y / host_input::POINTS_PER_NOTCH,
                        egui::MouseWheelUnit::Line | egui::MouseWheelUnit::Page => delta.y,
                    };
                }
            }
        }
        let keys = (always_keys || inside) && !typing;
        InputSnapshot {
            mouse_position: pointer.map(|p| {
                InputSnapshot::normalized_position(
                    glam::Vec2::new(p.x - area.min.x, p.y - area.min.y),
                    glam::Vec2::new(area.width(), area.height()),
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
            mouse_wheel: *wheel,
            keys_down: if keys {
                i.keys_down.iter().map(|k| k.name().to_owned()).collect()
            } else {
                Default::default()
            },
            window_size: Some(size),
        }
    })
}
