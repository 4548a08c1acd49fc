//! Errors of a solved problem file against the ground truth it carries
//! (its optional `truth` object: the true value of variables by name, in
//! the JSON form of their `value`), printed by `solve` after the summary,
//! initially → finally:
//!
//! - over the pose variables — `Se3` (world to camera, the documents'
//!   factors') and `Se3RhoTheta` (body to world, `between`'s and g2o's),
//!   as world-to-camera poses — the absolute
//!   trajectory error: the RMS distance of the camera centres `−Rᵀ t` to the
//!   true ones after aligning them to the truth (Umeyama's method, [`crate::align`])
//!   as a rigid motion (SE(3)) and as a similarity (Sim(3)), and the RMS
//!   angle of the camera rotations after the SE(3) alignment (degrees);
//! - over the `OrthonormalLine` variables, after the SE(3) alignment, the
//!   mean angle between the directions (degrees, sign ignored) and the mean
//!   difference of the distances from the origin (m);
//! - over the `InfinitePlane` variables, after the SE(3) alignment, the mean
//!   angle between the normals (degrees, `[n, d]` and `[−n, −d]` the same
//!   plane) and the mean difference of the offsets (m, unit normals).
//!
//! `Vector3` variables may carry a truth (it is checked) but are not
//! reported; other types may not.

use crate::InputError;
use crate::decode::at_part;
use crate::document::{Json, Members};
use crate::field_path::join;
use crate::input::{Object, numbers};
use factor_core::Storage;
use factor_core::geometry::{InfinitePlane, OrthonormalLine};
use factor_core::lie::Se3;
use factor_core::validation::number_text;
use nalgebra::{Isometry3, Point3, Similarity3, UnitQuaternion, Vector3, Vector4};

use crate::align::umeyama;
use crate::truth::angle;

/// A variable's value, as far as its errors go.
#[derive(Debug, Clone, Copy)]
enum Reading {
    /// A world-to-camera pose.
    Pose(Isometry3<f64>),
    Point,
    /// A line: its point nearest the origin and its direction.
    Line(Vector3<f64>, Vector3<f64>),
    /// A plane `[n, d]`, `|n| = 1`.
    Plane(Vector4<f64>),
}

/// The value `value` at `path` of a variable of type `kind`, checked as a
/// value of that type is (its type's `Storage::from_input`: a unit
/// quaternion, Plücker coordinates, a plane with a normal) and with every
/// number of magnitude at most [`slam_data::MAX_MAGNITUDE`], so that the
/// errors computed from it stay finite.
fn reading(kind: &str, value: Json<'_>, path: &str) -> Result<Reading, InputError> {
    fn checked<T: Storage<f64>>(input: &[f64], path: &str) -> Result<Vec<f64>, InputError> {
        if let Some(x) = input.iter().find(|x| x.abs() > slam_data::MAX_MAGNITUDE) {
            return Err(InputError::new(
                path,
                format!(
                    "{} is out of range: a truth's numbers are at most {:e} in magnitude",
                    number_text(*x),
                    slam_data::MAX_MAGNITUDE
                ),
            ));
        }
        T::from_input(input).map_err(|e| at_part(path.to_owned(), e))
    }
    match kind {
        "Se3" | "Se3RhoTheta" => {
            let pose = Object::new(value, path, &["rotation", "translation"])?;
            let mut input = pose.quaternion("rotation")?;
            input.extend(pose.numbers("translation", 3)?);
            // The two store the same scalars.
            let stored = checked::<Se3<f64>>(&input, path)?;
            let (q, t) = (&stored[..4], &stored[4..]);
            let pose = Isometry3::from_parts(
                Vector3::new(t[0], t[1], t[2]).into(),
                UnitQuaternion::from_quaternion(nalgebra::Quaternion::new(q[3], q[0], q[1], q[2])),
            );
            // World to camera, as the errors read every pose.
            Ok(Reading::Pose(if kind == "Se3" {
                pose
            } else {
                pose.inverse()
            }))
        }
        "Vector3" => {
            checked::<Vector3<f64>>(&numbers(value, path, 3)?, path).map(|_| Reading::Point)
        }
        "OrthonormalLine" => {
            let line = Object::new(value, path, &["normal", "direction"])?;
            let mut input = line.numbers("normal", 3)?;
            input.extend(line.numbers("direction", 3)?);
            let input = common_scale::<6>(input);
            checked::<OrthonormalLine<f64>>(&input, path)?;
            let (n, v) = (
                Vector3::from_column_slice(&input[..3]),
                Vector3::from_column_slice(&input[3..]),
            );
            // The moment `n = p × v`: the point nearest the origin is `v × n / |v|²`.
            Ok(Reading::Line(v.cross(&n) / v.norm_squared(), v))
        }
        "InfinitePlane" => {
            let c = Vector4::from_vec(common_scale::<4>(numbers(value, path, 4)?));
            checked::<InfinitePlane<f64>>(c.as_slice(), path)?;
            Ok(Reading::Plane(c / c.xyz().norm()))
        }
        other => Err(InputError::new(
            path,
            format!(
                "a truth is read for Se3, Se3RhoTheta, Vector3, OrthonormalLine and InfinitePlane \
                 variables, not {other}"
            ),
        )),
    }
}

