//! SO(3): rotations stored as unit quaternions, with `hat`/`vee`, `Exp`/`Log`
//! and the left and right Jacobians and their inverses.
//!
//! With `θ = |ω|` and `W = hat(ω)`:
//! - `Exp(ω) = I + (sin θ/θ) W + (1 − cos θ)/θ² W²` (Rodrigues);
//! - `Jl(ω) = I + (1 − cos θ)/θ² W + (θ − sin θ)/θ³ W²`;
//! - `Jl⁻¹(ω) = I − ½ W + (1/θ² − cot(θ/2)/(2θ)) W²`, finite up to `θ = π`
//!   (the form `(1 + cos θ)/(2θ sin θ)` of the literature is 0/0 there);
//! - `Jr(ω) = Jl(−ω)`, `Jr⁻¹(ω) = Jl⁻¹(−ω)`, and `Jl(ω) = Exp(ω) Jr(ω)`.

use nalgebra::{Matrix3, Vector3};

use crate::dual::Dual;
use crate::lie::{LieGroup, Quaternion, SMALL_ANGLE_SQUARED};
use crate::linalg::squared_norm;
use crate::manifold::{Manifold, NoLocal, Perturbation};
use crate::scalar::Scalar;
use crate::storage::{Layout, Storage, StorageError};

/// `hat(ω)`, the skew matrix with `hat(ω) b = ω × b`.
pub fn hat<S: Scalar>(w: &Vector3<S>) -> Matrix3<S> {
    let z = S::zero();
    Matrix3::new(z, -w.z, w.y, w.z, z, -w.x, -w.y, w.x, z)
}

/// `vee(S)`, the inverse of [`hat`] (reads the skew part of `S`).
pub fn vee<S: Scalar>(m: &Matrix3<S>) -> Vector3<S> {
    let half = S::from_f64(0.5);
    Vector3::new(
        (m[(2, 1)] - m[(1, 2)]) * half,
        (m[(0, 2)] - m[(2, 0)]) * half,
        (m[(1, 0)] - m[(0, 1)]) * half,
    )
}

/// Evaluates `f(θ)` exactly, or its Taylor series in `θ²` below the small-angle
/// threshold [`SMALL_ANGLE_SQUARED`]. `series` gets `θ²`, `exact` gets `θ`.
///
/// This is how a small-angle case is written so that dual numbers and the
/// symbolic tracer can differentiate it (the rules of [`crate::manifold`]):
/// the branch is decided on `θ²`, a smooth function of its argument, and the
/// series is in `θ²`, so `θ = √θ²`, whose derivative is infinite at zero, is
/// only taken in the exact arm, which is not selected there (both arms are
/// evaluated; the unselected one may be non-finite). `series` must be accurate
/// to machine precision below the threshold (terms up to `θ⁴` suffice when its
/// first omitted term is `O(θ⁶)`).
pub fn angle_coefficient<S: Scalar>(
    theta2: S,
    series: impl Fn(S) -> S,
    exact: impl Fn(S) -> S,
) -> S {
    S::select_lt(
        theta2,
        S::from_f64(SMALL_ANGLE_SQUARED),
        series(theta2),
        exact(theta2.sqrt()),
    )
}

/// `I + a W + b W²`.
fn quadratic_in_hat<S: Scalar>(w: &Vector3<S>, a: S, b: S) -> Matrix3<S> {
    let h = hat(w);
    Matrix3::identity() + h.map(|x| a * x) + (h * h).map(|x| b * x)
}

/// `(1 − cos θ)/θ²` from `θ²`, written `2 sin²(θ/2)/θ²` to avoid
/// cancellation (`cos θ = 1 − θ² · this`).
pub fn one_minus_cos_over_theta2<S: Scalar>(theta2: S) -> S {
    angle_coefficient(
        theta2,
        |t2| S::from_f64(0.5) - t2 / S::from_f64(24.0) + t2 * t2 / S::from_f64(720.0),
        |t| {
            let s = (t * S::from_f64(0.5)).sin();
            S::from_f64(2.0) * s * s / (t * t)
        },
    )
}

