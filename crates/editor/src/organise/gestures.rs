//! vvvv's patching gestures on the canvas: a wire dropped on empty canvas
//! opens the node browser for a node that takes it; a double-clicked link
//! opens it for a node to put into the link. Here what the browser is
//! opened for and how the dropped wire is caught from egui-snarl; the
//! document side is `model/organise.rs`, the glue `app/organise.rs`.

use egui::{Id, Pos2, Ui};
use egui_snarl::Snarl;
use egui_snarl::ui::AnyPins;
use spreadlight_graph::{LinkDoc, PinRef, Registry};

use crate::canvas_units::{CanvasNode, SCALE};
use crate::model::EditorDoc;
use crate::model::organise::DroppedWire;

/// What the node browser places its node into, besides the canvas.
#[derive(Clone, Debug, PartialEq)]
pub enum BrowserLink {
    /// A wire dropped on empty canvas: the node is linked to its pins.
    Wire(DroppedWire),
    /// A double-clicked link: the node is put into it.
    Insert(LinkDoc),
}

impl BrowserLink {
    /// Whether a node of `type_name` can take the wire or the link.
    pub fn fits(&self, doc: &EditorDoc, registry: &Registry, type_name: &str) -> bool {
        match self {
            BrowserLink::Wire(wire) => doc.wire_fits(registry, type_name, wire).is_some(),
            BrowserLink::Insert(link) => doc.link_fits(registry, type_name, link).is_some(),
        }
    }
}

/// Where a dropped wire waits for the app between snarl's menu and the
/// browser: snarl calls its viewer inside its own widget, so the viewer
/// leaves it in egui's memory and the app takes it after the widget.
fn dropped_id() -> Id {
    Id::new("spreadlight-dropped-wire")
}

/// Called from snarl's dropped-wire menu: note the wire's pins and where it
/// was dropped (canvas units and screen), and close the menu at once (the
/// node browser opens instead).
pub fn catch_dropped_wire(
    doc: &EditorDoc,
    registry: &Registry,
    snarl: &Snarl<CanvasNode>,
    pins: AnyPins<'_>,
    pos: Pos2,
    ui: &mut Ui,
) {
    let type_of = |node: egui_snarl::NodeId| {
        let id = snarl.get_node(node)?.0;
        Some((id, registry.get(&doc.node(id)?.type_name)?))
    };
    let wire = match pins {
        AnyPins::Out(pins) => DroppedWire::Outputs(
            pins.iter()
                .filter_map(|p| {
                    let (id, def) = type_of(p.node)?;
                    Some(PinRef(id, def.outputs.get(p.output)?.name.to_string()))
                })
                .collect(),
        ),
        AnyPins::In(pins) => DroppedWire::Inputs(
            pins.iter()
                .filter_map(|p| {
                    let (id, def) = type_of(p.node)?;
                    Some(PinRef(id, def.inputs.get(p.input)?.name.to_string()))
                })
                .collect(),
        ),
    };
    let screen = ui
        .ctx()
        .input(|i| i.pointer.latest_pos())
        .unwrap_or(ui.min_rect().min);
    let at = ((pos.x / SCALE).round(), (pos.y / SCALE).round());
    ui.ctx()
        .data_mut(|d| d.insert_temp(dropped_id(), (wire, at, screen)));
    ui.close();
}

/// The wire dropped this frame, if any: its pins, where (canvas units), and where on screen.
pub fn take_dropped_wire(ctx: &egui::Context) -> Option<(DroppedWire, (f32, f32), Pos2)> {
    ctx.data_mut(|d| {
        let dropped = d.get_temp(dropped_id());
        d.remove::<(DroppedWire, (f32, f32), Pos2)>(dropped_id());
        dropped
    })
}
