//! IOBoxes on the canvas as vvvv shows them: every slice of the value as a
//! row in the node, edited in place (drag, `−` to remove one, `+ slice` to
//! add); with the IOBox's input linked, the rows show the live value instead,
//! updating as the patch runs.

use egui::Ui;
use spreadlight_graph::{NodeId, PinRef, Registry, RuntimeSnapshot, Spread};

use crate::model::EditorDoc;
use crate::values;

/// More slices than this show as a count below the rows.
pub const MAX_ROWS: usize = 8;

/// Whether a node type is an IOBox (a constant value node with rows).
pub fn is_iobox(type_name: &str) -> bool {
    type_name.starts_with("IOBox (")
}

/// The IOBox's rows: its live value when its input is linked, else its value, editable.
pub fn rows(
    ui: &mut Ui,
    doc: &mut EditorDoc,
    registry: &Registry,
    runtime: &RuntimeSnapshot,
    path: &[NodeId],
) {
    let Some(&id) = path.last() else {
        return;
    };
    let Some(def) = doc
        .node(id)
        .and_then(|n| registry.get(&n.type_name))
        .cloned()
    else {
        return;
    };
    let Some(pin) = def.inputs.first() else {
        return;
    };
    if doc.link_into(&PinRef(id, pin.name.to_string())).is_some() {
        match runtime.output_at(path, "Output") {
            Some(live) => live_rows(ui, live),
            None => {
                ui.weak("not evaluated");
            }
        }
        return;
    }
    let Some(mut value) = doc.input_value(registry, id, &pin.name) else {
        return;
    };
    let edited = ui
        .push_id(("iobox", id), |ui| {
            values::edit_spread(ui, pin.ty, pin.range, &mut value, &pin.name, None)
        })
        .inner;
    if edited.changed {
        doc.set_value(id, &pin.name, Some(value), edited.continuing);
    }
}

fn live_rows(ui: &mut Ui, live: &Spread) {
    let n = live.len();
    for i in 0..n.min(MAX_ROWS) {
        ui.horizontal(|ui| {
            ui.weak(format!("{i}"));
            ui.monospace(slice_text(live, i));
        });
    }
    if n > MAX_ROWS {
        ui.weak(format!("… {} slices", n));
    } else if n == 0 {
        ui.weak("empty");
    }
}

/// One slice as a row shows it.
pub fn slice_text(spread: &Spread, i: usize) -> String {
    let f = |v: &[f32]| {
        v.iter()
            .map(|x| format!("{x:.3}"))
            .collect::<Vec<_>>()
            .join(", ")
    };
    match spread {
        Spread::Float(v) => format!("{:.3}", v[i]),
        Spread::Int(v) => v[i].to_string(),
        Spread::Bool(v) => v[i].to_string(),
        Spread::String(v) => v[i].clone(),
        Spread::Enum(v) => v[i].clone(),
        Spread::Vec2(v) => f(&v[i].to_array()),
        Spread::Vec3(v) => f(&v[i].to_array()),
        Spread::Vec4(v) => f(&v[i].to_array()),
        Spread::Color(v) => f(&v[i].to_vec4().to_array()),
        Spread::Mat4(_) => "transform".to_owned(),
        Spread::Resource(kind, _) => format!("{kind:?}"),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn rows_show_each_slice_in_its_own_terms() {
        let s = Spread::Float(vec![0.5, 1.25]);
        assert_eq!(slice_text(&s, 1), "1.250");
        let v = Spread::Vec3(vec![glam::Vec3::new(1.0, 2.0, 3.0)]);
        assert_eq!(slice_text(&v, 0), "1.000, 2.000, 3.000");
        assert!(is_iobox("IOBox (Value)") && !is_iobox("Inlet"));
    }
}
