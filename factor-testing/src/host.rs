//! Jacobians in a host's chart ([`factor_core::host`]) against central
//! differences through the host's exact retraction.

use factor_core::FactorError;
use factor_core::host::{
    Host, HostFactor, HostKernel, HostLayout, HostManifold, host_parameters, host_residual,
    inputs_of, linearize_host, linearize_host_dual,
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

/// The Jacobian (column-major, every part's columns in order) by central
/// differences with Richardson's extrapolation (`(4 D(h/2) − D(h)) / 3`,
/// error `O(h⁴)`), each host part stepped through `retract` (the host's
/// exact retraction: the solver's own, or its description's
/// [`HostManifold::retract`]).
fn central_differences<F: HostFactor<H>, H: Host>(
    layout: &HostLayout<H::Manifold>,
    template: &[f64],
    parts: &[Vec<f64>],
    step: f64,
    retract: &impl Fn(H::Manifold, &[f64], &[f64], &mut [f64]),
) -> Vec<f64> {
    let zero = vec![0.0; layout.columns()];
    let residual_at = |parts: &[Vec<f64>]| {
        let slices: Vec<&[f64]> = parts.iter().map(Vec::as_slice).collect();
        host_residual::<F, H, f64>(layout, &inputs_of(layout, template, &slices), &zero)
    };
    let mut jacobian = Vec::with_capacity(layout.residual * layout.columns());
    for (index, part) in layout.parts.iter().enumerate() {
        let dof = part.manifold.dof();
        for c in 0..dof {
            let quotient = |h: f64| {
                let mut moved = parts.to_vec();
                let mut at = |sign: f64| {
                    let mut delta = vec![0.0; dof];
                    delta[c] = sign * h;
                    retract(part.manifold, &parts[index], &delta, &mut moved[index]);
                    residual_at(&moved)
                };
                let (plus, minus) = (at(1.0), at(-1.0));
                plus.iter()
                    .zip(&minus)
                    .map(|(p, m)| (p - m) / (2.0 * h))
                    .collect::<Vec<f64>>()
            };
            let (coarse, fine) = (quotient(step), quotient(step / 2.0));
            jacobian.extend(
                fine.iter()
                    .zip(&coarse)
                    .map(|(fine, coarse)| (4.0 * fine - coarse) / 3.0),
            );
        }
    }
    jacobian
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
        &[f64],
        &[&[f64]],
        &mut [f64],
        Option<&mut [f64]>,
    ) -> Result<(), FactorError>,
    step: f64,
    retract: impl Fn(H::Manifold, &[f64], &[f64], &mut [f64]),
) -> Result<HostCheck, FactorError> {
    let layout = HostLayout::of::<F, H>();
    let template = factor.to_scalars();
    let parts = host_parameters::<F, H>(&layout, factor);
    let slices: Vec<&[f64]> = parts.iter().map(Vec::as_slice).collect();
    let rows = layout.residual;
    let mut residual = vec![0.0; rows];
    let mut jacobian = vec![0.0; rows * layout.columns()];
    linearize(
        &layout,
        &template,
        &slices,
        &mut residual,
        Some(&mut jacobian),
    )?;
    let expected = factor.residual_dyn()?;
    // As generated kernels are judged: relative to the residual's terms.
    let residual_error = relative_error(
        &residual,
        expected.as_slice(),
        crate::generated::input_scale(factor),
    );
    let numeric = central_differences::<F, H>(&layout, &template, &parts, step, &retract);
    let names = layout.inputs.iter().filter_map(|input| match input {
        factor_core::host::HostInput::Part { .. } => Some(input.name()),
        _ => None,
    });
    let mut offset = 0;
    let block_errors = names
        .zip(&layout.parts)
        .map(|(name, part)| {
            let len = rows * part.manifold.dof();
            let range = offset..offset + len;
            offset += len;
            (
                name,
                relative_error(&jacobian[range.clone()], &numeric[range], 1e-9),
            )
        })
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
