//! The hint for quaternions written `[w, x, y, z]` (Eigen's coefficient
//! order) where `[x, y, z, w]` is expected. Such a quaternion is a valid but
//! different rotation, so it surfaces far from its cause, as a degenerate
//! configuration (a point "behind the camera"). The rule: when a factor's
//! `validate()` rejects the input, each input quaternion is read `[w, x, y, z]`
//! in turn, and the hint names those for which the input then validates; when
//! none does alone but all of them read so together do, it names them all.

use factor_core::FactorError;

use crate::error::CliError;
use crate::input::QuaternionReading;

/// `error` (a factor's `validate()` error for an input whose quaternions were
/// read at the paths `quaternions`), with the w-first hint where the rule of
/// the module docs finds one. `evaluate` evaluates the same input reading
/// its quaternions as given.
pub fn with_hint<T>(
    error: FactorError,
    quaternions: &[String],
    evaluate: impl Fn(&QuaternionReading) -> Result<T, CliError>,
) -> CliError {
    // Validation passed when the evaluation succeeded or failed only after it.
    let validates = |w_first: &[String]| {
        matches!(
            evaluate(&QuaternionReading::w_first(w_first)),
            Ok(_) | Err(CliError::Factor(FactorError::NonFinite { .. }))
        )
    };
    let mut named: Vec<&str> = quaternions
        .iter()
        .filter(|path| validates(std::slice::from_ref(*path)))
        .map(String::as_str)
        .collect();
    if named.is_empty() && quaternions.len() > 1 && validates(quaternions) {
        named = quaternions.iter().map(String::as_str).collect();
    }
    if named.is_empty() {
        return CliError::Factor(error);
    }
    let verb = if named.len() == 1 { "looks" } else { "look" };
    CliError::Hinted {
        error,
        hint: format!(
            "{} {verb} w-first: quaternions are [x, y, z, w]",
            named.join(", ")
        ),
    }
}
