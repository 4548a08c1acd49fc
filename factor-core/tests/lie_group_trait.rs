//! The [`LieGroup`] vocabulary of SO(2), SO(3), unit quaternions and SE(3).
//!
//! For every group, at random elements and tangents (with extra weight on
//! `θ = 0`, on the small-angle series and near `θ = π`) and at fixed edge
//! cases:
//! - group axioms, `X Exp(τ) X⁻¹ = Exp(Ad_X τ)`, `Ad_{XY} = Ad_X Ad_Y`,
//!   `Jl(τ) = Ad_{Exp(τ)} Jr(τ)`, `Jl Jl⁻¹ = Jr Jr⁻¹ = I`,
//!   `minus(plus(X, τ, s), X, s) = τ` on both sides, `act` against the
//!   homogeneous matrix (the quaternion sandwich for unit quaternions);
//! - the Jacobians and the adjoint against dual numbers through `Exp`/`Log`
//!   (`Jr(τ) = ∂ Log(Exp(τ)⁻¹ Exp(τ + δ))/∂δ` and so on), and the side
//!   conversion `J_left = J_right · Ad_{X⁻¹}` of the trait documentation.
//!
//! SE(3) also against independent references: the Jacobians as the power
//! series `Σ adᵏ/(k+1)!` of the 6×6 `ad` matrix (inverses by LU), the
//! adjoint by conjugating the 4×4 generators; and against numbers published
//! by GTSAM (`testPose3.cpp`) and manif (`gtest_se3.cpp`), converted as
//! stated at each test.

use std::f64::consts::{FRAC_PI_2, FRAC_PI_4, PI};

use factor_core::lie::so3::hat;
use factor_core::lie::{LieGroup, Quaternion, SMALL_ANGLE_SQUARED, Se3, So2, So3};
use factor_core::{Perturbation, Scalar};
use nalgebra::{
    Const, DVector, Matrix3, Matrix4, Matrix6, SMatrix, SVector, U1, Vector1, Vector2, Vector3,
    Vector4, Vector6,
};
use num_dual::DualSVec64;
use proptest::prelude::*;

type D<const N: usize> = DualSVec64<N>;

const SIDES: [Perturbation; 2] = [Perturbation::Left, Perturbation::Right];

// ---------------------------------------------------------------------------
// The groups under test
// ---------------------------------------------------------------------------

/// A group under test: its `f64` form with `N`-vector tangents acting on
/// `P`-vectors, its dual-number form, and forms independent of the code
/// under test to compare with.
trait Group<const N: usize, const P: usize>:
    LieGroup<f64, Tangent = SVector<f64, N>, Jacobian = SMatrix<f64, N, N>, Point = SVector<f64, P>>
    + std::fmt::Debug
{
    /// The same group over dual numbers.
    type Dual: LieGroup<
            D<N>,
            Tangent = SVector<D<N>, N>,
            Jacobian = SMatrix<D<N>, N, N>,
            Point = SVector<D<N>, P>,
        >;
    /// The element as a constant dual.
    fn lift(&self) -> Self::Dual;
    /// Coordinates that determine the element: the matrix entries, or for
    /// unit quaternions the four coefficients (`q` and `−q` differ there).
    fn coordinates(&self) -> DVector<f64>;
    /// The action computed independently of `act`.
    fn act_reference(&self, p: &SVector<f64, P>) -> SVector<f64, P>;
}

fn d<const N: usize>(x: f64) -> D<N> {
    DualSVec64::from_re(x)
}

fn lift_quaternion<const N: usize>(q: &Quaternion<f64>) -> Quaternion<D<N>> {
    Quaternion::new(d(q.x), d(q.y), d(q.z), d(q.w))
}

fn flatten<const R: usize, const C: usize>(m: &SMatrix<f64, R, C>) -> DVector<f64> {
    DVector::from_iterator(R * C, m.iter().copied())
}

impl Group<1, 2> for So2<f64> {
    type Dual = So2<D<1>>;
    fn lift(&self) -> So2<D<1>> {
        So2::new(d(self.cos), d(self.sin))
    }
    fn coordinates(&self) -> DVector<f64> {
        DVector::from_vec(vec![self.cos, self.sin])
    }
    /// `[[cos, −sin], [sin, cos]] p`, written out.
    fn act_reference(&self, p: &Vector2<f64>) -> Vector2<f64> {
        Vector2::new(
            self.cos * p.x - self.sin * p.y,
            self.sin * p.x + self.cos * p.y,
        )
    }
}

