//! The organising tools as the app shows them: their shortcuts and menu,
//! dragging and editing comments and frames, find in patch, the legend, and
//! the gestures that make linked nodes (a dropped wire, a link to insert
//! into, an IOBox from a pin, Alt-dropping a node onto a link). The
//! document side is `model/organise.rs`; painting is `crate::organise`.

use super::*;
use crate::organise::find::{self, Target};
use crate::organise::gestures::{self, BrowserLink};
use crate::organise::layout::Direction;
use crate::organise::{Dragging, comments, frames, measure};
use spreadlight_graph::{CommentDoc, FrameDoc, LinkDoc};

/// How far arrow keys nudge the selection, in canvas units (Shift: ten times).
const NUDGE: f32 = 2.0;
/// How near a pin a click must be to be on it, in points.
const PIN_REACH: f32 = 8.0;

/// The app's state of the organising tools.
#[derive(Default)]
pub(super) struct OrganiseUi {
    find: Option<FindState>,
    editing_comment: Option<(usize, String)>,
    editing_frame: Option<(usize, FrameDoc)>,
    drag: Option<AnnotationDrag>,
    /// A point of the canvas (snarl's coordinates) to centre the view on next frame.
    pub(super) jump: Option<Pos2>,
    legend: bool,
    /// Where the comments and frames were on screen last frame (fitting the view takes them in).
    pub(super) rects: Vec<egui::Rect>,
}

struct FindState {
    query: String,
    highlighted: usize,
    focus: bool,
}

struct AnnotationDrag {
    target: Target,
    start: Pos2,
    /// The frame's nodes: snarl's ids and where they were.
    nodes: Vec<(egui_snarl::NodeId, Pos2)>,
}

/// Place a `name` node from the browser at `at`, linked as `link` asks.
pub(super) fn place_node(
    doc: &mut EditorDoc,
    registry: &spreadlight_graph::Registry,
    name: &str,
    at: (f32, f32),
    link: Option<&BrowserLink>,
) -> Result<NodeId, crate::LinkError> {
    match link {
        None => Ok(doc.add_node(name, at)),
        Some(BrowserLink::Wire(wire)) => Ok(doc.add_linked_node(registry, name, at, wire)),
        Some(BrowserLink::Insert(l)) => doc.insert_new_into_link(registry, l, name, at),
    }
}

/// An invisible hit area over `rect` (screen), above the canvas and below windows.
fn hit_area(ctx: &egui::Context, id: Id, rect: egui::Rect) -> egui::Response {
    egui::Area::new(id)
        .fixed_pos(rect.min)
        .order(egui::Order::Middle)
        .constrain(false)
        .show(ctx, |ui| {
            ui.allocate_exact_size(rect.size(), egui::Sense::click_and_drag())
                .1
        })
        .inner
}

impl EditorApp {
    /// The organising shortcuts (not while typing): Ctrl+F, Ctrl+B, Ctrl+M,
    /// Ctrl+Shift+F, Ctrl+L, Shift+L, L, the arrow keys. Shifted keys are
    /// tried first: `consume_key` with no modifiers takes a shifted press too.
    pub(super) fn organise_shortcuts(&mut self, ctx: &egui::Context) {
        let consume = |m: Modifiers, key| ctx.input_mut(|i| i.consume_key(m, key));
        let ids = self.selected();
        if consume(Modifiers::COMMAND | Modifiers::SHIFT, Key::F) {
            self.frame_selection();
        }
        if consume(Modifiers::COMMAND, Key::F) {
            self.open_find();
        }
        if consume(Modifiers::COMMAND, Key::B) {
            self.doc.toggle_bypass(&ids);
        }
        if consume(Modifiers::COMMAND, Key::M) {
            self.comment_at_pointer(ctx);
        }
        if consume(Modifiers::COMMAND, Key::L) {
            self.doc.align(&self.registry, &ids);
        }
        if consume(Modifiers::SHIFT, Key::L) {
            self.layout_selection_or_all(Direction::TopToBottom);
        }
        if consume(Modifiers::NONE, Key::L) {
            self.layout_selection_or_all(Direction::LeftToRight);
        }
        for (key, d) in [
            (Key::ArrowLeft, (-1.0, 0.0)),
            (Key::ArrowRight, (1.0, 0.0)),
            (Key::ArrowUp, (0.0, -1.0)),
            (Key::ArrowDown, (0.0, 1.0)),
        ] {
            let step = if consume(Modifiers::SHIFT, key) {
                NUDGE * 10.0
            } else if consume(Modifiers::NONE, key) {
                NUDGE
            } else {
                continue;
            };
            if !ids.is_empty() {
                self.doc.nudge(&ids, (d.0 * step, d.1 * step));
            }
        }
    }

