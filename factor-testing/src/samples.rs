//! Well-conditioned random configurations of the shipped factors, for tests,
//! benchmarks and audits.
//!
//! Every sample is built from what a camera would see: landmarks are drawn in
//! the camera frame in front of it (depth 1–10 m, inside a ±31° field of view)
//! and mapped to the world through a random pose, and the measurements are
//! their exact projections plus small noise, so the residuals are realistic
//! (a few pixels, a few degrees) and no configuration is near a degeneracy.
//! Samples are reproducible from a seed.

mod g2o;

use nalgebra::{Matrix3, Matrix6, Unit, Vector2, Vector3, Vector4, Vector6};
use rand::rngs::StdRng;
use rand::{Rng, SeedableRng};

use factor_core::geometry::plane::transpose_transform;
use factor_core::geometry::{FreeLine, InfinitePlane, Intrinsics, OrthonormalLine, PluckerLine};
use factor_core::lie::{Quaternion, Se3, Se3RhoTheta, So3};
use slam_factors::{
    BetweenFactor, FreeLineFactor, LineReprojection, PlaneFactor, PluckerLineReprojection,
    PointReprojection, RadialIntrinsics, SnavelyReprojection, SqrtInformation6, StereoIntrinsics,
    StereoReprojection,
};

/// A seeded random source of configurations.
pub struct Sampler {
    rng: StdRng,
}

impl Sampler {
    /// A sampler whose sequence is fixed by `seed`.
    pub fn new(seed: u64) -> Self {
        Sampler {
            rng: StdRng::seed_from_u64(seed),
        }
    }

    /// Uniform in `[lo, hi)`; `lo` when the range is empty.
    pub fn uniform(&mut self, lo: f64, hi: f64) -> f64 {
        if lo < hi {
            self.rng.random_range(lo..hi)
        } else {
            lo
        }
    }

    /// Each coordinate uniform in `[−r, r)`.
    pub fn vector3(&mut self, r: f64) -> Vector3<f64> {
        Vector3::new(
            self.uniform(-r, r),
            self.uniform(-r, r),
            self.uniform(-r, r),
        )
    }

    /// A rotation uniformly distributed on SO(3) (a uniform point of the unit
    /// 4-ball's shell, by rejection).
    pub fn rotation(&mut self) -> So3<f64> {
        loop {
            let c = Vector4::new(
                self.uniform(-1.0, 1.0),
                self.uniform(-1.0, 1.0),
                self.uniform(-1.0, 1.0),
                self.uniform(-1.0, 1.0),
            );
            let n = c.norm();
            if (0.1..1.0).contains(&n) {
                return So3::from_quaternion(Quaternion::from_coords(c / n));
            }
        }
    }

    /// A rotation by an angle below `max_angle` about a random axis.
    pub fn small_rotation(&mut self, max_angle: f64) -> So3<f64> {
        let axis = loop {
            let a = self.vector3(1.0);
            if (0.1..1.0).contains(&a.norm()) {
                break a.normalize();
            }
        };
        So3::exp(&(axis * self.uniform(0.0, max_angle)))
    }

    /// A pose with a uniform rotation and a translation in `[−2, 2)³` metres.
    pub fn pose(&mut self) -> Se3<f64> {
        let rotation = self.rotation();
        Se3::new(rotation, self.vector3(2.0))
    }

    /// Intrinsics of a VGA-like camera.
    pub fn intrinsics(&mut self) -> Intrinsics<f64> {
        Intrinsics::new(
            self.uniform(400.0, 600.0),
            self.uniform(400.0, 600.0),
            self.uniform(300.0, 340.0),
            self.uniform(220.0, 260.0),
        )
    }

    /// A camera-frame point in front of the camera, inside the field of view.
    pub fn point_in_view(&mut self) -> Vector3<f64> {
        let z = self.uniform(1.0, 10.0);
        Vector3::new(z * self.uniform(-0.6, 0.6), z * self.uniform(-0.6, 0.6), z)
    }

    /// A point reprojection factor: the observation is the projection plus up
    /// to 3 px of noise.
    pub fn point_reprojection(&mut self) -> PointReprojection {
        let intrinsics = self.intrinsics();
        let pose = self.pose();
        let p_c = self.point_in_view();
        let observed = intrinsics.project(&p_c)
            + Vector2::new(self.uniform(-3.0, 3.0), self.uniform(-3.0, 3.0));
        PointReprojection {
            intrinsics,
            observed,
            pose,
            point: pose.inverse().transform_point(&p_c),
        }
    }

