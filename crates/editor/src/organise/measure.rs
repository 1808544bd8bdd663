//! How big a node, a comment and a frame title are on the canvas, without
//! drawing them: the layout, the tidiness test of the shipped patches and the
//! canvas (fitting the view to comments, jumping to a found node) all ask
//! here. The estimate errs large: a node drawn is never bigger than measured
//! (`tests/organise.rs` checks it against the drawn nodes of a real patch).

use std::collections::BTreeSet;

use spreadlight_graph::{NodeDoc, Patch, PinType, Registry, Spread};

use crate::canvas_units::SCALE;

/// Width of one character of egui's body text (12.5 points), generously.
pub const CHAR_W: f32 = 7.2;
/// One pin row: a value editor's height and the spacing under it.
pub const ROW_H: f32 = 19.0;
/// The title row with its frame.
pub const HEADER_H: f32 = 24.0;
/// A comment's line of body text.
pub const LINE_H: f32 = 17.0;

/// The size of `node` drawn at zoom 1, in canvas units (as `NodeDoc::pos`).
/// A type the registry lacks (a subpatch file not found, say) is sized from
/// the pins its links and values name.
pub fn node_size(node: &NodeDoc, registry: &Registry, patch: &Patch) -> (f32, f32) {
    let (w, h) = node_points(node, registry, patch);
    (w / SCALE, h / SCALE)
}

fn text_w(text: &str) -> f32 {
    text.chars().count() as f32 * CHAR_W
}

/// What a compact value editor takes on the node (`values::edit_first`).
fn editor_w(ty: PinType, value: Option<&Spread>) -> f32 {
    let float = |x: f32| text_w(format!("{x:.4}").trim_end_matches('0')) + 16.0;
    let number = |x: f32| float(x).max(text_w(&format!("{x:.2}")) + 16.0).max(32.0);
    if let Some(v) = value {
        if v.len() > 1 {
            return text_w(&format!("{} slices", v.len()));
        }
        if v.is_empty() {
            return text_w("empty");
        }
    }
    match (ty, value) {
        (PinType::Float, Some(Spread::Float(v))) => number(v[0]),
        (PinType::Int, Some(Spread::Int(v))) => text_w(&v[0].to_string()).max(16.0) + 16.0,
        (PinType::Bool, _) => 20.0,
        (PinType::String, _) => 72.0,
        (PinType::Vec2 | PinType::Vec3 | PinType::Vec4, Some(v)) => {
            let comps: Vec<f32> = match v {
                Spread::Vec2(v) => v[0].to_array().to_vec(),
                Spread::Vec3(v) => v[0].to_array().to_vec(),
                Spread::Vec4(v) => v[0].to_array().to_vec(),
                _ => vec![0.0; 4],
            };
            comps.iter().map(|&x| number(x) + 4.0).sum()
        }
        (PinType::Color, _) => 40.0,
        (PinType::Mat4, _) => text_w("transform"),
        (PinType::Enum(def), Some(Spread::Enum(v))) => {
            let longest = def.options.iter().map(|o| text_w(o)).fold(0.0, f32::max);
            text_w(&v[0]).max(longest.min(64.0)) + 28.0
        }
        (PinType::Resource(kind), _) => text_w(&format!("{kind:?}")),
        (PinType::Float | PinType::Int, _) => 48.0,
        (PinType::Vec2, _) => 2.0 * 52.0,
        (PinType::Vec3, _) => 3.0 * 52.0,
        (PinType::Vec4, _) => 4.0 * 52.0,
        _ => 64.0,
    }
}

