//! What a batch computes for every shape of input: any number of rows (none,
//! fewer than a lane group, a scalar tail, more than a thread chunk), fixed
//! variables, every instruction set and thread setting, and columns that do
//! not fit, which are refused with an error naming them.

use factor_batch::{
    BatchError, CHUNK, Columns, Isa, JacobianColumns, NormalColumns, Options, Threads, linearize,
    normal,
};
use factor_lanes::{F32x8, F64x4, F64x8};
use factor_testing::samples::Sampler;
use slam_factors::{PlaneFactor, PointReprojection};

fn points(count: usize) -> Vec<PointReprojection> {
    let mut s = Sampler::new(31);
    (0..count).map(|_| s.point_reprojection()).collect()
}

fn planes(count: usize) -> Vec<PlaneFactor> {
    let mut s = Sampler::new(32);
    (0..count).map(|_| s.plane()).collect()
}

/// The point Jacobians of `inputs` in `F64x4` with `options`, with the
/// blocks of `free`.
fn point_jacobians(inputs: &Columns<f64>, free: &[bool], options: Options) -> JacobianColumns<f64> {
    let mut out = JacobianColumns::new::<PointReprojection>(inputs.len(), free);
    linearize::<PointReprojection, F64x4>(inputs, &mut out, options).expect("shapes fit");
    out
}

#[test]
fn every_row_count_gives_each_factor_its_own_linearization() {
    // 0, fewer than one group, whole groups, a tail, across 8-lane groups.
    for n in [0, 1, 3, 4, 5, 7, 8, 9, 17] {
        let factors = points(n);
        let inputs = Columns::from_factors(&factors);
        for lanes in ["f64", "F64x4", "F64x8"] {
            let mut out = JacobianColumns::new::<PointReprojection>(n, &[]);
            let options = Options::default();
            match lanes {
                "f64" => linearize::<PointReprojection, f64>(&inputs, &mut out, options),
                "F64x4" => linearize::<PointReprojection, F64x4>(&inputs, &mut out, options),
                _ => linearize::<PointReprojection, F64x8>(&inputs, &mut out, options),
            }
            .expect("shapes fit");
            for (i, f) in factors.iter().enumerate() {
                let one = f.linearize_generated().expect("valid");
                assert_eq!(
                    out.residual.row(i),
                    one.residual.as_slice(),
                    "{lanes}, {n} rows"
                );
                let pose = out.blocks[0].as_ref().expect("free").row(i);
                assert_eq!(pose, one.pose.transpose().as_slice(), "{lanes}, {n} rows");
            }
        }
    }
}

#[test]
fn no_rows_is_no_work_and_no_error() {
    let inputs = Columns::<f64>::zeros(16, 0);
    let mut out = JacobianColumns::new::<PointReprojection>(0, &[]);
    linearize::<PointReprojection, F64x4>(&inputs, &mut out, Options::rayon()).expect("empty");
    assert!(out.residual.is_empty());
    assert!(out.non_finite_rows().is_empty());
    let inputs = Columns::<f32>::zeros(16, 0);
    let mut out = NormalColumns::<f32>::new::<PointReprojection>(0, &[true, false]);
    normal::<PointReprojection, F32x8>(&inputs, None, &mut out, Options::default()).expect("empty");
    assert!(out.cost.is_empty());
}

#[test]
fn a_fixed_variable_has_no_block_and_changes_nothing_else() {
    let factors = points(1001);
    let inputs = Columns::from_factors(&factors);
    let all = point_jacobians(&inputs, &[true, true], Options::default());
    for free in [[false, true], [true, false], [false, false]] {
        let some = point_jacobians(&inputs, &free, Options::default());
        assert_eq!(some.residual, all.residual);
        for (k, block) in some.blocks.iter().enumerate() {
            match block {
                Some(block) => assert_eq!(Some(block), all.blocks[k].as_ref(), "{free:?}"),
                None => assert!(!free[k]),
            }
        }
    }

    let w: Vec<f64> = (0..factors.len()).map(|i| 0.5 + (i % 7) as f64).collect();
    let mut full = NormalColumns::new::<PointReprojection>(factors.len(), &[]);
    normal::<PointReprojection, F64x4>(&inputs, Some(&w), &mut full, Options::default()).unwrap();
    let mut pose_fixed = NormalColumns::new::<PointReprojection>(factors.len(), &[false, true]);
    normal::<PointReprojection, F64x4>(&inputs, Some(&w), &mut pose_fixed, Options::default())
        .unwrap();
    assert_eq!(pose_fixed.cost, full.cost);
    assert!(pose_fixed.gradient[0].is_none());
    assert_eq!(pose_fixed.gradient[1], full.gradient[1]);
    // Pairs (pose, pose), (pose, point) are gone; (point, point) stays.
    assert!(pose_fixed.hessian[0].is_none() && pose_fixed.hessian[1].is_none());
    assert_eq!(pose_fixed.hessian[2], full.hessian[2]);
}

