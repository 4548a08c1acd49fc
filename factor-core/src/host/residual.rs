//! A factor's residual and Jacobians in a host's chart, from the host's
//! parameter slices: by dual numbers or through the generated host kernel.

use num_dual::DualSVec64;

use crate::factor::{FactorError, first_non_finite};
use crate::host::{Host, HostFactor, HostInput, HostKernel, HostLayout, HostManifold};
use crate::scalar::Scalar;

/// The most host parameters one variable may have (its parts' together).
pub const MAX_VARIABLE_PARAMETERS: usize = 32;
/// The most stored scalars a factor served to a host may have.
pub const MAX_STORED: usize = 128;

/// Writes the stored scalars of factor `F` (in `stored`, `layout.stored`
/// long) from its kernel inputs in `H`'s layout (`inputs`, one slice per
/// [`HostInput`]), each host part passed through `part` first: the identity
/// for values, the first-order retraction for derivatives.
fn assemble_stored<F: HostFactor<H>, H: Host, T: Scalar>(
    layout: &HostLayout<H::Manifold>,
    inputs: &[&[T]],
    stored: &mut [T],
    mut part: impl FnMut(&HostInput<H::Manifold>, &[T], &mut [T]),
) {
    let mut params = [T::zero(); MAX_VARIABLE_PARAMETERS];
    let mut filled = 0;
    for (k, (input, values)) in layout.inputs.iter().zip(inputs).enumerate() {
        match input {
            HostInput::Constant { stored: range, .. } => {
                stored[range.clone()].copy_from_slice(values);
            }
            HostInput::Part {
                variable,
                stored: range,
                part: host_part,
                ..
            } => {
                let n = host_part.manifold.parameters();
                part(input, values, &mut params[filled..filled + n]);
                filled += n;
                let last_part = !matches!(
                    layout.inputs.get(k + 1),
                    Some(HostInput::Part { variable: next, .. }) if next == variable
                );
                if last_part {
                    F::stored_from_host(*variable, &params[..filled], &mut stored[range.clone()]);
                    filled = 0;
                }
            }
        }
    }
}

/// The stored scalars of factor `F` whose kernel inputs in `H`'s layout are
/// `inputs` (one slice per [`HostInput`]): the factor at the host's values.
///
/// # Panics
///
/// If a slice's length is not the layout's, or `stored` is not
/// `layout.stored` long.
pub fn stored_from_host_inputs<F: HostFactor<H>, H: Host>(
    layout: &HostLayout<H::Manifold>,
    inputs: &[&[f64]],
    stored: &mut [f64],
) {
    assemble_stored::<F, H, f64>(layout, inputs, stored, |_, values, out| {
        out.copy_from_slice(values)
    });
}

/// The kernel inputs in `H`'s layout of the factor `factor`: its constants'
/// stored scalars and its variables' host parameters
/// ([`HostMap::host_from_stored`](crate::host::HostMap::host_from_stored)),
/// one vector per [`HostInput`].
pub fn host_inputs<F: HostFactor<H>, H: Host>(
    layout: &HostLayout<H::Manifold>,
    factor: &F,
) -> Vec<Vec<f64>> {
    let stored = factor.to_scalars();
    let mut inputs = Vec::with_capacity(layout.inputs.len());
    let mut k = 0;
    while k < layout.inputs.len() {
        match &layout.inputs[k] {
            HostInput::Constant { stored: range, .. } => {
                inputs.push(stored[range.clone()].to_vec());
                k += 1;
            }
            HostInput::Part {
                variable,
                stored: range,
                ..
            } => {
                // The variable's parts, consecutive in the layout.
                let parts: Vec<usize> = layout.inputs[k..]
                    .iter()
                    .take_while(
                        |i| matches!(i, HostInput::Part { variable: v, .. } if v == variable),
                    )
                    .map(HostInput::len)
                    .collect();
                let mut host = vec![0.0; parts.iter().sum()];
                F::host_from_stored(*variable, &stored[range.clone()], &mut host);
                let mut rest = host.as_slice();
                for n in &parts {
                    let (head, tail) = rest.split_at(*n);
                    inputs.push(head.to_vec());
                    rest = tail;
                }
                k += parts.len();
            }
        }
    }
    inputs
}

/// The residual of factor `F` at the host values `inputs` (one slice per
/// [`HostInput`] of `layout`), every host part retracted to first order in
/// `H`'s chart by its columns of `delta` (the parts' tangents stacked, in
/// order): the function whose derivative at `δ = 0` is the Jacobian in the
/// host's chart. Dual numbers evaluate it; the code generator traces it.
///
/// # Panics
///
/// If a slice's or `delta`'s length is not the layout's.
pub fn host_residual<F: HostFactor<H>, H: Host, T: Scalar>(
    layout: &HostLayout<H::Manifold>,
    inputs: &[&[T]],
    delta: &[T],
) -> Vec<T> {
    let mut stored = vec![T::zero(); layout.stored];
    assemble_stored::<F, H, T>(layout, inputs, &mut stored, |input, values, out| {
        if let HostInput::Part { part, columns, .. } = input {
            part.manifold
                .retract_first_order(values, &delta[columns.clone()], out);
        }
    });
    F::residual_over(&stored)
}

