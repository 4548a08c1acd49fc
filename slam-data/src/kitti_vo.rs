//! Stereo visual odometry on KITTI, as GTSAM ships it (`StereoVOExample_large`):
//! three files, one record per line.
//!
//! ```text
//! VO_calibration.txt           fx fy skew u0 v0 baseline
//! VO_camera_poses<S>.txt       id m₁₁ m₁₂ m₁₃ m₁₄ m₂₁ … m₄₄      (per pose)
//! VO_stereo_factors<S>.txt     pose landmark uL uR v X Y Z       (per observation)
//! ```
//!
//! The 4×4 matrix, row by row, is the camera-to-world pose (rotation within
//! [`crate::ROTATION_TOLERANCE`], last row exactly `0 0 0 1`). The camera
//! frame is the computer-vision one (x right, y down, z forward). An
//! observation gives the rectified stereo pixel `(uL, uR, v)` of a landmark
//! and `(X, Y, Z)`, the landmark in that pose's camera frame (triangulated,
//! for initialisation; `Z > 0`). The model, GTSAM's `Cal3_S2Stereo`, is in
//! [`StereoCalibration::project`]. Ids are arbitrary non-negative integers;
//! every observation's pose must be in the poses file.

use std::collections::{HashMap, HashSet};
use std::io::{BufRead, Write};
use std::path::{Path, PathBuf};

use nalgebra::{Isometry3, Matrix3, Translation3, UnitQuaternion, Vector3};

use crate::checks::{check_rotation_matrix, nearest_rotation};
use crate::error::{Error, ordinal};
use crate::input::all_in_range;
use crate::input::{self, Cursor, Lines};
use crate::output::{Real, commit, create, io_error};

/// Stereo intrinsics: `fx fy skew u0 v0 baseline` (pixels, and metres for
/// the baseline).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct StereoCalibration {
    /// Horizontal focal length.
    pub fx: f64,
    /// Vertical focal length.
    pub fy: f64,
    /// Skew.
    pub skew: f64,
    /// Principal point, horizontal.
    pub u0: f64,
    /// Principal point, vertical.
    pub v0: f64,
    /// Distance from the left to the right camera, along the left camera's x.
    pub baseline: f64,
}

impl StereoCalibration {
    /// `(uL, uR, v)` of a point `(x, y, z)` in the left camera's frame:
    /// `uL = fx x/z + skew y/z + u0`, `uR = uL − fx baseline / z`,
    /// `v = fy y/z + v0`; `None` unless `z > 0`.
    pub fn project(&self, p: &Vector3<f64>) -> Option<[f64; 3]> {
        if p.z <= 0.0 {
            return None;
        }
        let (x, y) = (p.x / p.z, p.y / p.z);
        let u_left = self.fx * x + self.skew * y + self.u0;
        Some([
            u_left,
            u_left - self.fx * self.baseline / p.z,
            self.fy * y + self.v0,
        ])
    }

    fn check(&self) -> Result<(), String> {
        let values = [self.fx, self.fy, self.skew, self.u0, self.v0, self.baseline];
        if !all_in_range(&values) {
            return Err("non-finite or too large calibration value".into());
        }
        for (name, value) in [
            ("fx", self.fx),
            ("fy", self.fy),
            ("baseline", self.baseline),
        ] {
            if value <= 0.0 {
                return Err(format!("{name} must be positive, found {value}"));
            }
        }
        Ok(())
    }
}

/// A camera pose: camera to world, as written.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct CameraPose {
    /// The pose's id.
    pub id: usize,
    /// Rotation, camera to world (within [`crate::ROTATION_TOLERANCE`] of a rotation).
    pub rotation: Matrix3<f64>,
    /// The camera's position in the world.
    pub translation: Vector3<f64>,
}

impl CameraPose {
    /// World-from-camera pose, with the rotation nearest to the written one.
    pub fn isometry(&self) -> Isometry3<f64> {
        Isometry3::from_parts(
            Translation3::from(self.translation),
            UnitQuaternion::from_rotation_matrix(&nearest_rotation(&self.rotation)),
        )
    }

