//! The canvas's own state: snarl and its node ids, the selection, the view
//! and what the last frame drew (node rectangles, pins, the culling), kept
//! apart from the document it shows and the panels around it.

use std::collections::{BTreeSet, HashMap};

use egui::{LayerId, Pos2};
use egui_snarl::Snarl;
use spreadlight_graph::NodeId;

use super::FIT_FROM_SCRATCH;
use crate::canvas::{self, CanvasNode, PinPositions};

pub(super) struct CanvasState {
    pub(super) snarl: Snarl<CanvasNode>,
    pub(super) snarl_ids: HashMap<NodeId, egui_snarl::NodeId>,
    pub(super) selected: BTreeSet<NodeId>,
    pub(super) focused: Option<NodeId>,
    /// Where a Shift-drag selection rectangle started, while it is being drawn.
    pub(super) rect_select: Option<Pos2>,
    /// Fitting the view to the patch alternates measuring the nodes (even)
    /// and fitting them (odd) down to 0, twice: node sizes change with zoom
    /// (editors are left out when small), so one pass may not settle.
    pub(super) fit: u8,
    /// The nodes snarl drew last frame, on screen, in drawing order: what a
    /// click or the pointer can be over (the others lie outside the view,
    /// `canvas/cull.rs`). Every node's: [`super::EditorApp::node_screen_rects`].
    pub(super) node_rects: Vec<(NodeId, egui::Rect)>,
    /// The canvas's view last frame (canvas to screen).
    pub(super) view: Option<egui::emath::TSTransform>,
    /// The canvas's area on screen last frame.
    pub(super) rect: Option<egui::Rect>,
    /// Where each pin was drawn last frame.
    pub(super) pins: PinPositions,
    pub(super) layer: Option<LayerId>,
    pub(super) last_pointer: Pos2,
    /// The canvas draws the nodes near its view only (`canvas/cull.rs`).
    pub(super) culling: canvas::Culling,
}

impl CanvasState {
    pub(super) fn new() -> Self {
        CanvasState {
            snarl: Snarl::new(),
            snarl_ids: HashMap::new(),
            selected: BTreeSet::new(),
            focused: None,
            rect_select: None,
            fit: FIT_FROM_SCRATCH,
            node_rects: Vec::new(),
            view: None,
            rect: None,
            pins: PinPositions::default(),
            layer: None,
            last_pointer: Pos2::ZERO,
            culling: canvas::Culling::default(),
        }
    }

    /// Another document opens: nothing selected or drawn of the last, and
    /// the view fitted to the new one from scratch.
    pub(super) fn forget_document(&mut self) {
        self.selected.clear();
        self.snarl = Snarl::new();
        self.snarl_ids.clear();
        self.fit = FIT_FROM_SCRATCH;
    }

    /// The node the inspector shows: the last one clicked, while it is selected.
    pub(super) fn focus_node(&self) -> Option<NodeId> {
        self.focused
            .filter(|id| self.selected.contains(id))
            .or_else(|| self.selected.last().copied())
    }
}
