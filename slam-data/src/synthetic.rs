//! Seeded synthetic bundle-adjustment problems, in the BAL camera model.
//!
//! The scene: `cameras` cameras evenly spaced on a ring of radius
//! [`RING_RADIUS`] (heights varying by ±[`RING_HEIGHT`]), each looking at the
//! centre (aim jittered uniformly within ±[`AIM_JITTER`] per axis), and
//! `points` points uniform in a ball of radius [`SCENE_RADIUS`] at the
//! centre, so every point is in front of every camera and inside its image.
//! Image [`IMAGE_WIDTH`] × [`IMAGE_HEIGHT`] pixels (BAL pixels: origin at
//! the centre, y up); focal length uniform in [800, 1200] px, k1 uniform
//! in [−0.15, −0.05], k2 uniform in [−0.05, 0.05].
//!
//! Each point is seen by `views_per_point` cameras of the ring starting at a
//! uniformly drawn one, with a stride that spreads them over about 60° of
//! the ring ([`Visibility::Ring`]: every camera shares points with cameras
//! all around the ring). With [`Visibility::Local`], as in a real
//! reconstruction from a sequence, each point is seen by consecutive
//! cameras and lies near them: in front of the middle one of its views, at
//! a distance of about twice the baseline its views span (so that they
//! see it about 28° apart, at most the ring radius), jittered within its
//! image, and every view inside its image (redrawn until it is); each
//! camera then shares points with its `views_per_point − 1` neighbours on
//! either side only. An observation is an outlier with probability
//! `outlier_fraction` (default 5%), drawn uniformly in the image; otherwise
//! it is the exact projection plus Gaussian noise of `pixel_sigma` (default
//! 1 px) on each coordinate.
//!
//! The problem's cameras and points are the truth perturbed (defaults):
//! rotation by `exp(δ)`, δ ~ N(0, 0.01² I) rad, on the left; translation
//! and points by N(0, 0.05² I) (0.5% of the ring radius); focal length by a
//! factor 1 + N(0, 0.01²); k1 by N(0, 0.01²); k2 by N(0, 0.001²).
//!
//! The same seed gives the same problem on every platform (ChaCha8; the
//! cameras, the points, the observations and the points' perturbations each
//! draw from their own stream of it, so that any of them can be drawn again).
//! [`write()`] streams the problem to a BAL file in one pass, holding only the
//! cameras in memory (about 270 bytes each, [`MAX_CAMERAS`] at most): any
//! number of points up to [`MAX_OBSERVATIONS`] takes the same memory.
//! [`generate`] builds the same problem in memory, with its ground truth.

use std::io::Write;
use std::path::Path;

use nalgebra::{Rotation3, Vector2, Vector3};
use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;
use rand_distr::StandardNormal;

use crate::bal::{
    BalCamera, BalProblem, Observation, check_camera, check_observation, check_point, write_camera,
    write_header, write_observation, write_point,
};
use crate::camera::{SnavelyCamera, SnavelyIntrinsics};
use crate::error::{Error, ordinal};
use crate::output::{io_error, write_file};

/// Radius of the ring of cameras.
pub const RING_RADIUS: f64 = 10.0;
/// Camera heights vary as `RING_HEIGHT sin(3θ)` around the ring.
pub const RING_HEIGHT: f64 = 1.0;
/// Radius of the ball the points are drawn in.
pub const SCENE_RADIUS: f64 = 2.0;
/// Each camera aims at the centre moved by up to this along each axis.
pub const AIM_JITTER: f64 = 0.3;
/// Image width in pixels.
pub const IMAGE_WIDTH: f64 = 1024.0;
/// Image height in pixels.
pub const IMAGE_HEIGHT: f64 = 768.0;
/// Most observations a generated problem may have (10⁸: a BAL file of
/// about 6 GB, 3.2 GB in memory as [`generate`] holds them).
pub const MAX_OBSERVATIONS: usize = 100_000_000;
/// Most cameras a generated problem may have (10⁶): [`write()`] holds them
/// in memory, truth, model and initial value, 264 bytes each (`synth-bal`
/// peaks at 256 MiB at the cap).
pub const MAX_CAMERAS: usize = 1_000_000;

/// Which cameras see a point.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum Visibility {
    /// Cameras spread over about 60° of the ring, points in the central
    /// ball.
    #[default]
    Ring,
    /// Consecutive cameras, points near them (module documentation).
    Local,
}

