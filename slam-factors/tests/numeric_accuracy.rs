//! The numerical method (`Factor::linearize_numeric`: Ridders' extrapolation
//! of central differences) against a double-double evaluation of the exact
//! Jacobian (`factor_testing::reference`), on sampled configurations and on
//! configurations approaching each factor's degeneracy.
//!
//! The fixed step of 1e-3 it replaces returned blocks off by 14 % for a line
//! 1e-3 from the optical centre, 72 % for an error quaternion 1e-4 from
//! antipodal and 99 % for a free-line anchor 1e6 from the origin, all with
//! success, and refused a point at depth 1e-4 (its step crossed the image
//! plane); now they are within 2e-9.
//! Asserted here (the README quotes it): every block returned is within
//! 1e-7 of the reference (relative Frobenius; measured 5.8e-8 at worst),
//! within 1e-11 on the sampled configurations (measured 2.3e-13), and within
//! 4 times its own estimate (measured 2.8); where the estimate cannot reach
//! the tolerance, the method fails with `NumericNotConverged`.

use factor_core::factor::relative_frobenius_error;
use factor_core::numeric::NUMERIC_TOLERANCE;
use factor_core::{Factor, FactorError, NumericLinearize};
use factor_testing::near_degenerate::{
    free_line_far, line_at_distance, plane_near_antipodal, point_at_depth,
};
use factor_testing::reference::reference_linearization;
use factor_testing::samples::Sampler;

/// Per block of an accepted linearization: the actual error against the
/// reference and the method's estimate; `None` when it did not converge.
fn errors<F: Factor>(factor: &F) -> Option<Vec<(f64, f64)>> {
    let reference = reference_linearization(factor);
    match factor.linearize_numeric() {
        Ok(numeric) => Some(
            (0..reference.jacobians.len())
                .map(|k| {
                    let actual = relative_frobenius_error(
                        &numeric.linearization.jacobians[k],
                        &reference.jacobians[k],
                        1e-300,
                    );
                    (actual, numeric.relative_block_error(k))
                })
                .collect(),
        ),
        Err(FactorError::NumericNotConverged { estimate, .. }) => {
            assert!(estimate > NUMERIC_TOLERANCE, "{estimate}");
            None
        }
        Err(e) => panic!("{}: {e}", F::NAME),
    }
}

/// Asserts the accepted blocks are within `bound` of the reference and
/// within 4 times their estimate; returns how many configurations did not
/// converge. Configurations the factor itself rejects (outside its
/// accuracy envelope, where no method is accurate) are skipped: only the
/// most extreme ones of a sweep, which starts at its extreme, may be.
fn check<F: Factor>(label: &str, factors: impl IntoIterator<Item = F>, bound: f64) -> usize {
    let mut refused = 0;
    let mut invalid = Vec::new();
    for (i, factor) in factors.into_iter().enumerate() {
        if factor.validate().is_err() {
            invalid.push(i);
            continue;
        }
        let Some(blocks) = errors(&factor) else {
            refused += 1;
            continue;
        };
        for (k, (actual, estimate)) in blocks.into_iter().enumerate() {
            assert!(
                actual <= bound,
                "{label} {i} block {k}: off by {actual:e} (estimate {estimate:e})"
            );
            assert!(
                actual <= 4.0 * estimate.max(1e-14),
                "{label} {i} block {k}: off by {actual:e}, estimated {estimate:e}"
            );
        }
    }
    assert!(
        invalid.iter().enumerate().all(|(k, &i)| k == i),
        "{label}: rejected {invalid:?}"
    );
    refused
}

/// `count` values from `10^lo` to `10^hi`, evenly in the exponent.
fn logspace(lo: f64, hi: f64, count: usize) -> impl Iterator<Item = f64> {
    (0..count).map(move |i| 10f64.powf(lo + (hi - lo) * i as f64 / (count - 1) as f64))
}

#[test]
fn the_issue_configurations_are_accurate() {
    let cases: Vec<(&str, Vec<(f64, f64)>)> = vec![
        (
            "line 1e-3 from the optical centre",
            errors(&line_at_distance(12, 1e-3)).expect("converges"),
        ),
        (
            "error quaternion 1e-4 from antipodal",
            errors(&plane_near_antipodal(3, 1e-4)).expect("converges"),
        ),
        (
            "free-line anchor 1e6 from the origin",
            errors(&free_line_far(5, 1e6)).expect("converges"),
        ),
        (
            // Refused before: the step crossed the image plane.
            "point at depth 1e-4",
            errors(&point_at_depth(10, 1e-4)).expect("converges"),
        ),
    ];
    for (label, blocks) in cases {
        for (k, (actual, estimate)) in blocks.into_iter().enumerate() {
            assert!(
                actual <= 1e-8 && actual <= 4.0 * estimate,
                "{label}, block {k}: off by {actual:e}, estimated {estimate:e}"
            );
        }
    }
}

