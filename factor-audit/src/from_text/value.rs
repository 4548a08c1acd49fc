//! The values a formula evaluates to, generic over the scalar (so `f64`,
//! dual numbers and the symbolic engine all evaluate it), and the
//! arithmetic the documents' notation means on them.
//!
//! A scalar is a 1 × 1 matrix and a vector a column. Rotations and poses
//! keep their group structure (`Exp(ω₁) Exp(ω₂)` composes, `Log` inverts
//! `Exp`) and act as their 3 × 3 and 4 × 4 matrices everywhere else (a
//! pose's transpose is the 4 × 4 transpose, as the plane formulas use it).
//! A quaternion is a 4-vector `[x, y, z, w]`: `⊕` is the Hamilton product.
//! `I` and `0` without a printed size, and block matrices whose blocks are
//! not all sized, stay unsized until where they are used tells their size
//! (a neighbour in a product, a shape annotation, the claimed Jacobian).

use nalgebra::{DMatrix, Matrix3, Vector3, Vector4};

use factor_core::geometry::{FreeLine, OrthonormalLine};
use factor_core::lie::{LieGroup, Quaternion, Se3, Sim3, So3};
use factor_core::manifold::Perturbation;
use factor_core::scalar::Scalar;
use factor_core::storage::Storage;

/// Largest number of rows or columns a value may have: formulas of
/// Jacobians are small, and a hostile `I_{10^6 × 10^6}` must not allocate.
pub const MAX_DIMENSION: usize = 64;

/// Why a formula cannot be evaluated as printed: dimensions that do not
/// fit, an operation its operands do not have. The same at every sample.
#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error)]
#[error("{0}")]
pub struct ShapeError(pub String);

fn fail<T>(message: impl Into<String>) -> Result<T, ShapeError> {
    Err(ShapeError(message.into()))
}

/// A value of a formula.
#[derive(Debug, Clone, PartialEq)]
pub enum Value<S: Scalar> {
    /// A matrix (a scalar is 1 × 1, a vector a column).
    Matrix(DMatrix<S>),
    /// A rotation.
    Rotation(So3<S>),
    /// A pose.
    Pose(Se3<S>),
    /// A similarity (Sim(3)).
    Similarity(Sim3<S>),
    /// `c I` whose size is told by where it is used.
    Identity(S),
    /// A zero block whose size is told by where it is used.
    Zero,
    /// A zero block printed with a size in a block matrix: sized by its
    /// block row and column, the printed rows and columns where they do not
    /// tell ([`super::term::Term::BlockZero`]).
    BlockZero(Option<usize>, Option<usize>),
    /// A block matrix some of whose blocks are not sized yet.
    Blocks(Blocks<S>),
    /// A line in orthonormal representation `(U, W)` (no matrix).
    OrthonormalLine(OrthonormalLine<S>),
    /// A free line `[q, d]` (no matrix).
    FreeLine(FreeLine<S>),
}

/// `(rows, columns)` as printed in messages: `2 × 3`.
pub fn shape_text((r, c): (usize, usize)) -> String {
    format!("{r} × {c}")
}

impl<S: Scalar> Value<S> {
    /// A scalar.
    pub fn scalar(x: S) -> Self {
        Value::Matrix(DMatrix::from_element(1, 1, x))
    }

    /// A column vector.
    pub fn column(entries: &[S]) -> Self {
        Value::Matrix(DMatrix::from_column_slice(entries.len(), 1, entries))
    }

    /// Its size, when it has one.
    pub fn shape(&self) -> Option<(usize, usize)> {
        match self {
            Value::Matrix(m) => Some(m.shape()),
            Value::Rotation(_) => Some((3, 3)),
            Value::Pose(_) | Value::Similarity(_) => Some((4, 4)),
            Value::Identity(_)
            | Value::Zero
            | Value::BlockZero(..)
            | Value::Blocks(_)
            | Value::OrthonormalLine(_)
            | Value::FreeLine(_) => None,
        }
    }

    /// What it is, for messages: `a 2 × 3 matrix`, `a rotation`.
    pub fn describe(&self) -> String {
        match self {
            Value::Matrix(m) if m.shape() == (1, 1) => "a scalar".into(),
            Value::Matrix(m) if m.ncols() == 1 => format!("a {}-vector", m.nrows()),
            Value::Matrix(m) => format!("a {} matrix", shape_text(m.shape())),
            Value::Rotation(_) => "a rotation".into(),
            Value::Pose(_) => "a pose".into(),
            Value::Similarity(_) => "a similarity".into(),
            Value::Identity(_) => "an identity of unprinted size".into(),
            Value::Zero => "a zero of unprinted size".into(),
            Value::BlockZero(..) => "a zero block".into(),
            Value::Blocks(_) => "a block matrix of unprinted size".into(),
            Value::OrthonormalLine(_) => "an orthonormal line".into(),
            Value::FreeLine(_) => "a free line".into(),
        }
    }