impl Group<3, 3> for So3<f64> {
    type Dual = So3<D<3>>;
    fn lift(&self) -> So3<D<3>> {
        So3::from_quaternion(lift_quaternion(&self.quaternion))
    }
    fn coordinates(&self) -> DVector<f64> {
        flatten(&self.matrix())
    }
    fn act_reference(&self, p: &Vector3<f64>) -> Vector3<f64> {
        self.matrix() * p
    }
}

impl Group<3, 3> for Quaternion<f64> {
    type Dual = Quaternion<D<3>>;
    fn lift(&self) -> Quaternion<D<3>> {
        lift_quaternion(self)
    }
    fn coordinates(&self) -> DVector<f64> {
        DVector::from_iterator(4, self.coords().iter().copied())
    }
    /// `q ⊗ [p, 0] ⊗ q*`, the vector part.
    fn act_reference(&self, p: &Vector3<f64>) -> Vector3<f64> {
        self.mul(&Quaternion::from_parts(*p, 0.0))
            .mul(&self.conjugate())
            .vector()
    }
}

impl Group<6, 3> for Se3<f64> {
    type Dual = Se3<D<6>>;
    fn lift(&self) -> Se3<D<6>> {
        let rotation = So3::from_quaternion(lift_quaternion(&self.rotation.quaternion));
        Se3::new(rotation, self.translation.map(d))
    }
    fn coordinates(&self) -> DVector<f64> {
        flatten(&self.matrix())
    }
    /// `(T [p; 1])` without its last entry.
    fn act_reference(&self, p: &Vector3<f64>) -> Vector3<f64> {
        (self.matrix() * Vector4::new(p.x, p.y, p.z, 1.0)).xyz()
    }
}

// ---------------------------------------------------------------------------
// Helpers
// ---------------------------------------------------------------------------

/// Rows: outputs, columns: the seeded directions.
fn jacobian<const R: usize, const N: usize>(v: &SVector<D<N>, R>) -> SMatrix<f64, R, N> {
    SMatrix::from_fn(|i, j| v[i].eps.unwrap_generic(Const::<N>, U1)[j])
}

/// `x + δ`, `δ` the seeded directions.
fn seeded<const N: usize>(x: &SVector<f64, N>) -> SVector<D<N>, N> {
    SVector::from_fn(|i, _| DualSVec64::from_re(x[i]).derivative(i))
}

/// Largest absolute difference, relative to the larger of 1 and the
/// reference's largest entry.
fn error<const R: usize, const C: usize>(a: &SMatrix<f64, R, C>, b: &SMatrix<f64, R, C>) -> f64 {
    (a - b).amax() / b.amax().max(1.0)
}

fn coordinate_error<const N: usize, const P: usize, G: Group<N, P>>(a: &G, b: &G) -> f64 {
    let (a, b) = (a.coordinates(), b.coordinates());
    (a - &b).amax() / b.amax().max(1.0)
}

