//! A [`Problem`]: variables (their stored scalars, held fixed or eliminated)
//! and factors of any derived type, grouped by type: those with fused
//! normal-equation kernels linearized in lane batches ([`Problem::add`]),
//! any other one factor at a time ([`Problem::add_linearized`]).

use std::any::{Any, TypeId};

use factor_core::noise::Noise;
use factor_core::{Factor, WithKernel};
use factor_lanes::NormalKernel;
use factor_minimizer::Damping;
use slam_problems::Kernels;
use slam_problems::Robust;

use crate::error::SchurError;
use crate::group::{FactorGroup, Group};
pub use crate::layout::Lane;
use crate::layout::{Chart, MAX_SCALARS, MAX_SLOTS, Variable};
pub use crate::linearization::{Jacobians, Linearized};
use crate::structure::Structure;

/// A variable of a [`Problem`].
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub struct VariableId(pub(crate) u32);

impl VariableId {
    /// Its index, in the order the variables were added.
    pub fn index(self) -> usize {
        self.0 as usize
    }
}

/// Which group a factor type goes to: its type, and how the group
/// linearizes (`None`: the batch kernels).
type GroupKey = (TypeId, Option<Jacobians>);

/// A nonlinear least-squares problem, `Σ ½ ρ(‖rᵢ‖²)` over factors of
/// derived types, in the shape a Schur complement solves: some variables
/// are eliminated (landmarks), and no factor touches two of them.
///
/// Variables hold the stored scalars of the type their factors declare
/// ([`factor_core::Storage`] order); each is retracted by that type's
/// [`factor_core::manifold::Manifold::retract`] on the side its factors
/// declare, and every factor on a variable must declare the same type,
/// side and tangent ([`SchurError::Chart`] otherwise).
#[derive(Default)]
pub struct Problem {
    /// Every variable's stored scalars, end to end.
    pub(crate) values: Vec<f64>,
    pub(crate) variables: Vec<Variable>,
    pub(crate) groups: Vec<Box<dyn Group>>,
    group_types: Vec<GroupKey>,
    pub(crate) robust: Option<Robust>,
    pub(crate) damping: Damping,
}

impl Problem {
    /// An empty problem (plain least squares).
    pub fn new() -> Self {
        Problem::default()
    }

    /// The structure of the reduced system ([`Structure::build`]): reorders
    /// the factors and the stored values as it lays them out.
    pub(crate) fn structure(&mut self) -> Result<Structure, SchurError> {
        Structure::build(&mut self.variables, &mut self.values, &mut self.groups)
    }

    /// A robust loss on every factor without its own, or plain least
    /// squares.
    pub fn set_robust(&mut self, robust: Option<Robust>) {
        self.robust = robust;
    }

    /// How Levenberg–Marquardt damps the steps ([`Damping::Diagonal`] by
    /// default, as the general path; [`Damping::Uniform`] for a problem in
    /// one unit system, a pose graph).
    pub fn set_damping(&mut self, damping: Damping) {
        self.damping = damping;
    }

    /// A variable whose value is `stored` (the stored scalars of the type
    /// its factors declare).
    pub fn add_variable(&mut self, stored: &[f64]) -> VariableId {
        let id = VariableId(u32::try_from(self.variables.len()).expect("fewer than 2³² variables"));
        self.variables.push(Variable {
            offset: self.values.len(),
            scalars: stored.len(),
            fixed: false,
            eliminated: false,
            chart: None,
        });
        self.values.extend_from_slice(stored);
        id
    }

    /// Holds `id` at its value.
    pub fn fix(&mut self, id: VariableId) {
        self.variables[id.index()].fixed = true;
    }

    /// Marks `id` for elimination by the Schur complement (a landmark).
    pub fn eliminate(&mut self, id: VariableId) {
        self.variables[id.index()].eliminated = true;
    }

    /// The variables.
    pub fn variable_count(&self) -> usize {
        self.variables.len()
    }

    /// The variables marked for elimination.
    pub fn eliminated_count(&self) -> usize {
        self.variables.iter().filter(|v| v.eliminated).count()
    }

    /// The factors.
    pub fn factor_count(&self) -> usize {
        self.groups.iter().map(|g| g.len()).sum()
    }

    /// Each factor type's name, its count and how it is linearized, in the
    /// order the types were first added.
    pub fn linearized(&self) -> Vec<(&'static str, usize, Linearized)> {
        self.groups
            .iter()
            .map(|g| (g.name(), g.len(), g.linearized()))
            .collect()
    }

    /// The stored scalars of `id` (after a solve, its solution).
    pub fn value(&self, id: VariableId) -> &[f64] {
        let v = &self.variables[id.index()];
        &self.values[v.offset..v.offset + v.scalars]
    }