    /// The value as a matrix of the given size when it has none yet.
    pub fn sized(self, hint: Hint) -> Result<DMatrix<S>, ShapeError> {
        match self {
            Value::Matrix(m) => Ok(m),
            Value::Rotation(r) => Ok(dynamic(&r.matrix())),
            Value::Pose(p) => Ok(dynamic(&p.matrix())),
            Value::Similarity(x) => Ok(dynamic(&x.matrix())),
            Value::Identity(c) => {
                let n = match hint {
                    (Some(r), Some(c)) if r != c => {
                        return fail(format!("an identity cannot be {}", shape_text((r, c))));
                    }
                    (Some(n), _) | (_, Some(n)) => n,
                    (None, None) => return fail("the size of an identity cannot be told"),
                };
                Ok(DMatrix::identity(checked(n)?, n) * c)
            }
            Value::Zero => match hint {
                (Some(r), Some(c)) => Ok(DMatrix::zeros(checked(r)?, checked(c)?)),
                _ => fail("the size of a zero block cannot be told"),
            },
            Value::BlockZero(rows, cols) => match (hint.0.or(rows), hint.1.or(cols).or(rows)) {
                (Some(r), Some(c)) => Ok(DMatrix::zeros(checked(r)?, checked(c)?)),
                _ => fail("the size of a zero block cannot be told"),
            },
            Value::Blocks(b) => b.resolve(hint),
            other => fail(format!("{} is not a matrix", other.describe())),
        }
    }

    /// As a sized matrix, with no hint.
    pub fn matrix(self) -> Result<DMatrix<S>, ShapeError> {
        self.sized((None, None))
    }

    /// The scalar this is, if it is 1 × 1.
    pub fn as_scalar(&self) -> Option<S> {
        match self {
            Value::Matrix(m) if m.shape() == (1, 1) => Some(m[(0, 0)]),
            _ => None,
        }
    }

    /// The vector of length `n` this is.
    pub fn vector(self, n: usize, what: &str) -> Result<Vec<S>, ShapeError> {
        match self {
            Value::Matrix(m) if m.shape() == (n, 1) => Ok(m.as_slice().to_vec()),
            Value::Zero => Ok(vec![S::zero(); n]),
            other => fail(format!(
                "{what} needs a {n}-vector, not {}",
                other.describe()
            )),
        }
    }

    /// A 3-vector.
    pub fn vector3(self, what: &str) -> Result<Vector3<S>, ShapeError> {
        Ok(Vector3::from_scalars(&self.vector(3, what)?))
    }

    /// A quaternion `[x, y, z, w]`.
    pub fn quaternion(self, what: &str) -> Result<Quaternion<S>, ShapeError> {
        Ok(Quaternion::from_scalars(&self.vector(4, what)?))
    }

    /// A rotation (a rotation value only: a matrix is not checked to be one).
    pub fn rotation(self, what: &str) -> Result<So3<S>, ShapeError> {
        match self {
            Value::Rotation(r) => Ok(r),
            other => fail(format!("{what} needs a rotation, not {}", other.describe())),
        }
    }

    /// A pose.
    pub fn pose(self, what: &str) -> Result<Se3<S>, ShapeError> {
        match self {
            Value::Pose(p) => Ok(p),
            other => fail(format!("{what} needs a pose, not {}", other.describe())),
        }
    }

    /// A scalar operand.
    pub fn scalar_of(self, what: &str) -> Result<S, ShapeError> {
        match self.as_scalar() {
            Some(x) => Ok(x),
            None => fail(format!("{what} needs a scalar, not {}", self.describe())),
        }
    }

    /// `−x`.
    pub fn negated(self) -> Result<Self, ShapeError> {
        self.scale(-S::one())
    }

    /// `c x`.
    pub fn scale(self, c: S) -> Result<Self, ShapeError> {
        Ok(match self {
            Value::Identity(k) => Value::Identity(k * c),
            Value::Zero => Value::Zero,
            zero @ Value::BlockZero(..) => zero,
            Value::Blocks(b) => Value::Blocks(b.map(|v| v.scale(c))?),
            other => Value::Matrix(other.matrix()? * c),
        })
    }

    /// `a + b` (or `a − b` when `minus`).
    pub fn add(self, b: Self, minus: bool) -> Result<Self, ShapeError> {
        let b = if minus { b.negated()? } else { b };
        match (self, b) {
            (Value::Zero | Value::BlockZero(..), x) | (x, Value::Zero | Value::BlockZero(..)) => {
                Ok(x)
            }
            (Value::Identity(p), Value::Identity(q)) => Ok(Value::Identity(p + q)),
            (a, b) => {
                let hint = a.shape().or(b.shape());
                let hint = (hint.map(|s| s.0), hint.map(|s| s.1));
                let (a, b) = (a.sized(hint)?, b.sized(hint)?);
                if a.shape() != b.shape() {
                    return fail(format!(
                        "a {} matrix plus a {} matrix",
                        shape_text(a.shape()),
                        shape_text(b.shape())
                    ));
                }
                Ok(Value::Matrix(a + b))
            }
        }
    }

