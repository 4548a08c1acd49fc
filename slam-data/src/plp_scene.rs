//! Seeded point-line-plane scenes: a room or a corridor (a box of planes),
//! line segments on its walls, points on its planes and in its volume, a
//! camera trajectory inside it, the ground truth, perturbed initial values,
//! and noisy measurements of the kinds the documents' factors take.
//!
//! # Units and conventions
//!
//! - Metres, radians, pixels. World frame: z up, the box centred at the
//!   origin (`x ∈ [−L/2, L/2]`, `y ∈ [−W/2, W/2]`, `z ∈ [−H/2, H/2]`), so
//!   no plane and no line passes through the origin (where the orthonormal
//!   line is undefined).
//! - Cameras: world-to-camera poses `T` (`X_c = R X_w + t`, document 000),
//!   camera frame x right, y down, z forward; pinhole intrinsics `[f_u,
//!   f_v, c_u, c_v]`, pixel `[f_u X/Z + c_u, f_v Y/Z + c_v]` in an image of
//!   [`PlpConfig::image`] pixels (`u ∈ [0, width]`, `v ∈ [0, height]`).
//! - Planes: `π = [n, d]`, `n · x + d = 0`, `|n| = 1`, `n` pointing into the
//!   box. A camera measures a plane in its own frame, `π_c = T⁻ᵀ π_w` (so
//!   `Tᵀ π_c = π_w`, the documents' plane factor), with its normal turned
//!   by `Exp(σ_θ ξ)` and `d` moved by `σ_d ε` (ξ, ε standard normal), unit
//!   normal.
//! - Lines: segments with world endpoints; the infinite line through them is
//!   the landmark (Plücker `n = p × q`, `v = q − p`). A camera observes the
//!   part of a segment inside its image (clipped to the image and to depth
//!   ≥ [`NEAR`]) if it spans at least [`MIN_SEGMENT_PIXELS`]; the observation
//!   is the clipped endpoints' pixels plus Gaussian noise of `σ_px` per
//!   coordinate.
//! - Points: observed when in front (depth ≥ [`NEAR`]) and inside the
//!   image, pixel plus Gaussian noise of `σ_px` per coordinate.
//!
//! - Planes: measured by a camera that sees one of an 11 × 11 grid of
//!   points of the face.
//!
//! The box is convex and the cameras inside it, so nothing occludes a wall.
//! The same seed gives the same scene on every platform (ChaCha8).

use nalgebra::{
    Isometry3, Point3, Rotation3, Translation3, UnitQuaternion, Vector2, Vector3, Vector4,
};
use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;
use rand_distr::StandardNormal;

/// Nearest depth at which a camera observes anything (m).
pub const NEAR: f64 = 0.1;

/// Shortest image segment observed (px).
pub const MIN_SEGMENT_PIXELS: f64 = 20.0;

/// The layout of the scene.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Layout {
    /// Cameras on an ellipse around the box's centre (a fifth of its
    /// extent), each looking outward and turned 0.6 rad towards the next
    /// corner, 11–22° down, turning once around.
    Room,
    /// Cameras along the box's long axis (x), looking forward, 6–17° down.
    Corridor,
}

/// What to generate.
#[derive(Debug, Clone, PartialEq)]
pub struct PlpConfig {
    /// Seed of the random generator.
    pub seed: u64,
    /// The camera trajectory's shape.
    pub layout: Layout,
    /// Box size `[L, W, H]` (m): along x, y, z.
    pub size: [f64; 3],
    /// Number of cameras (at least 2).
    pub cameras: usize,
    /// Doors: three segments each (two jambs and a lintel, 0.9 × 2.1 m) on
    /// random walls.
    pub doors: usize,
    /// Further segments on random walls (horizontal or vertical, 0.5–2 m:
    /// shelves, frames).
    pub wall_segments: usize,
    /// Points on the planes (uniform over their rectangles).
    pub plane_points: usize,
    /// Points in the volume (uniform inside the box, 0.3 m from its faces).
    pub volume_points: usize,
    /// Intrinsics `[f_u, f_v, c_u, c_v]` (px).
    pub intrinsics: [f64; 4],
    /// Image size `[width, height]` (px).
    pub image: [f64; 2],
    /// Height of the cameras above the floor (m).
    pub eye_height: f64,
    /// Pixel noise of points and segment endpoints, per coordinate (px).
    pub pixel_sigma: f64,
    /// Plane measurement noise: normal rotation (rad, per axis).
    pub plane_angle_sigma: f64,
    /// Plane measurement noise: offset `d` (m).
    pub plane_offset_sigma: f64,
    /// Initial values: camera rotation perturbation (rad, per axis, left).
    pub rotation_sigma: f64,
    /// Initial values: perturbation of camera positions, points and segment
    /// endpoints (m, per axis).
    pub position_sigma: f64,
    /// Initial values: plane normal rotation (rad, per axis) and offset
    /// (m) perturbations.
    pub plane_sigma: [f64; 2],
}

