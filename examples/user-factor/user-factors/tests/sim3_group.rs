//! The group identities of [`Sim3`], as `factor-core/tests/lie_group_trait.rs`
//! checks them for the library's groups, at random elements and tangents
//! (with extra weight on zero rotation and scale, the small-angle series,
//! the switch of `W`'s series at `σ² + θ² = 0.04`, and `θ` near π) and at
//! fixed edge cases:
//!
//! - group axioms; `X Exp(τ) X⁻¹ = Exp(Ad_X τ)`, `Ad_{XY} = Ad_X Ad_Y`,
//!   `Ad_{X⁻¹} = Ad_X⁻¹`; `Log(Exp(τ)) = τ`; the exact retraction inverted
//!   by `Log` on both sides, and `X Exp(τ) = Exp(Ad_X τ) X`; the action
//!   against the homogeneous matrix, which is a representation;
//! - against references independent of the code under test: `Exp` against
//!   the power series of the 4×4 generator, `W` against `Σ Aᵏ/(k+1)!`
//!   (`A = σI + [ω]×`), and the adjoint against dual numbers through `Exp`
//!   and `Log` (`Ad_X = ∂ Log(X Exp(δ) X⁻¹)/∂δ`);
//! - the first-order retraction against the exact one: equal derivatives at
//!   `δ = 0` on both sides (the rule `factor_core::Manifold` states).

use std::f64::consts::PI;

use factor_core::lie::so3::hat;
use factor_core::lie::{SMALL_ANGLE_SQUARED, So3};
use factor_core::{Manifold, Perturbation, Storage};
use nalgebra::{Const, Matrix3, Matrix4, SMatrix, SVector, U1, Vector3, Vector4};
use num_dual::DualSVec64;
use proptest::prelude::*;
use user_factors::sim3::w_matrix::{SERIES_RADIUS_SQUARED, w_matrix, w_matrix_inverse};
use user_factors::sim3::{Sim3, Sim3Tangent};

type D = DualSVec64<7>;
type Tangent = Sim3Tangent<f64>;

const SIDES: [Perturbation; 2] = [Perturbation::Left, Perturbation::Right];

/// Below π by at least 1e-6: `Log` returns rotation angles `θ ≤ π`.
const BELOW_PI: f64 = PI - 1e-6;

/// Largest absolute difference relative to the larger of 1 and the
/// reference's largest entry.
fn error<const R: usize, const C: usize>(a: &SMatrix<f64, R, C>, b: &SMatrix<f64, R, C>) -> f64 {
    (a - b).amax() / b.amax().max(1.0)
}

/// Two elements compared through their homogeneous matrices (`q` and `−q`
/// are one rotation).
fn element_error(a: &Sim3<f64>, b: &Sim3<f64>) -> f64 {
    error(&a.matrix(), &b.matrix())
}

fn tangent(omega: &Vector3<f64>, rho: &Vector3<f64>, sigma: f64) -> Tangent {
    Tangent::from_column_slice(&[omega.x, omega.y, omega.z, rho.x, rho.y, rho.z, sigma])
}

/// `ξ^ = [[[ω]× + σ I, ρ], [0, 0]]`.
fn generator(xi: &Tangent) -> Matrix4<f64> {
    let mut m = Matrix4::zeros();
    let block = hat(&xi.fixed_rows::<3>(0).into_owned()) + Matrix3::identity() * xi[6];
    m.fixed_view_mut::<3, 3>(0, 0).copy_from(&block);
    m.fixed_view_mut::<3, 1>(0, 3)
        .copy_from(&xi.fixed_rows::<3>(3));
    m
}

/// `Σ_{k<60} Mᵏ/(k + offset)!` for a square matrix: `offset = 0` is the
/// exponential, `offset = 1` the `W` series. Exact to rounding for the
/// norms used here (below 5, where the largest term is below 30).
fn power_series<const N: usize>(m: &SMatrix<f64, N, N>, offset: usize) -> SMatrix<f64, N, N> {
    let mut term = SMatrix::<f64, N, N>::identity();
    for k in 1..=offset {
        term /= k as f64;
    }
    let mut sum = term;
    for k in 1..60 {
        term = term * m / (k + offset) as f64;
        sum += term;
    }
    sum
}