/// Every property of the module documentation that needs no derivative,
/// with the worst error it saw.
fn check_identities<const N: usize, const P: usize, G: Group<N, P>>(
    x: &G,
    y: &G,
    tau: &SVector<f64, N>,
    p: &SVector<f64, P>,
) -> Result<(), TestCaseError> {
    const TOL: f64 = 1e-12;
    let eye = SMatrix::<f64, N, N>::identity();
    prop_assert!(coordinate_error(&x.compose(&G::identity()), x) < TOL);
    prop_assert!(coordinate_error(&G::identity().compose(x), x) < TOL);
    prop_assert!(coordinate_error(&x.compose(&x.inverse()), &G::identity()) < TOL);
    prop_assert!(
        coordinate_error(
            &x.compose(y).compose(&G::exp(tau)),
            &x.compose(&y.compose(&G::exp(tau)))
        ) < TOL
    );

    // X Exp(τ) X⁻¹ = Exp(Ad_X τ).
    let conjugated = x.compose(&G::exp(tau)).compose(&x.inverse());
    let e = coordinate_error(&G::exp(&(x.adjoint() * tau)), &conjugated);
    prop_assert!(e < TOL, "X Exp(τ) X⁻¹: {:e}", e);
    // Ad_{XY} = Ad_X Ad_Y, Ad_{X⁻¹} = Ad_X⁻¹.
    let e = error(&(x.adjoint() * y.adjoint()), &x.compose(y).adjoint());
    prop_assert!(e < TOL, "Ad_XY: {:e}", e);
    let e = error(&(x.adjoint() * x.inverse().adjoint()), &eye);
    prop_assert!(e < TOL, "Ad_X⁻¹: {:e}", e);

    // Jl(τ) = Ad_{Exp(τ)} Jr(τ); Jl Jl⁻¹ = Jr Jr⁻¹ = I; Jr(τ) = Jl(−τ).
    let (jl, jr) = (G::left_jacobian(tau), G::right_jacobian(tau));
    let e = error(&(G::exp(tau).adjoint() * jr), &jl);
    prop_assert!(e < TOL, "Jl = Ad Jr: {:e}", e);
    let e = error(&(jl * G::left_jacobian_inverse(tau)), &eye);
    prop_assert!(e < TOL, "Jl Jl⁻¹: {:e}", e);
    let e = error(&(jr * G::right_jacobian_inverse(tau)), &eye);
    prop_assert!(e < TOL, "Jr Jr⁻¹: {:e}", e);
    prop_assert!(error(&G::left_jacobian(&-tau), &jr) < TOL);

    // minus ∘ plus = id on both sides; the sides differ by the adjoint.
    for side in SIDES {
        let back = x.plus(tau, side).minus(x, side);
        let e = error(&back, tau);
        prop_assert!(e < 1e-11, "{:?}: minus(plus) {:e}", side, e);
    }
    let e = coordinate_error(
        &x.plus(tau, Perturbation::Right),
        &x.plus(&(x.adjoint() * tau), Perturbation::Left),
    );
    prop_assert!(e < TOL, "X Exp(τ) = Exp(Ad τ) X: {:e}", e);

    // act against the matrix (or the quaternion sandwich), and as a
    // representation: (XY) p = X (Y p).
    let e = error(&x.act(p), &x.act_reference(p));
    prop_assert!(e < TOL, "act: {:e}", e);
    prop_assert!(error(&x.compose(y).act(p), &x.act(&y.act(p))) < TOL);
    Ok(())
}

/// The Jacobians and the adjoint against dual numbers through `Exp`/`Log`,
/// and the side conversion of a Jacobian.
fn check_against_duals<const N: usize, const P: usize, G: Group<N, P>>(
    x: &G,
    y: &G,
    tau: &SVector<f64, N>,
    p: &SVector<f64, P>,
    tol: f64,
) -> Result<(), TestCaseError> {
    let delta = seeded(&SVector::<f64, N>::zeros());
    let exp_tau = G::exp(tau);
    let moved = <G::Dual as LieGroup<D<N>>>::exp(&seeded(tau));

    // Jr(τ) = ∂ Log(Exp(τ)⁻¹ Exp(τ + δ)), Jl(τ) = ∂ Log(Exp(τ + δ) Exp(τ)⁻¹).
    let jr = jacobian(&exp_tau.inverse().lift().compose(&moved).log());
    let jl = jacobian(&moved.compose(&exp_tau.inverse().lift()).log());
    // Jr⁻¹(τ) = ∂ Log(Exp(τ) Exp(δ)), Jl⁻¹(τ) = ∂ Log(Exp(δ) Exp(τ)).
    let step = <G::Dual as LieGroup<D<N>>>::exp(&delta);
    let jr_inv = jacobian(&exp_tau.lift().compose(&step).log());
    let jl_inv = jacobian(&step.compose(&exp_tau.lift()).log());
    // Ad_X = ∂ Log(X Exp(δ) X⁻¹).
    let ad = jacobian(&x.lift().compose(&step).compose(&x.inverse().lift()).log());
    let cases = [
        ("Jr", G::right_jacobian(tau), jr),
        ("Jl", G::left_jacobian(tau), jl),
        ("Jr⁻¹", G::right_jacobian_inverse(tau), jr_inv),
        ("Jl⁻¹", G::left_jacobian_inverse(tau), jl_inv),
        ("Ad", x.adjoint(), ad),
    ];
    for (name, actual, reference) in cases {
        let e = error(&actual, &reference);
        prop_assert!(
            e < tol,
            "{}: {:e}\n{}\nvs dual\n{}",
            name,
            e,
            actual,
            reference
        );
    }

    // J_left = J_right · Ad_{X⁻¹} and J_right = J_left · Ad_X, for the action
    // on a point and for a relative "between" residual Log(Y⁻¹ X).
    let on_side = |side| x.lift().plus(&delta, side);
    let act = |side| jacobian(&on_side(side).act(&p.map(d)));
    let (act_left, act_right) = (act(Perturbation::Left), act(Perturbation::Right));
    prop_assert!(error(&act_left, &(act_right * x.inverse().adjoint())) < tol);
    prop_assert!(error(&act_right, &(act_left * x.adjoint())) < tol);
    let between = |side| jacobian(&y.inverse().lift().compose(&on_side(side)).log());
    let (between_left, between_right) = (between(Perturbation::Left), between(Perturbation::Right));
    let e = error(&between_left, &(between_right * x.inverse().adjoint()));
    prop_assert!(e < tol, "between, left from right: {:e}", e);
    Ok(())
}