    fn check(&self) -> Result<(), String> {
        if !all_in_range(self.rotation.iter().chain(self.translation.iter())) {
            return Err("non-finite or too large pose entry".into());
        }
        check_rotation_matrix(&self.rotation)
    }
}

/// One stereo observation of a landmark from a pose.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct StereoObservation {
    /// Id of the observing pose.
    pub pose: usize,
    /// Id of the landmark.
    pub landmark: usize,
    /// Left-image column.
    pub u_left: f64,
    /// Right-image column.
    pub u_right: f64,
    /// Row (both images, rectified).
    pub v: f64,
    /// The landmark in the pose's camera frame (triangulated; `z > 0`).
    pub landmark_in_camera: Vector3<f64>,
}

impl StereoObservation {
    fn check(&self) -> Result<(), String> {
        let values = [self.u_left, self.u_right, self.v];
        if !all_in_range(values.iter().chain(self.landmark_in_camera.iter())) {
            return Err("non-finite or too large observation value".into());
        }
        if self.landmark_in_camera.z <= 0.0 {
            return Err(format!(
                "the landmark must be in front of the camera, Z > 0; found Z = {}",
                self.landmark_in_camera.z
            ));
        }
        Ok(())
    }
}

/// A stereo visual-odometry problem: calibration, poses, observations.
#[derive(Debug, Clone, PartialEq)]
pub struct StereoVo {
    /// The stereo rig's intrinsics.
    pub calibration: StereoCalibration,
    /// The poses (initial values), in file order.
    pub poses: Vec<CameraPose>,
    /// The observations, in file order.
    pub observations: Vec<StereoObservation>,
}

impl StereoVo {
    /// Initial landmark positions as GTSAM's `StereoVOExample_large` makes
    /// them: each landmark, in order of first appearance, at its `(X, Y, Z)`
    /// of its first observation mapped to the world by that pose. (GTSAM
    /// uses the written 3×3 matrix, this the nearest rotation: they differ
    /// by at most [`crate::ROTATION_TOLERANCE`] relative.)
    pub fn initial_landmarks(&self) -> Vec<(usize, Vector3<f64>)> {
        let poses: HashMap<usize, Isometry3<f64>> =
            self.poses.iter().map(|p| (p.id, p.isometry())).collect();
        let mut seen = HashSet::new();
        self.observations
            .iter()
            .filter(|o| seen.insert(o.landmark))
            .filter_map(|o| {
                let pose = poses.get(&o.pose)?;
                Some((
                    o.landmark,
                    pose.transform_point(&o.landmark_in_camera.into()).coords,
                ))
            })
            .collect()
    }

    /// Fails, saying what is wrong, unless the problem is one a reader
    /// accepts.
    pub fn validate(&self) -> Result<(), String> {
        self.calibration
            .check()
            .map_err(|e| format!("calibration: {e}"))?;
        let mut ids = HashSet::with_capacity(self.poses.len());
        for (k, p) in self.poses.iter().enumerate() {
            let pose = || ordinal("pose", k, self.poses.len());
            p.check().map_err(|e| format!("{}: {e}", pose()))?;
            if !ids.insert(p.id) {
                return Err(format!("{}: id {} defined again", pose(), p.id));
            }
        }
        for (k, o) in self.observations.iter().enumerate() {
            let observation = || ordinal("observation", k, self.observations.len());
            o.check().map_err(|e| format!("{}: {e}", observation()))?;
            if !ids.contains(&o.pose) {
                return Err(format!(
                    "{}: pose {} is not in the poses",
                    observation(),
                    o.pose
                ));
            }
        }
        Ok(())
    }
}

/// The three files of a problem.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct VoFiles {
    /// `VO_calibration….txt`.
    pub calibration: PathBuf,
    /// `VO_camera_poses<S>.txt`.
    pub poses: PathBuf,
    /// `VO_stereo_factors<S>.txt`.
    pub factors: PathBuf,
}

const CALIBRATION: &str = "VO_calibration";
const POSES: &str = "VO_camera_poses";
const FACTORS: &str = "VO_stereo_factors";