    pub fn open_find(&mut self) {
        self.organise.find = Some(FindState {
            query: String::new(),
            highlighted: 0,
            focus: true,
        });
    }

    /// Lay out the selection, or the whole patch when nothing is selected,
    /// its layers following each other in `direction`.
    pub fn layout_selection_or_all(&mut self, direction: Direction) {
        let ids = self.selected();
        self.doc.layout(&self.registry, &ids, direction);
        let way = match direction {
            Direction::LeftToRight => "left to right",
            Direction::TopToBottom => "top to bottom",
        };
        self.status = if ids.is_empty() {
            format!("laid out the patch {way} (Ctrl+Z undoes it)")
        } else {
            format!("laid out {} nodes {way} (Ctrl+Z undoes it)", ids.len())
        };
    }

    /// A frame around the selection, with its title being edited.
    pub fn frame_selection(&mut self) {
        let ids = self.selected();
        if let Some(i) = self.doc.frame_around(&self.registry, &ids, "Frame") {
            self.organise.editing_frame = self.doc.patch().frames.get(i).cloned().map(|f| (i, f));
        }
    }

    /// A comment where the pointer is (or the canvas's top left), with its text being edited.
    fn comment_at_pointer(&mut self, ctx: &egui::Context) {
        let Some(layer) = self.canvas.layer else {
            return;
        };
        let from_global = ctx.layer_transform_from_global(layer).unwrap_or_default();
        let screen = match self.canvas.rect {
            Some(r) if r.contains(self.canvas.last_pointer) => self.canvas.last_pointer,
            Some(r) => r.min + egui::vec2(20.0, 20.0),
            None => self.canvas.last_pointer,
        };
        let p = from_global * screen;
        let at = ((p.x / SCALE).round(), (p.y / SCALE).round());
        let text = "# Comment\nWhat this part does.";
        let i = self.doc.add_comment(at, text);
        self.organise.editing_comment = Some((i, text.to_owned()));
    }

    /// The Organise menu.
    pub(super) fn organise_menu(&mut self, ui: &mut Ui) {
        ui.menu_button("Organise", |ui| {
            let ids = self.selected();
            if ui.button("Find…").on_hover_text("Ctrl+F").clicked() {
                self.open_find();
            }
            ui.separator();
            if ui.button("Add comment").on_hover_text("Ctrl+M").clicked() {
                self.comment_at_pointer(ui.ctx());
            }
            if ui
                .add_enabled(!ids.is_empty(), egui::Button::new("Frame selection"))
                .on_hover_text("Ctrl+Shift+F")
                .clicked()
            {
                self.frame_selection();
            }
            if ui
                .add_enabled(!ids.is_empty(), egui::Button::new("Bypass selection"))
                .on_hover_text("Ctrl+B: the first input passes to the output of its type")
                .clicked()
            {
                self.doc.toggle_bypass(&ids);
            }
            ui.separator();
            if ui
                .button("Layout left to right")
                .on_hover_text("L: the selection, or the whole patch, in columns")
                .clicked()
            {
                self.layout_selection_or_all(Direction::LeftToRight);
            }
            if ui
                .button("Layout top to bottom")
                .on_hover_text("Shift+L: the selection, or the whole patch, in rows")
                .clicked()
            {
                self.layout_selection_or_all(Direction::TopToBottom);
            }
            if ui
                .add_enabled(ids.len() > 1, egui::Button::new("Align"))
                .on_hover_text("Ctrl+L: in a row or a column")
                .clicked()
            {
                self.doc.align(&self.registry, &ids);
            }
            ui.separator();
            ui.checkbox(&mut self.organise.legend, "Pin-type legend");
        });
    }

