//! The types and values expressions compute with: scalars, 2/3/4-vectors and
//! matrices, and the two helpers the built-in functions share with the type
//! checker (how argument types unify, how a scalar function maps over lanes).

use glam::{Mat4, Vec2, Vec3, Vec4};

use super::parse::{ExprError, error};

#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Ty {
    Scalar,
    Vec2,
    Vec3,
    Vec4,
    Mat4,
}

impl Ty {
    pub(super) fn size(self) -> Option<usize> {
        match self {
            Ty::Scalar => Some(1),
            Ty::Vec2 => Some(2),
            Ty::Vec3 => Some(3),
            Ty::Vec4 => Some(4),
            Ty::Mat4 => None,
        }
    }

    pub(super) fn of_size(n: usize) -> Ty {
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
    pub(super) fn lanes(self) -> Option<(Vec4, usize)> {
        Some(match self {
            Value::Scalar(s) => (Vec4::splat(s), 1),
            Value::Vec2(v) => (v.extend(0.0).extend(0.0), 2),
            Value::Vec3(v) => (v.extend(0.0), 3),
            Value::Vec4(v) => (v, 4),
            Value::Mat4(_) => return None,
        })
    }

    pub(super) fn from_lanes(v: Vec4, n: usize) -> Value {
        match n {
            1 => Value::Scalar(v.x),
            2 => Value::Vec2(v.truncate().truncate()),
            3 => Value::Vec3(v.truncate()),
            _ => Value::Vec4(v),
        }
    }

    /// The scalar inside, or 0 (type checking rules the other cases out).
    pub(super) fn scalar(self) -> f32 {
        match self {
            Value::Scalar(s) => s,
            _ => 0.0,
        }
    }

    pub(super) fn matrix(self) -> Mat4 {
        match self {
            Value::Mat4(m) => m,
            _ => Mat4::IDENTITY,
        }
    }
}

pub(super) fn unify(tys: &[Ty], at: usize, what: &str) -> Result<Ty, ExprError> {
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

pub(super) fn map(args: &[Value], f: impl Fn(&[f32]) -> f32) -> Value {
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
