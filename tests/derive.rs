//! `#[derive(Factor)]` (crate `factor-macros`) checked with the test helpers
//! of `factor-testing`, on small factors over vector spaces (and one pose):
//! the single-pass and per-block dual linearizations agree with each other,
//! with central differences, and with known Jacobians exactly.

use factor_core::host::{
    Apex, ApexManifold, HostFactor, HostLayout, linearize_host, linearize_host_dual,
};
use factor_core::lie::Se3;
use factor_core::{Factor, FactorError, Manifold, Perturbation, Scalar, Storage};
use factor_testing::seeding::{assert_seeding_matches_retraction, dual_through_retraction};
use factor_testing::{DEFAULT_TOLERANCE, assert_correct_jacobians};
use nalgebra::{Matrix2x3, Matrix3, Vector2, Vector3, Vector6};

/// `r = x − y + c`: linear, with Jacobians `I` and `−I`.
#[derive(Clone, Debug, Factor)]
#[factor(residual = difference_residual, dim = 3)]
pub struct Difference<S: Scalar = f64> {
    pub offset: Vector3<S>,
    #[variable]
    pub x: Vector3<S>,
    #[variable(right)]
    pub y: Vector3<S>,
}

pub fn difference_residual<S: Scalar>(f: &Difference<S>) -> Vector3<S> {
    f.x - f.y + f.offset
}

/// `r = [x·y, |x|²] · weight`, refused when `x` is zero.
#[derive(Clone, Debug, Factor)]
#[factor(residual = products_residual, dim = 2, validate = products_validate, name = "dot_and_norm")]
pub struct Products<S: Scalar = f64> {
    #[variable(left)]
    pub x: Vector3<S>,
    pub weight: S,
    #[variable]
    pub y: Vector3<S>,
}

pub fn products_residual<S: Scalar>(f: &Products<S>) -> Vector2<S> {
    Vector2::new(f.x.dot(&f.y), f.x.dot(&f.x)) * f.weight
}

pub fn products_validate(f: &Products<f64>) -> Result<(), FactorError> {
    if f.x.norm() == 0.0 {
        return Err(FactorError::Degenerate {
            factor: <Products as Factor>::NAME,
            reason: "x is zero".into(),
        });
    }
    Ok(())
}

/// `r = T · p − observed`, the pose perturbed on the right.
#[derive(Clone, Debug, Factor)]
#[factor(residual = transfer_residual, dim = 3)]
pub struct Transfer<S: Scalar = f64> {
    pub observed: Vector3<S>,
    #[variable(right)]
    pub pose: Se3<S>,
    #[variable]
    pub point: Vector3<S>,
}

pub fn transfer_residual<S: Scalar>(f: &Transfer<S>) -> Vector3<S> {
    f.pose.transform_point(&f.point) - f.observed
}

/// `r = s · x` with a scalar variable: its Jacobian is the column `x`.
#[derive(Clone, Debug, Factor)]
#[factor(residual = scaled_residual, dim = 2)]
pub struct Scaled<S: Scalar = f64> {
    pub x: Vector2<S>,
    #[variable]
    pub s: S,
}

pub fn scaled_residual<S: Scalar>(f: &Scaled<S>) -> Vector2<S> {
    f.x * f.s
}

fn difference() -> Difference {
    Difference {
        offset: Vector3::new(0.5, -1.0, 2.0),
        x: Vector3::new(1.0, 2.0, 3.0),
        y: Vector3::new(-4.0, 0.25, 7.0),
    }
}

fn products() -> Products {
    Products {
        x: Vector3::new(0.3, -1.2, 2.0),
        weight: 1.5,
        y: Vector3::new(4.0, 0.5, -0.7),
    }
}

fn transfer() -> Transfer {
    Transfer {
        observed: Vector3::new(0.1, 0.2, 3.0),
        pose: Se3::exp(&Vector6::new(0.3, -0.2, 0.5, 1.0, -2.0, 0.5)),
        point: Vector3::new(0.4, -0.3, 2.5),
    }
}

