//! `Manifold::local`, the inverse of the retraction, for every type the
//! crate ships: on both sides, `local(x, retract(x, δ)) = δ` for steps up to
//! near the end of the invertible domain, and `retract(x, local(x, y)) = y`
//! for points `y` anywhere (the stored scalars themselves: a quaternion on
//! the far sheet comes back as itself, not as its negation).

use factor_core::geometry::{FreeLine, InfinitePlane, OrthonormalLine, PluckerLine};
use factor_core::lie::{Quaternion, Se3, Se3RhoTheta, So2, So3};
use factor_core::manifold::{ChartMap, NoLocal, apply_chart};
use factor_core::{Manifold, Perturbation, Storage};
use nalgebra::{Vector3, Vector4};
use proptest::prelude::*;

const SIDES: [Perturbation; 2] = [Perturbation::Left, Perturbation::Right];

/// A unit quaternion from four coordinates in `[−1, 1]` (far from zero).
fn quaternion(c: [f64; 4]) -> Quaternion<f64> {
    let v = Vector4::from(c) + Vector4::new(0.0, 0.0, 0.0, 1e-3);
    Quaternion::from_coords(v / v.norm())
}

/// `local(retract(δ)) = δ` and `retract(local(y)) = y` through
/// [`apply_chart`], on both sides, to `tolerance` (absolute on `δ`, on the
/// stored scalars of `y`).
fn assert_inverse<M: Manifold<f64> + Storage<f64>>(
    x: &M,
    y: &M,
    delta: &[f64],
    tolerance: f64,
) -> Result<(), TestCaseError> {
    let (x, y) = (x.to_scalars(), y.to_scalars());
    for side in SIDES {
        let mut moved = vec![0.0; x.len()];
        apply_chart::<M, f64>(ChartMap::Retract, side, &x, delta, &mut moved).unwrap();
        let mut back = vec![0.0; delta.len()];
        apply_chart::<M, f64>(ChartMap::Local, side, &x, &moved, &mut back).unwrap();
        for (a, b) in back.iter().zip(delta) {
            prop_assert!(
                (a - b).abs() <= tolerance,
                "{side:?}: δ {delta:?} → {back:?}"
            );
        }
        let mut coordinates = vec![0.0; delta.len()];
        apply_chart::<M, f64>(ChartMap::Local, side, &x, &y, &mut coordinates).unwrap();
        let mut reached = vec![0.0; x.len()];
        apply_chart::<M, f64>(ChartMap::Retract, side, &x, &coordinates, &mut reached).unwrap();
        for (a, b) in reached.iter().zip(&y) {
            prop_assert!(
                (a - b).abs() <= tolerance,
                "{side:?}: y {y:?} → {reached:?}"
            );
        }
    }
    Ok(())
}

proptest! {
    #[test]
    fn rotations_planes_and_free_lines_invert(
        a in prop::array::uniform4(-1.0..1.0_f64),
        b in prop::array::uniform4(-1.0..1.0_f64),
        d in prop::array::uniform3(-2.0..2.0_f64),
        distances in prop::array::uniform2(-5.0..5.0_f64),
    ) {
        let (qa, qb) = (quaternion(a), quaternion(b));
        let (so3a, so3b) = (So3::from_quaternion(qa), So3::from_quaternion(qb));
        assert_inverse(&so3a, &so3b, &d, 1e-12)?;
        let plane = |q: Quaternion<f64>| InfinitePlane { quaternion: q };
        assert_inverse(&plane(qa), &plane(qb), &d, 1e-12)?;
        let line = |q, distance| FreeLine::new(q, distance);
        let step = [d[0], d[1], d[2], 0.7];
        assert_inverse(&line(qa, distances[0]), &line(qb, distances[1]), &step, 1e-12)?;
    }

    #[test]
    fn poses_invert(
        a in prop::array::uniform4(-1.0..1.0_f64),
        b in prop::array::uniform4(-1.0..1.0_f64),
        ta in prop::array::uniform3(-10.0..10.0_f64),
        tb in prop::array::uniform3(-10.0..10.0_f64),
        d in prop::array::uniform6(-2.0..2.0_f64),
    ) {
        let x = Se3::new(So3::from_quaternion(quaternion(a)), Vector3::from(ta));
        let y = Se3::new(So3::from_quaternion(quaternion(b)), Vector3::from(tb));
        assert_inverse(&x, &y, &d, 1e-11)?;
        assert_inverse(&Se3RhoTheta::new(x), &Se3RhoTheta::new(y), &d, 1e-11)?;
    }

    #[test]
    fn orthonormal_lines_and_vector_spaces_invert(
        a in prop::array::uniform4(-1.0..1.0_f64),
        b in prop::array::uniform4(-1.0..1.0_f64),
        angles in prop::array::uniform2(-3.0..3.0_f64),
        d in prop::array::uniform6(-2.0..2.0_f64),
        p in prop::array::uniform6(-5.0..5.0_f64),
    ) {
        let line = |q, angle| OrthonormalLine::new(So3::from_quaternion(q), So2::exp(angle));
        let (x, y) = (line(quaternion(a), angles[0]), line(quaternion(b), angles[1]));
        assert_inverse(&x, &y, &d[..4], 1e-12)?;
        let plucker = |v: &[f64]| {
            PluckerLine::new(Vector3::new(v[0], v[1], v[2]), Vector3::new(v[3], v[4], v[5]))
        };
        assert_inverse(&plucker(&p), &plucker(&d), &d, 1e-12)?;
        assert_inverse(&Vector3::new(p[0], p[1], p[2]), &Vector3::new(d[0], d[1], d[2]), &d[3..], 1e-12)?;
        assert_inverse(&p[0], &d[0], &d[1..2], 1e-12)?;
    }
}

/// A type that gives no `local` is reported, not guessed.
#[test]
fn a_type_without_local_says_so() {
    #[derive(Clone, Copy)]
    struct Angle(f64);
    impl Storage<f64> for Angle {
        type With<T: factor_core::Scalar> = T;
        const SCALARS: usize = 1;
        fn layout() -> factor_core::Layout {
            factor_core::Layout::Scalar
        }
        fn map_scalars<T: factor_core::Scalar>(&self, f: &mut impl FnMut(f64) -> T) -> T {
            f(self.0)
        }
        fn read_scalars(next: &mut impl FnMut() -> f64) -> Self {
            Angle(next())
        }
    }
    impl Manifold<f64> for Angle {
        const DIM: usize = 1;
        fn retract(&self, delta: &[f64], _side: Perturbation) -> Self {
            Angle(self.0 + delta[0])
        }
        fn tangent_description(_side: Perturbation) -> &'static str {
            "additive"
        }
    }
    let mut out = [0.0];
    let local = apply_chart::<Angle, f64>(ChartMap::Local, SIDES[0], &[1.0], &[2.0], &mut out);
    assert_eq!(local, Err(NoLocal));
    let retract = apply_chart::<Angle, f64>(ChartMap::Retract, SIDES[0], &[1.0], &[2.0], &mut out);
    assert_eq!((retract, out), (Ok(()), [3.0]));
}
