//! The IOBoxes of a subpatch, `Inlet` and `Outlet`: what makes its pins.
//!
//! An `Inlet`'s `Name` names an input pin of the subpatch's node; its value is
//! that pin's default; the parent's link or value replaces it. An `Outlet`
//! names an output pin. Neither declares a type: a pin takes the type of what
//! the IOBox is linked to inside (an `Inlet` the first input it feeds, an
//! `Outlet` the output feeding it), so one `Inlet` carries floats, G-buffers or
//! enum choices alike. Pins are ordered left to right by the IOBoxes' positions,
//! as in vvvv.

use std::collections::HashMap;
use std::sync::Arc;

use crate::document::{NodeDoc, NodeId, Patch};
use crate::registry::{NodeDef, Registry};
use crate::spread::Spread;
use crate::value::PinType;

/// The type name of a subpatch's input IOBox.
pub const INLET: &str = "Inlet";
/// The type name of a subpatch's output IOBox.
pub const OUTLET: &str = "Outlet";

const CATEGORY: &str = "Subpatch";
const INLET_HELP: &str = "An input pin of the subpatch it is in: `Name` names the pin, the value \
     on `Input` is its default, the parent's link or value replaces it. Its type is that of the \
     first input it feeds.";
const OUTLET_HELP: &str = "An output pin of the subpatch it is in: `Name` names the pin; what \
     reaches `Input` leaves the subpatch there. Its type is that of the output feeding it.";

/// Whether a node type is one of the IOBoxes that make subpatch pins.
pub fn is_iobox(type_name: &str) -> bool {
    type_name == INLET || type_name == OUTLET
}

/// `Inlet` and `Outlet` as the browser lists them (of any type; a compiled
/// patch types each one from its links).
pub fn register(r: &mut Registry) {
    // A one-slice default, so each passes something on when tried alone.
    r.add(inlet_def(PinType::Any, Spread::Float(vec![0.0])));
    let mut outlet = outlet_def(PinType::Any);
    outlet.inputs[0].default = Spread::Float(vec![0.0]);
    r.add(outlet);
}

/// An `Inlet` of one type: passes its input on.
pub(crate) fn inlet_def(ty: PinType, default: Spread) -> NodeDef {
    NodeDef::new(INLET, CATEGORY, INLET_HELP)
        .input_spread("Input", ty, default)
        .input("Name", "Input".to_owned())
        .output_typed("Output", ty)
        .evaluate(pass_on)
}

/// An `Outlet` of one type: passes its input on.
pub(crate) fn outlet_def(ty: PinType) -> NodeDef {
    NodeDef::new(OUTLET, CATEGORY, OUTLET_HELP)
        .input_spread("Input", ty, Spread::empty(ty))
        .input("Name", "Output".to_owned())
        .output_typed("Output", ty)
        .evaluate(pass_on)
}

fn pass_on(cx: &mut crate::EvalContext<'_>) -> Result<(), crate::NodeError> {
    let input = cx.input_arc(0).clone();
    cx.set_output_arc(0, input);
    Ok(())
}

/// The pin name an IOBox gives, from its `Name` value.
pub fn pin_name(node: &NodeDoc) -> String {
    match node.values.get("Name") {
        Some(Spread::String(names)) if !names.is_empty() => names[0].clone(),
        _ if node.type_name == OUTLET => "Output".to_owned(),
        _ => "Input".to_owned(),
    }
}

/// The IOBoxes of a document of one kind, in pin order (left to right, then by id).
pub fn ioboxes<'p>(doc: &'p Patch, kind: &str) -> Vec<&'p NodeDoc> {
    let mut boxes: Vec<&NodeDoc> = doc.nodes.iter().filter(|n| n.type_name == kind).collect();
    boxes.sort_by(|a, b| a.pos.0.total_cmp(&b.pos.0).then(a.id.cmp(&b.id)));
    boxes
}

/// The pin type of a value with no link to say more (enums cannot be told from their value).
fn value_type(value: &Spread) -> PinType {
    match value {
        Spread::Float(_) => PinType::Float,
        Spread::Int(_) => PinType::Int,
        Spread::Bool(_) => PinType::Bool,
        Spread::String(_) => PinType::String,
        Spread::Vec2(_) => PinType::Vec2,
        Spread::Vec3(_) => PinType::Vec3,
        Spread::Vec4(_) => PinType::Vec4,
        Spread::Color(_) => PinType::Color,
        Spread::Mat4(_) => PinType::Mat4,
        Spread::Resource(kind, _) => PinType::Resource(*kind),
        Spread::Enum(_) => PinType::Any,
    }
}

