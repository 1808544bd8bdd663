//! The registry of node types: what a node is called, where it sits in the
//! browser, its pins with types and defaults, and how to make one.
//!
//! A node type is declared once, with [`NodeDef`]'s builder, beside its code;
//! its family registers it with [`Registry::add`]. Nothing else lists node types.
//! Types made at run time (shader files, subpatches) have owned names and are
//! swapped in place with [`Registry::replace`] when their source changes.

use std::collections::BTreeMap;
use std::sync::Arc;

use crate::node::{EvalContext, Node, NodeError};
pub use crate::pin::{Name, PinDef};
use crate::spread::{SliceValue, Spread, map1, map2, map3, map4};
use crate::typed_pins::Pins;
use crate::value::{EnumDef, PinType};

type Constructor = Arc<dyn Fn() -> Box<dyn Node> + Send + Sync>;

/// How much of the past a node's outputs depend on beyond what the clock
/// tells it: the frames evaluated before the current one. A render that
/// starts at frame N must evaluate that much first (`spreadlight render`'s
/// preroll) to give what a run from frame 0 gives. Ordered: `None` <
/// `Frames(1)` < `Frames(2)` < ... < `Unbounded`.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, PartialOrd, Ord)]
pub enum Memory {
    /// Its outputs follow from its inputs and the clock alone (a node that
    /// reads the time, such as an LFO seeded from it, is here).
    #[default]
    None,
    /// The last N frames: a frame delay, last frame's camera or transforms
    /// for motion vectors.
    Frames(u32),
    /// Every frame since it started: a simulation, a filter, a history that
    /// accumulates or adapts.
    Unbounded,
}

/// A node type.
#[derive(Clone)]
pub struct NodeDef {
    /// The type name as saved in patches and shown in the browser, e.g. `Add (Value)`.
    pub name: Name,
    pub category: Name,
    pub help: Name,
    pub inputs: Vec<PinDef>,
    pub outputs: Vec<PinDef>,
    /// Re-evaluated every frame even when its inputs did not change (it reads the clock or keeps state over time).
    pub time_dependent: bool,
    /// Evaluation starts from sinks: outputs, renderers, previews, probes.
    pub sink: bool,
    /// Its pins are not known now (a shader file that has never compiled):
    /// values and links for pins it lacks are left out quietly, as a
    /// placeholder's are, for the type that has them again; the node's own
    /// error says why.
    pub pins_unknown: bool,
    /// How far back its outputs depend on earlier frames ([`Memory`]).
    pub memory: Memory,
    constructor: Constructor,
}

impl std::fmt::Debug for NodeDef {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("NodeDef")
            .field("name", &self.name)
            .field("category", &self.category)
            .field("inputs", &self.inputs)
            .field("outputs", &self.outputs)
            .finish_non_exhaustive()
    }
}

struct Unimplemented(Name);

impl Node for Unimplemented {
    fn evaluate(&mut self, _: &mut EvalContext<'_>) -> Result<(), NodeError> {
        Err(NodeError::Other(format!(
            "node type `{}` was registered without an evaluation",
            self.0
        )))
    }
}

impl NodeDef {
    pub fn new(name: impl Into<Name>, category: impl Into<Name>, help: impl Into<Name>) -> Self {
        let name = name.into();
        let unimplemented = name.clone();
        NodeDef {
            name,
            category: category.into(),
            help: help.into(),
            inputs: Vec::new(),
            outputs: Vec::new(),
            time_dependent: false,
            sink: false,
            pins_unknown: false,
            memory: Memory::None,
            constructor: Arc::new(move || Box::new(Unimplemented(unimplemented.clone()))),
        }
    }

    /// An input of a plain value type with a one-slice default.
    pub fn input<T: SliceValue>(self, name: impl Into<Name>, default: T) -> Self {
        self.input_spread(name, T::PIN_TYPE, T::into_spread(vec![default]))
    }

    /// An input whose default is a whole spread (or of a type with no [`SliceValue`]).
    pub fn input_spread(mut self, name: impl Into<Name>, ty: PinType, default: Spread) -> Self {
        let name = name.into();
        assert!(
            default.fits(ty),
            "{}: default of `{name}` does not fit {ty}",
            self.name
        );
        self.inputs.push(PinDef {
            name,
            ty,
            default,
            range: None,
        });
        self
    }

