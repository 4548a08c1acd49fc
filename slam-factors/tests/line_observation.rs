//! The 3D line observation's residual against the obvious way to compute
//! it: the world line moved into the camera frame as a Plücker line
//! (`H L_w`, document 000 (8)), converted to `(U, W)` through a rotation
//! matrix, and the errors taken with the groups' own `Log`s.

use factor_core::geometry::OrthonormalLine;
use factor_testing::samples::Sampler;
use slam_factors::LineObservation;

fn reference(f: &LineObservation) -> nalgebra::Vector4<f64> {
    let camera = OrthonormalLine::from_plucker(&f.line.to_plucker().transform(&f.pose));
    let e_u = f.measured.u.inverse().compose(&camera.u).log();
    let e_w = f.measured.w.inverse().compose(&camera.w).log();
    nalgebra::Vector4::new(e_u.x, e_u.y, e_u.z, e_w)
}

#[test]
fn the_residual_is_the_orthonormal_error_of_the_transformed_line() {
    let mut sampler = Sampler::new(31);
    let mut worst = 0.0_f64;
    for i in 0..500 {
        // Large errors too: up to 1.5 per coordinate.
        let max_error = [0.0, 1e-6, 0.1, 1.5][i % 4];
        let f = sampler.line_observation_with_error(max_error);
        let error = (f.residual().unwrap() - reference(&f)).amax();
        assert!(error <= 1e-12, "configuration {i}: {error:e}");
        worst = worst.max(error);
    }
    println!("worst difference {worst:e}");
}