fn node_points(node: &NodeDoc, registry: &Registry, patch: &Patch) -> (f32, f32) {
    let tag = if node.bypass {
        text_w(crate::canvas_units::BYPASS_TAG) + 4.0
    } else {
        0.0
    };
    let title = text_w(&node.type_name) + 16.0 + tag;
    let Some(def) = registry.get(&node.type_name) else {
        // Pins known only from the document: names, no editors.
        let inputs: BTreeSet<&str> = patch
            .links
            .iter()
            .filter(|l| l.to.node() == node.id)
            .map(|l| l.to.pin())
            .chain(node.values.keys().map(String::as_str))
            .collect();
        let outputs: BTreeSet<&str> = patch
            .links
            .iter()
            .filter(|l| l.from.node() == node.id)
            .map(|l| l.from.pin())
            .collect();
        let col = |pins: &BTreeSet<&str>| pins.iter().map(|p| text_w(p)).fold(0.0, f32::max);
        let w = (col(&inputs) + col(&outputs) + 48.0).max(title) + 8.0;
        let rows = inputs.len().max(outputs.len()) as f32;
        return (w, HEADER_H + rows * ROW_H + 8.0);
    };
    let iobox = crate::iobox::is_iobox(&def.name);
    let inputs = def
        .inputs
        .iter()
        .map(|p| {
            let editor = if iobox || !crate::values::editable(p.ty) {
                0.0
            } else {
                let value = node.values.get(&*p.name).unwrap_or(&p.default);
                editor_w(p.ty, Some(value)) + 4.0
            };
            12.0 + text_w(&p.name) + 4.0 + editor
        })
        .fold(0.0, f32::max);
    let outputs = def
        .outputs
        .iter()
        .map(|p| 6.0 + text_w(&p.name) + 14.0)
        .fold(0.0, f32::max);
    let rows = def.inputs.len().max(def.outputs.len()) as f32;
    let mut w = (inputs + outputs + 16.0).max(title) + 8.0;
    let mut h = HEADER_H + rows * ROW_H + 8.0;
    if iobox {
        // The body edits every slice in a row: its index, an editor and `−`,
        // then `+ slice` (up to the rows shown).
        let slices = def
            .inputs
            .first()
            .map_or(1, |p| node.values.get(&*p.name).unwrap_or(&p.default).len());
        let shown = slices.clamp(1, crate::iobox::MAX_ROWS) as f32;
        let ty = def.inputs.first().map_or(PinType::Float, |p| p.ty);
        let body = shown * (editor_w(ty, None) + 50.0) + 70.0;
        w = w.max(inputs + body + outputs + 24.0);
        h += 2.0 * ROW_H;
    }
    (w, h)
}

/// How a comment's line is drawn: its text size relative to the body, and
/// its text without the markup that says so (`# `, `## `, `- `). Here, with
/// the measures, so drawing a comment (comments.rs) and measuring it share it.
pub fn line_style(line: &str) -> (f32, &str) {
    if let Some(rest) = line.strip_prefix("## ") {
        (1.25, rest)
    } else if let Some(rest) = line.strip_prefix("# ") {
        (1.5, rest)
    } else if let Some(rest) = line.strip_prefix("- ").or_else(|| line.strip_prefix("* ")) {
        // The bullet takes the two characters the markup did.
        (1.0, rest)
    } else {
        (1.0, line)
    }
}

/// A comment's size in canvas units, as `organise::comments` draws it at zoom 1.
pub fn comment_size(text: &str) -> (f32, f32) {
    let mut w: f32 = 40.0;
    let mut h = 8.0;
    for line in text.lines() {
        let (scale, body) = line_style(line);
        w = w.max(text_w(body) * scale + 16.0);
        h += LINE_H * scale;
    }
    (w / SCALE, h / SCALE)
}

/// Whether two rectangles given as (pos, size) overlap (touching is not overlapping).
pub fn overlaps(a: ((f32, f32), (f32, f32)), b: ((f32, f32), (f32, f32))) -> bool {
    let ((ax, ay), (aw, ah)) = a;
    let ((bx, by), (bw, bh)) = b;
    ax < bx + bw && bx < ax + aw && ay < by + bh && by < ay + ah
}

/// Every pair of nodes of `patch` (not of its subpatches) whose measured rectangles overlap.
pub fn overlapping_nodes(
    patch: &Patch,
    registry: &Registry,
) -> Vec<(spreadlight_graph::NodeId, spreadlight_graph::NodeId)> {
    let rects: Vec<_> = patch
        .nodes
        .iter()
        .map(|n| (n.id, (n.pos, node_size(n, registry, patch))))
        .collect();
    let mut found = Vec::new();
    for (i, a) in rects.iter().enumerate() {
        for b in &rects[i + 1..] {
            if overlaps(a.1, b.1) {
                found.push((a.0, b.0));
            }
        }
    }
    found
}