    /// Limit the last input's numbers to `min..=max` (either end may be
    /// infinite): the editor drags within it; the node clamps what it reads.
    pub fn range(mut self, min: f64, max: f64) -> Self {
        if let Some(pin) = self.inputs.last_mut() {
            pin.range = Some((min, max));
        }
        self
    }

    /// An enum input; `default` must be one of the enum's options.
    pub fn input_enum(self, name: impl Into<Name>, def: &'static EnumDef, default: &str) -> Self {
        assert!(
            def.index_of(default).is_some(),
            "{}: `{default}` is not an option of {}",
            self.name,
            def.name
        );
        self.input_spread(
            name,
            PinType::Enum(def),
            Spread::Enum(vec![default.to_owned()]),
        )
    }

    pub fn output<T: SliceValue>(self, name: impl Into<Name>) -> Self {
        self.output_typed(name, T::PIN_TYPE)
    }

    pub fn output_typed(mut self, name: impl Into<Name>, ty: PinType) -> Self {
        self.outputs.push(PinDef {
            name: name.into(),
            ty,
            default: Spread::empty(ty),
            range: None,
        });
        self
    }

    pub fn time_dependent(mut self) -> Self {
        self.time_dependent = true;
        self
    }

    pub fn sink(mut self) -> Self {
        self.sink = true;
        self
    }

    /// See [`NodeDef::pins_unknown`].
    pub fn pins_unknown(mut self) -> Self {
        self.pins_unknown = true;
        self
    }

    /// Its outputs depend on every frame evaluated before ([`Memory::Unbounded`]).
    pub fn stateful(mut self) -> Self {
        self.memory = Memory::Unbounded;
        self
    }

    /// Its outputs depend on the last `frames` frames evaluated ([`Memory::Frames`]).
    pub fn remembers(mut self, frames: u32) -> Self {
        self.memory = self.memory.max(Memory::Frames(frames));
        self
    }

