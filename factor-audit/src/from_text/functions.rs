//! The functions a formula or a definition may apply: the documents'
//! function words (`sin`, `Exp`, `log`, `sinc`, `cos^{-1}`) and the
//! toolchain's own geometry (`transform`, `project`, `left_jacobian`, …),
//! each computed by `factor-core`'s generic code, so the truth of a map
//! written with them comes from the toolchain and not from a document.
//!
//! Functions are dispatched on their argument's type:
//! - `exp` of a scalar is `eˣ`; of a 3-vector the quaternion exponential
//!   `[sin(θ/2) ω/θ, cos(θ/2)]` (as document 000 writes it); of a quaternion
//!   (4-vector `[x, y, z, w]`) the quaternion exponential `e^w [sin|v| v/|v|,
//!   cos|v|]`; of a 3 × 3 skew matrix (`so(3)`) the rotation; of a 4 × 4
//!   twist matrix (`se(3)`) the pose; of any other square matrix (a 3 × 3
//!   that is not skew, a 4 × 4 that is no twist: the structure is read from
//!   its value) the matrix exponential. `log` inverts each: of a quaternion its
//!   logarithm `θ/2`-vector, of a rotation its `so(3)` matrix, of a pose its
//!   twist matrix.
//! - `Exp` of a 3-vector (or `so(3)` matrix) is SO(3)'s, of a 6-vector (or
//!   `se(3)` matrix) SE(3)'s, of a 7-vector `[ω, ρ, σ]` Sim(3)'s; `Log`
//!   inverts each (of a unit quaternion, the rotation vector).
//! - `left_jacobian`, `right_jacobian` and their `_inverse`s are SO(3)'s,
//!   SE(3)'s or Sim(3)'s by the tangent's length; `adjoint` (`Ad_X`) of a
//!   rotation, pose or similarity; `ad` of a tangent or an algebra matrix.

use nalgebra::{DMatrix, Vector2, Vector3, Vector6};

