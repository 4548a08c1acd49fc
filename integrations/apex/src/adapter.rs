//! [`ApexFactor`]: any derived factor as an apex-solver factor, in apex's
//! own chart and parameter layout.
//!
//! apex-solver calls `Factor::linearize(params, residual, jacobian)` with one
//! parameter slice per apex variable and a column-major `rows × Σ dof`
//! Jacobian. A factor's variables are served as apex variables through
//! their [`HostMap<Apex>`](factor_core::host::HostMap) (a pose is one `SE3`,
//! an orthonormal line an `SO3` and an `SO2`, …; [`factor_core::host`]), so
//! each apex slice is one input of the factor's kernel in apex's layout
//! ([`HostLayout`]), and the factor's constants are the others. The
//! generated apex kernel (`<factor>_apex`, [`HostKernel`]) reads those
//! slices where apex keeps them and writes its column-major blocks straight
//! into apex's matrix: nothing is copied or permuted, and no adjoint is
//! applied, whatever chart the factor was written in. Dual numbers through
//! the same host trace ([`linearize_host_dual`]) are the comparison path.
//!
//! A configuration the factor rejects (a point behind the camera, a folding
//! distortion) has no residual: the adapter writes NaN, which makes apex
//! reject a trial step there (its step quality is NaN, so not above the
//! acceptance threshold) as Ceres rejects a step when a cost function
//! returns `false`; each such evaluation is counted in [`Rejections`].

use std::any::TypeId;
use std::collections::HashMap;
use std::marker::PhantomData;
use std::sync::atomic::{AtomicUsize, Ordering};
use std::sync::{Arc, Mutex, OnceLock, PoisonError};

use apex_solver::core::variable::ManifoldVariable;
use factor_core::FactorError;
use factor_core::host::{
    Apex, ApexManifold, HostFactor, HostKernel, HostLayout, HostManifold, MAX_STORED,
    MAX_VARIABLE_PARAMETERS, host_parameters, linearize_host, linearize_host_dual,
    linearize_host_validated,
};
use faer::prelude::ReborrowMut;
/// How an [`ApexFactor`] linearizes: its generated apex kernel
/// ([`HostKernel`]) or dual numbers through the same host trace
/// ([`linearize_host_dual`]).
pub use slam_problems::Kernels;
use smallvec::SmallVec;

use crate::error::AdapterError;

/// Evaluations at configurations a factor rejected, shared by the factors
/// of a problem.
#[derive(Debug, Default)]
pub struct Rejections {
    count: AtomicUsize,
    first: OnceLock<String>,
}

impl Rejections {
    /// A shared, empty record.
    pub fn new() -> Arc<Self> {
        Arc::new(Rejections::default())
    }

    fn record(&self, error: &FactorError) {
        self.count.fetch_add(1, Ordering::Relaxed);
        self.first.get_or_init(|| error.to_string());
    }

    /// How many evaluations were rejected.
    pub fn count(&self) -> usize {
        self.count.load(Ordering::Relaxed)
    }

    /// The first rejection's message.
    pub fn first(&self) -> Option<&str> {
        self.first.get().map(String::as_str)
    }
}

/// What every factor of one type shares: its layout in apex's chart.
/// Computed once per factor type ([`plan_of`]) and shared by reference, so
/// a problem of a million blocks holds a million references, not a million
/// layouts, and a linearization pass reads one plan from cache.
#[derive(Debug)]
struct Plan {
    layout: HostLayout<ApexManifold>,
}

/// The plan of factor type `F`: built the first time it is asked for and
/// kept for the process (one per factor type served: a bounded set).
fn plan_of<F: HostFactor<Apex> + 'static>() -> &'static Plan {
    static PLANS: OnceLock<Mutex<HashMap<TypeId, &'static Plan>>> = OnceLock::new();
    let mut plans = PLANS
        .get_or_init(Default::default)
        .lock()
        .unwrap_or_else(PoisonError::into_inner);
    plans.entry(TypeId::of::<F>()).or_insert_with(|| {
        Box::leak(Box::new(Plan {
            layout: HostLayout::of::<F, Apex>(),
        }))
    })
}

/// A linearization through the host layout for the factor type
/// ([`linearize_host`], [`linearize_validated`], [`linearize_host_dual`]).
type Linearize = fn(
    &HostLayout<ApexManifold>,
    &[f64],
    &[&[f64]],
    &mut [f64],
    Option<&mut [f64]>,
) -> Result<(), FactorError>;

/// A factor's stored scalars, inline up to this many (the shipped
/// reprojection factors hold 14 to 20): no allocation per block.
const INLINE_STORED: usize = 24;

