//! "Bundle Adjustment in the Large" (BAL) files (Agarwal et al., ECCV 2010).
//!
//! Whitespace-separated tokens, line breaks free:
//!
//! ```text
//! ncameras npoints nobservations
//! camera point u v          × nobservations (indices from 0; pixel origin
//!                             at the image centre, x right, y up)
//! ω₁ ω₂ ω₃ t₁ t₂ t₃ f k1 k2  × ncameras (angle-axis ω of R, world to camera)
//! X Y Z                     × npoints
//! ```
//!
//! The camera model is [`crate::camera`]'s. Values are kept exactly as read.

use std::io::{BufRead, Write};
use std::path::Path;

use nalgebra::{Rotation3, Vector2, Vector3};

use crate::camera::{SnavelyCamera, SnavelyIntrinsics};
use crate::error::{Error, ordinal};
use crate::input::all_in_range;
use crate::input::{self, Cursor, Lines, MAX_RESERVED, Tokens};
use crate::output::{Real, io_error, write_file};

/// A BAL camera: the nine numbers of the file.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct BalCamera {
    /// Angle-axis vector of `R` (world to camera): `R = exp([ω]×)`.
    pub rotation: Vector3<f64>,
    /// `t` (world to camera): `P = R X + t`.
    pub translation: Vector3<f64>,
    /// Focal length and radial distortion.
    pub intrinsics: SnavelyIntrinsics,
}

impl BalCamera {
    /// The camera of the model.
    pub fn camera(&self) -> SnavelyCamera {
        SnavelyCamera {
            rotation: Rotation3::new(self.rotation),
            translation: self.translation,
            intrinsics: self.intrinsics,
        }
    }
}

/// One observation: camera `camera` sees point `point` at `pixel`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Observation {
    /// Index into the cameras.
    pub camera: usize,
    /// Index into the points.
    pub point: usize,
    /// The pixel `(u, v)`: origin at the image centre, x right, y up.
    pub pixel: Vector2<f64>,
}

/// A bundle-adjustment problem: cameras, points and observations; what a
/// BAL file holds.
#[derive(Debug, Clone, PartialEq, Default)]
pub struct BalProblem {
    /// The cameras (initial values).
    pub cameras: Vec<BalCamera>,
    /// The 3D points in the world (initial values).
    pub points: Vec<Vector3<f64>>,
    /// The observations, in file order.
    pub observations: Vec<Observation>,
}

impl BalProblem {
    /// Fails, saying what is wrong, unless every index is in range, every
    /// value finite and every focal length positive (what a reader accepts).
    pub fn validate(&self) -> Result<(), String> {
        let (cameras, points) = (self.cameras.len(), self.points.len());
        for (k, o) in self.observations.iter().enumerate() {
            check_observation(o, cameras, points).map_err(|e| {
                format!(
                    "{}: {e}",
                    ordinal("observation", k, self.observations.len())
                )
            })?;
        }
        for (i, c) in self.cameras.iter().enumerate() {
            check_camera(c).map_err(|e| format!("{}: {e}", ordinal("camera", i, cameras)))?;
        }
        for (j, p) in self.points.iter().enumerate() {
            check_point(p).map_err(|e| format!("{}: {e}", ordinal("point", j, points)))?;
        }
        Ok(())
    }
}

/// Fails unless `o` is an observation a reader accepts among `cameras`
/// cameras and `points` points.
pub(crate) fn check_observation(
    o: &Observation,
    cameras: usize,
    points: usize,
) -> Result<(), String> {
    if o.camera >= cameras || o.point >= points {
        return Err(format!(
            "camera index {} or point index {} out of range ({cameras} cameras, {points} points)",
            o.camera, o.point
        ));
    }
    if !all_in_range(o.pixel.iter()) {
        return Err("non-finite or too large pixel".into());
    }
    Ok(())
}

/// Fails unless `c` is a camera a reader accepts.
pub(crate) fn check_camera(c: &BalCamera) -> Result<(), String> {
    let values = c.rotation.iter().chain(c.translation.iter());
    let intrinsics = [c.intrinsics.focal, c.intrinsics.k1, c.intrinsics.k2];
    if !all_in_range(values.chain(&intrinsics)) {
        return Err("non-finite or too large value".into());
    }
    check_focal(c.intrinsics.focal)
}

/// Fails unless `p` is a point a reader accepts.
pub(crate) fn check_point(p: &Vector3<f64>) -> Result<(), String> {
    if all_in_range(p.iter()) {
        Ok(())
    } else {
        Err("non-finite or too large coordinate".into())
    }
}

/// Fails unless `focal` is a usable focal length.
pub(crate) fn check_focal(focal: f64) -> Result<(), String> {
    if focal > 0.0 {
        Ok(())
    } else {
        Err(format!("focal length must be positive, found {focal}"))
    }
}

/// Reads the BAL file at `path`.
pub fn read(path: impl AsRef<Path>) -> Result<BalProblem, Error> {
    let (reader, name) = input::open(path.as_ref())?;
    read_from(reader, &name)
}

