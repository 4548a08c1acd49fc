//! The observations of one factor type against the fixed map, and their
//! contribution to the pose's normal equations.

use std::any::Any;

use factor_core::lie::Se3;
use factor_core::noise::Noise;
use factor_core::{Factor, FactorError, Perturbation, Storage};
use nalgebra::{Matrix6, Vector6};

use crate::error::PoseError;

/// The most variables a tracked factor may have (one slot per variable in
/// the Jacobian request, on the stack).
const MAX_VARIABLES: usize = 8;

/// `S` of `noise` as a row-major `dim × dim` array, or the error naming
/// `factor` when the model does not fit the residual.
fn whitening(noise: &Noise, factor: &'static str, dim: usize) -> Result<Vec<f64>, PoseError> {
    noise
        .check(dim)
        .map_err(|reason| PoseError::Noise { factor, reason })?;
    Ok(noise.sqrt_information(dim).transpose().as_slice().to_vec())
}

/// The cost `½ Σ ‖S r‖²` of a pose's observations and its normal
/// equations: `H = Σ J̃ᵀ J̃`, `g = Σ J̃ᵀ r̃` with `J̃ = S J`, `r̃ = S r`, `J` the
/// residual's Jacobian w.r.t. the pose's tangent (on the factors' side).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Normal {
    /// `½ Σ ‖S r‖²`.
    pub cost: f64,
    /// `H`, symmetric.
    pub hessian: Matrix6<f64>,
    /// `g`: the cost's gradient.
    pub gradient: Vector6<f64>,
}

impl Normal {
    fn zero() -> Normal {
        Normal {
            cost: 0.0,
            hessian: Matrix6::zeros(),
            gradient: Vector6::zeros(),
        }
    }
}

/// Observations of any factor type, as the problem holds them.
pub(crate) trait Terms {
    /// Adds the cost and normal equations of the active observations at
    /// the pose stored as `pose` (`H`'s upper triangle only) to `normal`,
    /// and to `determination`, when given, `Σ uuᵀ` over the whitened rows
    /// `u` of their Jacobians each scaled to unit norm (upper triangle).
    fn accumulate(
        &mut self,
        pose: &[f64; 7],
        normal: &mut Normal,
        determination: Option<&mut Matrix6<f64>>,
    ) -> Result<(), PoseError>;
    /// Sets aside the observations whose residual is undefined at `pose`
    /// (inactive), the others active; returns how many were set aside.
    fn set_aside_undefined(&mut self, pose: &[f64; 7]) -> usize;
    /// Makes every observation active.
    fn activate_all(&mut self);
    /// The active observations.
    fn active(&self) -> usize;
    /// Their residual rows.
    fn rows(&self) -> usize;
    /// The pose's perturbation side.
    fn side(&self) -> Perturbation;
    /// For [`crate::PoseProblem::add`] to find its factor type's terms.
    fn as_any_mut(&mut self) -> &mut dyn Any;
}

/// Observations of factor type `F`: their stored scalars (the pose's
/// rewritten at every linearization) and whitening matrices.
pub(crate) struct Observations<F> {
    /// Each factor's stored scalars, one after the other.
    stored: Vec<f64>,
    /// Each factor's `S`, row-major.
    whitening: Vec<f64>,
    /// Each factor's index in the problem.
    indices: Vec<usize>,
    /// Whether each factor enters the cost.
    active: Vec<bool>,
    /// The pose variable's index among `F`'s variables.
    pose: usize,
    /// Its first stored scalar.
    pose_offset: usize,
    /// `F`'s variables.
    variables: usize,
    side: Perturbation,
    /// Scratch: the residual, the pose's Jacobian block, the whitened block.
    residual: Vec<f64>,
    block: Vec<f64>,
    whitened: Vec<f64>,
    _factor: std::marker::PhantomData<F>,
}

impl<F: Factor> Observations<F> {
    /// No observations yet; fails when `F` has not exactly one `Se3` variable.
    pub(crate) fn new() -> Result<Self, PoseError> {
        let variables = F::variables();
        let poses: Vec<usize> = (0..variables.len())
            .filter(|&k| variables[k].type_name == "Se3<S>")
            .collect();
        let [pose] = poses[..] else {
            return Err(PoseError::NoPose {
                factor: F::NAME,
                found: poses.len(),
            });
        };
        assert!(
            variables.len() <= MAX_VARIABLES,
            "{} variables",
            variables.len()
        );
        let pose_offset = F::fields()
            .iter()
            .take_while(|f| f.variable != Some(pose))
            .map(|f| f.scalars)
            .sum();
        let dim = F::RESIDUAL_DIM;
        Ok(Observations {
            stored: Vec::new(),
            whitening: Vec::new(),
            indices: Vec::new(),
            active: Vec::new(),
            pose,
            pose_offset,
            variables: variables.len(),
            side: variables[pose].perturbation,
            residual: vec![0.0; dim],
            block: vec![0.0; dim * 6],
            whitened: vec![0.0; dim * 7],
            _factor: std::marker::PhantomData,
        })
    }

    /// Adds `factor` (its pose's value is not used) as observation `index`.
    pub(crate) fn push(
        &mut self,
        factor: &F,
        noise: &Noise,
        index: usize,
    ) -> Result<(), PoseError> {
        let s = whitening(noise, F::NAME, F::RESIDUAL_DIM)?;
        self.stored.extend(factor.to_scalars());
        self.whitening.extend(s);
        self.indices.push(index);
        self.active.push(true);
        Ok(())
    }
}