#[test]
fn threads_and_instruction_sets_change_nothing() {
    let factors = planes(2 * CHUNK + 13);
    let inputs = Columns::from_factors(&factors);
    let reference = point_free_plane(&inputs, Options::default());
    for threads in [Threads::One, Threads::Rayon] {
        for isa in [Isa::Baseline, Isa::Avx2, Isa::Avx512] {
            let out = point_free_plane(&inputs, Options { threads, isa });
            assert_eq!(out, reference, "{threads:?}, {isa:?}");
        }
    }
}

/// The plane batch in `F64x8` with every block.
fn point_free_plane(inputs: &Columns<f64>, options: Options) -> JacobianColumns<f64> {
    let mut out = JacobianColumns::new::<PlaneFactor>(inputs.len(), &[]);
    linearize::<PlaneFactor, F64x8>(inputs, &mut out, options).expect("shapes fit");
    out
}

#[test]
fn a_degenerate_configuration_is_reported_by_row() {
    let mut factors = points(10);
    // A point in the camera's plane: depth exactly zero.
    factors[6].pose = factor_core::lie::Se3::identity();
    factors[6].point = nalgebra::Vector3::new(1.0, 2.0, 0.0);
    let inputs = Columns::from_factors(&factors);
    let out = point_jacobians(&inputs, &[], Options::default());
    assert_eq!(out.non_finite_rows(), vec![6]);
}

#[test]
fn columns_that_do_not_fit_are_refused_by_name() {
    let factors = points(9);
    let inputs = Columns::from_factors(&factors);
    let run = |inputs: &Columns<f64>, out: &mut JacobianColumns<f64>| {
        linearize::<PointReprojection, F64x4>(inputs, out, Options::default())
    };

    let narrow = Columns::<f64>::zeros(15, 9);
    let error = run(
        &narrow,
        &mut JacobianColumns::new::<PointReprojection>(9, &[]),
    )
    .unwrap_err();
    assert_eq!(
        error.to_string(),
        "point_reprojection: inputs has 15 columns, expected 16"
    );

    let error = run(
        &inputs,
        &mut JacobianColumns::new::<PointReprojection>(8, &[]),
    )
    .unwrap_err();
    assert_eq!(
        error.to_string(),
        "point_reprojection: residual has 8 rows, the inputs 9"
    );

    let mut out = JacobianColumns::new::<PointReprojection>(9, &[]);
    out.blocks[1] = Some(Columns::zeros(5, 9));
    let error = run(&inputs, &mut out).unwrap_err();
    assert_eq!(
        error.to_string(),
        "point_reprojection: the Jacobian w.r.t. `point` has 5 columns, expected 6"
    );

    out.blocks.pop();
    assert!(matches!(
        run(&inputs, &mut out),
        Err(BatchError::Blocks {
            found: 1,
            expected: 2,
            ..
        })
    ));

    let mut normals = NormalColumns::new::<PointReprojection>(9, &[]);
    let error = normal::<PointReprojection, F64x4>(
        &inputs,
        Some(&[1.0; 8]),
        &mut normals,
        Options::default(),
    )
    .unwrap_err();
    assert_eq!(
        error.to_string(),
        "point_reprojection: weights has 8 rows, the inputs 9"
    );

    normals.gradient[0] = None;
    let error = normal::<PointReprojection, F64x4>(&inputs, None, &mut normals, Options::default())
        .unwrap_err();
    assert_eq!(
        error.to_string(),
        "point_reprojection: the Hessian block of `pose` and `pose` is present, but the \
         gradient blocks say the variables are not both free"
    );
}

#[test]
fn columns_round_trip_the_factors_storage() {
    let factors = points(5);
    let inputs = Columns::from_factors(&factors);
    assert_eq!((inputs.len(), inputs.width()), (5, 16));
    for (i, f) in factors.iter().enumerate() {
        assert_eq!(inputs.row(i), factor_core::Storage::to_scalars(f));
    }
    assert!(Columns::from_vec(3, vec![0.0; 7]).is_none());
    assert_eq!(
        Columns::from_vec(0, Vec::<f64>::new()).map(|c| c.width()),
        Some(0)
    );
}
