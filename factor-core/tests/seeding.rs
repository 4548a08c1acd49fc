//! `Manifold::seeded`'s closed forms (SO(3), SE(3) in both tangent orders,
//! SO(2), the orthonormal, Plücker and free lines, the plane, vectors,
//! scalars) against its default, the first-order retraction on
//! dual numbers (`seeded_through_retraction`), on both sides, at points
//! spread over the groups.

use factor_core::dual::Dual;
use factor_core::geometry::{FreeLine, InfinitePlane, OrthonormalLine, PluckerLine};
use factor_core::lie::{Se3, Se3RhoTheta, So2, So3};
use factor_core::manifold::seeded_through_retraction;
use factor_core::{Manifold, Perturbation, Storage};
use nalgebra::{Vector3, Vector4};

/// Every stored scalar's value and derivative, in storage order.
fn scalars<V: Storage<Dual<N>>, const N: usize>(x: &V) -> Vec<Dual<N>> {
    let mut out = Vec::new();
    x.map_scalars(&mut |s| {
        out.push(s);
        s
    });
    out
}

/// The closed form and the default agree to a few ulp at `offset` of 9.
fn agree<V, const D: usize>(x: &V, offset: usize)
where
    V: Manifold<f64> + Storage<f64> + std::fmt::Debug,
    V::With<Dual<D>>: Manifold<Dual<D>> + Storage<Dual<D>, With<Dual<9>> = V::With<Dual<9>>>,
    V::With<Dual<9>>: Storage<Dual<9>>,
{
    for side in [Perturbation::Left, Perturbation::Right] {
        let closed = scalars(&Manifold::<f64>::seeded::<D, 9>(x, side, offset));
        let default = scalars(&seeded_through_retraction::<f64, V, D, 9>(x, side, offset));
        assert_eq!(closed.len(), default.len());
        for (a, b) in closed.iter().zip(&default) {
            assert_eq!(a.re, b.re, "{x:?} on the {side:?}");
            for (da, db) in a.eps.iter().zip(&b.eps) {
                assert!(
                    (da - db).abs() <= 4.0 * f64::EPSILON,
                    "{x:?} on the {side:?}: {a:?} against {b:?}"
                );
            }
        }
    }
}

#[test]
fn closed_form_seeds_are_the_retractions_derivatives() {
    for k in 0..40 {
        let t = k as f64;
        let axis = Vector3::new((0.7 * t).sin(), (1.3 * t).cos(), (0.4 * t + 1.0).sin());
        // Angles up to π, the identity among them.
        let rotation = So3::exp(&(axis * (0.08 * t)));
        let pose = Se3::new(rotation, Vector3::new(t - 20.0, 0.5 * t, -3.0 + 0.1 * t));
        agree::<_, 3>(&rotation, 2);
        agree::<_, 6>(&pose, 3);
        agree::<_, 6>(&Se3RhoTheta::new(pose), 1);
        agree::<_, 4>(&Vector4::new(t, -t, 0.5, 2.0), 5);
        agree::<_, 1>(&(t - 7.5), 8);
        let angle = 0.3 * t - 4.0;
        let w = So2::new(angle.cos(), angle.sin());
        agree::<_, 1>(&w, 4);
        agree::<_, 4>(&OrthonormalLine::new(rotation, w), 2);
        agree::<_, 4>(&FreeLine::new(rotation.quaternion, 0.25 * t - 3.0), 5);
        agree::<_, 3>(
            &InfinitePlane {
                quaternion: rotation.quaternion,
            },
            6,
        );
        agree::<_, 6>(
            &PluckerLine::new(Vector3::new(t, 1.0, -2.0), Vector3::new(0.5, -t, 3.0)),
            0,
        );
    }
}