impl<F: Factor + 'static> Terms for Observations<F> {
    fn accumulate(
        &mut self,
        pose: &[f64; 7],
        normal: &mut Normal,
        mut determination: Option<&mut Matrix6<f64>>,
    ) -> Result<(), PoseError> {
        let dim = F::RESIDUAL_DIM;
        let chunks = self
            .stored
            .chunks_exact_mut(F::SCALARS)
            .zip(self.whitening.chunks_exact(dim * dim))
            .zip(&self.indices)
            .zip(&self.active)
            .filter(|(_, active)| **active);
        for (((stored, s), &index), _) in chunks {
            stored[self.pose_offset..self.pose_offset + 7].copy_from_slice(pose);
            let mut slots: [Option<&mut [f64]>; MAX_VARIABLES] = Default::default();
            slots[self.pose] = Some(&mut self.block[..]);
            F::linearize_stored_into(stored, &mut self.residual, &mut slots[..self.variables])
                .map_err(|error: FactorError| PoseError::Observation {
                    observation: index,
                    error,
                })?;
            // [S J | S r], row by row.
            for i in 0..dim {
                let row = &mut self.whitened[i * 7..(i + 1) * 7];
                row.fill(0.0);
                for k in 0..dim {
                    let sik = s[i * dim + k];
                    if sik != 0.0 {
                        for (c, x) in row[..6].iter_mut().enumerate() {
                            *x += sik * self.block[k * 6 + c];
                        }
                        row[6] += sik * self.residual[k];
                    }
                }
            }
            for row in self.whitened.chunks_exact(7) {
                let r = row[6];
                normal.cost += 0.5 * r * r;
                for a in 0..6 {
                    normal.gradient[a] += row[a] * r;
                    for b in a..6 {
                        normal.hessian[(a, b)] += row[a] * row[b];
                    }
                }
                if let Some(d) = determination.as_deref_mut() {
                    add_unit_row(d, &row[..6]);
                }
            }
        }
        Ok(())
    }

    fn set_aside_undefined(&mut self, pose: &[f64; 7]) -> usize {
        let mut set_aside = 0;
        for (stored, active) in self
            .stored
            .chunks_exact_mut(F::SCALARS)
            .zip(&mut self.active)
        {
            stored[self.pose_offset..self.pose_offset + 7].copy_from_slice(pose);
            let mut slots: [Option<&mut [f64]>; MAX_VARIABLES] = Default::default();
            *active =
                F::linearize_stored_into(stored, &mut self.residual, &mut slots[..self.variables])
                    .is_ok();
            set_aside += usize::from(!*active);
        }
        set_aside
    }

    fn activate_all(&mut self) {
        self.active.fill(true);
    }

    fn active(&self) -> usize {
        self.active.iter().filter(|a| **a).count()
    }

    fn rows(&self) -> usize {
        self.active() * F::RESIDUAL_DIM
    }

    fn side(&self) -> Perturbation {
        self.side
    }

    fn as_any_mut(&mut self) -> &mut dyn Any {
        self
    }
}

/// `d += uuᵀ/‖u‖²` (upper triangle) for the Jacobian row `u`: a row of
/// zeros adds nothing; its scale, and so its weight, does not count.
fn add_unit_row(d: &mut Matrix6<f64>, row: &[f64]) {
    let scale = row.iter().fold(0.0_f64, |m, x| m.max(x.abs()));
    if !(scale > 0.0 && scale.is_finite()) {
        return;
    }
    let mut u = [0.0; 6];
    for (u, x) in u.iter_mut().zip(row) {
        *u = x / scale;
    }
    let squared: f64 = u.iter().map(|x| x * x).sum();
    for a in 0..6 {
        for b in a..6 {
            d[(a, b)] += u[a] * u[b] / squared;
        }
    }
}

/// `pose`'s stored scalars, `[qx, qy, qz, qw, tx, ty, tz]`: what the
/// observations are linearized at.
pub(crate) fn stored_scalars(pose: &Se3<f64>) -> [f64; 7] {
    let mut stored = [0.0; 7];
    pose.write_scalars(&mut stored);
    stored
}

/// The normal equations of `terms` at the pose stored as `pose`.
pub(crate) fn normal(terms: &mut [Box<dyn Terms>], pose: &[f64; 7]) -> Result<Normal, PoseError> {
    normal_with(terms, pose, None)
}

/// [`normal`], and `Σ uuᵀ` of the unit Jacobian rows into `determination`
/// when given (both made symmetric).
pub(crate) fn normal_with(
    terms: &mut [Box<dyn Terms>],
    pose: &[f64; 7],
    mut determination: Option<&mut Matrix6<f64>>,
) -> Result<Normal, PoseError> {
    let mut normal = Normal::zero();
    for t in terms {
        t.accumulate(pose, &mut normal, determination.as_deref_mut())?;
    }
    symmetric(&mut normal.hessian);
    if let Some(d) = determination {
        symmetric(d);
    }
    Ok(normal)
}

/// The lower triangle of `m` from its upper one.
fn symmetric(m: &mut Matrix6<f64>) {
    for a in 0..6 {
        for b in 0..a {
            m[(a, b)] = m[(b, a)];
        }
    }
}
