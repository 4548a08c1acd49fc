//! Bundler v0.3 reconstructions (`bundle.out`, Snavely et al.).
//!
//! A first line `# Bundle file v0.3`, then whitespace-separated tokens:
//!
//! ```text
//! ncameras npoints
//! f k1 k2                      ┐
//! r11 r12 r13                  │ × ncameras: R (world to camera, rows)
//! r21 r22 r23                  │ and t, P = R X + t
//! r31 r32 r33                  │
//! t1 t2 t3                     ┘
//! X Y Z                        ┐
//! red green blue               │ × npoints: position, colour (0–255),
//! n  (camera key u v) × n      ┘ and the views that see it
//! ```
//!
//! `key` is the index of the SIFT feature in that camera's image; `(u, v)`
//! is the pixel with its origin at the image centre, x right, y up. The
//! camera model is [`crate::camera`]'s, the same as BAL's. Values are kept
//! exactly as read; a camera that Bundler did not reconstruct (all zeros)
//! is rejected, as GTSAM does.

use std::io::{BufRead, Write};
use std::path::Path;

use nalgebra::{Matrix3, Vector2, Vector3};

use crate::bal::{BalCamera, BalProblem, Observation, check_focal};
use crate::camera::{SnavelyCamera, SnavelyIntrinsics};
use crate::checks::{check_rotation_matrix, nearest_rotation};
use crate::error::{Error, ordinal};
use crate::input::all_in_range;
use crate::input::{self, Cursor, Lines, MAX_RESERVED, Tokens};
use crate::output::{Real, io_error, write_file};

/// The first line of a Bundler v0.3 file.
pub const HEADER: &str = "# Bundle file v0.3";

/// A Bundler camera: the fifteen numbers of the file.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct BundlerCamera {
    /// Focal length and radial distortion.
    pub intrinsics: SnavelyIntrinsics,
    /// `R` (world to camera) as written: a rotation within
    /// [`crate::ROTATION_TOLERANCE`].
    pub rotation: Matrix3<f64>,
    /// `t` (world to camera): `P = R X + t`.
    pub translation: Vector3<f64>,
}

impl BundlerCamera {
    /// The camera of the model, with the rotation nearest to the written `R`.
    pub fn camera(&self) -> SnavelyCamera {
        SnavelyCamera {
            rotation: nearest_rotation(&self.rotation),
            translation: self.translation,
            intrinsics: self.intrinsics,
        }
    }
}

/// A reconstructed point: position and colour.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct BundlerPoint {
    /// Position in the world.
    pub position: Vector3<f64>,
    /// Red, green, blue.
    pub colour: [u8; 3],
}

/// One view of a point.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct BundlerObservation {
    /// Index into the cameras.
    pub camera: usize,
    /// Index into the points.
    pub point: usize,
    /// Index of the SIFT feature in the camera's image.
    pub key: usize,
    /// The pixel `(u, v)`: origin at the image centre, x right, y up.
    pub pixel: Vector2<f64>,
}

/// What a Bundler file holds.
#[derive(Debug, Clone, PartialEq, Default)]
pub struct BundlerProblem {
    /// The cameras.
    pub cameras: Vec<BundlerCamera>,
    /// The points.
    pub points: Vec<BundlerPoint>,
    /// The views, grouped by point in file order.
    pub observations: Vec<BundlerObservation>,
}

impl BundlerProblem {
    /// The same problem as BAL: rotations as angle-axis vectors of the
    /// nearest rotation, colours and feature keys dropped.
    pub fn to_bal(&self) -> BalProblem {
        BalProblem {
            cameras: self
                .cameras
                .iter()
                .map(|c| {
                    let camera = c.camera();
                    BalCamera {
                        rotation: camera.rotation.scaled_axis(),
                        translation: camera.translation,
                        intrinsics: camera.intrinsics,
                    }
                })
                .collect(),
            points: self.points.iter().map(|p| p.position).collect(),
            observations: self
                .observations
                .iter()
                .map(|o| Observation {
                    camera: o.camera,
                    point: o.point,
                    pixel: o.pixel,
                })
                .collect(),
        }
    }