/// Every identity of the module documentation that needs no derivative.
fn check_identities(
    x: &Sim3<f64>,
    y: &Sim3<f64>,
    tau: &Tangent,
    p: &Vector3<f64>,
) -> Result<(), TestCaseError> {
    const TOL: f64 = 1e-12;
    let id = Sim3::identity();
    prop_assert!(element_error(&x.compose(&id), x) < TOL);
    prop_assert!(element_error(&id.compose(x), x) < TOL);
    prop_assert!(element_error(&x.compose(&x.inverse()), &id) < TOL);
    let exp = Sim3::exp(tau);
    let e = element_error(&x.compose(y).compose(&exp), &x.compose(&y.compose(&exp)));
    prop_assert!(e < TOL, "associativity: {:e}", e);

    let e = element_error(
        &x.compose(&exp).compose(&x.inverse()),
        &Sim3::exp(&(x.adjoint() * tau)),
    );
    prop_assert!(e < TOL, "X Exp(τ) X⁻¹: {:e}", e);
    let e = error(&(x.adjoint() * y.adjoint()), &x.compose(y).adjoint());
    prop_assert!(e < TOL, "Ad_XY: {:e}", e);
    let eye = SMatrix::<f64, 7, 7>::identity();
    prop_assert!(error(&(x.adjoint() * x.inverse().adjoint()), &eye) < TOL);

    let e = error(&exp.log(), tau);
    prop_assert!(e < 1e-11, "Log(Exp(τ)): {:e}", e);
    for side in SIDES {
        let moved = x.retract(tau.as_slice(), side);
        let back = match side {
            Perturbation::Left => moved.compose(&x.inverse()).log(),
            Perturbation::Right => x.inverse().compose(&moved).log(),
        };
        let e = error(&back, tau);
        prop_assert!(e < 1e-11, "{:?}: Log after retract {:e}", side, e);
    }
    let e = element_error(
        &x.retract(tau.as_slice(), Perturbation::Right),
        &x.retract((x.adjoint() * tau).as_slice(), Perturbation::Left),
    );
    prop_assert!(e < TOL, "X Exp(τ) = Exp(Ad τ) X: {:e}", e);

    let homogeneous = x.matrix() * Vector4::new(p.x, p.y, p.z, 1.0);
    prop_assert!(error(&x.transform_point(p), &homogeneous.xyz()) < TOL);
    prop_assert!(error(&x.compose(y).matrix(), &(x.matrix() * y.matrix())) < TOL);
    Ok(())
}

/// `Exp` and `W` against power series; the adjoint and the first-order
/// retraction against dual numbers.
fn check_references(x: &Sim3<f64>, tau: &Tangent) -> Result<(), TestCaseError> {
    let e = error(&Sim3::exp(tau).matrix(), &power_series(&generator(tau), 0));
    prop_assert!(e < 1e-13, "Exp against the series: {:e}", e);
    let omega = tau.fixed_rows::<3>(0).into_owned();
    let a = hat(&omega) + Matrix3::identity() * tau[6];
    let w = w_matrix(&omega, tau[6]);
    let e = error(&w, &power_series(&a, 1));
    prop_assert!(e < 4e-15, "W against the series: {:e}", e);
    let e = error(
        &(w * w_matrix_inverse(&omega, tau[6])),
        &Matrix3::identity(),
    );
    prop_assert!(e < 1e-13, "W W⁻¹: {:e}", e);

    // δ ↦ X Exp(δ) X⁻¹ through dual numbers: its Log's derivative is Ad_X.
    let lift = |s: &Sim3<f64>| -> Sim3<D> { s.map_scalars(&mut D::from_re) };
    let delta: SVector<D, 7> = SVector::from_fn(|i, _| D::from_re(0.0).derivative(i));
    let conjugated = lift(x)
        .compose(&Sim3::exp(&delta))
        .compose(&lift(&x.inverse()))
        .log();
    let ad = jacobian(&conjugated.iter().copied().collect::<Vec<_>>());
    let e = error(&x.adjoint(), &ad);
    prop_assert!(e < 1e-12, "Ad against duals: {:e}", e);

    // Both retractions have the same derivative at δ = 0 (per stored scalar).
    for side in SIDES {
        let exact = lift(x).retract(delta.as_slice(), side).to_scalars();
        let first = lift(x)
            .retract_first_order(delta.as_slice(), side)
            .to_scalars();
        let e = error(&jacobian::<8>(&first), &jacobian::<8>(&exact));
        prop_assert!(e < 1e-14, "{:?}: first-order retraction {:e}", side, e);
    }
    Ok(())
}

