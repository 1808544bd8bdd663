//! Problems found in a patch, each placed on the node and pin it concerns.
//!
//! A problem never stops the rest of the patch: the network leaves out the
//! offending link or value (the document keeps it) and evaluates the rest.

use std::fmt;

use serde::Serialize;

use crate::document::{LinkDoc, NodeId};

#[derive(Clone, Copy, Debug, PartialEq, Eq, PartialOrd, Ord, Serialize)]
pub enum Severity {
    /// The patch runs, but not all of it as written (e.g. an unknown node type kept as a placeholder).
    Warning,
    /// Part of the patch cannot run as written.
    Error,
}

#[derive(Clone, Debug, PartialEq, Serialize)]
pub enum ProblemKind {
    /// A type this build does not know: the node is kept as a placeholder
    /// that outputs nothing (the editor needs it so while a type is being
    /// written or a file is missing).
    UnknownNodeType {
        /// The known type whose name is nearest, when near enough to be a slip.
        suggestion: Option<String>,
        /// A sink the placeholder feeds, directly or through other nodes:
        /// what it makes lacks the placeholder's work. Headless commands
        /// refuse such a patch (`spreadlight render --allow-unknown` takes it).
        feeds: Option<FedSink>,
    },
    DuplicateNodeId,
    LinkFromMissingNode {
        link: String,
    },
    LinkToMissingNode {
        link: String,
    },
    MissingOutputPin {
        available: Vec<String>,
    },
    MissingInputPin {
        available: Vec<String>,
    },
    IncompatibleLink {
        link: String,
        from_type: String,
        to_type: String,
    },
    InputLinkedTwice {
        link: String,
    },
    Cycle {
        link: String,
        path: Vec<NodeId>,
    },
    ValueForMissingPin {
        available: Vec<String>,
    },
    ValueWrongType {
        expected: String,
        found: String,
    },
    UnknownEnumOption {
        value: String,
        options: Vec<String>,
    },
    NonFiniteValue {
        slice: usize,
    },
    /// A subpatch that contains itself, directly or through others: the chain of type names.
    RecursiveSubpatch {
        chain: Vec<String>,
    },
    /// A subpatch file that exists but cannot be read as a patch.
    UnreadableSubpatch {
        message: String,
    },
    /// Two IOBoxes of one subpatch give the same pin name; only the first becomes a pin.
    DuplicatePinName {
        name: String,
    },
}

/// The sink an unknown node's work was meant for.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct FedSink {
    /// Where the sink sits: the subpatch nodes around it, then its own id.
    pub path: Vec<NodeId>,
    pub node_type: String,
}

impl fmt::Display for FedSink {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "`{}` ", self.node_type)?;
        let parts: Vec<String> = self.path.iter().map(NodeId::to_string).collect();
        f.write_str(&parts.join(" > "))
    }
}

/// One problem, located on a node (and a pin where one is involved).
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct Problem {
    pub severity: Severity,
    pub node: NodeId,
    /// The subpatch nodes the problem's node lies in, outermost first (empty at the top).
    #[serde(skip_serializing_if = "Vec::is_empty")]
    pub within: Vec<NodeId>,
    /// The node's type name, so a message reads well without the patch at hand.
    pub node_type: String,
    pub pin: Option<String>,
    pub kind: ProblemKind,
}

pub(crate) fn link_text(link: &LinkDoc) -> String {
    format!("{} -> {}", link.from, link.to)
}

fn names(list: &[String]) -> String {
    if list.is_empty() {
        "none".to_owned()
    } else {
        list.iter()
            .map(|p| format!("`{p}`"))
            .collect::<Vec<_>>()
            .join(", ")
    }
}

impl fmt::Display for ProblemKind {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        use ProblemKind::*;
        match self {
            UnknownNodeType { suggestion, feeds } => {
                f.write_str("unknown node type")?;
                if let Some(known) = suggestion {
                    write!(f, " (did you mean `{known}`?)")?;
                }
                f.write_str(
                    "; kept as a placeholder with its values and links (saved back unchanged), outputs nothing",
                )?;
                if let Some(sink) = feeds {
                    write!(f, ", so {sink}, which it feeds, runs without its work")?;
                }
                Ok(())
            }
            DuplicateNodeId => write!(
                f,
                "another node already has this id; this one is left out of evaluation"
            ),
            LinkFromMissingNode { link } => {
                write!(f, "link {link} comes from a node that is not in the patch")
            }
            LinkToMissingNode { link } => {
                write!(f, "link {link} goes to a node that is not in the patch")
            }
            MissingOutputPin { available } => {
                write!(f, "no such output pin (outputs: {})", names(available))
            }
            MissingInputPin { available } => {
                write!(f, "no such input pin (inputs: {})", names(available))
            }
            IncompatibleLink {
                link,
                from_type,
                to_type,
            } => {
                write!(
                    f,
                    "link {link} joins an output of type {from_type} to an input of type {to_type}"
                )
            }
            InputLinkedTwice { link } => {
                write!(f, "input already has a link; link {link} is ignored")
            }
            Cycle { link, path } => {
                let path: Vec<String> = path.iter().map(|n| n.to_string()).collect();
                write!(
                    f,
                    "link {link} closes a cycle ({}); it is ignored",
                    path.join(" -> ")
                )
            }
            ValueForMissingPin { available } => {
                write!(
                    f,
                    "value for an input the node does not have (inputs: {}); kept in the file, unused",
                    names(available)
                )
            }
            ValueWrongType { expected, found } => {
                write!(
                    f,
                    "value is {found}, the pin takes {expected}; the default is used"
                )
            }
            UnknownEnumOption { value, options } => {
                write!(
                    f,
                    "`{value}` is not an option (options: {}); the default is used",
                    names(options)
                )
            }
            NonFiniteValue { slice } => {
                write!(f, "slice {slice} is NaN or infinite; the default is used")
            }
            RecursiveSubpatch { chain } => {
                let chain: Vec<String> = chain.iter().map(|c| format!("`{c}`")).collect();
                write!(
                    f,
                    "recursive subpatch: {} includes itself; kept as a placeholder, outputs nothing",
                    chain.join(" -> ")
                )
            }
            UnreadableSubpatch { message } => write!(
                f,
                "subpatch file cannot be read ({message}); kept as a placeholder with its values and links, outputs nothing"
            ),
            DuplicatePinName { name } => write!(
                f,
                "another IOBox of this subpatch already makes the pin `{name}`; this one is not a pin"
            ),
        }
    }
}

impl fmt::Display for Severity {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(match self {
            Severity::Warning => "warning",
            Severity::Error => "error",
        })
    }
}

impl Problem {
    /// The problem as one line of a report about the file at `path`: `error: FILE: node #3 ...`.
    pub fn located(&self, path: &std::path::Path) -> String {
        format!("{}: {}: {self}", self.severity, path.display())
    }
}

impl fmt::Display for Problem {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str("node ")?;
        for outer in &self.within {
            write!(f, "{outer} > ")?;
        }
        write!(f, "{} `{}`", self.node, self.node_type)?;
        if let Some(pin) = &self.pin {
            write!(f, ", pin `{pin}`")?;
        }
        write!(f, ": {}", self.kind)
    }
}
