//! The factors `slamjac` ships, each written once as a generic residual with
//! `#[derive(Factor)]` on the runtime crate `factor-core`: the four factors
//! of the specification documents, the Plücker-line variant peers are
//! compared on, the three factors of the estimation problems `slamjac
//! solve` runs (bundle adjustment, stereo visual odometry, pose graphs), a
//! 3D line observation over the documents' orthonormal line, and g2o's own
//! errors for its pose, line, plane, point and prior edges ([`g2o`]).
//!
//! | factor | source | variables (perturbation) |
//! | --- | --- | --- |
//! | [`PointReprojection`] | document 000 §II | pose (left), point (additive) |
//! | [`LineReprojection`] | document 000 §III | pose (left), orthonormal line (left) |
//! | [`PlaneFactor`] | document 000 §IV | pose (left), plane quaternion (left) |
//! | [`FreeLineFactor`] | document 001 | body pose (right), free line (left) |
//! | [`PluckerLineReprojection`] | document 000 §III, (6)–(8) | pose (left), Plücker `[n, v]` (additive) |
//! | [`SnavelyReprojection`] | BAL / Bundler camera | pose (right, `[δρ, δθ]`), `[f, k1, k2]`, point (additive) |
//! | [`StereoReprojection`] | rectified stereo (KITTI VO) | camera-to-world pose (right, `[δρ, δθ]`), landmark (additive) |
//! | [`BetweenFactor`] | pose graphs (g2o, EDGE3) | two body-to-world poses (right, `[δρ, δθ]`) |
//! | [`LineObservation`] | a 3D line in the camera frame, over document 000 §III's orthonormal line | pose (left), orthonormal line (left) |
//! | [`G2oSe3Edge`], [`G2oLineEdge`], [`G2oPlaneEdge`], [`G2oPointEdge`], [`G2oPriorEdge`] | g2o's own pose, line, plane, point and prior edge errors ([`g2o`]) | body-to-world poses (right, `[δρ, δθ]`), orthonormal line, plane (right), point (Euclidean) |
//!
//! The Snavely, stereo and between factors and g2o's declare their poses
//! [`factor_core::lie::Se3RhoTheta`] perturbed on the right: the chart of
//! apex-solver (crate `factor-apex` serves them to it), so their generated
//! kernels emit the solver's Jacobian columns as they are
//! ([`factor_core::lie::inverse_pose_block`] moves a block between the
//! documents' world-to-camera pose and that chart).
//!
//! Degenerate configurations, and those near a degeneracy where the `f64`
//! inputs no longer determine the outputs to 1e-6 (each factor's accuracy
//! envelope, measured against a double-double evaluation in
//! `tests/accuracy_envelope.rs`), are rejected by each factor's `validate`
//! with [`factor_core::FactorError::Degenerate`] before anything is
//! evaluated; no factor returns a NaN, an infinity, an inaccurate number or
//! a panic for them.

//!
//! With the default feature `kernels`, each factor's `linearize()` goes
//! through its generated kernel in the crate `factor-generated`
//! (`generated/`); without it, through dual numbers (the way to regenerate
//! kernels that no longer compile). [`analytic`] holds the documents'
//! hand-derived Jacobians, corrected where the derivation audit found them
//! wrong, for comparison and benchmarks.

pub mod analytic;
pub mod between;
pub mod free_line;
pub mod g2o;
pub mod line_observation;
pub mod line_reprojection;
pub mod plane;
pub mod plucker_line_reprojection;
pub mod point_reprojection;
pub mod snavely;
pub mod stereo;

pub use between::{BetweenFactor, SqrtInformation6};
pub use free_line::FreeLineFactor;
pub use g2o::{G2oLineEdge, G2oPlaneEdge, G2oPointEdge, G2oPriorEdge, G2oSe3Edge};
pub use line_observation::LineObservation;
pub use line_reprojection::LineReprojection;
pub use plane::PlaneFactor;
pub use plucker_line_reprojection::PluckerLineReprojection;
pub use point_reprojection::PointReprojection;
pub use snavely::{RadialIntrinsics, SnavelyReprojection};
pub use stereo::{StereoIntrinsics, StereoReprojection};

use factor_core::FactorError;
use factor_core::validation::{exceeds, number_text};

/// Relative threshold below which a length counts as zero in the validations
/// (`|x| ≤ DEGENERACY_TOLERANCE · scale`).
pub const DEGENERACY_TOLERANCE: f64 = 1e-9;

