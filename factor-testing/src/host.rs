//! Jacobians in a host's chart ([`factor_core::host`]) against central
//! differences through the host's exact retraction.

use factor_core::FactorError;
use factor_core::host::{
    Host, HostFactor, HostKernel, HostLayout, HostManifold, host_inputs, host_residual,
    linearize_host, linearize_host_dual,
};

/// How far a host linearization is from central differences.
#[derive(Debug, Clone, PartialEq)]
pub struct HostCheck {
    /// Error of the residual against the factor's own, relative to
    /// `max(‖r‖, input scale)` ([`crate::generated::input_scale`]).
    pub residual_error: f64,
    /// Per host part (`<variable>` or `<variable>_<part>`): the relative
    /// Frobenius error of its block.
    pub block_errors: Vec<(String, f64)>,
}

impl HostCheck {
    /// The largest error over the residual and every block.
    pub fn max_error(&self) -> f64 {
        self.block_errors
            .iter()
            .map(|(_, e)| *e)
            .fold(self.residual_error, f64::max)
    }
}

/// One host part's columns by central differences with Richardson's
/// extrapolation (`(4 D(h/2) − D(h)) / 3`, error `O(h⁴)`), each part stepped
/// through `retract` (the host's exact retraction: the solver's own, or its
/// description's [`HostManifold::retract`]).
fn central_differences<F: HostFactor<H>, H: Host>(
    layout: &HostLayout<H::Manifold>,
    inputs: &[Vec<f64>],
    step: f64,
    retract: &impl Fn(H::Manifold, &[f64], &[f64], &mut [f64]),
) -> Vec<Vec<f64>> {
    let rows = layout.residual;
    let zero = vec![0.0; layout.columns()];
    let residual_at = |inputs: &[Vec<f64>]| {
        let slices: Vec<&[f64]> = inputs.iter().map(Vec::as_slice).collect();
        host_residual::<F, H, f64>(layout, &slices, &zero)
    };
    let mut blocks = Vec::with_capacity(layout.parts.len());
    for (index, input) in layout.inputs.iter().enumerate() {
        let factor_core::host::HostInput::Part { part, .. } = input else {
            continue;
        };
        let dof = part.manifold.dof();
        let mut block = vec![0.0; rows * dof];
        for c in 0..dof {
            let quotient = |h: f64| {
                let mut moved = inputs.to_vec();
                let mut delta = vec![0.0; dof];
                let mut at = |sign: f64, moved: &mut Vec<Vec<f64>>| {
                    delta[c] = sign * h;
                    retract(part.manifold, &inputs[index], &delta, &mut moved[index]);
                    residual_at(moved)
                };
                let plus = at(1.0, &mut moved);
                let minus = at(-1.0, &mut moved);
                plus.iter()
                    .zip(&minus)
                    .map(|(p, m)| (p - m) / (2.0 * h))
                    .collect::<Vec<f64>>()
            };
            let (coarse, fine) = (quotient(step), quotient(step / 2.0));
            for row in 0..rows {
                block[c * rows + row] = (4.0 * fine[row] - coarse[row]) / 3.0;
            }
        }
        blocks.push(block);
    }
    blocks
}

/// Relative Frobenius error of `a` against `b`, floored at `floor`.
fn relative_error(a: &[f64], b: &[f64], floor: f64) -> f64 {
    let difference: f64 = a.iter().zip(b).map(|(x, y)| (x - y).powi(2)).sum();
    let norm: f64 = b.iter().map(|y| y * y).sum();
    difference.sqrt() / norm.sqrt().max(floor)
}

/// The host linearization of `factor` (dual numbers, or the generated host
/// kernel) against central differences through `retract` with steps
/// `step`: the relative error of the residual and of each host part's
/// block (named `<variable>` or `<variable>_<part>`).
///
/// # Errors
///
/// The factor's own, where it cannot be linearized.
pub fn check_host_linearization<F: HostFactor<H>, H: Host>(
    factor: &F,
    linearize: impl Fn(
        &HostLayout<H::Manifold>,
        &[&[f64]],
        &mut [f64],
        &mut [Option<&mut [f64]>],
    ) -> Result<(), FactorError>,
    step: f64,
    retract: impl Fn(H::Manifold, &[f64], &[f64], &mut [f64]),
) -> Result<HostCheck, FactorError> {
    let layout = HostLayout::of::<F, H>();
    let inputs = host_inputs::<F, H>(&layout, factor);
    let slices: Vec<&[f64]> = inputs.iter().map(Vec::as_slice).collect();
    let rows = layout.residual;
    let mut residual = vec![0.0; rows];
    let mut blocks: Vec<Vec<f64>> = layout
        .parts
        .iter()
        .map(|p| vec![0.0; rows * p.manifold.dof()])
        .collect();
    {
        let mut outputs: Vec<Option<&mut [f64]>> =
            blocks.iter_mut().map(|b| Some(b.as_mut_slice())).collect();
        linearize(&layout, &slices, &mut residual, &mut outputs)?;
    }
    let expected = factor.residual_dyn()?;
    // As generated kernels are judged: relative to the residual's terms.
    let residual_error = relative_error(
        &residual,
        expected.as_slice(),
        crate::generated::input_scale(factor),
    );
    let numeric = central_differences::<F, H>(&layout, &inputs, step, &retract);
    let names = layout.inputs.iter().filter_map(|input| match input {
        factor_core::host::HostInput::Part { .. } => Some(input.name()),
        _ => None,
    });
    let block_errors = names
        .zip(blocks.iter().zip(&numeric))
        .map(|(name, (b, n))| (name, relative_error(b, n, 1e-9)))
        .collect();
    Ok(HostCheck {
        residual_error,
        block_errors,
    })
}

/// [`check_host_linearization`] by dual numbers.
///
/// # Errors
///
/// As [`check_host_linearization`].
pub fn check_host_dual<F: HostFactor<H>, H: Host>(
    factor: &F,
    step: f64,
    retract: impl Fn(H::Manifold, &[f64], &[f64], &mut [f64]),
) -> Result<HostCheck, FactorError> {
    check_host_linearization(factor, linearize_host_dual::<F, H>, step, retract)
}

/// [`check_host_linearization`] through the generated host kernel.
///
/// # Errors
///
/// As [`check_host_linearization`].
pub fn check_host_kernel<F: HostKernel<H>, H: Host>(
    factor: &F,
    step: f64,
    retract: impl Fn(H::Manifold, &[f64], &[f64], &mut [f64]),
) -> Result<HostCheck, FactorError> {
    check_host_linearization(factor, linearize_host::<F, H>, step, retract)
}
