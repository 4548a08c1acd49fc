//! The functions a formula or a definition may apply: the documents'
//! function words (`sin`, `Exp`, `log`, `sinc`, `cos^{-1}`) and the
//! toolchain's own geometry (`transform`, `project`, `left_jacobian`, …),
//! each computed by `factor-core`'s generic code, so the truth of a map
//! written with them comes from the toolchain and not from a document.
//!
//! `exp` and `log` follow the documents: of a 3-vector, the quaternion
//! exponential `[sin(θ/2) ω/θ, cos(θ/2)]`; of a quaternion (4-vector), its
//! logarithm; of a scalar, `eˣ` and `ln x`. `Exp` and `Log` are the
//! exponential and logarithm of SO(3) (3-vectors) and SE(3) (6-vectors).

use nalgebra::{Vector2, Vector3, Vector6};

use super::value::{ShapeError, Value, determinant, dynamic, quaternion_value};
use factor_core::geometry::{Intrinsics, PluckerLine, bearing_plane_normal};
use factor_core::lie::so3::{left_jacobian, right_jacobian};
use factor_core::lie::{Quaternion, Se3, So3};
use factor_core::scalar::Scalar;
use factor_core::storage::Storage;

/// A function of formulas.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum Builtin {
    /// `sin`.
    Sin,
    /// `cos`.
    Cos,
    /// `tan`.
    Tan,
    /// `arcsin`, `sin^{-1}`.
    Asin,
    /// `arccos`, `cos^{-1}`.
    Acos,
    /// `arctan`, `tan^{-1}`.
    Atan,
    /// `sinc x = sin x / x`.
    Sinc,
    /// `ln`.
    Ln,
    /// `exp`: `eˣ`, or the quaternion exponential of a 3-vector.
    Exp,
    /// `log`: `ln x`, or the logarithm of a quaternion.
    Log,
    /// `Exp` of SO(3) or SE(3).
    GroupExp,
    /// `Log` of SO(3) or SE(3).
    GroupLog,
    /// `det`.
    Det,
    /// `√`.
    Sqrt,
    /// `left_jacobian(ω)`: `Jl` of SO(3).
    LeftJacobian,
    /// `right_jacobian(ω)`: `Jr` of SO(3).
    RightJacobian,
    /// `normalize(x) = x / |x|`.
    Normalize,
    /// `transform(T, X) = R X + t`.
    Transform,
    /// `project(K, P)`: the pinhole projection with `K = [fu, fv, cu, cv]`.
    Project,
    /// `project_line(K, n)`: the image line `𝒦 n` of a Plücker normal.
    ProjectLine,
    /// `line_projection_matrix(K) = 𝒦`.
    LineProjectionMatrix,
    /// `transform_line(T, L)`: a Plücker line `[n, v]` moved by a pose.
    TransformLine,
    /// `plucker(L)`: the Plücker coordinates `[n, v]` of an orthonormal line.
    Plucker,
    /// `rotation(T)`: the rotation of a pose.
    RotationOf,
    /// `translation(T)`: the translation of a pose.
    TranslationOf,
    /// `vector(q)`: the vector part `[x, y, z]` of a quaternion.
    VectorPart,
    /// `scalar(q)`: the scalar part `w` of a quaternion.
    ScalarPart,
    /// `direction(l)`: the direction of a free line.
    Direction,
    /// `anchor(l)`: the anchor point of a free line.
    Anchor,
    /// `bearing_normal(f₁, f₂) = f₁ × f₂ / |f₁ × f₂|`.
    BearingNormal,
    /// `column(M, k)`: column `k` (1-based; `k` a printed number).
    Column(usize),
    /// `entry(v, k)`: entry `k` (1-based; `k` a printed number).
    Entry(usize),
    /// `rows(M, a, b)`: rows `a` to `b` (1-based, inclusive; printed numbers).
    Rows(usize, usize),
}