/// `(θ − sin θ)/θ³`.
pub(crate) fn theta_minus_sin_over_theta3<S: Scalar>(theta2: S) -> S {
    angle_coefficient(
        theta2,
        |t2| S::from_f64(1.0 / 6.0) - t2 / S::from_f64(120.0) + t2 * t2 / S::from_f64(5040.0),
        |t| (t - t.sin()) / (t * t * t),
    )
}

/// `sin θ / θ` from `θ²`.
pub fn sin_over_theta<S: Scalar>(theta2: S) -> S {
    angle_coefficient(
        theta2,
        |t2| S::one() - t2 / S::from_f64(6.0) + t2 * t2 / S::from_f64(120.0),
        |t| t.sin() / t,
    )
}

/// `1/θ² − cot(θ/2)/(2θ)`, the `W²` coefficient of `Jl⁻¹`.
fn inverse_jacobian_coefficient<S: Scalar>(theta2: S) -> S {
    angle_coefficient(
        theta2,
        |t2| S::from_f64(1.0 / 12.0) + t2 / S::from_f64(720.0) + t2 * t2 / S::from_f64(30240.0),
        |t| {
            let half = t * S::from_f64(0.5);
            S::one() / (t * t) - half.cos() / (S::from_f64(2.0) * t * half.sin())
        },
    )
}

/// `Exp(ω)` as a matrix, by Rodrigues' formula.
pub fn exp_matrix<S: Scalar>(w: &Vector3<S>) -> Matrix3<S> {
    let t2 = squared_norm(w);
    quadratic_in_hat(w, sin_over_theta(t2), one_minus_cos_over_theta2(t2))
}

/// The left Jacobian `Jl(ω)`: `Exp(ω + δ) ≈ Exp(Jl(ω) δ) Exp(ω)`.
pub fn left_jacobian<S: Scalar>(w: &Vector3<S>) -> Matrix3<S> {
    let t2 = squared_norm(w);
    quadratic_in_hat(
        w,
        one_minus_cos_over_theta2(t2),
        theta_minus_sin_over_theta3(t2),
    )
}

/// The right Jacobian `Jr(ω) = Jl(−ω)`: `Exp(ω + δ) ≈ Exp(ω) Exp(Jr(ω) δ)`.
pub fn right_jacobian<S: Scalar>(w: &Vector3<S>) -> Matrix3<S> {
    left_jacobian(&-w)
}

/// `Jl(ω)⁻¹`, finite for `θ < 2π`.
pub fn left_jacobian_inverse<S: Scalar>(w: &Vector3<S>) -> Matrix3<S> {
    let t2 = squared_norm(w);
    quadratic_in_hat(w, S::from_f64(-0.5), inverse_jacobian_coefficient(t2))
}

/// `Jr(ω)⁻¹ = Jl(−ω)⁻¹`.
pub fn right_jacobian_inverse<S: Scalar>(w: &Vector3<S>) -> Matrix3<S> {
    left_jacobian_inverse(&-w)
}

/// A rotation, stored as a unit quaternion `[x, y, z, w]`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct So3<S> {
    /// The unit quaternion; `q` and `−q` are the same rotation.
    pub quaternion: Quaternion<S>,
}

impl<S: Scalar> So3<S> {
    /// From a unit quaternion (not re-normalised).
    pub fn from_quaternion(quaternion: Quaternion<S>) -> Self {
        So3 { quaternion }
    }

    /// The identity.
    pub fn identity() -> Self {
        Self::from_quaternion(Quaternion::identity())
    }

    /// `Exp(ω)`.
    pub fn exp(w: &Vector3<S>) -> Self {
        Self::from_quaternion(Quaternion::exp(w))
    }

    /// `Log(R)`, the rotation vector with `|ω| ≤ π`: the quaternion is first
    /// brought to `w ≥ 0`, so the result is accurate near `θ = π` as well.
    pub fn log(&self) -> Vector3<S> {
        let q = self.quaternion;
        let q = Quaternion::select(q.w, S::zero(), &q.negated(), &q);
        q.log()
    }

