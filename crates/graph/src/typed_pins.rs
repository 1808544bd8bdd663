//! Typed pin handles: a node declares each pin once and gets back a handle
//! that knows the pin's position and Rust type, so its evaluation reads and
//! writes through names it declared instead of numbers kept in step by hand.
//!
//! ```ignore
//! NodeDef::new("FXAA", "Post", "...").with_pins(|p| {
//!     let texture = p.input_resource::<TextureRef>("Texture", ResourceKind::Texture);
//!     let quality = p.input_choice("Quality", &QUALITY, FxaaQuality::High);
//!     let subpixel = p.input("Subpixel", 0.75f32);
//!     let out = p.output_resource::<TextureRef>("Texture", ResourceKind::Texture);
//!     move |cx| {
//!         let source = cx.resources(texture)?;
//!         let quality: FxaaQuality = cx.choice(quality)?;
//!         let subpixel = cx.get(subpixel)?.first().copied().unwrap_or(0.75);
//!         cx.put_resources(out, vec![...]);
//!         Ok(())
//!     }
//! })
//! ```
//!
//! A handle is `Copy` and carries what reading needs beside the position
//! (an enum pin's options, a resource pin's kind), so a closure captures the
//! handles and nothing else. Reading a handle from another node type's
//! declaration is not prevented by the types, but every handle comes from the
//! `Pins` of the definition whose evaluation captures it.

use std::marker::PhantomData;
use std::sync::Arc;

use crate::node::{EvalContext, NodeError};
use crate::pin::{Name, PinDef};
use crate::spread::{SliceValue, Spread};
use crate::value::{EnumDef, PinType, Resource, ResourceKind};

/// What a pin carries, as a Rust type, and what a handle must remember to
/// read it beyond its position.
pub trait PinData: 'static {
    type Meta: Copy + Send + Sync + 'static;
}

macro_rules! plain_pin_data {
    ($($t:ty),*) => { $(impl PinData for $t { type Meta = (); })* };
}
plain_pin_data!(
    f32,
    i64,
    bool,
    String,
    glam::Vec2,
    glam::Vec3,
    glam::Vec4,
    crate::value::Color,
    glam::Mat4
);

/// A pin of shared resources whose objects are `T` (a texture, a mesh, a
/// light world): read with [`EvalContext::resources`].
pub struct Res<T>(PhantomData<fn() -> T>);

impl<T: Send + Sync + 'static> PinData for Res<T> {
    type Meta = ResourceKind;
}

/// A pin read as a whole spread, whatever it holds (a generic or a
/// pass-through pin): read with [`EvalContext::spread`].
pub struct AnySpread;

impl PinData for AnySpread {
    type Meta = ();
}

/// An enum pin read as the Rust value `E` each option stands for.
pub struct Choice<E>(PhantomData<fn() -> E>);

impl<E: Copy + Send + Sync + 'static> PinData for Choice<E> {
    /// The options, and the index of the one an empty spread reads as.
    type Meta = (&'static Choices<E>, usize);
}

/// The options of an enum pin beside the Rust value each names, in the same
/// order: the one place an option's spelling and its meaning meet.
pub struct Choices<E: 'static> {
    pub def: EnumDef,
    values: &'static [E],
}

impl<E: Copy + PartialEq + 'static> Choices<E> {
    /// `options[i]` names `values[i]`; the lengths must match (checked when
    /// the static is built).
    pub const fn new(
        name: &'static str,
        options: &'static [&'static str],
        values: &'static [E],
    ) -> Self {
        assert!(options.len() == values.len(), "each option names one value");
        Choices {
            def: EnumDef { name, options },
            values,
        }
    }

    /// The value an option's name stands for; a name that differs only in
    /// case counts (as typed on a command line or in a hand-written patch).
    pub fn value(&self, option: &str) -> Option<E> {
        self.def
            .index_of(option)
            .or_else(|| {
                self.def
                    .options
                    .iter()
                    .position(|o| o.eq_ignore_ascii_case(option))
            })
            .map(|i| self.values[i])
    }

    /// The option's name for a value (the first, if two options share one).
    pub fn name(&self, value: E) -> &'static str {
        self.values
            .iter()
            .position(|v| *v == value)
            .map(|i| self.def.options[i])
            .expect("every value of a Choices has an option")
    }
}