/// Types the IOBoxes of a flattened patch from their links (IOBoxes of
/// nested subpatches feed each other, so types are found recursively): each
/// one's pin type, and an `Inlet`'s default.
pub(crate) fn type_ioboxes(
    flat: &Patch,
    registry: &Registry,
) -> HashMap<NodeId, (PinType, Spread)> {
    let mut typer = Typer {
        flat,
        registry,
        nodes: flat.nodes.iter().map(|n| (n.id, n)).collect(),
        known: HashMap::new(),
        open: Vec::new(),
    };
    for node in &flat.nodes {
        if is_iobox(&node.type_name) {
            typer.pin(node.id);
        }
    }
    typer.known
}

/// Typed IOBox definitions by (is an `Inlet`, type name), shared by every compile.
type SharedDefs = HashMap<(bool, String), Arc<NodeDef>>;

/// The definitions the flat IOBoxes run with. An `Inlet`'s default becomes
/// its value in the flat patch, so a definition depends on the kind and type
/// alone and is shared (the runtime keeps a node's state while its
/// definition is the same one, so a recompile must hand out the same).
pub(crate) fn iobox_defs(
    flat: &mut Patch,
    typed: &HashMap<NodeId, (PinType, Spread)>,
) -> HashMap<NodeId, Arc<NodeDef>> {
    static SHARED: std::sync::OnceLock<std::sync::Mutex<SharedDefs>> = std::sync::OnceLock::new();
    let mut shared = SHARED
        .get_or_init(Default::default)
        .lock()
        .unwrap_or_else(std::sync::PoisonError::into_inner);
    let mut defs = HashMap::new();
    for node in &mut flat.nodes {
        let Some((ty, default)) = typed.get(&node.id) else {
            continue;
        };
        let inlet = node.type_name == INLET;
        if inlet && !node.values.contains_key("Input") {
            node.values.insert("Input".to_owned(), default.clone());
        }
        let def = shared.entry((inlet, ty.name())).or_insert_with(|| {
            Arc::new(if inlet {
                inlet_def(*ty, Spread::empty(*ty))
            } else {
                outlet_def(*ty)
            })
        });
        defs.insert(node.id, def.clone());
    }
    defs
}

struct Typer<'a> {
    flat: &'a Patch,
    registry: &'a Registry,
    nodes: HashMap<NodeId, &'a NodeDoc>,
    known: HashMap<NodeId, (PinType, Spread)>,
    /// IOBoxes being typed now: a link cycle through IOBoxes types them `Any`.
    open: Vec<NodeId>,
}

impl Typer<'_> {
    /// The type of an IOBox's pin, and an `Inlet`'s default.
    fn pin(&mut self, id: NodeId) -> (PinType, Spread) {
        if let Some(known) = self.known.get(&id) {
            return known.clone();
        }
        if self.open.contains(&id) {
            return (PinType::Any, Spread::empty(PinType::Any));
        }
        self.open.push(id);
        let node = self.nodes[&id];
        let found = if node.type_name == INLET {
            self.inlet(node)
        } else {
            self.outlet(node)
        };
        self.open.pop();
        self.known.insert(id, found.clone());
        found
    }

    fn inlet(&mut self, node: &NodeDoc) -> (PinType, Spread) {
        let consumers: Vec<(NodeId, String)> = self
            .flat
            .links
            .iter()
            .filter(|l| l.from.node() == node.id && l.from.pin() == "Output")
            .map(|l| (l.to.node(), l.to.pin().to_owned()))
            .collect();
        let own = node.values.get("Input");
        for (to, pin) in consumers {
            let Some(target) = self.nodes.get(&to).copied() else {
                continue;
            };
            let found = if is_iobox(&target.type_name) {
                (pin == "Input").then(|| self.pin(to))
            } else {
                self.registry.get(&target.type_name).and_then(|def| {
                    let k = def.input_index(&pin)?;
                    Some((def.inputs[k].ty, def.inputs[k].default.clone()))
                })
            };
            if let Some((ty, default)) = found
                && ty != PinType::Any
            {
                // The IOBox's own value is the default where it fits; the consumer's otherwise.
                let default = match own {
                    Some(v) if v.fits(ty) => v.clone(),
                    _ => default,
                };
                return (ty, default);
            }
        }
        match own {
            Some(v) => (value_type(v), v.clone()),
            None => (PinType::Any, Spread::empty(PinType::Any)),
        }
    }

    fn outlet(&mut self, node: &NodeDoc) -> (PinType, Spread) {
        let producer = self
            .flat
            .links
            .iter()
            .find(|l| l.to.node() == node.id && l.to.pin() == "Input")
            .map(|l| (l.from.node(), l.from.pin().to_owned()));
        let ty = producer
            .and_then(|(from, pin)| {
                let source = self.nodes.get(&from).copied()?;
                if is_iobox(&source.type_name) {
                    return (pin == "Output").then(|| self.pin(from).0);
                }
                let def = self.registry.get(&source.type_name)?;
                Some(def.outputs[def.output_index(&pin)?].ty)
            })
            .unwrap_or(PinType::Any);
        (ty, Spread::empty(ty))
    }
}
