//! Property and edge-case tests of `factor_core::lie`.
//!
//! Conventions under test: quaternions `[x, y, z, w]`, Hamilton product,
//! `R(q) v = q ⊗ [v, 0] ⊗ q⁻¹`; `hat(ω) b = ω × b`;
//! `Jl(ω) = I + (1−cos θ)/θ² W + (θ−sin θ)/θ³ W²`, `Jr(ω) = Jl(−ω)`;
//! SE(3) tangents `[ω, ρ]`.
//!
//! References are computed independently of the code under test: matrix
//! exponentials and Jacobians as power series of `W` summed in `f64` with
//! many terms (the inverse Jacobian as the LU inverse of that series), the
//! quaternion's half-angle functions as scalar Taylor sums, and the defining
//! properties of the Jacobians by forward-mode differentiation (dual numbers)
//! of the exact `Exp`/`Log`.

use std::f64::consts::{FRAC_1_SQRT_2, FRAC_PI_2, PI};

use factor_core::lie::so3::{
    exp_matrix, hat, left_jacobian, left_jacobian_inverse, right_jacobian, right_jacobian_inverse,
    vee,
};
use factor_core::lie::{Quaternion, SMALL_ANGLE_SQUARED, Se3, So2, So3};
use factor_core::linalg::squared_norm;
use factor_core::{Manifold, Perturbation, Scalar, Storage};
use nalgebra::{Const, Matrix3, Matrix4, SMatrix, SVector, U1, Vector3, Vector4, Vector6};
use num_dual::DualSVec64;
use proptest::prelude::*;

type D3 = DualSVec64<3>;

const TAU: f64 = 2.0 * PI;
const SIDES: [Perturbation; 2] = [Perturbation::Left, Perturbation::Right];

// ---------------------------------------------------------------------------
// Helpers: dual numbers
// ---------------------------------------------------------------------------

/// The derivative part of a dual number.
fn grad<const N: usize>(x: &DualSVec64<N>) -> SVector<f64, N> {
    x.eps.unwrap_generic(Const::<N>, U1)
}

/// Rows: outputs, columns: seeded inputs.
fn jacobian<const R: usize, const N: usize>(v: &SVector<DualSVec64<N>, R>) -> SMatrix<f64, R, N> {
    SMatrix::from_fn(|i, j| grad(&v[i])[j])
}

/// Real parts.
fn values<const R: usize, const C: usize, const N: usize>(
    m: &SMatrix<DualSVec64<N>, R, C>,
) -> SMatrix<f64, R, C> {
    m.map(|x| x.re)
}

/// The derivative of every entry w.r.t. seeded input `k`.
fn partial<const R: usize, const C: usize, const N: usize>(
    m: &SMatrix<DualSVec64<N>, R, C>,
    k: usize,
) -> SMatrix<f64, R, C> {
    m.map(|x| grad(&x)[k])
}

/// `x + δ` with `δ` the seeded inputs.
fn seeded<const N: usize>(x: &SVector<f64, N>) -> SVector<DualSVec64<N>, N> {
    SVector::from_fn(|i, _| DualSVec64::from_re(x[i]).derivative(i))
}

/// The seeded inputs at zero, as a retraction's `δ`.
fn seeded_zero<const N: usize>() -> [DualSVec64<N>; N] {
    std::array::from_fn(|i| DualSVec64::from_re(0.0).derivative(i))
}

/// A constant lifted to dual numbers (zero derivative).
fn lift<const N: usize, M: Storage<f64>>(x: &M) -> M::With<DualSVec64<N>> {
    x.map_scalars(&mut |s| DualSVec64::<N>::from_re(s))
}

fn dual_finite<const R: usize, const C: usize, const N: usize>(
    m: &SMatrix<DualSVec64<N>, R, C>,
) -> bool {
    m.iter()
        .all(|x| x.re.is_finite() && grad(x).iter().all(|d| d.is_finite()))
}

fn finite<const R: usize, const C: usize>(m: &SMatrix<f64, R, C>) -> bool {
    m.iter().all(|x| x.is_finite())
}

/// Largest absolute entry difference.
fn diff<const R: usize, const C: usize>(a: &SMatrix<f64, R, C>, b: &SMatrix<f64, R, C>) -> f64 {
    (a - b).amax()
}

/// Distance between quaternions up to sign (`q` and `−q` are one rotation).
fn diff_up_to_sign(a: &Quaternion<f64>, b: &Quaternion<f64>) -> f64 {
    a.max_abs_diff(b).min(a.max_abs_diff(&b.negated()))
}

// ---------------------------------------------------------------------------
// Helpers: independent references
// ---------------------------------------------------------------------------

/// The skew matrix of `w`, written out independently of `so3::hat`.
fn skew<S: Scalar>(w: &Vector3<S>) -> Matrix3<S> {
    let z = S::zero();
    Matrix3::new(z, -w[2], w[1], w[2], z, -w[0], -w[1], w[0], z)
}

/// `Σ_{k<50} W^k / c_k` with `c_k = k!` (`shift = 0`) or `(k+1)!` (`shift = 1`).
/// For `θ ≤ π` the largest term is below 6 and the tail below `1e-40`.
/// Generic, so on dual numbers it also gives the series' derivatives.
fn power_series<S: Scalar>(w: &Vector3<S>, shift: usize) -> Matrix3<S> {
    let h = skew(w);
    let mut term = Matrix3::<S>::identity();
    let mut sum = term;
    for k in 1..50 {
        let divisor = S::from_f64((k + shift) as f64);
        term = (term * h).map(|x| x / divisor);
        sum += term;
    }
    sum
}

/// `Exp(ω) = Σ W^k / k!`.
fn exp_series<S: Scalar>(w: &Vector3<S>) -> Matrix3<S> {
    power_series(w, 0)
}

/// `Jl(ω) = Σ W^k / (k+1)!`, the series defining the left Jacobian.
fn jl_series<S: Scalar>(w: &Vector3<S>) -> Matrix3<S> {
    power_series(w, 1)
}

/// `Jr(ω) = Σ (−W)^k / (k+1)!`.
fn jr_series<S: Scalar>(w: &Vector3<S>) -> Matrix3<S> {
    jl_series(&-w)
}

/// `Jl(ω)⁻¹` as the LU inverse of the series.
fn jl_inverse_reference(w: &Vector3<f64>) -> Matrix3<f64> {
    jl_series(w)
        .try_inverse()
        .expect("Jl is invertible for θ < 2π")
}

