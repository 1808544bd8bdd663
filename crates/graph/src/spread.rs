//! Spreads: vvvv's lists of slices, the only thing that flows along links.
//!
//! Every pin carries a spread, never a lone value. The spreading rule is
//! written once, here: a node's output slice count is the largest of its
//! inputs' counts, zero if any input is empty, and shorter inputs wrap around.

use glam::{Mat4, Vec2, Vec3, Vec4};
use serde::{Deserialize, Serialize};

use crate::value::{Color, PinType, Resource, ResourceKind};

/// A list of slices of one type.
///
/// In a `.ron` patch a spread is written with its type, e.g. `Float([0.5, 1.0])`,
/// so a value of the wrong type for its pin is caught on load.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub enum Spread {
    Float(Vec<f32>),
    Int(Vec<i64>),
    Bool(Vec<bool>),
    String(Vec<String>),
    Vec2(Vec<Vec2>),
    Vec3(Vec<Vec3>),
    Vec4(Vec<Vec4>),
    Color(Vec<Color>),
    Mat4(Vec<Mat4>),
    /// Enum choices by name; the pin's [`crate::EnumDef`] says which names are legal.
    Enum(Vec<String>),
    /// Opaque handles: runtime-only, never saved.
    #[serde(skip)]
    Resource(ResourceKind, Vec<Resource>),
}

impl Spread {
    /// An empty spread of the given type.
    pub fn empty(ty: PinType) -> Spread {
        match ty {
            PinType::Float => Spread::Float(Vec::new()),
            PinType::Int => Spread::Int(Vec::new()),
            PinType::Bool => Spread::Bool(Vec::new()),
            PinType::String => Spread::String(Vec::new()),
            PinType::Vec2 => Spread::Vec2(Vec::new()),
            PinType::Vec3 => Spread::Vec3(Vec::new()),
            PinType::Vec4 => Spread::Vec4(Vec::new()),
            PinType::Color => Spread::Color(Vec::new()),
            PinType::Mat4 => Spread::Mat4(Vec::new()),
            PinType::Enum(_) => Spread::Enum(Vec::new()),
            PinType::Resource(kind) => Spread::Resource(kind, Vec::new()),
            // Nothing is known of an unlinked generic input; an empty Float spread stands for "nothing".
            PinType::Any => Spread::Float(Vec::new()),
        }
    }

    pub fn len(&self) -> usize {
        match self {
            Spread::Float(v) => v.len(),
            Spread::Int(v) => v.len(),
            Spread::Bool(v) => v.len(),
            Spread::String(v) => v.len(),
            Spread::Vec2(v) => v.len(),
            Spread::Vec3(v) => v.len(),
            Spread::Vec4(v) => v.len(),
            Spread::Color(v) => v.len(),
            Spread::Mat4(v) => v.len(),
            Spread::Enum(v) => v.len(),
            Spread::Resource(_, v) => v.len(),
        }
    }

    pub fn is_empty(&self) -> bool {
        self.len() == 0
    }

