//! Frames on the canvas: translucent rectangles with a title bar, painted
//! behind the nodes in canvas coordinates. Dragging the title bar moves the
//! frame and the nodes it holds (`app/organise.rs`).

use egui::{Align2, Color32, FontId, Painter, Pos2, Rect, Stroke, Vec2};
use spreadlight_graph::FrameDoc;

use crate::canvas_units::SCALE;

/// The title bar's height, in canvas points.
pub const TITLE_H: f32 = 22.0;

/// The frame's rectangle in canvas points (snarl's coordinates).
pub fn rect(frame: &FrameDoc) -> Rect {
    Rect::from_min_size(
        Pos2::new(frame.pos.0 * SCALE, frame.pos.1 * SCALE),
        Vec2::new(frame.size.0 * SCALE, frame.size.1 * SCALE),
    )
}

/// The title bar, where a drag moves the frame.
pub fn title_rect(frame: &FrameDoc) -> Rect {
    let r = rect(frame);
    Rect::from_min_size(r.min, Vec2::new(r.width(), TITLE_H.min(r.height())))
}

fn color(frame: &FrameDoc, alpha: u8) -> Color32 {
    let (r, g, b) = frame.color;
    Color32::from_rgba_unmultiplied(r, g, b, alpha)
}

/// Paint the frames (in canvas points), with `offset` added to frame `moving`.
pub fn paint(painter: &Painter, frames: &[FrameDoc], moving: Option<(usize, Vec2)>) {
    let text = painter.ctx().global_style().visuals.strong_text_color();
    for (i, f) in frames.iter().enumerate() {
        let d = match moving {
            Some((m, d)) if m == i => d,
            _ => Vec2::ZERO,
        };
        let r = rect(f).translate(d);
        if !painter.clip_rect().intersects(r) {
            continue;
        }
        painter.rect(
            r,
            4.0,
            color(f, 45),
            Stroke::new(1.5, color(f, 200)),
            egui::StrokeKind::Inside,
        );
        let bar = title_rect(f).translate(d);
        painter.rect_filled(bar, 4.0, color(f, 150));
        painter.text(
            bar.left_center() + Vec2::new(8.0, 0.0),
            Align2::LEFT_CENTER,
            &f.title,
            FontId::proportional(15.0),
            text,
        );
    }
}