/// An input pin's handle.
pub struct In<T: PinData> {
    index: usize,
    meta: T::Meta,
}

/// An output pin's handle.
pub struct Out<T: PinData> {
    index: usize,
    meta: T::Meta,
}

impl<T: PinData> Clone for In<T> {
    fn clone(&self) -> Self {
        *self
    }
}
impl<T: PinData> Copy for In<T> {}
impl<T: PinData> Clone for Out<T> {
    fn clone(&self) -> Self {
        *self
    }
}
impl<T: PinData> Copy for Out<T> {}

impl<T: PinData> std::fmt::Debug for In<T> {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(f, "In({})", self.index)
    }
}
impl<T: PinData> std::fmt::Debug for Out<T> {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(f, "Out({})", self.index)
    }
}

impl<T: PinData> In<T> {
    /// The pin's position, for code that must still speak of it by number
    /// (the runtime, a host that walks every pin).
    pub fn index(self) -> usize {
        self.index
    }
}

impl<T: PinData> Out<T> {
    pub fn index(self) -> usize {
        self.index
    }
}

/// Any input handle, for what is the same whatever the pin carries
/// (an error naming the pin, the whole spread).
pub trait InputPin: Copy {
    fn input_index(self) -> usize;
}
impl<T: PinData> InputPin for In<T> {
    fn input_index(self) -> usize {
        self.index
    }
}

/// Any output handle.
pub trait OutputPin: Copy {
    fn output_index(self) -> usize;
}
impl<T: PinData> OutputPin for Out<T> {
    fn output_index(self) -> usize {
        self.index
    }
}

/// The pins being declared for one node type: each call appends a pin and
/// returns its handle. Given by [`crate::NodeDef::with_pins`].
pub struct Pins<'d> {
    pub(crate) inputs: &'d mut Vec<PinDef>,
    pub(crate) outputs: &'d mut Vec<PinDef>,
    pub(crate) node: &'d str,
}