    /// Fails, saying what is wrong, unless the problem is one a reader
    /// accepts: indices in range, values finite, focal lengths positive,
    /// rotations within tolerance.
    pub fn validate(&self) -> Result<(), String> {
        for (i, c) in self.cameras.iter().enumerate() {
            let intrinsics = [c.intrinsics.focal, c.intrinsics.k1, c.intrinsics.k2];
            let values = intrinsics
                .iter()
                .chain(c.rotation.iter())
                .chain(c.translation.iter());
            if !all_in_range(values) {
                return Err(format!(
                    "{} has a non-finite or too large value",
                    ordinal("camera", i, self.cameras.len())
                ));
            }
            check_focal(c.intrinsics.focal)
                .and_then(|()| check_rotation_matrix(&c.rotation))
                .map_err(|e| format!("{}: {e}", ordinal("camera", i, self.cameras.len())))?;
        }
        for (j, p) in self.points.iter().enumerate() {
            if !all_in_range(p.position.iter()) {
                return Err(format!(
                    "{} has a non-finite or too large coordinate",
                    ordinal("point", j, self.points.len())
                ));
            }
        }
        for (k, o) in self.observations.iter().enumerate() {
            if o.camera >= self.cameras.len() || o.point >= self.points.len() {
                return Err(format!(
                    "{}: camera index {} or point index {} out of range ({} cameras, {} points)",
                    ordinal("observation", k, self.observations.len()),
                    o.camera,
                    o.point,
                    self.cameras.len(),
                    self.points.len()
                ));
            }
            if !all_in_range(o.pixel.iter()) {
                return Err(format!(
                    "{} has a non-finite or too large pixel",
                    ordinal("observation", k, self.observations.len())
                ));
            }
        }
        Ok(())
    }
}

/// Reads the Bundler file at `path`.
pub fn read(path: impl AsRef<Path>) -> Result<BundlerProblem, Error> {
    let (reader, name) = input::open(path.as_ref())?;
    read_from(reader, &name)
}

/// Reads Bundler text; `name` is the file name used in errors.
pub fn from_text(text: &str, name: &str) -> Result<BundlerProblem, Error> {
    read_from(text.as_bytes(), name)
}

/// Reads Bundler text from `reader`; `name` is the file name used in errors.
pub fn read_from(reader: impl BufRead, name: &str) -> Result<BundlerProblem, Error> {
    let mut lines = Lines::new(reader, name);
    let first = lines.next_line()?;
    if first.as_ref().map(|line| line.text.trim_end()) != Some(HEADER) {
        return Err(lines.error(format!(
            "not a Bundler v0.3 file: the first line must be `{HEADER}`"
        )));
    }
    let mut tokens = Tokens::new(lines);
    let camera_count = tokens.integer("the number of cameras")?;
    let point_count = tokens.integer("the number of points")?;

    let mut problem = BundlerProblem {
        cameras: Vec::with_capacity(camera_count.min(MAX_RESERVED)),
        points: Vec::with_capacity(point_count.min(MAX_RESERVED)),
        observations: Vec::new(),
    };
    for i in 0..camera_count {
        let camera = read_camera(&mut tokens)
            .map_err(|e| e.context(format_args!("camera {} of {camera_count}", i + 1)))?;
        problem.cameras.push(camera);
    }
    for j in 0..point_count {
        read_point(&mut tokens, j, &mut problem)
            .map_err(|e| e.context(format_args!("point {} of {point_count}", j + 1)))?;
    }
    tokens.finish("the last point (the header's counts disagree with the body)")?;
    Ok(problem)
}

fn read_camera(tokens: &mut impl Cursor) -> Result<BundlerCamera, Error> {
    let focal = tokens.real("the focal length")?;
    let k1 = tokens.real("k1")?;
    let k2 = tokens.real("k2")?;
    let mut rotation = Matrix3::zeros();
    for r in 0..3 {
        for c in 0..3 {
            rotation[(r, c)] = tokens.real("a rotation entry")?;
        }
    }
    let translation = tokens.vector3("a translation component")?;
    if focal == 0.0 && rotation == Matrix3::zeros() {
        return Err(tokens.error("not reconstructed (all zeros): not supported".into()));
    }
    check_focal(focal)
        .and_then(|()| check_rotation_matrix(&rotation))
        .map_err(|e| tokens.error(e))?;
    Ok(BundlerCamera {
        intrinsics: SnavelyIntrinsics { focal, k1, k2 },
        rotation,
        translation,
    })
}