/// Names written `\operatorname{…}` in definitions or bound to a symbol
/// with `{ function = "…" }`, and the documents' function words.
const NAMES: &[(&str, Builtin)] = &[
    ("sin", Builtin::Sin),
    ("cos", Builtin::Cos),
    ("tan", Builtin::Tan),
    ("arcsin", Builtin::Asin),
    ("arccos", Builtin::Acos),
    ("arctan", Builtin::Atan),
    ("sinc", Builtin::Sinc),
    ("ln", Builtin::Ln),
    ("exp", Builtin::Exp),
    ("log", Builtin::Log),
    ("Exp", Builtin::GroupExp),
    ("Log", Builtin::GroupLog),
    ("det", Builtin::Det),
    ("sqrt", Builtin::Sqrt),
    ("left_jacobian", Builtin::LeftJacobian),
    ("right_jacobian", Builtin::RightJacobian),
    ("normalize", Builtin::Normalize),
    ("transform", Builtin::Transform),
    ("project", Builtin::Project),
    ("project_line", Builtin::ProjectLine),
    ("line_projection_matrix", Builtin::LineProjectionMatrix),
    ("transform_line", Builtin::TransformLine),
    ("plucker", Builtin::Plucker),
    ("rotation", Builtin::RotationOf),
    ("translation", Builtin::TranslationOf),
    ("vector", Builtin::VectorPart),
    ("scalar", Builtin::ScalarPart),
    ("direction", Builtin::Direction),
    ("anchor", Builtin::Anchor),
    ("bearing_normal", Builtin::BearingNormal),
];

/// Functions that take printed indices as their last arguments, and how many.
const INDEXED: &[(&str, usize)] = &[("column", 1), ("entry", 1), ("rows", 2)];

impl Builtin {
    /// The function named `name` (`column`, `entry` and `rows` need their
    /// indices: [`Builtin::indexed`]).
    pub fn named(name: &str) -> Option<Builtin> {
        NAMES.iter().find(|(n, _)| *n == name).map(|(_, b)| *b)
    }

    /// How many printed indices `name` takes last (0 for most functions).
    pub fn indices(name: &str) -> usize {
        INDEXED
            .iter()
            .find(|(n, _)| *n == name)
            .map_or(0, |(_, k)| *k)
    }

    /// `column`, `entry` or `rows` with its indices (1-based).
    pub fn indexed(name: &str, k: &[usize]) -> Option<Builtin> {
        match (name, k) {
            ("column", [k]) => Some(Builtin::Column(*k)),
            ("entry", [k]) => Some(Builtin::Entry(*k)),
            ("rows", [a, b]) => Some(Builtin::Rows(*a, *b)),
            _ => None,
        }
    }

    /// Every name, for messages.
    pub fn all_names() -> String {
        let mut names: Vec<&str> = NAMES.iter().map(|(n, _)| *n).collect();
        names.extend(INDEXED.iter().map(|(n, _)| *n));
        names.join(", ")
    }

    /// The inverse function, for `f^{-1}` (`cos^{-1}` is `arccos`).
    pub fn inverse(self) -> Option<Builtin> {
        match self {
            Builtin::Sin => Some(Builtin::Asin),
            Builtin::Cos => Some(Builtin::Acos),
            Builtin::Tan => Some(Builtin::Atan),
            Builtin::Exp => Some(Builtin::Log),
            Builtin::GroupExp => Some(Builtin::GroupLog),
            _ => None,
        }
    }

    /// How many arguments it takes.
    pub fn arity(self) -> usize {
        match self {
            Builtin::Transform
            | Builtin::Project
            | Builtin::ProjectLine
            | Builtin::TransformLine
            | Builtin::BearingNormal => 2,
            _ => 1,
        }
    }

