//! Drawing previews: thumbnails in a node's body, the large preview of a
//! hovered pin or wire. Each asks for its preview only when it is drawn on
//! screen, so what is off screen is neither rendered nor scaled.

use egui::{Color32, Rect, Sense, Ui, Vec2};
use spreadlight_graph::{NodeId, PinType, ResourceKind};

use super::{
    CanvasPreviews, Channel, ChannelName, LARGE_POINTS, PreviewKey, PreviewOut, THUMB_POINTS,
    has_thumbnail,
};

/// The key of the preview of `pin` on the node at `path`.
fn key(
    previews: &CanvasPreviews,
    path: &[NodeId],
    pin: &str,
    ty: PinType,
    large: bool,
) -> PreviewKey {
    let channel =
        matches!(ty, PinType::Resource(ResourceKind::GBuffer)).then(|| previews.channel_of(path));
    PreviewKey {
        path: path.to_vec(),
        pin: pin.to_owned(),
        channel,
        large,
    }
}

/// Height over width of what the preview shows (16:9 until it is known).
fn aspect(out: Option<&PreviewOut>) -> f32 {
    out.and_then(|o| o.source)
        .map_or(9.0 / 16.0, |((w, h), _)| {
            (h as f32 / w.max(1) as f32).clamp(0.1, 1.0)
        })
}

/// Whether the node at `path` with output pins `outputs` shows thumbnails now.
pub fn shows_thumbnails(
    previews: &CanvasPreviews,
    path: &[NodeId],
    outputs: &[(&str, PinType)],
) -> bool {
    previews.settings.shows(previews.file.as_deref(), path)
        && outputs.iter().any(|(_, ty)| has_thumbnail(*ty))
}

/// A node's thumbnails, one per texture or G-buffer output, in its body.
pub fn thumbnails(
    ui: &mut Ui,
    previews: &mut CanvasPreviews,
    path: &[NodeId],
    outputs: &[(&str, PinType)],
) {
    ui.vertical(|ui| {
        for (pin, ty) in outputs.iter().filter(|(_, ty)| has_thumbnail(*ty)) {
            ui.push_id(pin, |ui| thumbnail(ui, previews, path, pin, *ty));
        }
    });
}

fn thumbnail(ui: &mut Ui, previews: &mut CanvasPreviews, path: &[NodeId], pin: &str, ty: PinType) {
    if matches!(ty, PinType::Resource(ResourceKind::GBuffer)) {
        let mut channel = previews.channel_of(path);
        egui::ComboBox::from_id_salt("channel")
            .width(THUMB_POINTS - 8.0)
            .selected_text(channel.channel().name())
            .show_ui(ui, |ui| {
                for (k, c) in Channel::ALL.iter().enumerate() {
                    ui.selectable_value(&mut channel, ChannelName(k), c.name());
                }
            });
        if channel != previews.channel_of(path) {
            previews.channels.insert(path.to_vec(), channel);
        }
    }
    let small = key(previews, path, pin, ty, false);
    let out = previews.outputs.get(&small).cloned();
    let size = Vec2::new(THUMB_POINTS, THUMB_POINTS * aspect(out.as_ref()));
    let (rect, response) = ui.allocate_exact_size(size, Sense::hover());
    // Off screen: nothing asked for, nothing drawn.
    if !ui.is_rect_visible(rect) {
        return;
    }
    let probe = response.hover_pos().map(|p| {
        let uv = (p - rect.min) / rect.size();
        (uv.x, uv.y)
    });
    let to_screen = ui
        .ctx()
        .layer_transform_to_global(ui.layer_id())
        .unwrap_or_default();
    previews.drawn.push((small.clone(), to_screen * rect));
    previews.want(small, probe);
    paint(ui, rect, out.as_ref());
    if response.hovered() {
        let large = key(previews, path, pin, ty, true);
        previews.want(large.clone(), None);
        let probed = out.as_ref().and_then(|o| o.value);
        response.on_hover_ui(|ui| {
            let out = previews.outputs.get(&large).cloned();
            let rect = large_image(ui, out.as_ref());
            record(ui, previews, large, rect);
            describe(ui, out.as_ref(), probed);
        });
    }
}