#[test]
fn the_jacobians_of_a_linear_residual_are_its_matrices_exactly() {
    let f = difference();
    let expected = DifferenceLinearization {
        residual: Vector3::new(5.5, 0.75, -2.0),
        x: Matrix3::identity(),
        y: -Matrix3::identity(),
    };
    assert_eq!(f.linearize_dual().unwrap(), expected);
    assert_eq!(dual_through_retraction(&f), expected.to_dyn());
    assert_eq!(f.linearize().unwrap(), expected);
    assert_eq!(f.residual().unwrap(), expected.residual);
}

#[test]
fn a_scalar_variable_has_a_one_column_block() {
    let f = Scaled {
        x: Vector2::new(3.0, -4.0),
        s: 0.5,
    };
    let lin = f.linearize_dual().unwrap();
    assert_eq!(lin.s, nalgebra::Matrix2x1::new(3.0, -4.0));
    assert_eq!(lin.to_dyn(), dual_through_retraction(&f));
    assert_eq!(Scaled::variables()[0].tangent_dim, 1);
    // Named for what it is (problem files write `"type": "f64"`), not `S`.
    assert_eq!(Scaled::variables()[0].type_name, "f64");
}

#[test]
fn a_nonlinear_residual_has_its_analytic_jacobians() {
    let f = products();
    let lin = f.linearize_dual().unwrap();
    let w = f.weight;
    let expected_x = Matrix2x3::from_rows(&[f.y.transpose() * w, f.x.transpose() * (2.0 * w)]);
    let expected_y = Matrix2x3::from_rows(&[f.x.transpose() * w, Vector3::zeros().transpose()]);
    assert!((lin.x - expected_x).norm() < 1e-14);
    assert!((lin.y - expected_y).norm() < 1e-14);
    assert_eq!(lin.to_dyn(), dual_through_retraction(&f));
}

#[test]
fn dual_jacobians_agree_with_central_differences() {
    assert_correct_jacobians(&difference(), DEFAULT_TOLERANCE);
    assert_correct_jacobians(&products(), DEFAULT_TOLERANCE);
    assert_correct_jacobians(&transfer(), DEFAULT_TOLERANCE);
    assert_seeding_matches_retraction(&transfer(), 1e-14);
}

#[test]
fn the_factor_trait_describes_the_variables() {
    assert_eq!(<Difference as Factor>::NAME, "difference");
    assert_eq!(<Products as Factor>::NAME, "dot_and_norm");
    assert_eq!(<Transfer as Factor>::RESIDUAL_DIM, 3);
    assert_eq!(Transfer::TANGENT_DIM, 9);
    let variables = Transfer::variables();
    assert_eq!(variables.len(), 2);
    assert_eq!(
        (
            variables[0].name,
            variables[0].type_name,
            variables[0].tangent_dim
        ),
        ("pose", "Se3<S>", 6)
    );
    assert_eq!(variables[0].perturbation, Perturbation::Right);
    assert_eq!(
        variables[0].tangent,
        <Se3<f64> as Manifold<f64>>::tangent_description(Perturbation::Right)
    );
    assert_eq!(
        (variables[1].name, variables[1].type_name),
        ("point", "Vector3<S>")
    );
    assert_eq!(variables[1].perturbation, Perturbation::Left);
}

#[test]
fn storage_visits_every_field_in_declaration_order() {
    assert_eq!(<Products as Storage<f64>>::SCALARS, 7);
    let mut seen = Vec::new();
    let lifted: Products<f32> = products().map_scalars(&mut |x| {
        seen.push(x);
        x as f32
    });
    assert_eq!(seen, [0.3, -1.2, 2.0, 1.5, 4.0, 0.5, -0.7]);
    assert_eq!(lifted.weight, 1.5_f32);
}

#[test]
fn storage_round_trips_and_names_every_field() {
    let f = products();
    let stored = f.to_scalars();
    assert_eq!(stored, [0.3, -1.2, 2.0, 1.5, 4.0, 0.5, -0.7]);
    let back = Products::<f64>::from_scalars(&stored);
    assert_eq!(back.to_scalars(), stored);
    assert_eq!(
        <Products as Storage<f64>>::layout().to_string(),
        "{x: [x, y, z], weight, y: [x, y, z]}"
    );
    // A factor written by a user is read field by field, each field's errors
    // named by its path.
    let transfer_input: Vec<f64> = transfer().to_scalars();
    assert_eq!(
        Transfer::<f64>::from_input(&transfer_input).unwrap(),
        transfer_input
    );
    let mut bad = transfer_input.clone();
    bad[3] = 3.0; // the pose's quaternion w
    let error = Transfer::<f64>::from_input(&bad).unwrap_err();
    assert_eq!(error.path, "pose.rotation");
}