impl Pins<'_> {
    fn push_input(&mut self, name: Name, ty: PinType, default: Spread) -> usize {
        assert!(
            default.fits(ty),
            "{}: default of `{name}` does not fit {ty}",
            self.node
        );
        self.inputs.push(PinDef {
            name,
            ty,
            default,
            range: None,
        });
        self.inputs.len() - 1
    }

    fn push_output(&mut self, name: Name, ty: PinType) -> usize {
        self.outputs.push(PinDef {
            name,
            ty,
            default: Spread::empty(ty),
            range: None,
        });
        self.outputs.len() - 1
    }

    /// An input of a plain value type with a one-slice default.
    pub fn input<T: SliceValue + PinData<Meta = ()>>(
        &mut self,
        name: impl Into<Name>,
        default: T,
    ) -> In<T> {
        self.input_spread(name, vec![default])
    }

    /// An input of a plain value type whose default is a whole spread.
    pub fn input_spread<T: SliceValue + PinData<Meta = ()>>(
        &mut self,
        name: impl Into<Name>,
        default: Vec<T>,
    ) -> In<T> {
        let index = self.push_input(name.into(), T::PIN_TYPE, T::into_spread(default));
        In { index, meta: () }
    }

    /// An input read as a whole spread, of any pin type (a generic node's
    /// input, or one whose default is not a plain value).
    pub fn input_any(
        &mut self,
        name: impl Into<Name>,
        ty: PinType,
        default: Spread,
    ) -> In<AnySpread> {
        let index = self.push_input(name.into(), ty, default);
        In { index, meta: () }
    }

    /// An input of shared resources (empty by default).
    pub fn input_resource<T: Send + Sync + 'static>(
        &mut self,
        name: impl Into<Name>,
        kind: ResourceKind,
    ) -> In<Res<T>> {
        let index = self.push_input(
            name.into(),
            PinType::Resource(kind),
            Spread::Resource(kind, Vec::new()),
        );
        In { index, meta: kind }
    }

    /// An enum input read as `E`; `default` is what it holds before anyone
    /// sets it, and what an empty spread reads as.
    pub fn input_choice<E: Copy + PartialEq + Send + Sync + 'static>(
        &mut self,
        name: impl Into<Name>,
        choices: &'static Choices<E>,
        default: E,
    ) -> In<Choice<E>> {
        let option = choices.name(default);
        let index = self.push_input(
            name.into(),
            PinType::Enum(&choices.def),
            Spread::Enum(vec![option.to_owned()]),
        );
        let default = choices
            .def
            .index_of(option)
            .expect("the default is an option");
        In {
            index,
            meta: (choices, default),
        }
    }

    /// Limit the last input's numbers to `min..=max` (either end may be
    /// infinite): the editor drags within it; the node clamps what it reads.
    pub fn range(&mut self, min: f64, max: f64) {
        if let Some(pin) = self.inputs.last_mut() {
            pin.range = Some((min, max));
        }
    }

    pub fn output<T: SliceValue + PinData<Meta = ()>>(&mut self, name: impl Into<Name>) -> Out<T> {
        let index = self.push_output(name.into(), T::PIN_TYPE);
        Out { index, meta: () }
    }

    /// An output of any pin type, written as a whole spread.
    pub fn output_any(&mut self, name: impl Into<Name>, ty: PinType) -> Out<AnySpread> {
        let index = self.push_output(name.into(), ty);
        Out { index, meta: () }
    }

    /// An output of shared resources of kind `kind`.
    pub fn output_resource<T: Send + Sync + 'static>(
        &mut self,
        name: impl Into<Name>,
        kind: ResourceKind,
    ) -> Out<Res<T>> {
        let index = self.push_output(name.into(), PinType::Resource(kind));
        Out { index, meta: kind }
    }
}

