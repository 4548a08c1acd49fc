//! A factor's residual and Jacobian in a host's chart, from the host's
//! parameter slices: by dual numbers or through the generated host kernel.
//!
//! The value paths take what a solver holds: the factor's stored scalars
//! (`template`: its constants; its variables' scalars are not read) and one
//! parameter slice per host part, as the host keeps them; they write the
//! residual and the column-major Jacobian (`rows × Σ dof`, the parts'
//! columns in order), as the host's factors do.

use crate::dual::Dual;
use crate::factor::FactorError;
use crate::host::{Host, HostFactor, HostInput, HostKernel, HostLayout, HostManifold};
use crate::scalar::Scalar;

/// The most host parameters one variable may have (its parts' together).
pub const MAX_VARIABLE_PARAMETERS: usize = 32;
/// The most stored scalars a factor served to a host may have.
pub const MAX_STORED: usize = 128;

/// The kernel inputs (one slice per [`HostInput`]) of the factor stored as
/// `template` whose host parts' parameters are `parts`.
///
/// # Panics
///
/// If `parts` has fewer slices than the layout's parts, or `template` is
/// shorter than the layout's stored scalars.
pub fn inputs_of<'a, M: HostManifold>(
    layout: &HostLayout<M>,
    template: &'a [f64],
    parts: &[&'a [f64]],
) -> Vec<&'a [f64]> {
    layout
        .inputs
        .iter()
        .map(|input| match input {
            HostInput::Constant { stored, .. } => &template[stored.clone()],
            HostInput::Part { index, .. } => parts[*index],
        })
        .collect()
}

/// The host parameters of each host part of `factor`'s variables
/// ([`HostMap::host_from_stored`](crate::host::HostMap::host_from_stored)),
/// in order.
pub fn host_parameters<F: HostFactor<H>, H: Host>(
    layout: &HostLayout<H::Manifold>,
    factor: &F,
) -> Vec<Vec<f64>> {
    let stored = factor.to_scalars();
    let mut out = Vec::with_capacity(layout.parts.len());
    for variable in &layout.variables {
        let sizes: Vec<usize> = layout.parts[variable.parts.clone()]
            .iter()
            .map(|p| p.manifold.parameters())
            .collect();
        let mut host = vec![0.0; sizes.iter().sum()];
        F::host_from_stored(
            variable.variable,
            &stored[variable.stored.clone()],
            &mut host,
        );
        let mut rest = host.as_slice();
        for n in sizes {
            let (head, tail) = rest.split_at(n);
            out.push(head.to_vec());
            rest = tail;
        }
    }
    out
}

/// Writes the stored scalars of factor `F`'s variables into `stored` (the
/// factor's storage, whose constants are left as they are) from its host
/// parts' parameters. A variable served as one host part is mapped straight
/// from its slice; one of several, from their slices put end to end on the
/// stack.
///
/// # Panics
///
/// If a slice's length is not the layout's, `stored` is not `layout.stored`
/// long, or a variable has more than [`MAX_VARIABLE_PARAMETERS`] host
/// parameters.
pub fn variables_from_host<F: HostFactor<H>, H: Host>(
    layout: &HostLayout<H::Manifold>,
    parts: &[&[f64]],
    stored: &mut [f64],
) {
    for variable in &layout.variables {
        let slices = &parts[variable.parts.clone()];
        let out = &mut stored[variable.stored.clone()];
        if let [single] = slices {
            F::stored_from_host(variable.variable, single, out);
        } else {
            let mut params = [0.0; MAX_VARIABLE_PARAMETERS];
            let mut filled = 0;
            for values in slices {
                params[filled..filled + values.len()].copy_from_slice(values);
                filled += values.len();
            }
            F::stored_from_host(variable.variable, &params[..filled], out);
        }
    }
}

/// The residual of factor `F` at the kernel inputs `inputs` (one slice per
/// [`HostInput`] of `layout`), every host part retracted to first order in
/// `H`'s chart by its columns of `delta` (the parts' tangents stacked, in
/// order): the function whose derivative at `δ = 0` is the Jacobian in the
/// host's chart. Dual numbers evaluate it; the code generator traces it.
///
/// # Panics
///
/// If a slice's or `delta`'s length is not the layout's, or a variable has
/// more than [`MAX_VARIABLE_PARAMETERS`] host parameters.
pub fn host_residual<F: HostFactor<H>, H: Host, T: Scalar>(
    layout: &HostLayout<H::Manifold>,
    inputs: &[&[T]],
    delta: &[T],
) -> Vec<T> {
    let mut stored = vec![T::zero(); layout.stored];
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
                part,
                columns,
                ..
            } => {
                let n = part.manifold.parameters();
                part.manifold.retract_first_order(
                    values,
                    &delta[columns.clone()],
                    &mut params[filled..filled + n],
                );
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
    F::residual_over(&stored)
}