impl PlpConfig {
    /// A 6 × 5 × 3 m room: 15 cameras, 2 doors, 12 wall segments (12 box
    /// edges too: 30 lines), 200 points on the planes and 100 in the
    /// volume; a 640 × 480 camera of 400 px focal length (77° × 62° field
    /// of view); 1 px noise, 0.01 rad and 0.02 m plane noise; initial values
    /// off by 0.02 rad, 0.05 m.
    pub fn room(seed: u64) -> Self {
        PlpConfig {
            seed,
            layout: Layout::Room,
            size: [6.0, 5.0, 3.0],
            cameras: 15,
            doors: 2,
            wall_segments: 12,
            plane_points: 200,
            volume_points: 100,
            intrinsics: [400.0, 400.0, 320.0, 240.0],
            image: [640.0, 480.0],
            eye_height: 1.5,
            pixel_sigma: 1.0,
            plane_angle_sigma: 0.01,
            plane_offset_sigma: 0.02,
            rotation_sigma: 0.02,
            position_sigma: 0.05,
            plane_sigma: [0.02, 0.05],
        }
    }

    /// A 20 × 2.5 × 3 m corridor walked along, with the room's other
    /// settings and 4 doors, 20 wall segments.
    pub fn corridor(seed: u64) -> Self {
        PlpConfig {
            layout: Layout::Corridor,
            size: [20.0, 2.5, 3.0],
            cameras: 20,
            doors: 4,
            wall_segments: 20,
            ..PlpConfig::room(seed)
        }
    }

    /// The same configuration without measurement noise (the initial values
    /// are still perturbed).
    pub fn noise_free(mut self) -> Self {
        self.pixel_sigma = 0.0;
        self.plane_angle_sigma = 0.0;
        self.plane_offset_sigma = 0.0;
        self
    }

    fn check(&self) -> Result<(), PlpError> {
        let fail = |what: String| Err(PlpError(what));
        if self.cameras < 2 {
            return fail(format!(
                "at least 2 cameras are needed, not {}",
                self.cameras
            ));
        }
        if !self.size.iter().all(|s| s.is_finite() && *s >= 2.0) {
            return fail(format!(
                "each side of the box must be at least 2 m, not {:?}",
                self.size
            ));
        }
        if !(self.eye_height > 0.2 && self.eye_height < self.size[2] - 0.2) {
            return fail(format!(
                "the eye height must be inside the box, 0.2 m from floor and ceiling, not {}",
                self.eye_height
            ));
        }
        let [fu, fv, cu, cv] = self.intrinsics;
        let [width, height] = self.image;
        if !(fu > 0.0
            && fv > 0.0
            && width > 0.0
            && height > 0.0
            && cu.is_finite()
            && cv.is_finite())
        {
            return fail("focal lengths and image size must be positive".into());
        }
        let sigmas = [
            self.pixel_sigma,
            self.plane_angle_sigma,
            self.plane_offset_sigma,
            self.rotation_sigma,
            self.position_sigma,
            self.plane_sigma[0],
            self.plane_sigma[1],
        ];
        if !sigmas.iter().all(|s| s.is_finite() && *s >= 0.0) {
            return fail("noise levels must be finite and not negative".into());
        }
        Ok(())
    }
}

/// Settings that cannot be generated.
#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error)]
#[error("point-line-plane scene: {0}")]
pub struct PlpError(pub String);

/// A line segment of the scene.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Segment {
    /// One endpoint (world).
    pub start: Vector3<f64>,
    /// The other endpoint (world).
    pub end: Vector3<f64>,
    /// The plane it lies on (an index into [`PlpState::planes`]).
    pub plane: usize,
}

