//! Calls the wrenfold-generated kernels on this project's factor samples and
//! checks them against [`linearize_dual`](slam_factors::PointReprojection::linearize_dual);
//! with the feature `generated`, calls this project's generated kernels
//! (`factor-generated`) the same way and checks them against wrenfold's
//! ([`ours`]), and the fewest-operations formulas written by hand as scalar
//! code ([`bound`]) against those.
//!
//! The kernels are `include!`d from `bench-peers/out/wrenfold_generated.rs`,
//! written by `bench-peers/wrenfold_factors.py` (run `bash bench-peers/run.sh`).

use nalgebra::SMatrix;
use slam_factors::{PluckerLineReprojection, PointReprojection};
use wrenfold_traits::{OutputSpan2D, Span2D};

/// The wrenfold output, as emitted (never committed).
#[allow(clippy::all, clippy::pedantic, missing_docs)]
pub mod wrenfold {
    include!(concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/../out/wrenfold_generated.rs"
    ));
}

/// A column input `N × 1` for the generated kernels.
#[derive(Debug, Clone, Copy)]
pub struct Col<const N: usize>(pub [f64; N]);

impl<const N: usize> Span2D<N, 1> for Col<N> {
    type ValueType = f64;
    #[inline(always)]
    fn get(&self, i: usize, _j: usize) -> f64 {
        self.0[i]
    }
}

/// A row-major `R × C` output of the generated kernels.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Out<const R: usize, const C: usize>(pub [[f64; C]; R]);

impl<const R: usize, const C: usize> Default for Out<R, C> {
    fn default() -> Self {
        Out([[0.0; C]; R])
    }
}

impl<const R: usize, const C: usize> OutputSpan2D<R, C> for Out<R, C> {
    type ValueType = f64;
    #[inline(always)]
    fn set(&mut self, i: usize, j: usize, val: f64) {
        self.0[i][j] = val;
    }
}

impl<const R: usize, const C: usize> Out<R, C> {
    /// As an nalgebra matrix, for the comparison.
    pub fn matrix(&self) -> SMatrix<f64, R, C> {
        SMatrix::from_fn(|i, j| self.0[i][j])
    }
}

/// The arguments of the generated point-reprojection kernel, in its order.
#[derive(Debug, Clone, Copy)]
pub struct PointInputs {
    /// Quaternion `[x, y, z, w]`.
    pub rotation: Col<4>,
    /// `t`.
    pub translation: Col<3>,
    /// World point.
    pub point: Col<3>,
    /// `[fu, fv, cu, cv]`.
    pub intrinsics: Col<4>,
    /// Observed pixel.
    pub observed: Col<2>,
}

/// Residual, 2×6 left pose block `[δω, δρ]`, 2×3 point block.
pub type PointOutputs = (Out<2, 1>, Out<2, 6>, Out<2, 3>);

impl PointInputs {
    /// The plain arrays of one factor.
    pub fn new(f: &PointReprojection) -> Self {
        let q = f.pose.rotation.quaternion;
        let (t, p, k) = (f.pose.translation, f.point, f.intrinsics);
        PointInputs {
            rotation: Col([q.x, q.y, q.z, q.w]),
            translation: Col([t.x, t.y, t.z]),
            point: Col([p.x, p.y, p.z]),
            intrinsics: Col([k.fu, k.fv, k.cu, k.cv]),
            observed: Col([f.observed.x, f.observed.y]),
        }
    }

    /// The wrenfold kernel.
    #[inline]
    pub fn wrenfold(&self) -> PointOutputs {
        let mut out = PointOutputs::default();
        wrenfold::point_reprojection(
            &self.rotation,
            &self.translation,
            &self.point,
            &self.intrinsics,
            &self.observed,
            &mut out.0,
            &mut out.1,
            &mut out.2,
        );
        out
    }
}

/// The arguments of the generated Plücker-line kernel, in its order.
#[derive(Debug, Clone, Copy)]
pub struct PluckerInputs {
    /// Quaternion `[x, y, z, w]`.
    pub rotation: Col<4>,
    /// `t`.
    pub translation: Col<3>,
    /// `[n, v]`.
    pub line: Col<6>,
    /// `[fu, fv, cu, cv]`.
    pub intrinsics: Col<4>,
    /// Observed start pixel.
    pub start: Col<2>,
    /// Observed end pixel.
    pub end: Col<2>,
}

