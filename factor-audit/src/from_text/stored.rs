//! Stored values: a factor's fields (or parts of them) and sampled free
//! variables, as the symbols file names them. What a stored value is comes
//! from its layout ([`Storage::layout`], the one storage vocabulary): a
//! pose, a rotation, a plane, a line, or a vector of named scalars. That
//! decides how its scalars become a value of a formula and how it is
//! perturbed ([`Manifold::retract`], on either side).

use nalgebra::Vector3;

use super::value::{ShapeError, Value};
use factor_core::geometry::{FreeLine, InfinitePlane, OrthonormalLine, PluckerLine};
use factor_core::lie::{Quaternion, Se3, So3};
use factor_core::manifold::{Manifold, Perturbation};
use factor_core::scalar::Scalar;
use factor_core::storage::{Layout, Storage};
use factor_testing::samples::Sampler;

/// What a stored value is.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Kind {
    /// One scalar.
    Scalar,
    /// Named scalars (`[x, y, z]`, `[fu, fv, cu, cv]`), additive.
    Vector(usize),
    /// A `rows × columns` matrix stored column by column, additive.
    Matrix(usize, usize),
    /// A unit quaternion `[qx, qy, qz, qw]` read as a rotation.
    Rotation,
    /// A pose `{rotation, translation}`.
    Pose,
    /// An infinite plane `[a, b, c, d]` (a unit quaternion), a 4-vector.
    Plane,
    /// A Plücker line `{normal, direction}`, a 6-vector.
    Plucker,
    /// An orthonormal line `{u, w}`.
    OrthonormalLine,
    /// A free line `{rotation, distance}`.
    FreeLine,
    /// Another record: only its parts are values.
    Record(usize),
}

fn layout_of<T: Storage<f64>>() -> Layout {
    T::layout()
}

impl Kind {
    /// The kind of a value stored with this layout.
    pub fn of(layout: &Layout) -> Kind {
        let known = [
            (layout_of::<Se3<f64>>(), Kind::Pose),
            (layout_of::<So3<f64>>(), Kind::Rotation),
            (layout_of::<InfinitePlane<f64>>(), Kind::Plane),
            (layout_of::<PluckerLine<f64>>(), Kind::Plucker),
            (layout_of::<OrthonormalLine<f64>>(), Kind::OrthonormalLine),
            (layout_of::<FreeLine<f64>>(), Kind::FreeLine),
        ];
        if let Some((_, kind)) = known.iter().find(|(l, _)| l == layout) {
            return *kind;
        }
        match layout {
            Layout::Scalar => Kind::Scalar,
            Layout::Array(names) => Kind::Vector(names.len()),
            Layout::Record(_) => Kind::Record(layout.scalars()),
        }
    }

    /// How many scalars it stores.
    pub fn scalars(self) -> usize {
        match self {
            Kind::Scalar => 1,
            Kind::Vector(n) | Kind::Record(n) => n,
            Kind::Matrix(r, c) => r * c,
            Kind::Rotation | Kind::Plane => 4,
            Kind::Pose => 7,
            Kind::Plucker | Kind::OrthonormalLine => 6,
            Kind::FreeLine => 5,
        }
    }

    /// Its tangent dimension (the Jacobian's columns).
    pub fn tangent_dim(self) -> usize {
        match self {
            Kind::Rotation | Kind::Plane => 3,
            Kind::Pose => 6,
            Kind::OrthonormalLine | Kind::FreeLine => 4,
            other => other.scalars(),
        }
    }

    /// Whether it is perturbed by adding to its scalars (no side).
    pub fn is_additive(self) -> bool {
        matches!(
            self,
            Kind::Scalar | Kind::Vector(_) | Kind::Matrix(..) | Kind::Plucker
        )
    }

    /// The value of a formula it stands for.
    pub fn value<S: Scalar>(self, stored: &[S]) -> Result<Value<S>, ShapeError> {
        Ok(match self {
            Kind::Scalar | Kind::Vector(_) | Kind::Plane | Kind::Plucker => Value::column(stored),
            Kind::Matrix(r, c) => Value::Matrix(nalgebra::DMatrix::from_column_slice(r, c, stored)),
            Kind::Rotation => Value::Rotation(So3::from_scalars(stored)),
            Kind::Pose => Value::Pose(Se3::from_scalars(stored)),
            Kind::OrthonormalLine => Value::OrthonormalLine(OrthonormalLine::from_scalars(stored)),
            Kind::FreeLine => Value::FreeLine(FreeLine::from_scalars(stored)),
            Kind::Record(_) => {
                return Err(ShapeError(
                    "a record of several values is not one value; name one of its parts".into(),
                ));
            }
        })
    }