    /// The name of the variant, as written in a patch file.
    pub fn type_name(&self) -> &'static str {
        match self {
            Spread::Float(_) => "Float",
            Spread::Int(_) => "Int",
            Spread::Bool(_) => "Bool",
            Spread::String(_) => "String",
            Spread::Vec2(_) => "Vec2",
            Spread::Vec3(_) => "Vec3",
            Spread::Vec4(_) => "Vec4",
            Spread::Color(_) => "Color",
            Spread::Mat4(_) => "Mat4",
            Spread::Enum(_) => "Enum",
            Spread::Resource(..) => "Resource",
        }
    }

    /// Whether this spread can sit on a pin of type `ty` as it is.
    pub fn fits(&self, ty: PinType) -> bool {
        match (self, ty) {
            (Spread::Resource(k, _), PinType::Resource(want)) => *k == want,
            (Spread::Enum(_), PinType::Enum(_)) | (_, PinType::Any) => true,
            _ => std::mem::discriminant(self) == std::mem::discriminant(&Spread::empty(ty)),
        }
    }

    /// Convert to the type of an input pin, for the links [`PinType::links_to`] allows.
    /// Returns `None` when no conversion exists.
    pub fn convert_to(&self, ty: PinType) -> Option<Spread> {
        if self.fits(ty) {
            return Some(self.clone());
        }
        match (self, ty) {
            (Spread::Int(v), PinType::Float) => {
                Some(Spread::Float(v.iter().map(|&i| i as f32).collect()))
            }
            (Spread::Color(v), PinType::Vec4) => {
                Some(Spread::Vec4(v.iter().map(|c| c.to_vec4()).collect()))
            }
            (Spread::Vec4(v), PinType::Color) => Some(Spread::Color(
                v.iter().map(|&c| Color::from_vec4(c)).collect(),
            )),
            _ => None,
        }
    }

    /// The first non-finite float in the spread, if any: used to keep NaN and
    /// infinity out of patch files and out of targets.
    pub fn first_non_finite(&self) -> Option<usize> {
        fn find<T>(v: &[T], finite: impl Fn(&T) -> bool) -> Option<usize> {
            v.iter().position(|x| !finite(x))
        }
        match self {
            Spread::Float(v) => find(v, |x| x.is_finite()),
            Spread::Vec2(v) => find(v, |x| x.is_finite()),
            Spread::Vec3(v) => find(v, |x| x.is_finite()),
            Spread::Vec4(v) => find(v, |x| x.is_finite()),
            Spread::Color(v) => find(v, |c| c.to_vec4().is_finite()),
            Spread::Mat4(v) => find(v, |m| m.is_finite()),
            _ => None,
        }
    }

    /// A short human-readable preview: the first slices and the count, as vvvv's tooltips show.
    pub fn preview(&self, max_slices: usize) -> String {
        fn list<T: std::fmt::Debug>(v: &[T], max: usize) -> String {
            let shown: Vec<String> = v.iter().take(max).map(|x| format!("{x:?}")).collect();
            let more = if v.len() > max { ", ..." } else { "" };
            format!("[{}{}] ({} slices)", shown.join(", "), more, v.len())
        }
        match self {
            Spread::Float(v) => list(v, max_slices),
            Spread::Int(v) => list(v, max_slices),
            Spread::Bool(v) => list(v, max_slices),
            Spread::String(v) => list(v, max_slices),
            Spread::Vec2(v) => list(v, max_slices),
            Spread::Vec3(v) => list(v, max_slices),
            Spread::Vec4(v) => list(v, max_slices),
            Spread::Color(v) => list(v, max_slices),
            Spread::Mat4(v) => list(v, max_slices),
            Spread::Enum(v) => list(v, max_slices),
            Spread::Resource(kind, v) => format!("{} {kind:?} handle(s)", v.len()),
        }
    }
}

/// The spreading rule: the largest count, or zero when any input is empty.
pub fn slice_count(counts: impl IntoIterator<Item = usize>) -> usize {
    let mut max = 0;
    for n in counts {
        if n == 0 {
            return 0;
        }
        max = max.max(n);
    }
    max
}

/// Slice `i` of `s`, wrapping around: how shorter spreads repeat.
#[inline]
pub fn wrapped<T>(s: &[T], i: usize) -> &T {
    &s[i % s.len()]
}

/// A Rust type that is the slice type of one spread variant.
///
/// Implemented for every plain value type, so node code can ask for `&[f32]`
/// or `&[Vec3]` and return `Vec<T>` without matching on [`Spread`].
pub trait SliceValue: Clone + Send + Sync + 'static {
    const PIN_TYPE: PinType;
    fn slices(spread: &Spread) -> Option<&[Self]>;
    fn into_spread(values: Vec<Self>) -> Spread;
}

macro_rules! slice_value {
    ($t:ty, $variant:ident) => {
        impl SliceValue for $t {
            const PIN_TYPE: PinType = PinType::$variant;
            fn slices(spread: &Spread) -> Option<&[Self]> {
                match spread {
                    Spread::$variant(v) => Some(v),
                    _ => None,
                }
            }
            fn into_spread(values: Vec<Self>) -> Spread {
                Spread::$variant(values)
            }
        }
        impl From<Vec<$t>> for Spread {
            fn from(values: Vec<$t>) -> Spread {
                Spread::$variant(values)
            }
        }
    };
}

