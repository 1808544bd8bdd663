//! Editors for input values: drag values for numbers, colour pickers, vector
//! editors, enum drop-downs, paths, and whole spreads in the inspector.

use egui::{DragValue, Ui};
use glam::{Mat4, Vec2, Vec3, Vec4};
use spreadlight_graph::{Color, PinType, Spread};

/// What an edit did this frame.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct Edited {
    pub changed: bool,
    /// The edit continues a drag begun earlier: merge it into the last undo step.
    pub continuing: bool,
}

/// Name the widget after its pin's label, for screen readers and for tests that find it by name.
fn track(resp: egui::Response, label: Option<egui::Id>) -> Edited {
    let resp = match label {
        Some(id) => resp.labelled_by(id),
        None => resp,
    };
    Edited::from(&resp)
}

impl Edited {
    fn from(resp: &egui::Response) -> Self {
        Edited {
            changed: resp.changed(),
            continuing: resp.dragged() && !resp.drag_started(),
        }
    }

    fn or(self, other: Edited) -> Edited {
        Edited {
            changed: self.changed || other.changed,
            continuing: self.continuing || other.continuing,
        }
    }
}

/// Whether pins of this type have an editor (resources only come through links).
pub fn editable(ty: PinType) -> bool {
    !matches!(ty, PinType::Resource(_) | PinType::Any)
}

/// Whether a string pin names a file, so it gets a file picker.
pub fn is_path_pin(name: &str) -> bool {
    let lower = name.to_lowercase();
    ["file", "path", "filename"]
        .iter()
        .any(|w| lower.contains(w))
}

/// A pin's range (its `PinDef::range`), which number editors stay within.
pub type Range = Option<(f64, f64)>;

/// Hold slice `i`'s numbers to `range` (what was typed past an end, say).
pub fn clamp_slice(spread: &mut Spread, i: usize, range: Range) {
    let Some((lo, hi)) = range else {
        return;
    };
    let f = |v: &mut f32| *v = (f64::from(*v)).clamp(lo, hi) as f32;
    match spread {
        Spread::Float(v) => f(&mut v[i]),
        Spread::Int(v) => v[i] = (v[i] as f64).clamp(lo, hi) as i64,
        Spread::Vec2(v) => v[i].as_mut().iter_mut().for_each(f),
        Spread::Vec3(v) => v[i].as_mut().iter_mut().for_each(f),
        Spread::Vec4(v) => v[i].as_mut().iter_mut().for_each(f),
        _ => {}
    }
}

/// A compact editor for slice 0, for use on the node itself.
pub fn edit_first(
    ui: &mut Ui,
    ty: PinType,
    range: Range,
    spread: &mut Spread,
    label: Option<egui::Id>,
) -> Edited {
    if spread.len() > 1 {
        ui.weak(format!("{} slices", spread.len()));
        return Edited::default();
    }
    if spread.is_empty() {
        ui.weak("empty");
        return Edited::default();
    }
    edit_slice(ui, ty, range, spread, 0, true, label)
}

/// The inspector's editor: every slice, with add and remove.
pub fn edit_spread(
    ui: &mut Ui,
    ty: PinType,
    range: Range,
    spread: &mut Spread,
    pin_name: &str,
    label: Option<egui::Id>,
) -> Edited {
    let mut edited = Edited::default();
    let mut remove = None;
    for i in 0..spread.len() {
        ui.horizontal(|ui| {
            ui.weak(format!("{i}"));
            edited = edited.or(edit_slice(ui, ty, range, spread, i, false, label));
            if matches!(spread, Spread::String(_))
                && is_path_pin(pin_name)
                && ui.small_button("Browse…").clicked()
            {
                ui.ctx().data_mut(|d| {
                    d.insert_temp(
                        egui::Id::new("file-picker-request"),
                        (pin_name.to_owned(), i),
                    )
                });
            }
            if ui
                .small_button("−")
                .on_hover_text("remove this slice")
                .clicked()
            {
                remove = Some(i);
            }
        });
    }
    if let Some(i) = remove {
        remove_slice(spread, i);
        edited.changed = true;
    }
    if ui
        .small_button("+ slice")
        .on_hover_text("append a slice (a copy of the last one)")
        .clicked()
    {
        add_slice(spread, ty);
        edited.changed = true;
    }
    edited
}