/// Rows: the values, columns: the seeded directions.
fn jacobian<const R: usize>(values: &[D]) -> SMatrix<f64, R, 7> {
    SMatrix::from_fn(|i, j| values[i].eps.unwrap_generic(Const::<7>, U1)[j])
}

fn unit_vector() -> impl Strategy<Value = Vector3<f64>> {
    (-1.0f64..=1.0, 0.0..2.0 * PI).prop_map(|(z, phi)| {
        let r = (1.0 - z * z).max(0.0).sqrt();
        Vector3::new(r * phi.cos(), r * phi.sin(), z)
    })
}

/// `(θ, σ)`, weighted towards zero, the small-angle series, both sides of
/// `W`'s series switch, and `θ` near `max`.
fn angle_and_log_scale(max: f64) -> impl Strategy<Value = (f64, f64)> {
    let r = SERIES_RADIUS_SQUARED.sqrt();
    prop_oneof![
        1 => Just((0.0, 0.0)),
        2 => (0.0..2.5e-3, -1e-3..1e-3),
        3 => (0.0..r, -1.0..1.0f64).prop_map(move |(t, u)| {
            // on the circle r² = 0.04, scaled by 1 ± 1e-6
            let s = (r * r - t * t).max(0.0).sqrt() * u.signum();
            let k = 1.0 + 1e-6 * u;
            (t * k, s * k)
        }),
        6 => (0.0..max, -3.0..3.0f64),
        2 => ((max - 1e-2)..max, -3.0..3.0f64),
    ]
}

fn point3() -> impl Strategy<Value = Vector3<f64>> {
    prop::array::uniform3(-3.0f64..3.0).prop_map(Vector3::from)
}

fn sim3_tangent(max: f64) -> impl Strategy<Value = Tangent> {
    (unit_vector(), angle_and_log_scale(max), point3())
        .prop_map(|(n, (theta, sigma), rho)| tangent(&(n * theta), &rho, sigma))
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(256))]

    #[test]
    fn sim3(a in sim3_tangent(PI), b in sim3_tangent(PI), tau in sim3_tangent(BELOW_PI), p in point3()) {
        let (x, y) = (Sim3::exp(&a), Sim3::exp(&b));
        check_identities(&x, &y, &tau, &p)?;
        check_references(&x, &tau)?;
    }
}

/// Every branch at fixed magnitudes: `θ` at 0, in the series, adjacent to
/// the small-angle switch and near π; `σ` at 0, tiny, adjacent to `W`'s
/// series switch alone (`θ = 0`) and large.
#[test]
fn edge_cases() {
    let switch = SMALL_ANGLE_SQUARED.sqrt();
    let r = SERIES_RADIUS_SQUARED.sqrt();
    let angles = [
        0.0,
        1e-12,
        switch.next_down(),
        switch.next_up(),
        r.next_down(),
        r.next_up(),
        1.0,
        PI - 1e-6,
    ];
    let log_scales = [0.0, 1e-12, -1e-7, r.next_down(), -r.next_up(), 1.5, -3.0];
    let x = Sim3::new(
        So3::exp(&Vector3::new(0.3, -1.2, 0.8)),
        Vector3::new(1.0, -2.0, 0.5),
        0.4,
    );
    let y = Sim3::new(
        So3::exp(&Vector3::new(-2.0, 0.4, 1.1)),
        Vector3::new(0.2, 0.7, -1.5),
        -0.9,
    );
    let p = Vector3::new(0.4, -1.3, 2.2);
    let axis = Vector3::new(1.0, -2.0, 3.0).normalize();
    for theta in angles {
        for sigma in log_scales {
            let tau = tangent(&(axis * theta), &Vector3::new(2.0, -1.0, 0.5), sigma);
            check_identities(&x, &y, &tau, &p).unwrap();
            check_references(&x, &tau).unwrap();
        }
    }
}