/// What to generate.
#[derive(Debug, Clone, PartialEq)]
pub struct SyntheticConfig {
    /// Number of cameras on the ring (at least 2).
    pub cameras: usize,
    /// Number of points.
    pub points: usize,
    /// Cameras that see each point (2 to `cameras`).
    pub views_per_point: usize,
    /// Which cameras see a point, and where the points are.
    pub visibility: Visibility,
    /// Seed of the random generator.
    pub seed: u64,
    /// Standard deviation of the pixel noise of inliers (px).
    pub pixel_sigma: f64,
    /// Probability that an observation is an outlier, uniform in the image.
    pub outlier_fraction: f64,
    /// Standard deviation of the rotation perturbation of the initial
    /// cameras (rad, per axis).
    pub rotation_sigma: f64,
    /// Standard deviation of the perturbation of the initial camera
    /// translations and points (per axis).
    pub position_sigma: f64,
    /// Relative standard deviation of the initial focal lengths.
    pub focal_sigma: f64,
    /// Standard deviation of the perturbation of the initial k1.
    pub k1_sigma: f64,
    /// Standard deviation of the perturbation of the initial k2.
    pub k2_sigma: f64,
}

impl SyntheticConfig {
    /// About `observations` observations (`5 ⌈observations / 5⌉`): five
    /// views per point, `⌈observations / 5⌉` points, and one camera per
    /// thousand observations (at least 10), with the default noise.
    pub fn with_observations(observations: usize, seed: u64) -> Self {
        let views_per_point = 5;
        SyntheticConfig {
            cameras: (observations / 1000).max(10),
            points: observations.div_ceil(views_per_point),
            views_per_point,
            visibility: Visibility::Ring,
            seed,
            pixel_sigma: 1.0,
            outlier_fraction: 0.05,
            rotation_sigma: 0.01,
            position_sigma: 0.05,
            focal_sigma: 0.01,
            k1_sigma: 0.01,
            k2_sigma: 0.001,
        }
    }

    /// Number of observations the problem will have.
    pub fn observations(&self) -> Option<usize> {
        self.points.checked_mul(self.views_per_point)
    }

    /// Fails, saying why, unless the problem can be generated: at least one
    /// point, counts within [`MAX_CAMERAS`] and [`MAX_OBSERVATIONS`] (checked before
    /// anything is allocated), views from 2 to the cameras, standard
    /// deviations finite and not negative, the outlier fraction in `[0, 1]`.
    pub fn check(&self) -> Result<(), SyntheticError> {
        let fail = |what: String| Err(SyntheticError(what));
        if !(2..=MAX_CAMERAS).contains(&self.cameras) {
            return fail(format!(
                "the number of cameras must be from 2 to {MAX_CAMERAS}, not {}",
                self.cameras
            ));
        }
        if self.points == 0 {
            return fail("at least 1 point is needed, not 0".into());
        }
        if !(2..=self.cameras).contains(&self.views_per_point) {
            return fail(format!(
                "views per point must be from 2 to the {} cameras, not {}",
                self.cameras, self.views_per_point
            ));
        }
        match self.observations() {
            Some(n) if n <= MAX_OBSERVATIONS => {}
            _ => {
                return fail(format!(
                    "more than {MAX_OBSERVATIONS} observations asked for"
                ));
            }
        }
        let sigmas = [
            ("pixel sigma", self.pixel_sigma),
            ("rotation sigma", self.rotation_sigma),
            ("position sigma", self.position_sigma),
            ("focal sigma", self.focal_sigma),
            ("k1 sigma", self.k1_sigma),
            ("k2 sigma", self.k2_sigma),
        ];
        for (name, sigma) in sigmas {
            if !(sigma.is_finite() && sigma >= 0.0) {
                return fail(format!(
                    "{name} must be finite and not negative, not {sigma}"
                ));
            }
        }
        if !(0.0..=1.0).contains(&self.outlier_fraction) {
            return fail(format!(
                "the outlier fraction must be in [0, 1], not {}",
                self.outlier_fraction
            ));
        }
        Ok(())
    }
}

/// Settings that cannot be generated.
#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error)]
#[error("synthetic BAL: {0}")]
pub struct SyntheticError(pub String);

/// A generated problem with its ground truth.
#[derive(Debug, Clone, PartialEq)]
pub struct SyntheticBal {
    /// The problem: perturbed cameras and points, noisy observations.
    pub problem: BalProblem,
    /// The cameras the observations were made with.
    pub true_cameras: Vec<BalCamera>,
    /// The points the observations were made of.
    pub true_points: Vec<Vector3<f64>>,
    /// Indices of the outlier observations, increasing.
    pub outliers: Vec<usize>,
}

