//! BAL / Bundler camera reprojection: Snavely's camera model, as the two
//! formats define it and as Ceres' `SnavelyReprojectionError` and GTSAM's
//! `Cal3Bundler` evaluate it.

use nalgebra::{Vector2, Vector3};

use crate::{DEGENERACY_TOLERANCE, check_residual_digits, degenerate, max_abs};
use factor_core::lie::Se3RhoTheta;
use factor_core::manifold::{Manifold, NoLocal, Perturbation};
use factor_core::storage::{Layout, Storage};
use factor_core::validation::{exceeds, number_text};
use factor_core::{Factor, FactorError, Scalar};

/// A BAL/Bundler camera's focal length (pixels) and radial distortion
/// coefficients, `[f, k1, k2]`: a point `p` of the normalised image plane
/// goes to the pixel `f (1 + k1 ‖p‖² + k2 ‖p‖⁴) p`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct RadialIntrinsics<S> {
    /// Focal length `f`, pixels.
    pub focal: S,
    /// Coefficient of `‖p‖²`.
    pub k1: S,
    /// Coefficient of `‖p‖⁴`.
    pub k2: S,
}

impl<S: Scalar> RadialIntrinsics<S> {
    /// From `f`, `k1`, `k2`.
    pub fn new(focal: S, k1: S, k2: S) -> Self {
        RadialIntrinsics { focal, k1, k2 }
    }

    /// The radial factor `r = 1 + k1 ρ² + k2 ρ⁴` at `ρ² = rho2`.
    pub fn radial_factor(&self, rho2: S) -> S {
        S::one() + rho2 * (self.k1 + self.k2 * rho2)
    }
}

/// Stored `[f, k1, k2]`.
impl<S: Scalar> Storage<S> for RadialIntrinsics<S> {
    type With<T: Scalar> = RadialIntrinsics<T>;
    const SCALARS: usize = 3;
    fn layout() -> Layout {
        Layout::array(&["f", "k1", "k2"])
    }
    fn map_scalars<T: Scalar>(&self, f: &mut impl FnMut(S) -> T) -> RadialIntrinsics<T> {
        RadialIntrinsics::new(f(self.focal), f(self.k1), f(self.k2))
    }
    fn read_scalars(next: &mut impl FnMut() -> S) -> Self {
        RadialIntrinsics::new(next(), next(), next())
    }
}

// Served to apex-solver as `Rn(3)`, `[f, k1, k2]`.
factor_core::additive_maps!(RadialIntrinsics<S> => 3; [S: Scalar]);

/// A vector space: `[f, k1, k2] ← [f, k1, k2] + δ` on either side.
impl<S: Scalar> Manifold<S> for RadialIntrinsics<S> {
    const DIM: usize = 3;
    fn retract(&self, delta: &[S], _side: Perturbation) -> Self {
        RadialIntrinsics::new(
            self.focal + delta[0],
            self.k1 + delta[1],
            self.k2 + delta[2],
        )
    }
    fn tangent_description(_side: Perturbation) -> &'static str {
        "additive: [f, k1, k2] ← [f, k1, k2] + δ, columns [δf, δk1, δk2]"
    }
    fn local(&self, other: &Self, _side: Perturbation, delta: &mut [S]) -> Result<(), NoLocal> {
        delta[..3].copy_from_slice(&[
            other.focal - self.focal,
            other.k1 - self.k1,
            other.k2 - self.k2,
        ]);
        Ok(())
    }
}

