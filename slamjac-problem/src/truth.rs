//! Errors of a solved g2o line and plane graph against its ground truth
//! (`--truth FILE`, by default `STEM_truth.g2o` beside the file when it
//! exists), as `bench-peers/g2o/errors.py` computes them for g2o's own
//! solution: no alignment (the graphs fix a pose at its true value); over
//! the robot poses both hold, the RMS and largest translation and rotation
//! errors; per line the angle between the directions and the difference of
//! the distances from the origin; per plane the angle between the normals
//! and the difference of the offsets (unit normals); for each sensor offset
//! its translation and rotation errors.

use std::collections::{HashMap, HashSet};
use std::path::{Path, PathBuf};

use crate::field_path::shown_path;
use nalgebra::Vector3;
use slam_data::{Format, G2oGraph, Pose};

/// The ground truth a solve of `file` (in `format`, when given or told by
/// the name) reads, and its part in messages: `--truth` when given; else,
/// for a file that may be a g2o graph (`format` g2o with lines and planes,
/// or told from the content), `STEM_truth.g2o` beside it, if it exists.
/// The outputs are checked against it as against any input.
pub fn file(
    file: &Path,
    format: Option<Format>,
    truth: Option<&Path>,
) -> Option<(PathBuf, &'static str)> {
    match truth {
        Some(path) => Some((path.to_owned(), "--truth")),
        None if matches!(format, None | Some(Format::G2oAddons)) => {
            beside(file).map(|path| (path, "the ground truth read beside the input"))
        }
        None => None,
    }
}

/// `STEM_truth.g2o` beside `file`, if it exists.
fn beside(file: &Path) -> Option<PathBuf> {
    let stem = file.file_stem()?.to_str()?;
    let path = file.with_file_name(format!("{stem}_truth.g2o"));
    path.is_file().then_some(path)
}

/// Why a g2o graph's ground truth cannot be used.
#[derive(Debug, thiserror::Error)]
#[non_exhaustive]
pub enum TruthError {
    /// The truth file cannot be read as a g2o graph.
    #[error(transparent)]
    Read(#[from] slam_data::Error),
    /// The truth holds none of the graph's robot poses: nothing to compare.
    #[error("{0}")]
    NothingToCompare(String),
}

/// The ground truth of a g2o line and plane graph, read before the solve.
pub struct Truth {
    path: PathBuf,
    graph: G2oGraph,
    /// The errors of the initial values.
    before: Errors,
}

impl Truth {
    /// The truth of `data`, read from `file`'s truth ([`file()`]) when
    /// `data` is a g2o line and plane graph and it has one.
    ///
    /// # Errors
    ///
    /// A truth file that cannot be read, or that holds none of the graph's
    /// robot poses (there would be nothing to compare).
    pub fn read(
        file: &Path,
        format: Option<Format>,
        truth: Option<&Path>,
        data: &slam_data::Problem,
    ) -> Result<Option<Truth>, TruthError> {
        let slam_data::Problem::G2oAddons(initial) = data else {
            return Ok(None);
        };
        let Some((path, _)) = self::file(file, format, truth) else {
            return Ok(None);
        };
        let graph = slam_data::g2o::read_graph(&path)?;
        let before = Errors::of(initial, &graph);
        if before.poses.is_empty() {
            let offsets: HashSet<usize> = initial.plane_edges.iter().map(|e| e.offset).collect();
            let poses = initial
                .poses
                .iter()
                .filter(|v| !offsets.contains(&v.id))
                .count();
            return Err(TruthError::NothingToCompare(format!(
                "{}: the ground truth holds none of the graph's {poses} robot poses (by id): \
                 nothing to compare",
                shown_path(&path)
            )));
        }
        Ok(Some(Truth {
            path,
            graph,
            before,
        }))
    }

