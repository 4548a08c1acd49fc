//! `Manifold::local` of the crate's own manifolds, the inverse of their
//! exact retractions (what their Ceres manifolds' `Minus` is generated
//! from): on both sides, `local(x, retract(x, δ)) = δ` for steps well inside
//! the invertible domain, and `retract(x, local(x, y)) = y` for points `y`
//! anywhere (the stored scalars themselves: a Sim(3) whose quaternion is on
//! the far sheet comes back with that quaternion).

use factor_core::lie::{Quaternion, So3};
use factor_testing::local::assert_local_inverts;
use nalgebra::{Vector3, Vector4};
use proptest::prelude::*;
use user_factors::sim3::Sim3;
use user_factors::unit_vector::UnitVector3;

fn sim3(q: [f64; 4], t: [f64; 3], sigma: f64) -> Sim3<f64> {
    let q = Vector4::from(q) + Vector4::new(0.0, 0.0, 0.0, 1e-3);
    let rotation = So3::from_quaternion(Quaternion::from_coords(q / q.norm()));
    Sim3::new(rotation, Vector3::from(t), sigma)
}

proptest! {
    #[test]
    fn sim3_local_inverts_the_retraction(
        qa in prop::array::uniform4(-1.0..1.0_f64),
        qb in prop::array::uniform4(-1.0..1.0_f64),
        ta in prop::array::uniform3(-5.0..5.0_f64),
        tb in prop::array::uniform3(-5.0..5.0_f64),
        sigmas in prop::array::uniform2(-1.0..1.0_f64),
        rotation in prop::array::uniform3(-1.5..1.5_f64),
        rest in prop::array::uniform4(-1.0..1.0_f64),
    ) {
        let (x, y) = (sim3(qa, ta, sigmas[0]), sim3(qb, tb, sigmas[1]));
        let delta = [rotation[0], rotation[1], rotation[2], rest[0], rest[1], rest[2], rest[3]];
        assert_local_inverts(&x, &y, &delta, 1e-10);
    }

    #[test]
    fn unit_vector_local_inverts_the_geodesic(
        a in prop::array::uniform3(-1.0..1.0_f64),
        b in prop::array::uniform3(-1.0..1.0_f64),
        delta in prop::array::uniform2(-2.0..2.0_f64),
    ) {
        let direction = |c: [f64; 3]| {
            UnitVector3::from_direction(&(Vector3::from(c) + Vector3::new(1e-3, 0.0, 0.0)))
        };
        let (x, y) = (direction(a), direction(b));
        // Not the antipode, where the geodesic has no direction.
        prop_assume!(x.vector().dot(&y.vector()) > -0.999);
        assert_local_inverts(&x, &y, &delta, 1e-11);
    }
}