#[test]
fn fields_carry_their_documentation_and_the_type_its_path() {
    let fields = <Weighted as Factor>::fields();
    assert_eq!(fields.len(), 3);
    assert_eq!(
        (fields[0].name, fields[0].scalars, fields[0].variable),
        ("weight", 1, None)
    );
    assert_eq!(fields[2].variable, Some(1));
    assert_eq!(
        <Transfer as Factor>::DESCRIPTION,
        "`r = T · p − observed`, the pose perturbed on the right."
    );
    assert!(
        <Transfer as Factor>::TYPE_PATH.ends_with("::Transfer"),
        "{}",
        <Transfer as Factor>::TYPE_PATH
    );
}

#[test]
fn the_residual_over_stored_scalars_is_the_residual() {
    let f = transfer();
    let delta = [0.0; 9];
    let over = Transfer::perturbed_residual_over(&f.to_scalars(), &delta);
    assert_eq!(over.as_slice(), f.residual().unwrap().as_slice());
}

/// `linearize_into` writes the residual and the requested blocks only: a
/// variable held fixed (`None`) keeps its storage untouched, through a
/// kernel and through dual numbers alike.
#[test]
fn fixed_variables_skip_their_blocks() {
    let w = Weighted {
        weight: 2.0,
        x: Vector2::new(1.0, 5.0),
        y: Vector2::new(0.5, -1.0),
    };
    let full = w.linearize().unwrap();
    let mut residual = [0.0; 2];
    let mut d_y = [7.0; 4];
    w.linearize_into(&mut residual, &mut [None, Some(&mut d_y[..])])
        .unwrap();
    assert_eq!(residual.as_slice(), full.residual.as_slice());
    assert_eq!(d_y.as_slice(), full.y.transpose().as_slice());
    let f = transfer();
    let full = f.linearize().unwrap();
    let mut residual = [0.0; 3];
    let mut d_point = [0.0; 9];
    f.linearize_into(&mut residual, &mut [None, Some(&mut d_point[..])])
        .unwrap();
    assert_eq!(residual.as_slice(), full.residual.as_slice());
    assert_eq!(d_point.as_slice(), full.point.transpose().as_slice());
}

/// Through a kernel, every block requested or some: finite outputs whose
/// sum overflows are still finite (the quick test of their sum is
/// confirmed value by value), and a non-finite one is an error naming it.
#[test]
fn kernel_outputs_are_tested_for_finiteness_exactly() {
    let huge = Weighted {
        weight: 1e308,
        x: Vector2::new(1.0, 1.0),
        y: Vector2::zeros(),
    };
    let mut residual = [0.0; 2];
    let (mut d_x, mut d_y) = ([0.0; 4], [0.0; 4]);
    huge.linearize_into(&mut residual, &mut [Some(&mut d_x[..]), Some(&mut d_y[..])])
        .unwrap();
    // r = a (x − y), ∂r/∂x = a I, ∂r/∂y = −a I.
    assert_eq!(residual, [1e308, 1e308]);
    assert_eq!(d_x, [1e308, 0.0, 0.0, 1e308]);
    assert_eq!(d_y, [-1e308, 0.0, 0.0, -1e308]);
    let infinite = Weighted {
        weight: f64::INFINITY,
        ..huge
    };
    let expected = Err(FactorError::NonFinite {
        factor: "weighted",
        what: "residual".into(),
    });
    let every: &mut [Option<&mut [f64]>] = &mut [Some(&mut d_x[..]), Some(&mut d_y[..])];
    assert_eq!(infinite.linearize_into(&mut residual, every), expected);
    let some: &mut [Option<&mut [f64]>] = &mut [None, Some(&mut d_y[..])];
    assert_eq!(infinite.linearize_into(&mut residual, some), expected);
}