// ---------------------------------------------------------------------------
// Strategies
// ---------------------------------------------------------------------------

fn unit_vector() -> impl Strategy<Value = Vector3<f64>> {
    (-1.0f64..=1.0, 0.0..2.0 * PI).prop_map(|(z, phi)| {
        let r = (1.0 - z * z).max(0.0).sqrt();
        Vector3::new(r * phi.cos(), r * phi.sin(), z)
    })
}

/// Rotation vectors with `|ω| < max`, weighted towards 0, the series region
/// and `max`.
fn rotation_vector(max: f64) -> impl Strategy<Value = Vector3<f64>> {
    let magnitude = prop_oneof![
        1 => Just(0.0),
        2 => 0.0..2.5e-3,
        6 => 0.0..max,
        2 => (max - 1e-2)..max,
    ];
    (unit_vector(), magnitude).prop_map(|(n, t)| n * t)
}

fn point3() -> impl Strategy<Value = Vector3<f64>> {
    prop::array::uniform3(-3.0f64..3.0).prop_map(Vector3::from)
}

fn pose_tangent(max: f64) -> impl Strategy<Value = Vector6<f64>> {
    (rotation_vector(max), point3())
        .prop_map(|(w, rho)| Vector6::new(w[0], w[1], w[2], rho[0], rho[1], rho[2]))
}

/// Below π by at least 1e-6: `Log` of SO(3) and SE(3) returns `|ω| ≤ π`, and
/// at `θ = π` exactly `ω` and `−ω` are one rotation.
const BELOW_PI: f64 = PI - 1e-6;

proptest! {
    #![proptest_config(ProptestConfig::with_cases(256))]

    #[test]
    fn so2(a in -PI..PI, b in -PI..PI, t in -BELOW_PI..BELOW_PI, p in prop::array::uniform2(-3.0f64..3.0)) {
        let (x, y, tau, p) = (So2::exp(a), So2::exp(b), Vector1::new(t), Vector2::from(p));
        check_identities(&x, &y, &tau, &p)?;
        check_against_duals(&x, &y, &tau, &p, 1e-13)?;
    }

    #[test]
    fn so3(a in rotation_vector(PI), b in rotation_vector(PI), tau in rotation_vector(BELOW_PI), p in point3()) {
        let (x, y) = (So3::exp(&a), So3::exp(&b));
        check_identities(&x, &y, &tau, &p)?;
        check_against_duals(&x, &y, &tau, &p, 1e-12)?;
    }

    /// Unit quaternions: tangents up to 1.9π, past where SO(3)'s `Log` folds
    /// (`Jl⁻¹` grows like `cot(θ/2)` towards 2π).
    #[test]
    fn unit_quaternions(a in rotation_vector(2.0 * PI - 1e-3), b in rotation_vector(PI), tau in rotation_vector(1.9 * PI), p in point3()) {
        let (x, y) = (Quaternion::exp(&a), Quaternion::exp(&b));
        check_identities(&x, &y, &tau, &p)?;
        check_against_duals(&x, &y, &tau, &p, 1e-11)?;
    }

    #[test]
    fn se3(a in pose_tangent(PI), b in pose_tangent(PI), tau in pose_tangent(BELOW_PI), p in point3()) {
        let (x, y) = (Se3::exp(&a), Se3::exp(&b));
        check_identities(&x, &y, &tau, &p)?;
        check_against_duals(&x, &y, &tau, &p, 1e-11)?;
    }

    /// SE(3)'s Jacobians against the power series of its `ad` matrix and its
    /// adjoint against conjugated generators.
    #[test]
    fn se3_against_series_and_generators(tau in pose_tangent(BELOW_PI), a in pose_tangent(PI)) {
        check_se3_references(&tau, &Se3::exp(&a))?;
    }
}