impl VoFiles {
    /// The files of the problem `path` is one file of, to read: `path` is
    /// named `VO_calibration<S>.txt`, `VO_camera_poses<S>.txt` or
    /// `VO_stereo_factors<S>.txt` for a suffix `S` (`_large`), and the
    /// others are in the same folder; the calibration is
    /// `VO_calibration<S>.txt` if that exists, else `VO_calibration.txt`
    /// (GTSAM's `VO_calibration.txt` serves the `_large` set). Named by a
    /// shared `VO_calibration.txt` without poses of its own suffix, the
    /// problem is the one set in the folder it serves (the poses and
    /// factors whose suffix has no calibration of its own); when it serves
    /// several, name one by its poses or factors file.
    pub fn beside(path: &Path) -> Result<VoFiles, Error> {
        let (prefix, suffix) = Self::parts(path)?;
        let folder = path.parent().unwrap_or(Path::new(""));
        let files = Self::reading(folder, &suffix);
        if prefix != CALIBRATION || !suffix.is_empty() || files.poses.exists() {
            return Ok(files);
        }
        let served = Self::served_by_shared_calibration(folder);
        match served.as_slice() {
            [one] => Ok(Self::reading(folder, one)),
            [] => Err(Error::file(
                &path.display().to_string(),
                format!("no {POSES}*.txt beside it for this calibration to serve"),
            )),
            several => Err(Error::file(
                &path.display().to_string(),
                format!(
                    "this calibration serves {} problems here ({}): name one by its \
                     {POSES}*.txt or {FACTORS}*.txt file",
                    several.len(),
                    several
                        .iter()
                        .map(|s| format!("{POSES}{s}.txt"))
                        .collect::<Vec<_>>()
                        .join(", ")
                ),
            )),
        }
    }

    /// The files a problem named by `path` is written to: all three with
    /// `path`'s suffix (`--output VO_camera_poses_opt.txt` writes
    /// `VO_calibration_opt.txt`, `VO_camera_poses_opt.txt` and
    /// `VO_stereo_factors_opt.txt`), so that a written problem reads back
    /// with its own calibration and never overwrites a shared one.
    pub fn named(path: &Path) -> Result<VoFiles, Error> {
        let (_, suffix) = Self::parts(path)?;
        let folder = path.parent().unwrap_or(Path::new(""));
        Ok(VoFiles {
            calibration: folder.join(format!("{CALIBRATION}{suffix}.txt")),
            poses: folder.join(format!("{POSES}{suffix}.txt")),
            factors: folder.join(format!("{FACTORS}{suffix}.txt")),
        })
    }

    /// The three files, in the order read and written.
    pub fn all(&self) -> [&Path; 3] {
        [&self.calibration, &self.poses, &self.factors]
    }

    /// The prefix and the suffix `S` of a file of a problem.
    fn parts(path: &Path) -> Result<(&'static str, String), Error> {
        let name = path
            .file_name()
            .and_then(|n| n.to_str())
            .unwrap_or_default();
        [CALIBRATION, POSES, FACTORS]
            .into_iter()
            .find_map(|prefix| {
                let suffix = name.strip_prefix(prefix)?.strip_suffix(".txt")?;
                Some((prefix, suffix.to_owned()))
            })
            .ok_or_else(|| {
                Error::file(
                    &path.display().to_string(),
                    format!(
                        "a KITTI VO problem is named by one of its files: \
                         {CALIBRATION}*.txt, {POSES}*.txt or {FACTORS}*.txt"
                    ),
                )
            })
    }

    /// The files of the problem of suffix `suffix` in `folder`, to read.
    fn reading(folder: &Path, suffix: &str) -> VoFiles {
        let own = folder.join(format!("{CALIBRATION}{suffix}.txt"));
        VoFiles {
            calibration: if own.exists() {
                own
            } else {
                folder.join(format!("{CALIBRATION}.txt"))
            },
            poses: folder.join(format!("{POSES}{suffix}.txt")),
            factors: folder.join(format!("{FACTORS}{suffix}.txt")),
        }
    }