    /// Two camera-frame points in view whose line passes at least 0.2 m from
    /// the optical centre and which are at least 0.5 m apart.
    fn segment_in_view(&mut self) -> (Vector3<f64>, Vector3<f64>) {
        loop {
            let (p, q) = (self.point_in_view(), self.point_in_view());
            let line = PluckerLine::from_points(&p, &q);
            if (q - p).norm() > 0.5 && line.normal.norm() / line.direction.norm() > 0.2 {
                return (p, q);
            }
        }
    }

    /// A line reprojection factor: the observed endpoints are the projections
    /// of the segment's endpoints plus up to 2 px of noise.
    pub fn line_reprojection(&mut self) -> LineReprojection {
        let intrinsics = self.intrinsics();
        let pose = self.pose();
        let (p_c, q_c) = self.segment_in_view();
        let world = pose.inverse();
        let line_w =
            PluckerLine::from_points(&world.transform_point(&p_c), &world.transform_point(&q_c));
        let noise = |s: &mut Self| Vector2::new(s.uniform(-2.0, 2.0), s.uniform(-2.0, 2.0));
        LineReprojection {
            intrinsics,
            start: intrinsics.project(&p_c) + noise(self),
            end: intrinsics.project(&q_c) + noise(self),
            pose,
            line: OrthonormalLine::from_plucker(&line_w),
        }
    }

    /// The line reprojection factor over raw Plücker coordinates, with the
    /// world line scaled by a factor in `[0.5, 2)`.
    pub fn plucker_line_reprojection(&mut self) -> PluckerLineReprojection {
        let f = self.line_reprojection();
        let line = f.line.to_plucker();
        let scale = self.uniform(0.5, 2.0);
        PluckerLineReprojection {
            intrinsics: f.intrinsics,
            start: f.start,
            end: f.end,
            pose: f.pose,
            line: PluckerLine::new(line.normal * scale, line.direction * scale),
        }
    }

    /// A plane factor: the measured camera-frame plane is the landmark seen
    /// from the pose, rotated by up to `max_error` radians on the quaternion
    /// sphere (drawn at a scale in `[0.5, 3)`, stored at unit norm).
    pub fn plane_with_error(&mut self, max_error: f64) -> PlaneFactor {
        let pose = self.pose();
        let normal = self.rotation().rotate(&Vector3::z());
        let pi_w = Vector4::new(normal.x, normal.y, normal.z, self.uniform(-5.0, 5.0));
        // π_c = T⁻ᵀ π_w, so that Tᵀ π_c = π_w.
        let pi_c = transpose_transform(&pose.inverse(), &pi_w);
        let noisy = self
            .small_rotation(max_error)
            .quaternion
            .mul(&Quaternion::from_coords(pi_c.normalize()));
        PlaneFactor {
            // Given at a random scale, stored at unit norm.
            measured: Unit::new_normalize(noisy.coords() * self.uniform(0.5, 3.0)),
            pose,
            plane: InfinitePlane::from_coefficients(&pi_w),
        }
    }

    /// A plane factor with an error of up to 0.3 rad.
    pub fn plane(&mut self) -> PlaneFactor {
        self.plane_with_error(0.3)
    }

    /// A free-line factor: a body pose, camera extrinsics within 0.3 m of the
    /// body, a segment in view of the camera, and bearing vectors through its
    /// endpoints with up to 1 cm of noise at the points.
    pub fn free_line(&mut self) -> FreeLineFactor {
        loop {
            let body_pose = self.pose();
            let extrinsics = Se3::new(self.rotation(), self.vector3(0.3));
            let camera = extrinsics.compose(&body_pose); // T_CW = T_CB T_BW
            let (p_c, q_c) = self.segment_in_view();
            let world = camera.inverse();
            let (p, q) = (world.transform_point(&p_c), world.transform_point(&q_c));
            let x = (q - p).normalize();
            let anchor = p - x * p.dot(&x);
            let d = anchor.norm();
            if d < 0.05 || (world.translation - anchor).norm() < 0.3 {
                continue;
            }
            let z = anchor / d;
            let frame = Matrix3::from_columns(&[x, z.cross(&x), z]);
            let line = FreeLine::new(So3::from_matrix(&frame).quaternion, d);
            let bearing_start = Unit::new_normalize(p_c + self.vector3(0.01));
            let bearing_end = Unit::new_normalize(q_c + self.vector3(0.01));
            return FreeLineFactor {
                extrinsics,
                bearing_start,
                bearing_end,
                body_pose,
                line,
            };
        }
    }

