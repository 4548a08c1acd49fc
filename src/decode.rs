//! Each factor's `variables` and `constants` objects → the factor value
//! (SPEC.md, "The `eval` JSON interface").
//!
//! Checks made here, each reported at its field path (exit 2): shapes and
//! types, finiteness, unit quaternions (within
//! [`crate::input::QUATERNION_NORM_TOLERANCE`], then re-normalised), zero-norm
//! plane, line and bearing vectors, zero focal lengths, and the Plücker
//! constraint `n · v = 0`. What only the factor can judge (a point behind the
//! camera, parallel bearings, ...) is left to its `validate()`.

use factor_core::Factor;
use factor_core::geometry::{FreeLine, InfinitePlane, Intrinsics, OrthonormalLine, PluckerLine};
use slam_factors::{
    FreeLineFactor, LineReprojection, PlaneFactor, PluckerLineReprojection, PointReprojection,
};

use crate::error::InputError;
use crate::input::{Object, QUATERNION_NORM_TOLERANCE};

/// The JSON shape of the pose objects.
const POSE: &str = "{\"rotation\": [x, y, z, w], \"translation\": [tx, ty, tz]}";
/// The JSON shape of the intrinsics.
const INTRINSICS: &str = "[fu, fv, cu, cv]";

/// A factor that can be read from the `eval` JSON.
pub trait FromJson: Factor {
    /// The fields of `variables` and their JSON shapes, in the factor's
    /// declaration order (the names of [`Factor::variables`]).
    const VARIABLES: &'static [(&'static str, &'static str)];
    /// The fields of `constants` and their JSON shapes.
    const CONSTANTS: &'static [(&'static str, &'static str)];

    /// The factor from its checked `variables` and `constants` objects.
    fn from_json(variables: &Object, constants: &Object) -> Result<Self, InputError>;
}

/// `[fu, fv, cu, cv]` with non-zero focal lengths.
fn intrinsics(constants: &Object, key: &str) -> Result<Intrinsics<f64>, InputError> {
    let k = constants.vector::<4>(key)?;
    for (i, name) in [(0, "f_u"), (1, "f_v")] {
        if k[i] == 0.0 {
            return Err(InputError::new(
                format!("{}[{i}]", constants.path_of(key)),
                format!("focal length {name} is zero"),
            ));
        }
    }
    Ok(Intrinsics::new(k[0], k[1], k[2], k[3]))
}

impl FromJson for PointReprojection {
    const VARIABLES: &'static [(&'static str, &'static str)] =
        &[("pose", POSE), ("point", "[X, Y, Z]")];
    const CONSTANTS: &'static [(&'static str, &'static str)] =
        &[("intrinsics", INTRINSICS), ("observed", "[u, v]")];

    fn from_json(variables: &Object, constants: &Object) -> Result<Self, InputError> {
        let pose = variables.pose("pose")?;
        let point = variables.vector::<3>("point")?;
        Ok(PointReprojection {
            intrinsics: intrinsics(constants, "intrinsics")?,
            observed: constants.vector::<2>("observed")?,
            pose,
            point,
        })
    }
}

impl FromJson for LineReprojection {
    const VARIABLES: &'static [(&'static str, &'static str)] = &[
        ("pose", POSE),
        (
            "line",
            "{\"normal\": n [3], \"direction\": v [3]} (Plücker, any scale)",
        ),
    ];
    const CONSTANTS: &'static [(&'static str, &'static str)] = &[
        ("intrinsics", INTRINSICS),
        ("start", "[u, v]"),
        ("end", "[u, v]"),
    ];

    fn from_json(variables: &Object, constants: &Object) -> Result<Self, InputError> {
        let pose = variables.pose("pose")?;
        let line = variables.object("line", &["normal", "direction"])?;
        let normal = line.nonzero_vector::<3>(
            "normal",
            "line normal n (the line must not pass through the world origin)",
        )?;
        let direction = line.nonzero_vector::<3>("direction", "line direction v")?;
        let line = OrthonormalLine::try_from_plucker(&PluckerLine::new(normal, direction))
            .map_err(|e| InputError::new(variables.path_of("line"), e.to_string()))?;
        Ok(LineReprojection {
            intrinsics: intrinsics(constants, "intrinsics")?,
            start: constants.vector::<2>("start")?,
            end: constants.vector::<2>("end")?,
            pose,
            line,
        })
    }
}

impl FromJson for PluckerLineReprojection {
    const VARIABLES: &'static [(&'static str, &'static str)] = &[
        ("pose", POSE),
        (
            "line",
            "{\"normal\": n [3], \"direction\": v [3]} (Plücker, any scale)",
        ),
    ];
    const CONSTANTS: &'static [(&'static str, &'static str)] = LineReprojection::CONSTANTS;

    fn from_json(variables: &Object, constants: &Object) -> Result<Self, InputError> {
        let pose = variables.pose("pose")?;
        let line = variables.object("line", &["normal", "direction"])?;
        let normal = line.vector::<3>("normal")?;
        let direction = line.nonzero_vector::<3>("direction", "line direction v")?;
        Ok(PluckerLineReprojection {
            intrinsics: intrinsics(constants, "intrinsics")?,
            start: constants.vector::<2>("start")?,
            end: constants.vector::<2>("end")?,
            pose,
            line: PluckerLine::new(normal, direction),
        })
    }
}

impl FromJson for PlaneFactor {
    const VARIABLES: &'static [(&'static str, &'static str)] =
        &[("pose", POSE), ("plane", "[a, b, c, d] (world, any scale)")];
    const CONSTANTS: &'static [(&'static str, &'static str)] =
        &[("measured", "[a, b, c, d] (camera, any scale)")];

    fn from_json(variables: &Object, constants: &Object) -> Result<Self, InputError> {
        let pose = variables.pose("pose")?;
        let plane = variables.nonzero_vector::<4>("plane", "plane vector [a, b, c, d]")?;
        let plane = InfinitePlane::try_from_coefficients(&plane)
            .map_err(|e| InputError::new(variables.path_of("plane"), e.to_string()))?;
        Ok(PlaneFactor {
            measured: constants.nonzero_vector::<4>("measured", "plane vector [a, b, c, d]")?,
            pose,
            plane,
        })
    }
}

impl FromJson for FreeLineFactor {
    const VARIABLES: &'static [(&'static str, &'static str)] = &[
        ("body_pose", POSE),
        (
            "line",
            "{\"rotation\": q_WL [x, y, z, w], \"distance\": d_L}",
        ),
    ];
    const CONSTANTS: &'static [(&'static str, &'static str)] = &[
        ("extrinsics", POSE),
        ("bearing_start", "[x, y, z]"),
        ("bearing_end", "[x, y, z]"),
    ];

    fn from_json(variables: &Object, constants: &Object) -> Result<Self, InputError> {
        let body_pose = variables.pose("body_pose")?;
        let line = variables.object("line", &["rotation", "distance"])?;
        let line = FreeLine::try_new(
            line.quaternion("rotation")?,
            line.number("distance")?,
            QUATERNION_NORM_TOLERANCE,
        )
        .map_err(|e| InputError::new(variables.path_of("line"), e.to_string()))?;
        Ok(FreeLineFactor {
            extrinsics: constants.pose("extrinsics")?,
            bearing_start: constants.nonzero_vector::<3>("bearing_start", "bearing vector")?,
            bearing_end: constants.nonzero_vector::<3>("bearing_end", "bearing vector")?,
            body_pose,
            line,
        })
    }
}
