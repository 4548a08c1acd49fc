//! Calls the wrenfold-generated kernels on this project's factor samples and
//! checks them against [`linearize_dual`](factor_core::factors::PointReprojection::linearize_dual).
//!
//! The kernels are `include!`d from `bench-peers/out/wrenfold_generated.rs`,
//! written by `bench-peers/wrenfold_factors.py` (run `bash bench-peers/run.sh`).

use factor_core::factors::{PluckerLineReprojection, PointReprojection};
use nalgebra::SMatrix;
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
        check(i, "point_reprojection", &errors, tolerance)?;
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
        check(i, "plucker_line_reprojection", &errors, tolerance)?;
        agreement.update(errors[0].1, errors[1].1, errors[2].1);
    }
    Ok(agreement)
}

fn check(i: usize, factor: &str, errors: &[(&str, f64)], tolerance: f64) -> Result<(), String> {
    for (block, error) in errors {
        // NaN fails too.
        if error.is_nan() || *error > tolerance {
            return Err(format!(
                "{factor} configuration {i}: wrenfold's {block} differs from linearize_dual() \
                 by {error:e} relative (tolerance {tolerance:e})"
            ));
        }
    }
    Ok(())
}