fn read_point(
    tokens: &mut impl Cursor,
    point: usize,
    problem: &mut BundlerProblem,
) -> Result<(), Error> {
    let position = tokens.vector3("a coordinate")?;
    let mut colour = [0u8; 3];
    for channel in &mut colour {
        let value = tokens.integer("a colour channel")?;
        *channel = u8::try_from(value)
            .map_err(|_| tokens.error(format!("colour channel {value} is over 255")))?;
    }
    problem.points.push(BundlerPoint { position, colour });
    let view_count = tokens.integer("the number of views")?;
    for v in 0..view_count {
        let observation = read_view(tokens, problem.cameras.len(), point)
            .map_err(|e| e.context(format_args!("view {} of {view_count}", v + 1)))?;
        problem.observations.push(observation);
    }
    Ok(())
}

fn read_view(
    tokens: &mut impl Cursor,
    camera_count: usize,
    point: usize,
) -> Result<BundlerObservation, Error> {
    Ok(BundlerObservation {
        camera: tokens.index("the camera index", camera_count, "cameras")?,
        point,
        key: tokens.integer("the feature key")?,
        pixel: Vector2::new(
            tokens.real("the u coordinate")?,
            tokens.real("the v coordinate")?,
        ),
    })
}

/// Writes `problem` as a Bundler v0.3 file at `path`.
pub fn write(problem: &BundlerProblem, path: impl AsRef<Path>) -> Result<(), Error> {
    write_file(path.as_ref(), |out, name| write_to(problem, out, name))
}

/// Writes `problem` as Bundler v0.3 text to `out`; `name` is used in errors.
/// The views are written grouped by point, in their order within each
/// point. Fails without writing if the problem does not
/// [validate](BundlerProblem::validate).
pub fn write_to(problem: &BundlerProblem, out: &mut impl Write, name: &str) -> Result<(), Error> {
    problem.validate().map_err(|what| Error::file(name, what))?;
    write_unchecked(problem, out).map_err(|e| io_error(name, e))
}

fn write_unchecked(problem: &BundlerProblem, out: &mut impl Write) -> std::io::Result<()> {
    // Views grouped by point (a stable counting sort: no quadratic step).
    let mut start = vec![0usize; problem.points.len() + 1];
    for o in &problem.observations {
        start[o.point + 1] += 1;
    }
    for j in 0..problem.points.len() {
        start[j + 1] += start[j];
    }
    let mut by_point = vec![0usize; problem.observations.len()];
    let mut next = start.clone();
    for (k, o) in problem.observations.iter().enumerate() {
        by_point[next[o.point]] = k;
        next[o.point] += 1;
    }

    writeln!(out, "{HEADER}")?;
    writeln!(out, "{} {}", problem.cameras.len(), problem.points.len())?;
    for c in &problem.cameras {
        let k = &c.intrinsics;
        writeln!(out, "{} {} {}", Real(k.focal), Real(k.k1), Real(k.k2))?;
        for r in 0..3 {
            let row = c.rotation.row(r);
            writeln!(out, "{} {} {}", Real(row[0]), Real(row[1]), Real(row[2]))?;
        }
        let t = &c.translation;
        writeln!(out, "{} {} {}", Real(t.x), Real(t.y), Real(t.z))?;
    }
    for (j, p) in problem.points.iter().enumerate() {
        let x = &p.position;
        writeln!(out, "{} {} {}", Real(x.x), Real(x.y), Real(x.z))?;
        writeln!(out, "{} {} {}", p.colour[0], p.colour[1], p.colour[2])?;
        let views = &by_point[start[j]..start[j + 1]];
        write!(out, "{}", views.len())?;
        for &k in views {
            let o = &problem.observations[k];
            write!(
                out,
                " {} {} {} {}",
                o.camera,
                o.key,
                Real(o.pixel.x),
                Real(o.pixel.y)
            )?;
        }
        writeln!(out)?;
    }
    Ok(())
}