    /// The name as written.
    pub fn name(self) -> &'static str {
        match self {
            Builtin::Column(_) => "column",
            Builtin::Entry(_) => "entry",
            Builtin::Rows(..) => "rows",
            other => NAMES
                .iter()
                .find(|(_, b)| *b == other)
                .map_or("?", |(n, _)| n),
        }
    }

    /// The function at `args` (as many as [`Builtin::arity`]).
    pub fn apply<S: Scalar>(self, mut args: Vec<Value<S>>) -> Result<Value<S>, ShapeError> {
        let what = self.name();
        if args.len() != self.arity() {
            return Err(ShapeError(format!(
                "`{what}` takes {} argument(s), not {}",
                self.arity(),
                args.len()
            )));
        }
        let second = if args.len() == 2 { args.pop() } else { None };
        let x = args.pop().expect("arity is at least 1");
        let scalar = |f: fn(S) -> S, x: Value<S>| -> Result<Value<S>, ShapeError> {
            Ok(Value::scalar(f(x.scalar_of(what)?)))
        };
        let second = || {
            second
                .clone()
                .ok_or_else(|| ShapeError(format!("`{what}` needs two arguments")))
        };
        match self {
            Builtin::Sin => scalar(|x| x.sin(), x),
            Builtin::Cos => scalar(|x| x.cos(), x),
            Builtin::Tan => scalar(|x| x.sin() / x.cos(), x),
            Builtin::Asin => scalar(|x| x.asin(), x),
            Builtin::Acos => scalar(|x| x.acos(), x),
            Builtin::Atan => scalar(|x| x.atan(), x),
            Builtin::Sinc => scalar(|x| x.sin() / x, x),
            Builtin::Ln => scalar(|x| x.ln(), x),
            Builtin::Sqrt => scalar(|x| x.sqrt(), x),
            Builtin::Exp => match x.shape() {
                Some((1, 1)) => scalar(|x| x.exp(), x),
                _ => Ok(quaternion_value(&Quaternion::exp(&x.vector3("exp")?))),
            },
            Builtin::Log => match x.shape() {
                Some((1, 1)) => scalar(|x| x.ln(), x),
                _ => Ok(Value::column(x.quaternion("log")?.log().as_slice())),
            },
            Builtin::GroupExp => match x.shape() {
                Some((6, 1)) => Ok(Value::Pose(Se3::exp(&Vector6::from_scalars(
                    &x.vector(6, what)?,
                )))),
                _ => Ok(Value::Rotation(So3::exp(&x.vector3("Exp")?))),
            },
            Builtin::GroupLog => match x {
                Value::Pose(p) => Ok(Value::column(p.log().as_slice())),
                other => Ok(Value::column(other.rotation("Log")?.log().as_slice())),
            },
            Builtin::Det => Ok(Value::scalar(determinant(&x.matrix()?)?)),
            Builtin::LeftJacobian => Ok(Value::Matrix(dynamic(&left_jacobian(&x.vector3(what)?)))),
            Builtin::RightJacobian => {
                Ok(Value::Matrix(dynamic(&right_jacobian(&x.vector3(what)?))))
            }
            Builtin::Normalize => {
                let m = x.matrix()?;
                let n = Value::Matrix(m.clone()).norm()?.scalar_of(what)?;
                Ok(Value::Matrix(m * n.recip()))
            }
            Builtin::Transform => {
                let pose = x.pose(what)?;
                Ok(Value::column(
                    pose.transform_point(&second()?.vector3(what)?).as_slice(),
                ))
            }
            Builtin::Project => {
                let k = Intrinsics::from_scalars(&x.vector(4, what)?);
                let p: Vector2<S> = k.project(&second()?.vector3(what)?);
                Ok(Value::column(p.as_slice()))
            }
            Builtin::ProjectLine => {
                let k = Intrinsics::from_scalars(&x.vector(4, what)?);
                Ok(Value::column(
                    k.project_line(&second()?.vector3(what)?).as_slice(),
                ))
            }
            Builtin::LineProjectionMatrix => {
                let k = Intrinsics::from_scalars(&x.vector(4, what)?);
                Ok(Value::Matrix(dynamic(&k.line_projection_matrix())))
            }
            Builtin::TransformLine => {
                let pose = x.pose(what)?;
                let line = PluckerLine::from_scalars(&second()?.vector(6, what)?);
                Ok(Value::column(&line.transform(&pose).to_scalars()))
            }
            Builtin::Plucker => match x {
                Value::OrthonormalLine(l) => Ok(Value::column(&l.to_plucker().to_scalars())),
                other => Err(ShapeError(format!(
                    "`plucker` needs an orthonormal line, not {}",
                    other.describe()
                ))),
            },
            Builtin::RotationOf => Ok(Value::Rotation(x.pose(what)?.rotation)),
            Builtin::TranslationOf => Ok(Value::column(x.pose(what)?.translation.as_slice())),
            Builtin::VectorPart => {
                let q = x.quaternion(what)?;
                Ok(Value::column(q.vector().as_slice()))
            }
            Builtin::ScalarPart => Ok(Value::scalar(x.quaternion(what)?.w)),
            Builtin::Direction | Builtin::Anchor => match x {
                Value::FreeLine(l) => {
                    let v: Vector3<S> = if self == Builtin::Direction {
                        l.direction()
                    } else {
                        l.anchor()
                    };
                    Ok(Value::column(v.as_slice()))
                }
                other => Err(ShapeError(format!(
                    "`{what}` needs a free line, not {}",
                    other.describe()
                ))),
            },
            Builtin::BearingNormal => {
                let (f1, f2) = (x.vector3(what)?, second()?.vector3(what)?);
                Ok(Value::column(bearing_plane_normal(&f1, &f2).as_slice()))
            }
            Builtin::Column(k) => {
                let m = x.matrix()?;
                if k == 0 || k > m.ncols() {
                    return Err(ShapeError(format!(
                        "column {k} of a matrix of {} columns",
                        m.ncols()
                    )));
                }
                let column: Vec<S> = m.column(k - 1).iter().copied().collect();
                Ok(Value::column(&column))
            }
            Builtin::Entry(k) => {
                let m = x.matrix()?;
                if k == 0 || k > m.len() || m.ncols() != 1 {
                    return Err(ShapeError(format!(
                        "entry {k} of {}",
                        Value::Matrix(m).describe()
                    )));
                }
                Ok(Value::scalar(m[(k - 1, 0)]))
            }
            Builtin::Rows(a, b) => {
                let m = x.matrix()?;
                if a == 0 || a > b || b > m.nrows() {
                    return Err(ShapeError(format!(
                        "rows {a} to {b} of a matrix of {} rows",
                        m.nrows()
                    )));
                }
                Ok(Value::Matrix(m.rows(a - 1, b - a + 1).into_owned()))
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use factor_core::linalg::normalized;
    use nalgebra::Vector4;

    #[test]
    fn documents_words_and_library_functions() {
        let w = Value::column(&[0.1, -0.2, 0.3]);
        let q = Builtin::Exp.apply(vec![w.clone()]).unwrap();
        let back = Builtin::Log.apply(vec![q]).unwrap().matrix().unwrap();
        assert!((back - w.clone().matrix().unwrap()).norm() < 1e-14);
        let r = Builtin::GroupExp.apply(vec![w.clone()]).unwrap();
        assert!(matches!(r, Value::Rotation(_)));
        let back = Builtin::GroupLog.apply(vec![r]).unwrap().matrix().unwrap();
        assert!((back - w.matrix().unwrap()).norm() < 1e-14);
        assert_eq!(Builtin::Cos.inverse(), Some(Builtin::Acos));
        let n = normalized(&Vector4::new(1.0, 2.0, 2.0, 4.0));
        let v = Builtin::Normalize
            .apply(vec![Value::column(&[1.0, 2.0, 2.0, 4.0])])
            .unwrap()
            .matrix()
            .unwrap();
        assert!((v[(3, 0)] - n.w).abs() < 1e-15);
    }

    #[test]
    fn wrong_arguments_are_errors() {
        let e = Builtin::Transform
            .apply(vec![Value::column(&[1.0, 2.0]), Value::scalar(1.0)])
            .unwrap_err();
        assert!(e.0.contains("needs a pose"), "{e}");
        assert!(
            Builtin::Column(4)
                .apply(vec![Value::column(&[1.0, 2.0])])
                .is_err()
        );
    }
}