/// Validates factor `F` at the host values `parts`, its stored scalars
/// rebuilt in a stack buffer of `N` (at least `layout.stored`) from
/// `template` (its constants) and the parts.
fn validate_in<const N: usize, F: HostFactor<H>, H: Host>(
    layout: &HostLayout<H::Manifold>,
    template: &[f64],
    parts: &[&[f64]],
) -> Result<(), FactorError> {
    let mut stored = [0.0; N];
    let stored = &mut stored[..layout.stored];
    stored.copy_from_slice(template);
    variables_from_host::<F, H>(layout, parts, stored);
    F::from_scalars(stored).validate()
}

/// Validates factor `F` at the host values `parts`. The buffer's size class
/// is chosen by the factor's size: zeroing [`MAX_STORED`] scalars at every
/// call would cost as much as a small kernel.
fn validate<F: HostFactor<H>, H: Host>(
    layout: &HostLayout<H::Manifold>,
    template: &[f64],
    parts: &[&[f64]],
) -> Result<(), FactorError> {
    match layout.stored {
        ..=16 => validate_in::<16, F, H>(layout, template, parts),
        17..=32 => validate_in::<32, F, H>(layout, template, parts),
        33..=64 => validate_in::<64, F, H>(layout, template, parts),
        _ => validate_in::<MAX_STORED, F, H>(layout, template, parts),
    }
}

/// Residual and column-major Jacobian (`None` when not wanted) of factor `F`
/// in `H`'s chart through its generated host kernel, with the factor's
/// validation at the host's values: `template` is the factor's stored
/// scalars (its constants; its variables' are not read), `parts` the host
/// parts' parameters. No allocation. On an error the outputs hold
/// unspecified values (the kernel runs before the validation).
///
/// # Errors
///
/// The validation's error, [`FactorError::NonFinite`] naming the first
/// non-finite output (a Jacobian column by its variable), or (a debug
/// build) [`FactorError::StaleKernel`].
///
/// # Panics
///
/// If a length differs from the layout's, or the layout has more than
/// [`MAX_STORED`] stored scalars.
pub fn linearize_host<F: HostKernel<H>, H: Host>(
    layout: &HostLayout<H::Manifold>,
    template: &[f64],
    parts: &[&[f64]],
    residual: &mut [f64],
    mut jacobian: Option<&mut [f64]>,
) -> Result<(), FactorError> {
    run_host_kernel::<F, H>(template, parts, residual, jacobian.as_deref_mut());
    // After the kernel: the validation between its stores and the check's
    // loads of the same values keeps those loads from waiting for the stores.
    validate::<F, H>(layout, template, parts)?;
    F::check_host_kernel(template, parts, residual, jacobian.as_deref())?;
    check_finite::<F, H>(layout, residual, jacobian.as_deref())
}

/// [`linearize_host`] at host values the caller knows the factor accepts:
/// the same outputs without the validation, their finiteness still
/// checked. A solver that evaluates every trial step's residuals
/// ([`linearize_host`] with no Jacobian asked for) and linearizes only where
/// it accepted a step meets no configuration here that the validation has
/// not passed (`factor-apex` serves apex-solver's linearization passes so).
///
/// # Errors
///
/// [`FactorError::NonFinite`] naming the first non-finite output, or (a
/// debug build) [`FactorError::StaleKernel`].
///
/// # Panics
///
/// If a length differs from the layout's.
pub fn linearize_host_validated<F: HostKernel<H>, H: Host>(
    layout: &HostLayout<H::Manifold>,
    template: &[f64],
    parts: &[&[f64]],
    residual: &mut [f64],
    mut jacobian: Option<&mut [f64]>,
) -> Result<(), FactorError> {
    run_host_kernel::<F, H>(template, parts, residual, jacobian.as_deref_mut());
    F::check_host_kernel(template, parts, residual, jacobian.as_deref())?;
    check_finite::<F, H>(layout, residual, jacobian.as_deref())
}

/// `F`'s host kernel on the host values `parts`.
///
/// # Panics
///
/// If a length differs from the kernel's.
#[inline(always)]
fn run_host_kernel<F: HostKernel<H>, H: Host>(
    template: &[f64],
    parts: &[&[f64]],
    residual: &mut [f64],
    jacobian: Option<&mut [f64]>,
) {
    assert!(
        F::host_kernel(template, parts, residual, jacobian),
        "{}: the stored scalars, a part, the residual or the Jacobian differ in length from \
         the host kernel's",
        F::NAME
    );
}