    /// `a b`: scalars scale, groups compose, a rotation turns a 3-vector
    /// and a pose (or similarity) moves it, matrices multiply; unsized
    /// operands are sized by the other one.
    pub fn times(self, b: Self) -> Result<Self, ShapeError> {
        if let Some(c) = self.as_scalar() {
            return b.scale(c);
        }
        if let Some(c) = b.as_scalar() {
            return self.scale(c);
        }
        match (self, b) {
            (Value::Identity(c), x) | (x, Value::Identity(c)) => x.scale(c),
            (Value::Zero | Value::BlockZero(..), _) | (_, Value::Zero | Value::BlockZero(..)) => {
                Ok(Value::Zero)
            }
            (Value::Rotation(p), Value::Rotation(q)) => Ok(Value::Rotation(p.compose(&q))),
            (Value::Pose(p), Value::Pose(q)) => Ok(Value::Pose(p.compose(&q))),
            (Value::Similarity(p), Value::Similarity(q)) => Ok(Value::Similarity(p.compose(&q))),
            // A pose or similarity acting on a 3-vector: `T p = R p + t`.
            (Value::Pose(t), Value::Matrix(m)) if m.shape() == (3, 1) => Ok(Value::column(
                t.transform_point(&Vector3::from_column_slice(m.as_slice()))
                    .as_slice(),
            )),
            (Value::Similarity(t), Value::Matrix(m)) if m.shape() == (3, 1) => Ok(Value::column(
                t.act(&Vector3::from_column_slice(m.as_slice())).as_slice(),
            )),
            // A homogeneous transformation's matrix times a 3-vector (the
            // only product these shapes have): it moves the point.
            (Value::Matrix(t), Value::Matrix(p))
                if t.shape() == (4, 4) && p.shape() == (3, 1) && homogeneous(&t) =>
            {
                Ok(Value::Matrix(
                    t.view((0, 0), (3, 3)) * p + t.view((0, 3), (3, 1)),
                ))
            }
            (a, b) => {
                let a = match a {
                    Value::Blocks(blocks) => blocks.resolve((None, b.shape().map(|s| s.0)))?,
                    other => other.matrix()?,
                };
                let b = match b {
                    Value::Blocks(blocks) => blocks.resolve((Some(a.ncols()), None))?,
                    other => other.matrix()?,
                };
                if a.ncols() != b.nrows() {
                    return fail(format!(
                        "a {} matrix times a {} matrix",
                        shape_text(a.shape()),
                        shape_text(b.shape())
                    ));
                }
                Ok(Value::Matrix(a * b))
            }
        }
    }

    /// `a · b` between two columns of one length: their scalar product;
    /// otherwise a product.
    pub fn dot(self, b: Self) -> Result<Self, ShapeError> {
        match (self.shape(), b.shape()) {
            (Some((n, 1)), Some((m, 1))) if n == m && n > 1 => {
                let (a, b) = (self.matrix()?, b.matrix()?);
                Ok(Value::scalar(a.dot(&b)))
            }
            _ => self.times(b),
        }
    }

    /// `a × b`: the cross product of two 3-vectors, else a product.
    pub fn cross(self, b: Self) -> Result<Self, ShapeError> {
        match (self.shape(), b.shape()) {
            (Some((3, 1)), Some((3, 1))) => {
                let (a, b) = (self.vector3("×")?, b.vector3("×")?);
                Ok(Value::column(a.cross(&b).as_slice()))
            }
            _ => self.times(b),
        }
    }

    /// `a ⊕ b`: a group composition, a pose or similarity acting on a
    /// point (`T ⊕ p = T p`), the same with transformations as matrices
    /// (square ones compose, a homogeneous 4 × 4 moves a point), or the
    /// product of two quaternions (4-vectors: Hamilton's, or JPL's when
    /// `jpl`).
    pub fn oplus(self, b: Self, jpl: bool) -> Result<Self, ShapeError> {
        match (self.shape(), b.shape()) {
            _ if self.is_group() => self.times(b),
            (Some((4, 1)), Some((4, 1))) => self.quaternion_product(b, jpl),
            // A transformation's matrix: `A ⊕ B = A B`, `A ⊕ p` moves `p`
            // by the homogeneous `A` (`R p + t`).
            (Some((n, m)), Some((k, l))) if n == m && n == k && k == l => self.times(b),
            (Some((4, 4)), Some((3, 1))) => {
                let (a, p) = (self.matrix()?, b.matrix()?);
                Ok(Value::Matrix(
                    a.view((0, 0), (3, 3)) * p + a.view((0, 3), (3, 1)),
                ))
            }
            _ => fail(format!(
                "⊕ of {} and {}: it composes group elements, moves a point by a pose or \
                 multiplies quaternions",
                self.describe(),
                b.describe()
            )),
        }
    }

    /// `a ⊗ b`: the product of two quaternions (Hamilton's, or JPL's when
    /// `jpl`), a group composition, or the Kronecker product of other
    /// matrices (`I_3 ⊗ vᵀ`).
    pub fn otimes(self, b: Self, jpl: bool) -> Result<Self, ShapeError> {
        match (&self, &b) {
            (Value::Rotation(_), Value::Rotation(_))
            | (Value::Pose(_), Value::Pose(_))
            | (Value::Similarity(_), Value::Similarity(_)) => self.times(b),
            _ if self.shape() == Some((4, 1)) && b.shape() == Some((4, 1)) => {
                self.quaternion_product(b, jpl)
            }
            _ => self.kronecker(b),
        }
    }

    /// The product of two quaternions `[x, y, z, w]`: Hamilton's, or JPL's
    /// (Hamilton's with the factors swapped, so that `C(q ⊗ p) = C(q) C(p)`
    /// with `C(q) = R(q)ᵀ`).
    fn quaternion_product(self, b: Self, jpl: bool) -> Result<Self, ShapeError> {
        let (p, q) = (self.quaternion("⊗")?, b.quaternion("⊗")?);
        let product = if jpl { q.mul(&p) } else { p.mul(&q) };
        Ok(Value::column(product.coords().as_slice()))
    }