/// The reprojection error of a BAL or Bundler observation, predicted minus
/// observed, in pixels:
///
/// `P = R X + t`, `p = −P_xy / P_z`, `r = 1 + k1 ‖p‖² + k2 ‖p‖⁴`,
/// residual `f r p − observed`.
///
/// The camera looks down its −z axis (a point in front has `P_z < 0`); pixels
/// have their origin at the image centre, x right, y up. This is Ceres'
/// `SnavelyReprojectionError`; GTSAM's `Cal3Bundler` camera gives the same
/// residual with `v` negated (it flips the camera to look down +z).
///
/// - `pose` `[R | t]` maps world to camera, as the files store it:
///   **right** perturbation, tangent `[δρ, δθ]` ([`Se3RhoTheta`]), the chart
///   apex-solver uses for its SE(3) variables.
/// - `intrinsics` `[f, k1, k2]` and `point` `X`: additive.
///
/// Degenerate: a focal length that is not positive; the point at or behind
/// the camera (`−P_z ≤ 1e-9` times the largest coordinate of `P`, `X` or
/// `t`); and distortion that folds the image, i.e. a radial map
/// `ρ ↦ ρ (1 + k1 ρ² + k2 ρ⁴)` that is not increasing on `[0, ‖p‖]`
/// ([`radial_map_derivative_minimum`]): there two image radii have the same
/// pixel and the projection's Jacobian is singular or flips orientation;
/// and an observation so close to a far off-axis prediction that the
/// residual loses its digits ([`crate::check_residual_digits`]).
#[derive(Debug, Clone, Factor)]
#[factor(
    residual = snavely_reprojection_residual,
    dim = 2,
    validate = validate_snavely_reprojection
)]
#[cfg_attr(
    feature = "kernels",
    factor(
        kernel = factor_generated::snavely_reprojection::snavely_reprojection,
        regenerate = "cargo run --release --no-default-features -- generate",
        hosts(apex)
    )
)]
pub struct SnavelyReprojection<S: Scalar = f64> {
    /// The observed pixel `(u, v)`: origin at the image centre, x right, y up.
    pub observed: Vector2<S>,
    /// World-to-camera pose `[R | t]`, `P = R X + t`.
    #[variable(right)]
    pub pose: Se3RhoTheta<S>,
    /// Focal length and radial distortion `[f, k1, k2]`.
    #[variable]
    pub intrinsics: RadialIntrinsics<S>,
    /// The world point `X`.
    #[variable]
    pub point: Vector3<S>,
}

/// `f r p − observed` with `p = −P_xy / P_z`, `P = R X + t`.
pub fn snavely_reprojection_residual<S: Scalar>(f: &SnavelyReprojection<S>) -> Vector2<S> {
    snavely_pixel(&f.intrinsics, &f.pose.transform_point(&f.point)) - f.observed
}

/// The pixel `f r p`, `p = −P_xy / P_z`, of the camera-frame point `P`.
fn snavely_pixel<S: Scalar>(intrinsics: &RadialIntrinsics<S>, p_c: &Vector3<S>) -> Vector2<S> {
    let inverse_depth = -p_c.z.recip();
    let p = Vector2::new(p_c.x * inverse_depth, p_c.y * inverse_depth);
    let scale = intrinsics.focal * intrinsics.radial_factor(p.x * p.x + p.y * p.y);
    Vector2::new(p.x * scale, p.y * scale)
}

/// The smallest value of `d/dρ [ρ (1 + k1 ρ² + k2 ρ⁴)] = 1 + 3 k1 ρ² + 5 k2 ρ⁴`
/// over `ρ² ∈ [0, radius2]`, with the `ρ²` where it is reached: the radial
/// map is increasing (the image does not fold) up to the radius exactly when
/// it is positive. In `s = ρ²` the derivative is a quadratic; its minimum on
/// `[0, radius2]` is at an end or at the vertex `s = −3 k1 / (10 k2)`. (In
/// squared radii, so that the validation every linearization runs takes no
/// square root.)
pub fn radial_map_derivative_minimum(k1: f64, k2: f64, radius2: f64) -> (f64, f64) {
    let derivative = |s: f64| 1.0 + s * (3.0 * k1 + 5.0 * k2 * s);
    let (at_end, vertex) = (derivative(radius2), -3.0 * k1 / (10.0 * k2));
    let mut minimum = if at_end < 1.0 {
        (at_end, radius2)
    } else {
        (1.0, 0.0)
    };
    if k2 > 0.0 && vertex > 0.0 && vertex < radius2 && derivative(vertex) < minimum.0 {
        minimum = (derivative(vertex), vertex);
    }
    minimum
}