/// [`linearize_host`] by dual numbers: the same outputs to rounding, for
/// any [`HostFactor`], with or without a generated host kernel. One pass of
/// the factor's residual on [`Dual`] numbers as wide as its tangent, each
/// host part seeded through the host's retraction ([`dual_pass`]).
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
    template: &[f64],
    parts: &[&[f64]],
    residual: &mut [f64],
    jacobian: Option<&mut [f64]>,
) -> Result<(), FactorError> {
    F::linearize_host_dual_pass(layout, template, parts, residual, jacobian)
}

/// The most stored scalars, and residual entries, [`dual_pass`] keeps on the
/// stack; a larger factor's go to the heap.
const STACK_SCALARS: usize = 32;

/// `f` on a scratch slice of `len` copies of `zero`: on the stack up to `M`,
/// on the heap beyond.
fn scratch<T: Copy, const M: usize, R>(len: usize, zero: T, f: impl FnOnce(&mut [T]) -> R) -> R {
    if len <= M {
        f(&mut [zero; M][..len])
    } else {
        f(&mut vec![zero; len])
    }
}

/// The body of [`linearize_host_dual`] for a factor of `N` tangent columns
/// (the host's columns, when as many; otherwise, for a variable served as
/// more host coordinates than its dimension, one column at a time):
/// validates the factor at the host's
/// values, seeds each host part's parameters through the host's
/// [`HostManifold::retract_first_order`] (its derivative at `δ = 0`, by
/// one-component dual numbers per column: a few operations per part), maps
/// them to the variables' stored scalars ([`HostMap::stored_from_host`](crate::host::HostMap::stored_from_host)),
/// and evaluates the residual once on `Dual<N>`
/// ([`Factor::residual_over_into`](crate::Factor::residual_over_into)).
/// No allocation for factors of up to 32 stored scalars.
///
/// # Errors
///
/// As [`linearize_host`].
///
/// # Panics
///
/// As [`linearize_host`].
pub fn dual_pass<F: HostFactor<H>, H: Host, const N: usize>(
    layout: &HostLayout<H::Manifold>,
    template: &[f64],
    parts: &[&[f64]],
    residual: &mut [f64],
    mut jacobian: Option<&mut [f64]>,
) -> Result<(), FactorError> {
    validate::<F, H>(layout, template, parts)?;
    if layout.columns() != N {
        return dual_by_columns::<F, H>(layout, template, parts, residual, jacobian);
    }
    let zero = Dual::<N>::constant(0.0);
    let rows = layout.residual;
    scratch::<_, STACK_SCALARS, _>(layout.stored, zero, |stored| {
        let mut params = [zero; MAX_VARIABLE_PARAMETERS];
        let mut filled = 0;
        for (k, input) in layout.inputs.iter().enumerate() {
            match input {
                HostInput::Constant { stored: range, .. } => {
                    for (s, v) in stored[range.clone()]
                        .iter_mut()
                        .zip(&template[range.clone()])
                    {
                        *s = Dual::constant(*v);
                    }
                }
                HostInput::Part {
                    index,
                    variable,
                    stored: range,
                    part,
                    columns,
                    ..
                } => {
                    let n = part.manifold.parameters();
                    seed_part(
                        part.manifold,
                        parts[*index],
                        columns.start,
                        &mut params[filled..filled + n],
                    );
                    filled += n;
                    let last_part = !matches!(
                        layout.inputs.get(k + 1),
                        Some(HostInput::Part { variable: next, .. }) if next == variable
                    );
                    if last_part {
                        F::stored_from_host(
                            *variable,
                            &params[..filled],
                            &mut stored[range.clone()],
                        );
                        filled = 0;
                    }
                }
            }
        }
        scratch::<_, STACK_SCALARS, _>(rows, zero, |value| {
            F::residual_over_into(stored, value);
            for (out, r) in residual.iter_mut().zip(value.iter()) {
                *out = r.re;
            }
            if let Some(jacobian) = jacobian.as_deref_mut() {
                for (c, column) in jacobian.chunks_mut(rows).enumerate() {
                    for (out, r) in column.iter_mut().zip(value.iter()) {
                        *out = r.eps[c];
                    }
                }
            }
        });
    });
    check_finite::<F, H>(layout, residual, jacobian.as_deref())
}