#[test]
fn with_retracted_moves_one_variable_exactly() {
    let f = difference();
    let moved = f.with_retracted(1, &[1.0, 0.0, -1.0]);
    assert_eq!(moved.x, f.x);
    assert_eq!(moved.y, Vector3::new(-3.0, 0.25, 6.0));
    let g = transfer();
    let delta = [0.1, 0.0, 0.0, 0.0, 0.2, 0.0];
    assert_eq!(
        g.with_retracted(0, &delta).pose,
        g.pose.retract(&delta, Perturbation::Right)
    );
}

#[test]
fn perturbed_residual_retracts_each_variable_by_its_slice() {
    let f = difference();
    let delta = [1.0, 0.0, 0.0, 0.0, 2.0, 0.0];
    assert_eq!(f.perturbed_residual(&delta), Vector3::new(6.5, -1.25, -2.0));
}

#[test]
fn validation_and_non_finite_values_are_errors() {
    let mut f = products();
    f.x = Vector3::zeros();
    let expected: Result<(), _> = Err(FactorError::Degenerate {
        factor: "dot_and_norm",
        reason: "x is zero".into(),
    });
    assert_eq!(f.residual().map(|_| ()), expected);
    assert_eq!(f.linearize_dual().map(|_| ()), expected);
    assert_eq!(f.linearize_dual_dyn().map(|_| ()), expected);

    let mut g = products();
    g.weight = f64::NAN;
    let non_finite: Result<(), _> = Err(FactorError::NonFinite {
        factor: "dot_and_norm",
        what: "residual".into(),
    });
    assert_eq!(g.residual().map(|_| ()), non_finite);
    assert_eq!(g.linearize_dual().map(|_| ()), non_finite);
}

#[test]
fn to_dyn_keeps_the_blocks_in_declaration_order() {
    let f = transfer();
    let lin = f.linearize_dual().unwrap();
    let dynamic = f.linearize_dual_dyn().unwrap();
    assert_eq!(dynamic, lin.to_dyn());
    assert_eq!(dynamic.jacobians[0].shape(), (3, 6));
    assert_eq!(dynamic.jacobians[1].shape(), (3, 3));
    assert_eq!(
        dynamic.residual.as_slice(),
        f.residual().unwrap().as_slice()
    );
}

/// `r = a · (x − y)`, with a hand-written kernel in the calling convention of
/// the generated kernels: every field flattened, the residual, then one
/// optional row-major block per variable, beside its `SHAPE` and its slice
/// entry, as a generated module holds them, and its entry in apex-solver's
/// chart.
#[derive(Clone, Debug, Factor)]
#[factor(
    residual = weighted_residual,
    dim = 2,
    kernel = weighted::weighted,
    hosts(apex)
)]
pub struct Weighted<S: Scalar = f64> {
    pub weight: S,
    #[variable]
    pub x: Vector2<S>,
    #[variable(right)]
    pub y: Vector2<S>,
}

pub fn weighted_residual<S: Scalar>(f: &Weighted<S>) -> Vector2<S> {
    (f.x - f.y) * f.weight
}

/// What a generated module of `Weighted` would hold.
mod weighted {
    /// The module's marker type, which the derive names in `WithKernel`.
    pub struct Kernel;

    /// The array lengths of a kernel.
    pub struct Shape {
        pub inputs: &'static [usize],
        pub residual: usize,
        pub blocks: &'static [usize],
    }

    pub const SHAPE: Shape = Shape {
        inputs: &[1, 2, 2],
        residual: 2,
        blocks: &[4, 4],
    };

    pub fn weighted(
        weight: &[f64; 1],
        x: &[f64; 2],
        y: &[f64; 2],
        residual: &mut [f64; 2],
        d_x: Option<&mut [f64; 4]>,
        d_y: Option<&mut [f64; 4]>,
    ) {
        let a = weight[0];
        *residual = [a * (x[0] - y[0]), a * (x[1] - y[1])];
        if let Some(d) = d_x {
            *d = [a, 0.0, 0.0, a];
        }
        if let Some(d) = d_y {
            *d = [-a, 0.0, 0.0, -a];
        }
    }

