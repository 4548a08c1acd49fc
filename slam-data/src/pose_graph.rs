//! 3D pose graphs: poses with ids, relative-pose edges with 6×6
//! information matrices, and the odometry chain that initialises them.
//!
//! Information matrices are held in the tangent order `[δω, δρ]` (rotation
//! first), GTSAM's order for `Pose3`; [`crate::g2o`] reorders g2o's.

use std::collections::HashMap;
use std::collections::hash_map::Entry;

use nalgebra::{Isometry3, Matrix6, Translation3, UnitQuaternion, Vector3};

use crate::checks::{check_information, check_quaternion, unit_quaternion};
use crate::error::ordinal;
use crate::input::all_in_range;

/// A rotation as a pose-graph file writes it.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Rotation {
    /// Quaternion coefficients `[x, y, z, w]` as written (Hamilton, active);
    /// their norm is within [`crate::QUATERNION_TOLERANCE`] of one and
    /// [`Rotation::unit_quaternion`] renormalises.
    Quaternion([f64; 4]),
    /// `[roll, pitch, yaw]` in radians: `R = Rz(yaw) Ry(pitch) Rx(roll)`
    /// (GTSAM's `Rot3::Ypr(yaw, pitch, roll)`).
    RollPitchYaw([f64; 3]),
}

impl Rotation {
    /// The rotation as a unit quaternion.
    pub fn unit_quaternion(&self) -> UnitQuaternion<f64> {
        match self {
            Rotation::Quaternion(q) => unit_quaternion(q),
            Rotation::RollPitchYaw([roll, pitch, yaw]) => {
                UnitQuaternion::from_euler_angles(*roll, *pitch, *yaw)
            }
        }
    }

    /// `[x, y, z, w]`: as written for a quaternion, converted otherwise.
    pub(crate) fn quaternion_coefficients(&self) -> [f64; 4] {
        match self {
            Rotation::Quaternion(q) => *q,
            Rotation::RollPitchYaw(_) => {
                let q = self.unit_quaternion();
                [q.i, q.j, q.k, q.w]
            }
        }
    }

    /// `[roll, pitch, yaw]`: as written for angles, converted otherwise.
    pub(crate) fn roll_pitch_yaw(&self) -> [f64; 3] {
        match self {
            Rotation::RollPitchYaw(angles) => *angles,
            Rotation::Quaternion(_) => {
                let (roll, pitch, yaw) = self.unit_quaternion().euler_angles();
                [roll, pitch, yaw]
            }
        }
    }

    fn check(&self) -> Result<(), String> {
        match self {
            Rotation::Quaternion(q) if !all_in_range(q) => {
                Err("non-finite or too large quaternion".into())
            }
            Rotation::Quaternion(q) => check_quaternion(q),
            Rotation::RollPitchYaw(angles) if !all_in_range(angles) => {
                Err("non-finite or too large angle".into())
            }
            Rotation::RollPitchYaw(_) => Ok(()),
        }
    }
}

impl From<UnitQuaternion<f64>> for Rotation {
    fn from(q: UnitQuaternion<f64>) -> Self {
        Rotation::Quaternion([q.i, q.j, q.k, q.w])
    }
}

/// A pose `T = (R, t)`, mapping points of its frame to the parent frame.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Pose {
    /// `t`.
    pub translation: Vector3<f64>,
    /// `R`.
    pub rotation: Rotation,
}

impl Pose {
    /// The pose as an isometry.
    pub fn isometry(&self) -> Isometry3<f64> {
        Isometry3::from_parts(
            Translation3::from(self.translation),
            self.rotation.unit_quaternion(),
        )
    }

    pub(crate) fn check(&self) -> Result<(), String> {
        if !all_in_range(self.translation.iter()) {
            return Err("non-finite or too large translation".into());
        }
        self.rotation.check()
    }
}

impl From<Isometry3<f64>> for Pose {
    fn from(pose: Isometry3<f64>) -> Self {
        Pose {
            translation: pose.translation.vector,
            rotation: pose.rotation.into(),
        }
    }
}

/// A pose variable and its value (the initial estimate).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Vertex {
    /// The id edges refer to.
    pub id: usize,
    /// World-from-body pose.
    pub pose: Pose,
}

/// A relative-pose measurement `T_from⁻¹ T_to ≈ measurement`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Edge {
    /// Id of the first pose.
    pub from: usize,
    /// Id of the second pose.
    pub to: usize,
    /// The measured pose of `to` in the frame of `from`.
    pub measurement: Pose,
    /// Information matrix (inverse covariance) in tangent order `[δω, δρ]`,
    /// symmetric positive definite.
    pub information: Matrix6<f64>,
}