/// `(sin(θ/2)/θ, cos(θ/2))` by their Taylor sums in `x = θ/2`:
/// `sin(x)/(2x) = ½ Σ (−1)^j x^{2j}/(2j+1)!`, `cos x = Σ (−1)^j x^{2j}/(2j)!`.
fn half_angle_series(theta: f64) -> (f64, f64) {
    let x2 = (theta / 2.0) * (theta / 2.0);
    let (mut s_term, mut c_term) = (0.5, 1.0);
    let (mut s, mut c) = (s_term, c_term);
    for j in 1..60 {
        let j = j as f64;
        s_term *= -x2 / ((2.0 * j) * (2.0 * j + 1.0));
        c_term *= -x2 / ((2.0 * j - 1.0) * (2.0 * j));
        s += s_term;
        c += c_term;
    }
    (s, c)
}

/// The unit quaternion of `exp(ω)` from the scalar series.
fn quaternion_reference(w: &Vector3<f64>) -> Vector4<f64> {
    let (k, c) = half_angle_series(w.norm());
    Vector4::new(k * w[0], k * w[1], k * w[2], c)
}

/// `[v, 0]` as a quaternion.
fn pure(v: &Vector3<f64>) -> Quaternion<f64> {
    Quaternion::from_parts(*v, 0.0)
}

fn vector6(w: &Vector3<f64>, rho: &Vector3<f64>) -> Vector6<f64> {
    Vector6::new(w[0], w[1], w[2], rho[0], rho[1], rho[2])
}

/// Adjacent magnitudes `lo < hi = next_up(lo)` with `g(lo) < threshold ≤ g(hi)`,
/// starting the search at `start`; `g` must be increasing around there.
fn straddle(g: impl Fn(f64) -> f64, threshold: f64, start: f64) -> (f64, f64) {
    let mut t = start;
    while g(t) >= threshold {
        t = t.next_down();
    }
    while g(t.next_up()) < threshold {
        t = t.next_up();
    }
    let (lo, hi) = (t, t.next_up());
    assert!(g(lo) < threshold && g(hi) >= threshold);
    (lo, hi)
}

/// A handful of fixed directions, including axes and a generic one.
fn directions() -> Vec<Vector3<f64>> {
    vec![
        Vector3::x(),
        Vector3::y(),
        Vector3::z(),
        Vector3::new(1.0, 2.0, 3.0).normalize(),
        Vector3::new(-0.3, 0.9, -0.1).normalize(),
    ]
}

// ---------------------------------------------------------------------------
// Strategies
// ---------------------------------------------------------------------------

/// Uniform on the unit sphere (Archimedes: `z` uniform, azimuth uniform).
fn unit_vector() -> impl Strategy<Value = Vector3<f64>> {
    (-1.0f64..=1.0, 0.0..TAU).prop_map(|(z, phi)| {
        let r = (1.0 - z * z).max(0.0).sqrt();
        Vector3::new(r * phi.cos(), r * phi.sin(), z)
    })
}

/// Rotation vectors with `|ω| ∈ [0, max)`, with extra weight on the
/// small-angle series region and on exactly zero.
fn rotation_vector(max: f64) -> impl Strategy<Value = Vector3<f64>> {
    let magnitude = prop_oneof![
        1 => Just(0.0),
        2 => 0.0..2.5e-3,
        8 => 0.0..max,
        2 => (max - 1e-2).max(0.0)..max,
    ];
    (unit_vector(), magnitude).prop_map(|(n, t)| n * t)
}

fn unit_quaternion() -> impl Strategy<Value = Quaternion<f64>> {
    prop::array::uniform4(-1.0f64..1.0)
        .prop_filter("not too close to zero", |c| {
            c.iter().map(|x| x * x).sum::<f64>() > 1e-2
        })
        .prop_map(|c| Quaternion::from_coords(Vector4::from(c).normalize()))
}

fn translation() -> impl Strategy<Value = Vector3<f64>> {
    prop::array::uniform3(-5.0f64..5.0).prop_map(Vector3::from)
}

fn pose() -> impl Strategy<Value = Se3<f64>> {
    (unit_quaternion(), translation()).prop_map(|(q, t)| Se3::new(So3::from_quaternion(q), t))
}

fn unit_vector6() -> impl Strategy<Value = Vector6<f64>> {
    prop::array::uniform6(-1.0f64..1.0)
        .prop_filter("not too close to zero", |c| {
            c.iter().map(|x| x * x).sum::<f64>() > 1e-2
        })
        .prop_map(|c| Vector6::from(c).normalize())
}

// ---------------------------------------------------------------------------
// Property tests
// ---------------------------------------------------------------------------

