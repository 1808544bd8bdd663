//! The canvas panel: the snarl widget over the open document, selection by click and rectangle, double-click to open a subpatch or the node browser, wire values and refusals.

use super::*;

/// How fast the wheel zooms: the zoom factor per point of scroll is e^this.
const WHEEL_ZOOM_SPEED: f32 = 0.004;

impl EditorApp {
    /// The canvas's zoom: on-screen points per canvas point.
    pub fn canvas_zoom(&self, ctx: &egui::Context) -> Option<f32> {
        let layer = self.canvas.layer?;
        Some(
            ctx.layer_transform_to_global(layer)
                .unwrap_or_default()
                .scaling,
        )
    }

    /// How tall node titles and pin names are on screen, in points: the body
    /// text size at the canvas's zoom (what "readable" is asserted on).
    pub fn canvas_text_points(&self, ctx: &egui::Context) -> Option<f32> {
        let body = ctx
            .global_style()
            .text_styles
            .get(&egui::TextStyle::Body)?
            .size;
        Some(body * self.canvas_zoom(ctx)?)
    }

    /// The mouse wheel zooms around the pointer (as in vvvv); the canvas would
    /// otherwise pan with it. Its scroll is taken so the canvas does not also pan.
    fn wheel_zoom(
        &mut self,
        ui: &mut Ui,
        view: egui::emath::TSTransform,
        canvas_rect: egui::Rect,
    ) -> Option<egui::emath::TSTransform> {
        let pointer = ui.input(|i| i.pointer.hover_pos())?;
        if !canvas_rect.contains(pointer) || ui.input(|i| !i.modifiers.is_none()) {
            return None;
        }
        let scroll = ui.input(|i| i.smooth_scroll_delta.y);
        if scroll == 0.0 {
            return None;
        }
        ui.input_mut(|i| i.smooth_scroll_delta = egui::Vec2::ZERO);
        Some(canvas::zoom_around(
            view,
            pointer,
            (scroll * WHEEL_ZOOM_SPEED).exp(),
        ))
    }