    /// From a rotation matrix (Shepperd's method).
    pub fn from_matrix(m: &Matrix3<S>) -> Self {
        Self::from_quaternion(Quaternion::from_rotation_matrix(m))
    }

    /// The rotation matrix.
    pub fn matrix(&self) -> Matrix3<S> {
        self.quaternion.to_rotation_matrix()
    }

    /// `R v`.
    pub fn rotate(&self, v: &Vector3<S>) -> Vector3<S> {
        self.quaternion.rotate(v)
    }

    /// `Rᵀ v`.
    pub fn inverse_rotate(&self, v: &Vector3<S>) -> Vector3<S> {
        self.quaternion.inverse_rotate(v)
    }

    /// `R⁻¹`.
    pub fn inverse(&self) -> Self {
        Self::from_quaternion(self.quaternion.conjugate())
    }

    /// `self · rhs`.
    pub fn compose(&self, rhs: &Self) -> Self {
        Self::from_quaternion(self.quaternion.mul(&rhs.quaternion))
    }
}

/// Stored as its unit quaternion `[qx, qy, qz, qw]`.
impl<S: Scalar> Storage<S> for So3<S> {
    type With<T: Scalar> = So3<T>;
    const SCALARS: usize = 4;
    fn layout() -> Layout {
        <Quaternion<S> as Storage<S>>::layout()
    }
    fn map_scalars<T: Scalar>(&self, f: &mut impl FnMut(S) -> T) -> So3<T> {
        So3::from_quaternion(self.quaternion.map_scalars(f))
    }
    fn read_scalars(next: &mut impl FnMut() -> S) -> Self {
        So3::from_quaternion(Quaternion::read_scalars(next))
    }
    fn from_input(input: &[f64]) -> Result<Vec<f64>, StorageError> {
        <Quaternion<f64> as Storage<f64>>::from_input(input)
    }
}

/// SO(3) in the [`LieGroup`] vocabulary: tangent `ω`, acting on points by
/// `R p`, `Ad_R = R` (since `R Exp(ω) Rᵀ = Exp(R ω)`), Jacobians as in the
/// module documentation. `log` identifies `q` with `−q` (`|ω| ≤ π`).
impl<S: Scalar> LieGroup<S> for So3<S> {
    const DOF: usize = 3;
    type Tangent = Vector3<S>;
    type Jacobian = Matrix3<S>;
    type Point = Vector3<S>;

    fn identity() -> Self {
        So3::identity()
    }
    fn compose(&self, rhs: &Self) -> Self {
        So3::compose(self, rhs)
    }
    fn inverse(&self) -> Self {
        So3::inverse(self)
    }
    fn act(&self, point: &Vector3<S>) -> Vector3<S> {
        self.rotate(point)
    }
    fn exp(tau: &Vector3<S>) -> Self {
        So3::exp(tau)
    }
    fn log(&self) -> Vector3<S> {
        So3::log(self)
    }
    fn adjoint(&self) -> Matrix3<S> {
        self.matrix()
    }
    fn left_jacobian(tau: &Vector3<S>) -> Matrix3<S> {
        left_jacobian(tau)
    }
    fn left_jacobian_inverse(tau: &Vector3<S>) -> Matrix3<S> {
        left_jacobian_inverse(tau)
    }
}

/// Perturbs a unit quaternion by `exp(δ)` on the given side.
pub(crate) fn perturb_quaternion<S: Scalar>(
    q: &Quaternion<S>,
    delta: &[S],
    side: Perturbation,
    exp: fn(&Vector3<S>) -> Quaternion<S>,
) -> Quaternion<S> {
    let d = exp(&Vector3::new(delta[0], delta[1], delta[2]));
    match side {
        Perturbation::Left => d.mul(q),
        Perturbation::Right => q.mul(&d),
    }
}