/// The largest magnitude (and the inverse of the smallest) of a quantity a
/// residual squares or cubes (the image line `l` of the line factors, the
/// ray of the free line): within
/// `[1e-100, 1e100]` those powers stay normal `f64` numbers. Beyond it they
/// overflow to infinity or lose digits in subnormals, and a kernel returns
/// zeros or worse, so the validations reject it.
pub const MAGNITUDE_LIMIT: f64 = 1e100;

/// Rejects a configuration whose residual, an observation less a
/// prediction (pixels), keeps fewer digits than the accuracy envelope
/// promises. The prediction is computed from a depth (or a line's distance
/// from the optical centre) known to a relative `ε · conditioning`
/// (`conditioning`: the magnitudes it is computed from over itself, below
/// `1/DEGENERACY_TOLERANCE` once accepted), which moves the residual's
/// terms, up to `terms` pixels in size, by about `ε · conditioning ·
/// terms`: observed that close to a prediction that far off-axis, the
/// residual is mostly rounding (a point at depth 1e-9 observed at 1.5e11 px
/// had a residual off by 34 %). Accepted when
/// `max(‖r‖, 1)`, the scale the envelope is stated in, exceeds
/// `DEGENERACY_TOLERANCE · conditioning · terms`; with no cancellation
/// (`‖r‖ ≈ terms`) this is the depth's own bound. `residual` is evaluated
/// only when that rounding reaches 1 (below it, `max(‖r‖, 1) = 1` exceeds it
/// whatever `‖r‖`), so the check costs a product on the solver's path.
/// Public for factors of one's own whose residual is an observation less a
/// prediction.
///
/// # Errors
///
/// [`FactorError::Inaccurate`] naming the factor, the residual and its
/// rounding.
pub fn check_residual_digits(
    factor: &'static str,
    residual: impl FnOnce() -> f64,
    conditioning: f64,
    terms: f64,
) -> Result<(), FactorError> {
    let rounding = DEGENERACY_TOLERANCE * conditioning * terms;
    if rounding < 1.0 {
        return Ok(());
    }
    let residual = residual();
    // A residual that overflows is the evaluation's to report (non-finite).
    if !(residual.is_finite() && rounding.is_finite()) || exceeds(residual.max(1.0), rounding) {
        return Ok(());
    }
    Err(FactorError::Inaccurate {
        factor,
        reason: format!(
            "the residual ({} px) has lost its digits: its terms, up to {} px, follow from a \
             depth or a line distance {} of the magnitudes it is computed from, so they are \
             known only to about {} px",
            number_text(residual),
            number_text(terms),
            number_text(conditioning.recip()),
            number_text(f64::EPSILON * conditioning * terms)
        ),
    })
}

/// The largest `|·|` of the coordinates of `vectors` (the scale a
/// validation compares a depth with), a maximum per vector first: a short
/// dependency chain on every linearization's path.
#[inline]
pub(crate) fn max_abs<const N: usize>(vectors: &[nalgebra::Vector3<f64>; N]) -> f64 {
    // From 0, `x > m` leaves out a NaN as `f64::max` does, in one
    // instruction instead of three.
    let larger = |m: f64, x: f64| if x > m { x } else { m };
    let each = vectors.map(|v| larger(larger(larger(0.0, v.x.abs()), v.y.abs()), v.z.abs()));
    each.into_iter().fold(0.0, larger)
}

/// Rejects `magnitude` (of `what`, a max-abs norm) outside
/// `[1/MAGNITUDE_LIMIT, MAGNITUDE_LIMIT]`; `why` says what makes it so.
pub(crate) fn check_magnitude(
    factor: &'static str,
    what: &str,
    magnitude: f64,
    why: &str,
) -> Result<(), FactorError> {
    if (MAGNITUDE_LIMIT.recip()..=MAGNITUDE_LIMIT).contains(&magnitude) {
        return Ok(());
    }
    Err(degenerate(
        factor,
        format!(
            "{what} has magnitude {}, outside [1e-100, 1e100] where the residual is evaluated \
             accurately ({why})",
            factor_core::validation::magnitude_text(magnitude)
        ),
    ))
}

/// A [`FactorError::Degenerate`].
pub(crate) fn degenerate(factor: &'static str, reason: String) -> FactorError {
    FactorError::Degenerate { factor, reason }
}