    /// Dragging and double-clicking comments and frames; called after the
    /// canvas is drawn and before its node moves are recorded.
    pub(super) fn annotations_ui(&mut self, ui: &Ui, layer: LayerId) {
        let ctx = ui.ctx().clone();
        let Some(canvas) = self.canvas.rect else {
            return;
        };
        let to_global = ctx.layer_transform_to_global(layer).unwrap_or_default();
        let patch = self.doc.patch();
        let mut areas = Vec::new();
        self.organise.rects.clear();
        for (i, f) in patch.frames.iter().enumerate() {
            self.organise.rects.push(to_global * frames::rect(f));
            areas.push((Target::Frame(i), to_global * frames::title_rect(f)));
        }
        for (i, c) in patch.comments.iter().enumerate() {
            let r = to_global * comments::rect(c);
            self.organise.rects.push(r);
            areas.push((Target::Comment(i), r));
        }
        for (target, rect) in areas {
            let rect = rect.intersect(canvas);
            if !rect.is_positive() {
                continue;
            }
            let id = Id::new(("spreadlight-annotation", format!("{target:?}")));
            let response = hit_area(&ctx, id, rect);
            self.annotation_response(&ctx, target, &response, to_global.scaling);
        }
    }

    fn annotation_response(
        &mut self,
        ctx: &egui::Context,
        target: Target,
        response: &egui::Response,
        zoom: f32,
    ) {
        let pointer = ctx.input(|i| i.pointer.latest_pos()).unwrap_or_default();
        if response.drag_started() {
            let nodes = match target {
                Target::Frame(i) => self
                    .doc
                    .frame_nodes(i)
                    .into_iter()
                    .filter_map(|id| {
                        let sid = *self.canvas.snarl_ids.get(&id)?;
                        Some((sid, self.canvas.snarl.get_node_info(sid)?.pos))
                    })
                    .collect(),
                _ => Vec::new(),
            };
            // From where the button went down: egui reports the drag a few points later.
            let start = ctx.input(|i| i.pointer.press_origin()).unwrap_or(pointer);
            self.organise.drag = Some(AnnotationDrag {
                target,
                start,
                nodes,
            });
        }
        let Some(drag) = &self.organise.drag else {
            if response.double_clicked() {
                self.edit_annotation(target);
            }
            return;
        };
        if drag.target != target {
            return;
        }
        let d = (pointer - drag.start) / zoom.max(1e-3);
        // Whole canvas units, as saved.
        let du = ((d.x / SCALE).round(), (d.y / SCALE).round());
        let snapped = egui::vec2(du.0 * SCALE, du.1 * SCALE);
        for (sid, start) in &drag.nodes {
            if let Some(info) = self.canvas.snarl.get_node_info_mut(*sid) {
                info.pos = *start + snapped;
            }
        }
        if response.drag_stopped() {
            crate::organise::set_dragging(ctx, None);
            self.organise.drag = None;
            match target {
                Target::Frame(i) => {
                    if let Some(f) = self.doc.patch().frames.get(i) {
                        let to = (f.pos.0 + du.0, f.pos.1 + du.1);
                        self.doc.move_frame(i, to);
                    }
                }
                Target::Comment(i) => {
                    if let Some(c) = self.doc.patch().comments.get(i).cloned() {
                        let moved = CommentDoc {
                            pos: (c.pos.0 + du.0, c.pos.1 + du.1),
                            ..c
                        };
                        self.doc.set_comment(i, moved);
                    }
                }
                Target::Node(_) => {}
            }
        } else if response.dragged() {
            let drag = match target {
                Target::Frame(i) => Some(Dragging::Frame(i, snapped)),
                Target::Comment(i) => Some(Dragging::Comment(i, snapped)),
                Target::Node(_) => None,
            };
            crate::organise::set_dragging(ctx, drag);
        }
    }

    fn edit_annotation(&mut self, target: Target) {
        let patch = self.doc.patch();
        match target {
            Target::Comment(i) => {
                self.organise.editing_comment = patch.comments.get(i).map(|c| (i, c.text.clone()));
            }
            Target::Frame(i) => {
                self.organise.editing_frame = patch.frames.get(i).cloned().map(|f| (i, f));
            }
            Target::Node(_) => {}
        }
    }