    /// Adds `factor` on `variables` (one per variable of `F`, in declaration
    /// order), unwhitened, under the problem's loss. Its constants are
    /// kept; its variables' values are the problem's
    /// ([`Problem::add_variable`]).
    ///
    /// # Errors
    ///
    /// A count or size that does not fit `F`, a variable named twice, or a
    /// variable whose chart differs from another factor's.
    pub fn add<F>(&mut self, factor: &F, variables: &[VariableId]) -> Result<(), SchurError>
    where
        F: WithKernel + Send + Sync + 'static,
        F::Kernel: NormalKernel<Lane> + NormalKernel<f64>,
    {
        self.add_weighted(factor, variables, &Noise::Unit, None)
    }

    /// Adds `factor` as [`Problem::add`] does, its cost `½ ρ(‖S r‖²)` with
    /// `S` the square-root information of `noise` and `ρ` its own loss
    /// `robust` (the problem's when `None`). Isotropic noise keeps the
    /// fused kernels; per-component or full noise on a factor type makes
    /// that type's factors go through the Jacobian kernel, whitened
    /// (the module `noise`).
    ///
    /// # Errors
    ///
    /// As [`Problem::add`], and a noise model that does not fit the
    /// residual (a count of deviations, a shape, a deviation not finite
    /// and above 0, an entry not finite).
    pub fn add_weighted<F>(
        &mut self,
        factor: &F,
        variables: &[VariableId],
        noise: &Noise,
        robust: Option<Robust>,
    ) -> Result<(), SchurError>
    where
        F: WithKernel + Send + Sync + 'static,
        F::Kernel: NormalKernel<Lane> + NormalKernel<f64>,
    {
        self.add_to(
            (TypeId::of::<F>(), None),
            FactorGroup::<F>::batch,
            factor,
            variables,
            noise,
            robust,
        )
    }

    /// Adds `factor` as [`Problem::add_weighted`] does with
    /// `Kernels::Generated` (its fused kernels in lane batches), or one at a
    /// time by dual numbers with `Kernels::Dual` ([`Problem::add_linearized`]
    /// with [`Jacobians::Dual`]).
    ///
    /// # Errors
    ///
    /// As [`Problem::add_weighted`].
    pub fn add_by<F>(
        &mut self,
        factor: &F,
        variables: &[VariableId],
        noise: &Noise,
        robust: Option<Robust>,
        kernels: Kernels,
    ) -> Result<(), SchurError>
    where
        F: WithKernel + Send + Sync + 'static,
        F::Kernel: NormalKernel<Lane> + NormalKernel<f64>,
    {
        match kernels {
            Kernels::Generated => self.add_weighted(factor, variables, noise, robust),
            Kernels::Dual => self.add_linearized(factor, variables, noise, robust, Jacobians::Dual),
        }
    }