/// Validates factor `F` at the host values `inputs`.
fn validate<F: HostFactor<H>, H: Host>(
    layout: &HostLayout<H::Manifold>,
    inputs: &[&[f64]],
) -> Result<(), FactorError> {
    let mut stored = [0.0; MAX_STORED];
    let stored = &mut stored[..layout.stored];
    stored_from_host_inputs::<F, H>(layout, inputs, stored);
    F::from_scalars(stored).validate()
}

/// Residual and column-major blocks (one per host part, `None` for a block
/// not wanted) of factor `F` in `H`'s chart, through its generated host
/// kernel, after the factor's validation at the host's values. No
/// allocation.
///
/// # Errors
///
/// The validation's error, or [`FactorError::NonFinite`] naming the first
/// non-finite output (a block by its variable).
///
/// # Panics
///
/// If a length differs from the layout's, or the layout has more than
/// [`MAX_STORED`] stored scalars.
pub fn linearize_host<F: HostKernel<H>, H: Host>(
    layout: &HostLayout<H::Manifold>,
    inputs: &[&[f64]],
    residual: &mut [f64],
    blocks: &mut [Option<&mut [f64]>],
) -> Result<(), FactorError> {
    validate::<F, H>(layout, inputs)?;
    assert!(
        F::host_kernel(inputs, residual, blocks),
        "{}: the inputs, the residual or a block differ in length from the host kernel's",
        F::NAME
    );
    check_finite::<F, H>(layout, residual, blocks)
}

/// [`linearize_host`] by dual numbers, through [`host_residual`]: the same
/// outputs to rounding, for any [`HostFactor`], with or without a generated
/// host kernel. Allocates (a comparison path, not a solver's inner loop).
///
/// # Errors
///
/// As [`linearize_host`].
///
/// # Panics
///
/// As [`linearize_host`].
pub fn linearize_host_dual<F: HostFactor<H>, H: Host>(
    layout: &HostLayout<H::Manifold>,
    inputs: &[&[f64]],
    residual: &mut [f64],
    blocks: &mut [Option<&mut [f64]>],
) -> Result<(), FactorError> {
    validate::<F, H>(layout, inputs)?;
    type D = DualSVec64<1>;
    let lifted: Vec<Vec<D>> = inputs
        .iter()
        .map(|values| values.iter().map(|x| D::from_re(*x)).collect())
        .collect();
    let lifted: Vec<&[D]> = lifted.iter().map(Vec::as_slice).collect();
    let columns = layout.columns();
    let mut delta = vec![D::from_re(0.0); columns];
    let rows = layout.residual;
    let value = host_residual::<F, H, D>(layout, &lifted, &delta);
    for (out, r) in residual.iter_mut().zip(&value) {
        *out = r.re;
    }
    for (k, part) in layout.parts.iter().enumerate() {
        let Some(block) = blocks[k].as_deref_mut() else {
            continue;
        };
        let first = layout.parts[..k]
            .iter()
            .map(|p| p.manifold.dof())
            .sum::<usize>();
        for c in 0..part.manifold.dof() {
            delta[first + c] = D::from_re(0.0).derivative(0);
            let r = host_residual::<F, H, D>(layout, &lifted, &delta);
            delta[first + c] = D::from_re(0.0);
            for (row, value) in r.iter().enumerate() {
                block[c * rows + row] =
                    value.eps.unwrap_generic(nalgebra::Const::<1>, nalgebra::U1)[0];
            }
        }
    }
    check_finite::<F, H>(layout, residual, blocks)
}

/// [`FactorError::NonFinite`] for the first non-finite output, a block named
/// by its variable.
fn check_finite<F: HostFactor<H>, H: Host>(
    layout: &HostLayout<H::Manifold>,
    residual: &[f64],
    blocks: &[Option<&mut [f64]>],
) -> Result<(), FactorError> {
    match first_non_finite(residual, blocks) {
        None => Ok(()),
        Some(at) => {
            let variable = at.and_then(|k| {
                layout.inputs.iter().find_map(|input| match input {
                    HostInput::Part {
                        index, variable, ..
                    } if *index == k => Some(*variable),
                    _ => None,
                })
            });
            Err(FactorError::non_finite_output::<F>(variable))
        }
    }
}