/// A derived factor served to apex-solver: register it on the apex keys of
/// its variables' host parts, in declaration order ([`ApexFactor::parts`]).
pub struct ApexFactor<F> {
    /// The factor's stored scalars (its variables' are not read).
    stored: SmallVec<[f64; INLINE_STORED]>,
    plan: &'static Plan,
    /// The residual-only evaluation of a trial step: validates.
    evaluate: Linearize,
    /// The linearization pass, at a configuration apex has evaluated and
    /// accepted.
    linearize: Linearize,
    kernels: Kernels,
    rejections: Option<Arc<Rejections>>,
    _factor: PhantomData<fn() -> F>,
}

impl<F: HostFactor<Apex> + 'static> ApexFactor<F> {
    /// `factor` (its constants; its variables' values are read from apex at
    /// each call) served through `evaluate` (residual only) and `linearize`.
    fn with(
        factor: &F,
        evaluate: Linearize,
        linearize: Linearize,
        kernels: Kernels,
    ) -> Result<Self, AdapterError> {
        let plan = plan_of::<F>();
        let layout = &plan.layout;
        let variable_parameters = layout.variables.iter().map(|v| {
            layout.parts[v.parts.clone()]
                .iter()
                .map(|p| p.manifold.parameters())
                .sum::<usize>()
        });
        if layout.stored > MAX_STORED
            || variable_parameters
                .clone()
                .any(|n| n > MAX_VARIABLE_PARAMETERS)
        {
            return Err(AdapterError::TooLarge { factor: F::NAME });
        }
        let mut stored = SmallVec::from_elem(0.0, F::SCALARS);
        factor.write_scalars(&mut stored);
        Ok(ApexFactor {
            stored,
            plan,
            evaluate,
            linearize,
            kernels,
            rejections: None,
            _factor: PhantomData,
        })
    }

    /// `factor` linearized by dual numbers in apex's chart: any factor
    /// whose variables have a mapping onto apex, with or without a
    /// generated apex kernel.
    ///
    /// # Errors
    ///
    /// [`AdapterError::TooLarge`] beyond the adapter's stack buffers
    /// ([`MAX_STORED`], [`MAX_VARIABLE_PARAMETERS`]).
    pub fn dual(factor: &F) -> Result<Self, AdapterError> {
        let dual = linearize_host_dual::<F, Apex>;
        Self::with(factor, dual, dual, Kernels::Dual)
    }

    /// Linearizes the factor as the solver will, at its own values (`factor`,
    /// the one it was built from): its validation there, and in a debug
    /// build the check that its generated kernel is current
    /// ([`factor_core::kernel`]), before a solve depends on either.
    ///
    /// # Errors
    ///
    /// The linearization's: the validation's error,
    /// [`FactorError::NonFinite`], or [`FactorError::StaleKernel`].
    pub fn linearize_at(&self, factor: &F) -> Result<(), FactorError> {
        let layout = &self.plan.layout;
        let parts = host_parameters::<F, Apex>(layout, factor);
        let parts: Vec<&[f64]> = parts.iter().map(Vec::as_slice).collect();
        let mut residual = vec![0.0; layout.residual];
        let mut jacobian = vec![0.0; layout.residual * layout.columns()];
        (self.evaluate)(
            layout,
            &self.stored,
            &parts,
            &mut residual,
            Some(&mut jacobian),
        )
    }

    /// Counts rejected evaluations in `rejections`.
    pub fn with_rejections(mut self, rejections: Arc<Rejections>) -> Self {
        self.rejections = Some(rejections);
        self
    }

    /// The apex variables (host parts) the factor connects, in order: the
    /// keys it is registered on are theirs.
    pub fn parts(&self) -> Vec<ApexManifold> {
        self.plan.layout.parts.iter().map(|p| p.manifold).collect()
    }

    /// How it linearizes.
    pub fn kernels(&self) -> Kernels {
        self.kernels
    }
}

impl<F: HostKernel<Apex> + 'static> ApexFactor<F> {
    /// `factor` linearized by `kernels`: its generated apex kernel, or dual
    /// numbers in the same chart.
    ///
    /// # Errors
    ///
    /// As [`ApexFactor::dual`].
    pub fn new(factor: &F, kernels: Kernels) -> Result<Self, AdapterError> {
        match kernels {
            Kernels::Generated => Self::with(
                factor,
                linearize_host::<F, Apex>,
                linearize_validated::<F>,
                kernels,
            ),
            Kernels::Dual => Self::dual(factor),
        }
    }
}