/// `input`, the coordinates of something any non-zero multiple of which is
/// the same (Plücker coordinates, a plane), at unit norm, so that a value
/// of any finite scale (a solution keeps its file's, 1e300 say) passes the
/// magnitude check; as it is when it has no finite non-zero norm (for the
/// checks to name).
fn common_scale<const N: usize>(input: Vec<f64>) -> Vec<f64> {
    match factor_core::linalg::unit_of(&nalgebra::SVector::<f64, N>::from_column_slice(&input)) {
        Some(unit) => unit.as_slice().to_vec(),
        None => input,
    }
}

/// The checked truth of a problem file.
#[derive(Debug, Clone)]
pub struct Truth {
    /// By variable name, sorted: its type and true value.
    values: Vec<(String, &'static str, Reading)>,
}

/// The types [`reading`] knows, as `'static` names.
const KINDS: [&str; 5] = [
    "Se3",
    "Se3RhoTheta",
    "Vector3",
    "OrthonormalLine",
    "InfinitePlane",
];

impl Truth {
    /// Reads the `truth` object `value` of a file whose variables are
    /// `declared` (each with a string `type`).
    ///
    /// # Errors
    ///
    /// Naming the field: not an object, a name that is not a variable, a
    /// value not of its variable's form, a type without a truth.
    pub fn read(value: Json<'_>, declared: Members<'_>) -> Result<Truth, InputError> {
        let map = value
            .as_object()
            .ok_or_else(|| InputError::new("truth", "expected an object of values by name"))?;
        let mut values = Vec::with_capacity(map.len());
        for (name, value) in map.iter() {
            let path = join("truth", name);
            let declared = declared
                .get(name)
                .ok_or_else(|| InputError::new(&path, "no variable of this name in variables"))?;
            let kind = declared
                .get("type")
                .and_then(Json::as_str)
                .unwrap_or_default();
            let reading = reading(kind, value, &path)?;
            let kind = KINDS.iter().find(|k| **k == kind).expect("a known kind");
            values.push((name.to_owned(), *kind, reading));
        }
        values.sort_by(|a, b| a.0.cmp(&b.0));
        Ok(Truth { values })
    }

    /// The errors of `initial` and `solved` (the files' `variables`
    /// objects) in words.
    ///
    /// # Errors
    ///
    /// An estimate out of the range a truth may hold, or an error that is
    /// not finite (estimates too far off to measure): why, in words; no
    /// figure is printed.
    pub fn describe(&self, initial: Json<'_>, solved: Json<'_>) -> Result<String, String> {
        let (before, after) = (self.errors(initial)?, self.errors(solved)?);
        let figures = [&before, &after].into_iter().flat_map(|e| {
            let line = |l: Option<(usize, f64, f64)>| l.map(|(_, a, d)| [a, d]);
            [e.ate_se3, e.ate_sim3, e.rotation]
                .into_iter()
                .flatten()
                .chain(line(e.lines).into_iter().flatten())
                .chain(line(e.planes).into_iter().flatten())
        });
        if let Some(x) = figures.into_iter().find(|x| !x.is_finite()) {
            return Err(format!(
                "an error against the file's truth is {x}: the estimates are too far from it to \
                 measure"
            ));
        }
        let mut lines = vec!["  errors against the file's truth, initially → finally:".to_owned()];
        let pair = |a: Option<f64>, b: Option<f64>, digits: usize| match (a, b) {
            (Some(a), Some(b)) => format!("{a:.digits$} → {b:.digits$}"),
            _ => "n/a".to_owned(),
        };
        if before.cameras > 0 {
            lines.push(format!(
                "    {} cameras: ATE RMSE SE(3)-aligned {} m, Sim(3)-aligned {} m; rotation RMS {}°",
                before.cameras,
                pair(before.ate_se3, after.ate_se3, 5),
                pair(before.ate_sim3, after.ate_sim3, 5),
                pair(before.rotation, after.rotation, 4),
            ));
        }
        for (what, angle, distance, b, a) in [
            ("lines", "direction", "distance", before.lines, after.lines),
            ("planes", "normal", "offset", before.planes, after.planes),
        ] {
            if let (Some((n, a0, d0)), Some((_, a1, d1))) = (b, a) {
                lines.push(format!(
                    "    {n} {what}: mean {angle} {a0:.4} → {a1:.4}°, mean {distance} \
                     {d0:.5} → {d1:.5} m"
                ));
            }
        }
        Ok(lines.join("\n"))
    }

