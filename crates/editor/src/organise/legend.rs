//! The pin-type legend: which colour and shape stands for which pin type,
//! from the same colours the canvas draws pins with.

use egui::{Color32, Ui};
use spreadlight_graph::{PinType, ResourceKind};

use crate::canvas::pin_color;

/// Any enum: the colour does not depend on which.
static LEGEND_ENUM: spreadlight_graph::EnumDef = spreadlight_graph::EnumDef {
    name: "",
    options: &[],
};

/// The legend's rows: a pin colour, whether the pin is square (a GPU resource), and the types.
pub fn rows() -> Vec<(Color32, bool, &'static str)> {
    vec![
        (pin_color(PinType::Float), false, "Float, Int"),
        (pin_color(PinType::Bool), false, "Bool"),
        (pin_color(PinType::String), false, "String"),
        (pin_color(PinType::Vec3), false, "Vec2, Vec3, Vec4"),
        (pin_color(PinType::Color), false, "Color"),
        (pin_color(PinType::Mat4), false, "Transform (Mat4)"),
        (
            pin_color(PinType::Enum(&LEGEND_ENUM)),
            false,
            "Enum (a choice)",
        ),
        (
            pin_color(PinType::Resource(ResourceKind::Texture)),
            true,
            "GPU resource: texture, mesh, buffer, G-buffer",
        ),
        (pin_color(PinType::Any), false, "Any"),
    ]
}

/// Draw the legend's rows.
pub fn show(ui: &mut Ui) {
    for (color, square, text) in rows() {
        ui.horizontal(|ui| {
            let (r, _) = ui.allocate_exact_size(egui::vec2(10.0, 10.0), egui::Sense::hover());
            if square {
                ui.painter().rect_filled(r, 0.0, color);
            } else {
                ui.painter().circle_filled(r.center(), 5.0, color);
            }
            ui.label(text);
        });
    }
}
