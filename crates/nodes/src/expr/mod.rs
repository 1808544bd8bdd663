//! `Expr`: a typed expression node. Its input pins are the expression's
//! variables by name (`a`, `b`, ... for scalars, `u`, `v` for vectors, `m`
//! for a transform), its output type is the node variant's: `Expr (Value)`,
//! `Expr (Vector 2d)`, `Expr (Vector 3d)`, `Expr (Vector 4d)`, `Expr (Transform)`.
//!
//! The language is small and our own (`parse.rs`, `typed.rs`) rather than a
//! crate such as evalexpr or meval: those evaluate scalars (evalexpr adds
//! tuples, untyped), while patchers need vectors and matrices with GLSL-like
//! rules checked before the first slice runs, and errors that point at a
//! character of the expression. Every pin spreads, the expression too; each
//! distinct expression is checked once and cached.

mod functions;
mod parse;
mod typed;
mod values;

use glam::{Mat4, Vec2, Vec3, Vec4};
use spreadlight_graph::spread::{slice_count, wrapped};
use spreadlight_graph::{EvalContext, Node, NodeDef, NodeError, Registry, SliceValue};

pub use functions::FUNCTIONS;
pub use parse::ExprError;
pub use typed::{Compiled, Ty, Value, compile, eval};

const CATEGORY: &str = "Value";

/// The most distinct expressions one node keeps checked.
const CACHE: usize = 16;

/// A pin type the expression language knows.
trait ExprType: SliceValue + Copy {
    const TY: Ty;
    /// The output from a result of the node's type, or a scalar spread over it; non-finite parts become 0.
    fn from_value(v: Value) -> Self;
}

fn finite(x: f32) -> f32 {
    if x.is_finite() { x } else { 0.0 }
}

impl ExprType for f32 {
    const TY: Ty = Ty::Scalar;
    fn from_value(v: Value) -> Self {
        match v {
            Value::Scalar(s) => finite(s),
            _ => 0.0,
        }
    }
}

macro_rules! vector_type {
    ($t:ty, $variant:ident) => {
        impl ExprType for $t {
            const TY: Ty = Ty::$variant;
            fn from_value(v: Value) -> Self {
                let out = match v {
                    Value::$variant(x) => x,
                    Value::Scalar(s) => <$t>::splat(s),
                    _ => <$t>::ZERO,
                };
                <$t>::from_array(out.to_array().map(finite))
            }
        }
    };
}
vector_type!(Vec2, Vec2);
vector_type!(Vec3, Vec3);
vector_type!(Vec4, Vec4);

impl ExprType for Mat4 {
    const TY: Ty = Ty::Mat4;
    fn from_value(v: Value) -> Self {
        match v {
            Value::Mat4(m) if m.is_finite() => m,
            _ => Mat4::IDENTITY,
        }
    }
}

pub fn register(r: &mut Registry) {
    r.add(expr_node::<f32>(
        "Expr (Value)",
        "a + b",
        &["a", "b", "c", "d"],
        &[],
        &[],
    ));
    r.add(expr_node::<Vec2>(
        "Expr (Vector 2d)",
        "u + v * a",
        &["a", "b"],
        &["u", "v"],
        &[],
    ));
    r.add(expr_node::<Vec3>(
        "Expr (Vector 3d)",
        "u + v * a",
        &["a", "b"],
        &["u", "v"],
        &[],
    ));
    r.add(expr_node::<Vec4>(
        "Expr (Vector 4d)",
        "u + v * a",
        &["a", "b"],
        &["u", "v"],
        &[],
    ));
    r.add(expr_node::<Mat4>(
        "Expr (Transform)",
        "translate(u) * rotate_y(a) * m",
        &["a", "b"],
        &["u", "v"],
        &["m"],
    ));
}

