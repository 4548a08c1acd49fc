//! The constructors and accessors a point-line-plane user needs: orthonormal
//! lines from two points, their direction, moment, distance and closest
//! point; planes from and to `(n, d)`; the two pose conventions and the
//! Jacobian block map between them. References are the defining
//! properties (points on the line, points on the plane, finite differences
//! through the retraction), not the code under test.

use factor_core::geometry::{InfinitePlane, OrthonormalLine, PluckerLine};
use factor_core::lie::so3::hat;
use factor_core::lie::{Se3, Se3RhoTheta, So3, inverse_pose_block};
use factor_core::{Manifold, Perturbation};
use nalgebra::{Matrix3x6, Vector3, Vector4};
use proptest::prelude::*;

fn vector(r: f64) -> impl Strategy<Value = Vector3<f64>> {
    prop::array::uniform3(-r..r).prop_map(Vector3::from)
}

fn pose() -> impl Strategy<Value = Se3<f64>> {
    (vector(3.0), vector(5.0)).prop_map(|(w, t)| Se3::new(So3::exp(&w), t))
}

/// Distance of `x` from the line with unit direction `d` and moment `m`:
/// `|x × d − m|` (zero exactly when `x` is on it).
fn off_line(x: &Vector3<f64>, line: &OrthonormalLine<f64>) -> f64 {
    (x.cross(&line.direction()) - line.moment()).norm()
}