    pub fn weighted_slices(
        inputs: &[&[f64]],
        residual: &mut [f64],
        blocks: &mut [Option<&mut [f64]>],
    ) -> bool {
        let ([weight, x, y], [d_x, d_y]) = (inputs, blocks) else {
            return false;
        };
        let (Ok(weight), Ok(x), Ok(y), Ok(residual)) = (
            <&[f64; 1]>::try_from(*weight),
            <&[f64; 2]>::try_from(*x),
            <&[f64; 2]>::try_from(*y),
            <&mut [f64; 2]>::try_from(residual),
        ) else {
            return false;
        };
        let d_x = d_x.as_deref_mut().map(<&mut [f64; 4]>::try_from);
        let d_y = d_y.as_deref_mut().map(<&mut [f64; 4]>::try_from);
        let (Ok(d_x), Ok(d_y)) = (d_x.transpose(), d_y.transpose()) else {
            return false;
        };
        weighted(weight, x, y, residual, d_x, d_y);
        true
    }

    /// The entry in apex-solver's chart: the stored scalars (`weight` read),
    /// one `Rn(2)` part per variable, the column-major 2 × 4 Jacobian.
    pub fn weighted_apex_host(
        stored: &[f64],
        parts: &[&[f64]],
        residual: &mut [f64],
        jacobian: Option<&mut [f64]>,
    ) -> bool {
        let (Some(&a), [x, y]) = (stored.first(), parts) else {
            return false;
        };
        if x.len() != 2 || y.len() != 2 || residual.len() != 2 {
            return false;
        }
        residual.copy_from_slice(&[a * (x[0] - y[0]), a * (x[1] - y[1])]);
        if let Some(d) = jacobian {
            if d.len() != 8 {
                return false;
            }
            d.copy_from_slice(&[a, 0.0, 0.0, a, -a, 0.0, 0.0, -a]);
        }
        true
    }
}

#[test]
fn a_kernel_is_what_linearize_goes_through() {
    let f = Weighted {
        weight: 2.0,
        x: Vector2::new(1.0, 5.0),
        y: Vector2::new(0.5, -1.0),
    };
    assert_eq!(<Weighted as Factor>::KERNEL, Some("weighted::weighted"));
    assert_eq!(
        std::any::type_name::<<Weighted as factor_core::WithKernel>::Kernel>(),
        std::any::type_name::<weighted::Kernel>()
    );
    let generated = f.linearize_generated().unwrap();
    assert_eq!(f.linearize().unwrap(), generated);
    assert_eq!(generated, f.linearize_dual().unwrap());
    assert_eq!(
        f.linearize_generated_dyn().unwrap().unwrap(),
        generated.to_dyn()
    );
    // Without a kernel there is no generated linearization.
    assert!(difference().linearize_generated_dyn().is_none());
    assert_eq!(<Difference as Factor>::KERNEL, None);
    let bad = Weighted {
        weight: f64::NAN,
        ..f
    };
    assert!(matches!(
        bad.linearize_generated(),
        Err(FactorError::NonFinite { .. })
    ));
}

/// `Weighted` with its residual's sign flipped since the kernel it names was
/// written: the layout is unchanged, so it compiles, and it is the values
/// that tell the kernel is stale.
#[derive(Clone, Debug, Factor)]
#[factor(
    residual = flipped_residual,
    dim = 2,
    kernel = weighted::weighted,
    regenerate = "cargo run -p my-cli --no-default-features -- generate",
    hosts(apex)
)]
pub struct Flipped<S: Scalar = f64> {
    pub weight: S,
    #[variable]
    pub x: Vector2<S>,
    #[variable(right)]
    pub y: Vector2<S>,
}

pub fn flipped_residual<S: Scalar>(f: &Flipped<S>) -> Vector2<S> {
    (f.y - f.x) * f.weight
}

fn flipped() -> Flipped {
    Flipped {
        weight: 2.0,
        x: Vector2::new(1.0, 5.0),
        y: Vector2::new(0.5, -1.0),
    }
}

/// The stale kernel's residual, `2 · (x − y)`, which a release build returns.
const STALE_RESIDUAL: [f64; 2] = [1.0, 12.0];

