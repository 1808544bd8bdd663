//! Culling: only the nodes in or near the canvas's view are snarl's, so a
//! patch of thousands of nodes costs a frame what its visible part costs.
//!
//! egui-snarl lays out and draws every node it holds each frame, and
//! gathers each pin's wires by scanning all of them (`InPin::new`), so its
//! cost grows with nodes times wires. The canvas therefore gives it only the
//! nodes whose rectangle meets the view grown by [`MARGIN`] (`sync`), and
//! draws the wires that lead to the others itself, from where their pins
//! were when last drawn ([`Culling::pin_at`]). Everything else about a node
//! (its document entry, its value in the runtime) is untouched: a culled node
//! still runs. Fitting the view (on open, F) measures every node, so culling
//! is off while it runs.

use std::cell::RefCell;
use std::collections::HashMap;

use egui::emath::TSTransform;
use egui::{Pos2, Rect, Vec2};
use spreadlight_graph::{NodeDoc, NodeId, Registry};

use super::pins::{PinKey, PinOffsets};
use super::sync::SCALE;

/// How far around the view (a share of its larger side) nodes stay in snarl:
/// a pan or zoom of a frame never brings an outside node on screen.
pub const MARGIN: f32 = 0.5;

/// The size assumed for a node never drawn (canvas px): its real one is
/// known after its first frame on screen.
const UNKNOWN_SIZE: Vec2 = Vec2::new(160.0, 90.0);

/// Culled nodes and their rectangles on screen.
pub type CulledRects = Vec<(NodeId, Rect)>;

/// What the canvas remembers of nodes it drew, to leave them out later.
pub struct Culling {
    /// Off (`SPREADLIGHT_EDITOR_CULLING=0`): snarl holds every node, as it
    /// did before; for measuring what culling saves.
    pub enabled: bool,
    /// Each node's size when last drawn (canvas px).
    sizes: HashMap<NodeId, Vec2>,
    /// Each drawn pin's offset from its node's position.
    pub offsets: PinOffsets,
    /// How many nodes the viewer laid out in the last frame (their titles
    /// and pins): what culling keeps down, read by the tests.
    pub laid_out: usize,
    /// The document (subpatch instance) the sizes and offsets are of.
    pub instance: Vec<NodeId>,
    /// The kept area snarl was last synced for (`None` inside: every node).
    pub kept_area: Option<Option<Rect>>,
    /// The culled nodes' rectangles on screen, for a view of a document.
    pub culled_rects: RefCell<(Option<RectsKey>, CulledRects)>,
    /// The wires to culled nodes across the canvas, for a view of a document.
    pub culled_wires: RefCell<(Option<WiresKey>, Vec<CulledWire>)>,
}

/// What the culled rectangles depend on: the view, the document's generation, the nodes kept.
pub type RectsKey = (TSTransform, u64, usize);

/// What the wires to culled nodes depend on: the view, the canvas, the document, the nodes kept.
pub type WiresKey = (TSTransform, Rect, u64, usize);

/// A wire to or from a culled node, on screen.
pub struct CulledWire {
    pub from: PinKey,
    pub to: PinKey,
    pub a: Pos2,
    pub b: Pos2,
    pub color: egui::Color32,
}

impl Default for Culling {
    fn default() -> Self {
        Culling {
            enabled: std::env::var_os("SPREADLIGHT_EDITOR_CULLING").is_none_or(|v| v != "0"),
            sizes: HashMap::new(),
            offsets: PinOffsets::default(),
            laid_out: 0,
            instance: Vec::new(),
            kept_area: None,
            culled_rects: RefCell::default(),
            culled_wires: RefCell::default(),
        }
    }
}

impl Culling {
    /// Forget what was drawn: another document is shown (ids mean other nodes there).
    pub fn forget(&mut self, instance: &[NodeId]) {
        *self = Culling {
            enabled: self.enabled,
            instance: instance.to_vec(),
            ..Culling::default()
        };
    }

