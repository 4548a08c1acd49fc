//! Configurations of the shipped factors a given distance from one of their
//! degeneracies (or far from the origin), built from a seeded well-conditioned
//! sample ([`Sampler`]) by moving one thing: for accuracy tests of the
//! numerical method and of the factors' accuracy envelopes.

use nalgebra::{Matrix3, Unit, Vector3};

use factor_core::geometry::{FreeLine, OrthonormalLine, PluckerLine};
use factor_core::lie::{Quaternion, So3};
use slam_factors::{FreeLineFactor, LineReprojection, PlaneFactor, PointReprojection};

use crate::samples::Sampler;

/// A point reprojection factor whose point lies at camera-frame
/// `(0.3, −0.2, depth)`.
pub fn point_at_depth(seed: u64, depth: f64) -> PointReprojection {
    let mut f = Sampler::new(seed).point_reprojection();
    let p_c = Vector3::new(0.3, -0.2, depth);
    f.point = f.pose.inverse().transform_point(&p_c);
    f
}

/// A line reprojection factor whose line passes `distance` from the optical
/// centre (camera frame), through the points `c + 2u` and `c + 4u` with `u`
/// along `(0.1, 0.2, 1)` and `|c| = distance`, `c ⊥ u`.
pub fn line_at_distance(seed: u64, distance: f64) -> LineReprojection {
    let mut f = Sampler::new(seed).line_reprojection();
    let u = Vector3::new(0.1, 0.2, 1.0).normalize();
    let x = Vector3::x();
    let c = (x - u * x.dot(&u)).normalize() * distance;
    let world = f.pose.inverse();
    let line = PluckerLine::from_points(
        &world.transform_point(&(c + u * 2.0)),
        &world.transform_point(&(c + u * 4.0)),
    );
    f.line = OrthonormalLine::from_plucker(&line);
    f
}

/// A plane factor whose error quaternion is `angle` (radians, on the
/// quaternion sphere) from the antipode: the measured plane is the predicted
/// one rotated by `angle` and negated (the same plane, written antipodally).
pub fn plane_near_antipodal(seed: u64, angle: f64) -> PlaneFactor {
    let mut f = Sampler::new(seed).plane_with_error(0.0);
    let rotation = So3::exp(&(Vector3::new(0.3, -0.5, 0.8).normalize() * angle)).quaternion;
    let measured = Quaternion::from_coords(f.measured.into_inner());
    f.measured = Unit::new_normalize(-rotation.mul(&measured).coords());
    f
}

/// A free-line factor moved `distance` away from the world origin, with the
/// camera still a few metres from the line's anchor: the anchor (and the
/// world) is shifted perpendicular to the line, and the body pose with it.
pub fn free_line_far(seed: u64, distance: f64) -> FreeLineFactor {
    let mut f = Sampler::new(seed).free_line();
    let x = f.line.direction();
    let s = Vector3::new(0.6, -0.3, 0.74);
    let shift = (s - x * s.dot(&x)).normalize() * distance;
    // The anchor stays the line's point nearest the origin: the shift is
    // perpendicular to the line, as the anchor is.
    let anchor = f.line.anchor() + shift;
    let z = anchor.normalize();
    let frame = Matrix3::from_columns(&[x, z.cross(&x), z]);
    f.line = FreeLine::new(So3::from_matrix(&frame).quaternion, anchor.norm());
    // X_B = C_BW (X_W − shift) + t_BW: the body sees the same scene.
    f.body_pose.translation -= f.body_pose.rotation.rotate(&shift);
    f
}
