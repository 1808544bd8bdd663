//! Keeping a patch in order: the node size measure, the layout, tidying
//! files, and on the canvas comments, frames, find, the gestures and the
//! pin-type legend. The document side of each edit is in `model/organise.rs`.

pub mod comments;
pub mod find;
pub mod frames;
pub mod gestures;
pub mod layout;
pub mod legend;
pub mod measure;
pub mod tidy;

use egui::{Id, Painter, Vec2};
use spreadlight_graph::Patch;

/// A comment or frame being dragged, and by how much so far (canvas points).
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Dragging {
    Comment(usize, Vec2),
    Frame(usize, Vec2),
}

fn dragging_id() -> Id {
    Id::new("spreadlight-annotation-drag")
}

/// The drag in progress: the canvas paints it there until it ends (the
/// document changes once, when it ends).
pub fn dragging(ctx: &egui::Context) -> Option<Dragging> {
    ctx.data(|d| d.get_temp(dragging_id()))
}

pub fn set_dragging(ctx: &egui::Context, drag: Option<Dragging>) {
    ctx.data_mut(|d| match drag {
        Some(drag) => {
            d.insert_temp(dragging_id(), drag);
        }
        None => d.remove::<Dragging>(dragging_id()),
    });
}

/// Frames, then comments, behind the nodes (called from the canvas's background).
pub fn paint_annotations(painter: &Painter, patch: &Patch) {
    let drag = dragging(painter.ctx());
    let frame = match drag {
        Some(Dragging::Frame(i, d)) => Some((i, d)),
        _ => None,
    };
    let comment = match drag {
        Some(Dragging::Comment(i, d)) => Some((i, d)),
        _ => None,
    };
    frames::paint(painter, &patch.frames, frame);
    comments::paint(painter, &patch.comments, comment);
}
