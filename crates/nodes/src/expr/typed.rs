//! Types and evaluation: the syntax tree checked against the types of the
//! named inputs once (so a wrong expression is an error before any slice
//! runs), then evaluated per slice over plain values.
//!
//! Scalars and vectors mix as in GLSL: a scalar with a vector applies to
//! every component, two vectors must be the same size and combine
//! component-wise; `m * v` transforms (a 3d vector as a point), `m * m`
//! composes. Angles are radians, as in vvvv's Expr.

use glam::{Mat4, Vec2, Vec3, Vec4};

use super::parse::{Ast, BinOp, ExprError, error, parse};

#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Ty {
    Scalar,
    Vec2,
    Vec3,
    Vec4,
    Mat4,
}

impl Ty {
    fn size(self) -> Option<usize> {
        match self {
            Ty::Scalar => Some(1),
            Ty::Vec2 => Some(2),
            Ty::Vec3 => Some(3),
            Ty::Vec4 => Some(4),
            Ty::Mat4 => None,
        }
    }

    fn of_size(n: usize) -> Ty {
        [Ty::Scalar, Ty::Vec2, Ty::Vec3, Ty::Vec4][n.clamp(1, 4) - 1]
    }
}

#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Value {
    Scalar(f32),
    Vec2(Vec2),
    Vec3(Vec3),
    Vec4(Vec4),
    Mat4(Mat4),
}

impl Value {
    /// The components of a scalar or vector in a Vec4, with their count; matrices give none.
    fn lanes(self) -> Option<(Vec4, usize)> {
        Some(match self {
            Value::Scalar(s) => (Vec4::splat(s), 1),
            Value::Vec2(v) => (v.extend(0.0).extend(0.0), 2),
            Value::Vec3(v) => (v.extend(0.0), 3),
            Value::Vec4(v) => (v, 4),
            Value::Mat4(_) => return None,
        })
    }

    fn from_lanes(v: Vec4, n: usize) -> Value {
        match n {
            1 => Value::Scalar(v.x),
            2 => Value::Vec2(v.truncate().truncate()),
            3 => Value::Vec3(v.truncate()),
            _ => Value::Vec4(v),
        }
    }

    /// The scalar inside, or 0 (type checking rules the other cases out).
    fn scalar(self) -> f32 {
        match self {
            Value::Scalar(s) => s,
            _ => 0.0,
        }
    }

    fn matrix(self) -> Mat4 {
        match self {
            Value::Mat4(m) => m,
            _ => Mat4::IDENTITY,
        }
    }
}

/// Built-in functions.
#[derive(Clone, Copy, Debug)]
enum Func {
    /// Component-wise with 1 to 3 arguments (scalars spread over vectors).
    Map1(fn(f32) -> f32),
    Map2(fn(f32, f32) -> f32),
    Map3(fn(f32, f32, f32) -> f32),
    Length,
    Distance,
    Dot,
    Normalize,
    Cross,
    Construct(usize),
    Translate,
    Scale,
    Rotate(fn(f32) -> Mat4),
    Transpose,
    Inverse,
    Identity,
    If,
}