    /// A node with state (or any node that wants the whole [`EvalContext`]).
    pub fn construct<N: Node + 'static>(
        mut self,
        make: impl Fn() -> N + Send + Sync + 'static,
    ) -> Self {
        self.constructor = Arc::new(move || Box::new(make()));
        self
    }

    /// Declare the pins through typed handles and give the evaluation that
    /// reads and writes through them ([`crate::typed_pins`]): the closure
    /// `declare` returns captures the handles it was given.
    pub fn with_pins<F>(mut self, declare: impl FnOnce(&mut Pins<'_>) -> F) -> Self
    where
        F: Fn(&mut EvalContext<'_>) -> Result<(), NodeError> + Clone + Send + Sync + 'static,
    {
        let evaluate = declare(&mut Pins {
            inputs: &mut self.inputs,
            outputs: &mut self.outputs,
            node: &self.name,
        });
        self.evaluate_with(evaluate)
    }

    /// [`NodeDef::with_pins`] for a node with state: `declare` returns how to
    /// make one, capturing the handles the node's struct keeps.
    pub fn with_pins_node<N: Node + 'static, M: Fn() -> N + Send + Sync + 'static>(
        mut self,
        declare: impl FnOnce(&mut Pins<'_>) -> M,
    ) -> Self {
        let make = declare(&mut Pins {
            inputs: &mut self.inputs,
            outputs: &mut self.outputs,
            node: &self.name,
        });
        self.construct(make)
    }

    /// A stateless node given as one function over the context.
    pub fn evaluate(self, f: fn(&mut EvalContext<'_>) -> Result<(), NodeError>) -> Self {
        self.construct(move || FnNode(f))
    }

    /// A pure one-input, one-output node, written per slice.
    pub fn per_slice1<A: SliceValue, O: SliceValue>(
        self,
        f: impl Fn(&A) -> O + Copy + Send + Sync + 'static,
    ) -> Self {
        self.check_shape(&[A::PIN_TYPE], O::PIN_TYPE);
        self.evaluate_with(move |cx| {
            let out = map1(cx.slices::<A>(0)?, f);
            cx.set(0, out);
            Ok(())
        })
    }

    /// A pure two-input, one-output node, written per slice; spreading and wrapping come free.
    pub fn per_slice2<A: SliceValue, B: SliceValue, O: SliceValue>(
        self,
        f: impl Fn(&A, &B) -> O + Copy + Send + Sync + 'static,
    ) -> Self {
        self.check_shape(&[A::PIN_TYPE, B::PIN_TYPE], O::PIN_TYPE);
        self.evaluate_with(move |cx| {
            let out = map2(cx.slices::<A>(0)?, cx.slices::<B>(1)?, f);
            cx.set(0, out);
            Ok(())
        })
    }

    /// A pure three-input, one-output node, written per slice.
    pub fn per_slice3<A: SliceValue, B: SliceValue, C: SliceValue, O: SliceValue>(
        self,
        f: impl Fn(&A, &B, &C) -> O + Copy + Send + Sync + 'static,
    ) -> Self {
        self.check_shape(&[A::PIN_TYPE, B::PIN_TYPE, C::PIN_TYPE], O::PIN_TYPE);
        self.evaluate_with(move |cx| {
            let out = map3(
                cx.slices::<A>(0)?,
                cx.slices::<B>(1)?,
                cx.slices::<C>(2)?,
                f,
            );
            cx.set(0, out);
            Ok(())
        })
    }

    /// A pure four-input, one-output node, written per slice.
    pub fn per_slice4<A: SliceValue, B: SliceValue, C: SliceValue, D: SliceValue, O: SliceValue>(
        self,
        f: impl Fn(&A, &B, &C, &D) -> O + Copy + Send + Sync + 'static,
    ) -> Self {
        self.check_shape(
            &[A::PIN_TYPE, B::PIN_TYPE, C::PIN_TYPE, D::PIN_TYPE],
            O::PIN_TYPE,
        );
        self.evaluate_with(move |cx| {
            let out = map4(
                cx.slices::<A>(0)?,
                cx.slices::<B>(1)?,
                cx.slices::<C>(2)?,
                cx.slices::<D>(3)?,
                f,
            );
            cx.set(0, out);
            Ok(())
        })
    }

    fn evaluate_with(
        self,
        f: impl Fn(&mut EvalContext<'_>) -> Result<(), NodeError> + Clone + Send + Sync + 'static,
    ) -> Self {
        self.construct(move || ClosureNode(f.clone()))
    }

    /// A per-slice function must match the declared pins; a mismatch is a bug in the node's code.
    fn check_shape(&self, inputs: &[PinType], output: PinType) {
        let declared: Vec<PinType> = self.inputs.iter().map(|p| p.ty).collect();
        assert_eq!(
            declared, inputs,
            "{}: per-slice function does not match the input pins",
            self.name
        );
        assert_eq!(
            self.outputs.len(),
            1,
            "{}: per-slice nodes have exactly one output",
            self.name
        );
        assert_eq!(
            self.outputs[0].ty, output,
            "{}: per-slice function does not match the output pin",
            self.name
        );
    }

    pub fn instantiate(&self) -> Box<dyn Node> {
        (self.constructor)()
    }

    pub fn input_index(&self, pin: &str) -> Option<usize> {
        self.inputs.iter().position(|p| p.name == pin)
    }

    pub fn output_index(&self, pin: &str) -> Option<usize> {
        self.outputs.iter().position(|p| p.name == pin)
    }
}

struct FnNode(fn(&mut EvalContext<'_>) -> Result<(), NodeError>);

impl Node for FnNode {
    fn evaluate(&mut self, cx: &mut EvalContext<'_>) -> Result<(), NodeError> {
        (self.0)(cx)
    }
}

struct ClosureNode<F>(F);

impl<F: Fn(&mut EvalContext<'_>) -> Result<(), NodeError> + Send> Node for ClosureNode<F> {
    fn evaluate(&mut self, cx: &mut EvalContext<'_>) -> Result<(), NodeError> {
        (self.0)(cx)
    }
}

/// All node types known to this build, by type name.
#[derive(Default, Clone)]
pub struct Registry {
    defs: BTreeMap<Name, Entry>,
}

/// A registered type: made, or made the first time it is looked up ([`Registry::add_lazy`]).
#[derive(Clone)]
enum Entry {
    Made(Arc<NodeDef>),
    /// Shared by the registry's clones, so every clone gets the same
    /// definition (a runtime tells a replaced type by its pointer).
    Lazy(Arc<LazyDef>),
}

struct LazyDef {
    made: std::sync::OnceLock<Arc<NodeDef>>,
    make: Box<dyn Fn() -> NodeDef + Send + Sync>,
}

impl Entry {
    fn def(&self) -> &Arc<NodeDef> {
        match self {
            Entry::Made(def) => def,
            Entry::Lazy(lazy) => lazy.made.get_or_init(|| Arc::new((lazy.make)())),
        }
    }
}

impl Registry {
    pub fn new() -> Self {
        Self::default()
    }

    /// Register a node type. Two types with one name is a bug in the node library, so it panics.
    pub fn add(&mut self, def: NodeDef) {
        let name = def.name.clone();
        let previous = self.defs.insert(name.clone(), Entry::Made(Arc::new(def)));
        assert!(previous.is_none(), "node type `{name}` registered twice");
    }

    /// Register node type `name`, made by `make` the first time it is looked
    /// up (or listed): for types whose making costs (a shader node example
    /// is parsed and validated), which most patches never use. `make` must
    /// make a type of that name.
    pub fn add_lazy(
        &mut self,
        name: impl Into<Name>,
        make: impl Fn() -> NodeDef + Send + Sync + 'static,
    ) {
        let name = name.into();
        let lazy = LazyDef {
            made: std::sync::OnceLock::new(),
            make: Box::new(make),
        };
        let previous = self.defs.insert(name.clone(), Entry::Lazy(Arc::new(lazy)));
        assert!(previous.is_none(), "node type `{name}` registered twice");
    }

    /// Register a node type made at run time, replacing the one of that name
    /// if any (a reloaded shader file, an edited subpatch). A [`Runtime`](crate::Runtime)
    /// given the new registry re-instantiates the nodes of a replaced type.
    pub fn replace(&mut self, def: NodeDef) -> Option<Arc<NodeDef>> {
        self.defs
            .insert(def.name.clone(), Entry::Made(Arc::new(def)))
            .map(|e| e.def().clone())
    }

    /// Forget a node type (its file was deleted); nodes of it become unknown-type placeholders.
    pub fn remove(&mut self, name: &str) -> Option<Arc<NodeDef>> {
        self.defs.remove(name).map(|e| e.def().clone())
    }

    pub fn get(&self, name: &str) -> Option<&Arc<NodeDef>> {
        self.defs.get(name).map(Entry::def)
    }

    /// Every node type, sorted by name (types registered lazily are made).
    pub fn iter(&self) -> impl Iterator<Item = &Arc<NodeDef>> {
        self.defs.values().map(Entry::def)
    }

    pub fn len(&self) -> usize {
        self.defs.len()
    }

    /// The registered type name nearest `name`, when near enough to be a
    /// misspelling of it ([`crate::spelling::nearest`]): what an unknown
    /// type's message suggests.
    pub fn nearest(&self, name: &str) -> Option<&str> {
        crate::spelling::nearest(name, self.defs.keys().map(|k| &**k))
    }

    pub fn is_empty(&self) -> bool {
        self.defs.is_empty()
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::sync::atomic::{AtomicUsize, Ordering};

    #[test]
    fn a_lazy_type_is_made_once_when_first_looked_up_and_clones_share_it() {
        static MADE: AtomicUsize = AtomicUsize::new(0);
        let mut registry = Registry::new();
        registry.add(NodeDef::new("Eager", "Test", ""));
        registry.add_lazy("Lazy", || {
            MADE.fetch_add(1, Ordering::Relaxed);
            NodeDef::new("Lazy", "Test", "made when looked up")
        });
        // Counting and spelling suggestions go by name: nothing is made.
        assert_eq!(registry.len(), 2);
        assert_eq!(registry.nearest("Lazi"), Some("Lazy"));
        assert_eq!(MADE.load(Ordering::Relaxed), 0);
        let copy = registry.clone();
        let def = registry.get("Lazy").expect("registered").clone();
        assert_eq!(def.help, "made when looked up");
        assert_eq!(MADE.load(Ordering::Relaxed), 1);
        // The clone finds the same definition (a runtime tells a replaced type by its pointer).
        assert!(Arc::ptr_eq(&def, copy.get("Lazy").expect("in the clone")));
        assert_eq!(registry.iter().count(), 2);
        assert_eq!(MADE.load(Ordering::Relaxed), 1);
        // Replacing it hands back the one it replaced.
        let replaced = registry.replace(NodeDef::new("Lazy", "Test", "a file's"));
        assert!(replaced.is_some_and(|old| Arc::ptr_eq(&old, &def)));
        assert_eq!(registry.get("Lazy").expect("replaced").help, "a file's");
    }
}