fn edit_f32(
    ui: &mut Ui,
    v: &mut f32,
    range: Range,
    compact: bool,
    label: Option<egui::Id>,
) -> Edited {
    let speed = (v.abs() * 0.01).max(0.001);
    let mut dv = DragValue::new(v).speed(speed).max_decimals(4);
    if let Some((lo, hi)) = range {
        dv = dv.range(lo..=hi);
    }
    if compact {
        dv = dv.min_decimals(2);
    }
    track(ui.add(dv), label)
}

fn edit_vec(
    ui: &mut Ui,
    v: &mut [f32],
    range: Range,
    compact: bool,
    label: Option<egui::Id>,
) -> Edited {
    let mut e = Edited::default();
    for x in v.iter_mut() {
        e = e.or(edit_f32(ui, x, range, compact, label));
    }
    e
}

fn edit_slice(
    ui: &mut Ui,
    ty: PinType,
    range: Range,
    spread: &mut Spread,
    i: usize,
    compact: bool,
    label: Option<egui::Id>,
) -> Edited {
    let edited = edit_slice_unclamped(ui, ty, range, spread, i, compact, label);
    if edited.changed {
        clamp_slice(spread, i, range);
    }
    edited
}

fn edit_slice_unclamped(
    ui: &mut Ui,
    ty: PinType,
    range: Range,
    spread: &mut Spread,
    i: usize,
    compact: bool,
    label: Option<egui::Id>,
) -> Edited {
    match spread {
        Spread::Float(v) => edit_f32(ui, &mut v[i], range, compact, label),
        Spread::Int(v) => {
            let mut dv = DragValue::new(&mut v[i]).speed(0.1);
            if let Some((lo, hi)) = range {
                dv = dv.range(lo..=hi);
            }
            track(ui.add(dv), label)
        }
        Spread::Bool(v) => track(ui.checkbox(&mut v[i], ""), label),
        Spread::String(v) => {
            let width = if compact { 64.0 } else { 160.0 };
            track(
                ui.add(egui::TextEdit::singleline(&mut v[i]).desired_width(width)),
                label,
            )
        }
        Spread::Vec2(v) => {
            let mut a = v[i].to_array();
            let e = edit_vec(ui, &mut a, range, compact, label);
            v[i] = Vec2::from_array(a);
            e
        }
        Spread::Vec3(v) => {
            let mut a = v[i].to_array();
            let e = edit_vec(ui, &mut a, range, compact, label);
            v[i] = Vec3::from_array(a);
            e
        }
        Spread::Vec4(v) => {
            let mut a = v[i].to_array();
            let e = edit_vec(ui, &mut a, range, compact, label);
            v[i] = Vec4::from_array(a);
            e
        }
        Spread::Color(v) => {
            // Our colours are linear RGBA, as egui's float colour editor expects.
            let c = v[i];
            let mut rgba = [c.r, c.g, c.b, c.a];
            let e = track(ui.color_edit_button_rgba_unmultiplied(&mut rgba), label);
            v[i] = Color::rgba(rgba[0], rgba[1], rgba[2], rgba[3]);
            e
        }
        Spread::Mat4(v) => {
            if compact {
                ui.weak("transform");
                return Edited::default();
            }
            let mut a = v[i].to_cols_array();
            let mut e = Edited::default();
            ui.vertical(|ui| {
                for row in 0..4 {
                    ui.horizontal(|ui| {
                        for col in 0..4 {
                            e = e.or(edit_f32(ui, &mut a[col * 4 + row], None, false, label));
                        }
                    });
                }
            });
            v[i] = Mat4::from_cols_array(&a);
            e
        }
        Spread::Enum(v) => {
            let PinType::Enum(def) = ty else {
                ui.label(&v[i]);
                return Edited::default();
            };
            let mut changed = false;
            let id = ui.next_auto_id();
            let combo = egui::ComboBox::from_id_salt(id)
                .selected_text(v[i].clone())
                .show_ui(ui, |ui| {
                    for option in def.options {
                        if ui.selectable_label(v[i] == *option, *option).clicked()
                            && v[i] != *option
                        {
                            v[i] = (*option).to_owned();
                            changed = true;
                        }
                    }
                });
            track(combo.response, label);
            Edited {
                changed,
                continuing: false,
            }
        }
        Spread::Resource(kind, _) => {
            ui.weak(format!("{kind:?}"));
            Edited::default()
        }
    }
}

