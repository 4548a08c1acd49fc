//! Values of this project's types as apex-solver variables, through their
//! [`HostMap<Apex>`] ([`factor_core::host`]).
//!
//! Which apex manifolds a type is served as is stated once, by its mapping
//! (for the shipped types, in `factor_core::host`'s documentation): a pose of
//! either side and tangent order is one `SE3`, `So3` and the unit-quaternion
//! plane an `SO3`, the orthonormal line `(U, W)` and the Plücker line
//! `[n, v]` (through its orthonormal chart) an `SO3` and an `SO2`, the
//! free line `[q_WL, d_L]` an `SO3` and an `Rn(1)`, vectors `Rn`. A type
//! without a mapping is refused at compile time.

use apex_solver::ManifoldType;
use factor_core::Storage;
use factor_core::host::{Apex, ApexManifold, HostManifold, HostMap, HostPart};

/// apex-solver's [`ManifoldType`] of `manifold`.
pub fn manifold_type(manifold: ApexManifold) -> ManifoldType {
    match manifold {
        ApexManifold::Se3 => ManifoldType::SE3,
        ApexManifold::So3 => ManifoldType::SO3,
        ApexManifold::So2 => ManifoldType::SO2,
        ApexManifold::Rn(_) => ManifoldType::RN,
    }
}

/// The apex parameters of `value`, one vector per host part of its type
/// ([`HostMap::PARTS`]), quaternions normalised (apex keeps its quaternions
/// unit; a file's six-decimal quaternions are not quite unit, and the
/// rotation they stand for is the normalised one).
pub fn to_apex<V: HostMap<Apex> + Storage<f64>>(value: &V) -> Vec<Vec<f64>> {
    let parts = V::PARTS;
    let mut host = vec![0.0; parts.iter().map(|p| p.manifold.parameters()).sum()];
    V::host_from_stored(&value.to_scalars(), &mut host);
    split_parts(parts, &host)
}

/// The host parameters `host` of a value (its parts' concatenated) as one
/// vector per part, quaternions normalised (see [`to_apex`]).
pub(crate) fn split_parts(parts: &[HostPart<ApexManifold>], host: &[f64]) -> Vec<Vec<f64>> {
    let mut rest = host;
    parts
        .iter()
        .map(|part| {
            let (head, tail) = rest.split_at(part.manifold.parameters());
            rest = tail;
            let mut params = head.to_vec();
            normalise_quaternion(part.manifold, &mut params);
            params
        })
        .collect()
}

/// The value of type `V` whose apex parameters are `parts` (one slice per
/// host part, as [`to_apex`] gives them).
///
/// # Panics
///
/// If the number or the lengths of the slices are not `V`'s parts'.
pub fn from_apex<V: HostMap<Apex> + Storage<f64>>(parts: &[&[f64]]) -> V {
    assert_eq!(
        parts.len(),
        V::PARTS.len(),
        "one parameter slice per host part"
    );
    let host: Vec<f64> = parts.iter().flat_map(|p| p.iter().copied()).collect();
    let mut stored = vec![0.0; V::SCALARS];
    V::stored_from_host(&host, &mut stored);
    V::from_scalars(&stored)
}

/// Normalises the quaternion of an `SE3` or `SO3` parameter block.
fn normalise_quaternion(manifold: ApexManifold, params: &mut [f64]) {
    let quaternion = match manifold {
        ApexManifold::Se3 => &mut params[3..7],
        ApexManifold::So3 => &mut params[..4],
        ApexManifold::So2 | ApexManifold::Rn(_) => return,
    };
    let norm = quaternion.iter().map(|x| x * x).sum::<f64>().sqrt();
    if norm > 0.0 && norm.is_finite() {
        quaternion.iter_mut().for_each(|x| *x /= norm);
    }
}

/// The `SE3` parameters `[tx, ty, tz, qw, qx, qy, qz]` of a pose (either
/// pose type), its quaternion normalised.
pub fn apex_pose<V: HostMap<Apex> + Storage<f64>>(pose: &V) -> Vec<f64> {
    let mut parts = to_apex(pose);
    assert_eq!(parts.len(), 1, "a pose is one SE3");
    parts.remove(0)
}

/// The pose of apex's `SE3` parameters `[tx, ty, tz, qw, qx, qy, qz]`
/// ([`apex_pose`]'s inverse): the pose reader the data-set keys'
/// write-backs are given here.
pub fn apex_se3(parameters: &[f64]) -> factor_core::lie::Se3<f64> {
    from_apex(&[parameters])
}