/// `q` over `Dual<N>` seeded as [`perturb_quaternion`] with
/// [`Quaternion::exp_first_order`] perturbs it: `∂q/∂δ_k = ½ e_k ⊗ q` (left)
/// or `½ q ⊗ e_k` (right), `e_k` the pure quaternion of axis `k`, at
/// coordinate `offset + k` ([`Manifold::seeded`] in closed form).
#[inline(always)]
pub(crate) fn seeded_quaternion<S: Scalar + Into<f64>, const N: usize>(
    q: &Quaternion<S>,
    side: Perturbation,
    offset: usize,
) -> Quaternion<Dual<N>> {
    let q: Quaternion<f64> = q.map_scalars(&mut |s| s.into());
    let mut out = Quaternion::new(
        Dual::constant(q.x),
        Dual::constant(q.y),
        Dual::constant(q.z),
        Dual::constant(q.w),
    );
    for k in 0..3 {
        let mut axis = Vector3::zeros();
        axis[k] = 0.5;
        let half = Quaternion::from_parts(axis, 0.0);
        let d = match side {
            Perturbation::Left => half.mul(&q),
            Perturbation::Right => q.mul(&half),
        };
        let column = offset + k;
        out.x.eps[column] = d.x;
        out.y.eps[column] = d.y;
        out.z.eps[column] = d.z;
        out.w.eps[column] = d.w;
    }
    out
}

/// The inverse of [`perturb_quaternion`] with [`Quaternion::exp`]: `δ` with
/// `exp(δ) ⊗ q = p` (left) or `q ⊗ exp(δ) = p` (right), `|δ| < 2π`, by
/// [`Quaternion::log`] on the whole sphere, so that perturbing `q` by it
/// gives `p` itself, not `−p`. `q`'s inverse is its conjugate (exact on the
/// sphere, and smooth off it in `p`, which is differentiated there).
pub(crate) fn quaternion_local<S: Scalar>(
    q: &Quaternion<S>,
    p: &Quaternion<S>,
    side: Perturbation,
) -> Vector3<S> {
    let step = match side {
        Perturbation::Left => p.mul(&q.conjugate()),
        Perturbation::Right => q.conjugate().mul(p),
    };
    step.log()
}

/// Writes `v` into the first three entries of `out`.
pub(crate) fn write3<S: Scalar>(v: &Vector3<S>, out: &mut [S]) {
    out[..3].copy_from_slice(v.as_slice());
}

/// Left: `R ← Exp(δ) R`; right: `R ← R Exp(δ)`; tangent `δ = [δx, δy, δz]`;
/// `local` inverts both on the quaternion sphere.
impl<S: Scalar> Manifold<S> for So3<S> {
    const DIM: usize = 3;
    fn retract(&self, delta: &[S], side: Perturbation) -> Self {
        Self::from_quaternion(perturb_quaternion(
            &self.quaternion,
            delta,
            side,
            Quaternion::exp,
        ))
    }
    fn retract_first_order(&self, delta: &[S], side: Perturbation) -> Self {
        Self::from_quaternion(perturb_quaternion(
            &self.quaternion,
            delta,
            side,
            Quaternion::exp_first_order,
        ))
    }
    /// In closed form (`seeded_quaternion`).
    #[inline(always)]
    fn seeded<const D: usize, const N: usize>(
        &self,
        side: Perturbation,
        offset: usize,
    ) -> <Self as Storage<S>>::With<Dual<N>>
    where
        S: Into<f64>,
    {
        So3::from_quaternion(seeded_quaternion(&self.quaternion, side, offset))
    }
    fn tangent_description(side: Perturbation) -> &'static str {
        match side {
            Perturbation::Left => "left: R ← Exp(δ) R, columns δ = [δx, δy, δz]",
            Perturbation::Right => "right: R ← R Exp(δ), columns δ = [δx, δy, δz]",
        }
    }
    fn local(&self, other: &Self, side: Perturbation, delta: &mut [S]) -> Result<(), NoLocal> {
        write3(
            &quaternion_local(&self.quaternion, &other.quaternion, side),
            delta,
        );
        Ok(())
    }
}