proptest! {
    #![proptest_config(ProptestConfig::with_cases(256))]

    // --- Exp / Log round trips ---------------------------------------------

    #[test]
    fn so3_exp_of_log_is_identity(w in rotation_vector(PI)) {
        let r = So3::exp(&w);
        let back = So3::exp(&r.log());
        prop_assert!(diff(&back.matrix(), &r.matrix()) < 1e-14);
        // Exp lands on SO(3) and agrees with the series.
        let m = r.matrix();
        prop_assert!(diff(&(m.transpose() * m), &Matrix3::identity()) < 1e-14);
        prop_assert!((m.determinant() - 1.0).abs() < 1e-14);
        prop_assert!(diff(&m, &exp_series(&w)) < 1e-14);
    }

    #[test]
    fn so3_exp_of_log_for_every_rotation(q in unit_quaternion()) {
        let r = So3::from_quaternion(q);
        let w = r.log();
        prop_assert!(w.norm() <= PI + 1e-15);
        prop_assert!(diff(&So3::exp(&w).matrix(), &r.matrix()) < 1e-14);
    }

    #[test]
    fn so3_log_of_exp_is_identity(w in rotation_vector(PI - 1e-6)) {
        let back = So3::exp(&w).log();
        prop_assert!((back - w).amax() < 1e-14, "{:?} vs {:?}", back, w);
    }

    #[test]
    fn se3_exp_of_log_is_identity(t in pose()) {
        let xi = t.log();
        let back = Se3::exp(&xi);
        prop_assert!(diff(&back.matrix(), &t.matrix()) < 1e-12);
    }

    #[test]
    fn se3_log_of_exp_is_identity(w in rotation_vector(PI - 1e-6), rho in translation()) {
        let xi = vector6(&w, &rho);
        let back = Se3::exp(&xi).log();
        prop_assert!((back - xi).amax() < 1e-12, "{:?} vs {:?}", back, xi);
    }

    #[test]
    fn se3_exp_is_the_matrix_exponential(w in rotation_vector(PI), rho in translation()) {
        // exp([[W, ρ], [0, 0]]) = Σ_k [[W^k/k!, W^{k−1}ρ/k!], [0, δ_k0]], whose
        // top-right block is (Σ W^j/(j+1)!) ρ = Jl ρ; summed here directly.
        let mut generator = Matrix4::zeros();
        generator.fixed_view_mut::<3, 3>(0, 0).copy_from(&skew(&w));
        generator.fixed_view_mut::<3, 1>(0, 3).copy_from(&rho);
        let mut term = Matrix4::identity();
        let mut sum = term;
        for k in 1..80 {
            term = term * generator / k as f64;
            sum += term;
        }
        let t = Se3::exp(&vector6(&w, &rho));
        prop_assert!(diff(&t.matrix(), &sum) < 1e-13);
    }

    #[test]
    fn se3_group_operations_match_homogeneous_matrices(a in pose(), b in pose(), x in translation()) {
        prop_assert!(diff(&a.compose(&b).matrix(), &(a.matrix() * b.matrix())) < 1e-13);
        prop_assert!(diff(&a.inverse().matrix(), &a.matrix().try_inverse().unwrap()) < 1e-13);
        let h = a.matrix() * Vector4::new(x[0], x[1], x[2], 1.0);
        prop_assert!((a.transform_point(&x) - h.xyz()).amax() < 1e-13);
    }

    // --- Jacobian identities -----------------------------------------------

    #[test]
    fn jacobian_identities(w in rotation_vector(PI - 1e-3)) {
        let (jl, jr) = (left_jacobian(&w), right_jacobian(&w));
        let eye = Matrix3::identity();
        prop_assert!(diff(&jl, &(exp_matrix(&w) * jr)) < 1e-14);
        prop_assert!(diff(&(jl * left_jacobian_inverse(&w)), &eye) < 1e-13);
        prop_assert!(diff(&(jr * right_jacobian_inverse(&w)), &eye) < 1e-13);
        prop_assert!(diff(&(left_jacobian_inverse(&w) * jl), &eye) < 1e-13);
        prop_assert_eq!(jr, left_jacobian(&-w));
        prop_assert_eq!(right_jacobian_inverse(&w), left_jacobian_inverse(&-w));
        // W is skew, so Jl(−ω) = Jl(ω)ᵀ.
        prop_assert!(diff(&jr, &jl.transpose()) < 1e-15);
    }

    #[test]
    fn jacobians_match_their_series(w in rotation_vector(PI)) {
        prop_assert!(diff(&exp_matrix(&w), &exp_series(&w)) < 1e-14);
        prop_assert!(diff(&left_jacobian(&w), &jl_series(&w)) < 1e-14);
        prop_assert!(diff(&right_jacobian(&w), &jr_series(&w)) < 1e-14);
        prop_assert!(diff(&left_jacobian_inverse(&w), &jl_inverse_reference(&w)) < 1e-13);
        prop_assert!(
            diff(&right_jacobian_inverse(&w), &jr_series(&w).try_inverse().unwrap()) < 1e-13
        );
    }

    /// `Exp(ω + δ) Exp(ω)⁻¹ = Exp(Jl(ω) δ + O(δ²))` and
    /// `Exp(ω)⁻¹ Exp(ω + δ) = Exp(Jr(ω) δ + O(δ²))`, by dual numbers.
    #[test]
    fn jacobians_satisfy_their_defining_properties(w in rotation_vector(PI - 1e-3)) {
        let r0 = lift::<3, _>(&So3::exp(&w));
        let moved = So3::exp(&seeded(&w));
        let left = moved.compose(&r0.inverse()).log();
        let right = r0.inverse().compose(&moved).log();
        prop_assert!(diff(&jacobian(&left), &left_jacobian(&w)) < 1e-12);
        prop_assert!(diff(&jacobian(&right), &right_jacobian(&w)) < 1e-12);
        // The real parts are the identity rotation.
        prop_assert!(values(&left).amax() < 1e-15 && values(&right).amax() < 1e-15);
    }

    /// `Log(Exp(δ) Exp(ω)) = ω + Jl(ω)⁻¹ δ + O(δ²)` and
    /// `Log(Exp(ω) Exp(δ)) = ω + Jr(ω)⁻¹ δ + O(δ²)`, by dual numbers.
    #[test]
    fn inverse_jacobians_are_derivatives_of_log(w in rotation_vector(PI - 1e-3)) {
        let r0 = lift::<3, _>(&So3::exp(&w));
        let delta = So3::exp(&seeded(&Vector3::zeros()));
        let left = delta.compose(&r0).log();
        let right = r0.compose(&delta).log();
        prop_assert!(diff(&jacobian(&left), &left_jacobian_inverse(&w)) < 1e-11);
        prop_assert!(diff(&jacobian(&right), &right_jacobian_inverse(&w)) < 1e-11);
    }

    /// From `Exp(ω + δ) ≈ Exp(ω) Exp(Jr(ω) δ)`: `∂Exp(ω)/∂ω_k = Exp(ω) hat(Jr(ω) e_k)`,
    /// checked on the dual derivative of Rodrigues' formula.
    #[test]
    fn exp_matrix_derivative_is_right_jacobian(w in rotation_vector(PI)) {
        let m = exp_matrix(&seeded(&w));
        let r = exp_matrix(&w);
        let jr = right_jacobian(&w);
        for k in 0..3 {
            let expected = r * skew(&jr.column(k).into_owned());
            prop_assert!(diff(&partial(&m, k), &expected) < 1e-13);
        }
    }

    // --- Quaternion path against the matrix path ----------------------------

    #[test]
    fn quaternion_exp_matches_rodrigues(w in rotation_vector(TAU), v in translation()) {
        let q = Quaternion::exp(&w);
        let m = exp_matrix(&w);
        prop_assert!((q.squared_norm() - 1.0).abs() < 1e-15);
        prop_assert!(diff(&q.to_rotation_matrix(), &m) < 1e-14);
        prop_assert!(diff(&q.coords(), &quaternion_reference(&w)) < 1e-15);
        prop_assert!((q.rotate(&v) - m * v).amax() < 1e-13);
    }

    #[test]
    fn rotate_is_the_sandwich_product(q in unit_quaternion(), v in translation()) {
        let sandwich = q.mul(&pure(&v)).mul(&q.inverse());
        prop_assert!(sandwich.w.abs() < 1e-14);
        prop_assert!((q.rotate(&v) - sandwich.vector()).amax() < 1e-13);
        prop_assert!((q.rotate(&v) - q.to_rotation_matrix() * v).amax() < 1e-13);
        prop_assert!((So3::from_quaternion(q).inverse_rotate(&q.rotate(&v)) - v).amax() < 1e-13);
    }

    #[test]
    fn from_rotation_matrix_inverts_to_rotation_matrix(q in unit_quaternion()) {
        let back = Quaternion::from_rotation_matrix(&q.to_rotation_matrix());
        prop_assert!(diff_up_to_sign(&back, &q) < 1e-14, "{:?} vs {:?}", back, q);
        prop_assert!((back.squared_norm() - 1.0).abs() < 1e-14);
    }

    #[test]
    fn hamilton_product_is_matrix_product(a in unit_quaternion(), b in unit_quaternion()) {
        let ab = a.mul(&b);
        prop_assert!(
            diff(&ab.to_rotation_matrix(), &(a.to_rotation_matrix() * b.to_rotation_matrix())) < 1e-14
        );
        let (ra, rb) = (So3::from_quaternion(a), So3::from_quaternion(b));
        prop_assert!(diff(&ra.compose(&rb).matrix(), &(ra.matrix() * rb.matrix())) < 1e-14);
    }

    #[test]
    fn conjugate_is_transpose(q in unit_quaternion()) {
        prop_assert!(diff(&q.conjugate().to_rotation_matrix(), &q.to_rotation_matrix().transpose()) < 1e-15);
        prop_assert!(diff_up_to_sign(&q.mul(&q.conjugate()), &Quaternion::identity()) < 1e-15);
        prop_assert!(q.inverse().max_abs_diff(&q.conjugate()) < 1e-15);
        let r = So3::from_quaternion(q);
        prop_assert!(diff(&r.inverse().matrix(), &r.matrix().transpose()) < 1e-15);
    }

    /// The full-sphere logarithm, including the band just below 2π where the
    /// quaternion is close to `−1`.
    #[test]
    fn quaternion_log_inverts_exp_on_the_whole_sphere(
        n in unit_vector(),
        t in prop_oneof![
            1 => Just(0.0),
            2 => 0.0..2.5e-3,
            6 => 0.0..TAU - 1e-3,
            2 => (TAU - 4e-3)..(TAU - 1e-3),
        ],
    ) {
        let w = n * t;
        let q = Quaternion::exp(&w);
        let back = q.log();
        prop_assert!((back - w).amax() < 1e-12, "{:?} vs {:?}", back, w);
        prop_assert!(Quaternion::exp(&back).max_abs_diff(&q) < 1e-14);
    }

    #[test]
    fn hat_and_vee(a in translation(), b in translation()) {
        prop_assert_eq!(hat(&a), skew(&a));
        prop_assert!((hat(&a) * b - a.cross(&b)).amax() < 1e-13);
        prop_assert_eq!(vee(&hat(&a)), a);
    }

    // --- Retractions -------------------------------------------------------

    /// `retract` and `retract_first_order` agree to `O(|δ|²)`: at three scales
    /// the difference is below `C |δ|²`, and below `1e-7` at `|δ| = 1e-4`.
    #[test]
    fn first_order_retractions_agree_to_second_order(t in pose(), dir in unit_vector6()) {
        let bound = 1.0 + t.translation.norm();
        for side in SIDES {
            for scale in [1e-2, 1e-3, 1e-4] {
                let d = dir * scale;
                let exact = t.retract(d.as_slice(), side);
                let first = t.retract_first_order(d.as_slice(), side);
                let e = diff(&exact.matrix(), &first.matrix());
                prop_assert!(e < bound * scale * scale, "{:?} {} {}", side, scale, e);
                if scale == 1e-4 {
                    prop_assert!(e < 1e-7);
                }

                let r = t.rotation;
                let dw = [d[0], d[1], d[2]];
                let e = diff(
                    &r.retract(&dw, side).matrix(),
                    &r.retract_first_order(&dw, side).matrix(),
                );
                prop_assert!(e < scale * scale, "{:?} {} {}", side, scale, e);
                if scale == 1e-4 {
                    prop_assert!(e < 1e-7);
                }
            }
        }
    }

    /// The first-order retractions have the exact retractions' derivative at `δ = 0`.
    #[test]
    fn first_order_retractions_have_the_same_derivative(t in pose()) {
        let td = lift::<6, _>(&t);
        let rd = lift::<3, _>(&t.rotation);
        for side in SIDES {
            let d6 = seeded_zero::<6>();
            let exact = td.retract(&d6, side).matrix();
            let first = td.retract_first_order(&d6, side).matrix();
            prop_assert!(dual_finite(&exact) && dual_finite(&first));
            prop_assert!(diff(&values(&exact), &t.matrix()) < 1e-15);
            for k in 0..6 {
                prop_assert!(diff(&partial(&exact, k), &partial(&first, k)) < 1e-14);
            }
            let d3 = seeded_zero::<3>();
            let exact = rd.retract(&d3, side).matrix();
            let first = rd.retract_first_order(&d3, side).matrix();
            let r = t.rotation.matrix();
            for k in 0..3 {
                // Left: d/dδ Exp(δ) R = hat(e_k) R; right: R hat(e_k).
                let g = skew(&Vector3::ith(k, 1.0));
                let expected = match side {
                    Perturbation::Left => g * r,
                    Perturbation::Right => r * g,
                };
                prop_assert!(diff(&partial(&exact, k), &expected) < 1e-14);
                prop_assert!(diff(&partial(&first, k), &expected) < 1e-14);
            }
        }
    }

    #[test]
    fn retractions_are_the_documented_group_actions(
        t in pose(),
        w in rotation_vector(PI),
        rho in translation(),
    ) {
        let d = vector6(&w, &rho);
        // Left SE(3): T ← Exp(δ) T, with the exact exponential, exactly.
        prop_assert_eq!(t.retract(d.as_slice(), Perturbation::Left), Se3::exp(&d).compose(&t));
        prop_assert!(
            diff(
                &t.retract(d.as_slice(), Perturbation::Left).matrix(),
                &(Se3::exp(&d).matrix() * t.matrix()),
            ) < 1e-12
        );
        // Right SE(3): R ← R Exp(δω), t ← t + R δρ.
        let right = t.retract(d.as_slice(), Perturbation::Right);
        let r = t.rotation.matrix();
        prop_assert!(diff(&right.rotation.matrix(), &(r * exp_series(&w))) < 1e-14);
        prop_assert!((right.translation - (t.translation + r * rho)).amax() < 1e-13);
        // SO(3): left R ← Exp(δ) R, right R ← R Exp(δ).
        let dw = [w[0], w[1], w[2]];
        let rot = t.rotation;
        prop_assert_eq!(rot.retract(&dw, Perturbation::Right), rot.compose(&So3::exp(&w)));
        prop_assert_eq!(rot.retract(&dw, Perturbation::Left), So3::exp(&w).compose(&rot));
        prop_assert!(diff(&rot.retract(&dw, Perturbation::Right).matrix(), &(r * exp_series(&w))) < 1e-14);
        prop_assert!(diff(&rot.retract(&dw, Perturbation::Left).matrix(), &(exp_series(&w) * r)) < 1e-14);
    }

    /// The right SE(3) retraction agrees with `T Exp(δ)` to second order.
    #[test]
    fn right_se3_retraction_is_t_exp_to_second_order(t in pose(), dir in unit_vector6()) {
        let bound = 1.0 + t.translation.norm();
        for scale in [1e-2, 1e-3, 1e-4] {
            let d = dir * scale;
            let e = diff(
                &t.retract(d.as_slice(), Perturbation::Right).matrix(),
                &t.compose(&Se3::exp(&d)).matrix(),
            );
            prop_assert!(e < bound * scale * scale, "{} {}", scale, e);
        }
    }

    // --- SO(2) -------------------------------------------------------------

    #[test]
    fn so2_exp_log_compose_retract(a in -PI..PI, b in -PI..PI, d in -1e-2f64..1e-2) {
        let (wa, wb) = (So2::exp(a), So2::exp(b));
        prop_assert!((wa.cos * wa.cos + wa.sin * wa.sin - 1.0).abs() < 1e-15);
        prop_assert!((wa.log() - a).abs() < 1e-15);
        // Composition adds angles (modulo 2π) and commutes.
        let ab = wa.compose(&wb);
        let sum = So2::exp(a + b);
        prop_assert!((ab.cos - sum.cos).abs() < 1e-15 && (ab.sin - sum.sin).abs() < 1e-15);
        let ba = wb.compose(&wa);
        prop_assert!((ab.cos - ba.cos).abs() < 1e-15 && (ab.sin - ba.sin).abs() < 1e-15);
        let wrapped = (a + b + PI).rem_euclid(TAU) - PI;
        prop_assert!((ab.log() - wrapped).abs() < 1e-14 || (ab.log().abs() - PI).abs() < 1e-14);
        // Retraction: W ← R(δ) W on either side, i.e. angle + δ.
        for side in SIDES {
            let r = wa.retract(&[d], side);
            let expected = So2::exp(a + d);
            prop_assert!((r.cos - expected.cos).abs() < 1e-15 && (r.sin - expected.sin).abs() < 1e-15);
            let first = wa.retract_first_order(&[d], side);
            prop_assert!((first.cos - r.cos).abs() <= d * d && (first.sin - r.sin).abs() <= d * d);
        }
        // Derivatives at δ = 0 agree: d/dδ (cos(a+δ), sin(a+δ)) = (−sin a, cos a).
        let lifted = So2::new(DualSVec64::<1>::from_re(wa.cos), DualSVec64::<1>::from_re(wa.sin));
        let zero = [DualSVec64::<1>::from_re(0.0).derivative(0)];
        for side in SIDES {
            for r in [lifted.retract(&zero, side), lifted.retract_first_order(&zero, side)] {
                prop_assert!((grad(&r.cos)[0] + wa.sin).abs() < 1e-15);
                prop_assert!((grad(&r.sin)[0] - wa.cos).abs() < 1e-15);
            }
        }
    }
}