    /// The errors of the values `variables` (a file's `variables` object),
    /// or why they cannot be measured.
    fn errors(&self, variables: Json<'_>) -> Result<Errors, String> {
        let mut estimated = Vec::new();
        let mut poses = Vec::new();
        for (name, kind, truth) in &self.values {
            let value = variables
                .get(name)
                .and_then(|variable| variable.get("value"))
                .expect("checked: every variable with a truth has a value");
            let estimate = reading(kind, value, &join("variables", name))
                .map_err(|e| format!("the estimate of {e}"))?;
            if let (Reading::Pose(e), Reading::Pose(t)) = (estimate, truth) {
                poses.push((e.inverse(), t.inverse()));
            }
            estimated.push((estimate, *truth));
        }
        let (from, to): (Vec<Vector3<f64>>, Vec<Vector3<f64>>) = poses
            .iter()
            .map(|(e, t)| (e.translation.vector, t.translation.vector))
            .unzip();
        let rms = |sim: &Similarity3<f64>| {
            let sum: f64 = from
                .iter()
                .zip(&to)
                .map(|(x, y)| (sim * Point3::from(*x) - Point3::from(*y)).norm_squared())
                .sum();
            (sum / from.len() as f64).sqrt()
        };
        let se3 = umeyama(&from, &to, false);
        let sim3 = umeyama(&from, &to, true);
        let rotation = se3.map(|a| {
            let sum: f64 = poses
                .iter()
                .map(|(e, t)| {
                    (a.isometry.rotation * e.rotation)
                        .angle_to(&t.rotation)
                        .to_degrees()
                        .powi(2)
                })
                .sum();
            (sum / poses.len() as f64).sqrt()
        });
        let align = se3.unwrap_or_else(Similarity3::identity);
        let mut lines = Vec::new();
        let mut planes = Vec::new();
        for (estimate, truth) in &estimated {
            match (estimate, truth) {
                (Reading::Line(p, v), Reading::Line(pt, vt)) => {
                    let (p, v) = (align * Point3::from(*p), align.isometry.rotation * v);
                    // The distance from the origin of the line through `p` along `v`.
                    let distance = p.coords.cross(&v).norm() / v.norm();
                    let a = angle(&v, vt);
                    lines.push((a.min(180.0 - a), (distance - pt.norm()).abs()));
                }
                (Reading::Plane(c), Reading::Plane(ct)) => {
                    let n = align.isometry.rotation * c.xyz();
                    let d = c.w - n.dot(&align.isometry.translation.vector);
                    let sign = if n.dot(&ct.xyz()) < 0.0 { -1.0 } else { 1.0 };
                    planes.push((angle(&(sign * n), &ct.xyz()), (sign * d - ct.w).abs()));
                }
                _ => {}
            }
        }
        let mean = |v: &[(f64, f64)]| {
            let n = v.len() as f64;
            (!v.is_empty()).then(|| {
                (
                    v.len(),
                    v.iter().map(|x| x.0).sum::<f64>() / n,
                    v.iter().map(|x| x.1).sum::<f64>() / n,
                )
            })
        };
        Ok(Errors {
            cameras: poses.len(),
            ate_se3: se3.as_ref().map(rms),
            ate_sim3: sim3.as_ref().map(rms),
            rotation,
            lines: mean(&lines),
            planes: mean(&planes),
        })
    }
}

/// The errors of one set of values.
struct Errors {
    cameras: usize,
    ate_se3: Option<f64>,
    ate_sim3: Option<f64>,
    rotation: Option<f64>,
    /// Count, mean angle (°), mean distance (m).
    lines: Option<(usize, f64, f64)>,
    planes: Option<(usize, f64, f64)>,
}