/// Rejects a focal length that is not positive, a point at or behind the
/// camera, distortion that folds the image up to the point's radius, and a
/// residual that has lost its digits to the depth's rounding.
///
/// Every linearization a solver makes runs this, so it first takes a
/// conservative test (`certainly_valid`) that accepts only what the full
/// checks accept, with no square root and one division; the full checks,
/// which name what failed, run only when that test does not pass.
pub fn validate_snavely_reprojection(f: &SnavelyReprojection<f64>) -> Result<(), FactorError> {
    if certainly_valid(f) {
        return Ok(());
    }
    diagnose(f)
}

/// Sufficient for every check of [`validate_snavely_reprojection`] to pass
/// (false on a NaN), with `P = R X + t`, `s` the largest `|·|` of `P`, `X`,
/// `t`, and `ρ² = ‖P_xy‖² / P_z²`:
///
/// - `f > 0` and `−P_z > 1e-9 s`: the same tests;
/// - the radial map increasing up to `ρ`: `1 + 3 k1 ρ'² + 5 k2 ρ'⁴ ≥
///   1 − ρ² (3|k1| + 5|k2| ρ²)` for every `ρ' ≤ ρ`, so the latter positive
///   suffices;
/// - the digits: the check passes when `1e-9 (s / −P_z) f σ (1 + ρ) < 1`,
///   `σ = 1 + ρ² (3|k1| + 5|k2| ρ²)`; as `1 + ρ ≤ 2 + ρ²` (`ρ ≤ max(1, ρ²)`),
///   `1e-9 s f σ (2 + ρ²) < −P_z` suffices.
#[inline]
fn certainly_valid(f: &SnavelyReprojection<f64>) -> bool {
    let RadialIntrinsics { focal, k1, k2 } = f.intrinsics;
    let p_c = f.pose.transform_point(&f.point);
    let t = f.pose.translation();
    let scale = max_abs(&[p_c, f.point, t]);
    let depth = -p_c.z;
    let radius2 = (p_c.x * p_c.x + p_c.y * p_c.y) / (depth * depth);
    let spread = radius2 * (3.0 * k1.abs() + 5.0 * k2.abs() * radius2);
    let rounding = DEGENERACY_TOLERANCE * scale;
    exceeds(focal, 0.0)
        & exceeds(depth, rounding)
        & exceeds(1.0 - spread, 0.0)
        & exceeds(depth, rounding * focal * (1.0 + spread) * (2.0 + radius2))
}

/// The checks of [`validate_snavely_reprojection`] one by one, naming the
/// first that fails.
#[cold]
#[inline(never)]
fn diagnose(f: &SnavelyReprojection<f64>) -> Result<(), FactorError> {
    let name = SnavelyReprojection::NAME;
    let RadialIntrinsics { focal, k1, k2 } = f.intrinsics;
    if !exceeds(focal, 0.0) {
        return Err(degenerate(
            name,
            format!("focal length f = {} is not positive", number_text(focal)),
        ));
    }
    let p_c = f.pose.transform_point(&f.point);
    let t = f.pose.translation();
    let scale = max_abs(&[p_c, f.point, t]);
    // The camera looks down −z: a point in front has −P_z > 0.
    if !exceeds(-p_c.z, DEGENERACY_TOLERANCE * scale) {
        return Err(degenerate(
            name,
            format!(
                "point is at or behind the camera (depth −P_z = {}; the camera looks down −z)",
                number_text(-p_c.z)
            ),
        ));
    }
    let radius2 = (p_c.x * p_c.x + p_c.y * p_c.y) / (p_c.z * p_c.z);
    let (minimum, at) = radial_map_derivative_minimum(k1, k2, radius2);
    if !exceeds(minimum, 0.0) {
        return Err(degenerate(
            name,
            format!(
                "distortion folds the image: d/dρ [ρ (1 + k1 ρ² + k2 ρ⁴)] = {} at ρ = {}, \
                 within the point's radius ‖p‖ = {} (k1 = {}, k2 = {})",
                number_text(minimum),
                number_text(at.sqrt()),
                number_text(radius2.sqrt()),
                number_text(k1),
                number_text(k2)
            ),
        ));
    }
    // The pixel `f r(ρ²) p` moves by `f (1 + 3|k1|ρ² + 5|k2|ρ⁴)(1 + ‖p‖)` per
    // relative error of the depth and of `P_xy`.
    let radius = radius2.sqrt();
    let slope = 1.0 + radius2 * (3.0 * k1.abs() + 5.0 * k2.abs() * radius2);
    let terms = focal * slope * (1.0 + radius);
    let residual = || (snavely_pixel(&f.intrinsics, &p_c) - f.observed).norm();
    check_residual_digits(name, residual, scale / -p_c.z, terms)
}

