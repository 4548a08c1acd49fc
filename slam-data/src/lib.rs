//! Readers and writers of real SLAM data sets, a seeded synthetic BAL
//! generator and a seeded point-line-plane scene generator. Plain
//! `nalgebra` types; no dependency on the rest of the workspace.
//!
//! # Formats
//!
//! | format ([`Format`]) | module | holds | problem type |
//! | --- | --- | --- | --- |
//! | `bal` | [`bal`] | Bundle Adjustment in the Large: cameras `[ω, t, f, k1, k2]`, points, observations | [`BalProblem`] |
//! | `bundler` | [`bundler`] | Bundler v0.3 `bundle.out`: cameras `f k1 k2, R, t`, points with colours and views | [`BundlerProblem`] |
//! | `g2o` | [`g2o`] | `VERTEX_SE3:QUAT`, `EDGE_SE3:QUAT` pose graphs | [`PoseGraph`] |
//! | `g2o-addons` ([`g2o::read_graph`]) | [`g2o`] | g2o's 3D lines, planes and points beside the poses: `VERTEX_LINE3D`, `VERTEX_PLANE`, `VERTEX_TRACKXYZ`, `EDGE_SE3_LINE3D`, `EDGE_SE3_PLANE_CALIB`, `EDGE_SE3_TRACKXYZ`, `EDGE_SE3_PRIOR`, `PARAMS_SE3OFFSET`, `FIX` | [`G2oGraph`] |
//! | `edge3` | [`edge3`] | `VERTEX3`, `EDGE3` pose graphs (`sphere2500`) | [`PoseGraph`] |
//! | `kitti-vo` | [`kitti_vo`] | GTSAM's KITTI stereo VO: calibration, camera poses, stereo observations | [`StereoVo`] |
//!
//! Each module has `read(path)`, `read_from(reader, name)`,
//! `from_text(text, name)`, `write(problem, path)` and
//! `write_to(problem, out, name)` (KITTI VO takes its three files together).
//! [`Problem::read`] reads any of them, the format given or told by the
//! file's name ([`Format::from_name`]) or else by its content
//! ([`Format::from_content`]: `.txt` is ambiguous), opening and reading the
//! input once, so that a pipe (`/dev/stdin`) reads as a file does
//! ([`Problem::read_from`] reads any stream). [`Problem::write`] writes one
//! back in its format, each file to a temporary file renamed into place
//! once complete, so a failed write leaves the old file as it was.
//! [`Problem::files_read`] and [`Problem::files_written`] name the files a
//! path stands for (three for KITTI VO) without touching them, for a
//! command to check its outputs against its inputs before any work. Values
//! are kept exactly as read and written as the shortest decimals that read
//! back to the same doubles, so read → write → read gives the same problem
//! bit for bit.
//!
//! # Conventions
//!
//! - **BAL and Bundler cameras** ([`camera`]): `P = R X + t` (world to
//!   camera), the camera looking down **−z** (y up): `p = −P / P_z`,
//!   `r = 1 + k1 ‖p‖² + k2 ‖p‖⁴`, pixel `f r p`, origin at the image centre,
//!   x right, y up. BAL writes `R` as an angle-axis vector (`R = exp([ω]×)`),
//!   Bundler as a matrix, row by row. [`SnavelyCamera::world_from_camera_cv`]
//!   converts to the computer-vision convention GTSAM uses (x right, y down,
//!   z forward; pixel `(u, −v)`).
//! - **Pose graphs**: a vertex is a world-from-body pose; an edge `i j`
//!   measures `T_i⁻¹ T_j`. Quaternions are Hamilton, stored `[x, y, z, w]`
//!   as written (g2o order). `EDGE3` angles give `R = Rz(yaw) Ry(pitch)
//!   Rx(roll)`, as GTSAM's `Rot3::Ypr`. Information matrices are returned in
//!   tangent order **`[δω, δρ]`** (rotation first): g2o's, written in
//!   `[δt, δq]` order, have their 3×3 blocks swapped, as GTSAM does;
//!   `EDGE3`'s are taken unchanged, as GTSAM does (see [`edge3`] for iSAM's
//!   different reading). Pose graphs without vertices are initialised by
//!   [`PoseGraph::odometry_initial_values`].
//! - **KITTI VO**: poses are camera-to-world 4×4 matrices (computer-vision
//!   camera frame); an observation is `(uL, uR, v)` with the landmark in the
//!   observing camera's frame, from which [`StereoVo::initial_landmarks`]
//!   initialises landmarks as GTSAM's example does.
//!
//! # Limits and tolerances
//!
//! - Files over [`MAX_FILE_BYTES`] (4 GiB) and lines over
//!   [`MAX_LINE_BYTES`] (64 MiB) are rejected; input must be UTF-8. The
//!   format is told from at most the first [`SNIFF_BYTES`] (1 MiB).
//! - Counts in headers are not trusted: at most 65 536 items are reserved
//!   ahead, the rest grows as items are actually read, and a body that
//!   disagrees with its header is an error at the line where it shows.
//! - Numbers must be finite doubles of magnitude at most [`MAX_MAGNITUDE`]
//!   (1e100; `1e999`, `1e101`, `nan`, `inf` are errors);
//!   counts, indices and ids non-negative integers; indices in range; focal
//!   lengths, stereo focal lengths and baseline positive; colours 0–255.
//! - A 3×3 rotation is accepted when every entry of `RᵀR − I` and
//!   `det R − 1` is within [`ROTATION_TOLERANCE`] (1e-5) of zero and kept
//!   as written; `camera()`/`isometry()` use the nearest rotation.
//! - A quaternion is accepted when its norm is within
//!   [`QUATERNION_TOLERANCE`] (1e-5) of one, and renormalised when used
//!   ([`Rotation::unit_quaternion`]).
//! - Information matrices must be positive definite (a Cholesky
//!   factorisation exists; that of g2o's `EDGE_SE3_PRIOR` positive
//!   semi-definite and not zero, as g2o's planar-motion simulator writes
//!   it); vertex and pose ids must be distinct; edges may
//!   not join a pose to itself and, when the file has vertices, must join
//!   two of them.
//! - Unknown record tags are errors, not skipped.
//!
//! Every error is one line, `FILE:LINE: what` ([`Error`]), unprintable
//! characters of the input escaped; items are counted from 1 (`observation
//! 3 of 19`, `camera 1 of 5`), indices and ids shown as the file writes them.
//!
//! # Synthetic problems
//!
//! [`synthetic::generate`] makes a seeded BAL problem (cameras on a ring
//! looking at a ball of points, Gaussian pixel noise, uniform outliers,
//! perturbed initial values), with its ground truth, and
//! [`synthetic::write()`] streams the same problem to a file in memory that
//! does not grow with the points; see [`synthetic`].
//! [`plp_scene::generate`] makes a seeded point-line-plane scene (a room or
//! a corridor: planes, line segments on them, points, a camera trajectory)
//! with its ground truth, perturbed initial values and the measurements the
//! documents' point, line and plane factors take; see [`plp_scene`].