    /// The suffixes of the poses files in `folder` without a calibration of
    /// their own, sorted.
    fn served_by_shared_calibration(folder: &Path) -> Vec<String> {
        let listed = if folder.as_os_str().is_empty() {
            Path::new(".")
        } else {
            folder
        };
        let mut suffixes: Vec<String> = std::fs::read_dir(listed)
            .into_iter()
            .flatten()
            .flatten()
            .filter_map(|entry| {
                let name = entry.file_name().into_string().ok()?;
                let suffix = name.strip_prefix(POSES)?.strip_suffix(".txt")?;
                let own = folder.join(format!("{CALIBRATION}{suffix}.txt"));
                (!own.exists()).then(|| suffix.to_owned())
            })
            .collect();
        suffixes.sort();
        suffixes
    }
}

/// Reads the three files of a problem.
pub fn read(files: &VoFiles) -> Result<StereoVo, Error> {
    let (calibration, calibration_name) = input::open(&files.calibration)?;
    let (poses, poses_name) = input::open(&files.poses)?;
    let (factors, factors_name) = input::open(&files.factors)?;
    read_from(
        (calibration, &calibration_name),
        (poses, &poses_name),
        (factors, &factors_name),
    )
}

/// Reads a problem from three texts, each with its file name for errors.
pub fn from_texts(
    calibration: (&str, &str),
    poses: (&str, &str),
    factors: (&str, &str),
) -> Result<StereoVo, Error> {
    read_from(
        (calibration.0.as_bytes(), calibration.1),
        (poses.0.as_bytes(), poses.1),
        (factors.0.as_bytes(), factors.1),
    )
}

/// Reads a problem from three readers, each with its file name for errors.
pub fn read_from(
    calibration: (impl BufRead, &str),
    poses: (impl BufRead, &str),
    factors: (impl BufRead, &str),
) -> Result<StereoVo, Error> {
    let calibration = read_calibration(Lines::new(calibration.0, calibration.1))?;
    let poses = read_poses(Lines::new(poses.0, poses.1))?;
    let ids: HashSet<usize> = poses.iter().map(|p| p.id).collect();
    let observations = read_observations(Lines::new(factors.0, factors.1), &ids)?;
    Ok(StereoVo {
        calibration,
        poses,
        observations,
    })
}

fn read_calibration(mut lines: Lines<impl BufRead>) -> Result<StereoCalibration, Error> {
    let Some(line) = lines.next_record()? else {
        return Err(lines.error("empty calibration file: expected `fx fy skew u0 v0 baseline`"));
    };
    let mut fields = line.fields();
    let calibration = StereoCalibration {
        fx: fields.real("fx")?,
        fy: fields.real("fy")?,
        skew: fields.real("skew")?,
        u0: fields.real("u0")?,
        v0: fields.real("v0")?,
        baseline: fields.real("the baseline")?,
    };
    fields.finish()?;
    calibration.check().map_err(|e| line.error(e))?;
    if lines.next_record()?.is_some() {
        return Err(lines.error("unexpected second record: a calibration file has one line"));
    }
    Ok(calibration)
}

fn read_poses(mut lines: Lines<impl BufRead>) -> Result<Vec<CameraPose>, Error> {
    let mut poses = Vec::new();
    let mut ids = HashMap::new();
    while let Some(line) = lines.next_record()? {
        let mut fields = line.fields();
        let id = fields.integer("the pose id")?;
        let mut m = [[0.0; 4]; 4];
        for row in &mut m {
            for entry in row {
                *entry = fields.real("a pose matrix entry (16 expected)")?;
            }
        }
        fields.finish()?;
        if m[3] != [0.0, 0.0, 0.0, 1.0] {
            return Err(line.error(format!(
                "the last row of the pose matrix must be 0 0 0 1, found {:?}",
                m[3]
            )));
        }
        let pose = CameraPose {
            id,
            rotation: Matrix3::from_fn(|r, c| m[r][c]),
            translation: Vector3::new(m[0][3], m[1][3], m[2][3]),
        };
        pose.check().map_err(|e| line.error(e))?;
        if let Some(first) = ids.insert(id, line.number) {
            return Err(line.error(format!("pose {id} defined again (first at line {first})")));
        }
        poses.push(pose);
    }
    Ok(poses)
}

