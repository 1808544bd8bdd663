//! Types and evaluation: the syntax tree checked against the types of the
//! named inputs once (so a wrong expression is an error before any slice
//! runs), then evaluated per slice over plain values.
//!
//! Scalars and vectors mix as in GLSL: a scalar with a vector applies to
//! every component, two vectors must be the same size and combine
//! component-wise; `m * v` transforms (a 3d vector as a point), `m * m`
//! composes. Angles are radians, as in vvvv's Expr.

use glam::Vec4;

use super::functions::{FUNCTIONS, Func, call, call_type, lookup};
use super::parse::{Ast, BinOp, ExprError, error, parse};
pub use super::values::{Ty, Value};
use super::values::{map, unify};

/// A checked expression: a tree over input slots, and its result type.
#[derive(Clone, Debug)]
pub struct Compiled {
    root: Node,
    pub ty: Ty,
}

#[derive(Clone, Debug)]
enum Node {
    Const(Value),
    Input(usize),
    Call(Func, Vec<Node>),
    Binary(BinOp, Box<Node>, Box<Node>),
    Neg(Box<Node>),
    Swizzle(Box<Node>, [usize; 4], usize),
}

/// Parse `text` and check it against the named inputs (name and type, in slot order).
pub fn compile(text: &str, inputs: &[(&str, Ty)]) -> Result<Compiled, ExprError> {
    let ast = parse(text)?;
    let (root, ty) = check(&ast, inputs)?;
    Ok(Compiled { root, ty })
}

fn check(ast: &Ast, inputs: &[(&str, Ty)]) -> Result<(Node, Ty), ExprError> {
    match ast {
        Ast::Num(v) => Ok((Node::Const(Value::Scalar(*v)), Ty::Scalar)),
        Ast::Name(name, at) => {
            if let Some(k) = inputs.iter().position(|(n, _)| n == name) {
                return Ok((Node::Input(k), inputs[k].1));
            }
            let c = match name.as_str() {
                "pi" => std::f32::consts::PI,
                "tau" => std::f32::consts::TAU,
                "e" => std::f32::consts::E,
                _ => {
                    let names: Vec<&str> = inputs.iter().map(|i| i.0).collect();
                    return error(
                        *at,
                        format!(
                            "unknown name `{name}` (inputs: {}; constants: pi, tau, e)",
                            names.join(", ")
                        ),
                    );
                }
            };
            Ok((Node::Const(Value::Scalar(c)), Ty::Scalar))
        }
        Ast::Neg(inner) => {
            let (n, t) = check(inner, inputs)?;
            Ok((Node::Neg(Box::new(n)), t))
        }
        Ast::Swizzle(inner, s, at) => {
            let (n, t) = check(inner, inputs)?;
            let Some(size) = t.size().filter(|&s| s > 1) else {
                return error(*at, format!("`.{s}` needs a vector, this is {t:?}"));
            };
            if s.is_empty() || s.len() > 4 {
                return error(*at, format!("`.{s}` picks 1 to 4 components"));
            }
            let mut idx = [0usize; 4];
            for (k, c) in s.chars().enumerate() {
                let i = "xyzw".find(c).or_else(|| "rgba".find(c));
                match i {
                    Some(i) if i < size => idx[k] = i,
                    _ => return error(*at, format!("`.{s}`: {t:?} has no component `{c}`")),
                }
            }
            Ok((
                Node::Swizzle(Box::new(n), idx, s.len()),
                Ty::of_size(s.len()),
            ))
        }
        Ast::Binary(op, l, r, at) => {
            let (ln, lt) = check(l, inputs)?;
            let (rn, rt) = check(r, inputs)?;
            let ty = binary_type(*op, lt, rt, *at)?;
            Ok((Node::Binary(*op, Box::new(ln), Box::new(rn)), ty))
        }
        Ast::Call(name, args, at) => {
            let Some(func) = lookup(name) else {
                return error(
                    *at,
                    format!("unknown function `{name}` (known: {FUNCTIONS})"),
                );
            };
            let checked = args
                .iter()
                .map(|a| check(a, inputs))
                .collect::<Result<Vec<_>, _>>()?;
            let tys: Vec<Ty> = checked.iter().map(|c| c.1).collect();
            let ty = call_type(func, name, &tys, *at)?;
            Ok((
                Node::Call(func, checked.into_iter().map(|c| c.0).collect()),
                ty,
            ))
        }
    }
}