    /// The errors of the initial values and of `solved` in words.
    ///
    /// # Errors
    ///
    /// An error that is not finite (estimates too far off to measure), in
    /// words.
    pub fn describe(&self, solved: &slam_data::Problem) -> Result<String, String> {
        let slam_data::Problem::G2oAddons(solved) = solved else {
            unreachable!("the solution of a g2o line and plane graph is one");
        };
        let after = Errors::of(solved, &self.graph);
        after.describe(&self.before, &self.path)
    }
}

/// The errors of a graph's vertices against the truth.
#[derive(Debug, Clone, PartialEq)]
pub struct Errors {
    /// Per robot pose both hold: translation error (m), rotation error (°).
    pub poses: Vec<(f64, f64)>,
    /// Per line (id): direction angle (°), distance difference (m).
    pub lines: Vec<(usize, f64, f64)>,
    /// Per plane (id): normal angle (°), offset difference (m).
    pub planes: Vec<(usize, f64, f64)>,
    /// Per sensor offset (id): translation (m) and rotation (°) errors.
    pub offsets: Vec<(usize, f64, f64)>,
}

/// Translation (m) and rotation (°) errors of `pose` against `truth`.
fn pose_error(pose: &Pose, truth: &Pose) -> (f64, f64) {
    let angle = pose
        .rotation
        .unit_quaternion()
        .angle_to(&truth.rotation.unit_quaternion())
        .to_degrees();
    ((pose.translation - truth.translation).norm(), angle)
}

/// The angle between two directions, degrees.
pub(crate) fn angle(a: &Vector3<f64>, b: &Vector3<f64>) -> f64 {
    (a.dot(b) / (a.norm() * b.norm()))
        .clamp(-1.0, 1.0)
        .acos()
        .to_degrees()
}

impl Errors {
    /// The errors of `graph` against `truth`, over the vertices both hold.
    pub fn of(graph: &G2oGraph, truth: &G2oGraph) -> Errors {
        let offsets: HashSet<usize> = graph.plane_edges.iter().map(|e| e.offset).collect();
        let true_poses: HashMap<usize, &Pose> =
            truth.poses.iter().map(|v| (v.id, &v.pose)).collect();
        let mut errors = Errors {
            poses: Vec::new(),
            lines: Vec::new(),
            planes: Vec::new(),
            offsets: Vec::new(),
        };
        for v in &graph.poses {
            if let Some(t) = true_poses.get(&v.id) {
                let (dt, dr) = pose_error(&v.pose, t);
                if offsets.contains(&v.id) {
                    errors.offsets.push((v.id, dt, dr));
                } else {
                    errors.poses.push((dt, dr));
                }
            }
        }
        let true_lines: HashMap<usize, _> = truth.lines.iter().map(|v| (v.id, v.line)).collect();
        for v in &graph.lines {
            if let Some(t) = true_lines.get(&v.id) {
                let split = |l: &nalgebra::Vector6<f64>| {
                    (
                        l.fixed_rows::<3>(0).into_owned(),
                        l.fixed_rows::<3>(3).into_owned(),
                    )
                };
                let ((w, d), (wt, dt)) = (split(&v.line), split(t));
                let distance = w.norm() / d.norm() - wt.norm() / dt.norm();
                errors.lines.push((v.id, angle(&d, &dt), distance));
            }
        }
        let true_planes: HashMap<usize, _> = truth.planes.iter().map(|v| (v.id, v.plane)).collect();
        for v in &graph.planes {
            if let Some(t) = true_planes.get(&v.id) {
                let (n, nt) = (v.plane.xyz(), t.xyz());
                let offset = v.plane.w / n.norm() - t.w / nt.norm();
                errors.planes.push((v.id, angle(&n, &nt), offset));
            }
        }
        errors
    }

    /// RMS and largest translation and rotation errors of the poses.
    pub fn pose_summary(&self) -> [f64; 4] {
        let n = self.poses.len().max(1) as f64;
        let rms = |f: fn(&(f64, f64)) -> f64| {
            (self.poses.iter().map(|p| f(p).powi(2)).sum::<f64>() / n).sqrt()
        };
        let max = |f: fn(&(f64, f64)) -> f64| self.poses.iter().map(f).fold(0.0, f64::max);
        [rms(|p| p.0), max(|p| p.0), rms(|p| p.1), max(|p| p.1)]
    }

    /// Every figure, to check they are finite.
    fn figures(&self) -> impl Iterator<Item = f64> + '_ {
        self.pose_summary()
            .into_iter()
            .chain(self.lines.iter().flat_map(|l| [l.1, l.2]))
            .chain(self.planes.iter().flat_map(|p| [p.1, p.2]))
            .chain(self.offsets.iter().flat_map(|o| [o.1, o.2]))
    }

    /// The errors in words, with `before`'s beside them, or why they cannot
    /// be measured.
    fn describe(&self, before: &Errors, path: &Path) -> Result<String, String> {
        if let Some(x) = before
            .figures()
            .chain(self.figures())
            .find(|x| !x.is_finite())
        {
            return Err(format!(
                "an error against the ground truth {} is {x}: the estimates are too far from \
                 it to measure",
                shown_path(path)
            ));
        }
        let [t, tm, r, rm] = self.pose_summary();
        let [t0, tm0, r0, rm0] = before.pose_summary();
        let mut lines = vec![
            format!(
                "  errors against {} (no alignment), initially → finally:",
                shown_path(path)
            ),
            format!(
                "    {} poses: translation RMS {t0:.4} → {t:.4} m (max {tm0:.4} → {tm:.4}), \
                 rotation RMS {r0:.3} → {r:.3}° (max {rm0:.3} → {rm:.3})",
                self.poses.len()
            ),
        ];
        for ((id, da, dd), (_, da0, dd0)) in self.lines.iter().zip(&before.lines) {
            lines.push(format!(
                "    line {id}: direction {da0:.3} → {da:.3}°, distance {dd0:+.4} → {dd:+.4} m"
            ));
        }
        for ((id, da, dd), (_, da0, dd0)) in self.planes.iter().zip(&before.planes) {
            lines.push(format!(
                "    plane {id}: normal {da0:.3} → {da:.3}°, offset {dd0:+.4} → {dd:+.4} m"
            ));
        }
        for ((id, dt, dr), (_, dt0, dr0)) in self.offsets.iter().zip(&before.offsets) {
            lines.push(format!(
                "    sensor offset {id}: translation {dt0:.4} → {dt:.4} m, rotation {dr0:.3} → \
                 {dr:.3}°"
            ));
        }
        Ok(lines.join("\n"))
    }
}