/// The report of the stale kernel `kernel` of `Flipped` in a debug build.
fn assert_stale(result: Result<(), FactorError>, kernel: &str) {
    let error = result.expect_err("a debug build reports the stale kernel");
    assert!(
        matches!(
            error,
            FactorError::StaleKernel {
                factor: "flipped",
                ..
            }
        ),
        "{error:?}"
    );
    let message = error.to_string();
    let expected = format!(
        "flipped: the generated kernel `{kernel}` is stale: its residual[0] is 1 where dual \
         numbers through the current definition give -1 (a residual, a function it calls or a \
         variable's retraction changed since the kernel was generated); regenerate it with \
         `cargo run -p my-cli --no-default-features -- generate`."
    );
    assert!(message.starts_with(&expected), "{message}");
}

/// A debug build reports the stale kernel at the first linearization, as an
/// error (`eval` prints it on one line; a test fails with it), and at every
/// later one: a kernel found stale is not used again. A release build
/// returns the stale kernel's values.
#[test]
fn a_stale_kernel_is_an_error_in_debug_builds() {
    for _ in 0..2 * factor_core::kernel::DEBUG_CHECKS {
        let result = flipped().linearize();
        if cfg!(debug_assertions) {
            assert_stale(result.map(|_| ()), "weighted::weighted");
        } else {
            assert_eq!(result.unwrap().residual.as_slice(), STALE_RESIDUAL);
        }
    }
}

#[test]
fn a_stale_kernel_is_an_error_on_the_solver_path_too() {
    let mut residual = [0.0; 2];
    let (mut d_x, mut d_y) = ([0.0; 4], [0.0; 4]);
    let result =
        flipped().linearize_into(&mut residual, &mut [Some(&mut d_x[..]), Some(&mut d_y[..])]);
    if cfg!(debug_assertions) {
        assert_stale(result, "weighted::weighted");
    } else {
        result.unwrap();
        assert_eq!(residual, STALE_RESIDUAL);
    }
}

/// `flipped()` in apex-solver's chart: its stored scalars and its two
/// `Rn(2)` parts.
fn in_apex_chart<F: HostFactor<Apex>>(f: &F) -> (HostLayout<ApexManifold>, Vec<f64>) {
    (HostLayout::of::<F, Apex>(), f.to_scalars())
}

/// A current kernel in a host's chart runs without complaint and gives
/// dual numbers' outputs in that chart.
#[test]
fn a_current_host_kernel_agrees_with_dual_numbers_in_its_chart() {
    let f = Weighted {
        weight: 2.0,
        x: Vector2::new(1.0, 5.0),
        y: Vector2::new(0.5, -1.0),
    };
    let (layout, stored) = in_apex_chart(&f);
    let parts: [&[f64]; 2] = [&[1.0, 5.0], &[0.5, -1.0]];
    let (mut r, mut j) = ([0.0; 2], [0.0; 8]);
    linearize_host::<Weighted, Apex>(&layout, &stored, &parts, &mut r, Some(&mut j)).unwrap();
    let (mut r_dual, mut j_dual) = ([0.0; 2], [0.0; 8]);
    linearize_host_dual::<Weighted, Apex>(&layout, &stored, &parts, &mut r_dual, Some(&mut j_dual))
        .unwrap();
    assert_eq!((r, j), (r_dual, j_dual));
    assert_eq!(r, [1.0, 12.0]);
}

/// The stale kernel served in apex-solver's chart, as a solver calls it:
/// a debug build reports it at the first call (its residual only, as a
/// solver's cost evaluation asks) and every later one, a release build
/// returns the old values.
#[test]
fn a_stale_host_kernel_is_an_error_in_debug_builds() {
    let (layout, stored) = in_apex_chart(&flipped());
    let parts: [&[f64]; 2] = [&[1.0, 5.0], &[0.5, -1.0]];
    for _ in 0..2 * factor_core::kernel::DEBUG_CHECKS {
        let mut residual = [0.0; 2];
        let result = linearize_host::<Flipped, Apex>(&layout, &stored, &parts, &mut residual, None);
        if cfg!(debug_assertions) {
            assert_stale(result, "weighted::weighted_apex");
        } else {
            result.unwrap();
            assert_eq!(residual, STALE_RESIDUAL);
        }
    }
}