    /// A BAL / Bundler observation: a world-to-camera pose, `f` in
    /// `[400, 1200)` px, `k1` in `[−0.2, 0.2)`, `k2` in `[−0.05, 0.05)` (the
    /// radial map stays increasing inside the view), a point 1–10 m in front
    /// of the camera (which looks down −z) inside a ±31° view, and the
    /// observation its pixel plus up to 3 px of noise.
    pub fn snavely_reprojection(&mut self) -> SnavelyReprojection {
        let pose = self.pose();
        let intrinsics = RadialIntrinsics::new(
            self.uniform(400.0, 1200.0),
            self.uniform(-0.2, 0.2),
            self.uniform(-0.05, 0.05),
        );
        // `point_in_view` looks down +z; the Snavely camera looks down −z.
        let p_c = self
            .point_in_view()
            .component_mul(&Vector3::new(1.0, 1.0, -1.0));
        let p = -p_c.xy() / p_c.z;
        let pixel = p * (intrinsics.focal * intrinsics.radial_factor(p.norm_squared()));
        SnavelyReprojection {
            observed: pixel + Vector2::new(self.uniform(-3.0, 3.0), self.uniform(-3.0, 3.0)),
            pose: Se3RhoTheta::new(pose),
            intrinsics,
            point: pose.inverse().transform_point(&p_c),
        }
    }

    /// A stereo observation: a KITTI-like rig (`fx`, `fy` in `[600, 800)`,
    /// skew within ±1, baseline 0.1–0.6 m), a camera-to-world pose, a landmark
    /// in view 1–10 m ahead, and its `[u_L, u_R, v]` plus up to 2 px of noise.
    pub fn stereo_reprojection(&mut self) -> StereoReprojection {
        let calibration = StereoIntrinsics::new(
            self.uniform(600.0, 800.0),
            self.uniform(600.0, 800.0),
            self.uniform(-1.0, 1.0),
            self.uniform(300.0, 340.0),
            self.uniform(220.0, 260.0),
            self.uniform(0.1, 0.6),
        );
        let pose = self.pose();
        let p_c = self.point_in_view();
        let noise = Vector3::new(
            self.uniform(-2.0, 2.0),
            self.uniform(-2.0, 2.0),
            self.uniform(-2.0, 2.0),
        );
        StereoReprojection {
            calibration,
            observed: calibration.project(&p_c) + noise,
            pose: Se3RhoTheta::new(pose),
            landmark: pose.transform_point(&p_c),
        }
    }

    /// A pose-graph edge whose measurement is the true relative pose moved
    /// by `Exp` of a step of up to `max_error` (radians and metres, per
    /// coordinate), with a random information matrix: `B Bᵀ + D`, `B` entries
    /// in `[−1, 1)`, `D` diagonal with entries in `[1, 100)`.
    pub fn between_with_error(&mut self, max_error: f64) -> BetweenFactor {
        let (pose_i, pose_j) = (self.pose(), self.pose());
        let step = Vector6::from_fn(|_, _| self.uniform(-max_error, max_error));
        let measured = pose_i.inverse().compose(&pose_j).compose(&Se3::exp(&step));
        let b = Matrix6::from_fn(|_, _| self.uniform(-1.0, 1.0));
        let d = Vector6::from_fn(|_, _| self.uniform(1.0, 100.0));
        let information = b * b.transpose() + Matrix6::from_diagonal(&d);
        BetweenFactor {
            sqrt_information: SqrtInformation6::from_information(&information)
                .expect("B Bᵀ + D is positive definite"),
            measured,
            pose_i: Se3RhoTheta::new(pose_i),
            pose_j: Se3RhoTheta::new(pose_j),
        }
    }

    /// A pose-graph edge with an error of up to 0.3 per coordinate.
    pub fn between(&mut self) -> BetweenFactor {
        self.between_with_error(0.3)
    }
}