/// Residual, 2×6 left pose block `[δω, δρ]`, 2×6 block w.r.t. `[n, v]`.
pub type PluckerOutputs = (Out<2, 1>, Out<2, 6>, Out<2, 6>);

impl PluckerInputs {
    /// The plain arrays of one factor.
    pub fn new(f: &PluckerLineReprojection) -> Self {
        let q = f.pose.rotation.quaternion;
        let (t, k) = (f.pose.translation, f.intrinsics);
        let (n, v) = (f.line.normal, f.line.direction);
        PluckerInputs {
            rotation: Col([q.x, q.y, q.z, q.w]),
            translation: Col([t.x, t.y, t.z]),
            line: Col([n.x, n.y, n.z, v.x, v.y, v.z]),
            intrinsics: Col([k.fu, k.fv, k.cu, k.cv]),
            start: Col([f.start.x, f.start.y]),
            end: Col([f.end.x, f.end.y]),
        }
    }

    /// The wrenfold kernel.
    #[inline]
    pub fn wrenfold(&self) -> PluckerOutputs {
        let mut out = PluckerOutputs::default();
        wrenfold::plucker_line_reprojection(
            &self.rotation,
            &self.translation,
            &self.line,
            &self.intrinsics,
            &self.start,
            &self.end,
            &mut out.0,
            &mut out.1,
            &mut out.2,
        );
        out
    }
}

/// `max |a − b| / max |b|` over a block (`b` the reference; absolute when
/// `b = 0`).
pub fn relative_error<const R: usize, const C: usize>(
    a: &SMatrix<f64, R, C>,
    b: &SMatrix<f64, R, C>,
) -> f64 {
    let diff = (a - b).amax();
    let scale = b.amax();
    if scale > 0.0 { diff / scale } else { diff }
}

/// The worst relative error of each output over all configurations.
#[derive(Debug, Clone, Copy, Default)]
pub struct Agreement {
    /// Residual.
    pub residual: f64,
    /// Pose block.
    pub pose: f64,
    /// Point or line block.
    pub other: f64,
}

impl Agreement {
    fn update(&mut self, residual: f64, pose: f64, other: f64) {
        self.residual = self.residual.max(residual);
        self.pose = self.pose.max(pose);
        self.other = self.other.max(other);
    }

    /// The largest of the three.
    pub fn worst(&self) -> f64 {
        self.residual.max(self.pose).max(self.other)
    }
}

/// Compares wrenfold's outputs with `linearize_dual()` at every configuration.
///
/// # Errors
///
/// The first configuration and block that differ by more than `tolerance`
/// (relative), or a failed `linearize_dual()`.
pub fn check_point(factors: &[PointReprojection], tolerance: f64) -> Result<Agreement, String> {
    let mut agreement = Agreement::default();
    for (i, f) in factors.iter().enumerate() {
        let dual = f
            .linearize_dual()
            .map_err(|e| format!("point configuration {i}: linearize_dual: {e}"))?;
        let (residual, pose, point) = PointInputs::new(f).wrenfold();
        let errors = [
            (
                "residual",
                relative_error(&residual.matrix(), &dual.residual),
            ),
            ("pose", relative_error(&pose.matrix(), &dual.pose)),
            ("point", relative_error(&point.matrix(), &dual.point)),
        ];
        check(
            i,
            "point_reprojection",
            ("wrenfold's", "linearize_dual()"),
            &errors,
            tolerance,
        )?;
        agreement.update(errors[0].1, errors[1].1, errors[2].1);
    }
    Ok(agreement)
}