    /// `A ⊗ B`: the Kronecker product (block `(i, j)` is `A_ij B`); an
    /// unsized identity takes the size of a square other factor.
    fn kronecker(self, b: Self) -> Result<Self, ShapeError> {
        let square = |v: &Value<S>| v.shape().filter(|(r, c)| r == c).map(|s| s.0);
        let (ha, hb) = (square(&b), square(&self));
        let a = self.sized((ha, ha))?;
        let b = b.sized((hb, hb))?;
        let (rows, cols) = (a.nrows() * b.nrows(), a.ncols() * b.ncols());
        checked(rows)?;
        checked(cols)?;
        Ok(Value::Matrix(DMatrix::from_fn(rows, cols, |r, c| {
            a[(r / b.nrows(), c / b.ncols())] * b[(r % b.nrows(), c % b.ncols())]
        })))
    }

    /// `a / b` for a scalar `b`.
    pub fn divided_by(self, b: Self) -> Result<Self, ShapeError> {
        match b.as_scalar() {
            Some(d) => self.scale(d.recip()),
            None => fail(format!("division by {}", b.describe())),
        }
    }

    /// `aᵀ`: a rotation's inverse; a pose's 4 × 4 transpose.
    pub fn transpose(self) -> Result<Self, ShapeError> {
        Ok(match self {
            Value::Rotation(r) => Value::Rotation(r.inverse()),
            Value::Identity(_) | Value::Zero => self,
            Value::BlockZero(rows, cols) => Value::BlockZero(cols, rows),
            other => Value::Matrix(other.matrix()?.transpose()),
        })
    }

    /// `a⁻¹`: of a scalar, a group element, a quaternion (a 4-vector) or a
    /// square matrix of size up to 3 (by its adjugate).
    pub fn inverse(self) -> Result<Self, ShapeError> {
        match self {
            Value::Rotation(r) => Ok(Value::Rotation(r.inverse())),
            Value::Pose(p) => Ok(Value::Pose(p.inverse())),
            Value::Similarity(x) => Ok(Value::Similarity(x.inverse())),
            Value::Identity(c) => Ok(Value::Identity(c.recip())),
            Value::Matrix(m) if m.shape() == (4, 1) => {
                let q = Quaternion::from_scalars(m.as_slice());
                Ok(Value::column(q.inverse().coords().as_slice()))
            }
            Value::Matrix(m) => inverse(&m).map(Value::Matrix),
            other => fail(format!("the inverse of {}", other.describe())),
        }
    }

    /// `x^p` for a number `p`: a scalar's power (a half-integer `p` through
    /// the square root), a square matrix's integer power, `p = −1` the
    /// inverse.
    pub fn power(self, p: f64) -> Result<Self, ShapeError> {
        if p == -1.0 {
            return self.inverse();
        }
        if let Some(x) = self.as_scalar() {
            return Ok(Value::scalar(scalar_power(x, p)));
        }
        let integer = p.fract() == 0.0 && (1.0..=16.0).contains(&p);
        match self.shape() {
            Some((r, c)) if r == c && integer => {
                let base = self.clone();
                let mut out = self;
                for _ in 1..p as usize {
                    out = out.times(base.clone())?;
                }
                Ok(out)
            }
            _ => fail(format!("{} to the power {p}", self.describe())),
        }
    }

    /// `|x|`: the absolute value of a scalar, the Euclidean (Frobenius)
    /// norm of a vector or matrix.
    pub fn norm(self) -> Result<Self, ShapeError> {
        if let Some(x) = self.as_scalar() {
            return Ok(Value::scalar(x.abs()));
        }
        let m = self.matrix()?;
        let squares = m.iter().fold(S::zero(), |acc, x| acc + *x * *x);
        Ok(Value::scalar(squares.sqrt()))
    }

    /// `ω^∧`, `⌊ω⌋×`: the skew matrix of a 3-vector, or the 4 × 4 twist
    /// matrix of a 6-vector `[ω, ρ]`.
    pub fn hat(self) -> Result<Self, ShapeError> {
        match self.shape() {
            Some((3, 1)) => {
                let w = self.vector3("^∧")?;
                Ok(Value::Matrix(dynamic(&factor_core::lie::so3::hat(&w))))
            }
            // se(3), `[ω, ρ]`: `[ω^, ρ; 0, 0]`; sim(3), `[ω, ρ, σ]`:
            // `[ω^ + σ I, ρ; 0, 0]`.
            Some((n @ (6 | 7), 1)) => {
                let v = self.vector(n, "^∧")?;
                let mut m = DMatrix::zeros(4, 4);
                let w = Vector3::new(v[0], v[1], v[2]);
                m.view_mut((0, 0), (3, 3))
                    .copy_from(&factor_core::lie::so3::hat(&w));
                for i in 0..3 {
                    m[(i, 3)] = v[3 + i];
                    if n == 7 {
                        m[(i, i)] = v[6];
                    }
                }
                Ok(Value::Matrix(m))
            }
            _ => fail(format!("the hat of {}", self.describe())),
        }
    }

    /// Whether it is a matrix of so(3) (3 × 3 skew) or se(3) (a 4 × 4
    /// twist: a skew block, a translation column, a zero last row), read
    /// from its numbers; `None` for a value with no numbers (symbolic) or
    /// of another size.
    pub fn in_algebra(&self) -> Option<bool> {
        let m = match self {
            Value::Matrix(m) => m,
            Value::Rotation(_) | Value::Pose(_) | Value::Similarity(_) => return Some(false),
            _ => return None,
        };
        let n = m.nrows();
        if !matches!(m.shape(), (3, 3) | (4, 4)) {
            return None;
        }
        let at = |r: usize, c: usize| m[(r, c)].known_value();
        let mut scale: f64 = 0.0;
        let mut off: f64 = 0.0;
        for r in 0..n {
            for c in 0..n {
                let v = at(r, c)?;
                scale = scale.max(v.abs());
                let broken = if r == 3 {
                    v
                } else if c < 3 {
                    v + at(c, r)?
                } else {
                    0.0
                };
                off = off.max(broken.abs());
            }
        }
        Some(off <= 1e-9 * scale.max(1.0))
    }

