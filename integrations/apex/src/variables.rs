//! How a factor's variables meet apex-solver's: which apex manifold each one
//! is, and how apex's parameter block maps to the stored scalars a
//! generated kernel reads.
//!
//! | factor variable | apex variable | apex parameters | stored scalars |
//! | --- | --- | --- | --- |
//! | `Se3RhoTheta<S>`, `#[variable(right)]` | `SE3` | `[tx, ty, tz, qw, qx, qy, qz]` | `[qx, qy, qz, qw, tx, ty, tz]` |
//! | an additive vector of `n` scalars | `Rn(n)` | the `n` scalars | the same |
//!
//! The tangents then agree without conversion: apex retracts `SE3` on the
//! right with the tangent `[ρ, θ]` (`T ⊕ τ = T Exp(τ)`), which is
//! `Se3RhoTheta`'s right perturbation to first order, and `Rn` additively.
//! Any other variable (a left-perturbed pose, this project's `Se3` with its
//! `[δω, δρ]` tangent, a quaternion, a line) is refused: serving it would
//! need the adjoint or a permutation at every call, where declaring it in
//! apex's chart makes the generated kernel emit apex's columns directly.

use factor_core::lie::{Se3, Se3RhoTheta};
use factor_core::manifold::{Manifold, Perturbation};
use factor_core::{Factor, Layout, Storage};
use nalgebra::Vector3;

use crate::AdapterError;

/// The apex-solver manifold a factor variable is served as.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum ApexManifold {
    /// `SE3`: 7 parameters, 6 tangent coordinates `[ρ, θ]`.
    Se3,
    /// `Rn(n)`: `n` parameters, additive.
    Rn(usize),
}

impl ApexManifold {
    /// apex-solver's [`ManifoldType`](apex_solver::ManifoldType) for it.
    pub fn manifold_type(self) -> apex_solver::ManifoldType {
        match self {
            ApexManifold::Se3 => apex_solver::ManifoldType::SE3,
            ApexManifold::Rn(_) => apex_solver::ManifoldType::RN,
        }
    }

    /// The number of apex parameters.
    pub fn parameters(self) -> usize {
        match self {
            ApexManifold::Se3 => 7,
            ApexManifold::Rn(n) => n,
        }
    }

    /// The tangent dimension.
    pub fn dof(self) -> usize {
        match self {
            ApexManifold::Se3 => 6,
            ApexManifold::Rn(n) => n,
        }
    }

    /// Writes the stored scalars of the variable whose apex parameters are
    /// `apex` into `stored` (no allocation).
    pub fn stored_from_apex(self, apex: &[f64], stored: &mut [f64]) {
        match self {
            ApexManifold::Se3 => {
                stored[..4].copy_from_slice(&[apex[4], apex[5], apex[6], apex[3]]);
                stored[4..7].copy_from_slice(&apex[..3]);
            }
            ApexManifold::Rn(n) => stored[..n].copy_from_slice(&apex[..n]),
        }
    }

    /// The apex parameters of the variable stored as `stored`.
    pub fn apex_from_stored(self, stored: &[f64]) -> Vec<f64> {
        match self {
            ApexManifold::Se3 => vec![
                stored[4], stored[5], stored[6], stored[3], stored[0], stored[1], stored[2],
            ],
            ApexManifold::Rn(n) => stored[..n].to_vec(),
        }
    }
}

/// apex-solver's `SE3` parameters `[tx, ty, tz, qw, qx, qy, qz]` of a pose,
/// its quaternion normalised (apex keeps it unit by normalising after each
/// step; a file's six-decimal quaternions are not quite unit).
pub fn apex_pose(pose: &Se3<f64>) -> Vec<f64> {
    let q = pose.rotation.quaternion.normalized();
    let t = pose.translation;
    vec![t.x, t.y, t.z, q.w, q.x, q.y, q.z]
}

/// The pose of apex-solver's `SE3` parameters.
pub fn pose_from_apex(apex: &[f64]) -> Se3<f64> {
    let mut stored = [0.0; 7];
    ApexManifold::Se3.stored_from_apex(apex, &mut stored);
    Se3::from_scalars(&stored)
}

/// The position part of apex-solver's `Rn(3)` parameters.
pub fn point_from_apex(apex: &[f64]) -> Vector3<f64> {
    Vector3::new(apex[0], apex[1], apex[2])
}

/// The apex manifold of each variable of `F`, in declaration order, with the
/// offset of its stored scalars in the factor's storage; an error naming the
/// first variable apex-solver cannot serve with the same tangent.
pub fn classify<F: Factor>() -> Result<Vec<(ApexManifold, usize)>, AdapterError> {
    let variables = F::variables();
    let mut offset = 0;
    let mut out = Vec::with_capacity(variables.len());
    for field in F::fields() {
        if let Some(k) = field.variable {
            let info = &variables[k];
            let pose_layout = <Se3<f64> as Storage<f64>>::layout();
            let apex_chart =
                <Se3RhoTheta<f64> as Manifold<f64>>::tangent_description(Perturbation::Right);
            let manifold = if field.layout == pose_layout
                && info.tangent_dim == 6
                && info.perturbation == Perturbation::Right
                && info.tangent == apex_chart
            {
                ApexManifold::Se3
            } else if matches!(field.layout, Layout::Array(_) | Layout::Scalar)
                && field.scalars == info.tangent_dim
                && info.tangent.starts_with("additive")
            {
                ApexManifold::Rn(field.scalars)
            } else {
                return Err(AdapterError::Unsupported {
                    factor: F::NAME,
                    variable: info.name,
                    type_name: info.type_name,
                    tangent: info.tangent,
                });
            };
            out.push((manifold, offset));
        }
        offset += field.scalars;
    }
    Ok(out)
}