/// The random streams of a seed (see the module documentation).
const CAMERA_STREAM: u64 = 0;
const POINT_STREAM: u64 = 1;
const OBSERVATION_STREAM: u64 = 2;
const POINT_NOISE_STREAM: u64 = 3;

/// Stream `stream` of `seed`'s generator.
fn rng(seed: u64, stream: u64) -> ChaCha8Rng {
    let mut rng = ChaCha8Rng::seed_from_u64(seed);
    rng.set_stream(stream);
    rng
}

/// The cameras of a problem, true and initial, and how to draw the rest.
struct Scene<'a> {
    config: &'a SyntheticConfig,
    true_cameras: Vec<BalCamera>,
    /// The true cameras with their rotation matrices, to project through.
    models: Vec<SnavelyCamera>,
    cameras: Vec<BalCamera>,
    stride: usize,
}

impl<'a> Scene<'a> {
    /// The cameras of `config`, which passed [`SyntheticConfig::check`].
    fn new(config: &'a SyntheticConfig) -> Self {
        let mut rng = rng(config.seed, CAMERA_STREAM);
        let true_cameras: Vec<BalCamera> = (0..config.cameras)
            .map(|i| ring_camera(i, config.cameras, &mut rng))
            .collect();
        let cameras = true_cameras
            .iter()
            .map(|c| perturb_camera(c, config, &mut rng))
            .collect();
        Scene {
            config,
            models: true_cameras.iter().map(BalCamera::camera).collect(),
            true_cameras,
            cameras,
            stride: match config.visibility {
                Visibility::Ring => view_stride(config.cameras, config.views_per_point),
                Visibility::Local => 1,
            },
        }
    }

    /// The true points, drawn again at each call, each with the first camera
    /// of its views where the point depends on it ([`Visibility::Local`]; a
    /// ring point's first camera is drawn with its observations).
    fn true_points(
        &self,
    ) -> impl Iterator<Item = Result<(Option<usize>, Vector3<f64>), SyntheticError>> + '_ {
        let mut rng = rng(self.config.seed, POINT_STREAM);
        (0..self.config.points).map(move |_| match self.config.visibility {
            Visibility::Ring => Ok((None, point_in_ball(&mut rng))),
            Visibility::Local => {
                let first = rng.random_range(0..self.config.cameras);
                local_point(first, self.config, &self.models, &mut rng).map(|p| (Some(first), p))
            }
        })
    }

    /// The initial points: the true ones perturbed.
    fn points(&self) -> impl Iterator<Item = Result<Vector3<f64>, SyntheticError>> + '_ {
        let mut noise = rng(self.config.seed, POINT_NOISE_STREAM);
        let sigma = self.config.position_sigma;
        self.true_points()
            .map(move |p| p.map(|(_, p)| p + gaussian3(&mut noise) * sigma))
    }

    /// The observations, grouped by point, each with whether it is an
    /// outlier.
    fn observations(
        &self,
    ) -> impl Iterator<Item = Result<(Observation, bool), SyntheticError>> + '_ {
        let config = self.config;
        let mut rng = rng(config.seed, OBSERVATION_STREAM);
        self.true_points().enumerate().flat_map(move |(j, drawn)| {
            let (first, point) = match drawn {
                Ok(drawn) => drawn,
                Err(e) => return vec![Err(e)],
            };
            let first = first.unwrap_or_else(|| rng.random_range(0..config.cameras));
            (0..config.views_per_point)
                .map(|v| {
                    let camera = (first + v * self.stride) % config.cameras;
                    let outlier = rng.random_bool(config.outlier_fraction);
                    let pixel = if outlier {
                        Vector2::new(
                            rng.random_range(-0.5..0.5) * IMAGE_WIDTH,
                            rng.random_range(-0.5..0.5) * IMAGE_HEIGHT,
                        )
                    } else {
                        let exact = self.models[camera]
                            .project(&point)
                            .expect("a scene point is in front of the cameras that see it");
                        exact + gaussian2(&mut rng) * config.pixel_sigma
                    };
                    let observation = Observation {
                        camera,
                        point: j,
                        pixel,
                    };
                    Ok((observation, outlier))
                })
                .collect::<Vec<_>>()
        })
    }
}