/// The pins of one variant: scalars, then vectors of the output's type (Vec3 for
/// transforms), then matrices.
fn expr_node<T: ExprType>(
    name: &'static str,
    example: &str,
    scalars: &'static [&'static str],
    vectors: &'static [&'static str],
    matrices: &'static [&'static str],
) -> NodeDef {
    let mut def = NodeDef::new(
        name,
        CATEGORY,
        "Evaluates Expression over its inputs, slice by slice (every pin spreads, the \
         Expression too). The other input pins are the variables, by their names \
         (whichever this node has): a, b, c, d scalars; u, v vectors of the node's type (Vec3 in \
         Expr (Transform)); m a transform. Operators + - * \
         / % ^ and comparisons < > <= >= == != (1 or 0); a scalar with a vector applies to each \
         component, m * v transforms a point, m * m composes; swizzles like u.xy, u.zyx; \
         constants pi, tau, e; functions sin cos tan asin acos atan sqrt abs floor ceil round \
         fract exp log sign atan2 pow min max mod step clamp mix smoothstep length distance dot \
         normalize cross vec2 vec3 vec4 translate scale rotate_x rotate_y rotate_z transpose \
         inverse identity if(c, a, b). Angles in radians. The result must be the node's type (a \
         scalar fills a vector). A wrong expression is an error on Expression naming the \
         character; a non-finite result component is output as 0.",
    )
    .input("Expression", example.to_owned());
    let vector_ty = if T::TY == Ty::Mat4 { Ty::Vec3 } else { T::TY };
    for &pin in scalars {
        def = def.input(pin, 0.0f32);
    }
    for &pin in vectors {
        def = match vector_ty {
            Ty::Vec2 => def.input(pin, Vec2::ZERO),
            Ty::Vec4 => def.input(pin, Vec4::ZERO),
            _ => def.input(pin, Vec3::ZERO),
        };
    }
    for &pin in matrices {
        def = def.input(pin, Mat4::IDENTITY);
    }
    let vars: Vec<(&'static str, Ty)> = scalars
        .iter()
        .map(|&n| (n, Ty::Scalar))
        .chain(vectors.iter().map(|&n| (n, vector_ty)))
        .chain(matrices.iter().map(|&n| (n, Ty::Mat4)))
        .collect();
    def.output::<T>("Output").construct(move || ExprNode::<T> {
        vars: vars.clone(),
        cache: Vec::new(),
        _out: std::marker::PhantomData,
    })
}

struct ExprNode<T> {
    vars: Vec<(&'static str, Ty)>,
    /// Checked expressions by their text, most recent last.
    cache: Vec<(String, Compiled)>,
    _out: std::marker::PhantomData<T>,
}

/// One input pin's slices as expression values.
fn values(cx: &EvalContext<'_>, pin: usize, ty: Ty) -> Result<Vec<Value>, NodeError> {
    fn of<T: SliceValue + Copy>(
        cx: &EvalContext<'_>,
        pin: usize,
        f: fn(T) -> Value,
    ) -> Result<Vec<Value>, NodeError> {
        Ok(cx.slices::<T>(pin)?.iter().map(|&x| f(x)).collect())
    }
    match ty {
        Ty::Scalar => of::<f32>(cx, pin, Value::Scalar),
        Ty::Vec2 => of::<Vec2>(cx, pin, Value::Vec2),
        Ty::Vec3 => of::<Vec3>(cx, pin, Value::Vec3),
        Ty::Vec4 => of::<Vec4>(cx, pin, Value::Vec4),
        Ty::Mat4 => of::<Mat4>(cx, pin, Value::Mat4),
    }
}

impl<T: ExprType> ExprNode<T> {
    /// The checked form of `text`, from the cache or compiled now.
    fn compiled(&mut self, cx: &EvalContext<'_>, text: &str) -> Result<usize, NodeError> {
        if let Some(k) = self.cache.iter().position(|(t, _)| t == text) {
            return Ok(k);
        }
        let c =
            compile(text, &self.vars).map_err(|e| cx.input_error(0, format!("`{text}` {e}")))?;
        let result_fits = c.ty == T::TY || (c.ty == Ty::Scalar && T::TY != Ty::Mat4);
        if !result_fits {
            return Err(cx.input_error(
                0,
                format!("`{text}` gives {:?}, this node outputs {:?}", c.ty, T::TY),
            ));
        }
        if self.cache.len() == CACHE {
            self.cache.remove(0);
        }
        self.cache.push((text.to_owned(), c));
        Ok(self.cache.len() - 1)
    }
}

impl<T: ExprType> Node for ExprNode<T> {
    fn evaluate(&mut self, cx: &mut EvalContext<'_>) -> Result<(), NodeError> {
        let texts = cx.slices::<String>(0)?;
        let inputs = self
            .vars
            .iter()
            .enumerate()
            .map(|(k, (_, ty))| values(cx, k + 1, *ty))
            .collect::<Result<Vec<_>, _>>()?;
        let n = slice_count([texts.len()].into_iter().chain(inputs.iter().map(Vec::len)));
        let mut out = Vec::with_capacity(n);
        let mut slot = vec![Value::Scalar(0.0); inputs.len()];
        for i in 0..n {
            let k = self.compiled(cx, wrapped(texts, i).as_str())?;
            for (s, input) in slot.iter_mut().zip(&inputs) {
                *s = *wrapped(input, i);
            }
            out.push(T::from_value(eval(&self.cache[k].1, &slot)));
        }
        cx.set(0, out);
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use glam::{Mat4, Vec3};
    use spreadlight_graph::Spread;

    use crate::testing::{eval_err, eval_out, floats, strings_of};

    #[test]
    fn expr_value_spreads_inputs_and_expressions() {
        let out: Vec<f32> = eval_out(
            "Expr (Value)",
            &[
                ("Expression", strings_of(&["a * b", "a - b"])),
                ("a", floats(&[3.0])),
                ("b", floats(&[2.0, 5.0, 1.0])),
            ],
            "Output",
        );
        assert_eq!(out, [6.0, -2.0, 3.0]);
        // Division by zero is not finite: the slice is 0.
        let out: Vec<f32> = eval_out(
            "Expr (Value)",
            &[("Expression", strings_of(&["1 / a"]))],
            "Output",
        );
        assert_eq!(out, [0.0]);
    }

    #[test]
    fn expr_vectors_and_transforms() {
        let out: Vec<Vec3> = eval_out(
            "Expr (Vector 3d)",
            &[
                ("Expression", strings_of(&["normalize(u) * a + v.zyx", "a"])),
                ("a", floats(&[2.0])),
                ("u", Spread::Vec3(vec![Vec3::new(0.0, 3.0, 0.0)])),
                ("v", Spread::Vec3(vec![Vec3::new(1.0, 0.0, 0.0)])),
            ],
            "Output",
        );
        assert_eq!(out, [Vec3::new(0.0, 2.0, 1.0), Vec3::splat(2.0)]);
        let out: Vec<Mat4> = eval_out(
            "Expr (Transform)",
            &[
                ("Expression", strings_of(&["translate(u) * m"])),
                ("u", Spread::Vec3(vec![Vec3::X])),
            ],
            "Output",
        );
        assert_eq!(out, [Mat4::from_translation(Vec3::X)]);
    }

    #[test]
    fn bad_expressions_are_errors_on_the_expression_pin() {
        let e = eval_err(
            "Expr (Value)",
            &[("Expression", strings_of(&["a +* b"]))],
            "Expression",
        );
        assert!(e.to_string().contains("character 4"), "{e}");
        let e = eval_err(
            "Expr (Value)",
            &[("Expression", strings_of(&["vec2(a, b)"]))],
            "Expression",
        );
        assert!(e.to_string().contains("this node outputs Scalar"), "{e}");
        eval_err(
            "Expr (Transform)",
            &[("Expression", strings_of(&["a"]))],
            "Expression",
        );
    }
}