fn lookup(name: &str) -> Option<Func> {
    use Func::*;
    Some(match name {
        "sin" => Map1(f32::sin),
        "cos" => Map1(f32::cos),
        "tan" => Map1(f32::tan),
        "asin" => Map1(|x| x.clamp(-1.0, 1.0).asin()),
        "acos" => Map1(|x| x.clamp(-1.0, 1.0).acos()),
        "atan" => Map1(f32::atan),
        "sqrt" => Map1(|x| x.max(0.0).sqrt()),
        "abs" => Map1(f32::abs),
        "floor" => Map1(f32::floor),
        "ceil" => Map1(f32::ceil),
        "round" => Map1(f32::round),
        "fract" => Map1(|x| x - x.floor()),
        "exp" => Map1(f32::exp),
        "log" => Map1(f32::ln),
        "sign" => Map1(|x| if x == 0.0 { 0.0 } else { x.signum() }),
        "atan2" => Map2(f32::atan2),
        "pow" => Map2(f32::powf),
        "min" => Map2(f32::min),
        "max" => Map2(f32::max),
        "mod" => Map2(f32::rem_euclid),
        "step" => Map2(|edge, x| if x < edge { 0.0 } else { 1.0 }),
        "clamp" => Map3(|x, lo, hi| x.max(lo.min(hi)).min(hi.max(lo))),
        "mix" | "lerp" => Map3(|a, b, t| a + (b - a) * t),
        "smoothstep" => Map3(|e0, e1, x| {
            let t = ((x - e0) / (e1 - e0)).clamp(0.0, 1.0);
            t * t * (3.0 - 2.0 * t)
        }),
        "length" => Length,
        "distance" => Distance,
        "dot" => Dot,
        "normalize" => Normalize,
        "cross" => Cross,
        "vec2" => Construct(2),
        "vec3" => Construct(3),
        "vec4" => Construct(4),
        "translate" => Translate,
        "scale" => Scale,
        "rotate_x" => Rotate(Mat4::from_rotation_x),
        "rotate_y" => Rotate(Mat4::from_rotation_y),
        "rotate_z" => Rotate(Mat4::from_rotation_z),
        "transpose" => Transpose,
        "inverse" => Inverse,
        "identity" => Identity,
        "if" => If,
        _ => return None,
    })
}

/// The function names, for the help text and error messages.
pub const FUNCTIONS: &str = "sin cos tan asin acos atan sqrt abs floor ceil round fract exp log \
     sign atan2 pow min max mod step clamp mix lerp smoothstep length distance dot normalize \
     cross vec2 vec3 vec4 translate scale rotate_x rotate_y rotate_z transpose inverse identity if";

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

