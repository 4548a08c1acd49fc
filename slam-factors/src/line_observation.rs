//! A 3D line observed in the camera frame, over the orthonormal line of
//! document 000 §III.

use nalgebra::Vector4;

use crate::{DEGENERACY_TOLERANCE, degenerate};
use factor_core::geometry::OrthonormalLine;
use factor_core::lie::{Quaternion, Se3, So2, So3};
use factor_core::linalg::{dot, mul};
use factor_core::validation::{exceeds, number_text};
use factor_core::{Factor, FactorError, Scalar};

/// A 3D line measured in the camera frame (from depth, stereo, or a g2o
/// line edge), compared with the world line seen from the pose in the
/// orthonormal representation `(U, W)`:
/// `r = [Log(U_mᵀ U_c), Log(W_mᵀ W_c)]`, the right tangent that carries the
/// measured line `(U_m, W_m)` to the predicted camera-frame line `(U_c,
/// W_c)` (`U_c`, `W_c` those of `H L_w`, document 000 (8)).
///
/// - `pose` `T` maps world to camera; **left** perturbation `T ← Exp(δξ) T`,
///   tangent `[δω, δρ]` (as [`crate::LineReprojection`]).
/// - `line` `(U, W)`: **left** perturbation `U ← Exp(δΘ) U`, `W ← R(δρ) W`.
///
/// The orthonormal representation has a sign: `[n, v]` and `[−n, −v]` are
/// the same line with `U`s a half-turn apart, so a measurement must be
/// oriented as the landmark (its direction within 90° of the landmark's
/// seen from the pose); one given the other way round has a residual near
/// π. A g2o line edge maps onto this factor with
/// [`crate::g2o::line_observation`].
///
/// Computed without converting a matrix to a quaternion: with `a = R u₁`,
/// `b = R u₂` (`u₁`, `u₂` the first columns of the landmark's `U`), the
/// camera-frame moment of the unit Plücker line is `n_c = c a − s R u₃`
/// with `c = w₁ − w₂ t · R u₃`, `s = −w₂ t · a`, so `U_c = R U Ry(φ)`, `φ`
/// the angle of `(c, s)`, and `W_c` is the angle of `(|n_c|, w₂)`.
///
/// Degenerate: a line through the optical centre (`n_c = 0`, to 1e-9 of
/// the magnitudes it is computed from), where `U_c` is undefined; an error
/// rotation of π (`|w| ≤ 1e-9` of its quaternion), where the logarithm has
/// no unique value.
#[derive(Debug, Clone, Factor)]
#[factor(
    residual = line_observation_residual,
    dim = 4,
    validate = validate_line_observation,
    name = "line_observation"
)]
#[cfg_attr(
    feature = "kernels",
    factor(
        kernel = factor_generated::line_observation::line_observation,
        regenerate = "cargo run --release --no-default-features -- generate",
        hosts(apex)
    )
)]
pub struct LineObservation<S: Scalar = f64> {
    /// The measured line in the camera frame.
    pub measured: OrthonormalLine<S>,
    /// World-to-camera pose.
    #[variable(left)]
    pub pose: Se3<S>,
    /// The world line.
    #[variable(left)]
    pub line: OrthonormalLine<S>,
}

/// `(c, s)` and `|n_c|` of the camera-frame moment `n_c = c a − s R u₃`.
fn camera_moment<S: Scalar>(f: &LineObservation<S>) -> (S, S, S) {
    let r = mul(&f.pose.rotation.matrix(), &f.line.u.matrix());
    let (a, u3) = (r.column(0).into_owned(), r.column(2).into_owned());
    let t = f.pose.translation;
    let (w1, w2) = (f.line.w.cos, f.line.w.sin);
    let c = w1 - w2 * dot(&t, &u3);
    let s = -(w2 * dot(&t, &a));
    (c, s, (c * c + s * s).sqrt())
}

/// `U_c` as a quaternion (up to a positive or negative factor: the same
/// rotation) and `W_c` up to a positive factor.
fn camera_line<S: Scalar>(f: &LineObservation<S>) -> (Quaternion<S>, So2<S>) {
    let (c, s, length) = camera_moment(f);
    let z = S::zero();
    // `Ry(φ)`'s quaternion `[0, sin(φ/2), 0, cos(φ/2)]` up to a factor, from
    // whichever half-angle form is far from zero: `[0, s, 0, |n_c| + c]`, or
    // `[0, |n_c| − c, 0, s]` when `c < 0`.
    let from_plus = Quaternion::new(z, s, z, length + c);
    let from_minus = Quaternion::new(z, length - c, z, s);
    let turn = Quaternion::select(c, z, &from_minus, &from_plus);
    let u = f
        .pose
        .rotation
        .quaternion
        .mul(&f.line.u.quaternion)
        .mul(&turn);
    (u, So2::new(length, f.line.w.sin))
}

/// `[Log(U_mᵀ U_c), Log(W_mᵀ W_c)]`.
pub fn line_observation_residual<S: Scalar>(f: &LineObservation<S>) -> Vector4<S> {
    let (u, w) = camera_line(f);
    let e_u = So3::from_quaternion(f.measured.u.quaternion.conjugate().mul(&u)).log();
    let e_w = f.measured.w.inverse().compose(&w).log();
    Vector4::new(e_u.x, e_u.y, e_u.z, e_w)
}

/// Rejects a line through the optical centre and an error rotation of π.
pub fn validate_line_observation(f: &LineObservation<f64>) -> Result<(), FactorError> {
    let (_, _, length) = camera_moment(f);
    let plucker = f.line.to_plucker();
    let terms = plucker.normal.norm() + f.pose.translation.norm() * plucker.direction.norm();
    if !exceeds(length, DEGENERACY_TOLERANCE * terms) {
        return Err(degenerate(
            LineObservation::NAME,
            "the line passes through the optical centre (its camera-frame moment is zero), \
             where its orthonormal representation is undefined"
                .into(),
        ));
    }
    let (u, _) = camera_line(f);
    let e = f.measured.u.quaternion.conjugate().mul(&u);
    let e = e.coords() / e.coords().norm();
    if !exceeds(e.w.abs(), DEGENERACY_TOLERANCE) {
        return Err(degenerate(
            LineObservation::NAME,
            format!(
                "the measured line's U is a half-turn from the predicted one (error quaternion \
                 w = {}; a measurement [−n, −v] of the landmark's [n, v]?): the logarithm has \
                 no unique value",
                number_text(e.w)
            ),
        ));
    }
    Ok(())
}