proptest! {
    #![proptest_config(ProptestConfig {
        cases: 500,
        rng_seed: proptest::test_runner::RngSeed::Fixed(3),
        failure_persistence: None,
        ..ProptestConfig::default()
    })]

    /// The line through `p` and `q` holds both, points from `p` to `q`,
    /// and its closest point is on it, perpendicular to it, at its distance.
    #[test]
    fn a_line_from_two_points_holds_them(p in vector(10.0), q in vector(10.0)) {
        let line = PluckerLine::from_points(&p, &q);
        prop_assume!((q - p).norm() > 1e-3 && line.normal.norm() > 1e-3 * (q - p).norm());
        let l = OrthonormalLine::try_from_points(&p, &q).unwrap();
        let scale = p.norm().max(q.norm());
        prop_assert!(off_line(&p, &l) <= 1e-13 * scale, "{}", off_line(&p, &l));
        prop_assert!(off_line(&q, &l) <= 1e-13 * scale);
        let d = l.direction();
        prop_assert!((d - (q - p).normalize()).norm() <= 1e-13);
        let c = l.closest_point();
        prop_assert!(off_line(&c, &l) <= 1e-13 * scale);
        prop_assert!(c.dot(&d).abs() <= 1e-13 * scale);
        prop_assert!((c.norm() - l.distance()).abs() <= 1e-13 * scale);
        prop_assert!((l.moment().norm() - l.distance()).abs() <= 1e-13 * scale);
        // The closest point is no farther than the two points.
        prop_assert!(c.norm() <= p.norm().min(q.norm()) * (1.0 + 1e-13));
        // The Plücker line it came from, scaled to a unit direction.
        let back = l.to_plucker();
        let unit = back.direction.norm();
        prop_assert!((back.normal / unit - l.moment()).norm() <= 1e-13 * scale);
        prop_assert!((line.normal / line.direction.norm() - l.moment()).norm() <= 1e-12 * scale);
    }

    /// `from_normal_offset` and `normal_offset` are inverse (`n` unit), the
    /// plane holds the points `n · x = −d`, and any common scale of `(n, d)`
    /// is the same plane.
    #[test]
    fn planes_from_and_to_normal_and_offset(
        n in vector(1.0), d in -10.0..10.0_f64, s in 0.01..100.0_f64, t in vector(10.0),
    ) {
        prop_assume!(n.norm() > 0.1);
        let unit = n.normalize();
        let plane = InfinitePlane::from_normal_offset(&unit, d);
        let (back_n, back_d) = plane.normal_offset();
        prop_assert!((back_n - unit).norm() <= 1e-14 && (back_d - d).abs() <= 1e-13 * d.abs().max(1.0));
        // A point of the plane: −d n plus any step perpendicular to n.
        let x = -unit * d + (t - unit * unit.dot(&t));
        let pi = plane.coefficients();
        prop_assert!((pi.xyz().dot(&x) + pi.w).abs() <= 1e-13 * (1.0 + x.norm()));
        let scaled = InfinitePlane::try_from_normal_offset(&(n * s), d * n.norm() * s).unwrap();
        let (sn, sd) = scaled.normal_offset();
        prop_assert!((sn - unit).norm() <= 1e-14 && (sd - d).abs() <= 1e-13 * d.abs().max(1.0));
    }

    /// The world-to-camera pose and the camera-to-world pose are inverse,
    /// and `inverse_pose_block` turns the left block w.r.t. `T` of `r(T) =
    /// T p` into the right block w.r.t. `X = T⁻¹` that central differences
    /// through `X`'s retraction give.
    #[test]
    fn pose_conventions_and_their_jacobian_blocks(t in pose(), p in vector(5.0)) {
        let x = Se3RhoTheta::from_world_to_camera(&t);
        let round = x.world_to_camera();
        prop_assert!((round.matrix() - t.matrix()).amax() <= 1e-14 * (1.0 + t.translation.norm()));
        prop_assert!((x.transform_point(&t.transform_point(&p)) - p).norm() <= 1e-13 * (1.0 + p.norm()));
        // d(Exp(δ) T p)/dδ = [−[T p]×, I] in [δω, δρ] order.
        let tp = t.transform_point(&p);
        let mut left = Matrix3x6::zeros();
        left.fixed_view_mut::<3, 3>(0, 0).copy_from(&-hat(&tp));
        left.fixed_view_mut::<3, 3>(0, 3).copy_from(&nalgebra::Matrix3::identity());
        let converted = inverse_pose_block(&left);
        let h = 1e-6;
        for k in 0..6 {
            let mut step = [0.0; 6];
            step[k] = h;
            let plus = x.retract(&step, Perturbation::Right).world_to_camera().transform_point(&p);
            step[k] = -h;
            let minus = x.retract(&step, Perturbation::Right).world_to_camera().transform_point(&p);
            let column = (plus - minus) / (2.0 * h);
            prop_assert!(
                (column - converted.column(k)).norm() <= 1e-7 * (1.0 + tp.norm()),
                "column {}: {} vs {}", k, column, converted.column(k)
            );
        }
        // Its own inverse.
        prop_assert_eq!(inverse_pose_block(&converted), left);
    }
}

#[test]
fn degenerate_lines_and_planes_are_refused() {
    let p = Vector3::new(1.0, 2.0, 3.0);
    let e = OrthonormalLine::try_from_points(&p, &p).unwrap_err();
    assert!(e.message.contains("the same"), "{e}");
    // Through the origin: no orthonormal representation.
    let e = OrthonormalLine::try_from_points(&p, &(p * 2.0)).unwrap_err();
    assert!(e.message.contains("passes through the world origin"), "{e}");
    let e = InfinitePlane::try_from_normal_offset(&Vector3::zeros(), 1.0).unwrap_err();
    assert!(e.message.contains("normal n is zero"), "{e}");
    let e = InfinitePlane::try_from_normal_offset(&Vector3::z(), f64::NAN).unwrap_err();
    assert!(e.message.contains("not finite"), "{e}");
    // The floor z = −5 with its normal up.
    let floor = InfinitePlane::try_from_normal_offset(&Vector3::z(), 5.0).unwrap();
    let expected = Vector4::new(0.0, 0.0, 1.0, 5.0) / 26f64.sqrt();
    assert!((floor.coefficients() - expected).amax() <= 1e-15);
    let (n, d) = floor.normal_offset();
    assert!(n == Vector3::z() && (d - 5.0).abs() <= 1e-14, "{n} {d}");
}