fn unify(tys: &[Ty], at: usize, what: &str) -> Result<Ty, ExprError> {
    let mut out = Ty::Scalar;
    for &t in tys {
        if t == Ty::Mat4 {
            return error(
                at,
                format!("{what} takes scalars and vectors, not a matrix"),
            );
        }
        if t != Ty::Scalar {
            if out != Ty::Scalar && out != t {
                return error(at, format!("{what}: {out:?} and {t:?} do not match"));
            }
            out = t;
        }
    }
    Ok(out)
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

fn arity(name: &str, tys: &[Ty], n: usize, at: usize) -> Result<(), ExprError> {
    if tys.len() == n {
        Ok(())
    } else {
        error(
            at,
            format!("`{name}` takes {n} argument(s), got {}", tys.len()),
        )
    }
}

fn call_type(func: Func, name: &str, tys: &[Ty], at: usize) -> Result<Ty, ExprError> {
    use Func::*;
    let what = format!("`{name}`");
    let want = |n| arity(name, tys, n, at);
    match func {
        Map1(_) => want(1).and_then(|()| unify(tys, at, &what)),
        Map2(_) => want(2).and_then(|()| unify(tys, at, &what)),
        Map3(_) => want(3).and_then(|()| unify(tys, at, &what)),
        Length | Normalize => {
            want(1)?;
            let t = unify(tys, at, &what)?;
            Ok(if matches!(func, Length) {
                Ty::Scalar
            } else {
                t
            })
        }
        Distance | Dot => want(2)
            .and_then(|()| unify(tys, at, &what))
            .map(|_| Ty::Scalar),
        Cross => {
            want(2)?;
            if tys != [Ty::Vec3, Ty::Vec3] {
                return error(at, "`cross` takes two Vec3");
            }
            Ok(Ty::Vec3)
        }
        Construct(n) => {
            let total: Option<usize> = tys.iter().map(|t| t.size()).sum();
            match total {
                Some(t) if t == n || (t == 1 && tys.len() == 1) => Ok(Ty::of_size(n)),
                _ => error(
                    at,
                    format!("`{name}` needs {n} components in all (or one scalar), got {tys:?}"),
                ),
            }
        }
        Translate => {
            want(1)?;
            if tys[0] != Ty::Vec3 {
                return error(at, "`translate` takes a Vec3");
            }
            Ok(Ty::Mat4)
        }
        Scale => {
            want(1)?;
            if !matches!(tys[0], Ty::Vec3 | Ty::Scalar) {
                return error(at, "`scale` takes a Vec3 or a scalar");
            }
            Ok(Ty::Mat4)
        }
        Rotate(_) => {
            want(1)?;
            if tys[0] != Ty::Scalar {
                return error(at, format!("`{name}` takes an angle in radians"));
            }
            Ok(Ty::Mat4)
        }
        Transpose | Inverse => {
            want(1)?;
            if tys[0] != Ty::Mat4 {
                return error(at, format!("`{name}` takes a Mat4"));
            }
            Ok(Ty::Mat4)
        }
        Identity => want(0).map(|()| Ty::Mat4),
        If => {
            want(3)?;
            if tys[0] != Ty::Scalar || tys[1] != tys[2] {
                return error(
                    at,
                    "`if(condition, a, b)` takes a scalar condition and two values of one type",
                );
            }
            Ok(tys[1])
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

fn map(args: &[Value], f: impl Fn(&[f32]) -> f32) -> Value {
    let lanes: Vec<(Vec4, usize)> = args.iter().filter_map(|a| a.lanes()).collect();
    let n = lanes.iter().map(|l| l.1).max().unwrap_or(1);
    let mut out = Vec4::ZERO;
    let mut buf = [0.0f32; 3];
    for i in 0..n {
        for (k, (v, size)) in lanes.iter().enumerate().take(3) {
            buf[k] = if *size == 1 { v.x } else { v[i] };
        }
        out[i] = f(&buf[..lanes.len().min(3)]);
    }
    Value::from_lanes(out, n)
}

fn eval_node(node: &Node, inputs: &[Value]) -> Value {
    use Func::*;
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
            let vec = |k: usize| a[k].lanes().map(|l| l.0).unwrap_or(Vec4::ZERO);
            match *func {
                Map1(f) => map(&a, |x| f(x[0])),
                Map2(f) => map(&a, |x| f(x[0], x[1])),
                Map3(f) => map(&a, |x| f(x[0], x[1], x[2])),
                Length => Value::Scalar(vec(0).length()),
                Distance => Value::Scalar((vec(0) - vec(1)).length()),
                Dot => Value::Scalar(vec(0).dot(vec(1))),
                Normalize => {
                    let n = a[0].lanes().map_or(1, |l| l.1);
                    Value::from_lanes(vec(0).normalize_or_zero(), n)
                }
                Cross => Value::Vec3(vec(0).truncate().cross(vec(1).truncate())),
                Construct(n) => {
                    let mut out = Vec4::ZERO;
                    let mut i = 0;
                    for (v, size) in a.iter().filter_map(|v| v.lanes()) {
                        for k in 0..size {
                            if i < 4 {
                                out[i] = v[k];
                                i += 1;
                            }
                        }
                    }
                    if i == 1 {
                        out = Vec4::splat(out.x);
                    }
                    Value::from_lanes(out, n)
                }
                Translate => Value::Mat4(Mat4::from_translation(vec(0).truncate())),
                Scale => Value::Mat4(match a[0] {
                    Value::Scalar(s) => Mat4::from_scale(Vec3::splat(s)),
                    _ => Mat4::from_scale(vec(0).truncate()),
                }),
                Rotate(f) => Value::Mat4(f(a[0].scalar())),
                Transpose => Value::Mat4(a[0].matrix().transpose()),
                Inverse => {
                    let m = a[0].matrix();
                    // A singular matrix has no inverse: give the identity rather than NaN.
                    Value::Mat4(if m.determinant().abs() > f32::EPSILON {
                        m.inverse()
                    } else {
                        Mat4::IDENTITY
                    })
                }
                Identity => Value::Mat4(Mat4::IDENTITY),
                If => {
                    if a[0].scalar() != 0.0 {
                        a[1]
                    } else {
                        a[2]
                    }
                }
            }
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