    /// Adds `factor` as [`Problem::add_weighted`] does, for a factor type
    /// without fused normal-equation kernels (or to differentiate one by
    /// dual numbers): its factors are linearized one at a time by
    /// `jacobians`, their residuals and Jacobians whitened and formed into
    /// the same normal blocks. A type added both ways forms two groups.
    ///
    /// # Errors
    ///
    /// As [`Problem::add_weighted`].
    pub fn add_linearized<F: Factor + Send + Sync + 'static>(
        &mut self,
        factor: &F,
        variables: &[VariableId],
        noise: &Noise,
        robust: Option<Robust>,
        jacobians: Jacobians,
    ) -> Result<(), SchurError> {
        self.add_to(
            (TypeId::of::<F>(), Some(jacobians)),
            || FactorGroup::<F>::per_factor(jacobians),
            factor,
            variables,
            noise,
            robust,
        )
    }

    /// Adds `factor` to the group `key`, made by `make` if new.
    fn add_to<F: Factor + Send + Sync + 'static>(
        &mut self,
        key: GroupKey,
        make: impl FnOnce() -> FactorGroup<F>,
        factor: &F,
        variables: &[VariableId],
        noise: &Noise,
        robust: Option<Robust>,
    ) -> Result<(), SchurError> {
        let group = self.group_index(key, make)?;
        let slots = self.groups[group].slot_info();
        if variables.len() != slots.len() {
            return Err(SchurError::Arity {
                factor: F::NAME,
                given: variables.len(),
                expected: slots.len(),
            });
        }
        for (k, a) in variables.iter().enumerate() {
            if variables[..k].contains(a) {
                return Err(SchurError::Repeated {
                    factor: F::NAME,
                    variable: a.index(),
                });
            }
        }
        for id in variables {
            if id.index() >= self.variables.len() {
                return Err(SchurError::UnknownVariable(id.index()));
            }
        }
        // Nothing is recorded before the noise model is known to fit.
        let ids: Vec<u32> = variables.iter().map(|v| v.0).collect();
        let any: &mut dyn Any = self.groups[group].as_any_mut();
        any.downcast_mut::<FactorGroup<F>>()
            .expect("the group of F's type holds F")
            .check_noise(noise)
            .map_err(|message| SchurError::Noise {
                factor: F::NAME,
                message,
            })?;
        let slots = self.groups[group].slot_info();
        for (slot, (id, info)) in variables.iter().zip(slots).enumerate() {
            let variable = &mut self.variables[id.index()];
            if variable.scalars != info.scalars {
                return Err(SchurError::Scalars {
                    factor: F::NAME,
                    variable: id.index(),
                    name: info.name,
                    expected: info.scalars,
                    found: variable.scalars,
                });
            }
            match variable.chart {
                None => {
                    variable.chart = Some(Chart {
                        group,
                        slot,
                        tangent: info.tangent,
                    });
                }
                // The same slot of the same factor type: the same chart.
                Some(known) if (known.group, known.slot) == (group, slot) => {}
                Some(known) => {
                    let first = &self.groups[known.group].slot_info()[known.slot];
                    if !first.same_chart(info) {
                        return Err(SchurError::Chart {
                            variable: id.index(),
                            first: first.describe(),
                            second: info.describe().replace(" declares it", ""),
                        });
                    }
                }
            }
        }
        let any: &mut dyn Any = self.groups[group].as_any_mut();
        any.downcast_mut::<FactorGroup<F>>()
            .expect("the group of F's type holds F")
            .push(factor, &ids, noise, robust)
            .map_err(|message| SchurError::Noise {
                factor: F::NAME,
                message,
            })
    }

    /// The index of the group `key`, made by `make` if new.
    ///
    /// # Errors
    ///
    /// A factor type beyond the solver's buffers.
    fn group_index<F: Factor + Send + Sync + 'static>(
        &mut self,
        key: GroupKey,
        make: impl FnOnce() -> FactorGroup<F>,
    ) -> Result<usize, SchurError> {
        if let Some(k) = self.group_types.iter().position(|t| *t == key) {
            return Ok(k);
        }
        if F::SCALARS > MAX_SCALARS || F::variables().len() > MAX_SLOTS {
            return Err(SchurError::TooLarge(format!(
                "{}: more than {MAX_SCALARS} stored scalars or {MAX_SLOTS} variables",
                F::NAME
            )));
        }
        self.group_types.push(key);
        self.groups.push(Box::new(make()));
        Ok(self.groups.len() - 1)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use factor_core::Storage;
    use factor_core::lie::{Se3, Se3RhoTheta, So3};
    use nalgebra::{Vector2, Vector3};
    use slam_factors::{
        RadialIntrinsics, SnavelyReprojection, StereoIntrinsics, StereoReprojection,
    };

    fn snavely() -> SnavelyReprojection {
        SnavelyReprojection {
            observed: Vector2::new(1.0, 2.0),
            pose: Se3RhoTheta::new(Se3::new(So3::identity(), Vector3::new(0.0, 0.0, -5.0))),
            intrinsics: RadialIntrinsics::new(500.0, 0.0, 0.0),
            point: Vector3::new(0.1, 0.2, 0.3),
        }
    }

    #[test]
    fn factors_are_checked_as_they_are_added() {
        let f = snavely();
        let mut problem = Problem::new();
        let pose = problem.add_variable(&f.pose.to_scalars());
        let intrinsics = problem.add_variable(&[500.0, 0.0, 0.0]);
        let point = problem.add_variable(&[0.1, 0.2, 0.3]);
        problem.add(&f, &[pose, intrinsics, point]).unwrap();
        assert_eq!(problem.factor_count(), 1);
        assert!(matches!(
            problem.add(&f, &[pose, intrinsics]),
            Err(SchurError::Arity {
                given: 2,
                expected: 3,
                ..
            })
        ));
        assert!(matches!(
            problem.add(&f, &[pose, point, point]),
            Err(SchurError::Repeated { variable: 2, .. })
        ));
        assert!(matches!(
            problem.add(&f, &[point, intrinsics, pose]),
            Err(SchurError::Scalars { variable: 2, .. })
        ));
        // The stereo factor's landmark is a `Vector3` as the point is, but
        // its pose (camera to world) is the same `Se3RhoTheta` chart: both
        // fit. A 3-vector used as intrinsics somewhere and as a point
        // elsewhere does not.
        let stereo = StereoReprojection {
            calibration: StereoIntrinsics::new(500.0, 500.0, 0.0, 0.0, 0.0, 0.5),
            observed: Vector3::new(0.0, 0.0, 0.0),
            pose: f.pose,
            landmark: f.point,
        };
        problem.add(&stereo, &[pose, point]).unwrap();
        let error = problem.add(&stereo, &[pose, intrinsics]).unwrap_err();
        assert!(
            matches!(error, SchurError::Chart { variable: 1, .. }),
            "{error}"
        );
        assert!(error.to_string().contains("RadialIntrinsics"), "{error}");
    }
}