proptest! {
    // Dual matrix series are slow in debug builds: fewer cases.
    #![proptest_config(ProptestConfig::with_cases(64))]

    /// Dual derivatives of Exp, Jl, Jr, Jl⁻¹, Jr⁻¹ against the series'
    /// derivatives (`1e-12`: the closed forms' cancellation near the switch,
    /// see `so3_functions_are_continuous_across_the_small_angle_switch`).
    #[test]
    fn dual_derivatives_match_the_series(w in rotation_vector(PI - 1e-3)) {
        for (name, f, reference) in so3_matrix_functions() {
            let (value, derivative) = errors(&split(&f(&seeded(&w))), &reference(&w));
            prop_assert!(value < 1e-13 && derivative < 1e-12, "{} {:e} {:e}", name, value, derivative);
        }
    }
}

// ---------------------------------------------------------------------------
// Edge cases
// ---------------------------------------------------------------------------

#[test]
fn everything_is_exact_at_zero() {
    let zero = Vector3::<f64>::zeros();
    let eye = Matrix3::identity();
    // Every series reduces to its constant term at θ = 0.
    assert_eq!(exp_matrix(&zero), eye);
    assert_eq!(left_jacobian(&zero), eye);
    assert_eq!(right_jacobian(&zero), eye);
    assert_eq!(left_jacobian_inverse(&zero), eye);
    assert_eq!(right_jacobian_inverse(&zero), eye);
    assert_eq!(Quaternion::exp(&zero), Quaternion::identity());
    assert_eq!(Quaternion::identity().log(), zero);
    assert_eq!(So3::exp(&zero), So3::identity());
    assert_eq!(So3::<f64>::identity().log(), zero);
    assert_eq!(So3::<f64>::identity().matrix(), eye);
    assert_eq!(So3::from_matrix(&eye), So3::identity());
    assert_eq!(Se3::exp(&Vector6::<f64>::zeros()), Se3::identity());
    assert_eq!(Se3::<f64>::identity().log(), Vector6::zeros());
    assert_eq!(Se3::<f64>::identity().matrix(), Matrix4::identity());
    assert_eq!(So2::exp(0.0), So2::new(1.0, 0.0));
    assert_eq!(So2::new(1.0, 0.0).log(), 0.0);
}

