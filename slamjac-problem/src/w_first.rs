//! The hint for quaternions written `[w, x, y, z]` (Eigen's coefficient
//! order) where `[x, y, z, w]` is expected. Such a quaternion is a valid but
//! different rotation, so it surfaces far from its cause, as a degenerate
//! configuration (a point "behind the camera"). The rule: when a factor's
//! `validate()` rejects the input, each input quaternion is read `[w, x, y, z]`
//! in turn, and the hint names those for which the input then validates; when
//! none does alone but all of them read so together do, it names them all.

use crate::input::QuaternionReading;

/// The w-first hint for an input that a factor's `validate()` rejected and
/// whose quaternions were read at the paths `quaternions`, where the rule of
/// the module docs finds one (`None` where it does not). `validates` says
/// whether the same input validates reading its quaternions as the given
/// reading says.
pub fn hint(
    quaternions: &[String],
    validates: impl Fn(&QuaternionReading) -> bool,
) -> Option<String> {
    let validates_w_first = |w_first: &[String]| validates(&QuaternionReading::w_first(w_first));
    let mut named: Vec<&str> = quaternions
        .iter()
        .filter(|path| validates_w_first(std::slice::from_ref(*path)))
        .map(String::as_str)
        .collect();
    if named.is_empty() && quaternions.len() > 1 && validates_w_first(quaternions) {
        named = quaternions.iter().map(String::as_str).collect();
    }
    if named.is_empty() {
        return None;
    }
    let verb = if named.len() == 1 { "looks" } else { "look" };
    Some(format!(
        "{} {verb} w-first: quaternions are [x, y, z, w]",
        named.join(", ")
    ))
}