    /// `S^∨`: the vector of a 3 × 3 skew matrix, or the 6-vector `[ω, ρ]`
    /// of a 4 × 4 twist matrix (another matrix has none).
    pub fn vee(self) -> Result<Self, ShapeError> {
        if self.in_algebra() == Some(false) {
            return fail(format!(
                "the vee of {} that is not in so(3) or se(3)",
                self.describe()
            ));
        }
        let m = self.matrix()?;
        match m.shape() {
            (3, 3) => Ok(Value::column(&[m[(2, 1)], m[(0, 2)], m[(1, 0)]])),
            (4, 4) => Ok(Value::column(&[
                m[(2, 1)],
                m[(0, 2)],
                m[(1, 0)],
                m[(0, 3)],
                m[(1, 3)],
                m[(2, 3)],
            ])),
            shape => fail(format!("the vee of a {} matrix", shape_text(shape))),
        }
    }

    /// Whether it is a group element (a rotation, pose or similarity).
    pub fn is_group(&self) -> bool {
        matches!(
            self,
            Value::Rotation(_) | Value::Pose(_) | Value::Similarity(_)
        )
    }

    /// `self ⊖ base` in local coordinates on `side` (`Log(base⁻¹ self)` on
    /// the right, `Log(self base⁻¹)` on the left), for group elements of
    /// one kind.
    pub fn minus(self, base: Self, side: Perturbation) -> Result<Self, ShapeError> {
        fn on<S: Scalar, G: LieGroup<S>>(a: &G, b: &G, side: Perturbation) -> G::Tangent {
            a.minus(b, side)
        }
        Ok(match (&self, &base) {
            (Value::Rotation(a), Value::Rotation(b)) => {
                Value::column(on::<S, So3<S>>(a, b, side).as_slice())
            }
            (Value::Pose(a), Value::Pose(b)) => {
                Value::column(on::<S, Se3<S>>(a, b, side).as_slice())
            }
            (Value::Similarity(a), Value::Similarity(b)) => {
                Value::column(on::<S, Sim3<S>>(a, b, side).as_slice())
            }
            _ => {
                return fail(format!(
                    "local coordinates of {} about {}",
                    self.describe(),
                    base.describe()
                ));
            }
        })
    }
}

/// A size hint: rows and columns where known.
pub type Hint = (Option<usize>, Option<usize>);

fn checked(n: usize) -> Result<usize, ShapeError> {
    if n == 0 || n > MAX_DIMENSION {
        return fail(format!(
            "a dimension of {n} (a value may have 1 to {MAX_DIMENSION} rows and columns)"
        ));
    }
    Ok(n)
}

/// The entries of a matrix value a derivative of it moves, column by
/// column: all of them, but the fixed last row `[0 0 0 1]` of a
/// homogeneous transformation (its top 3 × 4, as `vec` of a pose's matrix
/// is taken); and their shape.
pub fn moving_entries<S: Scalar>(m: &DMatrix<S>) -> (Vec<S>, (usize, usize)) {
    let homogeneous = m.shape() == (4, 4)
        && (0..4).all(|c| m[(3, c)].known_value() == Some(if c == 3 { 1.0 } else { 0.0 }));
    if homogeneous {
        let top = m.rows(0, 3).into_owned();
        (top.as_slice().to_vec(), (3, 4))
    } else {
        (m.as_slice().to_vec(), m.shape())
    }
}

/// A fixed-size matrix as a dynamic one.
pub fn dynamic<S: Scalar, const R: usize, const C: usize>(
    m: &nalgebra::SMatrix<S, R, C>,
) -> DMatrix<S> {
    DMatrix::from_column_slice(R, C, m.as_slice())
}

/// `x^p`: integer powers by multiplication, half-integers through `√x`,
/// others as `exp(p ln x)`.
pub fn scalar_power<S: Scalar>(x: S, p: f64) -> S {
    let integer = |k: f64, base: S| {
        let mut out = S::one();
        for _ in 0..(k.abs() as u32) {
            out *= base;
        }
        if k < 0.0 { out.recip() } else { out }
    };
    if p.fract() == 0.0 && p.abs() <= 64.0 {
        integer(p, x)
    } else if (2.0 * p).fract() == 0.0 && p.abs() <= 64.0 {
        integer(2.0 * p, x.sqrt())
    } else {
        (x.ln() * S::from_f64(p)).exp()
    }
}