#[test]
fn sampled_configurations_are_accurate_to_1e_11() {
    let mut s = Sampler::new(77);
    let n = 40;
    let refused = check("point", (0..n).map(|_| s.point_reprojection()), 1e-11)
        + check("line", (0..n).map(|_| s.line_reprojection()), 1e-11)
        + check(
            "plucker",
            (0..n).map(|_| s.plucker_line_reprojection()),
            1e-11,
        )
        + check("plane", (0..n).map(|_| s.plane()), 1e-11)
        + check("free line", (0..n).map(|_| s.free_line()), 1e-11);
    assert_eq!(refused, 0);
}

#[test]
fn near_degenerate_configurations_are_accurate_or_refused() {
    let bound = NUMERIC_TOLERANCE;
    let refused = [
        check(
            "point depth",
            logspace(-8.0, 0.0, 17).map(|z| point_at_depth(10, z)),
            bound,
        ),
        check(
            "line distance",
            logspace(-8.0, 0.0, 17).map(|d| line_at_distance(12, d)),
            bound,
        ),
        check(
            "antipodal",
            logspace(-8.0, 0.0, 17).map(|a| plane_near_antipodal(3, a)),
            bound,
        ),
        check(
            "far free line",
            logspace(0.0, 8.0, 17).map(|d| free_line_far(5, d)),
            bound,
        ),
    ];
    // Refused only where the f64 residual is too noisy for the tolerance:
    // the most extreme configurations of each sweep (measured: 2, 2, 2, 2;
    // before them, the line sweep's two most extreme, 1e-8 and 3.2e-8 from
    // the optical centre, are rejected by the factor itself: observed 74 px
    // from the line, their residuals have lost their digits).
    assert!(
        refused.iter().all(|&r| r <= 3),
        "refused {refused:?} of 17 each"
    );
}

/// A line 1 m from the camera centre seen from the identity pose: the pose
/// Jacobian's column along the normal of the interpretation plane (`δρ_z`
/// here) is exactly zero, the residual being invariant to the scale of
/// `n_c`. Its quotients are rounding alone; the estimate blew up on them
/// and refused the configuration at some focal lengths (420 for the
/// Plücker factor, 400 for the orthonormal one) and not at others.
#[test]
fn an_exactly_zero_column_is_accurate_at_every_focal_length() {
    use factor_core::geometry::{Intrinsics, OrthonormalLine, PluckerLine};
    use factor_core::lie::Se3;
    use nalgebra::{Vector2, Vector3};
    let line = PluckerLine::new(Vector3::new(0.0, -1.0, 0.0), Vector3::new(1.0, 0.0, 0.0));
    let (start, end) = (Vector2::new(100.0, 700.0), Vector2::new(500.0, 720.0));
    let focals = [400.0, 410.0, 420.0, 430.0, 450.0, 480.0, 500.0];
    let intrinsics = |f: f64| Intrinsics::new(f, f, 320.0, 240.0);
    let plucker = focals.map(|f| slam_factors::PluckerLineReprojection {
        intrinsics: intrinsics(f),
        start,
        end,
        pose: Se3::identity(),
        line,
    });
    let orthonormal = focals.map(|f| slam_factors::LineReprojection {
        intrinsics: intrinsics(f),
        start,
        end,
        pose: Se3::identity(),
        line: OrthonormalLine::from_plucker(&line),
    });
    assert_eq!(check("zero column, Plücker", plucker.clone(), 1e-10), 0);
    assert_eq!(check("zero column, orthonormal", orthonormal, 1e-10), 0);
    let numeric = plucker[2].linearize_numeric().unwrap();
    assert_eq!(numeric.linearization.jacobians[0].column(5).amax(), 0.0);
    assert!(numeric.zero_columns[0][5]);
    assert!(
        numeric.column_errors[0][5] < 1e-9,
        "{}",
        numeric.column_errors[0][5]
    );
}