    /// Remember a node's size as drawn (canvas px).
    pub fn drawn(&mut self, id: NodeId, size: Vec2) {
        self.sizes.insert(id, size);
    }

    /// The node's rectangle on the canvas (canvas px), as last drawn.
    pub fn rect(&self, node: &NodeDoc) -> Rect {
        Rect::from_min_size(
            Pos2::new(node.pos.0 * SCALE, node.pos.1 * SCALE),
            self.sizes.get(&node.id).copied().unwrap_or(UNKNOWN_SIZE),
        )
    }

    /// The part of the canvas (canvas px) whose nodes snarl holds, for the
    /// canvas area `screen` seen through `to_global`.
    pub fn kept_area(to_global: egui::emath::TSTransform, screen: Rect) -> Rect {
        let view = to_global.inverse() * screen;
        view.expand(view.width().max(view.height()) * MARGIN)
    }

    /// Where pin `pin` of `node`, placed at `origin`, is on the canvas (canvas
    /// px): where it was last drawn relative to the node, else where a
    /// node's rows would put it.
    pub fn pin_at(
        &self,
        registry: &Registry,
        node: &NodeDoc,
        origin: Pos2,
        pin: &str,
        input: bool,
    ) -> Pos2 {
        if let Some(offset) = self.offsets.borrow().get(&node.id).and_then(|pins| {
            pins.iter()
                .find(|(name, is_input, _)| name == pin && *is_input == input)
                .map(|(_, _, offset)| *offset)
        }) {
            return origin + offset;
        }
        let def = registry.get(&node.type_name);
        let row = def
            .and_then(|d| {
                if input {
                    d.input_index(pin)
                } else {
                    d.output_index(pin)
                }
            })
            .unwrap_or(0);
        let x = if input { 0.0 } else { self.rect(node).width() };
        origin + Vec2::new(x, 30.0 + 20.0 * row as f32)
    }
}

/// The colour of a wire from output `pin` of `node`, as snarl draws it.
pub fn wire_color(registry: &Registry, node: &NodeDoc, pin: &str) -> egui::Color32 {
    registry
        .get(&node.type_name)
        .and_then(|d| d.outputs.iter().find(|p| p.name == pin))
        .map_or(egui::Color32::DARK_GRAY, |p| super::style::pin_color(p.ty))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_kept_area_is_the_view_and_a_margin_around_it() {
        let screen = Rect::from_min_size(Pos2::ZERO, Vec2::new(200.0, 100.0));
        // Zoomed out to a half: the view covers twice the canvas.
        let half = egui::emath::TSTransform::from_scaling(0.5);
        let kept = Culling::kept_area(half, screen);
        assert_eq!(kept.min, Pos2::new(-200.0, -200.0));
        assert_eq!(kept.max, Pos2::new(600.0, 400.0));
    }

    #[test]
    fn a_pin_is_where_it_was_drawn_else_on_its_row() {
        let registry = crate::nodes::registry();
        let mut c = Culling::default();
        let node = NodeDoc::new(1, "Multiply (Value)").at(10.0, 20.0);
        let origin = Pos2::new(30.0, 60.0);
        assert_eq!(
            c.pin_at(&registry, &node, origin, "Input 2", true),
            origin + Vec2::new(0.0, 50.0)
        );
        c.drawn(node.id, Vec2::new(100.0, 60.0));
        assert_eq!(
            c.pin_at(&registry, &node, origin, "Output", false),
            origin + Vec2::new(100.0, 30.0)
        );
        c.offsets.borrow_mut().insert(
            node.id,
            vec![("Output".into(), false, Vec2::new(96.0, 41.0))],
        );
        assert_eq!(
            c.pin_at(&registry, &node, origin, "Output", false),
            origin + Vec2::new(96.0, 41.0)
        );
    }
}
