//! apex-solver 1.5 as a host: its manifolds, their parameter layouts and
//! their right retractions, as apex-solver defines them (a description; this
//! crate does not depend on apex-solver).
//!
//! | manifold | parameters | tangent | retraction `x ⊞ δ` |
//! | --- | --- | --- | --- |
//! | `SE3` | `[tx, ty, tz, qw, qx, qy, qz]` | `[ρ, θ]` (6) | `T Exp([ρ, θ])`: `R ← R Exp(θ)`, `t ← t + R Jl(θ) ρ` |
//! | `SO3` | `[qw, qx, qy, qz]` | `θ` (3) | `q ⊗ exp(θ)` |
//! | `SO2` | `[angle]` | `δ` (1) | `angle + δ` |
//! | `Rn(n)` | the `n` values | `δ` (`n`) | `x + δ` |
//!
//! apex-solver keeps its quaternions unit (it normalises after each step).
//! Its other manifolds (SE2, Sim3, SE23, SGal3) are not needed by the types
//! this project ships; a user type needing one adds a variant here.
//!
//! # The types this project ships, served to apex
//!
//! Each type's [`HostMap<Apex>`](crate::host::HostMap): the apex variables
//! it becomes and how their parameters give its stored scalars. Whatever
//! side and tangent order a factor declares for a variable, its Jacobian
//! columns in apex are the apex variables' tangents, in this order.
//!
//! | type | as declared by the shipped factors | apex variables | stored scalars ← apex parameters |
//! | --- | --- | --- | --- |
//! | [`Se3`](crate::lie::Se3) (document 000's pose) | left, `[δω, δρ]` | `SE3`, `[ρ, θ]` | `[qx, qy, qz, qw, tx, ty, tz]` ← `[tx, ty, tz, qw, qx, qy, qz]` |
//! | [`Se3RhoTheta`](crate::lie::Se3RhoTheta) | right, `[δρ, δθ]` | `SE3`, `[ρ, θ]` | as `Se3` |
//! | [`So3`] | either side, `δ` | `SO3`, `θ` | `[qx, qy, qz, qw]` ← `[qw, qx, qy, qz]` |
//! | [`InfinitePlane`](crate::geometry::InfinitePlane) (the unit-quaternion plane) | left, `δω` | `SO3`, `θ` | `[a, b, c, d]` ← `[qw, qx, qy, qz]` (`a, b, c` the vector part) |
//! | [`OrthonormalLine`](crate::geometry::OrthonormalLine) `(U, W)` | left, `[δΘ, δρ]` | `SO3` (`u`) × `SO2` (`w`), `[θ, δ]` | `U`'s quaternion, `W = (cos, sin)` ← `[qw, qx, qy, qz]`, `[angle]` |
//! | [`FreeLine`](crate::geometry::FreeLine) `[q_WL, d_L]` | left, `[δθ, δd]` | `SO3` (`rotation`) × `Rn(1)` (`distance`) | `q_WL`, `d_L` |
//! | [`PluckerLine`](crate::geometry::PluckerLine) `[n, v]` | additive | `SO3` (`u`) × `SO2` (`w`), `[θ, δ]`: the orthonormal chart | `[n, v] = [(w₁/w₂) u₁, u₂]` (unit direction, `n` the moment) ← `U`, `W` of the line put on the Klein quadric |
//! | [`So2`](crate::lie::So2) | `δ` | `SO2` | `(cos, sin)` ← `[angle]` |
//! | `nalgebra` vectors and matrices, `f64` | additive | `Rn(n)` | the same |
//!
//! A type of one's own maps onto these with its own `HostMap<Apex>`: the
//! example crate `user-factors` serves its Sim(3) as `SE3 × Rn(1)` and its
//! S² direction as `Rn(3)`; [`crate::additive_maps!`] serves a vector-space
//! type as `Rn(n)` in one line.

use std::fmt;

use nalgebra::Vector3;

use crate::host::{Host, HostManifold};
use crate::lie::so3::left_jacobian;
use crate::lie::{Quaternion, So3};
use crate::scalar::Scalar;
use crate::storage::Layout;

/// apex-solver (crate `apex-solver` 1.5), retracting every manifold on the
/// right.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Apex;

impl Host for Apex {
    const NAME: &'static str = "apex";
    const SOLVER: &'static str = "apex-solver 1.5";
    const MANIFOLDS: &'static str = "SE3 [tx, ty, tz, qw, qx, qy, qz] with tangent [ρ, θ], \
        SO3 [qw, qx, qy, qz], SO2 [angle] and Rn, each retracted on the right";
    type Manifold = ApexManifold;
}

/// An apex-solver manifold.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum ApexManifold {
    /// `SE3`: `[tx, ty, tz, qw, qx, qy, qz]`, tangent `[ρ, θ]`.
    Se3,
    /// `SO3`: `[qw, qx, qy, qz]`, tangent `θ`.
    So3,
    /// `SO2`: `[angle]`, tangent `δ`.
    So2,
    /// `Rn(n)`: `n` values, additive.
    Rn(usize),
}

impl fmt::Display for ApexManifold {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            ApexManifold::Se3 => f.write_str("SE3"),
            ApexManifold::So3 => f.write_str("SO3"),
            ApexManifold::So2 => f.write_str("SO2"),
            ApexManifold::Rn(n) => write!(f, "Rn({n})"),
        }
    }
}

/// The quaternion stored `[w, x, y, z]` in `params`.
fn quaternion_wxyz<T: Scalar>(params: &[T]) -> Quaternion<T> {
    Quaternion::new(params[1], params[2], params[3], params[0])
}

/// Writes `q` as `[w, x, y, z]`.
fn write_wxyz<T: Scalar>(q: &Quaternion<T>, out: &mut [T]) {
    out[..4].copy_from_slice(&[q.w, q.x, q.y, q.z]);
}

