//! The documents' factors on g2o's measurements
//! (`slam_factors::g2o::{line_observation, plane_observation}`): with the
//! measurement moved off the truth by g2o's own noise model (its `oplus` on
//! the measured line or plane), the documents' cost with the mapped
//! information equals g2o's cost to first order in the noise.

use factor_core::geometry::OrthonormalLine;
use factor_core::geometry::plane::transpose_transform;
use factor_core::lie::{Quaternion, Se3, Se3RhoTheta, So2, So3};
use factor_testing::samples::Sampler;
use nalgebra::{Matrix3, Matrix4, SMatrix, SVector, Vector3, Vector4, Vector6};
use slam_factors::g2o::{line_observation, plane_observation};

fn chi2<const N: usize>(e: &SVector<f64, N>, information: &SMatrix<f64, N, N>) -> f64 {
    (e.transpose() * information * e)[0]
}

fn unit(pose: &Se3<f64>) -> Se3<f64> {
    Se3::new(
        So3::from_quaternion(pose.rotation.quaternion.normalized()),
        pose.translation,
    )
}

/// g2o's `Line3D::oplus`: `U ← U R(q(ν))` with `q(ν) = [ν, √(1 − |ν|²)]`,
/// `W ← W R(ν₄)`, written as `[w, d]` with a unit direction.
fn line_oplus(line: &OrthonormalLine<f64>, nu: &Vector4<f64>) -> Vector6<f64> {
    let q = Quaternion::new(nu.x, nu.y, nu.z, (1.0 - nu.xyz().norm_squared()).sqrt());
    let moved = OrthonormalLine::new(
        line.u.compose(&So3::from_quaternion(q)),
        line.w.compose(&So2::exp(nu.w)),
    )
    .to_plucker();
    let s = moved.direction.norm().recip();
    let (w, d) = (moved.normal * s, moved.direction * s);
    Vector6::new(w.x, w.y, w.z, d.x, d.y, d.z)
}

/// g2o's `Plane3D::oplus` of `[n, d]`: the normal of azimuth `ν₀` and
/// elevation `ν₁` in the frame `Rz(azimuth n) Ry(−elevation n)`, g2o's
/// distance `−d` moved by `ν₂`.
fn plane_oplus(plane: &Vector4<f64>, nu: &Vector3<f64>) -> Vector4<f64> {
    let p = plane / plane.xyz().norm();
    let n = p.xyz();
    let (azimuth, elevation) = (n.y.atan2(n.x), n.z.atan2(n.xy().norm()));
    let frame =
        So3::exp(&(Vector3::z() * azimuth)).compose(&So3::exp(&(Vector3::y() * -elevation)));
    let local = Vector3::new(nu.y.cos() * nu.x.cos(), nu.y.cos() * nu.x.sin(), nu.y.sin());
    let m = frame.rotate(&local);
    Vector4::new(m.x, m.y, m.z, p.w - nu.z)
}

/// The worst `|cost_documents / cost_g2o − 1|` over `n` configurations with
/// noise of size `scale`.
fn worst_ratio(scale: f64, n: usize, seed: u64) -> (f64, f64) {
    let mut s = Sampler::new(seed);
    let (mut lines, mut planes) = (0.0_f64, 0.0_f64);
    for _ in 0..n {
        let mut f = s.g2o_line_with_error(0.0);
        f.pose = Se3RhoTheta::new(unit(&f.pose.se3()));
        let local =
            OrthonormalLine::from_plucker(&f.line.to_plucker().transform(&f.pose.se3().inverse()));
        let nu = Vector4::from_fn(|_, _| s.uniform(-scale, scale));
        f.measured = line_oplus(&local, &nu);
        let information = Matrix4::from_diagonal(&Vector4::new(1e3, 2e3, 5e2, 1e4));
        let g2o = chi2(&f.residual().unwrap(), &information);
        let (doc, mapped) =
            line_observation(&f.pose.se3(), &f.line, &f.measured, &information).unwrap();
        lines = lines.max((chi2(&doc.residual().unwrap(), &mapped) / g2o - 1.0).abs());

        let mut f = s.g2o_plane_with_error(0.0);
        f.pose = Se3RhoTheta::new(unit(&f.pose.se3()));
        f.offset = Se3RhoTheta::new(unit(&f.offset.se3()));
        let to_sensor = f.pose.se3().compose(&f.offset.se3()).inverse();
        let predicted = transpose_transform(&to_sensor.inverse(), &f.plane.coefficients());
        let nu = Vector3::from_fn(|_, _| s.uniform(-scale, scale));
        f.measured = plane_oplus(&predicted, &nu);
        let information = Matrix3::from_diagonal(&Vector3::new(33.3, 50.0, 200.0));
        let g2o = chi2(&f.residual().unwrap(), &information);
        let (doc, mapped) = plane_observation(
            &f.pose.se3(),
            &f.plane,
            &f.offset.se3(),
            &f.measured,
            &information,
        )
        .unwrap();
        planes = planes.max((chi2(&doc.residual().unwrap(), &mapped) / g2o - 1.0).abs());
    }
    (lines, planes)
}