/// At `θ = 0` exactly the derivatives must come from the series arms (the
/// exact arms divide by `θ = √0`, whose derivative is infinite) and equal the
/// known first-order terms.
#[test]
fn dual_derivatives_at_zero_are_finite_and_exact() {
    let d = seeded(&Vector3::zeros());
    let generators: Vec<Matrix3<f64>> = (0..3).map(|k| skew(&Vector3::ith(k, 1.0))).collect();

    // Exp(δ) = I + hat(δ) + O(δ²): the derivatives are the generators, on
    // both the matrix and the quaternion path.
    for m in [exp_matrix(&d), So3::exp(&d).matrix()] {
        assert!(dual_finite(&m));
        assert_eq!(values(&m), Matrix3::identity());
        for (k, g) in generators.iter().enumerate() {
            assert!(diff(&partial(&m, k), g) < 1e-15);
        }
    }
    // Jl(δ) = I + ½ hat(δ) + O(δ²), Jr(δ) = I − ½ hat(δ), Jl⁻¹(δ) = I − ½ hat(δ),
    // Jr⁻¹(δ) = I + ½ hat(δ).
    let cases = [
        (left_jacobian(&d), 0.5),
        (right_jacobian(&d), -0.5),
        (left_jacobian_inverse(&d), -0.5),
        (right_jacobian_inverse(&d), 0.5),
    ];
    for (m, c) in cases {
        assert!(dual_finite(&m));
        assert_eq!(values(&m), Matrix3::identity());
        for (k, g) in generators.iter().enumerate() {
            assert!(diff(&partial(&m, k), &(g * c)) < 1e-15);
        }
    }

    // exp(δ) = [δ/2, 1] + O(δ²).
    let q = Quaternion::exp(&d).coords();
    assert!(dual_finite(&q));
    let mut expected = SMatrix::<f64, 4, 3>::zeros();
    expected
        .fixed_view_mut::<3, 3>(0, 0)
        .copy_from(&(Matrix3::identity() * 0.5));
    assert_eq!(jacobian(&q), expected);

    // log(exp(δ)) = δ on both logs, and via the rotation matrix path.
    let eye = Matrix3::identity();
    for l in [
        Quaternion::exp(&d).log(),
        So3::exp(&d).log(),
        So3::from_matrix(&exp_matrix(&d)).log(),
    ] {
        assert!(dual_finite(&l));
        assert_eq!(values(&l), Vector3::zeros());
        assert!(diff(&jacobian(&l), &eye) < 1e-15);
    }

    // log q = 2 v + O(|v|²) at the identity: ∂/∂v = 2I, ∂/∂w = 0.
    let q = Quaternion::from_coords(seeded(&Vector4::new(0.0, 0.0, 0.0, 1.0)));
    let l = q.log();
    assert!(dual_finite(&l));
    let mut expected = SMatrix::<f64, 3, 4>::zeros();
    expected
        .fixed_view_mut::<3, 3>(0, 0)
        .copy_from(&(eye * 2.0));
    assert_eq!(jacobian(&l), expected);

    // SE(3): Exp(ξ) = I + [[hat(ω), ρ], [0, 0]] + O(ξ²); Log(Exp(ξ)) = ξ.
    let xi = seeded(&Vector6::zeros());
    let t = Se3::exp(&xi);
    let m = t.matrix();
    assert!(dual_finite(&m));
    assert_eq!(values(&m), Matrix4::identity());
    for k in 0..6 {
        let mut g = Matrix4::zeros();
        if k < 3 {
            g.fixed_view_mut::<3, 3>(0, 0).copy_from(&generators[k]);
        } else {
            g[(k - 3, 3)] = 1.0;
        }
        assert!(diff(&partial(&m, k), &g) < 1e-15, "generator {k}");
    }
    let back = t.log();
    assert!(dual_finite(&back));
    assert!(diff(&jacobian(&back), &SMatrix::<f64, 6, 6>::identity()) < 1e-15);
}

