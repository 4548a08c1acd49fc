//! `Manifold::local`, the inverse of the retraction, for every type the
//! crate ships: on both sides, `local(x, retract(x, δ)) = δ` for steps up to
//! near the end of the invertible domain, and `retract(x, local(x, y)) = y`
//! for points `y` anywhere (the stored scalars themselves: a quaternion on
//! the far sheet comes back as itself, not as its negation).

use factor_core::geometry::{FreeLine, InfinitePlane, OrthonormalLine, PluckerLine};
use factor_core::lie::{Quaternion, Se3, Se3RhoTheta, So2, So3};
use factor_core::manifold::NoLocal;
use factor_core::{Manifold, Perturbation};
use factor_testing::local::assert_local_inverts;
use nalgebra::{Vector3, Vector4};
use proptest::prelude::*;

const SIDES: [Perturbation; 2] = [Perturbation::Left, Perturbation::Right];

/// A unit quaternion from four coordinates in `[−1, 1]` (far from zero).
fn quaternion(c: [f64; 4]) -> Quaternion<f64> {
    let v = Vector4::from(c) + Vector4::new(0.0, 0.0, 0.0, 1e-3);
    Quaternion::from_coords(v / v.norm())
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
        assert_local_inverts(&so3a, &so3b, &d, 1e-12);
        let plane = |q: Quaternion<f64>| InfinitePlane { quaternion: q };
        assert_local_inverts(&plane(qa), &plane(qb), &d, 1e-12);
        let line = |q, distance| FreeLine::new(q, distance);
        let step = [d[0], d[1], d[2], 0.7];
        assert_local_inverts(&line(qa, distances[0]), &line(qb, distances[1]), &step, 1e-12);
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
        assert_local_inverts(&x, &y, &d, 1e-11);
        assert_local_inverts(&Se3RhoTheta::new(x), &Se3RhoTheta::new(y), &d, 1e-11);
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
        assert_local_inverts(&x, &y, &d[..4], 1e-12);
        let plucker = |v: &[f64]| {
            PluckerLine::new(Vector3::new(v[0], v[1], v[2]), Vector3::new(v[3], v[4], v[5]))
        };
        assert_local_inverts(&plucker(&p), &plucker(&d), &d, 1e-12);
        assert_local_inverts(&Vector3::new(p[0], p[1], p[2]), &Vector3::new(d[0], d[1], d[2]), &d[3..], 1e-12);
        assert_local_inverts(&p[0], &d[0], &d[1..2], 1e-12);
    }
}

/// A type that gives no `local` says so, through the trait's default.
#[test]
fn a_type_without_local_says_so() {
    #[derive(Clone, Copy)]
    struct Angle(f64);
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
    assert_eq!(
        Angle(1.0).local(&Angle(2.0), SIDES[0], &mut out),
        Err(NoLocal)
    );
    assert_eq!(Angle(1.0).retract(&[2.0], SIDES[1]).0, 3.0);
}

/// Charts are named after their type and side.
#[test]
fn charts_are_named_after_the_type_and_the_side() {
    let info = |type_name, perturbation| factor_core::VariableInfo {
        name: "x",
        type_name,
        tangent_dim: 1,
        perturbation,
        tangent: "",
    };
    assert_eq!(info("Se3<S>", Perturbation::Left).chart_name(), "se3_left");
    assert_eq!(
        info("factor_core::lie::Se3RhoTheta<S>", Perturbation::Right).chart_name(),
        "se3_rho_theta_right"
    );
    assert_eq!(
        info("OrthonormalLine<S>", Perturbation::Left).chart_name(),
        "orthonormal_line_left"
    );
    assert_eq!(
        info("UnitVector3<S>", Perturbation::Left).chart_name(),
        "unit_vector3_left"
    );
    assert_eq!(info("S", Perturbation::Left).chart_name(), "s_left");
}