impl HostManifold for ApexManifold {
    fn parameters(self) -> usize {
        match self {
            ApexManifold::Se3 => 7,
            ApexManifold::So3 => 4,
            ApexManifold::So2 => 1,
            ApexManifold::Rn(n) => n,
        }
    }

    fn dof(self) -> usize {
        match self {
            ApexManifold::Se3 => 6,
            ApexManifold::So3 => 3,
            ApexManifold::So2 => 1,
            ApexManifold::Rn(n) => n,
        }
    }

    fn parameter_layout(self) -> Layout {
        match self {
            ApexManifold::Se3 => Layout::array(&["tx", "ty", "tz", "qw", "qx", "qy", "qz"]),
            ApexManifold::So3 => Layout::array(&["qw", "qx", "qy", "qz"]),
            ApexManifold::So2 => Layout::array(&["angle"]),
            ApexManifold::Rn(n) => Layout::Array((0..n).map(|k| format!("x{k}")).collect()),
        }
    }

    fn tangent_description(self) -> &'static str {
        match self {
            ApexManifold::Se3 => {
                "right: T ← T Exp([ρ, θ]), columns [ρ_x, ρ_y, ρ_z, θ_x, θ_y, θ_z] (apex-solver's SE3)"
            }
            ApexManifold::So3 => {
                "right: q ← q ⊗ exp(θ), columns [θ_x, θ_y, θ_z] (apex-solver's SO3)"
            }
            ApexManifold::So2 => "angle ← angle + δ (apex-solver's SO2)",
            ApexManifold::Rn(_) => "additive: x ← x + δ (apex-solver's Rn)",
        }
    }

    /// `SE3`: `R ← R (I + θ^)`, `t ← t + R ρ` (the first-order part of
    /// `T Exp([ρ, θ])`); `SO3`: `q ⊗ [θ/2, 1]`.
    fn retract_first_order<T: Scalar>(self, params: &[T], delta: &[T], out: &mut [T]) {
        match self {
            ApexManifold::Se3 => {
                let q = quaternion_wxyz(&params[3..7]);
                let theta = Vector3::new(delta[3], delta[4], delta[5]);
                let rho = Vector3::new(delta[0], delta[1], delta[2]);
                let step = q.rotate(&rho);
                for k in 0..3 {
                    out[k] = params[k] + step[k];
                }
                write_wxyz(&q.mul(&Quaternion::exp_first_order(&theta)), &mut out[3..7]);
            }
            ApexManifold::So3 => {
                let q = quaternion_wxyz(params);
                let theta = Vector3::new(delta[0], delta[1], delta[2]);
                write_wxyz(&q.mul(&Quaternion::exp_first_order(&theta)), out);
            }
            ApexManifold::So2 => out[0] = params[0] + delta[0],
            ApexManifold::Rn(n) => {
                for k in 0..n {
                    out[k] = params[k] + delta[k];
                }
            }
        }
    }

    /// `SE3`: `T Exp([ρ, θ])` with the SE(3) exponential (`t ← t + R Jl(θ) ρ`);
    /// `SO3`: `q ⊗ exp(θ)`; the quaternions normalised as apex does.
    fn retract(self, params: &[f64], delta: &[f64], out: &mut [f64]) {
        match self {
            ApexManifold::Se3 => {
                let q = quaternion_wxyz(&params[3..7]);
                let theta = Vector3::new(delta[3], delta[4], delta[5]);
                let rho = Vector3::new(delta[0], delta[1], delta[2]);
                let step = So3::from_quaternion(q).rotate(&(left_jacobian(&theta) * rho));
                for k in 0..3 {
                    out[k] = params[k] + step[k];
                }
                write_wxyz(
                    &q.mul(&Quaternion::exp(&theta)).normalized(),
                    &mut out[3..7],
                );
            }
            ApexManifold::So3 => {
                let q = quaternion_wxyz(params);
                let theta = Vector3::new(delta[0], delta[1], delta[2]);
                write_wxyz(&q.mul(&Quaternion::exp(&theta)).normalized(), out);
            }
            ApexManifold::So2 | ApexManifold::Rn(_) => self.retract_first_order(params, delta, out),
        }
    }
}

/// Serves vector-space types to [`Apex`] as `Rn(n)` with the same scalars:
/// `additive_maps!(Type<S> => n; [S: Scalar])` implements
/// [`HostMap<Apex>`](crate::host::HostMap) for a type whose stored scalars
/// are retracted additively (`x ← x + δ`, in storage order), listing the
/// impl's generics in brackets.
///
/// ```
/// use factor_core::additive_maps;
/// use factor_core::Scalar;
///
/// /// `[f, k1, k2]`, retracted additively.
/// pub struct Radial<S> {
///     pub values: [S; 3],
/// }
/// additive_maps!(Radial<S> => 3; [S: Scalar]);
/// ```
#[macro_export]
macro_rules! additive_maps {
    ($($ty:ty => $n:expr; [$($generics:tt)*]),* $(,)?) => {$(
        impl<$($generics)*> $crate::host::HostMap<$crate::host::Apex> for $ty {
            const PARTS: &'static [$crate::host::HostPart<$crate::host::ApexManifold>] =
                &[$crate::host::HostPart::whole($crate::host::ApexManifold::Rn($n))];
            fn stored_from_host<T: $crate::Scalar>(host: &[T], stored: &mut [T]) {
                stored[..$n].copy_from_slice(&host[..$n]);
            }
            fn host_from_stored(stored: &[f64], host: &mut [f64]) {
                host[..$n].copy_from_slice(&stored[..$n]);
            }
        }
    )*};
}
