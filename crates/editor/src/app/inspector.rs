//! The inspector panel: the selected node's values and outputs, and the viewports that show textures.

use super::*;

impl EditorApp {
    pub(super) fn inspector(&mut self, ui: &mut Ui) {
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
        ui.weak(&*def.help);
        self.inspector_thumbnail(ui, id, &def);
        let mut at = self.instance.clone();
        at.push(id);
        if let Some(e) = self.frame.runtime.node_error_at(&at) {
            ui.colored_label(egui::Color32::LIGHT_RED, e.to_string());
        }
        ui.separator();
        egui::ScrollArea::vertical().show(ui, |ui| {
            for pin in &def.inputs {
                ui.push_id(&*pin.name, |ui| {
                    let label = ui
                        .horizontal(|ui| {
                            let label = ui.label(egui::RichText::new(&*pin.name).strong());
                            ui.weak(pin.ty.name());
                            label.id
                        })
                        .inner;
                    let target = PinRef(id, pin.name.to_string());
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
                            .get(&*pin.name)
                            .cloned()
                            .unwrap_or_else(|| pin.default.clone());
                        let edited = values::edit_spread(
                            ui,
                            pin.ty,
                            pin.range,
                            &mut value,
                            &pin.name,
                            Some(label),
                        );
                        if edited.changed {
                            self.doc
                                .set_value(id, &pin.name, Some(value), edited.continuing);
                        }
                        if node.values.contains_key(&*pin.name)
                            && ui.small_button("reset to default").clicked()
                        {
                            self.doc.set_value(id, &pin.name, None, false);
                        }
                        if node.type_name == "MidiIn" && &*pin.name == "Controller" {
                            self.midi_learn_ui(ui, id);
                        }
                    }
                    ui.add_space(4.0);
                });
            }
            ui.separator();
            let mut path = self.instance.clone();
            path.push(id);
            for pin in &def.outputs {
                let value = self
                    .frame
                    .runtime
                    .output_at(&path, &pin.name)
                    .map_or_else(|| "not evaluated".to_owned(), |s| canvas::preview(s));
                ui.horizontal(|ui| {
                    let watched = self.watches.contains(&(path.clone(), pin.name.to_string()));
                    let eye = ui
                        .selectable_label(watched, "👁")
                        .on_hover_text(format!("watch {}", pin.name));
                    if eye.clicked() {
                        self.toggle_watch(path.clone(), &pin.name);
                    }
                    ui.label(format!("{} → {value}", pin.name));
                });
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

    /// MidiIn's `learn` button: armed, the next controller the node receives
    /// sets its Controller and Channel (an edit like any other, undoable).
    fn midi_learn_ui(&mut self, ui: &mut Ui, id: NodeId) {
        let learn = self.worker.midi_learn().clone();
        if let Some(b) = learn.take(id) {
            self.doc.set_value(
                id,
                "Controller",
                Some(Spread::Int(vec![i64::from(b.controller)])),
                false,
            );
            self.doc.set_value(
                id,
                "Channel",
                Some(Spread::Int(vec![i64::from(b.channel)])),
                false,
            );
        }
        let armed = learn.is_armed(id);
        let text = if armed {
            "learning: move a controller"
        } else {
            "learn"
        };
        if ui
            .selectable_label(armed, text)
            .on_hover_text("bind the next MIDI controller that moves")
            .clicked()
        {
            if armed {
                learn.cancel();
            } else {
                learn.arm(id);
            }
        }
        if armed {
            // The binding arrives from the patch thread: look again soon.
            ui.ctx()
                .request_repaint_after(std::time::Duration::from_millis(50));
        }
    }

    pub(super) fn texture_pins(&self) -> Vec<(NodeId, Name, String)> {
        let mut out = Vec::new();
        for n in &self.doc.top().nodes {
            if let Some(def) = self.registry.get(&n.type_name) {
                for p in &def.outputs {
                    if p.ty == PinType::Resource(ResourceKind::Texture) {
                        out.push((
                            n.id,
                            p.name.clone(),
                            format!("{} {}.{}", n.type_name, n.id, p.name),
                        ));
                    }
                }
            }
        }
        out
    }

    pub(super) fn viewport_ui(&mut self, ui: &mut Ui, k: usize, label: Option<Id>) {
        if k == 1 {
            let current = match &self.viewports.views[1].source {
                Source::None => "none".to_owned(),
                Source::Output => "Output".to_owned(),
                Source::Pin(n, p) => format!("{n}.{p}"),
            };
            let combo = egui::ComboBox::from_id_salt("second-viewport")
                .selected_text(current)
                .show_ui(ui, |ui| {
                    // Listed only while the drop-down is open: a look at every node.
                    let pins = self.texture_pins();
                    if ui
                        .selectable_label(
                            self.viewports.views[1].source == Source::Output,
                            "Output",
                        )
                        .clicked()
                    {
                        self.viewports.views[1].source = Source::Output;
                    }
                    for (node, pin, label) in pins {
                        let source = Source::Pin(node, pin.to_string());
                        if ui
                            .selectable_label(self.viewports.views[1].source == source, label)
                            .clicked()
                        {
                            self.viewports.views[1].source = source;
                        }
                    }
                });
            if let Some(label) = label {
                combo.response.labelled_by(label);
            }
        }
        let avail = ui.available_size();
        if k == 0 {
            self.viewports.area = Some(egui::Rect::from_min_size(ui.cursor().min, avail));
        }
        let ppp = ui.ctx().pixels_per_point();
        let size = (
            ((avail.x * ppp) as u32).clamp(16, 4096),
            ((avail.y * ppp) as u32).clamp(16, 4096),
        );
        self.viewports.views[k].size = size;
        let shown = self.frame.views.get(k).cloned().unwrap_or_default();
        match (&shown.target, &shown.error) {
            (_, Some(e)) => {
                ui.weak(e.to_string());
            }
            (Some(t), None) => {
                let tex_size =
                    egui::vec2(t.texture.width() as f32, t.texture.height() as f32) / ppp;
                let r = ui.add(egui::Image::new((t.id, tex_size)).fit_to_exact_size(avail));
                self.viewports.rects[k] = Some(r.rect);
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
}