    /// `stored` perturbed by `delta` on `side` (added, for an additive kind).
    pub fn retract<S: Scalar>(self, stored: &[S], delta: &[S], side: Perturbation) -> Vec<S> {
        fn on<S: Scalar, T: Storage<S> + Manifold<S>>(
            stored: &[S],
            delta: &[S],
            side: Perturbation,
        ) -> Vec<S> {
            T::from_scalars(stored).retract(delta, side).to_scalars()
        }
        match self {
            Kind::Rotation => on::<S, So3<S>>(stored, delta, side),
            Kind::Pose => on::<S, Se3<S>>(stored, delta, side),
            Kind::Plane => on::<S, InfinitePlane<S>>(stored, delta, side),
            Kind::OrthonormalLine => on::<S, OrthonormalLine<S>>(stored, delta, side),
            Kind::FreeLine => on::<S, FreeLine<S>>(stored, delta, side),
            _ => stored.iter().zip(delta).map(|(x, d)| *x + *d).collect(),
        }
    }
}

/// The part of a layout at a dotted path (`rotation`, `intrinsics.fu`):
/// its offset in the stored scalars and its layout.
pub fn part(layout: &Layout, path: &str) -> Option<(usize, Layout)> {
    let mut offset = 0;
    let mut layout = layout.clone();
    for key in path.split('.').filter(|k| !k.is_empty()) {
        let (skip, next) = match &layout {
            Layout::Record(parts) => {
                let i = parts.iter().position(|(k, _)| *k == key)?;
                let skip = parts[..i].iter().map(|(_, p)| p.scalars()).sum();
                (skip, parts[i].1.clone())
            }
            Layout::Array(names) => (names.iter().position(|n| n == key)?, Layout::Scalar),
            Layout::Scalar => return None,
        };
        offset += skip;
        layout = next;
    }
    Some((offset, layout))
}

/// A free variable the symbols file asks to be sampled (no factor holds it).
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum FreeSample {
    /// A rotation vector of angle in `(0.05, 3)`.
    RotationVector,
    /// A unit quaternion `exp(ω)` of such a rotation vector.
    UnitQuaternion,
    /// A 3-vector of norm at least 0.1 (each coordinate in `[−3, 3)`).
    Vector3,
    /// A uniformly distributed rotation.
    Rotation,
    /// A pose: a uniform rotation and a translation in `[−2, 2)³`.
    Pose,
    /// A vector of `size` entries, each uniform in `range`.
    Vector {
        /// Entries.
        size: usize,
        /// Where each is drawn.
        range: [f64; 2],
    },
    /// A scalar uniform in `range`.
    Scalar {
        /// Where it is drawn.
        range: [f64; 2],
    },
    /// A `rows × columns` matrix of entries uniform in `range` (a general
    /// matrix: no structure).
    Matrix {
        /// Rows.
        rows: usize,
        /// Columns.
        cols: usize,
        /// Where each entry is drawn.
        range: [f64; 2],
    },
}

/// The range of a `vector` or `scalar` sample when the file gives none.
pub const DEFAULT_RANGE: [f64; 2] = [-1.0, 1.0];
/// Most entries of a sampled `vector`.
pub const MAX_VECTOR_SIZE: usize = 32;
/// Most rows (and columns) of a sampled `matrix`.
pub const MAX_MATRIX_SIDE: usize = 12;