/// Reading and writing through handles.
impl EvalContext<'_> {
    /// The slices of a value input.
    pub fn get<T: SliceValue + PinData>(&self, pin: In<T>) -> Result<&[T], NodeError> {
        self.slices::<T>(pin.index)
    }

    /// The first slice of a value input, or `fallback` when the spread is empty.
    pub fn first<T: SliceValue + PinData + Copy>(
        &self,
        pin: In<T>,
        fallback: T,
    ) -> Result<T, NodeError> {
        Ok(self.get(pin)?.first().copied().unwrap_or(fallback))
    }

    /// The whole spread at any input.
    pub fn spread(&self, pin: impl InputPin) -> &Spread {
        self.input(pin.input_index())
    }

    /// The shared spread at any input (cheap to pass on unchanged).
    pub fn spread_arc(&self, pin: impl InputPin) -> &Arc<Spread> {
        self.input_arc(pin.input_index())
    }

    /// The objects at a resource input; a slice of another type is an error
    /// naming the pin.
    pub fn resources<T: Send + Sync + 'static>(
        &self,
        pin: In<Res<T>>,
    ) -> Result<Vec<Arc<T>>, NodeError> {
        self.resources_at(pin.index)
    }

    /// [`EvalContext::resources`] by position, for nodes that still read
    /// their pins by number.
    pub fn resources_at<T: Send + Sync + 'static>(
        &self,
        index: usize,
    ) -> Result<Vec<Arc<T>>, NodeError> {
        match self.input(index) {
            Spread::Resource(_, handles) => handles
                .iter()
                .map(|h| {
                    h.downcast_arc::<T>()
                        .ok_or_else(|| self.input_error(index, "holds a resource of another kind"))
                })
                .collect(),
            other => Err(self.input_error(
                index,
                format!("expected a resource, got {}", other.type_name()),
            )),
        }
    }

    /// The first object at a resource input, if any.
    pub fn first_resource<T: Send + Sync + 'static>(
        &self,
        pin: In<Res<T>>,
    ) -> Result<Option<Arc<T>>, NodeError> {
        Ok(self.resources(pin)?.into_iter().next())
    }

    /// Every slice of an enum input as its value; an option the pin does not
    /// know is an error naming the pin and the option.
    pub fn choices<E: Copy + PartialEq + Send + Sync + 'static>(
        &self,
        pin: In<Choice<E>>,
    ) -> Result<Vec<E>, NodeError> {
        let (choices, _) = pin.meta;
        self.enum_slices(pin.index)?
            .iter()
            .map(|option| {
                choices.value(option).ok_or_else(|| {
                    self.input_error(
                        pin.index,
                        format!(
                            "`{option}` is not one of {}: {}",
                            choices.def.name,
                            choices.def.options.join(", ")
                        ),
                    )
                })
            })
            .collect()
    }

    /// The first slice of an enum input as its value (the declared default
    /// when the spread is empty).
    pub fn choice<E: Copy + PartialEq + Send + Sync + 'static>(
        &self,
        pin: In<Choice<E>>,
    ) -> Result<E, NodeError> {
        let (choices, default) = pin.meta;
        match self.enum_slices(pin.index)?.first() {
            None => Ok(choices.values[default]),
            Some(option) => choices.value(option).ok_or_else(|| {
                self.input_error(
                    pin.index,
                    format!(
                        "`{option}` is not one of {}: {}",
                        choices.def.name,
                        choices.def.options.join(", ")
                    ),
                )
            }),
        }
    }

    /// An error naming any input, for node code to return.
    pub fn error(&self, pin: impl InputPin, message: impl Into<String>) -> NodeError {
        self.input_error(pin.input_index(), message)
    }

    /// Write a value output.
    pub fn put<T: SliceValue + PinData>(&mut self, pin: Out<T>, values: Vec<T>) {
        self.set(pin.index, values);
    }

    /// Write any output as a whole spread.
    pub fn put_spread(&mut self, pin: impl OutputPin, spread: Spread) {
        self.set_output(pin.output_index(), spread);
    }

    /// Pass a shared spread on to any output without copying it.
    pub fn put_arc(&mut self, pin: impl OutputPin, spread: Arc<Spread>) {
        self.set_output_arc(pin.output_index(), spread);
    }

    /// Write a resource output.
    pub fn put_resources<T: Send + Sync + 'static>(
        &mut self,
        pin: Out<Res<T>>,
        values: Vec<Arc<T>>,
    ) {
        let kind = pin.meta;
        self.set_output(
            pin.index,
            Spread::Resource(kind, values.into_iter().map(Resource::from_arc).collect()),
        );
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::NodeDef;

    #[derive(Clone, Copy, Debug, PartialEq)]
    enum Mode {
        Fast,
        Exact,
    }

    static MODES: Choices<Mode> =
        Choices::new("Test Mode", &["Fast", "Exact"], &[Mode::Fast, Mode::Exact]);

    #[test]
    fn handles_follow_declaration_order_and_types() {
        let def = NodeDef::new("Typed", "Test", "").with_pins(|p| {
            let a = p.input("A", 1.0f32);
            let mode = p.input_choice("Mode", &MODES, Mode::Exact);
            p.range(0.0, 1.0);
            let texture = p.input_resource::<String>("Thing", ResourceKind::Texture);
            let out = p.output::<f32>("Out");
            assert_eq!(
                (a.index(), mode.index(), texture.index(), out.index()),
                (0, 1, 2, 0)
            );
            move |cx| {
                let a = cx.first(a, 0.0)?;
                let mode = cx.choice(mode)?;
                cx.put(out, vec![if mode == Mode::Exact { a * 2.0 } else { a }]);
                Ok(())
            }
        });
        assert_eq!(def.inputs.len(), 3);
        assert_eq!(def.inputs[1].default, Spread::Enum(vec!["Exact".into()]));
        assert_eq!(def.inputs[1].range, Some((0.0, 1.0)));
        assert_eq!(def.inputs[2].ty, PinType::Resource(ResourceKind::Texture));
        assert_eq!(def.outputs[0].ty, PinType::Float);
    }

    /// Evaluate `def` once over `inputs` (the defaults where `None`).
    fn evaluate(def: &NodeDef, inputs: Vec<Option<Spread>>) -> Result<Vec<Arc<Spread>>, NodeError> {
        let inputs: Vec<Arc<Spread>> = def
            .inputs
            .iter()
            .zip(inputs)
            .map(|(pin, given)| Arc::new(given.unwrap_or_else(|| pin.default.clone())))
            .collect();
        let mut outputs: Vec<Arc<Spread>> = def
            .outputs
            .iter()
            .map(|p| Arc::new(p.default.clone()))
            .collect();
        let clock = crate::FrameClock::default();
        let mut probes = crate::ProbeLog::default();
        let services = crate::Services::default();
        let mut cx = EvalContext::new(
            &clock,
            &inputs,
            &def.inputs,
            &mut outputs,
            &mut probes,
            &services,
            crate::NodeId(0),
        );
        def.instantiate().evaluate(&mut cx)?;
        Ok(outputs)
    }

    fn doubler() -> NodeDef {
        NodeDef::new("Typed", "Test", "").with_pins(|p| {
            let a = p.input("A", 1.0f32);
            let mode = p.input_choice("Mode", &MODES, Mode::Exact);
            let things = p.input_resource::<String>("Things", ResourceKind::Texture);
            let out = p.output::<f32>("Out");
            let passed = p.output_resource::<String>("Things", ResourceKind::Texture);
            move |cx| {
                let a = cx.first(a, 0.0)?;
                let factor = match cx.choice(mode)? {
                    Mode::Exact => 2.0,
                    Mode::Fast => 1.0,
                };
                cx.put(out, vec![a * factor]);
                let things = cx.resources(things)?;
                cx.put_resources(passed, things);
                Ok(())
            }
        })
    }

    #[test]
    fn evaluation_reads_and_writes_through_the_handles() {
        let def = doubler();
        let out = evaluate(&def, vec![Some(Spread::Float(vec![3.0])), None, None]).unwrap();
        assert_eq!(*out[0], Spread::Float(vec![6.0]));
        let out = evaluate(
            &def,
            vec![None, Some(Spread::Enum(vec!["Fast".into()])), None],
        )
        .unwrap();
        assert_eq!(*out[0], Spread::Float(vec![1.0]));
        // An empty enum spread reads as the declared default.
        let out = evaluate(&def, vec![None, Some(Spread::Enum(vec![])), None]).unwrap();
        assert_eq!(*out[0], Spread::Float(vec![2.0]));
        let thing = Resource::new("a texture".to_string());
        let out = evaluate(
            &def,
            vec![
                None,
                None,
                Some(Spread::Resource(ResourceKind::Texture, vec![thing.clone()])),
            ],
        )
        .unwrap();
        assert_eq!(
            *out[1],
            Spread::Resource(ResourceKind::Texture, vec![thing])
        );
    }

    #[test]
    fn a_wrong_option_or_resource_names_the_pin() {
        let def = doubler();
        let error = evaluate(
            &def,
            vec![None, Some(Spread::Enum(vec!["Slow".into()])), None],
        )
        .unwrap_err();
        let text = error.to_string();
        assert!(
            text.contains("Mode") && text.contains("`Slow`") && text.contains("Fast, Exact"),
            "{text}"
        );
        let wrong = Resource::new(7u32);
        let error = evaluate(
            &def,
            vec![
                None,
                None,
                Some(Spread::Resource(ResourceKind::Texture, vec![wrong])),
            ],
        )
        .unwrap_err();
        assert!(error.to_string().contains("Things"), "{error}");
    }

    #[test]
    fn choices_name_and_value_agree() {
        assert_eq!(MODES.value("Fast"), Some(Mode::Fast));
        assert_eq!(MODES.value("Slow"), None);
        assert_eq!(MODES.value("exact"), Some(Mode::Exact));
        assert_eq!(MODES.name(Mode::Exact), "Exact");
    }
}