    /// Middle-click, or Ctrl-click, on an input pin: an IOBox holding the
    /// pin's current spread, linked to it. True when it took the click.
    pub(super) fn pin_gesture(&mut self, ui: &Ui) -> bool {
        let (middle, ctrl_click, pos) = ui.input(|i| {
            (
                i.pointer.button_clicked(egui::PointerButton::Middle),
                i.pointer.primary_clicked() && i.modifiers.command,
                i.pointer.interact_pos(),
            )
        });
        let Some(pos) = pos.filter(|_| middle || ctrl_click) else {
            return false;
        };
        let pin = self
            .canvas
            .pins
            .borrow()
            .iter()
            .filter(|((_, _, input), p)| *input && p.distance(pos) < PIN_REACH)
            .min_by(|a, b| a.1.distance(pos).total_cmp(&b.1.distance(pos)))
            .map(|((id, name, _), _)| PinRef(*id, name.clone()));
        let Some(pin) = pin else {
            return false;
        };
        let value = match self.doc.link_into(&pin) {
            Some(l) => {
                let mut path = self.instance.clone();
                path.push(l.from.node());
                self.frame
                    .runtime
                    .output_at(&path, l.from.pin())
                    .map(|s| (**s).clone())
            }
            None => None,
        }
        .or_else(|| self.doc.input_value(&self.registry, pin.node(), pin.pin()));
        let Some(value) = value else {
            return false;
        };
        match self.doc.iobox_for_input(&self.registry, &pin, value) {
            Some(id) => {
                self.canvas.selected = [id].into_iter().collect();
                self.status = format!("IOBox for {pin}");
            }
            None => self.status = format!("no IOBox holds the values of {pin}"),
        }
        true
    }

    /// A wire dropped on empty canvas this frame opens the browser for a node that takes it.
    pub(super) fn open_browser_for_dropped_wire(&mut self, ctx: &egui::Context) {
        if let Some((wire, at, screen)) = gestures::take_dropped_wire(ctx) {
            self.browser = Some(BrowserState {
                at,
                screen,
                query: String::new(),
                highlighted: 0,
                focus: true,
                link: Some(BrowserLink::Wire(wire)),
            });
        }
    }

    /// Record nodes moved on the canvas; a single node let go with Alt held
    /// over a link is put into it (one undo step with the move).
    pub(super) fn record_moves(&mut self, ui: &Ui, moves: &[(NodeId, (f32, f32))]) {
        let alt = ui.input(|i| i.modifiers.alt);
        let link: Option<LinkDoc> = match moves {
            [(id, _)] if alt => {
                canvas::wire_under(&self.doc, &self.canvas.pins, self.canvas.last_pointer, 8.0)
                    .filter(|l| l.from.node() != *id && l.to.node() != *id)
            }
            _ => None,
        };
        let Some(link) = link else {
            self.doc.move_nodes(moves);
            return;
        };
        let id = moves[0].0;
        let registry = &self.registry;
        let result = self.doc.grouped("insert into link", |doc| {
            doc.move_nodes(moves);
            doc.insert_into_link(registry, &link, id)
        });
        if let Err(e) = result {
            self.refusal = Some(Refusal {
                message: e.to_string(),
                at: self.canvas.last_pointer,
                since: ui.input(|i| i.time),
            });
        }
    }

    /// The view centred on the point find jumped to, at the zoom it has.
    pub(super) fn jump_view(
        &mut self,
        view: egui::emath::TSTransform,
        canvas: egui::Rect,
    ) -> Option<egui::emath::TSTransform> {
        let to = self.organise.jump.take()?;
        let scaling = view.scaling.max(crate::zoom::READABLE_ZOOM);
        Some(egui::emath::TSTransform::new(
            canvas.center().to_vec2() - to.to_vec2() * scaling,
            scaling,
        ))
    }

    fn jump_to(&mut self, target: Target) {
        let patch = self.doc.patch();
        let centre = match target {
            Target::Node(id) => {
                self.canvas.selected = [id].into_iter().collect();
                self.canvas.focused = Some(id);
                patch.node(id).map(|n| {
                    let (w, h) = measure::node_size(n, &self.registry, patch);
                    Pos2::new((n.pos.0 + w / 2.0) * SCALE, (n.pos.1 + h / 2.0) * SCALE)
                })
            }
            Target::Comment(i) => patch.comments.get(i).map(|c| comments::rect(c).center()),
            Target::Frame(i) => patch.frames.get(i).map(|f| frames::rect(f).center()),
        };
        self.organise.jump = centre;
    }

    /// The find panel, the comment and frame editors, and the legend.
    pub(super) fn organise_windows(&mut self, ctx: &egui::Context) {
        self.find_window(ctx);
        self.comment_editor(ctx);
        self.frame_editor(ctx);
        if self.organise.legend {
            let mut open = true;
            egui::Window::new("Pin types")
                .open(&mut open)
                .resizable(false)
                .collapsible(false)
                .default_pos(
                    self.canvas
                        .rect
                        .map_or(Pos2::ZERO, |r| r.left_bottom() - egui::vec2(-10.0, 230.0)),
                )
                .show(ctx, crate::organise::legend::show);
            self.organise.legend = open;
        }
    }

