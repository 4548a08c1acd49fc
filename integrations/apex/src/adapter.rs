//! [`ApexFactor`]: any derived factor as an apex-solver factor.
//!
//! apex-solver calls `Factor::linearize(params, residual, jacobian)` with one
//! parameter slice per variable and a column-major `rows × Σ dof` Jacobian.
//! The adapter writes the factor's stored scalars on the stack (its
//! constants, then each variable's apex parameters in the kernel's layout,
//! [`crate::variables`]), rebuilds the factor from them and calls its
//! allocation-free [`Factor::linearize_into`] (the generated kernel) or
//! [`Factor::linearize_dual_into`] (dual numbers), then copies the row-major
//! blocks into apex's matrix. No conversion of the Jacobian is needed: the
//! factor's poses are declared in apex's chart, so the kernel's columns are
//! apex's.
//!
//! A configuration the factor rejects (a point behind the camera, a folding
//! distortion) has no residual: the adapter writes NaN, which makes apex
//! reject a trial step there (its step quality is NaN, so not above the
//! acceptance threshold) as Ceres rejects a step when a cost function
//! returns `false`; each such evaluation is counted in [`Rejections`].

use std::marker::PhantomData;
use std::sync::atomic::{AtomicUsize, Ordering};
use std::sync::{Arc, OnceLock};

use apex_solver::core::variable::ManifoldVariable;
use factor_core::{Factor, FactorError};
use faer::prelude::ReborrowMut;

use crate::AdapterError;
use crate::variables::{ApexManifold, classify};

/// The most stored scalars a served factor may have (the between factor has 35).
pub const MAX_SCALARS: usize = 64;
/// The most variables a served factor may have.
pub const MAX_VARIABLES: usize = 4;
/// The most Jacobian entries (residual rows × tangent columns) a served factor may have.
pub const MAX_JACOBIAN: usize = 256;

/// How an [`ApexFactor`] linearizes.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum Kernels {
    /// The factor's generated kernel ([`Factor::linearize_into`]).
    #[default]
    Generated,
    /// Dual numbers ([`Factor::linearize_dual_into`]): the same factor, for
    /// comparison.
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

/// A derived factor served to apex-solver: register it with its variables'
/// keys in declaration order.
pub struct ApexFactor<F> {
    /// The factor's stored scalars; the variables' are overwritten per call.
    template: Vec<f64>,
    /// Each variable's apex manifold and the offset of its stored scalars.
    variables: Vec<(ApexManifold, usize)>,
    kernels: Kernels,
    rejections: Option<Arc<Rejections>>,
    _factor: PhantomData<fn() -> F>,
}

impl<F: Factor> ApexFactor<F> {
    /// Serves `factor` (its constants; its variables' values are read from
    /// apex at each call) through `kernels`.
    ///
    /// # Errors
    ///
    /// [`AdapterError::Unsupported`] for a variable apex cannot serve with
    /// the same tangent, [`AdapterError::TooLarge`] beyond the stack
    /// buffers ([`MAX_SCALARS`], [`MAX_VARIABLES`], [`MAX_JACOBIAN`]).
    pub fn new(factor: &F, kernels: Kernels) -> Result<Self, AdapterError> {
        if F::SCALARS > MAX_SCALARS
            || F::variables().len() > MAX_VARIABLES
            || F::RESIDUAL_DIM * F::TANGENT_DIM > MAX_JACOBIAN
        {
            return Err(AdapterError::TooLarge { factor: F::NAME });
        }
        Ok(ApexFactor {
            template: factor.to_scalars(),
            variables: classify::<F>()?,
            kernels,
            rejections: None,
            _factor: PhantomData,
        })
    }

    /// Counts rejected evaluations in `rejections`.
    pub fn with_rejections(mut self, rejections: Arc<Rejections>) -> Self {
        self.rejections = Some(rejections);
        self
    }

    /// The apex manifold of each variable, in declaration order.
    pub fn manifolds(&self) -> Vec<ApexManifold> {
        self.variables.iter().map(|(m, _)| *m).collect()
    }
}

/// Writes row-major blocks (`rows ×` each block's columns), side by side,
/// into apex's `rows × Σ columns` matrix, column by column: through
/// contiguous slices when its rows are contiguous (apex's always are).
fn write_column_major<'b>(
    mut jacobian: faer::mat::MatMut<'_, f64>,
    rows: usize,
    blocks: impl Iterator<Item = (usize, &'b [f64])>,
) {
    let columns = blocks.flat_map(|(dof, block)| (0..dof).map(move |c| (dof, block, c)));
    match jacobian.rb_mut().try_as_col_major_mut() {
        Some(matrix) => {
            for (column, (dof, block, c)) in matrix.col_iter_mut().zip(columns) {
                for (r, slot) in column.as_slice_mut().iter_mut().enumerate() {
                    *slot = block[r * dof + c];
                }
            }
        }
        None => {
            for (j, (dof, block, c)) in columns.enumerate() {
                for r in 0..rows {
                    *jacobian.rb_mut().get_mut(r, j) = block[r * dof + c];
                }
            }
        }
    }
}