/// As [`check_point`], for the Plücker-line factor.
///
/// # Errors
///
/// As [`check_point`].
pub fn check_plucker(
    factors: &[PluckerLineReprojection],
    tolerance: f64,
) -> Result<Agreement, String> {
    let mut agreement = Agreement::default();
    for (i, f) in factors.iter().enumerate() {
        let dual = f
            .linearize_dual()
            .map_err(|e| format!("Plücker configuration {i}: linearize_dual: {e}"))?;
        let (residual, pose, line) = PluckerInputs::new(f).wrenfold();
        let errors = [
            (
                "residual",
                relative_error(&residual.matrix(), &dual.residual),
            ),
            ("pose", relative_error(&pose.matrix(), &dual.pose)),
            ("line", relative_error(&line.matrix(), &dual.line)),
        ];
        check(
            i,
            "plucker_line_reprojection",
            ("wrenfold's", "linearize_dual()"),
            &errors,
            tolerance,
        )?;
        agreement.update(errors[0].1, errors[1].1, errors[2].1);
    }
    Ok(agreement)
}

/// `Err` naming the first block of `errors` above `tolerance` (or NaN);
/// `(subject, reference)` say whose block differs from what.
fn check(
    i: usize,
    factor: &str,
    (subject, reference): (&str, &str),
    errors: &[(&str, f64)],
    tolerance: f64,
) -> Result<(), String> {
    for (block, error) in errors {
        // NaN fails too.
        if error.is_nan() || *error > tolerance {
            return Err(format!(
                "{factor} configuration {i}: {subject} {block} differs from {reference} \
                 by {error:e} relative (tolerance {tolerance:e})"
            ));
        }
    }
    Ok(())
}

/// This project's generated kernels (`factor-generated`, feature `generated`)
/// on plain arrays prepared once per configuration, as wrenfold's are, and
/// their check against wrenfold's outputs.
#[cfg(feature = "generated")]
pub mod bound;

#[cfg(feature = "generated")]
pub mod ours {
    use factor_generated::plucker_line_reprojection::plucker_line_reprojection;
    use factor_generated::point_reprojection::point_reprojection;
    use nalgebra::SMatrix;
    use slam_factors::{PluckerLineReprojection, PointReprojection};

    use super::{Agreement, PluckerInputs, PointInputs, check, relative_error};

    /// The arguments of the generated point-reprojection kernel, in its order
    /// (the factor's fields in declaration order, each as its stored scalars).
    #[derive(Debug, Clone, Copy)]
    pub struct PointArrays {
        /// `[fu, fv, cu, cv]`.
        pub intrinsics: [f64; 4],
        /// Observed pixel.
        pub observed: [f64; 2],
        /// `[qx, qy, qz, qw, tx, ty, tz]`.
        pub pose: [f64; 7],
        /// World point.
        pub point: [f64; 3],
    }

    /// Residual, 2×6 left pose block `[δω, δρ]`, 2×3 point block, row-major.
    pub type PointArrayOutputs = ([f64; 2], [f64; 12], [f64; 6]);

    impl PointArrays {
        /// The plain arrays of one factor.
        pub fn new(f: &PointReprojection) -> Self {
            let q = f.pose.rotation.quaternion;
            let (t, p, k) = (f.pose.translation, f.point, f.intrinsics);
            PointArrays {
                intrinsics: [k.fu, k.fv, k.cu, k.cv],
                observed: [f.observed.x, f.observed.y],
                pose: [q.x, q.y, q.z, q.w, t.x, t.y, t.z],
                point: [p.x, p.y, p.z],
            }
        }

        /// The generated kernel, every block requested.
        #[inline]
        pub fn generated(&self) -> PointArrayOutputs {
            let mut out = PointArrayOutputs::default();
            point_reprojection::<f64>(
                &self.intrinsics,
                &self.observed,
                &self.pose,
                &self.point,
                &mut out.0,
                Some(&mut out.1),
                Some(&mut out.2),
            );
            out
        }
    }

    /// The arguments of the generated Plücker-line kernel, in its order.
    #[derive(Debug, Clone, Copy)]
    pub struct PluckerArrays {
        /// `[fu, fv, cu, cv]`.
        pub intrinsics: [f64; 4],
        /// Observed start pixel.
        pub start: [f64; 2],
        /// Observed end pixel.
        pub end: [f64; 2],
        /// `[qx, qy, qz, qw, tx, ty, tz]`.
        pub pose: [f64; 7],
        /// `[n, v]`.
        pub line: [f64; 6],
    }