/// The inverse of a square matrix: of size 1 to 3 by its adjugate (no
/// pivoting: generic over the scalar, exact), larger by elimination.
fn inverse<S: Scalar>(m: &DMatrix<S>) -> Result<DMatrix<S>, ShapeError> {
    match m.shape() {
        (1, 1) => Ok(DMatrix::from_element(1, 1, m[(0, 0)].recip())),
        (2, 2) => {
            let d = (m[(0, 0)] * m[(1, 1)] - m[(0, 1)] * m[(1, 0)]).recip();
            Ok(DMatrix::from_row_slice(
                2,
                2,
                &[m[(1, 1)] * d, -m[(0, 1)] * d, -m[(1, 0)] * d, m[(0, 0)] * d],
            ))
        }
        (3, 3) => {
            let a = Matrix3::from_column_slice(m.as_slice());
            let c = |i: usize, j: usize| {
                let (r0, r1) = ((i + 1) % 3, (i + 2) % 3);
                let (c0, c1) = ((j + 1) % 3, (j + 2) % 3);
                a[(r0, c0)] * a[(r1, c1)] - a[(r0, c1)] * a[(r1, c0)]
            };
            let det = a[(0, 0)] * c(0, 0) + a[(0, 1)] * c(0, 1) + a[(0, 2)] * c(0, 2);
            let inv = det.recip();
            // (A⁻¹)ᵢⱼ = Cⱼᵢ / det, the cyclic cofactors carry their signs.
            Ok(DMatrix::from_fn(3, 3, |i, j| c(j, i) * inv))
        }
        (n, k) if n == k => Ok(gauss_jordan_inverse(m)),
        shape => fail(format!("the inverse of a {} matrix", shape_text(shape))),
    }
}

/// The inverse of a larger square matrix by Gauss–Jordan elimination, each
/// pivot the entry of largest magnitude in its column (read from the
/// numbers: a symbolic matrix takes the diagonal in order). A singular
/// matrix gives non-finite entries, which the audit reports.
fn gauss_jordan_inverse<S: Scalar>(m: &DMatrix<S>) -> DMatrix<S> {
    let n = m.nrows();
    let mut a = m.clone();
    let mut inv = DMatrix::<S>::identity(n, n);
    for col in 0..n {
        let size = |r: usize| a[(r, col)].known_value().map_or(0.0, f64::abs);
        let pivot = (col..n)
            .max_by(|&x, &y| size(x).total_cmp(&size(y)))
            .unwrap_or(col);
        a.swap_rows(col, pivot);
        inv.swap_rows(col, pivot);
        let scale = a[(col, col)].recip();
        for c in 0..n {
            a[(col, c)] *= scale;
            inv[(col, c)] *= scale;
        }
        for r in (0..n).filter(|r| *r != col) {
            let factor = a[(r, col)];
            for c in 0..n {
                let (ac, ic) = (a[(col, c)], inv[(col, c)]);
                a[(r, c)] -= factor * ac;
                inv[(r, c)] -= factor * ic;
            }
        }
    }
    inv
}

/// The determinant of a square matrix of size 1 to 3.
pub fn determinant<S: Scalar>(m: &DMatrix<S>) -> Result<S, ShapeError> {
    match m.shape() {
        (1, 1) => Ok(m[(0, 0)]),
        (2, 2) => Ok(m[(0, 0)] * m[(1, 1)] - m[(0, 1)] * m[(1, 0)]),
        (3, 3) => {
            let minor = |r0: usize, r1: usize, c0: usize, c1: usize| {
                m[(r0, c0)] * m[(r1, c1)] - m[(r0, c1)] * m[(r1, c0)]
            };
            Ok(
                m[(0, 0)] * minor(1, 2, 1, 2) - m[(0, 1)] * minor(1, 2, 0, 2)
                    + m[(0, 2)] * minor(1, 2, 0, 1),
            )
        }
        shape => fail(format!(
            "the determinant of a {} matrix (only sizes up to 3 × 3)",
            shape_text(shape)
        )),
    }
}

/// A 4-vector quaternion value from its coordinates.
pub fn quaternion_value<S: Scalar>(q: &Quaternion<S>) -> Value<S> {
    let c: Vector4<S> = q.coords();
    Value::column(c.as_slice())
}

/// A block matrix as printed, some of whose blocks are not sized.
#[derive(Debug, Clone, PartialEq)]
pub struct Blocks<S: Scalar> {
    /// The block rows as printed (they may differ in length).
    pub rows: Vec<Vec<Value<S>>>,
}

impl<S: Scalar> Blocks<S> {
    /// The block matrix, sized now if its blocks tell every size, else kept
    /// as [`Value::Blocks`] for where it is used to tell the rest.
    pub fn build(rows: Vec<Vec<Value<S>>>) -> Result<Value<S>, ShapeError> {
        let blocks = Blocks { rows };
        match blocks.clone().sized((None, None), false) {
            Ok(m) => Ok(Value::Matrix(m)),
            Err(e) if e.0.contains("cannot be told") => Ok(Value::Blocks(blocks)),
            Err(e) => Err(e),
        }
    }

    fn map(self, f: impl Fn(Value<S>) -> Result<Value<S>, ShapeError>) -> Result<Self, ShapeError> {
        let rows = self
            .rows
            .into_iter()
            .map(|row| row.into_iter().map(&f).collect())
            .collect::<Result<_, _>>()?;
        Ok(Blocks { rows })
    }

    /// The matrix, its total size (rows, columns) fixed where `hint` gives
    /// it; a block row (column) of zeros nothing sizes is then one row
    /// (column).
    pub fn resolve(self, hint: Hint) -> Result<DMatrix<S>, ShapeError> {
        match self.clone().sized(hint, false) {
            Err(e) if e.0.contains("cannot be told") => self.sized(hint, true),
            other => other,
        }
    }

    fn sized(self, hint: Hint, zeros_are_scalars: bool) -> Result<DMatrix<S>, ShapeError> {
        let n = self.rows.first().map_or(0, Vec::len);
        if self.rows.iter().all(|r| r.len() == n) {
            return grid(self.rows, hint, zeros_are_scalars);
        }
        // Rows of different lengths: each block row on its own, stacked.
        let count = self.rows.len();
        let mut parts = Vec::with_capacity(count);
        for row in self.rows {
            let one_row_hint = (if count == 1 { hint.0 } else { None }, hint.1);
            parts.push(grid(vec![row], one_row_hint, zeros_are_scalars)?);
        }
        stack(&parts)
    }
}

