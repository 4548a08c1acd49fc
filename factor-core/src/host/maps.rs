//! How the types this crate ships are served by [`Apex`] (the table is in
//! [`crate::host::apex`]'s documentation).

use nalgebra::{SMatrix, Scalar as NalgebraScalar};

use crate::additive_maps;
use crate::geometry::{FreeLine, InfinitePlane, OrthonormalLine, PluckerLine};
use crate::host::{Apex, ApexManifold, HostMap, HostPart};
use crate::lie::{Se3, Se3RhoTheta, So2, So3};
use crate::scalar::Scalar;
use crate::storage::Storage;

/// `[qx, qy, qz, qw]` ← `[qw, qx, qy, qz]`.
fn xyzw_from_wxyz<T: Scalar>(host: &[T], stored: &mut [T]) {
    stored[..4].copy_from_slice(&[host[1], host[2], host[3], host[0]]);
}

/// `[qw, qx, qy, qz]` ← `[qx, qy, qz, qw]`.
fn wxyz_from_xyzw(stored: &[f64], host: &mut [f64]) {
    host[..4].copy_from_slice(&[stored[3], stored[0], stored[1], stored[2]]);
}

/// apex's `SE3` `[tx, ty, tz, qw, qx, qy, qz]` and a pose stored
/// `[qx, qy, qz, qw, tx, ty, tz]`.
macro_rules! pose_maps {
    ($($ty:ident),*) => {$(
        impl<S: Scalar> HostMap<Apex> for $ty<S> {
            const PARTS: &'static [HostPart<ApexManifold>] = &[HostPart::whole(ApexManifold::Se3)];
            fn stored_from_host<T: Scalar>(host: &[T], stored: &mut [T]) {
                xyzw_from_wxyz(&host[3..7], &mut stored[..4]);
                stored[4..7].copy_from_slice(&host[..3]);
            }
            fn host_from_stored(stored: &[f64], host: &mut [f64]) {
                host[..3].copy_from_slice(&stored[4..7]);
                wxyz_from_xyzw(&stored[..4], &mut host[3..7]);
            }
        }
    )*};
}

pose_maps!(Se3, Se3RhoTheta);

/// apex's `SO3` `[qw, qx, qy, qz]` and a unit quaternion stored
/// `[qx, qy, qz, qw]`.
macro_rules! rotation_maps {
    ($($ty:ident),*) => {$(
        impl<S: Scalar> HostMap<Apex> for $ty<S> {
            const PARTS: &'static [HostPart<ApexManifold>] = &[HostPart::whole(ApexManifold::So3)];
            fn stored_from_host<T: Scalar>(host: &[T], stored: &mut [T]) {
                xyzw_from_wxyz(host, stored);
            }
            fn host_from_stored(stored: &[f64], host: &mut [f64]) {
                wxyz_from_xyzw(stored, host);
            }
        }
    )*};
}

rotation_maps!(So3, InfinitePlane);

impl<S: Scalar> HostMap<Apex> for So2<S> {
    const PARTS: &'static [HostPart<ApexManifold>] = &[HostPart::whole(ApexManifold::So2)];
    fn stored_from_host<T: Scalar>(host: &[T], stored: &mut [T]) {
        stored[..2].copy_from_slice(&[host[0].cos(), host[0].sin()]);
    }
    fn host_from_stored(stored: &[f64], host: &mut [f64]) {
        host[0] = stored[1].atan2(stored[0]);
    }
}

/// `U` as `SO3` and `W` as `SO2`.
impl<S: Scalar> HostMap<Apex> for OrthonormalLine<S> {
    const PARTS: &'static [HostPart<ApexManifold>] = &[
        HostPart::named("u", ApexManifold::So3),
        HostPart::named("w", ApexManifold::So2),
    ];
    fn stored_from_host<T: Scalar>(host: &[T], stored: &mut [T]) {
        So3::<S>::stored_from_host(&host[..4], &mut stored[..4]);
        So2::<S>::stored_from_host(&host[4..5], &mut stored[4..6]);
    }
    fn host_from_stored(stored: &[f64], host: &mut [f64]) {
        So3::<S>::host_from_stored(&stored[..4], &mut host[..4]);
        So2::<S>::host_from_stored(&stored[4..6], &mut host[4..5]);
    }
}

/// `q_WL` as `SO3` and `d_L` as `Rn(1)`.
impl<S: Scalar> HostMap<Apex> for FreeLine<S> {
    const PARTS: &'static [HostPart<ApexManifold>] = &[
        HostPart::named("rotation", ApexManifold::So3),
        HostPart::named("distance", ApexManifold::Rn(1)),
    ];
    fn stored_from_host<T: Scalar>(host: &[T], stored: &mut [T]) {
        xyzw_from_wxyz(&host[..4], &mut stored[..4]);
        stored[4] = host[4];
    }
    fn host_from_stored(stored: &[f64], host: &mut [f64]) {
        wxyz_from_xyzw(&stored[..4], &mut host[..4]);
        host[4] = stored[4];
    }
}

/// The orthonormal chart, as [`OrthonormalLine`]: `U` as `SO3` (`u`), `W`
/// as `SO2` (`w`), never a free `Rn(6)` (which leaves the Klein quadric
/// `n · v = 0` and carries the scale of `[n, v]`, on which no residual
/// depends). The stored `[n, v]` is `[(w₁/w₂) u₁, u₂]`: the unit direction
/// and the moment `p × v` of any point `p` of the line, `|n|` its distance
/// from the origin ([`OrthonormalLine::moment`], [`OrthonormalLine::direction`]).
/// A Plücker line is homogeneous, so this scale loses nothing; a value read
/// in is put on the quadric first (its direction kept, its normal without
/// the component along the direction).
impl<S: Scalar> HostMap<Apex> for PluckerLine<S> {
    const PARTS: &'static [HostPart<ApexManifold>] = <OrthonormalLine<S> as HostMap<Apex>>::PARTS;
    fn stored_from_host<T: Scalar>(host: &[T], stored: &mut [T]) {
        let mut chart = [host[0]; 6];
        OrthonormalLine::<S>::stored_from_host(host, &mut chart);
        let line = OrthonormalLine::<T>::from_scalars(&chart);
        stored[..3].copy_from_slice(line.moment().as_slice());
        stored[3..6].copy_from_slice(line.direction().as_slice());
    }
    fn host_from_stored(stored: &[f64], host: &mut [f64]) {
        let line = OrthonormalLine::projected_from_plucker(&PluckerLine::from_scalars(stored));
        OrthonormalLine::<S>::host_from_stored(&line.to_scalars(), host);
    }
}

additive_maps!(
    f64 => 1; [],
    SMatrix<S, R, C> => R * C; [S: Scalar + NalgebraScalar, const R: usize, const C: usize]
);