impl<F: Factor> ApexFactor<F> {
    /// [`apex_solver::factors::Factor::linearize`] with stack buffers of `S`
    /// stored scalars and `J` Jacobian entries (zeroed at each call, so
    /// sized to the factor: see `linearize`).
    fn linearize_with<const S: usize, const J: usize>(
        &self,
        params: &[&[f64]],
        residual: &mut [f64],
        jacobian: Option<faer::mat::MatMut<'_, f64>>,
    ) {
        let rows = F::RESIDUAL_DIM;
        let mut stored = [0.0; S];
        let stored = &mut stored[..self.template.len()];
        stored.copy_from_slice(&self.template);
        for ((manifold, offset), apex) in self.variables.iter().zip(params) {
            manifold.stored_from_apex(apex, &mut stored[*offset..]);
        }
        let mut scratch = [0.0; J];
        let mut blocks: [Option<&mut [f64]>; MAX_VARIABLES] = Default::default();
        if jacobian.is_some() {
            let mut rest = &mut scratch[..];
            for ((manifold, _), block) in self.variables.iter().zip(blocks.iter_mut()) {
                let (head, tail) = rest.split_at_mut(rows * manifold.dof());
                *block = Some(head);
                rest = tail;
            }
        }
        let blocks = &mut blocks[..self.variables.len()];
        let result = match self.kernels {
            Kernels::Generated => F::linearize_stored_into(stored, residual, blocks),
            Kernels::Dual => F::from_scalars(stored).linearize_dual_into(residual, blocks),
        };
        match (result, jacobian) {
            (Ok(()), Some(jacobian)) => {
                let blocks =
                    self.variables
                        .iter()
                        .zip(blocks.iter())
                        .map(|((manifold, _), block)| {
                            (manifold.dof(), block.as_deref().unwrap_or_default())
                        });
                write_column_major(jacobian, rows, blocks);
            }
            (Ok(()), None) => {}
            (Err(error), jacobian) => {
                residual.fill(f64::NAN);
                if let Some(mut jacobian) = jacobian {
                    jacobian.fill(f64::NAN);
                }
                if let Some(rejections) = &self.rejections {
                    rejections.record(&error);
                }
            }
        }
    }
}

impl<F: Factor> apex_solver::factors::Factor for ApexFactor<F> {
    fn linearize(
        &self,
        params: &[&[f64]],
        residual: &mut [f64],
        jacobian: Option<faer::mat::MatMut<'_, f64>>,
    ) {
        // Size classes of the stack buffers, chosen by constants (the other
        // arms compile away): zeroing 2 KiB at every call would cost as much
        // as a small kernel.
        let (scalars, entries) = (F::SCALARS, F::RESIDUAL_DIM * F::TANGENT_DIM);
        match (scalars <= 16, entries <= 32) {
            (true, true) => self.linearize_with::<16, 32>(params, residual, jacobian),
            (false, true) => self.linearize_with::<MAX_SCALARS, 32>(params, residual, jacobian),
            (true, false) => self.linearize_with::<16, MAX_JACOBIAN>(params, residual, jacobian),
            (false, false) => {
                self.linearize_with::<MAX_SCALARS, MAX_JACOBIAN>(params, residual, jacobian)
            }
        }
    }

    fn residual_dim(&self) -> usize {
        F::RESIDUAL_DIM
    }

    fn jacobian_shape(&self) -> (usize, usize) {
        (F::RESIDUAL_DIM, F::TANGENT_DIM)
    }

    fn validate_variables(&self, variables: &[&dyn ManifoldVariable]) -> Result<(), String> {
        if variables.len() != self.variables.len() {
            return Err(format!(
                "{} connects {} variables, {} given",
                F::NAME,
                self.variables.len(),
                variables.len()
            ));
        }
        for (k, ((manifold, _), variable)) in self.variables.iter().zip(variables).enumerate() {
            let params = variable.as_param_slice().len();
            if params != manifold.parameters() || variable.dof() != manifold.dof() {
                return Err(format!(
                    "{}: variable {k} ({}) needs {} parameters and {} tangent coordinates, \
                     given {params} and {}",
                    F::NAME,
                    F::variables()[k].name,
                    manifold.parameters(),
                    manifold.dof(),
                    variable.dof()
                ));
            }
        }
        Ok(())
    }
}
