//! The built-in functions of expressions: their names, the types they
//! accept and give, and what they compute.

use glam::{Mat4, Vec3, Vec4};

use super::parse::{ExprError, error};
use super::values::{Ty, Value, map, unify};

/// Built-in functions.
#[derive(Clone, Copy, Debug)]
pub(super) enum Func {
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

pub(super) fn lookup(name: &str) -> Option<Func> {
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

pub(super) fn call_type(func: Func, name: &str, tys: &[Ty], at: usize) -> Result<Ty, ExprError> {
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

/// Apply `func` to its evaluated arguments (of the types `call_type` accepted).
pub(super) fn call(func: Func, a: &[Value]) -> Value {
    use Func::*;
    let vec = |k: usize| a[k].lanes().map(|l| l.0).unwrap_or(Vec4::ZERO);
    match func {
        Map1(f) => map(a, |x| f(x[0])),
        Map2(f) => map(a, |x| f(x[0], x[1])),
        Map3(f) => map(a, |x| f(x[0], x[1], x[2])),
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