/// Block rows stacked vertically.
fn stack<S: Scalar>(parts: &[DMatrix<S>]) -> Result<DMatrix<S>, ShapeError> {
    let cols = parts[0].ncols();
    if let Some(p) = parts.iter().find(|p| p.ncols() != cols) {
        return fail(format!("block rows of {} and {} columns", cols, p.ncols()));
    }
    let rows: usize = parts.iter().map(|p| p.nrows()).sum();
    let mut out = DMatrix::zeros(checked(rows)?, cols);
    let mut at = 0;
    for p in parts {
        out.view_mut((at, 0), p.shape()).copy_from(p);
        at += p.nrows();
    }
    Ok(out)
}

/// Whether a block has no size of its own.
fn has_no_size<S: Scalar>(v: &Value<S>) -> bool {
    matches!(
        v,
        Value::Identity(_) | Value::Zero | Value::BlockZero(..) | Value::Blocks(_)
    )
}

/// A rectangular grid of blocks: heights per block row and widths per
/// block column from the sized blocks, then identities (square), the
/// hint's totals, and rows or columns of scalars (size 1); last, when
/// `zeros_are_scalars`, a block row (column) of zeros nothing else sizes is
/// one row (column).
fn grid<S: Scalar>(
    rows: Vec<Vec<Value<S>>>,
    hint: Hint,
    zeros_are_scalars: bool,
) -> Result<DMatrix<S>, ShapeError> {
    let (nr, nc) = (rows.len(), rows.first().map_or(0, Vec::len));
    if nr == 0 || nc == 0 {
        return fail("an empty matrix");
    }
    let mut heights: Vec<Option<usize>> = vec![None; nr];
    let mut widths: Vec<Option<usize>> = vec![None; nc];
    for (i, row) in rows.iter().enumerate() {
        for (j, v) in row.iter().enumerate() {
            if let Some((r, c)) = v.shape() {
                for (slot, n, what, k) in [
                    (&mut heights[i], r, "rows", i),
                    (&mut widths[j], c, "columns", j),
                ] {
                    match *slot {
                        Some(m) if m != n => {
                            return fail(format!(
                                "the blocks of block {} {} have {m} and {n} {what}",
                                if what == "rows" { "row" } else { "column" },
                                k + 1
                            ));
                        }
                        _ => *slot = Some(n),
                    }
                }
            }
        }
    }
    loop {
        let before = (heights.clone(), widths.clone());
        for (i, row) in rows.iter().enumerate() {
            for (j, v) in row.iter().enumerate() {
                if matches!(v, Value::Identity(_)) {
                    match (heights[i], widths[j]) {
                        (Some(h), None) => widths[j] = Some(h),
                        (None, Some(w)) => heights[i] = Some(w),
                        _ => {}
                    }
                }
            }
        }
        fill_from_total(&mut heights, hint.0);
        fill_from_total(&mut widths, hint.1);
        // A block row all of whose blocks are unsized, in columns one wide,
        // is a row of scalars; the same for columns.
        for i in 0..nr {
            if heights[i].is_none()
                && rows[i].iter().all(has_no_size)
                && widths.iter().all(|w| w.is_none_or(|w| w == 1))
            {
                heights[i] = Some(1);
            }
        }
        for j in 0..nc {
            if widths[j].is_none()
                && rows.iter().all(|r| has_no_size(&r[j]))
                && heights.iter().all(|h| h.is_none_or(|h| h == 1))
            {
                widths[j] = Some(1);
            }
        }
        if (heights.clone(), widths.clone()) == before
            && printed_zero_sizes(&rows, &mut heights, &mut widths)
        {
            continue;
        }
        if (heights.clone(), widths.clone()) == before {
            // Nothing else tells: a block row of zeros printed once is a
            // row of scalars (`[ω^∧ v; 0 0]`), and so is a column.
            let zeros = |v: &Value<S>| matches!(v, Value::Zero);
            let row = (0..nr).find(|&i| heights[i].is_none() && rows[i].iter().all(zeros));
            let column =
                (0..nc).find(|&j| widths[j].is_none() && rows.iter().all(|r| zeros(&r[j])));
            match (row, column) {
                (Some(i), _) if zeros_are_scalars => heights[i] = Some(1),
                (_, Some(j)) if zeros_are_scalars => widths[j] = Some(1),
                _ => break,
            }
        }
    }
    let unknown = heights
        .iter()
        .position(Option::is_none)
        .map(|i| (i, 0))
        .or_else(|| widths.iter().position(Option::is_none).map(|j| (0, j)));
    if let Some((i, j)) = unknown {
        return fail(format!(
            "the size of block ({}, {}) cannot be told from the formula",
            i + 1,
            j + 1
        ));
    }
    let heights: Vec<usize> = heights.into_iter().flatten().collect();
    let widths: Vec<usize> = widths.into_iter().flatten().collect();
    let total = (
        checked(heights.iter().sum())?,
        checked(widths.iter().sum())?,
    );
    let mut out = DMatrix::zeros(total.0, total.1);
    let mut r0 = 0;
    for (i, row) in rows.into_iter().enumerate() {
        let mut c0 = 0;
        for (j, v) in row.into_iter().enumerate() {
            let m = v.sized((Some(heights[i]), Some(widths[j])))?;
            if m.shape() != (heights[i], widths[j]) {
                return fail(format!(
                    "block ({}, {}) is {}, its row and column make it {}",
                    i + 1,
                    j + 1,
                    shape_text(m.shape()),
                    shape_text((heights[i], widths[j]))
                ));
            }
            out.view_mut((r0, c0), m.shape()).copy_from(&m);
            c0 += widths[j];
        }
        r0 += heights[i];
    }
    if let Some(r) = hint.0.filter(|r| *r != total.0) {
        return fail(format!("a matrix of {} rows where {r} are needed", total.0));
    }
    if let Some(c) = hint.1.filter(|c| *c != total.1) {
        return fail(format!(
            "a matrix of {} columns where {c} are needed",
            total.1
        ));
    }
    Ok(out)
}