#[cfg(test)]
mod tests {
    use factor_core::lie::{Se3, So3};
    use proptest::prelude::*;

    use super::*;

    /// A configuration anywhere near the checks' boundaries: points behind,
    /// on and just in front of the image plane, far off-axis, far away
    /// beside a far camera; focal lengths of either sign; distortion that
    /// folds the image.
    fn configuration() -> impl Strategy<Value = SnavelyReprojection> {
        (
            prop::array::uniform3(-3.0..3.0_f64),
            prop::array::uniform3(-1.0..1.0_f64),
            prop::sample::select(vec![1e-9, 1.0, 1e9]),
            (-1e3..2e3_f64, -2.0..2.0_f64, -2.0..2.0_f64),
            (-3.0..3.0_f64, -3.0..3.0_f64, -1e-6..10.0_f64),
            (prop::array::uniform2(-3e3..3e3_f64), any::<bool>()),
        )
            .prop_map(|(w, t, scale, (focal, k1, k2), (x, y, depth), (o, near))| {
                let pose = Se3::new(So3::exp(&Vector3::from(w)), Vector3::from(t) * scale);
                let p_c = Vector3::new(x * depth, y * depth, -depth);
                let intrinsics = RadialIntrinsics::new(focal, k1, k2);
                // Near the prediction, where the residual's digits count.
                let observed = match near {
                    true => snavely_pixel(&intrinsics, &p_c) + Vector2::from(o) * 1e-6,
                    false => Vector2::from(o),
                };
                SnavelyReprojection {
                    observed,
                    pose: Se3RhoTheta::new(pose),
                    intrinsics,
                    point: pose.inverse().transform_point(&p_c),
                }
            })
    }

    proptest! {
        #![proptest_config(ProptestConfig::with_cases(20_000))]

        /// The quick test accepts only what the full checks accept.
        #[test]
        fn the_quick_test_accepts_only_valid_configurations(f in configuration()) {
            if certainly_valid(&f) {
                prop_assert!(diagnose(&f).is_ok(), "{:?}", diagnose(&f));
            }
        }
    }

    proptest! {
        /// Bundle adjustment's configurations (BAL's ranges: focal lengths
        /// 400–1200 px, |k1| < 0.2, |k2| < 0.05, points 1–50 m ahead within
        /// ±30° of the axis) take the quick path.
        #[test]
        fn ordinary_configurations_take_the_quick_test(
            w in prop::array::uniform3(-3.0..3.0_f64),
            t in prop::array::uniform3(-10.0..10.0_f64),
            (focal, k1, k2) in (400.0..1200.0_f64, -0.2..0.2_f64, -0.05..0.05_f64),
            (x, y, depth) in (-0.6..0.6_f64, -0.6..0.6_f64, 1.0..50.0_f64),
        ) {
            let pose = Se3::new(So3::exp(&Vector3::from(w)), Vector3::from(t));
            let p_c = Vector3::new(x * depth, y * depth, -depth);
            let f = SnavelyReprojection {
                observed: Vector2::new(3.0, -2.0),
                pose: Se3RhoTheta::new(pose),
                intrinsics: RadialIntrinsics::new(focal, k1, k2),
                point: pose.inverse().transform_point(&p_c),
            };
            prop_assert!(certainly_valid(&f));
        }
    }
}