    pub(super) fn canvas(&mut self, ui: &mut Ui) {
        let dragging = ui.input(|i| i.pointer.any_down());
        // The breadcrumb first: going back up changes the document the canvas
        // shows, and the canvas must be synced to it in this very frame, or
        // the nodes of the document left behind would read as moved ones.
        self.breadcrumb(ui);
        let changed = self.synced_generation != Some(self.doc.generation());
        if changed {
            self.refresh_subpatch_types();
        }
        if (changed && self.synced_generation.is_none())
            || self.canvas.culling.instance != self.instance
        {
            self.canvas.culling.forget(&self.instance);
        }
        let layer = LayerId::new(ui.layer_id().order, Id::new(CANVAS_ID));
        let canvas_rect = ui.max_rect().shrink(8.0);
        // Snarl holds the nodes near the view only (`canvas/cull.rs`); fitting
        // the view measures them all.
        let kept_area = ui
            .ctx()
            .layer_transform_to_global(layer)
            .filter(|_| self.canvas.fit == 0 && self.canvas.culling.enabled)
            .map(|view| canvas::Culling::kept_area(view, canvas_rect));
        let culling = &self.canvas.culling;
        let keep = |n: &spreadlight_graph::NodeDoc| {
            kept_area.is_none_or(|area| area.intersects(culling.rect(n)))
        };
        // Which nodes snarl holds changes only with the document or the kept area.
        if changed || self.canvas.culling.kept_area != Some(kept_area) {
            canvas::sync(
                &mut self.canvas.snarl,
                &mut self.canvas.snarl_ids,
                &self.doc,
                &self.registry,
                changed,
                &keep,
            );
            self.canvas.culling.kept_area = Some(kept_area);
        }
        self.synced_generation = Some(self.doc.generation());
        self.canvas.culling.laid_out = 0;
        // Only this frame's pins: a pin of a node left out must not keep its old place.
        self.canvas.pins.borrow_mut().clear();
        let now = ui.input(|i| i.time);
        self.canvas.layer = Some(layer);
        if let Some(p) = ui.input(|i| i.pointer.latest_pos()) {
            self.canvas.last_pointer = p;
        }
        // Labels that select text would take the drags that move nodes.
        ui.style_mut().interaction.selectable_labels = false;
        self.canvas.rect = Some(canvas_rect);
        let set_view = match ui.ctx().layer_transform_to_global(layer) {
            Some(view) if !self.canvas.fit.is_multiple_of(2) => {
                self.canvas.fit -= 1;
                ui.ctx().request_repaint();
                // Comments and frames are part of what the patch shows.
                let mut rects = self.canvas.node_rects.clone();
                rects.extend(self.organise.rects.iter().map(|r| (NodeId(u32::MAX), *r)));
                canvas::fit_view(view, &rects, canvas_rect, self.options.min_zoom)
            }
            Some(view) if self.organise.jump.is_some() => self.jump_view(view, canvas_rect),
            Some(view) => self.wheel_zoom(ui, view, canvas_rect),
            None => None,
        };
        let mut node_rects = Vec::new();
        self.previews
            .begin(self.frame.previews.clone(), self.path.as_deref());
        let response = {
            let mut viewer = Canvas {
                doc: &mut self.doc,
                registry: &self.registry,
                runtime: &self.frame.runtime,
                selected: &self.canvas.selected,
                node_rects: &mut node_rects,
                show_timings: self.show_timings,
                gpu_ms: &self.frame.gpu_ms,
                gpu_errors: &self.frame.gpu_errors,
                refusal: &mut self.refusal,
                pins: self.canvas.pins.clone(),
                pointer: self.canvas.last_pointer,
                set_view,
                now,
                instance: &self.instance,
                culling: &mut self.canvas.culling,
                previews: &mut self.previews,
            };
            canvas::compact_spacing(ui);
            SnarlWidget::new()
                .id(Id::new(CANVAS_ID))
                .style(canvas::style())
                .show(&mut self.canvas.snarl, &mut viewer, ui)
        };
        self.wires_to_culled_nodes(ui, layer, canvas_rect);
        self.canvas.view = ui.ctx().layer_transform_to_global(layer);
        self.annotations_ui(ui, layer);
        self.open_browser_for_dropped_wire(ui.ctx());
        if !dragging {
            let moves = canvas::moved_nodes(&self.canvas.snarl, &self.doc);
            self.record_moves(ui, &moves);
        }
        let pin_gesture = self.pin_gesture(ui);
        let double = ui.input(|i| {
            i.pointer
                .button_double_clicked(egui::PointerButton::Primary)
        });
        let on_node = ui.input(|i| i.pointer.interact_pos()).and_then(|p| {
            node_rects
                .iter()
                .rev()
                .find(|(_, r)| r.contains(p))
                .map(|(id, _)| *id)
        });
        if double && let Some(id) = on_node {
            // Double-click on a subpatch node opens it in place.
            self.open_subpatch(id);
        } else if double
            && let Some(screen) = ui.input(|i| i.pointer.interact_pos())
            // Over a wire snarl's own wire widget is hovered, not the canvas.
            && (response.hovered()
                || (canvas_rect.contains(screen)
                    && canvas::wire_under(&self.doc, &self.canvas.pins, screen, 5.0).is_some()))
        {
            let from_global = ui
                .ctx()
                .layer_transform_from_global(layer)
                .unwrap_or_default();
            let g = from_global * screen;
            // Double-click on a link: the new node goes into it.
            let link = canvas::wire_under(&self.doc, &self.canvas.pins, screen, 5.0)
                .map(crate::organise::gestures::BrowserLink::Insert);
            self.browser = Some(BrowserState {
                at: ((g.x / SCALE).round(), (g.y / SCALE).round()),
                screen,
                query: String::new(),
                highlighted: 0,
                focus: true,
                link,
            });
        } else if !pin_gesture
            && ui.input(|i| i.pointer.primary_clicked())
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
                Some(id) if add && self.canvas.selected.contains(&id) => {
                    self.canvas.selected.remove(&id);
                }
                Some(id) => {
                    if !add {
                        self.canvas.selected.clear();
                    }
                    self.canvas.selected.insert(id);
                    self.canvas.focused = Some(id);
                }
                None if response.hovered() && !add => self.canvas.selected.clear(),
                None => {}
            }
        }
        self.rectangle_selection(ui, &response, &node_rects);
        if self.canvas.fit > 0 && self.canvas.fit.is_multiple_of(2) {
            // An empty patch has nothing to fit; its first node must not jump the view.
            self.canvas.fit = if node_rects.is_empty() {
                0
            } else {
                self.canvas.fit - 1
            };
            ui.ctx().request_repaint();
        }
        self.canvas.node_rects = node_rects.clone();
        // Hovering a wire shows what flows through it, as hovering its output pin does.
        if response.hovered()
            && let Some(p) = ui.input(|i| i.pointer.hover_pos())
            && !node_rects.iter().any(|(_, r)| r.contains(p))
            && let Some(link) = canvas::wire_under(&self.doc, &self.canvas.pins, p, 5.0)
        {
            let value = self
                .frame
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
                        // What flows through a texture, G-buffer or mesh wire: its preview.
                        let ty = self
                            .doc
                            .patch()
                            .node(link.from.node())
                            .and_then(|n| self.registry.get(&n.type_name))
                            .and_then(|d| d.outputs.iter().find(|p| *p.name == *link.from.pin()))
                            .map(|p| p.ty)
                            .filter(|ty| crate::previews::previewable(*ty));
                        if let Some(ty) = ty {
                            let mut from = self.instance.clone();
                            from.push(link.from.node());
                            crate::previews::draw::large(
                                ui,
                                &mut self.previews,
                                &from,
                                link.from.pin(),
                                ty,
                            );
                        }
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

    /// Each node's rectangle on screen last frame: the nodes snarl did not
    /// hold (off the view), where they were last drawn, then those it drew,
    /// in drawing order. Hit tests need only the drawn ones (the others lie
    /// outside the view), so a frame does not build this; fitting the view
    /// and the tests do.
    pub fn node_screen_rects(&self) -> Vec<(NodeId, egui::Rect)> {
        let patch = self.doc.patch();
        let drawn = &self.canvas.node_rects;
        if self.canvas.snarl_ids.len() == patch.nodes.len() {
            return drawn.clone();
        }
        let to_global = self.canvas.view.unwrap_or_default();
        // The same view of the same document: the same rectangles as last frame.
        let key = (
            to_global,
            self.doc.generation(),
            self.canvas.snarl_ids.len(),
        );
        let mut cache = self.canvas.culling.culled_rects.borrow_mut();
        if cache.0 != Some(key) {
            cache.1 = patch
                .nodes
                .iter()
                .filter(|n| !self.canvas.snarl_ids.contains_key(&n.id))
                .map(|n| (n.id, to_global * self.canvas.culling.rect(n)))
                .collect();
            cache.0 = Some(key);
        }
        let mut all = cache.1.clone();
        all.extend(drawn.iter().copied());
        all
    }

    /// The wires snarl cannot draw: those to or from a node it does not hold
    /// (off the view, `canvas/cull.rs`), from where their pins were last
    /// drawn, under the nodes; their ends are recorded as drawn pins, so
    /// hovering one shows its value as any wire does.
    fn wires_to_culled_nodes(&self, ui: &Ui, layer: LayerId, canvas_rect: egui::Rect) {
        let patch = self.doc.patch();
        if self.canvas.snarl_ids.len() == patch.nodes.len() {
            return;
        }
        let to_global = ui
            .ctx()
            .layer_transform_to_global(layer)
            .unwrap_or_default();
        // The same view of the same document, nothing dragged: last frame's wires.
        let key = (
            to_global,
            canvas_rect,
            self.doc.generation(),
            self.canvas.snarl_ids.len(),
        );
        let dragging = ui.input(|i| i.pointer.any_down());
        let mut cache = self.canvas.culling.culled_wires.borrow_mut();
        if dragging || cache.0 != Some(key) {
            cache.1.clear();
            let view = to_global.inverse() * canvas_rect;
            for l in &patch.links {
                let (from, to) = (l.from.node(), l.to.node());
                let (sa, sb) = (
                    self.canvas.snarl_ids.get(&from),
                    self.canvas.snarl_ids.get(&to),
                );
                if sa.is_some() && sb.is_some() {
                    continue;
                }
                let (Some(na), Some(nb)) = (self.doc.node(from), self.doc.node(to)) else {
                    continue;
                };
                // A wire lies within its two nodes' rectangles: most lie off the view.
                if !self
                    .canvas
                    .culling
                    .rect(na)
                    .union(self.canvas.culling.rect(nb))
                    .intersects(view)
                {
                    continue;
                }
                // A node snarl holds is where snarl has it (a drag in progress).
                let origin = |n: &spreadlight_graph::NodeDoc, sid: Option<&egui_snarl::NodeId>| {
                    sid.and_then(|s| self.canvas.snarl.get_node_info(*s))
                        .map_or(Pos2::new(n.pos.0 * SCALE, n.pos.1 * SCALE), |i| i.pos)
                };
                let a = to_global
                    * self.canvas.culling.pin_at(
                        &self.registry,
                        na,
                        origin(na, sa),
                        l.from.pin(),
                        false,
                    );
                let b = to_global
                    * self.canvas.culling.pin_at(
                        &self.registry,
                        nb,
                        origin(nb, sb),
                        l.to.pin(),
                        true,
                    );
                if !egui::Rect::from_two_pos(a, b).intersects(canvas_rect) {
                    continue;
                }
                let color = canvas::wire_color(&self.registry, na, l.from.pin());
                cache.1.push(canvas::CulledWire {
                    from: (from, l.from.pin().to_owned(), false),
                    to: (to, l.to.pin().to_owned(), true),
                    a,
                    b,
                    color,
                });
            }
            cache.0 = (!dragging).then_some(key);
        }
        let painter = ui.painter().with_clip_rect(canvas_rect);
        let width = (0.8 * to_global.scaling).max(1.0);
        let mut pins = self.canvas.pins.borrow_mut();
        for w in &cache.1 {
            painter.line_segment([w.a, w.b], egui::Stroke::new(width, w.color));
            pins.insert(w.from.clone(), w.a);
            pins.insert(w.to.clone(), w.b);
        }
    }

    /// Shift-drag on empty canvas selects every node the rectangle touches
    /// (Shift keeps the selection and adds to it, as Shift-click does).
    pub(super) fn rectangle_selection(
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
            self.canvas.rect_select = Some(pos);
        }
        let Some(start) = self.canvas.rect_select else {
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
            self.canvas.rect_select = None;
            for (id, r) in node_rects {
                if r.intersects(area) {
                    self.canvas.selected.insert(*id);
                }
            }
        }
    }

    pub(super) fn node_browser(&mut self, ctx: &egui::Context) {
        let Some(b) = &mut self.browser else {
            return;
        };
        let mut hits = browser::filter(&self.registry, &b.query);
        if let Some(link) = &b.link {
            // Only types that can take the wire or go into the link.
            hits.retain(|name| link.fits(&self.doc, &self.registry, name));
        }
        let mut place = None;
        let mut close = false;
        let opened_now = b.focus;
        let area = egui::Area::new(Id::new("node-browser"))
            .fixed_pos(b.screen)
            .order(egui::Order::Foreground)
            .show(ctx, |ui| {
                egui::Frame::popup(ui.style()).show(ui, |ui| {
                    ui.set_width(260.0);
                    let keys = super::search_field::search_field(
                        ui,
                        (&mut b.query, &mut b.focus, &mut b.highlighted),
                        hits.len(),
                        "type a node name or category",
                        "node-browser-query",
                    );
                    if keys.enter {
                        place = hits.get(b.highlighted).copied();
                        close = true;
                    }
                    if keys.escape {
                        close = true;
                    }
                    egui::ScrollArea::vertical()
                        .max_height(300.0)
                        .show(ui, |ui| {
                            for (i, name) in hits.iter().enumerate() {
                                let category = self.registry.get(name).map_or("", |d| &*d.category);
                                let r = ui
                                    .selectable_label(i == b.highlighted, *name)
                                    .on_hover_text(
                                        self.registry.get(name).map_or("", |d| &*d.help),
                                    );
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
            let link = b.link.clone();
            match super::organise::place_node(
                &mut self.doc,
                &self.registry,
                name,
                at,
                link.as_ref(),
            ) {
                Ok(id) => self.canvas.selected = [id].into_iter().collect(),
                Err(e) => self.status = format!("{name} was not put into the link: {e}"),
            }
        }
        if close {
            self.browser = None;
        }
    }
}