    fn find_window(&mut self, ctx: &egui::Context) {
        let Some(state) = &mut self.organise.find else {
            return;
        };
        let hits = find::find(self.doc.patch(), &self.registry, &state.query);
        let mut jump = None;
        let mut close = false;
        egui::Window::new("Find in patch")
            .collapsible(false)
            .resizable(false)
            .default_pos(
                self.canvas
                    .rect
                    .map_or(Pos2::ZERO, |r| r.right_top() + egui::vec2(-300.0, 10.0)),
            )
            .show(ctx, |ui| {
                ui.set_width(260.0);
                let keys = super::search_field::search_field(
                    ui,
                    (&mut state.query, &mut state.focus, &mut state.highlighted),
                    hits.len(),
                    "node, pin, value or comment",
                    "find-query",
                );
                if keys.enter {
                    jump = hits.get(state.highlighted).map(|h| h.target);
                    // Enter takes the focus from the field; keep typing there.
                    state.focus = true;
                }
                if keys.escape {
                    close = true;
                }
                if !state.query.trim().is_empty() {
                    ui.weak(format!("{} found", hits.len()));
                }
                egui::ScrollArea::vertical()
                    .max_height(240.0)
                    .show(ui, |ui| {
                        for (i, hit) in hits.iter().enumerate() {
                            if ui
                                .selectable_label(i == state.highlighted, &hit.text)
                                .clicked()
                            {
                                state.highlighted = i;
                                jump = Some(hit.target);
                            }
                        }
                    });
            });
        if let Some(target) = jump {
            self.jump_to(target);
        }
        if close {
            self.organise.find = None;
        }
    }

    fn comment_editor(&mut self, ctx: &egui::Context) {
        let Some((index, text)) = &mut self.organise.editing_comment else {
            return;
        };
        let (index, mut done, mut delete) = (*index, false, false);
        egui::Window::new("Comment")
            .collapsible(false)
            .show(ctx, |ui| {
                ui.weak("# heading · ## smaller · **bold** · - list item");
                ui.add(
                    egui::TextEdit::multiline(text)
                        .desired_rows(6)
                        .desired_width(320.0)
                        .id(Id::new("comment-text")),
                );
                ui.horizontal(|ui| {
                    done = ui.button("Done").clicked();
                    delete = ui.button("Delete comment").clicked();
                });
            });
        let text = text.clone();
        if delete {
            self.doc.remove_comment(index);
            self.organise.editing_comment = None;
        } else if done {
            if let Some(c) = self.doc.patch().comments.get(index).cloned() {
                self.doc.set_comment(index, CommentDoc { text, ..c });
            }
            self.organise.editing_comment = None;
        }
    }

    fn frame_editor(&mut self, ctx: &egui::Context) {
        let Some((index, frame)) = &mut self.organise.editing_frame else {
            return;
        };
        let (index, mut done, mut delete) = (*index, false, false);
        egui::Window::new("Frame")
            .collapsible(false)
            .show(ctx, |ui| {
                ui.horizontal(|ui| {
                    ui.label("Title");
                    ui.add(egui::TextEdit::singleline(&mut frame.title).id(Id::new("frame-title")));
                });
                ui.horizontal(|ui| {
                    ui.label("Colour");
                    let mut rgb = [frame.color.0, frame.color.1, frame.color.2];
                    ui.color_edit_button_srgb(&mut rgb);
                    frame.color = (rgb[0], rgb[1], rgb[2]);
                });
                ui.horizontal(|ui| {
                    ui.label("Size");
                    ui.add(egui::DragValue::new(&mut frame.size.0).range(10.0..=10_000.0));
                    ui.add(egui::DragValue::new(&mut frame.size.1).range(10.0..=10_000.0));
                });
                ui.horizontal(|ui| {
                    done = ui.button("Done").clicked();
                    delete = ui.button("Delete frame").clicked();
                });
            });
        let frame = frame.clone();
        if delete {
            self.doc.remove_frame(index);
            self.organise.editing_frame = None;
        } else if done {
            self.doc.set_frame(index, frame);
            self.organise.editing_frame = None;
        }
    }

    /// Test hooks: the find panel's query, and the comment or frame editors' state.
    pub fn find_query_mut(&mut self) -> Option<&mut String> {
        self.organise.find.as_mut().map(|f| &mut f.query)
    }
}