/// A point seen by a camera.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct PointObservation {
    /// Index of the camera.
    pub camera: usize,
    /// Index of the point.
    pub point: usize,
    /// The measured pixel.
    pub pixel: Vector2<f64>,
}

/// A segment seen by a camera: the pixels of the ends of its visible part.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct SegmentObservation {
    /// Index of the camera.
    pub camera: usize,
    /// Index of the segment.
    pub segment: usize,
    /// Measured pixel of one end of the visible part.
    pub start: Vector2<f64>,
    /// Measured pixel of the other end.
    pub end: Vector2<f64>,
}

/// A plane measured by a camera, in the camera's frame.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct PlaneObservation {
    /// Index of the camera.
    pub camera: usize,
    /// Index of the plane.
    pub plane: usize,
    /// The measured plane `[n, d]` in the camera frame, unit normal.
    pub measured: Vector4<f64>,
}

/// The scene's landmarks and cameras (the truth, or initial values).
#[derive(Debug, Clone, PartialEq)]
pub struct PlpState {
    /// World-to-camera poses.
    pub cameras: Vec<Isometry3<f64>>,
    /// World points.
    pub points: Vec<Vector3<f64>>,
    /// Segments (their infinite lines are the line landmarks).
    pub segments: Vec<Segment>,
    /// World planes `[n, d]`, unit normal.
    pub planes: Vec<Vector4<f64>>,
}

/// A generated scene.
#[derive(Debug, Clone, PartialEq)]
pub struct PlpScene {
    /// What it was generated from.
    pub config: PlpConfig,
    /// The ground truth.
    pub truth: PlpState,
    /// The truth perturbed as [`PlpConfig`] says: where a solver starts.
    pub initial: PlpState,
    /// Point measurements.
    pub point_observations: Vec<PointObservation>,
    /// Segment measurements.
    pub segment_observations: Vec<SegmentObservation>,
    /// Plane measurements.
    pub plane_observations: Vec<PlaneObservation>,
}

/// Generates the scene `config` describes.
pub fn generate(config: &PlpConfig) -> Result<PlpScene, PlpError> {
    config.check()?;
    let mut rng = ChaCha8Rng::seed_from_u64(config.seed);
    let half = Vector3::from(config.size) / 2.0;
    let planes = box_planes(&half);
    let mut segments = box_edges(&half);
    for _ in 0..config.doors {
        segments.extend(door(&half, &mut rng));
    }
    for _ in 0..config.wall_segments {
        segments.push(wall_segment(&half, &mut rng));
    }
    let mut points: Vec<Vector3<f64>> = (0..config.plane_points)
        .map(|_| point_on_face(&half, rng.random_range(0..6), &mut rng))
        .collect();
    points.extend(
        (0..config.volume_points)
            .map(|_| Vector3::from_fn(|i, _| rng.random_range(-(half[i] - 0.3)..(half[i] - 0.3)))),
    );
    let cameras: Vec<Isometry3<f64>> = (0..config.cameras)
        .map(|i| camera(config, &half, i, &mut rng))
        .collect();
    let truth = PlpState {
        cameras,
        points,
        segments,
        planes,
    };
    let mut scene = PlpScene {
        config: config.clone(),
        initial: truth.clone(),
        truth,
        point_observations: Vec::new(),
        segment_observations: Vec::new(),
        plane_observations: Vec::new(),
    };
    observe(&mut scene, &mut rng);
    scene.initial = perturbed(&scene.truth, config, &mut rng);
    Ok(scene)
}

/// The six faces, normals inward: floor, ceiling, −x, +x, −y, +y walls.
fn box_planes(half: &Vector3<f64>) -> Vec<Vector4<f64>> {
    let mut planes = Vec::with_capacity(6);
    for axis in [2, 0, 1] {
        for sign in [1.0, -1.0] {
            // The face at −sign · half[axis], normal sign · e_axis inward:
            // n · x + half[axis] = 0.
            let mut p = Vector4::zeros();
            p[axis] = sign;
            p[3] = half[axis];
            planes.push(p);
        }
    }
    planes
}