impl FreeSample {
    /// The names a symbols file uses, with their samplers (and `vector`,
    /// `scalar`, which take a `size` and a `range`).
    pub const ALL: [(&'static str, FreeSample); 5] = [
        ("rotation_vector", FreeSample::RotationVector),
        ("unit_quaternion", FreeSample::UnitQuaternion),
        ("vector3", FreeSample::Vector3),
        ("rotation", FreeSample::Rotation),
        ("pose", FreeSample::Pose),
    ];

    /// Every sampler name, for messages.
    pub fn all_names() -> String {
        let mut names: Vec<&str> = Self::ALL.iter().map(|(n, _)| *n).collect();
        names.extend(["vector", "scalar", "matrix"]);
        names.join(", ")
    }

    /// The sampler named `name`, with the `size` and `range` a `vector` or
    /// `scalar` takes and the `shape` of a `matrix`; an error says what is
    /// wrong.
    pub fn from_spec(
        name: &str,
        size: Option<usize>,
        shape: Option<[usize; 2]>,
        range: Option<[f64; 2]>,
    ) -> Result<Self, String> {
        let range = range.unwrap_or(DEFAULT_RANGE);
        if !(range[0].is_finite() && range[1].is_finite() && range[0] < range[1]) {
            return Err(format!("the range [{}, {}] is empty", range[0], range[1]));
        }
        match (name, shape) {
            ("matrix", Some([r, c]))
                if (1..=MAX_MATRIX_SIDE).contains(&r) && (1..=MAX_MATRIX_SIDE).contains(&c) =>
            {
                return Ok(FreeSample::Matrix {
                    rows: r,
                    cols: c,
                    range,
                });
            }
            ("matrix", _) => {
                return Err(format!(
                    "a `matrix` sample needs a `shape = [rows, columns]` of 1 to {MAX_MATRIX_SIDE} each"
                ));
            }
            (_, Some(_)) => return Err("`shape` goes with a `matrix` sample".into()),
            _ => {}
        }
        let sized = matches!(name, "vector");
        match (name, size) {
            ("vector", Some(n)) if (1..=MAX_VECTOR_SIZE).contains(&n) => {
                Ok(FreeSample::Vector { size: n, range })
            }
            ("vector", _) => Err(format!(
                "a `vector` sample needs a `size` of 1 to {MAX_VECTOR_SIZE}"
            )),
            ("scalar", None) => Ok(FreeSample::Scalar { range }),
            (_, Some(_)) if !sized => Err("`size` goes with a `vector` sample".into()),
            _ => Self::ALL
                .iter()
                .find(|(n, _)| *n == name)
                .map(|(_, s)| *s)
                .ok_or_else(|| format!("no sampler `{name}` (samplers: {})", Self::all_names())),
        }
    }

    /// The layout of what it samples.
    pub fn layout(self) -> Layout {
        match self {
            FreeSample::RotationVector | FreeSample::Vector3 => layout_of::<Vector3<f64>>(),
            FreeSample::UnitQuaternion => layout_of::<Quaternion<f64>>(),
            FreeSample::Rotation => layout_of::<So3<f64>>(),
            FreeSample::Pose => layout_of::<Se3<f64>>(),
            FreeSample::Vector { size, .. } => {
                Layout::Array((1..=size).map(|i| i.to_string()).collect())
            }
            FreeSample::Scalar { .. } => Layout::Scalar,
            FreeSample::Matrix { rows, cols, .. } => Layout::Array(
                (0..rows * cols)
                    .map(|k| format!("{}{}", k % rows + 1, k / rows + 1))
                    .collect(),
            ),
        }
    }

    /// The kind of what it samples (a unit quaternion is a 4-vector).
    pub fn kind(self) -> Kind {
        match self {
            FreeSample::UnitQuaternion => Kind::Vector(4),
            FreeSample::Matrix { rows, cols, .. } => Kind::Matrix(rows, cols),
            other => Kind::of(&other.layout()),
        }
    }

    /// One draw, as stored scalars.
    pub fn draw(self, s: &mut Sampler) -> Vec<f64> {
        let rotation_vector = |s: &mut Sampler| {
            let axis = s.vector3(1.0).normalize();
            axis * s.uniform(0.05, 3.0)
        };
        match self {
            FreeSample::RotationVector => rotation_vector(s).to_scalars(),
            FreeSample::UnitQuaternion => Quaternion::exp(&rotation_vector(s)).to_scalars(),
            FreeSample::Vector3 => loop {
                let w = s.vector3(3.0);
                if w.norm() > 0.1 {
                    return w.to_scalars();
                }
            },
            FreeSample::Rotation => s.rotation().to_scalars(),
            FreeSample::Pose => s.pose().to_scalars(),
            FreeSample::Vector { size, range } => {
                (0..size).map(|_| s.uniform(range[0], range[1])).collect()
            }
            FreeSample::Scalar { range } => vec![s.uniform(range[0], range[1])],
            FreeSample::Matrix { rows, cols, range } => (0..rows * cols)
                .map(|_| s.uniform(range[0], range[1]))
                .collect(),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use factor_core::Factor;
    use slam_factors::PointReprojection;

    #[test]
    fn kinds_and_parts_come_from_layouts() {
        assert_eq!(Kind::of(&layout_of::<Se3<f64>>()), Kind::Pose);
        assert_eq!(Kind::of(&layout_of::<Vector3<f64>>()), Kind::Vector(3));
        let layout = PointReprojection::<f64>::layout();
        let (offset, rotation) = part(&layout, "pose.rotation").unwrap();
        assert_eq!(Kind::of(&rotation), Kind::Rotation);
        let fields = PointReprojection::<f64>::fields();
        let pose = fields.iter().position(|f| f.name == "pose").unwrap();
        let before: usize = fields[..pose].iter().map(|f| f.scalars).sum();
        assert_eq!(offset, before);
        assert_eq!(part(&layout, "intrinsics.fv").unwrap().0, 1);
        assert!(part(&layout, "pose.nothing").is_none());
    }

    #[test]
    fn retractions_follow_the_side() {
        let pose = Sampler::new(1).pose();
        let delta = [0.1, 0.2, 0.3, 0.0, 0.0, 0.0];
        let left = Kind::Pose.retract(&pose.to_scalars(), &delta, Perturbation::Left);
        let right = Kind::Pose.retract(&pose.to_scalars(), &delta, Perturbation::Right);
        assert_ne!(left, right);
        assert_eq!(
            Kind::Vector(2).retract(&[1.0, 2.0], &[0.5, 0.5], Perturbation::Left),
            [1.5, 2.5]
        );
    }
}