/// Small angles (`1e-8`, `1e-4`: both on the series side of the switch, and
/// `3e-3`: on the exact side) against the independent series.
#[test]
fn small_angles_match_the_series_references() {
    for theta in [1e-8, 1e-4, 3e-3] {
        for n in directions() {
            let w = n * theta;
            assert!(diff(&exp_matrix(&w), &exp_series(&w)) < 1e-16 * 4.0);
            assert!(diff(&So3::exp(&w).matrix(), &exp_series(&w)) < 1e-16 * 4.0);
            assert!(diff(&left_jacobian(&w), &jl_series(&w)) < 1e-16 * 4.0);
            assert!(diff(&right_jacobian(&w), &jr_series(&w)) < 1e-16 * 4.0);
            assert!(diff(&left_jacobian_inverse(&w), &jl_inverse_reference(&w)) < 1e-16 * 4.0);
            assert!(
                diff(
                    &right_jacobian_inverse(&w),
                    &jr_series(&w).try_inverse().unwrap()
                ) < 1e-16 * 4.0
            );
            let q = Quaternion::exp(&w).coords();
            assert!(diff(&q, &quaternion_reference(&w)) < 1e-16 * 2.0);
            // Log from the reference rotation (through Shepperd's method), and
            // from the quaternion: relative accuracy.
            let from_matrix = So3::from_matrix(&exp_series(&w)).log();
            assert!(
                (from_matrix - w).amax() < 4e-16 * theta,
                "{theta} {from_matrix:?}"
            );
            let from_quaternion = Quaternion::exp(&w).log();
            assert!(
                (from_quaternion - w).amax() < 4e-16 * theta,
                "{theta} {from_quaternion:?}"
            );
        }
    }
}

/// A matrix function's value and its three partial derivatives w.r.t. `ω`.
type WithPartials = (Matrix3<f64>, [Matrix3<f64>; 3]);

fn split(m: &Matrix3<D3>) -> WithPartials {
    (values(m), std::array::from_fn(|k| partial(m, k)))
}

/// `d(J⁻¹) = −J⁻¹ dJ J⁻¹`.
fn inverse_of((j, dj): WithPartials) -> WithPartials {
    let inv = j.try_inverse().expect("invertible");
    (inv, dj.map(|d| -inv * d * inv))
}

type MatrixFn = fn(&Vector3<D3>) -> Matrix3<D3>;
type ReferenceFn = fn(&Vector3<f64>) -> WithPartials;