slice_value!(f32, Float);
slice_value!(i64, Int);
slice_value!(bool, Bool);
slice_value!(String, String);
slice_value!(Vec2, Vec2);
slice_value!(Vec3, Vec3);
slice_value!(Vec4, Vec4);
slice_value!(Color, Color);
slice_value!(Mat4, Mat4);

/// Apply `f` slice by slice over one input.
pub fn map1<A, O>(a: &[A], mut f: impl FnMut(&A) -> O) -> Vec<O> {
    a.iter().map(&mut f).collect()
}

/// The first `n` slices of `s` repeated as often as needed: spreading as an
/// iterator, with no division per slice (unlike [`wrapped`]).
pub fn cycled<T>(s: &[T], n: usize) -> impl Iterator<Item = &T> {
    s.iter().cycle().take(n)
}

/// Apply `f` slice by slice over two inputs, spreading and wrapping.
pub fn map2<A, B, O>(a: &[A], b: &[B], mut f: impl FnMut(&A, &B) -> O) -> Vec<O> {
    let n = slice_count([a.len(), b.len()]);
    cycled(a, n)
        .zip(cycled(b, n))
        .map(|(x, y)| f(x, y))
        .collect()
}

/// Apply `f` slice by slice over three inputs, spreading and wrapping.
pub fn map3<A, B, C, O>(a: &[A], b: &[B], c: &[C], mut f: impl FnMut(&A, &B, &C) -> O) -> Vec<O> {
    let n = slice_count([a.len(), b.len(), c.len()]);
    cycled(a, n)
        .zip(cycled(b, n))
        .zip(cycled(c, n))
        .map(|((x, y), z)| f(x, y, z))
        .collect()
}

/// Apply `f` slice by slice over four inputs, spreading and wrapping.
pub fn map4<A, B, C, D, O>(
    a: &[A],
    b: &[B],
    c: &[C],
    d: &[D],
    mut f: impl FnMut(&A, &B, &C, &D) -> O,
) -> Vec<O> {
    let n = slice_count([a.len(), b.len(), c.len(), d.len()]);
    cycled(a, n)
        .zip(cycled(b, n))
        .zip(cycled(c, n))
        .zip(cycled(d, n))
        .map(|(((x, y), z), w)| f(x, y, z, w))
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn count_is_largest_input_or_zero_when_any_is_empty() {
        assert_eq!(slice_count([3, 1, 5]), 5);
        assert_eq!(slice_count([3, 0, 5]), 0);
        assert_eq!(slice_count([]), 0);
    }

    #[test]
    fn shorter_inputs_wrap_around() {
        let out = map2(&[1.0f32, 2.0, 3.0, 4.0, 5.0], &[10.0f32, 20.0], |a, b| {
            a + b
        });
        assert_eq!(out, vec![11.0, 22.0, 13.0, 24.0, 15.0]);
        let out = map3(&[1i64], &[1i64, 2], &[100i64, 200, 300], |a, b, c| {
            a + b + c
        });
        assert_eq!(out, vec![102, 203, 302]);
    }

    #[test]
    fn empty_input_gives_empty_output() {
        let out = map2(&[1.0f32, 2.0], &[] as &[f32], |a, b| a + b);
        assert!(out.is_empty());
    }

    #[test]
    fn conversions_follow_link_rules() {
        let ints = Spread::Int(vec![1, 2]);
        assert_eq!(
            ints.convert_to(PinType::Float),
            Some(Spread::Float(vec![1.0, 2.0]))
        );
        assert!(ints.convert_to(PinType::String).is_none());
        for (from, to) in [
            (PinType::Int, PinType::Float),
            (PinType::Color, PinType::Vec4),
            (PinType::Vec4, PinType::Color),
        ] {
            assert!(from.links_to(to));
            assert!(Spread::empty(from).convert_to(to).is_some());
        }
        assert!(!PinType::Float.links_to(PinType::Int));
    }

    #[test]
    fn non_finite_values_are_found() {
        assert_eq!(
            Spread::Float(vec![1.0, f32::NAN]).first_non_finite(),
            Some(1)
        );
        assert_eq!(Spread::Vec3(vec![Vec3::ONE]).first_non_finite(), None);
    }
}