// ---------------------------------------------------------------------------
// Fixed edge cases: θ = 0, the small-angle switch, near π
// ---------------------------------------------------------------------------

/// Magnitudes at which every branch is exercised: exactly 0, deep in the
/// series, adjacent to the switch `θ² = SMALL_ANGLE_SQUARED` on both sides,
/// moderate, and just below π.
fn edge_angles() -> Vec<f64> {
    let switch = SMALL_ANGLE_SQUARED.sqrt();
    vec![
        0.0,
        1e-12,
        1e-6,
        switch.next_down(),
        switch,
        switch.next_up(),
        1e-2,
        1.0,
        PI - 1e-3,
        PI - 1e-6,
    ]
}

fn edge_axes() -> Vec<Vector3<f64>> {
    vec![
        Vector3::x(),
        Vector3::z(),
        Vector3::new(1.0, -2.0, 3.0).normalize(),
    ]
}

#[test]
fn edge_cases_for_every_group() {
    let x_tangent = Vector6::new(0.3, -1.2, 0.8, 1.0, -2.0, 0.5);
    let y_tangent = Vector6::new(-2.0, 0.4, 1.1, 0.2, 0.7, -1.5);
    let p = Vector3::new(0.4, -1.3, 2.2);
    let (x_w, y_w) = (x_tangent.xyz(), y_tangent.xyz());
    for theta in edge_angles() {
        let so2 = Vector1::new(theta);
        check_identities(&So2::exp(1.0), &So2::exp(-2.5), &so2, &p.xy()).unwrap();
        check_against_duals(&So2::exp(1.0), &So2::exp(-2.5), &so2, &p.xy(), 1e-13).unwrap();
        for n in edge_axes() {
            let w = n * theta;
            let (x, y) = (So3::exp(&x_w), So3::exp(&y_w));
            check_identities(&x, &y, &w, &p).unwrap();
            check_against_duals(&x, &y, &w, &p, 1e-12).unwrap();
            let (x, y) = (Quaternion::exp(&x_w), Quaternion::exp(&y_w));
            check_identities(&x, &y, &w, &p).unwrap();
            check_against_duals(&x, &y, &w, &p, 1e-12).unwrap();
            for rho in [Vector3::zeros(), Vector3::new(2.0, -1.0, 0.5)] {
                let tau = Vector6::new(w[0], w[1], w[2], rho[0], rho[1], rho[2]);
                let (x, y) = (Se3::exp(&x_tangent), Se3::exp(&y_tangent));
                check_identities(&x, &y, &tau, &p).unwrap();
                check_against_duals(&x, &y, &tau, &p, 1e-11).unwrap();
                check_se3_references(&tau, &x).unwrap();
            }
        }
    }
}

// ---------------------------------------------------------------------------
// SE(3): independent references
// ---------------------------------------------------------------------------

/// `ad_ξ = [[W, 0], [P, W]]` for `ξ = [ω, ρ]`, written out.
fn small_adjoint(xi: &Vector6<f64>) -> Matrix6<f64> {
    let skew = |v: Vector3<f64>| Matrix3::new(0.0, -v.z, v.y, v.z, 0.0, -v.x, -v.y, v.x, 0.0);
    let (w, rho) = (skew(xi.xyz()), skew(Vector3::new(xi[3], xi[4], xi[5])));
    let mut m = Matrix6::zeros();
    m.fixed_view_mut::<3, 3>(0, 0).copy_from(&w);
    m.fixed_view_mut::<3, 3>(3, 3).copy_from(&w);
    m.fixed_view_mut::<3, 3>(3, 0).copy_from(&rho);
    m
}

