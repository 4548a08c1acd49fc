//! Violations of the rules a retraction must follow (the documentation of
//! `factor_core::Manifold`), and where they are caught.
//!
//! Dual numbers and the generated kernels both differentiate the
//! first-order retraction only, so they agree with each other whatever it
//! is; `assert_correct_jacobians` compares them with central differences
//! through the exact retraction, and so catches the two disagreeing. A
//! derivative taken through `θ = √(δ·δ)` at `δ = 0` is `0/0`: the dual
//! linearisation reports it as a non-finite Jacobian.

use factor_core::lie::So3;
use factor_core::{
    Factor, FactorError, Layout, Manifold, Perturbation, Scalar, Storage, StorageError,
};
use factor_testing::{DEFAULT_TOLERANCE, assert_correct_jacobians, check_jacobians};
use nalgebra::{Vector2, Vector3};
use user_factors::unit_vector::UnitVector3;

/// A direction on S² whose retractions are those of [`UnitVector3`] except
/// for the one the constant `SLIP` replaces by a slip.
#[derive(Debug, Clone, Copy, PartialEq)]
struct Slipped<S, const SLIP: u8>(UnitVector3<S>);

/// The exact retraction rotates `v` about `B δ` (a common slip: the
/// geodesic towards `B δ` rotates about `v × B δ`); the first-order one is
/// `v + B δ`. The two move `v` in perpendicular directions.
const ROTATES_ABOUT_THE_STEP: u8 = 0;

/// The first-order retraction `v + (sin θ/θ) B δ` with its small-angle
/// branch decided on `θ = √(δ·δ)` and its series written in `θ`.
const BRANCHES_ON_THETA: u8 = 1;

impl<S: Scalar, const SLIP: u8> Storage<S> for Slipped<S, SLIP> {
    type With<T: Scalar> = Slipped<T, SLIP>;
    const SCALARS: usize = 3;
    fn layout() -> Layout {
        UnitVector3::<S>::layout()
    }
    fn map_scalars<T: Scalar>(&self, f: &mut impl FnMut(S) -> T) -> Slipped<T, SLIP> {
        Slipped(self.0.map_scalars(f))
    }
    fn read_scalars(next: &mut impl FnMut() -> S) -> Self {
        Slipped(UnitVector3::read_scalars(next))
    }
    fn from_input(input: &[f64]) -> Result<Vec<f64>, StorageError> {
        UnitVector3::<f64>::from_input(input)
    }
}

impl<S: Scalar, const SLIP: u8> Manifold<S> for Slipped<S, SLIP> {
    const DIM: usize = 2;
    fn retract(&self, delta: &[S], side: Perturbation) -> Self {
        if SLIP == ROTATES_ABOUT_THE_STEP {
            let step = self.0.basis() * Vector2::new(delta[0], delta[1]);
            let rotated = So3::exp(&step).rotate(&self.0.vector());
            return Slipped(UnitVector3::from_unit(rotated));
        }
        Slipped(self.0.retract(delta, side))
    }
    fn retract_first_order(&self, delta: &[S], side: Perturbation) -> Self {
        if SLIP == BRANCHES_ON_THETA {
            let theta = (delta[0] * delta[0] + delta[1] * delta[1]).sqrt();
            let series = S::one() - theta * theta / S::from_f64(6.0);
            let sinc = S::select_lt(theta, S::from_f64(1e-3), series, theta.sin() / theta);
            let step = self.0.basis() * Vector2::new(delta[0], delta[1]);
            return Slipped(UnitVector3::from_unit(
                self.0.vector() + step.map(|x| sinc * x),
            ));
        }
        Slipped(self.0.retract_first_order(delta, side))
    }
    fn tangent_description(side: Perturbation) -> &'static str {
        UnitVector3::<S>::tangent_description(side)
    }
}

/// `d − t`: a direction observed directly.
#[derive(Debug, Clone, Factor)]
#[factor(residual = rotates_residual, dim = 3)]
struct RotatesAboutTheStep<S: Scalar = f64> {
    target: Vector3<S>,
    #[variable]
    direction: Slipped<S, ROTATES_ABOUT_THE_STEP>,
}

fn rotates_residual<S: Scalar>(f: &RotatesAboutTheStep<S>) -> Vector3<S> {
    f.direction.0.vector() - f.target
}

/// The same residual over the slip of [`BRANCHES_ON_THETA`].
#[derive(Debug, Clone, Factor)]
#[factor(residual = branches_residual, dim = 3)]
struct BranchesOnTheta<S: Scalar = f64> {
    target: Vector3<S>,
    #[variable]
    direction: Slipped<S, BRANCHES_ON_THETA>,
}

fn branches_residual<S: Scalar>(f: &BranchesOnTheta<S>) -> Vector3<S> {
    f.direction.0.vector() - f.target
}

/// The same residual over the correct [`UnitVector3`].
#[derive(Debug, Clone, Factor)]
#[factor(residual = correct_residual, dim = 3)]
struct Correct<S: Scalar = f64> {
    target: Vector3<S>,
    #[variable]
    direction: UnitVector3<S>,
}

fn correct_residual<S: Scalar>(f: &Correct<S>) -> Vector3<S> {
    f.direction.vector() - f.target
}

fn direction() -> UnitVector3<f64> {
    UnitVector3::from_direction(&Vector3::new(0.3, -0.4, 0.5))
}

const TARGET: Vector3<f64> = Vector3::new(0.1, 0.2, 0.9);

#[test]
fn the_correct_retraction_passes() {
    let f = Correct {
        target: TARGET,
        direction: direction(),
    };
    assert_correct_jacobians(&f, DEFAULT_TOLERANCE);
}

/// Here `∂r/∂δ = B` by dual numbers but `[v]× B`, `B` turned by a right
/// angle in the tangent plane, by central differences: a relative error of
/// `√2`.
#[test]
fn an_exact_retraction_disagreeing_with_the_first_order_one_is_caught() {
    let f = RotatesAboutTheStep {
        target: TARGET,
        direction: Slipped(direction()),
    };
    let check = check_jacobians(&f).expect("finite");
    let (name, error) = check.block_errors[0];
    assert_eq!(name, "direction");
    assert!((error - 2f64.sqrt()).abs() < 1e-9, "{error}");
}

#[test]
#[should_panic(expected = "rotates_about_the_step: Jacobian w.r.t. `direction` is off by")]
fn assert_correct_jacobians_names_the_variable() {
    let f = RotatesAboutTheStep {
        target: TARGET,
        direction: Slipped(direction()),
    };
    assert_correct_jacobians(&f, DEFAULT_TOLERANCE);
}

/// `θ = √(δ·δ)` has no derivative at `δ = 0`: the dual Jacobian is NaN, and
/// the linearisation says so instead of returning it. The same map written
/// in `θ²` ([`UnitVector3`]'s, through `factor_core::lie::so3`) is fine.
#[test]
fn a_branch_on_theta_gives_a_non_finite_jacobian() {
    let f = BranchesOnTheta {
        target: TARGET,
        direction: Slipped(direction()),
    };
    assert_eq!(
        f.linearize_dual_dyn().unwrap_err(),
        FactorError::NonFinite {
            factor: "branches_on_theta",
            what: "Jacobian w.r.t. `direction`".into(),
        }
    );
    assert!(
        f.residual().is_ok(),
        "the values are fine; the derivative is not"
    );
}