    /// Residual, 2×6 left pose block `[δω, δρ]`, 2×6 block w.r.t. `[n, v]`,
    /// row-major.
    pub type PluckerArrayOutputs = ([f64; 2], [f64; 12], [f64; 12]);

    impl PluckerArrays {
        /// The plain arrays of one factor.
        pub fn new(f: &PluckerLineReprojection) -> Self {
            let q = f.pose.rotation.quaternion;
            let (t, k) = (f.pose.translation, f.intrinsics);
            let (n, v) = (f.line.normal, f.line.direction);
            PluckerArrays {
                intrinsics: [k.fu, k.fv, k.cu, k.cv],
                start: [f.start.x, f.start.y],
                end: [f.end.x, f.end.y],
                pose: [q.x, q.y, q.z, q.w, t.x, t.y, t.z],
                line: [n.x, n.y, n.z, v.x, v.y, v.z],
            }
        }

        /// The generated kernel, every block requested.
        #[inline]
        pub fn generated(&self) -> PluckerArrayOutputs {
            let mut out = PluckerArrayOutputs::default();
            plucker_line_reprojection::<f64>(
                &self.intrinsics,
                &self.start,
                &self.end,
                &self.pose,
                &self.line,
                &mut out.0,
                Some(&mut out.1),
                Some(&mut out.2),
            );
            out
        }
    }

    /// A row-major `R × C` output as an nalgebra matrix.
    pub(crate) fn matrix<const R: usize, const C: usize>(entries: &[f64]) -> SMatrix<f64, R, C> {
        SMatrix::from_row_slice(entries)
    }

    /// Compares the generated point kernel with wrenfold's at every
    /// configuration (wrenfold the reference), each on its own inputs.
    ///
    /// # Errors
    ///
    /// The first configuration and block that differ by more than `tolerance`
    /// (relative), NaN included.
    pub fn check_point(factors: &[PointReprojection], tolerance: f64) -> Result<Agreement, String> {
        let mut agreement = Agreement::default();
        for (i, f) in factors.iter().enumerate() {
            let (residual, pose, point) = PointArrays::new(f).generated();
            let (w_residual, w_pose, w_point) = PointInputs::new(f).wrenfold();
            let errors = [
                (
                    "residual",
                    relative_error(&matrix::<2, 1>(&residual), &w_residual.matrix()),
                ),
                (
                    "pose",
                    relative_error(&matrix::<2, 6>(&pose), &w_pose.matrix()),
                ),
                (
                    "point",
                    relative_error(&matrix::<2, 3>(&point), &w_point.matrix()),
                ),
            ];
            check(
                i,
                "point_reprojection",
                ("the generated kernel's", "wrenfold's"),
                &errors,
                tolerance,
            )?;
            agreement.update(errors[0].1, errors[1].1, errors[2].1);
        }
        Ok(agreement)
    }

    /// As [`check_point`], for the Plücker-line kernel.
    ///
    /// # Errors
    ///
    /// As [`check_point`].
    pub fn check_plucker(
        factors: &[PluckerLineReprojection],
        tolerance: f64,
    ) -> Result<Agreement, String> {
        let mut agreement = Agreement::default();
        for (i, f) in factors.iter().enumerate() {
            let (residual, pose, line) = PluckerArrays::new(f).generated();
            let (w_residual, w_pose, w_line) = PluckerInputs::new(f).wrenfold();
            let errors = [
                (
                    "residual",
                    relative_error(&matrix::<2, 1>(&residual), &w_residual.matrix()),
                ),
                (
                    "pose",
                    relative_error(&matrix::<2, 6>(&pose), &w_pose.matrix()),
                ),
                (
                    "line",
                    relative_error(&matrix::<2, 6>(&line), &w_line.matrix()),
                ),
            ];
            check(
                i,
                "plucker_line_reprojection",
                ("the generated kernel's", "wrenfold's"),
                &errors,
                tolerance,
            )?;
            agreement.update(errors[0].1, errors[1].1, errors[2].1);
        }
        Ok(agreement)
    }
}
