//! The canvas's zoom: fitting a patch into view without going below a
//! readable zoom, and zooming around a point (the wheel, at the pointer).

use egui::{Pos2, Rect};
use spreadlight_graph::NodeId;

/// The smallest zoom fitting goes to: below it node titles would be too
/// small to read (at egui's 12.5-point body text, 0.75 keeps them above 9
/// points); a patch too big to fit at it is shown from its top left instead.
pub const READABLE_ZOOM: f32 = 0.75;

/// The zoom limits of the canvas (snarl's style says the same).
pub(crate) const ZOOM_RANGE: std::ops::RangeInclusive<f32> = 0.1..=1.0;

/// `view` zoomed by `factor` around the screen point `pivot` (which stays
/// where it is), within the canvas's zoom range.
pub fn zoom_around(
    view: egui::emath::TSTransform,
    pivot: Pos2,
    factor: f32,
) -> egui::emath::TSTransform {
    let scaling = (view.scaling * factor).clamp(*ZOOM_RANGE.start(), *ZOOM_RANGE.end());
    let factor = scaling / view.scaling;
    let around = egui::emath::TSTransform::from_translation(pivot.to_vec2())
        * egui::emath::TSTransform::from_scaling(factor)
        * egui::emath::TSTransform::from_translation(-pivot.to_vec2());
    around * view
}

/// The view that shows the whole patch at the largest zoom up to real size,
/// but never below `floor` ([`READABLE_ZOOM`] unless asked otherwise: `edit
/// --min-zoom`, to bring a whole patch on screen for a measurement).
pub fn fit_view(
    to_global: egui::emath::TSTransform,
    node_rects: &[(NodeId, Rect)],
    canvas: Rect,
    floor: f32,
) -> Option<egui::emath::TSTransform> {
    let from_global = to_global.inverse();
    let bb = node_rects
        .iter()
        .map(|(_, r)| from_global * *r)
        .reduce(|a, b| a.union(b))?
        .expand(20.0);
    let scale = (canvas.width() / bb.width())
        .min(canvas.height() / bb.height())
        .clamp(floor.clamp(*ZOOM_RANGE.start(), 1.0), 1.0);
    let fits =
        bb.width() * scale <= canvas.width() + 0.5 && bb.height() * scale <= canvas.height() + 0.5;
    // Patches too big to fit readably start at their top left, where patches begin.
    let anchor = if fits {
        canvas.center().to_vec2() - bb.center().to_vec2() * scale
    } else {
        canvas.min.to_vec2() - bb.min.to_vec2() * scale
    };
    Some(egui::emath::TSTransform::new(anchor, scale))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_fitted_view_holds_every_node_at_most_at_real_size_and_never_below_readable() {
        let canvas = Rect::from_min_size(Pos2::new(10.0, 30.0), egui::vec2(800.0, 600.0));
        let view = egui::emath::TSTransform::new(egui::vec2(5.0, 7.0), 0.5);
        let rects = vec![
            (
                NodeId(1),
                Rect::from_min_size(Pos2::new(-100.0, 0.0), egui::vec2(100.0, 50.0)),
            ),
            (
                NodeId(2),
                Rect::from_min_size(Pos2::new(300.0, 250.0), egui::vec2(100.0, 50.0)),
            ),
        ];
        let fit = fit_view(view, &rects, canvas, READABLE_ZOOM).expect("a view");
        assert!(fit.scaling >= READABLE_ZOOM, "readable: {}", fit.scaling);
        let back = fit * view.inverse();
        for (_, r) in &rects {
            assert!(canvas.contains_rect(back * *r), "{r:?} -> {:?}", back * *r);
        }
        // Too big to fit readably: readable zoom, top left node at the canvas's top left.
        let mut far = rects.clone();
        far.push((
            NodeId(3),
            Rect::from_min_size(Pos2::new(5000.0, 3000.0), egui::vec2(100.0, 50.0)),
        ));
        let fit = fit_view(view, &far, canvas, READABLE_ZOOM).expect("a view");
        assert_eq!(fit.scaling, READABLE_ZOOM);
        let top_left = fit * view.inverse() * far[0].1.min;
        assert!(canvas.contains(top_left), "{top_left:?}");
        let small = vec![(
            NodeId(1),
            Rect::from_min_size(Pos2::ZERO, egui::vec2(10.0, 10.0)),
        )];
        assert_eq!(
            fit_view(view, &small, canvas, READABLE_ZOOM)
                .expect("view")
                .scaling,
            1.0,
            "never blown up"
        );
        assert!(fit_view(view, &[], canvas, READABLE_ZOOM).is_none());
    }

    #[test]
    fn zooming_keeps_the_point_under_the_pointer_in_place() {
        let view = egui::emath::TSTransform::new(egui::vec2(30.0, -12.0), 0.5);
        let pivot = Pos2::new(200.0, 150.0);
        let under = view.inverse() * pivot;
        let zoomed = zoom_around(view, pivot, 1.5);
        assert!((zoomed.scaling - 0.75).abs() < 1e-6);
        assert!(
            (zoomed * under - pivot).length() < 1e-3,
            "the pivot stays put"
        );
        assert_eq!(
            zoom_around(view, pivot, 100.0).scaling,
            1.0,
            "never past real size"
        );
    }
}
