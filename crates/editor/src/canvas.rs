//! The canvas: an egui-snarl projection of the document. Snarl holds only
//! each node's document id; pins, values, errors and timings are read from
//! the document, the registry and the runtime while drawing, and every
//! action the canvas takes goes back through [`EditorDoc`] so it is undoable.
//!
//! Split by concern: how it looks and where pins were drawn (`style.rs`),
//! keeping snarl in step with the document (`sync.rs`), the wire under the
//! pointer (`wires.rs`); here the viewer that draws and edits nodes.

use std::collections::{BTreeSet, HashMap};

use egui::{Color32, Pos2, Rect, Stroke, Ui};
use egui_snarl::ui::{PinInfo, PinShape, SnarlPin, SnarlViewer};
use egui_snarl::{InPin, InPinId, OutPin, OutPinId, Snarl};
use spreadlight_graph::{NodeId, PinRef, PinType, Registry, RuntimeSnapshot, Severity, Spread};

use crate::model::EditorDoc;
use crate::values;

mod cull;
mod pins;
mod style;
mod sync;
mod wires;

pub use crate::zoom::{READABLE_ZOOM, fit_view, zoom_around};
pub use cull::{CulledWire, Culling, wire_color};
pub use pins::PinOffsets;
use style::RecordedPin;
pub use style::pin_color;
pub use style::{PinKey, PinPositions, compact_spacing, style};
pub use sync::{CanvasNode, SCALE, moved_nodes, sync};
pub use wires::wire_under;

/// Room between an output's name and its pin, which snarl draws over the row's end.
const OUTPUT_PIN_GAP: f32 = 6.0;

/// A bypassed node's header and body (`organise`: bypass).
const BYPASS_HEADER: Color32 = Color32::from_rgb(150, 105, 20);
const BYPASS_FILL: Color32 = Color32::from_rgb(45, 40, 30);
pub use crate::canvas_units::BYPASS_TAG;

/// Below this zoom the canvas shows pins without their value editors (the inspector still edits).
pub const EDITOR_MIN_ZOOM: f32 = 0.5;

/// A refused link, shown where it was dropped.
#[derive(Clone, Debug, PartialEq)]
pub struct Refusal {
    pub message: String,
    pub at: Pos2,
    pub since: f64,
}

/// Everything the canvas reads or changes while it draws.
pub struct Canvas<'a> {
    pub doc: &'a mut EditorDoc,
    pub registry: &'a Registry,
    pub runtime: &'a RuntimeSnapshot,
    pub selected: &'a BTreeSet<NodeId>,
    /// Each node's rectangle on screen, in drawing order (the last is on top).
    pub node_rects: &'a mut Vec<(NodeId, Rect)>,
    pub show_timings: bool,
    pub gpu_ms: &'a HashMap<u32, f64>,
    pub gpu_errors: &'a HashMap<u32, String>,
    pub refusal: &'a mut Option<Refusal>,
    pub pins: PinPositions,
    /// The last place the pointer was seen (a drop may come with the pointer leaving).
    pub pointer: Pos2,
    /// A view to show instead of snarl's own (fitting the patch after it opens).
    pub set_view: Option<egui::emath::TSTransform>,
    pub now: f64,
    /// The subpatch instance the open document is shown for (node ids from the
    /// top; empty at the top): live values, errors and timings are read there.
    pub instance: &'a [NodeId],
    /// What is remembered of drawn nodes, to leave off-screen ones out (`cull.rs`).
    pub culling: &'a mut Culling,
    /// Thumbnails and hover previews (`previews`).
    pub previews: &'a mut crate::previews::CanvasPreviews,
}

impl<'a> Canvas<'a> {
    /// The path of node `id` of the open document in the running patch.
    fn at(&self, id: NodeId) -> Vec<NodeId> {
        let mut path = self.instance.to_vec();
        path.push(id);
        path
    }

    /// The id GPU passes name node `id` of the open document by (its id in the flat network).
    fn flat_id(&self, id: NodeId) -> u32 {
        let network = self.runtime.network();
        network
            .index_at(&self.at(id))
            .map_or(id.0, |i| network.nodes()[i].id.0)
    }

