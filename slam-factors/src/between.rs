//! Relative pose ("between") factor of pose graphs, whitened by the square
//! root of the edge's information matrix.

use nalgebra::{Matrix6, Vector6};

use crate::degenerate;
use factor_core::lie::{Se3, Se3RhoTheta};
use factor_core::storage::{Layout, Storage};
use factor_core::validation::{exceeds, number_text};
use factor_core::{Factor, FactorError, Scalar};

/// The number of entries of a 6×6 upper-triangular matrix.
const UPPER_ENTRIES: usize = 21;

/// An upper-triangular square root `U` of a 6×6 information matrix,
/// `Ω = Uᵀ U`, stored as its upper triangle row by row (`u00 u01 … u05 u11
/// … u55`): whitening `r ↦ U r` then costs the 21 products the triangle has,
/// not 36.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct SqrtInformation6<S> {
    /// The upper triangle, row by row.
    pub upper: [S; UPPER_ENTRIES],
}

impl<S: Scalar> SqrtInformation6<S> {
    /// `U r`.
    pub fn whiten(&self, r: &Vector6<S>) -> Vector6<S> {
        let mut out = Vector6::zeros();
        let mut k = 0;
        for row in 0..6 {
            let mut sum = S::zero();
            for col in row..6 {
                sum += self.upper[k] * r[col];
                k += 1;
            }
            out[row] = sum;
        }
        out
    }
}

impl SqrtInformation6<f64> {
    /// The Cholesky factor `U` (`Ω = Uᵀ U`, positive diagonal) of a symmetric
    /// positive definite information matrix; `None` when `Ω` is not.
    pub fn from_information(information: &Matrix6<f64>) -> Option<Self> {
        let lower = information.cholesky()?.l();
        let mut upper = [0.0; UPPER_ENTRIES];
        let mut k = 0;
        for row in 0..6 {
            for col in row..6 {
                upper[k] = lower[(col, row)];
                k += 1;
            }
        }
        Some(SqrtInformation6 { upper })
    }

    /// `U` as a full matrix.
    pub fn matrix(&self) -> Matrix6<f64> {
        let mut m = Matrix6::zeros();
        let mut k = 0;
        for row in 0..6 {
            for col in row..6 {
                m[(row, col)] = self.upper[k];
                k += 1;
            }
        }
        m
    }
}

/// Stored as the upper triangle row by row, `[u00, u01, …, u55]`.
impl<S: Scalar> Storage<S> for SqrtInformation6<S> {
    type With<T: Scalar> = SqrtInformation6<T>;
    const SCALARS: usize = UPPER_ENTRIES;
    fn layout() -> Layout {
        Layout::Array(
            (0..6)
                .flat_map(|row| (row..6).map(move |col| format!("u{row}{col}")))
                .collect(),
        )
    }
    fn map_scalars<T: Scalar>(&self, f: &mut impl FnMut(S) -> T) -> SqrtInformation6<T> {
        SqrtInformation6 {
            upper: self.upper.map(&mut *f),
        }
    }
    fn read_scalars(next: &mut impl FnMut() -> S) -> Self {
        SqrtInformation6 {
            upper: std::array::from_fn(|_| next()),
        }
    }
}

/// The relative-pose error of a pose-graph edge, whitened:
/// `U · Log(Z⁻¹ · T_i⁻¹ · T_j)`, with `Z` the measured pose of `j` in the
/// frame of `i`, `Log` the exact SE(3) logarithm in the order `[δω, δρ]`
/// (GTSAM's `BetweenFactor<Pose3>`, `Z.localCoordinates(T_i⁻¹ T_j)`), and
/// `U` the square root of the edge's information matrix in that order, so
/// that `½ ‖r‖²` is the edge's cost `½ eᵀ Ω e`.
///
/// - `pose_i`, `pose_j` map body to world, as pose-graph files store them:
///   **right** perturbation, tangent `[δρ, δθ]` ([`Se3RhoTheta`]),
///   apex-solver's chart (GTSAM's `Pose3` retracts on the right too).
///
/// Degenerate: a relative rotation error of π, where the logarithm has no
/// unique value and no derivative.
#[derive(Debug, Clone, Factor)]
#[factor(residual = between_residual, dim = 6, validate = validate_between, name = "between")]
#[cfg_attr(
    feature = "kernels",
    factor(
        kernel = factor_generated::between::between,
        regenerate = "cargo run --release --no-default-features -- generate",
        hosts(apex)
    )
)]
pub struct BetweenFactor<S: Scalar = f64> {
    /// `U` with `Ω = Uᵀ U`, `Ω` in the order `[δω, δρ]`.
    pub sqrt_information: SqrtInformation6<S>,
    /// The measured pose `Z` of `j` in the frame of `i`.
    pub measured: Se3<S>,
    /// Body-to-world pose `T_i`.
    #[variable(right)]
    pub pose_i: Se3RhoTheta<S>,
    /// Body-to-world pose `T_j`.
    #[variable(right)]
    pub pose_j: Se3RhoTheta<S>,
}

/// `Z⁻¹ · T_i⁻¹ · T_j`.
fn error_pose<S: Scalar>(f: &BetweenFactor<S>) -> Se3<S> {
    f.measured
        .inverse()
        .compose(&f.pose_i.se3().inverse().compose(&f.pose_j.se3()))
}

/// `U · Log(Z⁻¹ · T_i⁻¹ · T_j)`.
pub fn between_residual<S: Scalar>(f: &BetweenFactor<S>) -> Vector6<S> {
    f.sqrt_information.whiten(&error_pose(f).log())
}

/// Rejects a relative rotation error of π.
pub fn validate_between(f: &BetweenFactor<f64>) -> Result<(), FactorError> {
    let q = error_pose(f).rotation.quaternion;
    // The angle is 2 atan2(|v|, |w|); at π the scalar part vanishes.
    if !exceeds(q.w.abs(), crate::DEGENERACY_TOLERANCE * q.coords().norm()) {
        return Err(degenerate(
            BetweenFactor::NAME,
            format!(
                "the relative rotation error is π (error quaternion w = {}): its logarithm \
                 has no unique value",
                number_text(q.w)
            ),
        ));
    }
    Ok(())
}