fn paint(ui: &Ui, rect: Rect, out: Option<&PreviewOut>) {
    let painter = ui.painter();
    match out.and_then(|o| o.target.as_ref()) {
        Some(target) => {
            let uv = Rect::from_min_max(egui::pos2(0.0, 0.0), egui::pos2(1.0, 1.0));
            painter.image(target.id, rect, uv, Color32::WHITE);
            if out.is_some_and(|o| o.note.is_some()) {
                // Refreshed at a low rate (its hover says why): an amber corner mark.
                let r = (rect.width() * 0.05).clamp(2.0, 5.0);
                let centre = rect.right_top() + Vec2::new(-r - 1.0, r + 1.0);
                painter.circle_filled(centre, r, Color32::from_rgb(230, 160, 40));
            }
        }
        None => {
            painter.rect_filled(rect, 2.0, Color32::from_gray(24));
            let text = out.and_then(|o| o.error.as_deref()).unwrap_or("…");
            painter.text(
                rect.center(),
                egui::Align2::CENTER_CENTER,
                text,
                egui::FontId::proportional(9.0),
                Color32::GRAY,
            );
        }
    }
}

/// Where a preview was drawn this frame, in screen points (the tests look there).
fn record(ui: &Ui, previews: &mut CanvasPreviews, key: PreviewKey, rect: Rect) {
    let to_screen = ui
        .ctx()
        .layer_transform_to_global(ui.layer_id())
        .unwrap_or_default();
    previews.drawn.push((key, to_screen * rect));
}

fn large_image(ui: &mut Ui, out: Option<&PreviewOut>) -> Rect {
    // A mesh's turntable is square and smaller.
    let width = if out.is_some_and(|o| o.mesh.is_some()) {
        LARGE_POINTS * 0.6
    } else {
        LARGE_POINTS
    };
    let size = Vec2::new(width, width * aspect(out));
    let (rect, _) = ui.allocate_exact_size(size, Sense::hover());
    paint(ui, rect, out);
    rect
}

/// The size, format, and the value probed under the pointer.
fn describe(ui: &mut Ui, out: Option<&PreviewOut>, probed: Option<((u32, u32), [f32; 4])>) {
    let Some(out) = out else {
        ui.weak("…");
        return;
    };
    if let Some(m) = out.mesh {
        ui.label(format!(
            "{} mesh{} · {} vertices · {} triangles",
            m.meshes,
            if m.meshes == 1 { "" } else { "es" },
            m.vertices,
            m.triangles
        ));
    }
    if let Some(((w, h), format)) = out.source {
        ui.label(format!("{w} × {h} · {format:?}"));
    }
    if let Some(((x, y), [r, g, b, a])) = probed.or(out.value) {
        ui.monospace(format!("({x}, {y}): {r:.3} {g:.3} {b:.3} {a:.3}"));
    }
    if let Some(note) = &out.note {
        ui.colored_label(Color32::from_rgb(230, 160, 40), note);
    }
    if let Some(e) = &out.error {
        ui.colored_label(Color32::LIGHT_RED, e);
    }
}

/// The large preview of output `pin` (of type `ty`) of the node at `path`,
/// inside a hover popup (a pin's or a wire's). Asks for it while shown.
pub fn large(ui: &mut Ui, previews: &mut CanvasPreviews, path: &[NodeId], pin: &str, ty: PinType) {
    let key = key(previews, path, pin, ty, true);
    previews.want(key.clone(), Some((0.5, 0.5)));
    let out = previews.outputs.get(&key).cloned();
    let rect = large_image(ui, out.as_ref());
    record(ui, previews, key, rect);
    describe(ui, out.as_ref(), None);
}
