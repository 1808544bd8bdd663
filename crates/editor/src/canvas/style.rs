//! How the canvas looks: compact node rows, snarl's style, pin colours by
//! type, and the pin shape that records where it was drawn (the wire hit
//! test and the tests read those positions).

use egui::{Color32, Pos2, Rect, Stroke, Ui};
use egui_snarl::ui::{PinInfo, PinWireInfo, SnarlPin, SnarlStyle};
use spreadlight_graph::PinType;

use crate::zoom::ZOOM_RANGE;

pub use super::pins::{PinKey, PinPositions};

/// Spacing inside nodes: rows close together, as vvvv's nodes are (the text size is unchanged).
pub fn compact_spacing(ui: &mut Ui) {
    let s = ui.spacing_mut();
    s.item_spacing = egui::vec2(4.0, 1.0);
    s.interact_size = egui::vec2(28.0, 16.0);
    s.button_padding = egui::vec2(3.0, 0.0);
    s.combo_width = 64.0;
    s.icon_width = 12.0;
    s.icon_spacing = 2.0;
}

pub fn style() -> SnarlStyle {
    let window = egui::Style::default();
    SnarlStyle {
        // A tight frame and no collapse button: a node is as wide as its
        // title and its widest row need (vvvv's nodes are small).
        node_frame: Some(egui::Frame {
            inner_margin: egui::Margin::symmetric(4, 2),
            fill: window.visuals.window_fill,
            stroke: window.visuals.window_stroke,
            corner_radius: egui::CornerRadius::same(2),
            ..egui::Frame::NONE
        }),
        header_frame: Some(egui::Frame {
            inner_margin: egui::Margin::symmetric(4, 1),
            fill: Color32::TRANSPARENT,
            corner_radius: egui::CornerRadius::same(2),
            ..egui::Frame::NONE
        }),
        collapsible: Some(false),
        header_drag_space: Some(egui::vec2(2.0, 0.0)),
        pin_size: Some(8.0),
        // Double-click on the canvas opens the node browser, as in vvvv.
        centering: Some(false),
        // A patch opens at its real size, or smaller to fit; never blown up.
        max_scale: Some(*ZOOM_RANGE.end()),
        min_scale: Some(*ZOOM_RANGE.start()),
        // Straight wires, as vvvv draws them; also what `wire_under` hit-tests.
        wire_style: Some(egui_snarl::ui::WireStyle::Line),
        // The editor keeps its own selection (click, shift-click) and draws it
        // on the node frame; snarl's would be a second, different one.
        select_style: Some(egui_snarl::ui::SelectionStyle {
            margin: egui::Margin::ZERO,
            rounding: egui::CornerRadius::ZERO,
            fill: Color32::TRANSPARENT,
            stroke: Stroke::NONE,
        }),
        ..SnarlStyle::new()
    }
}

/// A pin's colour by its type (the legend, `organise/legend.rs`, lists them).
pub fn pin_color(ty: PinType) -> Color32 {
    match ty {
        PinType::Float | PinType::Int => Color32::from_rgb(160, 160, 160),
        PinType::Bool => Color32::from_rgb(220, 120, 120),
        PinType::String => Color32::from_rgb(200, 180, 120),
        PinType::Vec2 | PinType::Vec3 | PinType::Vec4 => Color32::from_rgb(120, 180, 220),
        PinType::Color => Color32::from_rgb(230, 140, 220),
        PinType::Mat4 => Color32::from_rgb(120, 220, 160),
        PinType::Enum(_) => Color32::from_rgb(200, 200, 120),
        PinType::Resource(_) => Color32::from_rgb(240, 160, 60),
        PinType::Any => Color32::WHITE,
    }
}

/// A pin that remembers where it was drawn.
pub struct RecordedPin {
    pub(super) info: PinInfo,
    pub(super) key: PinKey,
    pub(super) sink: PinPositions,
    /// Its node's position (canvas px) and where offsets from it are kept (`cull.rs`).
    pub(super) origin: Pos2,
    pub(super) offsets: super::pins::PinOffsets,
}

impl SnarlPin for RecordedPin {
    fn draw(
        self,
        snarl_style: &SnarlStyle,
        style: &egui::Style,
        rect: Rect,
        painter: &egui::Painter,
    ) -> PinWireInfo {
        let to_global = painter
            .ctx()
            .layer_transform_to_global(painter.layer_id())
            .unwrap_or_default();
        super::pins::record_pin(
            &self.offsets,
            self.key.0,
            &self.key.1,
            self.key.2,
            rect.center() - self.origin,
        );
        self.sink
            .borrow_mut()
            .insert(self.key, to_global * rect.center());
        self.info.draw(snarl_style, style, rect, painter)
    }
}