/// The face index of [`box_planes`] for `axis` and side (`true`: the
/// negative side, normal `+e_axis`).
fn face(axis: usize, negative_side: bool) -> usize {
    let base = match axis {
        2 => 0,
        0 => 2,
        _ => 4,
    };
    base + usize::from(!negative_side)
}

/// The twelve edges of the box, each on one of the faces it bounds.
fn box_edges(half: &Vector3<f64>) -> Vec<Segment> {
    let mut edges = Vec::with_capacity(12);
    for axis in 0..3 {
        let (a, b) = ((axis + 1) % 3, (axis + 2) % 3);
        for (sa, sb) in [(-1.0, -1.0), (1.0, -1.0), (-1.0, 1.0), (1.0, 1.0)] {
            let mut start = Vector3::zeros();
            start[a] = sa * half[a];
            start[b] = sb * half[b];
            let mut end = start;
            start[axis] = -half[axis];
            end[axis] = half[axis];
            edges.push(Segment {
                start,
                end,
                plane: face(a, sa < 0.0),
            });
        }
    }
    edges
}

/// A wall: its axis (0 or 1) and side.
fn random_wall(rng: &mut ChaCha8Rng) -> (usize, bool) {
    (rng.random_range(0..2), rng.random_bool(0.5))
}

/// A point of the wall `(axis, side)` at `along` its horizontal direction
/// and height `z`.
fn on_wall(
    half: &Vector3<f64>,
    (axis, negative): (usize, bool),
    along: f64,
    z: f64,
) -> Vector3<f64> {
    let mut p = Vector3::zeros();
    p[axis] = if negative { -half[axis] } else { half[axis] };
    p[1 - axis] = along;
    p[2] = z;
    p
}

/// A door on a random wall: two jambs and a lintel.
fn door(half: &Vector3<f64>, rng: &mut ChaCha8Rng) -> [Segment; 3] {
    let wall = random_wall(rng);
    let (width, height) = (0.9, 2.1_f64.min(2.0 * half[2] - 0.3));
    let room = half[1 - wall.0] - width / 2.0 - 0.1;
    let centre = rng.random_range(-room..room);
    let (floor, top) = (-half[2], -half[2] + height);
    let corner = |along: f64, z: f64| on_wall(half, wall, along, z);
    let (left, right) = (centre - width / 2.0, centre + width / 2.0);
    let plane = face(wall.0, wall.1);
    [
        Segment {
            start: corner(left, floor),
            end: corner(left, top),
            plane,
        },
        Segment {
            start: corner(right, floor),
            end: corner(right, top),
            plane,
        },
        Segment {
            start: corner(left, top),
            end: corner(right, top),
            plane,
        },
    ]
}

/// A horizontal or vertical segment of 0.5–2 m on a random wall, 0.2 m
/// inside its edges.
fn wall_segment(half: &Vector3<f64>, rng: &mut ChaCha8Rng) -> Segment {
    let wall = random_wall(rng);
    let (across, up) = (half[1 - wall.0] - 0.2, half[2] - 0.2);
    let length: f64 = rng.random_range(0.5..2.0);
    let plane = face(wall.0, wall.1);
    if rng.random_bool(0.5) {
        let length = length.min(2.0 * across - 0.1);
        let start = rng.random_range(-across..(across - length));
        let z = rng.random_range(-up..up);
        Segment {
            start: on_wall(half, wall, start, z),
            end: on_wall(half, wall, start + length, z),
            plane,
        }
    } else {
        let length = length.min(2.0 * up - 0.1);
        let start = rng.random_range(-up..(up - length));
        let along = rng.random_range(-across..across);
        Segment {
            start: on_wall(half, wall, along, start),
            end: on_wall(half, wall, along, start + length),
            plane,
        }
    }
}

/// A point uniform on face `index` of [`box_planes`].
fn point_on_face(half: &Vector3<f64>, index: usize, rng: &mut ChaCha8Rng) -> Vector3<f64> {
    let axis = [2, 2, 0, 0, 1, 1][index];
    let mut p = Vector3::from_fn(|i, _| rng.random_range(-half[i]..half[i]));
    p[axis] = if index.is_multiple_of(2) {
        -half[axis]
    } else {
        half[axis]
    };
    p
}

