//! The wire under the pointer: hovering a wire shows what flows through it.

use egui::Pos2;

use super::pins::PinPositions;
use crate::model::EditorDoc;

/// The link under `pointer`, if one passes within `threshold` points of it:
/// wires are straight lines between the pins' drawn positions.
///
/// Only drawn wires can be under the pointer, and a wire is drawn only where
/// both its pins were: so the links looked at are those into the drawn input
/// pins (found by the document's index of links by input), not every link of
/// the patch. Hovering the canvas, which asks this every frame, costs what
/// the visible part of the patch costs, however big the patch is.
pub fn wire_under(
    doc: &EditorDoc,
    pins: &PinPositions,
    pointer: Pos2,
    threshold: f32,
) -> Option<spreadlight_graph::LinkDoc> {
    let pins = pins.borrow();
    pins.iter()
        .filter(|((_, _, input), _)| *input)
        .filter_map(|((node, name, _), &b)| {
            let l = doc.link_into(&spreadlight_graph::PinRef(*node, name.clone()))?;
            let a = *pins.get(&(l.from.node(), l.from.pin().to_owned(), false))?;
            let ab = b - a;
            let t = ((pointer - a).dot(ab) / ab.length_sq().max(1e-6)).clamp(0.0, 1.0);
            let d = (a + ab * t - pointer).length();
            (d < threshold).then_some((d, l))
        })
        // The nearest; a tie goes to the link listed first, whatever the map's order.
        .min_by(|x, y| {
            x.0.total_cmp(&y.0)
                .then_with(|| doc.link_position(x.1).cmp(&doc.link_position(y.1)))
        })
        .map(|(_, l)| l.clone())
}

#[cfg(test)]
mod tests {
    use super::*;
    use spreadlight_graph::{NodeDoc, NodeId, Patch};

    #[test]
    fn the_wire_under_the_pointer_is_the_nearest_within_reach() {
        let mut p = Patch::default();
        p.add(NodeDoc::new(1, "LFO"));
        p.add(NodeDoc::new(2, "Probe"));
        p.add(NodeDoc::new(3, "Probe"));
        p.link(1, "Output", 2, "Input");
        p.link(1, "Output", 3, "Input");
        let doc = EditorDoc::new(p);
        let pins = PinPositions::default();
        pins.borrow_mut()
            .insert((NodeId(1), "Output".into(), false), Pos2::new(0.0, 0.0));
        pins.borrow_mut()
            .insert((NodeId(2), "Input".into(), true), Pos2::new(100.0, 0.0));
        pins.borrow_mut()
            .insert((NodeId(3), "Input".into(), true), Pos2::new(100.0, 100.0));
        let hit = wire_under(&doc, &pins, Pos2::new(50.0, 3.0), 5.0).expect("a wire");
        assert_eq!(hit.to.node(), NodeId(2));
        let hit = wire_under(&doc, &pins, Pos2::new(50.0, 48.0), 5.0).expect("a wire");
        assert_eq!(hit.to.node(), NodeId(3));
        assert!(wire_under(&doc, &pins, Pos2::new(50.0, 20.0), 5.0).is_none());
        assert!(
            wire_under(&doc, &pins, Pos2::new(130.0, 0.0), 5.0).is_none(),
            "not past the pin"
        );
    }
}