fn remove_slice(spread: &mut Spread, i: usize) {
    fn rm<T>(v: &mut Vec<T>, i: usize) {
        if i < v.len() {
            v.remove(i);
        }
    }
    match spread {
        Spread::Float(v) => rm(v, i),
        Spread::Int(v) => rm(v, i),
        Spread::Bool(v) => rm(v, i),
        Spread::String(v) => rm(v, i),
        Spread::Vec2(v) => rm(v, i),
        Spread::Vec3(v) => rm(v, i),
        Spread::Vec4(v) => rm(v, i),
        Spread::Color(v) => rm(v, i),
        Spread::Mat4(v) => rm(v, i),
        Spread::Enum(v) => rm(v, i),
        Spread::Resource(_, v) => rm(v, i),
    }
}

/// Append a copy of the last slice, or a neutral value when the spread is empty.
pub fn add_slice(spread: &mut Spread, ty: PinType) {
    fn push<T: Clone>(v: &mut Vec<T>, fallback: T) {
        let next = v.last().cloned().unwrap_or(fallback);
        v.push(next);
    }
    match spread {
        Spread::Float(v) => push(v, 0.0),
        Spread::Int(v) => push(v, 0),
        Spread::Bool(v) => push(v, false),
        Spread::String(v) => push(v, String::new()),
        Spread::Vec2(v) => push(v, Vec2::ZERO),
        Spread::Vec3(v) => push(v, Vec3::ZERO),
        Spread::Vec4(v) => push(v, Vec4::ZERO),
        Spread::Color(v) => push(v, Color::WHITE),
        Spread::Mat4(v) => push(v, Mat4::IDENTITY),
        Spread::Enum(v) => {
            let first = match ty {
                PinType::Enum(def) => def.options.first().map(|o| (*o).to_owned()),
                _ => None,
            };
            if let Some(o) = v.last().cloned().or(first) {
                v.push(o);
            }
        }
        Spread::Resource(..) => {}
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn slices_are_added_as_copies_and_removed_by_index() {
        let mut s = Spread::Float(vec![1.0, 2.0]);
        add_slice(&mut s, PinType::Float);
        assert_eq!(s, Spread::Float(vec![1.0, 2.0, 2.0]));
        remove_slice(&mut s, 0);
        assert_eq!(s, Spread::Float(vec![2.0, 2.0]));
        let mut e = Spread::Color(vec![]);
        add_slice(&mut e, PinType::Color);
        assert_eq!(e, Spread::Color(vec![Color::WHITE]));
    }

    #[test]
    fn path_pins_are_recognised_by_name() {
        assert!(is_path_pin("Filename"));
        assert!(is_path_pin("File Path"));
        assert!(!is_path_pin("Name"));
    }
}

#[cfg(test)]
mod range_tests {
    use super::clamp_slice;
    use spreadlight_graph::Spread;

    #[test]
    fn an_edited_slice_is_held_to_its_pins_range() {
        let mut floats = Spread::Float(vec![-3.0, 40.0]);
        clamp_slice(&mut floats, 1, Some((0.0, 32.0)));
        clamp_slice(&mut floats, 0, Some((0.0, 32.0)));
        assert_eq!(floats, Spread::Float(vec![0.0, 32.0]));
        let mut ints = Spread::Int(vec![12]);
        clamp_slice(&mut ints, 0, Some((1.0, 8.0)));
        assert_eq!(ints, Spread::Int(vec![8]));
        let mut open = Spread::Vec2(vec![glam::Vec2::new(-5.0, 1e9)]);
        clamp_slice(&mut open, 0, Some((0.0, f64::INFINITY)));
        assert_eq!(open, Spread::Vec2(vec![glam::Vec2::new(0.0, 1e9)]));
        let mut free = Spread::Float(vec![1e9]);
        clamp_slice(&mut free, 0, None);
        assert_eq!(free, Spread::Float(vec![1e9]));
    }
}