/// The generated kernel without the validation
/// ([`linearize_host_validated`]): apex linearizes only at configurations
/// whose residuals it evaluated (validated there: a rejected evaluation is
/// NaN and its step is refused) or that the problem's builder validated
/// (the initial values), so the validation is where a configuration is
/// first met, not repeated in the linearization pass.
fn linearize_validated<F: HostKernel<Apex>>(
    layout: &HostLayout<ApexManifold>,
    template: &[f64],
    parts: &[&[f64]],
    residual: &mut [f64],
    jacobian: Option<&mut [f64]>,
) -> Result<(), FactorError> {
    linearize_host_validated::<F, Apex>(layout, template, parts, residual, jacobian)
}

/// apex's column-major Jacobian as one slice, when its columns lie end to
/// end (apex always passes such a matrix, built from a slice).
fn contiguous(jacobian: faer::mat::MatMut<'_, f64>) -> Option<&mut [f64]> {
    let (rows, columns) = (jacobian.nrows(), jacobian.ncols());
    let end_to_end = jacobian.row_stride() == 1
        && usize::try_from(jacobian.col_stride()).is_ok_and(|stride| stride == rows);
    if !end_to_end || rows * columns == 0 {
        return None;
    }
    // SAFETY: a `MatMut` is the unique borrow of its `rows × columns`
    // elements for its lifetime; with a row stride of 1 and a column stride
    // of `rows` those elements are exactly the `rows · columns` consecutive
    // values from `as_ptr_mut()`, which the returned slice borrows for the
    // same lifetime (the `MatMut` is consumed).
    Some(unsafe { std::slice::from_raw_parts_mut(jacobian.as_ptr_mut(), rows * columns) })
}

impl<F: HostFactor<Apex>> ApexFactor<F> {
    fn reject(&self, error: &FactorError, residual: &mut [f64]) {
        residual.fill(f64::NAN);
        if let Some(rejections) = &self.rejections {
            rejections.record(error);
        }
    }
}

impl<F: HostFactor<Apex>> apex_solver::factors::Factor for ApexFactor<F> {
    fn linearize(
        &self,
        params: &[&[f64]],
        residual: &mut [f64],
        jacobian: Option<faer::mat::MatMut<'_, f64>>,
    ) {
        let layout = &self.plan.layout;
        let result = match jacobian {
            None => (self.evaluate)(layout, &self.stored, params, residual, None),
            Some(mut jacobian) => match contiguous(jacobian.rb_mut()) {
                Some(slice) => {
                    let result =
                        (self.linearize)(layout, &self.stored, params, residual, Some(slice));
                    if result.is_err() {
                        jacobian.fill(f64::NAN);
                    }
                    result
                }
                // A view with other strides (apex never passes one): the
                // Jacobian goes through a buffer.
                None => {
                    let rows = layout.residual;
                    let mut scratch = vec![0.0; rows * layout.columns()];
                    let result = (self.linearize)(
                        layout,
                        &self.stored,
                        params,
                        residual,
                        Some(&mut scratch),
                    );
                    for (j, column) in scratch.chunks(rows).enumerate() {
                        for (r, value) in column.iter().enumerate() {
                            *jacobian.rb_mut().get_mut(r, j) =
                                if result.is_ok() { *value } else { f64::NAN };
                        }
                    }
                    result
                }
            },
        };
        if let Err(error) = result {
            self.reject(&error, residual);
        }
    }

    fn residual_dim(&self) -> usize {
        self.plan.layout.residual
    }

    fn jacobian_shape(&self) -> (usize, usize) {
        (self.plan.layout.residual, self.plan.layout.columns())
    }

    fn validate_variables(&self, variables: &[&dyn ManifoldVariable]) -> Result<(), String> {
        let parts = &self.plan.layout.parts;
        if variables.len() != parts.len() {
            return Err(format!(
                "{} connects {} apex variables ({}), {} given",
                F::NAME,
                parts.len(),
                parts
                    .iter()
                    .map(|p| p.manifold.to_string())
                    .collect::<Vec<_>>()
                    .join(", "),
                variables.len()
            ));
        }
        for (k, (part, variable)) in parts.iter().zip(variables).enumerate() {
            let params = variable.as_param_slice().len();
            let manifold = part.manifold;
            if params != manifold.parameters() || variable.dof() != manifold.dof() {
                return Err(format!(
                    "{}: apex variable {k} must be {manifold} ({} parameters, {} tangent \
                     coordinates), given {params} and {}",
                    F::NAME,
                    manifold.parameters(),
                    manifold.dof(),
                    variable.dof()
                ));
            }
        }
        Ok(())
    }
}