/// `Σ_{k<80} adᵏ/(k+1)!`, the series defining `Jl(ξ)`. For `θ < π` and
/// `|ρ| < 6` the largest term is below 1e3 and the tail below 1e-40.
fn jl_series(xi: &Vector6<f64>) -> Matrix6<f64> {
    let ad = small_adjoint(xi);
    let mut term = Matrix6::identity();
    let mut sum = term;
    for k in 1..80 {
        term = term * ad / (k + 1) as f64;
        sum += term;
    }
    sum
}

/// `ξ^ = [[W, ρ], [0, 0]]`.
fn wedge(xi: &Vector6<f64>) -> Matrix4<f64> {
    let mut m = Matrix4::zeros();
    m.fixed_view_mut::<3, 3>(0, 0).copy_from(&hat(&xi.xyz()));
    m[(0, 3)] = xi[3];
    m[(1, 3)] = xi[4];
    m[(2, 3)] = xi[5];
    m
}

fn check_se3_references(tau: &Vector6<f64>, x: &Se3<f64>) -> Result<(), TestCaseError> {
    let series_left = jl_series(tau);
    let series_right = jl_series(&-tau);
    let inverse = |m: Matrix6<f64>| m.try_inverse().expect("invertible below 2π");
    let cases = [
        ("Jl", Se3::left_jacobian(tau), series_left),
        ("Jr", Se3::right_jacobian(tau), series_right),
        (
            "Jl⁻¹",
            Se3::left_jacobian_inverse(tau),
            inverse(series_left),
        ),
        (
            "Jr⁻¹",
            Se3::right_jacobian_inverse(tau),
            inverse(series_right),
        ),
    ];
    for (name, actual, reference) in cases {
        let e = error(&actual, &reference);
        prop_assert!(e < 1e-12, "{}: {:e} at {:?}", name, e, tau);
    }
    // Column k of Ad_T is the vee of T e_k^ T⁻¹.
    let t = x.matrix();
    let t_inv = t.try_inverse().expect("rigid");
    let by_generators = Matrix6::from_fn(|i, k| {
        let g = t * wedge(&Vector6::ith(k, 1.0)) * t_inv;
        let vee = [
            g[(2, 1)],
            g[(0, 2)],
            g[(1, 0)],
            g[(0, 3)],
            g[(1, 3)],
            g[(2, 3)],
        ];
        vee[i]
    });
    prop_assert!(error(&x.adjoint(), &by_generators) < 1e-13);
    Ok(())
}

// ---------------------------------------------------------------------------
// Published test vectors
// ---------------------------------------------------------------------------

/// The rotation `Rz(z) Ry(y) Rx(x)` (GTSAM's `Rot3::RzRyRx(x, y, z)`;
/// manif's `SE3(x, y, z, roll, pitch, yaw)` rotation with roll = x, pitch
/// = y, yaw = z).
fn rz_ry_rx(x: f64, y: f64, z: f64) -> So3<f64> {
    So3::exp(&Vector3::new(0.0, 0.0, z))
        .compose(&So3::exp(&Vector3::new(0.0, y, 0.0)))
        .compose(&So3::exp(&Vector3::new(x, 0.0, 0.0)))
}