    fn node_id(snarl: &Snarl<CanvasNode>, node: egui_snarl::NodeId) -> Option<NodeId> {
        snarl.get_node(node).map(|n| n.0)
    }

    fn input_pin(
        &self,
        snarl: &Snarl<CanvasNode>,
        pin: InPinId,
    ) -> Option<(NodeId, &'a str, PinType)> {
        let id = Self::node_id(snarl, pin.node)?;
        let registry: &'a Registry = self.registry;
        let def = registry.get(&self.doc.node(id)?.type_name)?;
        let p = def.inputs.get(pin.input)?;
        Some((id, &*p.name, p.ty))
    }

    fn output_pin(
        &self,
        snarl: &Snarl<CanvasNode>,
        pin: OutPinId,
    ) -> Option<(NodeId, &'a str, PinType)> {
        let id = Self::node_id(snarl, pin.node)?;
        let registry: &'a Registry = self.registry;
        let def = registry.get(&self.doc.node(id)?.type_name)?;
        let p = def.outputs.get(pin.output)?;
        Some((id, &*p.name, p.ty))
    }

    /// The node's error: a problem found when compiling, the error of its last
    /// run, or an error of a GPU pass it declared in the viewport's frame.
    fn error_of(&self, id: NodeId) -> Option<String> {
        let mut messages: Vec<String> = self
            .runtime
            .problems()
            .iter()
            .filter(|p| p.node == id && p.within == self.instance && p.severity == Severity::Error)
            .map(|p| match &p.pin {
                Some(pin) => format!("{pin}: {}", p.kind),
                None => p.kind.to_string(),
            })
            .collect();
        if let Some(e) = self.runtime.node_error_at(&self.at(id)) {
            messages.push(e.to_string());
        }
        if let Some(e) = self.gpu_errors.get(&self.flat_id(id)) {
            messages.push(format!("GPU: {e}"));
        }
        (!messages.is_empty()).then(|| messages.join("\n"))
    }

    /// The node's output pins that have a preview, by name and type.
    fn preview_outputs(&self, id: NodeId) -> Vec<(&'a str, PinType)> {
        let registry: &'a Registry = self.registry;
        self.doc
            .node(id)
            .and_then(|n| registry.get(&n.type_name))
            .map(|d| {
                d.outputs
                    .iter()
                    .filter(|p| crate::previews::previewable(p.ty))
                    .map(|p| (&*p.name, p.ty))
                    .collect()
            })
            .unwrap_or_default()
    }

    /// The pin drawn for `key` on the node placed at `origin` (canvas px).
    fn recorded(&self, key: PinKey, ty: Option<PinType>, origin: Pos2) -> RecordedPin {
        let shape = if matches!(ty, Some(PinType::Resource(_))) {
            PinShape::Square
        } else {
            PinShape::Circle
        };
        let fill = ty.map_or(Color32::DARK_GRAY, pin_color);
        RecordedPin {
            info: PinInfo::default().with_shape(shape).with_fill(fill),
            key,
            sink: self.pins.clone(),
            origin,
            offsets: self.culling.offsets.clone(),
        }
    }

    fn refuse(&mut self, message: String) {
        let at = self.pointer;
        *self.refusal = Some(Refusal {
            message,
            at,
            since: self.now,
        });
    }
}

/// A slice preview as vvvv's tooltips show: the first slices and the count.
pub fn preview(spread: &Spread) -> String {
    spread.preview(4)
}