/// The SO(3) matrix functions under test, with their series references
/// (value and derivatives, the latter by dual numbers through the series).
fn so3_matrix_functions() -> [(&'static str, MatrixFn, ReferenceFn); 6] {
    [
        ("exp_matrix", exp_matrix, |w| split(&exp_series(&seeded(w)))),
        (
            "So3::exp matrix",
            |w| So3::exp(w).matrix(),
            |w| split(&exp_series(&seeded(w))),
        ),
        ("left_jacobian", left_jacobian, |w| {
            split(&jl_series(&seeded(w)))
        }),
        ("right_jacobian", right_jacobian, |w| {
            split(&jr_series(&seeded(w)))
        }),
        ("left_jacobian_inverse", left_jacobian_inverse, |w| {
            inverse_of(split(&jl_series(&seeded(w))))
        }),
        ("right_jacobian_inverse", right_jacobian_inverse, |w| {
            inverse_of(split(&jr_series(&seeded(w))))
        }),
    ]
}

/// Largest error of a function's value and of its derivatives.
fn errors(actual: &WithPartials, reference: &WithPartials) -> (f64, f64) {
    let value = diff(&actual.0, &reference.0);
    let derivative = (0..3)
        .map(|k| diff(&actual.1[k], &reference.1[k]))
        .fold(0.0, f64::max);
    (value, derivative)
}

/// The branch switch at `θ² = SMALL_ANGLE_SQUARED`: adjacent magnitudes on
/// either side give values that agree to ~1e-15 and derivatives that agree
/// to ~1e-12, and both sides match the series references.
///
/// The exact (closed-form) arms lose derivative digits just above the switch:
/// `(θ − sin θ)/θ³` and `1/θ² − cot(θ/2)/(2θ)` cancel, and their derivatives'
/// absolute error in the matrix is about `ε/θ ≈ 2e-13` at `θ = 1e-3` (measured:
/// up to 6e-14 for `Jl`, 3e-13 for `Jl⁻¹`). The series arms are exact to
/// ~1e-16; both sides' values are exact to ~1e-16.
#[test]
fn so3_functions_are_continuous_across_the_small_angle_switch() {
    for n in directions() {
        let (lo, hi) = straddle(
            |t| squared_norm(&(n * t)),
            SMALL_ANGLE_SQUARED,
            SMALL_ANGLE_SQUARED.sqrt(),
        );
        let (w_lo, w_hi) = (n * lo, n * hi);
        for (name, f, reference) in so3_matrix_functions() {
            let (a, b) = (f(&seeded(&w_lo)), f(&seeded(&w_hi)));
            assert!(dual_finite(&a) && dual_finite(&b), "{name}");
            let (a, b) = (split(&a), split(&b));
            let (value_jump, derivative_jump) = errors(&a, &b);
            assert!(value_jump < 1e-15, "{name}: value jump {value_jump:e}");
            assert!(
                derivative_jump < 1e-12,
                "{name}: derivative jump {derivative_jump:e}"
            );
            // Series side: exact. Closed-form side: value exact, derivative to ε/θ.
            let (value, derivative) = errors(&a, &reference(&w_lo));
            assert!(
                value < 4e-16 && derivative < 1e-15,
                "{name}: {value:e} {derivative:e}"
            );
            let (value, derivative) = errors(&b, &reference(&w_hi));
            assert!(
                value < 4e-16 && derivative < 1e-12,
                "{name}: {value:e} {derivative:e}"
            );
        }
        let (qa, qb) = (
            Quaternion::exp(&seeded(&w_lo)),
            Quaternion::exp(&seeded(&w_hi)),
        );
        assert!(diff(&values(&qa.coords()), &values(&qb.coords())) < 1e-15);
        assert!(diff(&jacobian(&qa.coords()), &jacobian(&qb.coords())) < 1e-15);
    }
}

/// The logarithm's switch is on the quaternion's `|v|² = sin²(θ/2)`, near
/// `θ = 2e-3`: both logs, their values and derivatives are continuous there.
#[test]
fn logs_are_continuous_across_the_small_angle_switch() {
    for n in directions() {
        let g = |t: f64| squared_norm(&Quaternion::exp(&(n * t)).vector());
        let (lo, hi) = straddle(
            g,
            SMALL_ANGLE_SQUARED,
            2.0 * SMALL_ANGLE_SQUARED.sqrt().asin(),
        );
        let mut results = Vec::new();
        for t in [lo, hi] {
            let q = Quaternion::exp(&(n * t));
            // The derivative w.r.t. the quaternion's coordinates, and the
            // derivative of So3::log along left perturbations (= Jl⁻¹(ω)).
            let qd = Quaternion::from_coords(seeded(&q.coords()));
            let along = So3::exp(&seeded(&Vector3::zeros()))
                .compose(&lift::<3, _>(&So3::from_quaternion(q)));
            let (l1, l2) = (qd.log(), along.log());
            assert!(dual_finite(&l1) && dual_finite(&l2));
            assert!((values(&l1) - n * t).amax() < 4e-16 * t);
            assert!(diff(&jacobian(&l2), &jl_inverse_reference(&(n * t))) < 1e-15);
            results.push((values(&l1), jacobian(&l1), jacobian(&l2)));
        }
        let ((v0, j0, k0), (v1, j1, k1)) = (results[0], results[1]);
        assert!((v0 - v1).amax() < 1e-15);
        assert!(diff(&j0, &j1) < 1e-14, "{:e}", diff(&j0, &j1));
        assert!(diff(&k0, &k1) < 1e-14);
    }
}

/// Closed forms, derived by hand:
/// - a quarter turn about z maps x → y and y → −x, so
///   `Exp((0, 0, π/2)) = [[0, −1, 0], [1, 0, 0], [0, 0, 1]]`;
/// - its quaternion is `[0, 0, sin(π/4), cos(π/4)] = [0, 0, 1/√2, 1/√2]`;
/// - the Hamilton units satisfy `i j = k`, `j i = −k`, `i² = −1`.
#[test]
fn closed_forms() {
    let w = Vector3::new(0.0, 0.0, FRAC_PI_2);
    let expected = Matrix3::new(0.0, -1.0, 0.0, 1.0, 0.0, 0.0, 0.0, 0.0, 1.0);
    assert!(diff(&exp_matrix(&w), &expected) < 1e-15);
    assert!(diff(&So3::exp(&w).matrix(), &expected) < 1e-15);
    let q = Quaternion::exp(&w);
    assert!(q.max_abs_diff(&Quaternion::new(0.0, 0.0, FRAC_1_SQRT_2, FRAC_1_SQRT_2)) < 4e-16);
    assert!((q.rotate(&Vector3::x()) - Vector3::y()).amax() < 1e-15);
    assert!((q.rotate(&Vector3::y()) + Vector3::x()).amax() < 1e-15);

    let (i, j, k) = (
        pure(&Vector3::x()),
        pure(&Vector3::y()),
        pure(&Vector3::z()),
    );
    assert_eq!(i.mul(&j), k);
    assert_eq!(j.mul(&i), k.negated());
    assert_eq!(i.mul(&i), Quaternion::identity().negated());

    // Jl of a quarter turn about z: (1 − cos θ)/θ² = 4/π², (θ − sin θ)/θ³ =
    // (π/2 − 1)·8/π³, with W = (π/2) hat(z), W² = −(π/2)² diag(1, 1, 0):
    // Jl = [[a, −b, 0], [b, a, 0], [0, 0, 1]], a = 1 − (π/2 − 1)(2/π) = 2/π,
    // b = (4/π²)(π/2) = 2/π.
    let c = 2.0 / PI;
    let jl = Matrix3::new(c, -c, 0.0, c, c, 0.0, 0.0, 0.0, 1.0);
    assert!(diff(&left_jacobian(&w), &jl) < 1e-15);
    assert!(diff(&jl_series(&w), &jl) < 1e-15);
    assert!(diff(&right_jacobian(&w), &jl.transpose()) < 1e-15);

    // SO(2): W(π/2) = [[0, −1], [1, 0]] is (cos, sin) = (0, 1).
    let r = So2::exp(FRAC_PI_2);
    assert!(r.cos.abs() < 1e-16 && (r.sin - 1.0).abs() < 1e-16);
    assert!((r.log() - FRAC_PI_2).abs() < 1e-16);
    let half = r.compose(&r);
    assert!((half.cos + 1.0).abs() < 1e-16 && half.sin.abs() < 1e-15);
    assert!((half.log().abs() - PI).abs() < 1e-15);
}

/// `θ → π`: `π − 1e-9` and `π` exactly along several axes.
#[test]
fn angles_near_pi() {
    for n in directions() {
        for theta in [PI - 1e-9, PI] {
            let w = n * theta;
            let outputs = [
                exp_matrix(&w),
                So3::exp(&w).matrix(),
                left_jacobian(&w),
                right_jacobian(&w),
                left_jacobian_inverse(&w),
                right_jacobian_inverse(&w),
            ];
            assert!(outputs.iter().all(finite));
            assert!(diff(&exp_matrix(&w), &exp_series(&w)) < 1e-14);
            assert!(diff(&So3::exp(&w).matrix(), &exp_series(&w)) < 1e-14);
            assert!(diff(&left_jacobian(&w), &jl_series(&w)) < 1e-14);
            assert!(diff(&right_jacobian(&w), &jr_series(&w)) < 1e-14);
            assert!(diff(&left_jacobian_inverse(&w), &jl_inverse_reference(&w)) < 1e-14);
            assert!(
                diff(
                    &(left_jacobian(&w) * left_jacobian_inverse(&w)),
                    &Matrix3::identity()
                ) < 1e-14
            );
            assert!(
                diff(
                    &(right_jacobian(&w) * right_jacobian_inverse(&w)),
                    &Matrix3::identity()
                ) < 1e-14
            );

            let r = So3::exp(&w);
            let l = r.log();
            assert!(finite(&l));
            assert!((l.norm() - theta).abs() < 1e-15);
            assert!(diff(&So3::exp(&l).matrix(), &r.matrix()) < 1e-15);
            if theta < PI {
                assert!((l - w).amax() < 1e-15, "{l:?} vs {w:?}");
            } else {
                // At π, ω and −ω are the same rotation; either is correct.
                assert!((l - w).amax().min((l + w).amax()) < 1e-15);
            }
            // The matrix path: Shepperd's method then Log.
            let from_matrix = So3::from_matrix(&exp_series(&w)).log();
            assert!((from_matrix.norm() - theta).abs() < 1e-14);
            assert!((from_matrix - w).amax().min((from_matrix + w).amax()) < 1e-14);

            let rho = Vector3::new(0.5, -1.0, 2.0);
            let t = Se3::exp(&vector6(&w, &rho));
            let xi = t.log();
            assert!(finite(&xi) && finite(&t.matrix()));
            assert!(diff(&Se3::exp(&xi).matrix(), &t.matrix()) < 1e-13);
        }
    }
}

/// Half turns `R = 2 n nᵀ − I` (`Exp(π n)`, symmetric, trace −1, where the
/// `w` pivot of Shepperd's method vanishes): the quaternion is `±[n, 0]` and
/// the logarithm `±π n`.
#[test]
fn half_turns() {
    let axes: [Vector3<f64>; 7] = [
        Vector3::x(),
        Vector3::y(),
        Vector3::z(),
        Vector3::new(1.0, 1.0, 0.0).normalize(),
        Vector3::new(0.0, -1.0, 1.0).normalize(),
        Vector3::new(1.0, 1.0, 1.0).normalize(),
        Vector3::new(1.0, -2.0, 3.0).normalize(),
    ];
    for n in axes {
        let r = n * n.transpose() * 2.0 - Matrix3::identity();
        assert!((r.trace() + 1.0).abs() < 1e-15);
        assert!(diff(&r, &exp_series(&(n * PI))) < 1e-14);

        let q = Quaternion::from_rotation_matrix(&r);
        assert!(finite(&q.coords()), "{n:?}");
        assert!(
            diff_up_to_sign(&q, &Quaternion::from_parts(n, 0.0)) < 1e-15,
            "{n:?} {q:?}"
        );
        assert!(diff(&q.to_rotation_matrix(), &r) < 1e-15);

        let rot = So3::from_matrix(&r);
        let l = rot.log();
        assert!(finite(&l));
        assert!((l.norm() - PI).abs() < 1e-15);
        assert!((l - n * PI).amax().min((l + n * PI).amax()) < 1e-15);
        assert!(diff(&So3::exp(&l).matrix(), &r) < 1e-15);
    }
    // The axis diagonals, spelled out: a half turn about x keeps x and flips y, z.
    let cases = [
        (
            Matrix3::from_diagonal(&Vector3::new(1.0, -1.0, -1.0)),
            Quaternion::new(1.0, 0.0, 0.0, 0.0),
        ),
        (
            Matrix3::from_diagonal(&Vector3::new(-1.0, 1.0, -1.0)),
            Quaternion::new(0.0, 1.0, 0.0, 0.0),
        ),
        (
            Matrix3::from_diagonal(&Vector3::new(-1.0, -1.0, 1.0)),
            Quaternion::new(0.0, 0.0, 1.0, 0.0),
        ),
    ];
    for (m, expected) in cases {
        let q = Quaternion::from_rotation_matrix(&m);
        assert!(diff_up_to_sign(&q, &expected) < 1e-16, "{q:?}");
        assert!((So3::from_quaternion(q).log().norm() - PI).abs() < 1e-15);
    }
    // Just short of a half turn, on both quaternion sheets.
    for n in directions() {
        let w = n * (PI - 1e-9);
        let q = Quaternion::exp(&w);
        for sheet in [q, q.negated()] {
            let l = So3::from_quaternion(sheet).log();
            assert!((l - w).amax() < 1e-15, "{l:?}");
        }
    }
}

/// The full-sphere quaternion logarithm near `q = −1` (angles just below 2π,
/// where `|v|² <` [`SMALL_ANGLE_SQUARED`] but `w ≈ −1`).
#[test]
fn quaternion_log_near_minus_one() {
    for n in directions() {
        for gap in [1e-6, 1e-4, 1e-3, 1.9e-3, 2.1e-3] {
            let w = n * (TAU - gap);
            let q = Quaternion::exp(&w);
            assert!(q.w < 0.0);
            let l = q.log();
            assert!(finite(&l));
            assert!((l - w).amax() < 1e-13, "gap {gap}: {l:?} vs {w:?}");
            assert!(Quaternion::exp(&l).max_abs_diff(&q) < 1e-15);
            // So3::log folds onto w ≥ 0: the short way round, −gap n.
            let short = So3::from_quaternion(q).log();
            assert!((short + n * gap).amax() < 1e-13, "{short:?}");
        }
    }
}

/// All outputs finite over a sweep of magnitudes from 0 to π, for f64 and for
/// duals (derivatives included), on both sides of every switch.
#[test]
fn outputs_are_finite_over_a_sweep() {
    let mut thetas = vec![
        0.0, 1e-300, 1e-160, 1e-20, 1e-12, 1e-8, 1e-4, 9.99e-4, 1.001e-3,
    ];
    thetas.extend((0..=64).map(|i| PI * i as f64 / 64.0));
    thetas.push(PI - 1e-9);
    for n in directions() {
        for &t in &thetas {
            let w = n * t;
            let d = seeded(&w);
            for m in [
                exp_matrix(&d),
                So3::exp(&d).matrix(),
                left_jacobian(&d),
                right_jacobian(&d),
                left_jacobian_inverse(&d),
                right_jacobian_inverse(&d),
            ] {
                assert!(dual_finite(&m), "θ = {t:e}");
            }
            if t < PI {
                assert!(dual_finite(&So3::exp(&d).log()), "θ = {t:e}");
                assert!(dual_finite(&Quaternion::exp(&d).log()), "θ = {t:e}");
            }
            let xi = vector6(&w, &Vector3::new(1.0, 2.0, 3.0));
            assert!(
                finite(&Se3::exp(&xi).log()) && finite(&Se3::exp(&xi).matrix()),
                "θ = {t:e}"
            );
        }
    }
}
