//! The patch document: what the user made and saved. Pure data.
//!
//! The document is never "fixed up" on load: a link to a missing pin, a node
//! type this build does not know, a value of the wrong type all stay in it as
//! they were written, so saving gives back everything that was loaded. The
//! running network is derived from it ([`crate::network`]) and the problems
//! are reported there.

use std::collections::BTreeMap;
use std::fmt;

use serde::{Deserialize, Serialize};

use crate::organise::{CommentDoc, FrameDoc};
use crate::spread::Spread;

/// The format version this build writes; it reads this one and every older one.
///
/// Version 2 added inline subpatch definitions (`subpatches`); version 3 added
/// comments, frames and bypassed nodes (`crate::organise`). An older file reads
/// unchanged and is written back at its own version while it uses nothing newer.
pub const FORMAT_VERSION: u32 = 3;

/// The first version whose files may define subpatches inline.
pub const SUBPATCH_VERSION: u32 = 2;

/// The first version whose files may hold comments, frames and bypassed nodes.
pub const ORGANISE_VERSION: u32 = 3;

/// A node's id: stable for the node's life, unique within its patch.
#[derive(Clone, Copy, Debug, PartialEq, Eq, PartialOrd, Ord, Hash, Serialize, Deserialize)]
#[serde(transparent)]
pub struct NodeId(pub u32);

impl fmt::Display for NodeId {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "#{}", self.0)
    }
}

#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct NodeDoc {
    pub id: NodeId,
    /// The node type's name, e.g. `Add (Value)`.
    #[serde(rename = "type")]
    pub type_name: String,
    /// Position on the canvas, in canvas units.
    #[serde(default)]
    pub pos: (f32, f32),
    /// Input values that differ from the pin defaults, by pin name.
    #[serde(default, skip_serializing_if = "BTreeMap::is_empty")]
    pub values: BTreeMap<String, Spread>,
    /// Bypassed: the node does not run; its first input passes to its first
    /// output of the same type and its other outputs are empty (`crate::runtime`).
    #[serde(default, skip_serializing_if = "is_false")]
    pub bypass: bool,
}

fn is_false(b: &bool) -> bool {
    !*b
}

impl NodeDoc {
    pub fn new(id: u32, type_name: &str) -> Self {
        NodeDoc {
            id: NodeId(id),
            type_name: type_name.to_owned(),
            pos: (0.0, 0.0),
            values: BTreeMap::new(),
            bypass: false,
        }
    }

    pub fn at(mut self, x: f32, y: f32) -> Self {
        self.pos = (x, y);
        self
    }

    pub fn with(mut self, pin: &str, value: impl Into<Spread>) -> Self {
        self.values.insert(pin.to_owned(), value.into());
        self
    }
}

/// One end of a link: a node and one of its pins, by name.
#[derive(Clone, Debug, PartialEq, Eq, PartialOrd, Ord, Hash, Serialize, Deserialize)]
pub struct PinRef(pub NodeId, pub String);

impl PinRef {
    pub fn new(node: u32, pin: &str) -> Self {
        PinRef(NodeId(node), pin.to_owned())
    }

    pub fn node(&self) -> NodeId {
        self.0
    }

    pub fn pin(&self) -> &str {
        &self.1
    }
}

impl fmt::Display for PinRef {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "{}.`{}`", self.0, self.1)
    }
}

/// A link from an output pin to an input pin.
#[derive(Clone, Debug, PartialEq, Eq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct LinkDoc {
    pub from: PinRef,
    pub to: PinRef,
}

impl LinkDoc {
    pub fn new(from_node: u32, from_pin: &str, to_node: u32, to_pin: &str) -> Self {
        LinkDoc {
            from: PinRef::new(from_node, from_pin),
            to: PinRef::new(to_node, to_pin),
        }
    }
}

/// A whole patch.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Patch {
    pub version: u32,
    #[serde(default)]
    pub nodes: Vec<NodeDoc>,
    #[serde(default)]
    pub links: Vec<LinkDoc>,
    /// Subpatches defined inline, by type name: a node whose type is one of
    /// these names is an instance of it (`crate::subpatch`).
    #[serde(default, skip_serializing_if = "BTreeMap::is_empty")]
    pub subpatches: BTreeMap<String, Patch>,
    /// Notes on the canvas (format version 3).
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub comments: Vec<CommentDoc>,
    /// Titled rectangles grouping nodes on the canvas (format version 3).
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub frames: Vec<FrameDoc>,
}

impl Default for Patch {
    fn default() -> Self {
        Patch {
            version: FORMAT_VERSION,
            nodes: Vec::new(),
            links: Vec::new(),
            subpatches: BTreeMap::new(),
            comments: Vec::new(),
            frames: Vec::new(),
        }
    }
}

impl Patch {
    pub fn node(&self, id: NodeId) -> Option<&NodeDoc> {
        self.nodes.iter().find(|n| n.id == id)
    }

    pub fn node_mut(&mut self, id: NodeId) -> Option<&mut NodeDoc> {
        self.nodes.iter_mut().find(|n| n.id == id)
    }

    /// An id no node in the patch has yet.
    pub fn next_id(&self) -> NodeId {
        NodeId(self.nodes.iter().map(|n| n.id.0 + 1).max().unwrap_or(1))
    }

    pub fn add(&mut self, node: NodeDoc) -> NodeId {
        let id = node.id;
        self.nodes.push(node);
        id
    }

    /// The oldest format version that can hold this patch: what saving writes
    /// at least, so an older build refuses a file it would misread.
    pub fn required_version(&self) -> u32 {
        let nested = self.subpatches.values().map(Patch::required_version);
        let organised = !self.comments.is_empty()
            || !self.frames.is_empty()
            || self.nodes.iter().any(|n| n.bypass);
        let own = if organised {
            ORGANISE_VERSION
        } else if self.subpatches.is_empty() {
            1
        } else {
            SUBPATCH_VERSION
        };
        nested.fold(own, u32::max)
    }

    pub fn link(&mut self, from_node: u32, from_pin: &str, to_node: u32, to_pin: &str) {
        self.links
            .push(LinkDoc::new(from_node, from_pin, to_node, to_pin));
    }
}