fn binary_type(op: BinOp, l: Ty, r: Ty, at: usize) -> Result<Ty, ExprError> {
    use BinOp::*;
    use Ty::*;
    let sym = match op {
        Add => "+",
        Sub => "-",
        Mul => "*",
        Div => "/",
        Rem => "%",
        Pow => "^",
        Lt => "<",
        Gt => ">",
        Le => "<=",
        Ge => ">=",
        Eq => "==",
        Ne => "!=",
    };
    let bad = || error(at, format!("cannot apply `{sym}` to {l:?} and {r:?}"));
    match (op, l, r) {
        (Lt | Gt | Le | Ge | Eq | Ne, Scalar, Scalar) => Ok(Scalar),
        (Lt | Gt | Le | Ge | Eq | Ne, _, _) => bad(),
        (Add | Sub, Mat4, Mat4) | (Mul, Mat4, Mat4) => Ok(Mat4),
        (Mul, Mat4, Vec3) => Ok(Vec3),
        (Mul, Mat4, Vec4) => Ok(Vec4),
        (Mul | Div, Mat4, Scalar) | (Mul, Scalar, Mat4) => Ok(Mat4),
        (_, Mat4, _) | (_, _, Mat4) => bad(),
        (Pow, _, Scalar) => Ok(l),
        _ => unify(&[l, r], at, &format!("`{sym}`")),
    }
}

/// Evaluate with one value per input slot (of the checked types).
pub fn eval(c: &Compiled, inputs: &[Value]) -> Value {
    eval_node(&c.root, inputs)
}

fn eval_node(node: &Node, inputs: &[Value]) -> Value {
    match node {
        Node::Const(v) => *v,
        Node::Input(k) => inputs.get(*k).copied().unwrap_or(Value::Scalar(0.0)),
        Node::Neg(inner) => match eval_node(inner, inputs) {
            Value::Mat4(m) => Value::Mat4(-m),
            v => map(&[v], |x| -x[0]),
        },
        Node::Swizzle(inner, idx, len) => {
            let (v, _) = eval_node(inner, inputs).lanes().unwrap_or((Vec4::ZERO, 1));
            let mut out = Vec4::ZERO;
            for k in 0..*len {
                out[k] = v[idx[k]];
            }
            Value::from_lanes(out, *len)
        }
        Node::Binary(op, l, r) => binary(*op, eval_node(l, inputs), eval_node(r, inputs)),
        Node::Call(func, args) => {
            let a: Vec<Value> = args.iter().map(|n| eval_node(n, inputs)).collect();
            call(*func, &a)
        }
    }
}

fn binary(op: BinOp, l: Value, r: Value) -> Value {
    use BinOp::*;
    let truth = |b: bool| Value::Scalar(if b { 1.0 } else { 0.0 });
    match (op, l, r) {
        (Mul, Value::Mat4(a), Value::Mat4(b)) => Value::Mat4(a * b),
        (Add, Value::Mat4(a), Value::Mat4(b)) => Value::Mat4(a + b),
        (Sub, Value::Mat4(a), Value::Mat4(b)) => Value::Mat4(a - b),
        (Mul, Value::Mat4(m), Value::Vec3(v)) => Value::Vec3(m.transform_point3(v)),
        (Mul, Value::Mat4(m), Value::Vec4(v)) => Value::Vec4(m * v),
        (Mul, Value::Mat4(m), Value::Scalar(s)) | (Mul, Value::Scalar(s), Value::Mat4(m)) => {
            Value::Mat4(m * s)
        }
        (Div, Value::Mat4(m), Value::Scalar(s)) => Value::Mat4(m * (1.0 / s)),
        (Lt, a, b) => truth(a.scalar() < b.scalar()),
        (Gt, a, b) => truth(a.scalar() > b.scalar()),
        (Le, a, b) => truth(a.scalar() <= b.scalar()),
        (Ge, a, b) => truth(a.scalar() >= b.scalar()),
        (Eq, a, b) => truth(a.scalar() == b.scalar()),
        (Ne, a, b) => truth(a.scalar() != b.scalar()),
        (op, a, b) => map(&[a, b], |x| match op {
            Add => x[0] + x[1],
            Sub => x[0] - x[1],
            Mul => x[0] * x[1],
            Div => x[0] / x[1],
            Rem => x[0].rem_euclid(x[1]),
            _ => x[0].powf(x[1]),
        }),
    }
}

