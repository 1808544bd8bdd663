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
use spreadlight_graph::{EvalContext, In, Node, NodeDef, NodeError, Out, Pins, Registry};

pub use functions::FUNCTIONS;
pub use parse::ExprError;
pub use typed::{Compiled, Ty, Value, compile, eval};

const CATEGORY: &str = "Value";

/// The most distinct expressions one node keeps checked.
const CACHE: usize = 16;

/// A pin type the expression language knows.
trait ExprType: crate::typed::Value + Copy {
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
    NodeDef::new(
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
    .with_pins_node(|p| {
        let expression = p.input("Expression", example.to_owned());
        let vector_ty = if T::TY == Ty::Mat4 { Ty::Vec3 } else { T::TY };
        let vars: Vec<(&'static str, VarPin)> = scalars
            .iter()
            .map(|&n| (n, Ty::Scalar))
            .chain(vectors.iter().map(|&n| (n, vector_ty)))
            .chain(matrices.iter().map(|&n| (n, Ty::Mat4)))
            .map(|(n, ty)| (n, VarPin::declare(p, n, ty)))
            .collect();
        let output = p.output::<T>("Output");
        move || ExprNode::<T> {
            expression,
            vars: vars.clone(),
            output,
            cache: Vec::new(),
        }
    })
}

/// A variable's input pin, of the type the expression sees it as.
#[derive(Clone, Copy)]
enum VarPin {
    Scalar(In<f32>),
    Vec2(In<Vec2>),
    Vec3(In<Vec3>),
    Vec4(In<Vec4>),
    Mat4(In<Mat4>),
}

impl VarPin {
    /// Declare the pin `name` for a variable of type `ty` (zero, or the identity, by default).
    fn declare(p: &mut Pins<'_>, name: &'static str, ty: Ty) -> VarPin {
        match ty {
            Ty::Scalar => VarPin::Scalar(p.input(name, 0.0f32)),
            Ty::Vec2 => VarPin::Vec2(p.input(name, Vec2::ZERO)),
            Ty::Vec3 => VarPin::Vec3(p.input(name, Vec3::ZERO)),
            Ty::Vec4 => VarPin::Vec4(p.input(name, Vec4::ZERO)),
            Ty::Mat4 => VarPin::Mat4(p.input(name, Mat4::IDENTITY)),
        }
    }

    fn ty(self) -> Ty {
        match self {
            VarPin::Scalar(_) => Ty::Scalar,
            VarPin::Vec2(_) => Ty::Vec2,
            VarPin::Vec3(_) => Ty::Vec3,
            VarPin::Vec4(_) => Ty::Vec4,
            VarPin::Mat4(_) => Ty::Mat4,
        }
    }

    /// The pin's slices as expression values.
    fn values(self, cx: &EvalContext<'_>) -> Result<Vec<Value>, NodeError> {
        fn of<T: crate::typed::Value + Copy>(
            cx: &EvalContext<'_>,
            pin: In<T>,
            f: fn(T) -> Value,
        ) -> Result<Vec<Value>, NodeError> {
            Ok(cx.get(pin)?.iter().map(|&x| f(x)).collect())
        }
        match self {
            VarPin::Scalar(pin) => of(cx, pin, Value::Scalar),
            VarPin::Vec2(pin) => of(cx, pin, Value::Vec2),
            VarPin::Vec3(pin) => of(cx, pin, Value::Vec3),
            VarPin::Vec4(pin) => of(cx, pin, Value::Vec4),
            VarPin::Mat4(pin) => of(cx, pin, Value::Mat4),
        }
    }
}

struct ExprNode<T: ExprType> {
    expression: In<String>,
    /// The variables by name, each with its pin.
    vars: Vec<(&'static str, VarPin)>,
    output: Out<T>,
    /// Checked expressions by their text, most recent last.
    cache: Vec<(String, Compiled)>,
}

impl<T: ExprType> ExprNode<T> {
    /// The checked form of `text`, from the cache or compiled now.
    fn compiled(&mut self, cx: &EvalContext<'_>, text: &str) -> Result<usize, NodeError> {
        if let Some(k) = self.cache.iter().position(|(t, _)| t == text) {
            return Ok(k);
        }
        let vars: Vec<(&'static str, Ty)> =
            self.vars.iter().map(|&(n, pin)| (n, pin.ty())).collect();
        let c =
            compile(text, &vars).map_err(|e| cx.error(self.expression, format!("`{text}` {e}")))?;
        let result_fits = c.ty == T::TY || (c.ty == Ty::Scalar && T::TY != Ty::Mat4);
        if !result_fits {
            return Err(cx.error(
                self.expression,
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
        let texts = cx.get(self.expression)?;
        let inputs = self
            .vars
            .iter()
            .map(|&(_, pin)| pin.values(cx))
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
        cx.put(self.output, out);
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
