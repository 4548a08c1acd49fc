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

use std::marker::PhantomData;
use std::ops::Range;
use std::sync::atomic::{AtomicUsize, Ordering};
use std::sync::{Arc, OnceLock};

use apex_solver::core::variable::ManifoldVariable;
use factor_core::FactorError;
use factor_core::host::{
    Apex, ApexManifold, HostFactor, HostInput, HostKernel, HostLayout, HostManifold, MAX_STORED,
    linearize_host, linearize_host_dual,
};
use faer::prelude::ReborrowMut;

use crate::AdapterError;

/// The most kernel inputs (constant fields and host parts) of a served factor.
pub const MAX_INPUTS: usize = 16;
/// The most host parts (apex variables) of a served factor.
pub const MAX_PARTS: usize = 8;
/// The most Jacobian entries (residual rows × tangent columns) of a served factor.
pub const MAX_JACOBIAN: usize = 256;

/// How an [`ApexFactor`] linearizes.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum Kernels {
    /// The factor's generated apex kernel ([`HostKernel`]).
    #[default]
    Generated,
    /// Dual numbers through the same host trace ([`linearize_host_dual`]):
    /// the same factor, for comparison.
    Dual,
}

impl Kernels {
    /// `generated` or `dual`.
    pub fn name(self) -> &'static str {
        match self {
            Kernels::Generated => "generated",
            Kernels::Dual => "dual",
        }
    }
}

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

/// Where one kernel input comes from at a call.
#[derive(Debug, Clone)]
enum Source {
    /// The factor's stored constants.
    Constant(Range<usize>),
    /// apex's parameter slice of this index.
    Apex(usize),
}

/// The linearization through the host layout: [`linearize_host`] or
/// [`linearize_host_dual`] for the factor type.
type Linearize = fn(
    &HostLayout<ApexManifold>,
    &[&[f64]],
    &mut [f64],
    &mut [Option<&mut [f64]>],
) -> Result<(), FactorError>;

/// A derived factor served to apex-solver: register it on the apex keys of
/// its variables' host parts, in declaration order ([`ApexFactor::parts`]).
pub struct ApexFactor<F> {
    /// The factor's stored scalars (its variables' are not read).
    stored: Vec<f64>,
    layout: HostLayout<ApexManifold>,
    sources: Vec<Source>,
    linearize: Linearize,
    kernels: Kernels,
    rejections: Option<Arc<Rejections>>,
    _factor: PhantomData<fn() -> F>,
}