/// Fills unknown block heights and widths from the sizes zeros are printed
/// with (`[\mathbf{0}_3; 1]`), once nothing else tells them: first the
/// printed rows and columns, then the square block a single size stands for;
/// whether anything was filled.
fn printed_zero_sizes<S: Scalar>(
    rows: &[Vec<Value<S>>],
    heights: &mut [Option<usize>],
    widths: &mut [Option<usize>],
) -> bool {
    let mut filled = false;
    for square in [false, true] {
        for (i, row) in rows.iter().enumerate() {
            for (j, v) in row.iter().enumerate() {
                let Value::BlockZero(r, c) = v else { continue };
                let (r, c) = if square {
                    (r.or(*c), c.or(*r))
                } else {
                    (*r, *c)
                };
                if heights[i].is_none() && r.is_some() {
                    heights[i] = r;
                    filled = true;
                }
                if widths[j].is_none() && c.is_some() {
                    widths[j] = c;
                    filled = true;
                }
            }
        }
        if filled {
            return true;
        }
    }
    false
}

/// Fills the one unknown size of `sizes` from their total, if known.
fn fill_from_total(sizes: &mut [Option<usize>], total: Option<usize>) {
    let Some(total) = total else { return };
    let unknown: Vec<usize> = (0..sizes.len()).filter(|i| sizes[*i].is_none()).collect();
    if let [i] = unknown.as_slice() {
        let known: usize = sizes.iter().flatten().sum();
        if total > known {
            sizes[*i] = Some(total - known);
        }
    }
}

/// Whether a 4 × 4 matrix's last row is `[0 0 0 1]` (a homogeneous
/// transformation's), read from its numbers.
fn homogeneous<S: Scalar>(t: &DMatrix<S>) -> bool {
    (0..4).all(|c| t[(3, c)].known_value() == Some(if c == 3 { 1.0 } else { 0.0 }))
}

#[cfg(test)]
mod tests {
    use super::*;

    fn m(rows: usize, cols: usize, v: &[f64]) -> Value<f64> {
        Value::Matrix(DMatrix::from_row_slice(rows, cols, v))
    }

    #[test]
    fn blocks_are_sized_by_their_neighbours_and_scalars() {
        // [K 0] with K 3 × 3: the zero's width comes from the next factor.
        let k = m(3, 3, &[1.0, 0.0, 0.0, 0.0, 2.0, 0.0, 0.0, 0.0, 3.0]);
        let row = Blocks::build(vec![vec![k, Value::Zero]]).unwrap();
        assert!(matches!(row, Value::Blocks(_)));
        let next = Value::Matrix(DMatrix::from_element(6, 2, 1.0));
        let product = row.times(next).unwrap().matrix().unwrap();
        assert_eq!(product.shape(), (3, 2));
        // [0 0 0] is a row of scalars.
        let zeros =
            Blocks::<f64>::build(vec![vec![Value::Zero, Value::Zero, Value::Zero]]).unwrap();
        assert_eq!(zeros.shape(), Some((1, 3)));
        // [I  a×] with a 3 × 3 block: I is 3 × 3.
        let i_block = Blocks::build(vec![vec![Value::Identity(1.0), m(3, 3, &[0.0; 9])]]).unwrap();
        assert_eq!(i_block.shape(), Some((3, 6)));
    }

    #[test]
    fn products_that_do_not_multiply_are_errors() {
        let a = m(2, 3, &[0.0; 6]);
        let b = m(4, 3, &[0.0; 12]);
        assert_eq!(
            a.times(b).unwrap_err().0,
            "a 2 × 3 matrix times a 4 × 3 matrix"
        );
    }

    #[test]
    fn inverses_and_powers() {
        let a = m(3, 3, &[2.0, 1.0, 0.0, 0.0, 1.0, 3.0, 1.0, 0.0, 1.0]);
        let inv = a.clone().inverse().unwrap();
        let id = a.times(inv).unwrap().matrix().unwrap();
        assert!((id - DMatrix::<f64>::identity(3, 3)).norm() < 1e-12);
        // Larger: by elimination with pivoting (a zero first pivot).
        let b = m(
            4,
            4,
            &[
                0.0, 2.0, 1.0, 0.5, 1.0, 0.0, 3.0, 1.0, 2.0, 1.0, 0.0, 4.0, 1.0, 1.0, 1.0, 1.0,
            ],
        );
        let id = b
            .clone()
            .times(b.inverse().unwrap())
            .unwrap()
            .matrix()
            .unwrap();
        assert!((id - DMatrix::<f64>::identity(4, 4)).norm() < 1e-12);
        assert!((scalar_power(4.0, 1.5) - 8.0).abs() < 1e-12);
        assert!((scalar_power(2.0, -2.0) - 0.25).abs() < 1e-12);
    }
}