/// Camera `i`: its centre and a view direction, then a small random roll,
/// as a world-to-camera pose.
fn camera(
    config: &PlpConfig,
    half: &Vector3<f64>,
    i: usize,
    rng: &mut ChaCha8Rng,
) -> Isometry3<f64> {
    let z = -half[2] + config.eye_height;
    let s = i as f64 / config.cameras as f64;
    let (centre, forward) = match config.layout {
        Layout::Room => {
            let angle = std::f64::consts::TAU * s;
            let centre = Vector3::new(0.2 * half[0] * angle.cos(), 0.2 * half[1] * angle.sin(), z);
            // Outward and turned towards the next corner.
            let yaw = angle + 0.6 + rng.random_range(-0.2..0.2);
            (
                centre,
                Vector3::new(yaw.cos(), yaw.sin(), rng.random_range(-0.4..-0.2)),
            )
        }
        Layout::Corridor => {
            let x = -half[0] + 1.0 + (2.0 * half[0] - 4.0) * s;
            let centre = Vector3::new(x, rng.random_range(-0.2..0.2) * half[1], z);
            let yaw: f64 = rng.random_range(-0.25..0.25);
            (
                centre,
                Vector3::new(yaw.cos(), yaw.sin(), rng.random_range(-0.3..-0.1)),
            )
        }
    };
    // Camera z forward, y down (world z up), then a roll about the view.
    let view = Rotation3::face_towards(&forward, &-Vector3::z());
    let roll = Rotation3::from_axis_angle(&Vector3::z_axis(), rng.random_range(-0.05..0.05));
    let camera_to_world = Isometry3::from_parts(
        Translation3::from(centre),
        UnitQuaternion::from_rotation_matrix(&(view * roll)),
    );
    camera_to_world.inverse()
}

/// The pixel of a camera-frame point (no depth check).
fn project(k: &[f64; 4], p: &Vector3<f64>) -> Vector2<f64> {
    Vector2::new(k[0] * p.x / p.z + k[2], k[1] * p.y / p.z + k[3])
}

/// The part `[t₀, t₁] ⊂ [0, 1]` of the camera-frame segment `a + t (b − a)`
/// in front (depth ≥ [`NEAR`]) and inside the image, if any: each bound is
/// a half-space `g · (x, y, z) ≥ 0`, linear in `t` (Liang–Barsky).
fn clip(k: &[f64; 4], image: &[f64; 2], a: &Vector3<f64>, b: &Vector3<f64>) -> Option<(f64, f64)> {
    let [fu, fv, cu, cv] = *k;
    let [width, height] = *image;
    // u ≥ 0: fu x + cu z ≥ 0; u ≤ W: (W − cu) z − fu x ≥ 0; same for v.
    let bounds = [
        (Vector3::new(fu, 0.0, cu), 0.0),
        (Vector3::new(-fu, 0.0, width - cu), 0.0),
        (Vector3::new(0.0, fv, cv), 0.0),
        (Vector3::new(0.0, -fv, height - cv), 0.0),
        (Vector3::z(), -NEAR),
    ];
    let (mut t0, mut t1) = (0.0_f64, 1.0_f64);
    for (g, c) in bounds {
        let (at_a, slope) = (g.dot(a) + c, g.dot(&(b - a)));
        if slope == 0.0 {
            if at_a < 0.0 {
                return None;
            }
        } else if slope > 0.0 {
            t0 = t0.max(-at_a / slope);
        } else {
            t1 = t1.min(-at_a / slope);
        }
    }
    (t0 < t1).then_some((t0, t1))
}

fn gaussian2(rng: &mut ChaCha8Rng) -> Vector2<f64> {
    Vector2::from_fn(|_, _| rng.sample(StandardNormal))
}

fn gaussian3(rng: &mut ChaCha8Rng) -> Vector3<f64> {
    Vector3::from_fn(|_, _| rng.sample(StandardNormal))
}

