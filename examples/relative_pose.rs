//! A factor the documents do not have, written as a user would: the relative
//! pose ("between") factor of pose-graph SLAM,
//! `r = Log(T̃_ij⁻¹ · T_i⁻¹ · T_j)` over two world-to-body poses.
//!
//! Everything below the imports is what a user writes: a struct holding the
//! measurement and the two variables, one generic residual, and a check. The
//! derive gives `linearize()` with a 6×6 block per pose on each pose's left
//! tangent `[δω, δρ]`, and the `Factor` impl the test helper uses.
//!
//! `cargo run --example relative_pose` prints a linearization and checks it
//! against central differences; `cargo test` runs the same check.

use factor_core::lie::{Se3, So3};
use factor_core::{Factor, Scalar};
use factor_testing::{DEFAULT_TOLERANCE, assert_correct_jacobians};
use nalgebra::{Vector3, Vector6};

/// `Log(T̃_ij⁻¹ T_i⁻¹ T_j)`: zero when the poses agree with the measurement.
#[derive(Debug, Clone, Factor)]
#[factor(residual = relative_pose_residual, dim = 6)]
pub struct RelativePose<S: Scalar = f64> {
    /// The measured relative pose `T̃_ij`.
    pub measured: Se3<S>,
    /// `T_i`, perturbed on the left: `T_i ← Exp(δξ) T_i`.
    #[variable(left)]
    pub pose_i: Se3<S>,
    /// `T_j`, perturbed on the left.
    #[variable(left)]
    pub pose_j: Se3<S>,
}

/// The residual, generic over the scalar: plain `f64`, dual numbers and
/// symbols all run this one definition.
pub fn relative_pose_residual<S: Scalar>(f: &RelativePose<S>) -> Vector6<S> {
    let predicted = f.pose_i.inverse().compose(&f.pose_j);
    f.measured.inverse().compose(&predicted).log()
}

fn example_factor() -> RelativePose {
    let pose = |w: [f64; 3], t: [f64; 3]| Se3::new(So3::exp(&Vector3::from(w)), Vector3::from(t));
    RelativePose {
        measured: pose([0.1, -0.2, 0.3], [1.0, 0.0, 0.2]),
        pose_i: pose([0.5, 0.1, -0.4], [0.3, -1.0, 2.0]),
        pose_j: pose([0.6, -0.05, -0.1], [1.2, -0.9, 2.3]),
    }
}

fn main() -> Result<(), factor_core::FactorError> {
    let factor = example_factor();
    let linearization = factor.linearize()?;
    println!("residual: {}", linearization.residual.transpose());
    println!("∂r/∂pose_i:{}", linearization.pose_i);
    println!("∂r/∂pose_j:{}", linearization.pose_j);
    for variable in RelativePose::variables() {
        println!("{}: {}", variable.name, variable.tangent);
    }
    assert_correct_jacobians(&factor, DEFAULT_TOLERANCE);
    println!("Jacobians agree with central differences.");
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn relative_pose_jacobians_are_correct() {
        assert_correct_jacobians(&example_factor(), DEFAULT_TOLERANCE);
    }

    /// At the measurement the residual vanishes, through the small-angle
    /// branches of `Log`, and the Jacobians are still exact.
    #[test]
    fn relative_pose_at_zero_error() {
        let mut factor = example_factor();
        factor.measured = factor.pose_i.inverse().compose(&factor.pose_j);
        let linearization = factor.linearize().expect("valid");
        assert!(linearization.residual.norm() < 1e-12);
        assert_correct_jacobians(&factor, DEFAULT_TOLERANCE);
    }
}
