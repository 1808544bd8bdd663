//! A node type's pins: names and types, defaults and ranges. Apart from
//! the registry so that nodes (which read their inputs' definitions) and the
//! registry (which makes nodes) both depend on it and not on each other.

use std::borrow::Cow;

use crate::spread::Spread;
use crate::value::PinType;

/// A name, category or help text: `&'static str` for node types built into
/// the binary, owned for those made at run time (no leaking on every reload).
pub type Name = Cow<'static, str>;

/// One input or output pin of a node type.
#[derive(Clone, Debug)]
pub struct PinDef {
    pub name: Name,
    pub ty: PinType,
    /// The spread an unlinked input holds when the patch sets no value (empty for outputs).
    pub default: Spread,
    /// Where a number pin's values make sense (an infinite end: open): the
    /// editor's drag values stop there and the node holds values to it.
    pub range: Option<(f64, f64)>,
}
