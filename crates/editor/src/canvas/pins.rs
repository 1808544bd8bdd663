//! Where the canvas drew its pins: the keys and the records the pin shape
//! writes as it draws (style.rs) and the culling reads (cull.rs), below both.

use std::cell::RefCell;
use std::collections::HashMap;
use std::rc::Rc;

use egui::{Pos2, Vec2};
use spreadlight_graph::NodeId;

/// A pin on the canvas, by node and name: `true` for inputs.
pub type PinKey = (NodeId, String, bool);

/// Where each pin was drawn this frame, in screen points (tests drag between them).
pub type PinPositions = Rc<RefCell<HashMap<PinKey, Pos2>>>;

/// Where a node's pins were drawn, relative to the node's position (canvas px).
pub type PinOffsets = Rc<RefCell<HashMap<NodeId, Vec<(String, bool, Vec2)>>>>;

/// Record where a pin was drawn (`offset` from its node's position), keeping
/// one entry per pin so a frame allocates nothing for pins seen before.
pub fn record_pin(offsets: &PinOffsets, node: NodeId, pin: &str, input: bool, offset: Vec2) {
    let mut offsets = offsets.borrow_mut();
    let pins = offsets.entry(node).or_default();
    match pins
        .iter_mut()
        .find(|(name, is_input, _)| name == pin && *is_input == input)
    {
        Some(entry) => entry.2 = offset,
        None => pins.push((pin.to_owned(), input, offset)),
    }
}