/// The differences vanish with the noise: as `ν²` for lines (both residuals
/// are odd in `ν` to second order; measured `0.65 ν²`) and as `ν` for planes
/// (the documents' plane residual, a quaternion logarithm in the world
/// frame, is curved in g2o's chart: measured `14 ν` at worst, so about 40%
/// at g2o's simulated noise of 0.03 rad). A wrong information mapping would
/// leave a difference that does not vanish.
#[test]
fn mapped_costs_equal_g2os_to_first_order_in_the_noise() {
    for scale in [1e-2, 1e-3, 1e-4, 1e-5] {
        let (lines, planes) = worst_ratio(scale, 100, 41);
        println!(
            "noise {scale:e}: worst relative difference, lines {lines:.1e}, planes {planes:.1e}"
        );
        assert!(
            lines <= 2.0 * scale * scale + 1e-9,
            "lines at {scale:e}: {lines:e}"
        );
        assert!(planes <= 20.0 * scale, "planes at {scale:e}: {planes:e}");
    }
}

/// The documents' factors on g2o's body-to-world pose `X` have the
/// residual of the documents' factor at `T = X⁻¹`, and their pose block
/// is the documents' left-chart block moved to `X`'s right chart by
/// `inverse_pose_block` (a closed form, independent of the dual numbers
/// that differentiate through the inverse).
#[test]
fn documents_factors_on_body_pose_are_the_documents_at_the_inverse() {
    use factor_core::Factor;
    use factor_core::lie::inverse_pose_block;
    use slam_factors::g2o::{LineObservationOnBody, PlaneFactorOnBody};

    fn compare<const R: usize>(documents: &impl Factor, on_body: &impl Factor) {
        let t = documents.linearize_dual_dyn().expect("documents' factor");
        let x = on_body.linearize_dual_dyn().expect("on the body pose");
        let scale = t.residual.norm().max(1.0);
        assert!(
            (&t.residual - &x.residual).norm() <= 1e-12 * scale,
            "{} against {}",
            t.residual,
            x.residual
        );
        let block_t = SMatrix::<f64, R, 6>::from_fn(|r, c| t.jacobians[0][(r, c)]);
        let moved = inverse_pose_block(&block_t);
        let block_x = SMatrix::<f64, R, 6>::from_fn(|r, c| x.jacobians[0][(r, c)]);
        let error = (moved - block_x).norm() / moved.norm().max(1e-300);
        assert!(
            error <= 1e-10,
            "pose block: relative error {error:e}\n{moved}\n{block_x}"
        );
    }
    let mut s = Sampler::new(41);
    for _ in 0..100 {
        let f = s.line_observation();
        let on_body = LineObservationOnBody::new(&f, Se3RhoTheta::new(f.pose.inverse()));
        compare::<4>(&f, &on_body);
        let f = s.plane();
        let on_body = PlaneFactorOnBody::new(&f, Se3RhoTheta::new(f.pose.inverse()));
        compare::<3>(&f, &on_body);
    }
}