pub mod bal;
pub mod bundler;
pub mod camera;
mod checks;
pub mod edge3;
mod error;
mod format;
pub mod g2o;
pub mod g2o_graph;
mod g2o_graph_file;
mod graph_file;
mod input;
pub mod kitti_vo;
mod output;
pub mod plp_scene;
pub mod pose_graph;
mod problem;
pub mod synthetic;

pub use bal::{BalCamera, BalProblem, Observation};
pub use bundler::{BundlerCamera, BundlerObservation, BundlerPoint, BundlerProblem};
pub use camera::{SnavelyCamera, SnavelyIntrinsics};
pub use checks::{QUATERNION_TOLERANCE, ROTATION_TOLERANCE};
pub use error::{Error, ordinal};
pub use format::{Format, SNIFF_BYTES, UnknownFormat};
pub use g2o_graph::{
    G2oGraph, LineEdge, LineVertex, PlaneEdge, PlaneVertex, PointEdge, PointVertex, PriorEdge,
    Se3Offset, VertexKind,
};
pub use input::{MAX_FILE_BYTES, MAX_LINE_BYTES, MAX_MAGNITUDE};
pub use kitti_vo::{CameraPose, StereoCalibration, StereoObservation, StereoVo, VoFiles};
pub use pose_graph::{ChainError, Edge, Pose, PoseGraph, Rotation, Vertex};
pub use problem::Problem;