impl Edge {
    /// Fails, saying why, unless the measurement is a valid pose, the
    /// information matrix finite, symmetric and positive definite, and the
    /// edge joins two different poses.
    pub(crate) fn check(&self) -> Result<(), String> {
        self.measurement.check()?;
        check_information(&self.information)?;
        if self.from == self.to {
            return Err(format!("edge from pose {} to itself", self.from));
        }
        Ok(())
    }
}

/// A 3D pose graph: what a g2o or EDGE3 file holds.
#[derive(Debug, Clone, PartialEq, Default)]
pub struct PoseGraph {
    /// The poses, in file order (may be empty: EDGE3 files often have none).
    pub vertices: Vec<Vertex>,
    /// The edges, in file order.
    pub edges: Vec<Edge>,
}

/// The element of a pose graph a defect is in.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(crate) enum Item {
    Vertex(usize),
    Edge(usize),
}

impl PoseGraph {
    /// Fails, saying what is wrong, unless the graph is one a reader
    /// accepts: values finite, quaternions unit within tolerance,
    /// information matrices symmetric positive definite, vertex ids
    /// distinct, no edge from a pose to itself and, when there are vertices,
    /// every edge between two of them.
    pub fn validate(&self) -> Result<(), String> {
        match self.find_defect() {
            None => Ok(()),
            Some((Item::Vertex(k), what)) => Err(format!(
                "{}: {what}",
                ordinal("vertex", k, self.vertices.len())
            )),
            Some((Item::Edge(k), what)) => {
                Err(format!("{}: {what}", ordinal("edge", k, self.edges.len())))
            }
        }
    }

    /// The first defect [`PoseGraph::validate`] looks for, and where it is.
    pub(crate) fn find_defect(&self) -> Option<(Item, String)> {
        let mut ids = HashMap::with_capacity(self.vertices.len());
        for (k, v) in self.vertices.iter().enumerate() {
            if let Err(what) = v.pose.check() {
                return Some((Item::Vertex(k), what));
            }
            match ids.entry(v.id) {
                Entry::Occupied(first) => {
                    let what = format!(
                        "vertex id {} defined again (first as {})",
                        v.id,
                        ordinal("vertex", *first.get(), self.vertices.len())
                    );
                    return Some((Item::Vertex(k), what));
                }
                Entry::Vacant(slot) => {
                    slot.insert(k);
                }
            }
        }
        for (k, e) in self.edges.iter().enumerate() {
            let defect = e.check().and_then(|()| {
                match [e.from, e.to].iter().find(|id| !ids.contains_key(id)) {
                    Some(missing) if !ids.is_empty() => {
                        Err(format!("pose {missing} is not a vertex"))
                    }
                    _ => Ok(()),
                }
            });
            if let Err(what) = defect {
                return Some((Item::Edge(k), what));
            }
        }
        None
    }

    /// Initial values by chaining odometry: the smallest pose id of the
    /// edges at the identity, then each next id `i + 1` composed from pose
    /// `i` through the first edge `i → i + 1` (or the inverse of the first
    /// `i + 1 → i`), as GTSAM's examples initialise `sphere2500`. Every id
    /// between the smallest and the largest must be chained.
    pub fn odometry_initial_values(&self) -> Result<Vec<Vertex>, ChainError> {
        let endpoints = self.edges.iter().flat_map(|e| [e.from, e.to]);
        let (Some(first), Some(last)) = (endpoints.clone().min(), endpoints.max()) else {
            return Err(ChainError::NoEdges);
        };
        // The first odometry edge between each `i` and `i + 1`, keyed by `i`.
        let mut odometry = HashMap::new();
        for e in &self.edges {
            if e.from.abs_diff(e.to) == 1 {
                odometry.entry(e.from.min(e.to)).or_insert(e);
            }
        }
        let mut pose = Isometry3::identity();
        let mut vertices = vec![Vertex {
            id: first,
            pose: pose.into(),
        }];
        for id in first..last {
            let edge = odometry.get(&id).ok_or(ChainError::MissingOdometry {
                from: id,
                to: id + 1,
            })?;
            let step = edge.measurement.isometry();
            pose *= if edge.from == id {
                step
            } else {
                step.inverse()
            };
            vertices.push(Vertex {
                id: id + 1,
                pose: pose.into(),
            });
        }
        Ok(vertices)
    }
}

/// Why odometry chaining cannot initialise a pose graph.
#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error)]
#[non_exhaustive]
pub enum ChainError {
    /// The graph has no edges.
    #[error("the pose graph has no edges to chain")]
    NoEdges,
    /// No edge joins two consecutive ids.
    #[error("no odometry edge between poses {from} and {to}")]
    MissingOdometry {
        /// The pose reached so far.
        from: usize,
        /// The next pose.
        to: usize,
    },
}
