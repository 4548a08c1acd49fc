use factor_core::lie::Se3;
use factor_core::{Factor, Scalar};
use nalgebra::Vector6;

// The residual written over `f64` (a `PosePrior` without `<S>` is a
// `PosePrior<f64>`), as a new user wrote it: one error, at the residual's
// path, saying how to write it.
#[derive(Clone, Factor)]
#[factor(residual = pose_prior, dim = 6)]
struct PosePrior<S: Scalar = f64> {
    measured: Se3<S>,
    #[variable]
    pose: Se3<S>,
}

fn pose_prior(f: &PosePrior) -> Vector6<f64> {
    f.measured.inverse().compose(&f.pose).log()
}

fn main() {}