impl SnarlViewer<CanvasNode> for Canvas<'_> {
    fn title(&mut self, node: &CanvasNode) -> String {
        self.doc
            .node(node.0)
            .map_or_else(|| "?".to_owned(), |n| n.type_name.clone())
    }

    fn header_frame(
        &mut self,
        default: egui::Frame,
        node: egui_snarl::NodeId,
        _inputs: &[InPin],
        _outputs: &[OutPin],
        snarl: &Snarl<CanvasNode>,
    ) -> egui::Frame {
        match Self::node_id(snarl, node) {
            Some(id) if self.error_of(id).is_some() => default.fill(Color32::from_rgb(150, 30, 30)),
            Some(id) if self.doc.node(id).is_some_and(|n| n.bypass) => default.fill(BYPASS_HEADER),
            _ => default,
        }
    }

    fn node_frame(
        &mut self,
        default: egui::Frame,
        node: egui_snarl::NodeId,
        _inputs: &[InPin],
        _outputs: &[OutPin],
        snarl: &Snarl<CanvasNode>,
    ) -> egui::Frame {
        // A bypassed node is dimmed with an amber rim, so it reads as "not running" at a glance.
        let default = match Self::node_id(snarl, node) {
            Some(id) if self.doc.node(id).is_some_and(|n| n.bypass) => default
                .fill(BYPASS_FILL)
                .stroke(Stroke::new(2.0, BYPASS_HEADER)),
            _ => default,
        };
        match Self::node_id(snarl, node) {
            Some(id) if self.selected.contains(&id) => {
                default.stroke(Stroke::new(2.0, Color32::from_rgb(90, 170, 255)))
            }
            _ => default,
        }
    }

    fn show_header(
        &mut self,
        node: egui_snarl::NodeId,
        _inputs: &[InPin],
        _outputs: &[OutPin],
        ui: &mut Ui,
        snarl: &mut Snarl<CanvasNode>,
    ) {
        let Some(id) = Self::node_id(snarl, node) else {
            return;
        };
        self.culling.laid_out += 1;
        let title = self.title(&snarl[node]);
        // Not clickable: a drag on the title moves the node; clicks select through `node_rects`.
        let resp = ui.label(egui::RichText::new(title).strong());
        if self.doc.node(id).is_some_and(|n| n.bypass) {
            ui.label(egui::RichText::new(BYPASS_TAG).color(Color32::from_rgb(255, 200, 90)));
        }
        match self.error_of(id) {
            Some(message) => resp.on_hover_text(message),
            None => resp.on_hover_text(format!("node {id}")),
        };
    }

    fn final_node_rect(
        &mut self,
        node: egui_snarl::NodeId,
        rect: Rect,
        ui: &mut Ui,
        snarl: &mut Snarl<CanvasNode>,
    ) {
        if let Some(id) = Self::node_id(snarl, node) {
            self.culling.drawn(id, rect.size());
            let to_global = ui
                .ctx()
                .layer_transform_to_global(ui.layer_id())
                .unwrap_or_default();
            self.node_rects.push((id, to_global * rect));
        }
    }

    fn inputs(&mut self, node: &CanvasNode) -> usize {
        self.doc
            .node(node.0)
            .and_then(|n| self.registry.get(&n.type_name))
            .map_or(0, |d| d.inputs.len())
    }

    fn outputs(&mut self, node: &CanvasNode) -> usize {
        self.doc
            .node(node.0)
            .and_then(|n| self.registry.get(&n.type_name))
            .map_or(0, |d| d.outputs.len())
    }

    fn show_input(
        &mut self,
        pin: &InPin,
        ui: &mut Ui,
        snarl: &mut Snarl<CanvasNode>,
    ) -> impl SnarlPin + 'static {
        let origin = snarl
            .get_node_info(pin.id.node)
            .map_or(Pos2::ZERO, |n| n.pos);
        let Some((id, name, ty)) = self.input_pin(snarl, pin.id) else {
            return self.recorded((NodeId(0), String::new(), true), None, origin);
        };
        let target = PinRef(id, name.to_owned());
        let linked = self.doc.link_into(&target).cloned();
        let label = ui.label(name);
        let label_id = label.id;
        // Previews are built only for the pin under the pointer: a big patch has thousands of pins.
        if label.hovered() {
            let shown = match &linked {
                Some(l) => self
                    .runtime
                    .output_at(&self.at(l.from.node()), l.from.pin())
                    .map(|s| preview(s)),
                None => self
                    .doc
                    .input_value(self.registry, id, name)
                    .map(|s| preview(&s)),
            };
            let text = format!(
                "{name}: {ty}\n{}",
                shown.unwrap_or_else(|| "no value yet".into())
            );
            match &linked {
                // What flows in from a texture, G-buffer or mesh: its preview.
                Some(l) if crate::previews::previewable(ty) => {
                    let from = self.at(l.from.node());
                    let previews = &mut *self.previews;
                    label.on_hover_ui(|ui| {
                        ui.label(text);
                        crate::previews::draw::large(ui, previews, &from, l.from.pin(), ty);
                    });
                }
                _ => {
                    label.on_hover_text(text);
                }
            }
        }
        // Zoomed far out the editors are too small to use, and a big patch
        // would spend most of its frame drawing them.
        let zoom = ui
            .ctx()
            .layer_transform_to_global(ui.layer_id())
            .map_or(1.0, |t| t.scaling);
        // An IOBox edits its value as rows in its body instead.
        let iobox = self
            .doc
            .node(id)
            .is_some_and(|n| crate::iobox::is_iobox(&n.type_name));
        if linked.is_none()
            && !iobox
            && zoom >= EDITOR_MIN_ZOOM
            && values::editable(ty)
            && let Some(mut value) = self.doc.input_value(self.registry, id, name)
        {
            let range = self
                .doc
                .node(id)
                .and_then(|n| self.registry.get(&n.type_name))
                .and_then(|d| d.inputs.iter().find(|p| p.name == name))
                .and_then(|p| p.range);
            let edited = ui
                .push_id((id, name), |ui| {
                    values::edit_first(ui, ty, range, &mut value, Some(label_id))
                })
                .inner;
            if edited.changed {
                self.doc.set_value(id, name, Some(value), edited.continuing);
            }
        }
        self.recorded((id, name.to_owned(), true), Some(ty), origin)
    }

    fn show_output(
        &mut self,
        pin: &OutPin,
        ui: &mut Ui,
        snarl: &mut Snarl<CanvasNode>,
    ) -> impl SnarlPin + 'static {
        let origin = snarl
            .get_node_info(pin.id.node)
            .map_or(Pos2::ZERO, |n| n.pos);
        let Some((id, name, ty)) = self.output_pin(snarl, pin.id) else {
            return self.recorded((NodeId(0), String::new(), false), None, origin);
        };
        // Snarl draws an output's pin over the row's end: keep the name clear of it.
        ui.add_space(OUTPUT_PIN_GAP);
        let label = ui.label(name);
        if label.hovered() {
            let shown = self
                .runtime
                .output_at(&self.at(id), name)
                .map_or_else(|| "not evaluated".to_owned(), |s| preview(s));
            let text = format!("{name}: {ty}\n{shown}");
            if crate::previews::previewable(ty) {
                let path = self.at(id);
                let previews = &mut *self.previews;
                label.on_hover_ui(|ui| {
                    ui.label(text);
                    crate::previews::draw::large(ui, previews, &path, name, ty);
                });
            } else {
                label.on_hover_text(text);
            }
        }
        self.recorded((id, name.to_owned(), false), Some(ty), origin)
    }

    fn has_body(&mut self, node: &CanvasNode) -> bool {
        self.doc
            .node(node.0)
            .is_some_and(|n| crate::iobox::is_iobox(&n.type_name))
            || crate::previews::draw::shows_thumbnails(
                &*self.previews,
                &self.at(node.0),
                &self.preview_outputs(node.0),
            )
    }

    fn show_body(
        &mut self,
        node: egui_snarl::NodeId,
        _inputs: &[InPin],
        _outputs: &[OutPin],
        ui: &mut Ui,
        snarl: &mut Snarl<CanvasNode>,
    ) {
        if let Some(id) = Self::node_id(snarl, node) {
            let path = self.at(id);
            let iobox = self
                .doc
                .node(id)
                .is_some_and(|n| crate::iobox::is_iobox(&n.type_name));
            if iobox {
                crate::iobox::rows(ui, self.doc, self.registry, self.runtime, &path);
            } else {
                let outputs = self.preview_outputs(id);
                crate::previews::draw::thumbnails(ui, &mut *self.previews, &path, &outputs);
            }
        }
    }

    fn has_footer(&mut self, _node: &CanvasNode) -> bool {
        self.show_timings
    }

    fn show_footer(
        &mut self,
        node: egui_snarl::NodeId,
        _inputs: &[InPin],
        _outputs: &[OutPin],
        ui: &mut Ui,
        snarl: &mut Snarl<CanvasNode>,
    ) {
        let Some(id) = Self::node_id(snarl, node) else {
            return;
        };
        let path = self.at(id);
        let stats = self.runtime.stats();
        // A subpatch node costs what its inside costs.
        let cpu = match stats.node_at(&path) {
            Some(s) => s.cpu_ns,
            None => stats.inside(&path).map(|s| s.cpu_ns).sum(),
        } as f64
            / 1e6;
        let text = match self.gpu_ms.get(&self.flat_id(id)) {
            Some(gpu) => format!("CPU {cpu:.3} ms · GPU {gpu:.3} ms"),
            None => format!("CPU {cpu:.3} ms"),
        };
        ui.weak(text);
    }

    fn draw_background(
        &mut self,
        background: Option<&egui_snarl::ui::BackgroundPattern>,
        viewport: &Rect,
        snarl_style: &egui_snarl::ui::SnarlStyle,
        style: &egui::Style,
        painter: &egui::Painter,
        _snarl: &Snarl<CanvasNode>,
    ) {
        if let Some(background) = background {
            background.draw(viewport, snarl_style, style, painter);
        }
        crate::organise::paint_annotations(painter, self.doc.patch());
    }

    fn has_dropped_wire_menu(
        &mut self,
        _src_pins: egui_snarl::ui::AnyPins,
        _snarl: &mut Snarl<CanvasNode>,
    ) -> bool {
        true
    }

    fn show_dropped_wire_menu(
        &mut self,
        pos: Pos2,
        ui: &mut Ui,
        src_pins: egui_snarl::ui::AnyPins,
        snarl: &mut Snarl<CanvasNode>,
    ) {
        crate::organise::gestures::catch_dropped_wire(
            self.doc,
            self.registry,
            snarl,
            src_pins,
            pos,
            ui,
        );
    }

    fn current_transform(
        &mut self,
        to_global: &mut egui::emath::TSTransform,
        _snarl: &mut Snarl<CanvasNode>,
    ) {
        if let Some(view) = self.set_view.take() {
            *to_global = view;
        }
    }

    fn connect(&mut self, from: &OutPin, to: &InPin, snarl: &mut Snarl<CanvasNode>) {
        let (Some((a, out, _)), Some((b, inp, _))) = (
            self.output_pin(snarl, from.id),
            self.input_pin(snarl, to.id),
        ) else {
            return;
        };
        let result = self.doc.link(
            self.registry,
            PinRef(a, out.to_owned()),
            PinRef(b, inp.to_owned()),
        );
        if let Err(e) = result {
            // Snarl passes no Ui here; the pointer is where the wire was dropped.
            self.refuse(e.to_string());
        }
    }

    fn disconnect(&mut self, from: &OutPin, to: &InPin, snarl: &mut Snarl<CanvasNode>) {
        if let (Some((a, out, _)), Some((b, inp, _))) = (
            self.output_pin(snarl, from.id),
            self.input_pin(snarl, to.id),
        ) {
            self.doc
                .unlink(&PinRef(a, out.to_owned()), &PinRef(b, inp.to_owned()));
        }
    }

    fn drop_inputs(&mut self, pin: &InPin, snarl: &mut Snarl<CanvasNode>) {
        if let Some((id, name, _)) = self.input_pin(snarl, pin.id) {
            self.doc.unlink_input(&PinRef(id, name.to_owned()));
        }
    }

    fn drop_outputs(&mut self, pin: &OutPin, snarl: &mut Snarl<CanvasNode>) {
        if let Some((id, name, _)) = self.output_pin(snarl, pin.id) {
            self.doc.unlink_output(&PinRef(id, name.to_owned()));
        }
    }
}