/// GTSAM orders its Pose3 tangent `[ω, v]` as here, and its `AdjointMap`
/// satisfies `T Exp(ξ) T⁻¹ = Exp(Ad_T ξ)` as here, so its numbers apply
/// unchanged. `TransformCovariance6` in `testPose3.cpp` maps a covariance
/// `Σ` to `Ad Σ Adᵀ` and states the results by hand:
/// - `R = Rz(90°) Ry(90°)`, `t = 0`, `Σ = σσᵀ` with
///   `σ = (0.1, 0.2, 0.3, 0.5, 0.7, 1.1)`: the diagonal becomes
///   `(Σ₁₁, Σ₂₂, Σ₀₀, Σ₄₄, Σ₅₅, Σ₃₃)` and the first column below the diagonal
///   `(−Σ₂₁, Σ₀₁, Σ₄₁, −Σ₅₁, Σ₃₁)`;
/// - `R = I`, `t = (20, 0, 0)`, `Σ` with `σ₁ = 0.7`, `σ₂ = 0.3` fully
///   correlated: `Σ'₅₁ = 0.7²·20`, `Σ'₅₅ = 0.7²·20²`, `Σ'₄₂ = −0.3²·20`,
///   `Σ'₄₄ = 0.3²·20²`, `Σ'₄₁ = −0.3·0.7·20`, `Σ'₅₂ = 0.3·0.7·20`,
///   `Σ'₅₄ = −0.3·0.7·20²`;
/// - `R = Rx(90°)`, `t = (20, 0, 0)`: `Σ₀₀ = 0.1²` alone is unchanged, and
///   `Σ₁₁ = 0.1²` alone becomes the diagonal `(0, 0, 0.1², 0, 0.1²·20², 0)`.
#[test]
fn gtsam_adjoint_covariance_transforms() {
    let transform = |pose: &Se3<f64>, cov: &Matrix6<f64>| {
        let ad = pose.adjoint();
        ad * cov * ad.transpose()
    };
    let deg = PI / 180.0;
    let close = |a: f64, b: f64| (a - b).abs() < 1e-12 * (1.0 + b.abs());

    let sigma = Vector6::new(0.1, 0.2, 0.3, 0.5, 0.7, 1.1);
    let cov = sigma * sigma.transpose();
    let pose = Se3::new(rz_ry_rx(0.0, 90.0 * deg, 90.0 * deg), Vector3::zeros());
    let out = transform(&pose, &cov);
    let diagonal = [
        cov[(1, 1)],
        cov[(2, 2)],
        cov[(0, 0)],
        cov[(4, 4)],
        cov[(5, 5)],
        cov[(3, 3)],
    ];
    for (i, expected) in diagonal.into_iter().enumerate() {
        assert!(close(out[(i, i)], expected), "({i}, {i}): {}", out[(i, i)]);
    }
    let column = [
        -cov[(2, 1)],
        cov[(0, 1)],
        cov[(4, 1)],
        -cov[(5, 1)],
        cov[(3, 1)],
    ];
    for (i, expected) in column.into_iter().enumerate() {
        assert!(close(out[(i + 1, 0)], expected), "({}, 0)", i + 1);
    }

    let mut cov = Matrix6::zeros();
    let (s1, s2) = (0.7, 0.3);
    cov[(1, 1)] = s1 * s1;
    cov[(2, 2)] = s2 * s2;
    cov[(1, 2)] = s1 * s2;
    cov[(2, 1)] = s1 * s2;
    let pose = Se3::new(So3::identity(), Vector3::new(20.0, 0.0, 0.0));
    let out = transform(&pose, &cov);
    let expected = [
        ((5, 1), 0.7 * 0.7 * 20.0),
        ((5, 5), 0.7 * 0.7 * 20.0 * 20.0),
        ((4, 2), -0.3 * 0.3 * 20.0),
        ((4, 4), 0.3 * 0.3 * 20.0 * 20.0),
        ((4, 1), -0.3 * 0.7 * 20.0),
        ((5, 2), 0.3 * 0.7 * 20.0),
        ((5, 4), -0.3 * 0.7 * 20.0 * 20.0),
    ];
    for (index, value) in expected {
        assert!(
            close(out[index], value),
            "{index:?}: {} vs {value}",
            out[index]
        );
    }

    let pose = Se3::new(rz_ry_rx(90.0 * deg, 0.0, 0.0), Vector3::new(20.0, 0.0, 0.0));
    let mut cov = Matrix6::zeros();
    cov[(0, 0)] = 0.01;
    assert!(error(&transform(&pose, &cov), &cov) < 1e-15);
    let mut cov = Matrix6::zeros();
    cov[(1, 1)] = 0.01;
    let out = transform(&pose, &cov);
    let expected = Vector6::new(0.0, 0.0, 0.01, 0.0, 0.01 * 400.0, 0.0);
    assert!(
        (out.diagonal() - expected).amax() < 1e-12,
        "{}",
        out.diagonal()
    );
}