/// Generates the problem `config` describes, in memory, with its truth.
pub fn generate(config: &SyntheticConfig) -> Result<SyntheticBal, SyntheticError> {
    config.check()?;
    let scene = Scene::new(config);
    let observation_count = config.points * config.views_per_point;
    let mut observations = Vec::with_capacity(observation_count);
    let mut outliers = Vec::new();
    for (k, drawn) in scene.observations().enumerate() {
        let (observation, outlier) = drawn?;
        if outlier {
            outliers.push(k);
        }
        observations.push(observation);
    }
    let points = scene.points().collect::<Result<_, _>>()?;
    let true_points = scene
        .true_points()
        .map(|p| p.map(|(_, p)| p))
        .collect::<Result<_, _>>()?;
    Ok(SyntheticBal {
        problem: BalProblem {
            cameras: scene.cameras,
            points,
            observations,
        },
        true_cameras: scene.true_cameras,
        true_points,
        outliers,
    })
}

/// What [`write()`] wrote.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Written {
    /// Cameras.
    pub cameras: usize,
    /// Points.
    pub points: usize,
    /// Observations.
    pub observations: usize,
    /// Outlier observations among them.
    pub outliers: usize,
}

/// Writes the problem `config` describes as the BAL file at `path`, the
/// file [`generate`] and [`crate::bal::write`] would write, streamed: only
/// the cameras are held in memory. The file is written to a temporary file
/// renamed into place once complete.
///
/// # Errors
///
/// Settings [`SyntheticConfig::check`] refuses, a generated value a reader
/// would refuse (a focal length perturbed below zero, a pixel beyond
/// [`crate::MAX_MAGNITUDE`]), or the file cannot be written; the file at
/// `path` is then unchanged.
pub fn write(config: &SyntheticConfig, path: impl AsRef<Path>) -> Result<Written, Error> {
    write_file(path.as_ref(), |out, name| write_to(config, out, name))
}

/// [`write()`] to `out`; `name` names it in errors.
///
/// # Errors
///
/// As [`write()`]; `out` then holds a part of the file.
pub fn write_to(
    config: &SyntheticConfig,
    out: &mut impl Write,
    name: &str,
) -> Result<Written, Error> {
    config
        .check()
        .map_err(|e| Error::file(name, e.to_string()))?;
    let scene = Scene::new(config);
    let observations = config.points * config.views_per_point;
    let invalid = |what: String| Error::file(name, format!("generated {what}"));
    let io = |e| io_error(name, e);
    write_header(out, config.cameras, config.points, observations).map_err(io)?;
    let mut outliers = 0;
    let unplaced = |e: SyntheticError| Error::file(name, e.to_string());
    for (k, drawn) in scene.observations().enumerate() {
        let (o, outlier) = drawn.map_err(unplaced)?;
        check_observation(&o, config.cameras, config.points)
            .map_err(|e| invalid(format!("{}: {e}", ordinal("observation", k, observations))))?;
        outliers += usize::from(outlier);
        write_observation(out, &o).map_err(io)?;
    }
    for (i, c) in scene.cameras.iter().enumerate() {
        check_camera(c)
            .map_err(|e| invalid(format!("{}: {e}", ordinal("camera", i, config.cameras))))?;
        write_camera(out, c).map_err(io)?;
    }
    for (j, p) in scene.points().enumerate() {
        let p = p.map_err(unplaced)?;
        check_point(&p)
            .map_err(|e| invalid(format!("{}: {e}", ordinal("point", j, config.points))))?;
        write_point(out, &p).map_err(io)?;
    }
    Ok(Written {
        cameras: config.cameras,
        points: config.points,
        observations,
        outliers,
    })
}

/// Camera `i` of `n` on the ring, aimed at the jittered centre.
fn ring_camera(i: usize, n: usize, rng: &mut ChaCha8Rng) -> BalCamera {
    let angle = std::f64::consts::TAU * i as f64 / n as f64;
    let centre = Vector3::new(
        RING_RADIUS * angle.cos(),
        RING_RADIUS * angle.sin(),
        RING_HEIGHT * (3.0 * angle).sin(),
    );
    let aim = Vector3::from_fn(|_, _| rng.random_range(-AIM_JITTER..AIM_JITTER));
    // World to camera, the view direction to the camera's −z, world z up.
    let rotation = Rotation3::look_at_rh(&(aim - centre), &Vector3::z());
    BalCamera {
        rotation: rotation.scaled_axis(),
        translation: -(rotation * centre),
        intrinsics: SnavelyIntrinsics {
            focal: rng.random_range(800.0..1200.0),
            k1: rng.random_range(-0.15..-0.05),
            k2: rng.random_range(-0.05..0.05),
        },
    }
}

