//! Configurations of g2o's edge errors ([`slam_factors::g2o`]), with pose
//! quaternions as g2o's six-digit files hold them: unit only to about 1e-6.

use nalgebra::{Vector3, Vector4, Vector6};

use factor_core::geometry::plane::transpose_transform;
use factor_core::geometry::{InfinitePlane, OrthonormalLine, PluckerLine};
use factor_core::lie::{Quaternion, Se3, Se3RhoTheta, So3};
use factor_core::{Factor, Manifold, Perturbation};
use slam_factors::{
    G2oLineEdge, G2oPlaneEdge, G2oPointEdge, G2oPriorEdge, G2oSe3Edge, LineObservation,
};

use super::Sampler;

impl Sampler {
    /// `pose` with its quaternion scaled by `1 + u`, `|u| < 1e-6`: what
    /// reading six significant digits leaves.
    pub fn as_written(&mut self, pose: Se3<f64>) -> Se3<f64> {
        let scale = 1.0 + self.uniform(-1e-6, 1e-6);
        let q = pose.rotation.quaternion.coords() * scale;
        Se3::new(
            So3::from_quaternion(Quaternion::from_coords(q)),
            pose.translation,
        )
    }

    /// A g2o pose edge: two poses and their relative pose moved by `Exp` of
    /// a step of up to `max_error` per coordinate, quaternions as written.
    pub fn g2o_se3_with_error(&mut self, max_error: f64) -> G2oSe3Edge {
        let (pose_i, pose_j) = (self.pose(), self.pose());
        let step = Vector6::from_fn(|_, _| self.uniform(-max_error, max_error));
        let measured = pose_i.inverse().compose(&pose_j).compose(&Se3::exp(&step));
        G2oSe3Edge {
            measured: self.as_written(measured),
            pose_i: Se3RhoTheta::new(self.as_written(pose_i)),
            pose_j: Se3RhoTheta::new(self.as_written(pose_j)),
        }
    }

    /// A g2o pose edge with an error of up to 0.3 per coordinate.
    pub fn g2o_se3(&mut self) -> G2oSe3Edge {
        self.g2o_se3_with_error(0.3)
    }

    /// A g2o line edge: a segment in view of the robot (its line at least
    /// 0.2 m from the robot's origin), the world line it is, and as the
    /// measurement the robot-frame line moved by up to `max_error` in each
    /// coordinate of the orthonormal line's tangent, written as `[w, d]`
    /// with a unit direction.
    pub fn g2o_line_with_error(&mut self, max_error: f64) -> G2oLineEdge {
        loop {
            let pose = self.pose();
            let pose = self.as_written(pose);
            let (p, q) = self.segment_in_view();
            let local = PluckerLine::from_points(&p, &q);
            let line = OrthonormalLine::from_plucker(&local.transform(&pose));
            let step: Vec<f64> = (0..4)
                .map(|_| self.uniform(-max_error, max_error))
                .collect();
            let noisy = OrthonormalLine::from_plucker(&local)
                .retract(&step, Perturbation::Right)
                .to_plucker();
            let scale = noisy.direction.norm().recip();
            let (w, d) = (noisy.normal * scale, noisy.direction * scale);
            let factor = G2oLineEdge {
                measured: Vector6::new(w.x, w.y, w.z, d.x, d.y, d.z),
                pose: Se3RhoTheta::new(pose),
                line,
            };
            if factor.validate().is_ok() {
                return factor;
            }
        }
    }

    /// A g2o line edge with an error of up to 0.05 per coordinate.
    pub fn g2o_line(&mut self) -> G2oLineEdge {
        self.g2o_line_with_error(0.05)
    }