fn read_observations(
    mut lines: Lines<impl BufRead>,
    pose_ids: &HashSet<usize>,
) -> Result<Vec<StereoObservation>, Error> {
    let mut observations = Vec::new();
    while let Some(line) = lines.next_record()? {
        let mut fields = line.fields();
        let observation = StereoObservation {
            pose: fields.integer("the pose id")?,
            landmark: fields.integer("the landmark id")?,
            u_left: fields.real("uL")?,
            u_right: fields.real("uR")?,
            v: fields.real("v")?,
            landmark_in_camera: fields.vector3("a landmark coordinate (X Y Z)")?,
        };
        fields.finish()?;
        observation.check().map_err(|e| line.error(e))?;
        if !pose_ids.contains(&observation.pose) {
            return Err(line.error(format!(
                "pose {} is not in the poses file",
                observation.pose
            )));
        }
        observations.push(observation);
    }
    Ok(observations)
}

/// Writes `vo` to its three files: all three are written to temporary files
/// before the first is renamed into place, so a failure while writing any
/// of them leaves all three untouched.
pub fn write(vo: &StereoVo, files: &VoFiles) -> Result<(), Error> {
    vo.validate()
        .map_err(|what| Error::file(&files.factors.display().to_string(), what))?;
    let mut calibration = create(&files.calibration)?;
    write_calibration(&vo.calibration, &mut calibration.0)
        .map_err(|e| io_error(&calibration.1, e))?;
    let mut poses = create(&files.poses)?;
    write_poses(&vo.poses, &mut poses.0).map_err(|e| io_error(&poses.1, e))?;
    let mut factors = create(&files.factors)?;
    write_observations(&vo.observations, &mut factors.0).map_err(|e| io_error(&factors.1, e))?;
    commit(calibration)?;
    commit(poses)?;
    commit(factors)
}

/// Writes `vo` as three texts; each output comes with its name for errors.
/// Fails without writing if the problem does not [validate](StereoVo::validate).
pub fn write_to(
    vo: &StereoVo,
    calibration: (&mut impl Write, &str),
    poses: (&mut impl Write, &str),
    factors: (&mut impl Write, &str),
) -> Result<(), Error> {
    vo.validate().map_err(|what| Error::file(factors.1, what))?;
    write_calibration(&vo.calibration, calibration.0).map_err(|e| io_error(calibration.1, e))?;
    write_poses(&vo.poses, poses.0).map_err(|e| io_error(poses.1, e))?;
    write_observations(&vo.observations, factors.0).map_err(|e| io_error(factors.1, e))
}

fn write_calibration(c: &StereoCalibration, out: &mut impl Write) -> std::io::Result<()> {
    writeln!(
        out,
        "{} {} {} {} {} {}",
        Real(c.fx),
        Real(c.fy),
        Real(c.skew),
        Real(c.u0),
        Real(c.v0),
        Real(c.baseline)
    )
}

fn write_poses(poses: &[CameraPose], out: &mut impl Write) -> std::io::Result<()> {
    for p in poses {
        write!(out, "{}", p.id)?;
        for r in 0..3 {
            for c in 0..3 {
                write!(out, " {}", Real(p.rotation[(r, c)]))?;
            }
            write!(out, " {}", Real(p.translation[r]))?;
        }
        writeln!(out, " 0 0 0 1")?;
    }
    Ok(())
}

fn write_observations(
    observations: &[StereoObservation],
    out: &mut impl Write,
) -> std::io::Result<()> {
    for o in observations {
        let x = &o.landmark_in_camera;
        writeln!(
            out,
            "{} {} {} {} {} {} {} {}",
            o.pose,
            o.landmark,
            Real(o.u_left),
            Real(o.u_right),
            Real(o.v),
            Real(x.x),
            Real(x.y),
            Real(x.z)
        )?;
    }
    Ok(())
}