impl<F: HostFactor<Apex>> ApexFactor<F> {
    /// `factor` (its constants; its variables' values are read from apex at
    /// each call) served through `linearize`.
    fn with(factor: &F, linearize: Linearize, kernels: Kernels) -> Result<Self, AdapterError> {
        let layout = HostLayout::of::<F, Apex>();
        if layout.stored > MAX_STORED
            || layout.inputs.len() > MAX_INPUTS
            || layout.parts.len() > MAX_PARTS
            || layout.residual * layout.columns() > MAX_JACOBIAN
        {
            return Err(AdapterError::TooLarge { factor: F::NAME });
        }
        let sources = layout
            .inputs
            .iter()
            .map(|input| match input {
                HostInput::Constant { stored, .. } => Source::Constant(stored.clone()),
                HostInput::Part { index, .. } => Source::Apex(*index),
            })
            .collect();
        Ok(ApexFactor {
            stored: factor.to_scalars(),
            layout,
            sources,
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
    /// ([`MAX_INPUTS`], [`MAX_PARTS`], [`MAX_JACOBIAN`], [`MAX_STORED`]).
    pub fn dual(factor: &F) -> Result<Self, AdapterError> {
        Self::with(factor, linearize_host_dual::<F, Apex>, Kernels::Dual)
    }

    /// Counts rejected evaluations in `rejections`.
    pub fn with_rejections(mut self, rejections: Arc<Rejections>) -> Self {
        self.rejections = Some(rejections);
        self
    }

    /// The apex variables (host parts) the factor connects, in order: the
    /// keys it is registered on are theirs.
    pub fn parts(&self) -> Vec<ApexManifold> {
        self.layout.parts.iter().map(|p| p.manifold).collect()
    }

    /// How it linearizes.
    pub fn kernels(&self) -> Kernels {
        self.kernels
    }
}

impl<F: HostKernel<Apex>> ApexFactor<F> {
    /// `factor` linearized by `kernels`: its generated apex kernel, or dual
    /// numbers in the same chart.
    ///
    /// # Errors
    ///
    /// As [`ApexFactor::dual`].
    pub fn new(factor: &F, kernels: Kernels) -> Result<Self, AdapterError> {
        match kernels {
            Kernels::Generated => Self::with(factor, linearize_host::<F, Apex>, kernels),
            Kernels::Dual => Self::dual(factor),
        }
    }
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
    /// The kernel inputs of one call: the constants and apex's slices.
    fn inputs<'a>(&'a self, params: &[&'a [f64]]) -> [&'a [f64]; MAX_INPUTS] {
        let mut inputs: [&[f64]; MAX_INPUTS] = [&[]; MAX_INPUTS];
        for (slot, source) in inputs.iter_mut().zip(&self.sources) {
            *slot = match source {
                Source::Constant(range) => &self.stored[range.clone()],
                Source::Apex(k) => params[*k],
            };
        }
        inputs
    }

    /// Splits `jacobian` (column-major, the parts' columns in order) into
    /// one block per part.
    fn blocks<'a>(&self, mut jacobian: &'a mut [f64]) -> [Option<&'a mut [f64]>; MAX_PARTS] {
        let mut blocks: [Option<&mut [f64]>; MAX_PARTS] = Default::default();
        for (block, part) in blocks.iter_mut().zip(&self.layout.parts) {
            let (head, tail) = jacobian.split_at_mut(self.layout.residual * part.manifold.dof());
            *block = Some(head);
            jacobian = tail;
        }
        blocks
    }

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
        let inputs = self.inputs(params);
        let inputs = &inputs[..self.sources.len()];
        let parts = self.layout.parts.len();
        let result = match jacobian {
            None => {
                let mut none: [Option<&mut [f64]>; MAX_PARTS] = Default::default();
                (self.linearize)(&self.layout, inputs, residual, &mut none[..parts])
            }
            Some(mut jacobian) => {
                let mut scratch = [0.0; MAX_JACOBIAN];
                let direct = contiguous(jacobian.rb_mut());
                let (result, copy_back) = match direct {
                    Some(slice) => {
                        let mut blocks = self.blocks(slice);
                        let result =
                            (self.linearize)(&self.layout, inputs, residual, &mut blocks[..parts]);
                        (result, false)
                    }
                    None => {
                        let len = self.layout.residual * self.layout.columns();
                        let mut blocks = self.blocks(&mut scratch[..len]);
                        let result =
                            (self.linearize)(&self.layout, inputs, residual, &mut blocks[..parts]);
                        (result, true)
                    }
                };
                if result.is_err() {
                    jacobian.fill(f64::NAN);
                } else if copy_back {
                    let rows = self.layout.residual;
                    for (j, column) in scratch.chunks(rows).take(jacobian.ncols()).enumerate() {
                        for (r, value) in column.iter().enumerate() {
                            *jacobian.rb_mut().get_mut(r, j) = *value;
                        }
                    }
                }
                result
            }
        };
        if let Err(error) = result {
            self.reject(&error, residual);
        }
    }

    fn residual_dim(&self) -> usize {
        self.layout.residual
    }

    fn jacobian_shape(&self) -> (usize, usize) {
        (self.layout.residual, self.layout.columns())
    }

    fn validate_variables(&self, variables: &[&dyn ManifoldVariable]) -> Result<(), String> {
        let parts = &self.layout.parts;
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