    /// A g2o plane edge: a robot pose, a sensor offset within 1 m, a plane
    /// 1–10 m from the sensor whose normal is at least 17° from the
    /// sensor's z axis, and as the measurement the sensor-frame plane with
    /// its normal rotated by up to `max_error` radians and its offset moved
    /// by up to `max_error` metres, written at a scale in `[0.5, 2)`.
    pub fn g2o_plane_with_error(&mut self, max_error: f64) -> G2oPlaneEdge {
        loop {
            let pose = self.pose();
            let pose = self.as_written(pose);
            let offset = Se3::new(self.rotation(), self.vector3(1.0));
            let offset = self.as_written(offset);
            let normal = self.rotation().rotate(&Vector3::z());
            if normal.xy().norm() < 0.3 {
                continue;
            }
            let pi_s = Vector4::new(normal.x, normal.y, normal.z, self.uniform(1.0, 10.0));
            let to_sensor = pose.compose(&offset).inverse();
            let pi_w = transpose_transform(&to_sensor, &pi_s);
            let noisy = self.small_rotation(max_error).rotate(&normal);
            let d = pi_s.w + self.uniform(-max_error, max_error);
            let scale = self.uniform(0.5, 2.0);
            let factor = G2oPlaneEdge {
                measured: Vector4::new(noisy.x, noisy.y, noisy.z, d) * scale,
                pose: Se3RhoTheta::new(pose),
                plane: InfinitePlane::from_coefficients(&pi_w),
                offset: Se3RhoTheta::new(offset),
            };
            if factor.validate().is_ok() {
                return factor;
            }
        }
    }

    /// A g2o plane edge with an error of up to 0.1.
    pub fn g2o_plane(&mut self) -> G2oPlaneEdge {
        self.g2o_plane_with_error(0.1)
    }
}

impl Sampler {
    /// A g2o pose prior: a robot pose, a sensor offset within 1 m, and as
    /// the measurement the world-from-sensor pose moved by `Exp` of a step
    /// of up to `max_error` per coordinate, quaternions as written.
    pub fn g2o_prior_with_error(&mut self, max_error: f64) -> G2oPriorEdge {
        let pose = self.pose();
        let offset = Se3::new(self.rotation(), self.vector3(1.0));
        let step = Vector6::from_fn(|_, _| self.uniform(-max_error, max_error));
        let measured = pose.compose(&offset).compose(&Se3::exp(&step));
        G2oPriorEdge {
            measured: self.as_written(measured),
            offset: self.as_written(offset),
            pose: Se3RhoTheta::new(self.as_written(pose)),
        }
    }

    /// A g2o pose prior with an error of up to 0.3 per coordinate.
    pub fn g2o_prior(&mut self) -> G2oPriorEdge {
        self.g2o_prior_with_error(0.3)
    }

    /// A g2o point edge: a robot pose, a sensor offset within 1 m, a point
    /// within 5 m of the sensor, and as the measurement the point in the
    /// sensor frame moved by up to `max_error` per coordinate, quaternions
    /// as written.
    pub fn g2o_point_with_error(&mut self, max_error: f64) -> G2oPointEdge {
        let pose = self.pose();
        let offset = Se3::new(self.rotation(), self.vector3(1.0));
        let in_sensor = self.vector3(5.0);
        let point = pose.compose(&offset).transform_point(&in_sensor);
        let noise = Vector3::from_fn(|_, _| self.uniform(-max_error, max_error));
        G2oPointEdge {
            measured: in_sensor + noise,
            offset: self.as_written(offset),
            pose: Se3RhoTheta::new(self.as_written(pose)),
            point,
        }
    }

    /// A g2o point edge with an error of up to 0.3 per coordinate.
    pub fn g2o_point(&mut self) -> G2oPointEdge {
        self.g2o_point_with_error(0.3)
    }
}

impl Sampler {
    /// A 3D line observation: a world-to-camera pose, a segment in view
    /// (its line at least 0.2 m from the optical centre), and as the
    /// measurement the camera-frame line moved by up to `max_error` in each
    /// coordinate of the orthonormal line's right tangent.
    pub fn line_observation_with_error(&mut self, max_error: f64) -> LineObservation {
        let pose = self.pose();
        let (p, q) = self.segment_in_view();
        let local = OrthonormalLine::from_plucker(&PluckerLine::from_points(&p, &q));
        let world = pose.inverse();
        let line = OrthonormalLine::from_plucker(&PluckerLine::from_points(
            &world.transform_point(&p),
            &world.transform_point(&q),
        ));
        let step: Vec<f64> = (0..4)
            .map(|_| self.uniform(-max_error, max_error))
            .collect();
        LineObservation {
            measured: local.retract(&step, Perturbation::Right),
            pose,
            line,
        }
    }

    /// A 3D line observation with an error of up to 0.1 per coordinate.
    pub fn line_observation(&mut self) -> LineObservation {
        self.line_observation_with_error(0.1)
    }
}