/// GTSAM's `Expmap` is the exact exponential with the `[ω, v]` tangent, as
/// here (`testPose3.cpp`):
/// - `screwPose3`: `Exp((0, 0, 0.3, 0.3, 0, 1)) = (Rz(0.3), (0.29552,
///   0.0446635, 1))`, published to 1e-6;
/// - `expmap_a_full`: `Exp((0.3, 0, 0, 0.2, 0.394742, −2.08998)) =
///   (Rx(0.3), (0.2, 0.7, −2))`, published to 1e-5.
#[test]
fn gtsam_exponential_values() {
    let screw = Se3::exp(&Vector6::new(0.0, 0.0, 0.3, 0.3, 0.0, 1.0));
    let rz = Matrix3::new(
        0.3f64.cos(),
        -0.3f64.sin(),
        0.0,
        0.3f64.sin(),
        0.3f64.cos(),
        0.0,
        0.0,
        0.0,
        1.0,
    );
    assert!(error(&screw.rotation.matrix(), &rz) < 1e-15);
    assert!((screw.translation - Vector3::new(0.29552, 0.0446635, 1.0)).amax() < 1e-6);

    let a = Se3::exp(&Vector6::new(0.3, 0.0, 0.0, 0.2, 0.394742, -2.08998));
    assert!(error(&a.rotation.matrix(), &rz_ry_rx(0.3, 0.0, 0.0).matrix()) < 1e-15);
    assert!((a.translation - Vector3::new(0.2, 0.7, -2.0)).amax() < 1e-5);
}

/// GTSAM's `ExpmapDerivative2` scenario: along `ξ(t) = (2t, sin t, 4t², 2t,
/// sin t, 4t²)`, `d/dt Exp(ξ(t)) = Exp(ξ(t)) (Jr(ξ(t)) ξ'(t))^` with their
/// `ξ'(t) = (2, cos t, 8t, 2, cos t, 8t)`, for `t = −2, −1.7, …, 1.9` (GTSAM
/// compares with a numerical derivative; here the left side is the dual
/// derivative of `Log(Exp(ξ(t₀))⁻¹ Exp(ξ(t)))`). The rotation angle reaches
/// 16.5 rad, far past π: `Jr` has no principal-domain restriction.
#[test]
fn gtsam_expmap_derivative_along_a_trajectory() {
    for step in 0..14 {
        let t = -2.0 + 0.3 * f64::from(step);
        let xi = |t: D<1>| {
            let (two, four) = (d::<1>(2.0), d::<1>(4.0));
            let sin = Scalar::sin(t);
            Vector6::new(two * t, sin, four * t * t, two * t, sin, four * t * t)
        };
        let td = DualSVec64::<1>::from_re(t).derivative(0);
        let at = xi(d(t)).map(|x| x.re);
        let xi_dot = Vector6::new(2.0, t.cos(), 8.0 * t, 2.0, t.cos(), 8.0 * t);
        let base = Se3::exp(&at).inverse();
        let lifted = Se3::new(
            So3::from_quaternion(lift_quaternion(&base.rotation.quaternion)),
            base.translation.map(d),
        );
        let velocity = jacobian(&lifted.compose(&Se3::exp(&xi(td))).log());
        let expected = Se3::right_jacobian(&at) * xi_dot;
        let e = error(&velocity, &expected);
        assert!(e < 1e-12, "t = {t}: {e:e}");
    }
}

/// manif's `TEST_SE3_ACT` (`gtest_se3.cpp`): `SE3(x, y, z, roll, pitch,
/// yaw)` is `(Rz(yaw) Ry(pitch) Rx(roll), (x, y, z))`, and
/// - `SE3(1, 1, 1, π, π/2, π/4).act((1, 1, 1)) = (1, −0.414213562373, 0)`;
/// - `SE3(−1, −1, −1, π/4, −π/2, −π).act((1, 1, 1)) = (0.414213562373, −1, 0)`.
#[test]
fn manif_act_values() {
    let cases = [
        (
            Vector3::new(1.0, 1.0, 1.0),
            (PI, FRAC_PI_2, FRAC_PI_4),
            Vector3::new(1.0, -0.414213562373, 0.0),
        ),
        (
            Vector3::new(-1.0, -1.0, -1.0),
            (FRAC_PI_4, -FRAC_PI_2, -PI),
            Vector3::new(0.414213562373, -1.0, 0.0),
        ),
    ];
    for (t, (roll, pitch, yaw), expected) in cases {
        let pose = Se3::new(rz_ry_rx(roll, pitch, yaw), t);
        let got = pose.act(&Vector3::new(1.0, 1.0, 1.0));
        assert!((got - expected).amax() < 1e-12, "{got:?}");
    }
}
