//! What the canvas and the tools that organise it (organise/, the
//! document's organising commands) share: the canvas's unit, what snarl
//! keeps per node, and the tag a bypassed node shows. Kept below both, so
//! the canvas can call the organising tools without them reaching back up.

use spreadlight_graph::NodeId;

/// Canvas pixels per patch canvas unit: patches are laid out on a coarse grid
/// (vvvv's nodes are small); snarl's nodes are larger.
pub const SCALE: f32 = 3.0;

/// What snarl stores per node: which document node it shows.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct CanvasNode(pub NodeId);

/// The tag a bypassed node shows in its header (its width is measured with the node's).
pub const BYPASS_TAG: &str = "bypassed";