#[cfg(test)]
mod tests {
    use glam::{Mat4, Vec2, Vec3};

    use super::{Ty, Value, compile, eval};

    fn run(text: &str, inputs: &[(&str, Ty)], values: &[Value]) -> Value {
        let c = compile(text, inputs).unwrap_or_else(|e| panic!("{text}: {e}"));
        eval(&c, values)
    }

    #[test]
    fn scalars_vectors_and_matrices() {
        let s = [("a", Ty::Scalar), ("b", Ty::Scalar)];
        assert_eq!(
            run(
                "a + b * 2 ^ 2",
                &s,
                &[Value::Scalar(1.0), Value::Scalar(3.0)]
            ),
            Value::Scalar(13.0)
        );
        assert_eq!(
            run(
                "if(a > b, a, b) + max(a, b) % 2",
                &s,
                &[Value::Scalar(1.0), Value::Scalar(3.0)]
            ),
            Value::Scalar(4.0)
        );
        let v = [("a", Ty::Scalar), ("u", Ty::Vec3), ("v", Ty::Vec3)];
        let vals = [
            Value::Scalar(2.0),
            Value::Vec3(Vec3::X),
            Value::Vec3(Vec3::Y),
        ];
        assert_eq!(
            run("cross(u, v) * a + u", &v, &vals),
            Value::Vec3(Vec3::new(1.0, 0.0, 2.0))
        );
        assert_eq!(run("dot(u + v, u)", &v, &vals), Value::Scalar(1.0));
        assert_eq!(run("(u + v).yx", &v, &vals), Value::Vec2(Vec2::ONE));
        assert_eq!(
            run("vec3(u.xy, a)", &v, &vals),
            Value::Vec3(Vec3::new(1.0, 0.0, 2.0))
        );
        assert_eq!(run("vec3(a)", &v, &vals), Value::Vec3(Vec3::splat(2.0)));
        let m = [("m", Ty::Mat4), ("u", Ty::Vec3)];
        let vals = [
            Value::Mat4(Mat4::from_translation(Vec3::Z)),
            Value::Vec3(Vec3::X),
        ];
        assert_eq!(
            run("m * u", &m, &vals),
            Value::Vec3(Vec3::new(1.0, 0.0, 1.0))
        );
        assert_eq!(
            run("translate(u) * inverse(m)", &m, &vals),
            Value::Mat4(Mat4::from_translation(Vec3::new(1.0, 0.0, -1.0)))
        );
        let Value::Vec3(r) = run("rotate_z(pi / 2) * u", &m, &vals) else {
            panic!("vec3")
        };
        assert!((r - Vec3::Y).length() < 1e-6, "{r}");
    }

    #[test]
    fn type_errors_name_the_place() {
        let v = [("a", Ty::Scalar), ("u", Ty::Vec3), ("w", Ty::Vec2)];
        let e = compile("a + u + w", &v).expect_err("mismatch");
        assert_eq!(e.at, 6);
        assert!(e.message.contains("Vec3 and Vec2"), "{e}");
        assert!(
            compile("u.q", &v)
                .expect_err("swizzle")
                .message
                .contains("no component")
        );
        assert!(
            compile("foo(a)", &v)
                .expect_err("func")
                .message
                .contains("unknown function")
        );
        assert!(
            compile("z", &v)
                .expect_err("name")
                .message
                .contains("inputs: a, u, w")
        );
        assert!(
            compile("sin(a, a)", &v)
                .expect_err("arity")
                .message
                .contains("1 argument")
        );
        assert!(compile("u < a", &v).is_err());
        assert!(compile("vec4(u)", &v).is_err());
    }
}