use super::value::{ShapeError, Value, determinant, dynamic, quaternion_value};
use factor_core::geometry::{Intrinsics, PluckerLine, bearing_plane_normal};
use factor_core::lie::sim3::{Sim3Matrix, Sim3Tangent};
use factor_core::lie::so3::hat;
use factor_core::lie::{LieGroup, Quaternion, Se3, Sim3, So3};
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
    /// `cot`.
    Cot,
    /// `sec`.
    Sec,
    /// `csc`.
    Csc,
    /// `sinh`.
    Sinh,
    /// `cosh`.
    Cosh,
    /// `tanh`.
    Tanh,
    /// `sinc x = sin x / x`.
    Sinc,
    /// `ln`.
    Ln,
    /// `exp`: `eˣ`, the quaternion exponential of a 3-vector or a
    /// quaternion, `Exp` of an so(3) or se(3) matrix, the matrix
    /// exponential of another square matrix.
    Exp,
    /// `expm`: the matrix exponential of any square matrix.
    MatrixExp,
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
    /// `left_jacobian(τ)`: `Jl` of SO(3), SE(3) or Sim(3).
    LeftJacobian,
    /// `right_jacobian(τ)`: `Jr` of SO(3), SE(3) or Sim(3).
    RightJacobian,
    /// `left_jacobian_inverse(τ)`: `Jl⁻¹`.
    LeftJacobianInverse,
    /// `right_jacobian_inverse(τ)`: `Jr⁻¹`.
    RightJacobianInverse,
    /// `adjoint(X)`, `Ad_X`: of a rotation, pose or similarity.
    Adjoint,
    /// `Ad_X y`: the adjoint acting on a tangent vector, or conjugating an
    /// algebra matrix `X y X⁻¹`.
    AdjointAct,
    /// `ad(τ)`, `ad_τ`: of a tangent (3-, 6- or 7-vector) or of an algebra
    /// matrix (`so(3)`, `se(3)`).
    SmallAdjoint,
    /// `ad_τ y`: on a tangent, `ad_τ y`; on algebra matrices, `τ y − y τ`.
    SmallAdjointAct,
    /// `matrix(X)`: a group element's matrix (`C(Φ)`); of a 3-vector, the
    /// matrix of the rotation it is the vector of (`C(φ) = Exp(φ)`).
    MatrixOf,
    /// `inverse(X)`.
    Inverse,
    /// `skew(v)`: the cross-product matrix.
    Skew,
    /// `tr(M)`: the trace.
    Trace,
    /// `diag(v)`: the diagonal matrix of a vector.
    Diag,
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
    /// `rotation(T)`: the rotation of a pose; `rotation(q)`: the rotation
    /// of a unit quaternion `[x, y, z, w]` (Hamilton's, active:
    /// `R(q) v = q ⊗ [v, 0] ⊗ q⁻¹`).
    RotationOf,
    /// `rotation(q)` in a file that states JPL quaternions: the rotation
    /// `C(q)` of JPL's convention, `R(q)ᵀ` (a pose's rotation unchanged).
    JplRotationOf,
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
    ("atan", Builtin::Atan),
    ("asin", Builtin::Asin),
    ("acos", Builtin::Acos),
    ("cot", Builtin::Cot),
    ("sec", Builtin::Sec),
    ("csc", Builtin::Csc),
    ("sinh", Builtin::Sinh),
    ("cosh", Builtin::Cosh),
    ("tanh", Builtin::Tanh),
    ("sinc", Builtin::Sinc),
    ("ln", Builtin::Ln),
    ("exp", Builtin::Exp),
    ("expm", Builtin::MatrixExp),
    ("log", Builtin::Log),
    ("Exp", Builtin::GroupExp),
    ("Log", Builtin::GroupLog),
    ("det", Builtin::Det),
    ("sqrt", Builtin::Sqrt),
    ("left_jacobian", Builtin::LeftJacobian),
    ("right_jacobian", Builtin::RightJacobian),
    ("left_jacobian_inverse", Builtin::LeftJacobianInverse),
    ("right_jacobian_inverse", Builtin::RightJacobianInverse),
    ("adjoint", Builtin::Adjoint),
    ("Ad", Builtin::Adjoint),
    ("ad", Builtin::SmallAdjoint),
    ("matrix", Builtin::MatrixOf),
    ("inverse", Builtin::Inverse),
    ("skew", Builtin::Skew),
    ("tr", Builtin::Trace),
    ("diag", Builtin::Diag),
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
            Builtin::LeftJacobian => Some(Builtin::LeftJacobianInverse),
            Builtin::RightJacobian => Some(Builtin::RightJacobianInverse),
            Builtin::LeftJacobianInverse => Some(Builtin::LeftJacobian),
            Builtin::RightJacobianInverse => Some(Builtin::RightJacobian),
            Builtin::Adjoint | Builtin::MatrixOf => Some(Builtin::Inverse),
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
            | Builtin::BearingNormal
            | Builtin::AdjointAct
            | Builtin::SmallAdjointAct => 2,
            _ => 1,
        }
    }

    /// The same function in a file that states JPL quaternions.
    pub fn in_jpl(self) -> Builtin {
        match self {
            Builtin::RotationOf => Builtin::JplRotationOf,
            other => other,
        }
    }

    /// The name as written.
    pub fn name(self) -> &'static str {
        match self {
            Builtin::Column(_) => "column",
            Builtin::Entry(_) => "entry",
            Builtin::Rows(..) => "rows",
            Builtin::JplRotationOf => "rotation",
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
            Builtin::Cot => scalar(|x| x.cos() / x.sin(), x),
            Builtin::Sec => scalar(|x| x.cos().recip(), x),
            Builtin::Csc => scalar(|x| x.sin().recip(), x),
            Builtin::Sinh => scalar(|x| (x.exp() - (-x).exp()) * S::from_f64(0.5), x),
            Builtin::Cosh => scalar(|x| (x.exp() + (-x).exp()) * S::from_f64(0.5), x),
            Builtin::Tanh => scalar(
                |x| {
                    let (a, b) = (x.exp(), (-x).exp());
                    (a - b) / (a + b)
                },
                x,
            ),
            Builtin::Sinc => scalar(|x| x.sin() / x, x),
            Builtin::Ln => scalar(|x| x.ln(), x),
            Builtin::Sqrt => scalar(|x| x.sqrt(), x),
            Builtin::Exp => match x.shape() {
                Some((1, 1)) => scalar(|x| x.exp(), x),
                Some((4, 1)) => Ok(quaternion_value(&quaternion_exp(&x.quaternion(what)?))),
                // A matrix of so(3) or se(3) exponentiates to its group
                // element; any other square matrix (a 4 × 4 that is no
                // twist) to its matrix exponential.
                Some((3, 3) | (4, 4)) if x.in_algebra() != Some(false) => group_exp(x),
                Some((n, m)) if n == m => Ok(Value::Matrix(matrix_exp(x.matrix()?))),
                _ => Ok(quaternion_value(&Quaternion::exp(&x.vector3("exp")?))),
            },
            Builtin::MatrixExp => {
                let m = x.matrix()?;
                if m.nrows() != m.ncols() {
                    return Err(ShapeError(format!(
                        "`expm` of {}, not a square matrix",
                        Value::Matrix(m).describe()
                    )));
                }
                Ok(Value::Matrix(matrix_exp(m)))
            }
            Builtin::Log => match x {
                Value::Rotation(r) => Ok(Value::Matrix(dynamic(&hat(&r.log())))),
                Value::Pose(p) => Value::column(p.log().as_slice()).hat(),
                other => match other.shape() {
                    Some((1, 1)) => scalar(|x| x.ln(), other),
                    _ => Ok(Value::column(other.quaternion("log")?.log().as_slice())),
                },
            },
            Builtin::GroupExp => group_exp(x),
            Builtin::GroupLog => match x {
                Value::Pose(p) => Ok(Value::column(p.log().as_slice())),
                Value::Similarity(s) => Ok(Value::column(s.log().as_slice())),
                Value::Matrix(m) if m.shape() == (4, 1) => {
                    let q = Quaternion::from_scalars(m.as_slice()).normalized();
                    Ok(Value::column(So3::from_quaternion(q).log().as_slice()))
                }
                Value::Matrix(m) if m.shape() == (3, 3) => {
                    let r = So3::from_matrix(&nalgebra::Matrix3::from_column_slice(m.as_slice()));
                    Ok(Value::column(r.log().as_slice()))
                }
                other => Ok(Value::column(other.rotation("Log")?.log().as_slice())),
            },
            Builtin::Det => Ok(Value::scalar(determinant(&x.matrix()?)?)),
            Builtin::LeftJacobian
            | Builtin::RightJacobian
            | Builtin::LeftJacobianInverse
            | Builtin::RightJacobianInverse => jacobian(self, x),
            Builtin::Adjoint => Ok(Value::Matrix(adjoint(&x)?)),
            Builtin::AdjointAct => {
                let y = second()?;
                match y.shape() {
                    Some((r, 1)) if r > 1 => Value::Matrix(adjoint(&x)?).times(y),
                    Some((3, 3) | (4, 4)) => x.clone().times(y)?.times(x.inverse()?),
                    _ => Err(ShapeError(format!("`Ad` acting on {}", y.describe()))),
                }
            }
            Builtin::SmallAdjoint => Ok(Value::Matrix(small_adjoint(x)?)),
            Builtin::SmallAdjointAct => {
                let y = second()?;
                match (x.shape(), y.shape()) {
                    (Some((n, n2)), Some((m, m2))) if n == n2 && n == m && m == m2 && n > 1 => {
                        let (a, b) = (x.matrix()?, y.matrix()?);
                        Ok(Value::Matrix(&a * &b - &b * &a))
                    }
                    _ => Value::Matrix(small_adjoint(x)?).times(y),
                }
            }
            Builtin::MatrixOf => match x.shape() {
                Some((3, 1)) => Ok(Value::Matrix(group_exp(x)?.matrix()?)),
                _ => Ok(Value::Matrix(x.matrix()?)),
            },
            Builtin::Inverse => x.inverse(),
            Builtin::Skew => x.hat(),
            Builtin::Trace => {
                let m = x.matrix()?;
                if m.nrows() != m.ncols() {
                    return Err(ShapeError(format!(
                        "the trace of {}",
                        Value::Matrix(m).describe()
                    )));
                }
                Ok(Value::scalar(
                    (0..m.nrows()).fold(S::zero(), |acc, i| acc + m[(i, i)]),
                ))
            }
            Builtin::Diag => {
                let m = x.matrix()?;
                if m.ncols() != 1 {
                    return Err(ShapeError(format!(
                        "the diagonal matrix of {}",
                        Value::Matrix(m).describe()
                    )));
                }
                let n = m.nrows();
                Ok(Value::Matrix(DMatrix::from_fn(n, n, |i, j| {
                    if i == j { m[(i, 0)] } else { S::zero() }
                })))
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
            Builtin::RotationOf | Builtin::JplRotationOf => match x.shape() {
                Some((4, 1)) => {
                    let r = So3::from_quaternion(x.quaternion(what)?.normalized());
                    Ok(Value::Rotation(if self == Builtin::JplRotationOf {
                        r.inverse()
                    } else {
                        r
                    }))
                }
                _ => Ok(Value::Rotation(x.pose(what)?.rotation)),
            },
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

/// `e^q` of a quaternion `q = [v, w]`: `e^w [sin|v| v/|v|, cos|v|]`.
fn quaternion_exp<S: Scalar>(q: &Quaternion<S>) -> Quaternion<S> {
    // `Quaternion::exp(ω)` is `[sin(θ/2) ω/θ, cos(θ/2)]`: at `ω = 2v` it is
    // the exponential of the pure quaternion `[v, 0]`.
    let pure = Quaternion::exp(&q.vector().map(|c| c * S::from_f64(2.0)));
    let m = q.w.exp();
    Quaternion::new(pure.x * m, pure.y * m, pure.z * m, pure.w * m)
}

/// Halvings before the Taylor series of [`matrix_exp`] (undone by as many
/// squarings).
const EXP_HALVINGS: i32 = 10;
/// Terms of that series.
const EXP_TERMS: usize = 18;

/// `e^X` of a square matrix, by scaling and squaring: `(Σₖ (X/2¹⁰)ᵏ/k!)`
/// to 18 terms, squared ten times. Without branches (dual numbers go
/// through); for `‖X‖ ≤ 100` the first omitted term is below `10⁻¹⁶`
/// relative.
pub fn matrix_exp<S: Scalar>(x: DMatrix<S>) -> DMatrix<S> {
    let n = x.nrows();
    let identity = DMatrix::<S>::identity(n, n);
    let scaled = x.map(|v| v * S::from_f64(2f64.powi(-EXP_HALVINGS)));
    let mut p = identity.clone();
    for k in (1..=EXP_TERMS).rev() {
        p = &identity + (&scaled * &p).map(|v| v / S::from_f64(k as f64));
    }
    for _ in 0..EXP_HALVINGS {
        p = &p * &p;
    }
    p
}

/// `Exp` of a tangent (3-, 6- or 7-vector) or of an algebra matrix.
fn group_exp<S: Scalar>(x: Value<S>) -> Result<Value<S>, ShapeError> {
    match x.shape() {
        Some((3, 3) | (4, 4)) => group_exp(x.vee()?),
        Some((6, 1)) => Ok(Value::Pose(Se3::exp(&Vector6::from_scalars(
            &x.vector(6, "Exp")?,
        )))),
        Some((7, 1)) => Ok(Value::Similarity(Sim3::exp(
            &Sim3Tangent::from_column_slice(&x.vector(7, "Exp")?),
        ))),
        _ => Ok(Value::Rotation(So3::exp(&x.vector3("Exp")?))),
    }
}

/// A Jacobian of SO(3), SE(3) or Sim(3) (by the tangent's length).
fn jacobian<S: Scalar>(which: Builtin, x: Value<S>) -> Result<Value<S>, ShapeError> {
    fn of<S: Scalar, G: LieGroup<S>>(which: Builtin, tau: &G::Tangent) -> G::Jacobian {
        match which {
            Builtin::LeftJacobian => G::left_jacobian(tau),
            Builtin::RightJacobian => G::right_jacobian(tau),
            Builtin::LeftJacobianInverse => G::left_jacobian_inverse(tau),
            _ => G::right_jacobian_inverse(tau),
        }
    }
    let what = which.name();
    Ok(Value::Matrix(match x.shape() {
        Some((6, 1)) => dynamic(&of::<S, Se3<S>>(
            which,
            &Vector6::from_scalars(&x.vector(6, what)?),
        )),
        Some((7, 1)) => dynamic::<S, 7, 7>(&of::<S, Sim3<S>>(
            which,
            &Sim3Tangent::from_column_slice(&x.vector(7, what)?),
        )),
        _ => dynamic(&of::<S, So3<S>>(which, &x.vector3(what)?)),
    }))
}

/// `Ad_X` of a group element.
fn adjoint<S: Scalar>(x: &Value<S>) -> Result<DMatrix<S>, ShapeError> {
    match x {
        Value::Rotation(r) => Ok(dynamic(&r.adjoint())),
        Value::Pose(p) => Ok(dynamic(&p.adjoint())),
        Value::Similarity(s) => Ok(dynamic::<S, 7, 7>(&s.adjoint())),
        other => Err(ShapeError(format!(
            "the adjoint of {} (a rotation, pose or similarity has one)",
            other.describe()
        ))),
    }
}

/// `ad_τ` of a tangent or an algebra matrix.
fn small_adjoint<S: Scalar>(x: Value<S>) -> Result<DMatrix<S>, ShapeError> {
    match x.shape() {
        Some((3, 3) | (4, 4)) => small_adjoint(x.vee()?),
        Some((3, 1)) => Ok(dynamic(&hat(&x.vector3("ad")?))),
        Some((6, 1)) => {
            let v = x.vector(6, "ad")?;
            let (w, rho) = (
                Vector3::new(v[0], v[1], v[2]),
                Vector3::new(v[3], v[4], v[5]),
            );
            let mut m = DMatrix::zeros(6, 6);
            m.view_mut((0, 0), (3, 3)).copy_from(&hat(&w));
            m.view_mut((3, 3), (3, 3)).copy_from(&hat(&w));
            m.view_mut((3, 0), (3, 3)).copy_from(&hat(&rho));
            Ok(m)
        }
        Some((7, 1)) => {
            let m: Sim3Matrix<S> =
                Sim3::small_adjoint(&Sim3Tangent::from_column_slice(&x.vector(7, "ad")?));
            Ok(dynamic(&m))
        }
        _ => Err(ShapeError(format!("`ad` of {}", x.describe()))),
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use factor_core::linalg::normalized;
    use nalgebra::Vector4;

    #[test]
    fn the_matrix_exponential_agrees_with_closed_forms() {
        // A plane rotation by 2.5 rad, e^{θ R_{π/2}}.
        let theta = 2.5;
        let x = DMatrix::from_row_slice(2, 2, &[0.0, -theta, theta, 0.0]);
        let e = matrix_exp(x);
        let want =
            DMatrix::from_row_slice(2, 2, &[theta.cos(), -theta.sin(), theta.sin(), theta.cos()]);
        assert!((e - want).norm() < 1e-13);
        // so(3): Rodrigues' formula, through `Exp`.
        let w = Vector3::new(0.4, -1.2, 2.1);
        let rodrigues = So3::exp(&w).matrix();
        assert!((matrix_exp(dynamic(&hat(&w))) - dynamic(&rodrigues)).norm() < 1e-12);
        // A diagonal matrix: the exponentials of its entries (a large one too).
        let d = DMatrix::from_diagonal(&nalgebra::DVector::from_vec(vec![-3.0, 0.5, 40.0]));
        let e = matrix_exp(d);
        for (k, v) in [-3.0f64, 0.5, 40.0].iter().enumerate() {
            assert!((e[(k, k)] / v.exp() - 1.0).abs() < 1e-12);
        }
        // `exp` of a 2 × 2 is the matrix exponential; `expm` of a 3-vector fails.
        let two = Value::Matrix(DMatrix::from_row_slice(2, 2, &[0.0, 1.0, 0.0, 0.0]));
        let m = Builtin::Exp.apply(vec![two]).unwrap().matrix().unwrap();
        assert_eq!(m, DMatrix::from_row_slice(2, 2, &[1.0, 1.0, 0.0, 1.0]));
        assert!(
            Builtin::MatrixExp
                .apply(vec![Value::column(&[1.0, 2.0, 3.0])])
                .is_err()
        );
    }

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
