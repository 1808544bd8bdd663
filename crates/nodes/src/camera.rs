//! (being written)
use spreadlight_graph::Registry;
pub fn register(_: &mut Registry) {}