/// [`dual_pass`] for a factor whose host columns are not its own tangent's
/// (a variable served as more host coordinates than its dimension, as S²
/// served as `Rn(3)` normalised): one pass of [`host_residual`] on
/// one-component dual numbers per column, allocating.
fn dual_by_columns<F: HostFactor<H>, H: Host>(
    layout: &HostLayout<H::Manifold>,
    template: &[f64],
    parts: &[&[f64]],
    residual: &mut [f64],
    mut jacobian: Option<&mut [f64]>,
) -> Result<(), FactorError> {
    type D = Dual<1>;
    let lifted: Vec<Vec<D>> = inputs_of(layout, template, parts)
        .iter()
        .map(|values| values.iter().map(|x| D::constant(*x)).collect())
        .collect();
    let lifted: Vec<&[D]> = lifted.iter().map(Vec::as_slice).collect();
    let mut delta = vec![D::constant(0.0); layout.columns()];
    let rows = layout.residual;
    let value = host_residual::<F, H, D>(layout, &lifted, &delta);
    for (out, r) in residual.iter_mut().zip(&value) {
        *out = r.re;
    }
    if let Some(jacobian) = jacobian.as_deref_mut() {
        for (c, column) in jacobian.chunks_mut(rows).enumerate() {
            delta[c] = D::variable(0.0, 0);
            let r = host_residual::<F, H, D>(layout, &lifted, &delta);
            delta[c] = D::constant(0.0);
            for (out, value) in column.iter_mut().zip(&r) {
                *out = value.eps[0];
            }
        }
    }
    check_finite::<F, H>(layout, residual, jacobian.as_deref())
}

/// A host part's parameters `values` as `Dual<N>` numbers carrying the
/// derivative of the host's first-order retraction at `δ = 0` in columns
/// `first_column..first_column + dof`: one pass of the retraction on
/// one-component dual numbers per column.
fn seed_part<M: HostManifold, const N: usize>(
    manifold: M,
    values: &[f64],
    first_column: usize,
    out: &mut [Dual<N>],
) {
    let (n, dof) = (values.len(), manifold.dof());
    let mut lifted = [Dual::<1>::constant(0.0); MAX_VARIABLE_PARAMETERS];
    for (l, v) in lifted.iter_mut().zip(values) {
        *l = Dual::constant(*v);
    }
    let mut delta = [Dual::<1>::constant(0.0); MAX_VARIABLE_PARAMETERS];
    let mut moved = [Dual::<1>::constant(0.0); MAX_VARIABLE_PARAMETERS];
    manifold.retract_first_order(&lifted[..n], &delta[..dof], &mut moved[..n]);
    for (o, m) in out.iter_mut().zip(&moved[..n]) {
        *o = Dual::constant(m.re);
    }
    for c in 0..dof {
        delta[c] = Dual::variable(0.0, 0);
        manifold.retract_first_order(&lifted[..n], &delta[..dof], &mut moved[..n]);
        delta[c] = Dual::constant(0.0);
        for (o, m) in out.iter_mut().zip(&moved[..n]) {
            o.eps[first_column + c] = m.eps[0];
        }
    }
}

/// [`FactorError::NonFinite`] for the first non-finite output, a Jacobian
/// column named by its variable. One pass sums the outputs (a sum of finite
/// values is finite unless it overflows); only a sum that is not finite is
/// followed by the search for the culprit.
fn check_finite<F: HostFactor<H>, H: Host>(
    layout: &HostLayout<H::Manifold>,
    residual: &[f64],
    jacobian: Option<&[f64]>,
) -> Result<(), FactorError> {
    let jacobian = jacobian.unwrap_or_default();
    // Not short-circuiting and not a sum: a sum's additions form one
    // dependent chain (a latency of ~100 cycles for BAL's 26 values, a
    // third of its kernel), these independent tests vectorise.
    let finite = |values: &[f64]| values.iter().fold(true, |ok, x| ok & x.is_finite());
    if finite(residual) & finite(jacobian) {
        return Ok(());
    }
    if residual.iter().any(|x| !x.is_finite()) {
        return Err(FactorError::non_finite_output::<F>(None));
    }
    let Some(at) = jacobian.iter().position(|x| !x.is_finite()) else {
        return Ok(());
    };
    let column = at / layout.residual.max(1);
    let variable = layout.inputs.iter().find_map(|input| match input {
        HostInput::Part {
            variable, columns, ..
        } if columns.contains(&column) => Some(*variable),
        _ => None,
    });
    Err(FactorError::non_finite_output::<F>(variable))
}
