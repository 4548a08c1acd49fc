//! How this crate's own manifolds are served to apex-solver
//! ([`factor_core::host::HostMap<Apex>`]): what a user writes so that
//! factors over their types are solved in apex's own variables, with exact
//! Jacobians in apex's chart (generated `<factor>_apex` kernels, or dual
//! numbers).
//!
//! - [`UnitVector3`] (S², 2-dof) as apex's `Rn(3)`, normalised: `v = p/‖p‖`.
//!   apex has no S²; the three coordinates over-parametrise it by the
//!   radius, along which the residual does not change (a gauge direction
//!   the solver's damping holds).
//! - [`Sim3`] as apex's `SE3` (rotation and translation, right-retracted)
//!   and `Rn(1)` (the log-scale `σ`, additive): a product chart of Sim(3),
//!   not its group chart, whose Jacobians are exact in it.

use factor_core::Scalar;
use factor_core::host::{Apex, ApexManifold, HostMap, HostPart};
use factor_core::lie::Se3;

use crate::sim3::Sim3;
use crate::unit_vector::UnitVector3;

impl<S: Scalar> HostMap<Apex> for UnitVector3<S> {
    const PARTS: &'static [HostPart<ApexManifold>] = &[HostPart::whole(ApexManifold::Rn(3))];
    fn stored_from_host<T: Scalar>(host: &[T], stored: &mut [T]) {
        let norm = (host[0] * host[0] + host[1] * host[1] + host[2] * host[2]).sqrt();
        for (out, p) in stored.iter_mut().zip(host) {
            *out = *p / norm;
        }
    }
    fn host_from_stored(stored: &[f64], host: &mut [f64]) {
        host[..3].copy_from_slice(&stored[..3]);
    }
}

/// `Sim3` is stored `[qx, qy, qz, qw, tx, ty, tz, σ]`: the first seven are a
/// pose's, served as apex's `SE3` by `Se3`'s own mapping.
impl<S: Scalar> HostMap<Apex> for Sim3<S> {
    const PARTS: &'static [HostPart<ApexManifold>] = &[
        HostPart::named("pose", ApexManifold::Se3),
        HostPart::named("log_scale", ApexManifold::Rn(1)),
    ];
    fn stored_from_host<T: Scalar>(host: &[T], stored: &mut [T]) {
        <Se3<S> as HostMap<Apex>>::stored_from_host(&host[..7], &mut stored[..7]);
        stored[7] = host[7];
    }
    fn host_from_stored(stored: &[f64], host: &mut [f64]) {
        <Se3<S> as HostMap<Apex>>::host_from_stored(&stored[..7], &mut host[..7]);
        host[7] = stored[7];
    }
}