/// Reads BAL text; `name` is the file name used in errors.
pub fn from_text(text: &str, name: &str) -> Result<BalProblem, Error> {
    read_from(text.as_bytes(), name)
}

/// Reads BAL text from `reader`; `name` is the file name used in errors.
pub fn read_from(reader: impl BufRead, name: &str) -> Result<BalProblem, Error> {
    let mut tokens = Tokens::new(Lines::new(reader, name));
    let camera_count = tokens.integer("the number of cameras")?;
    let point_count = tokens.integer("the number of points")?;
    let observation_count = tokens.integer("the number of observations")?;

    let mut problem = BalProblem {
        cameras: Vec::with_capacity(camera_count.min(MAX_RESERVED)),
        points: Vec::with_capacity(point_count.min(MAX_RESERVED)),
        observations: Vec::with_capacity(observation_count.min(MAX_RESERVED)),
    };
    for k in 0..observation_count {
        let observation = read_observation(&mut tokens, camera_count, point_count)
            .map_err(|e| e.context(format_args!("observation {} of {observation_count}", k + 1)))?;
        problem.observations.push(observation);
    }
    for i in 0..camera_count {
        let camera = read_camera(&mut tokens)
            .map_err(|e| e.context(format_args!("camera {} of {camera_count}", i + 1)))?;
        problem.cameras.push(camera);
    }
    for j in 0..point_count {
        let point = tokens
            .vector3("a coordinate")
            .map_err(|e| e.context(format_args!("point {} of {point_count}", j + 1)))?;
        problem.points.push(point);
    }
    tokens.finish("the last point (the header's counts disagree with the body)")?;
    Ok(problem)
}

fn read_observation(
    tokens: &mut impl Cursor,
    camera_count: usize,
    point_count: usize,
) -> Result<Observation, Error> {
    Ok(Observation {
        camera: tokens.index("the camera index", camera_count, "cameras")?,
        point: tokens.index("the point index", point_count, "points")?,
        pixel: Vector2::new(
            tokens.real("the u coordinate")?,
            tokens.real("the v coordinate")?,
        ),
    })
}

fn read_camera(tokens: &mut impl Cursor) -> Result<BalCamera, Error> {
    let rotation = tokens.vector3("an angle-axis component")?;
    let translation = tokens.vector3("a translation component")?;
    let focal = tokens.real("the focal length")?;
    check_focal(focal).map_err(|e| tokens.error(e))?;
    Ok(BalCamera {
        rotation,
        translation,
        intrinsics: SnavelyIntrinsics {
            focal,
            k1: tokens.real("k1")?,
            k2: tokens.real("k2")?,
        },
    })
}

/// Writes `problem` as a BAL file at `path` (one observation per line, then
/// one camera or point value per line, as Ceres writes them).
pub fn write(problem: &BalProblem, path: impl AsRef<Path>) -> Result<(), Error> {
    write_file(path.as_ref(), |out, name| write_to(problem, out, name))
}

/// Writes `problem` as BAL text to `out`; `name` is used in errors. Fails
/// without writing if the problem does not [validate](BalProblem::validate).
pub fn write_to(problem: &BalProblem, out: &mut impl Write, name: &str) -> Result<(), Error> {
    problem.validate().map_err(|what| Error::file(name, what))?;
    write_unchecked(problem, out).map_err(|e| io_error(name, e))
}

fn write_unchecked(problem: &BalProblem, out: &mut impl Write) -> std::io::Result<()> {
    write_header(
        out,
        problem.cameras.len(),
        problem.points.len(),
        problem.observations.len(),
    )?;
    for o in &problem.observations {
        write_observation(out, o)?;
    }
    for c in &problem.cameras {
        write_camera(out, c)?;
    }
    for p in &problem.points {
        write_point(out, p)?;
    }
    Ok(())
}

/// The counts line.
pub(crate) fn write_header(
    out: &mut impl Write,
    cameras: usize,
    points: usize,
    observations: usize,
) -> std::io::Result<()> {
    writeln!(out, "{cameras} {points} {observations}")
}

/// One observation line.
pub(crate) fn write_observation(out: &mut impl Write, o: &Observation) -> std::io::Result<()> {
    writeln!(
        out,
        "{} {} {} {}",
        o.camera,
        o.point,
        Real(o.pixel.x),
        Real(o.pixel.y)
    )
}

/// A camera, one value per line.
pub(crate) fn write_camera(out: &mut impl Write, c: &BalCamera) -> std::io::Result<()> {
    let intrinsics = [c.intrinsics.focal, c.intrinsics.k1, c.intrinsics.k2];
    for value in c
        .rotation
        .iter()
        .chain(c.translation.iter())
        .chain(&intrinsics)
    {
        writeln!(out, "{}", Real(*value))?;
    }
    Ok(())
}

/// A point, one coordinate per line.
pub(crate) fn write_point(out: &mut impl Write, p: &Vector3<f64>) -> std::io::Result<()> {
    for value in p.iter() {
        writeln!(out, "{}", Real(*value))?;
    }
    Ok(())
}