/// A point uniform in the ball of radius [`SCENE_RADIUS`] (by rejection).
fn point_in_ball(rng: &mut ChaCha8Rng) -> Vector3<f64> {
    loop {
        let p = Vector3::from_fn(|_, _| rng.random_range(-1.0..1.0));
        if p.norm_squared() <= 1.0 {
            return p * SCENE_RADIUS;
        }
    }
}

/// Attempts at placing a point of [`Visibility::Local`] inside every image
/// of its views.
const LOCAL_ATTEMPTS: usize = 1000;

/// A point seen by the `views_per_point` consecutive cameras from `first`:
/// in front of the middle one, at about twice the baseline they span (at
/// most the ring radius, at least a tenth of it), jittered across its
/// image, inside every image of its views.
fn local_point(
    first: usize,
    config: &SyntheticConfig,
    models: &[SnavelyCamera],
    rng: &mut ChaCha8Rng,
) -> Result<Vector3<f64>, SyntheticError> {
    let n = config.cameras;
    let views = config.views_per_point;
    let spacing = std::f64::consts::TAU * RING_RADIUS / n as f64;
    let distance = (2.0 * (views - 1) as f64 * spacing).clamp(0.1 * RING_RADIUS, RING_RADIUS);
    let middle = &models[(first + (views - 1) / 2) % n];
    // World to camera: the camera's axes are the rows of R; it looks down
    // its −z axis.
    let centre = middle.centre();
    let axis = |k: usize| middle.rotation.matrix().row(k).transpose();
    for _ in 0..LOCAL_ATTEMPTS {
        let depth = distance * rng.random_range(0.7..1.3);
        let point = centre - axis(2) * depth
            + axis(0) * (depth * rng.random_range(-0.2..0.2))
            + axis(1) * (depth * rng.random_range(-0.15..0.15));
        let visible = (0..views).all(|v| {
            models[(first + v) % n]
                .project(&point)
                .is_some_and(|pixel| in_image(&(pixel * 1.05)))
        });
        if visible {
            return Ok(point);
        }
    }
    Err(SyntheticError(format!(
        "local visibility: no point in every image of {views} consecutive cameras of {n} \
         after {LOCAL_ATTEMPTS} attempts (use fewer views or more cameras)"
    )))
}

/// Step between the cameras of a point so that its views span about 60° of
/// the ring (at least consecutive cameras).
fn view_stride(cameras: usize, views: usize) -> usize {
    let span = cameras as f64 / 6.0;
    ((span / (views - 1) as f64).round() as usize).max(1)
}

fn perturb_camera(c: &BalCamera, config: &SyntheticConfig, rng: &mut ChaCha8Rng) -> BalCamera {
    let delta = Rotation3::new(gaussian3(rng) * config.rotation_sigma);
    let k = &c.intrinsics;
    let focal_factor: f64 = rng.sample(StandardNormal);
    let k1_noise: f64 = rng.sample(StandardNormal);
    let k2_noise: f64 = rng.sample(StandardNormal);
    BalCamera {
        rotation: (delta * Rotation3::new(c.rotation)).scaled_axis(),
        translation: c.translation + gaussian3(rng) * config.position_sigma,
        intrinsics: SnavelyIntrinsics {
            focal: k.focal * (1.0 + focal_factor * config.focal_sigma),
            k1: k.k1 + k1_noise * config.k1_sigma,
            k2: k.k2 + k2_noise * config.k2_sigma,
        },
    }
}

fn gaussian2(rng: &mut ChaCha8Rng) -> Vector2<f64> {
    Vector2::from_fn(|_, _| rng.sample(StandardNormal))
}

fn gaussian3(rng: &mut ChaCha8Rng) -> Vector3<f64> {
    Vector3::from_fn(|_, _| rng.sample(StandardNormal))
}

/// Whether `pixel` is inside the generator's image.
pub fn in_image(pixel: &Vector2<f64>) -> bool {
    pixel.x.abs() <= IMAGE_WIDTH / 2.0 && pixel.y.abs() <= IMAGE_HEIGHT / 2.0
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn views_spread_over_about_a_sixth_of_the_ring() {
        assert_eq!(view_stride(10, 5), 1);
        assert_eq!(view_stride(100, 5), 4);
        assert_eq!(view_stride(1000, 5), 42);
    }
}