/// The measurements of every camera, in camera order.
fn observe(scene: &mut PlpScene, rng: &mut ChaCha8Rng) {
    let config = &scene.config;
    let (k, image) = (&config.intrinsics, &config.image);
    let inside =
        |p: &Vector2<f64>| (0.0..=image[0]).contains(&p.x) && (0.0..=image[1]).contains(&p.y);
    let truth = &scene.truth;
    let half = Vector3::from(config.size) / 2.0;
    for (c, pose) in truth.cameras.iter().enumerate() {
        for (j, point) in truth.points.iter().enumerate() {
            let p = pose * Point3::from(*point);
            if p.z >= NEAR && inside(&project(k, &p.coords)) {
                let pixel = project(k, &p.coords) + gaussian2(rng) * config.pixel_sigma;
                scene.point_observations.push(PointObservation {
                    camera: c,
                    point: j,
                    pixel,
                });
            }
        }
        for (j, segment) in truth.segments.iter().enumerate() {
            let (a, b) = (
                (pose * Point3::from(segment.start)).coords,
                (pose * Point3::from(segment.end)).coords,
            );
            let Some((t0, t1)) = clip(k, image, &a, &b) else {
                continue;
            };
            let (start, end) = (
                project(k, &(a + (b - a) * t0)),
                project(k, &(a + (b - a) * t1)),
            );
            if (end - start).norm() >= MIN_SEGMENT_PIXELS {
                scene.segment_observations.push(SegmentObservation {
                    camera: c,
                    segment: j,
                    start: start + gaussian2(rng) * config.pixel_sigma,
                    end: end + gaussian2(rng) * config.pixel_sigma,
                });
            }
        }
        for (j, plane) in truth.planes.iter().enumerate() {
            // Seen when one of an 11 × 11 grid of the face's points is.
            let axis = [2, 2, 0, 0, 1, 1][j];
            let (u, v) = ((axis + 1) % 3, (axis + 2) % 3);
            let seen = (0..121).any(|g| {
                let mut q = Vector3::zeros();
                q[axis] = -plane[3] * plane[axis];
                q[u] = half[u] * ((g % 11) as f64 / 5.0 - 1.0) * 0.98;
                q[v] = half[v] * ((g / 11) as f64 / 5.0 - 1.0) * 0.98;
                let p = pose * Point3::from(q);
                p.z >= NEAR && inside(&project(k, &p.coords))
            });
            if seen {
                let exact = plane_in_camera(pose, plane);
                let turn = Rotation3::new(gaussian3(rng) * config.plane_angle_sigma);
                let normal = turn * exact.xyz();
                let offset =
                    exact.w + rng.sample::<f64, _>(StandardNormal) * config.plane_offset_sigma;
                scene.plane_observations.push(PlaneObservation {
                    camera: c,
                    plane: j,
                    measured: Vector4::new(normal.x, normal.y, normal.z, offset),
                });
            }
        }
    }
}

/// The world plane `[n, d]` in the frame of the world-to-camera `pose`,
/// `T⁻ᵀ π`: `[R n, d − (R n) · t]`.
pub fn plane_in_camera(pose: &Isometry3<f64>, plane: &Vector4<f64>) -> Vector4<f64> {
    let n = pose.rotation * plane.xyz();
    Vector4::new(n.x, n.y, n.z, plane.w - n.dot(&pose.translation.vector))
}

/// The truth perturbed as `config` says.
fn perturbed(truth: &PlpState, config: &PlpConfig, rng: &mut ChaCha8Rng) -> PlpState {
    let cameras = truth
        .cameras
        .iter()
        .map(|pose| {
            // Left rotation about the camera's centre, centre moved.
            let centre = pose.inverse().translation.vector + gaussian3(rng) * config.position_sigma;
            let rotation = UnitQuaternion::from_scaled_axis(gaussian3(rng) * config.rotation_sigma)
                * pose.rotation;
            Isometry3::from_parts(Translation3::from(-(rotation * centre)), rotation)
        })
        .collect();
    let points = truth
        .points
        .iter()
        .map(|p| p + gaussian3(rng) * config.position_sigma)
        .collect();
    let segments = truth
        .segments
        .iter()
        .map(|s| Segment {
            start: s.start + gaussian3(rng) * config.position_sigma,
            end: s.end + gaussian3(rng) * config.position_sigma,
            plane: s.plane,
        })
        .collect();
    let planes = truth
        .planes
        .iter()
        .map(|p| {
            let n = Rotation3::new(gaussian3(rng) * config.plane_sigma[0]) * p.xyz();
            let d = p.w + rng.sample::<f64, _>(StandardNormal) * config.plane_sigma[1];
            Vector4::new(n.x, n.y, n.z, d)
        })
        .collect();
    PlpState {
        cameras,
        points,
        segments,
        planes,
    }
}
