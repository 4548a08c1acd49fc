//! The factors a command line knows ([`Registry`]): what `list` shows, what
//! `eval` evaluates, and what `generate` and `check` write into which
//! kernel crate ([`KernelCrate`]). `slamjac`'s own is
//! `slamjac::kernels::shipped`; a user's command line builds one of its own
//! factors (see `slamjac::cli`).
//!
//! Registering a factor is one call: its JSON form comes from its fields'
//! storage ([`slamjac_problem::decode`]).

use factor_codegen::{KernelSpec, Provenance};
use factor_core::host::{Apex, HostFactor, HostKernel};
use factor_core::{DynLinearization, Factor, FieldInfo, VariableInfo};
use slamjac_problem::InputError;
use slamjac_problem::decode::{decode, json_shape};
use slamjac_problem::field_path::quoted;
use slamjac_problem::input::Object;

use crate::error::RegistryError;
use crate::method::{Method, linearize};

/// One registered factor, its description and how to evaluate it from JSON.
#[derive(Debug, Clone, Copy)]
pub struct FactorEntry {
    /// The `factor` name used in the JSON input ([`factor_core::Factor::NAME`]).
    pub name: &'static str,
    /// Residual dimension (Jacobian rows).
    pub residual_dim: usize,
    /// The variables in declaration order ([`factor_core::Factor::variables`]).
    pub variables: fn() -> Vec<VariableInfo>,
    /// Every field in declaration order ([`factor_core::Factor::fields`]).
    pub fields: fn() -> Vec<FieldInfo>,
    /// The generated kernel `eval --method generated` uses
    /// ([`factor_core::Factor::KERNEL`]), if any.
    pub kernel: Option<&'static str>,
    /// Reads the factor from its checked `variables` and `constants` objects,
    /// validates it and linearizes it with the given method; returns the
    /// method used (see [`linearize`]).
    pub linearize: LinearizeFn,
    /// How `solve` linearizes it in apex-solver's chart, when it was
    /// registered for `solve` ([`Registry::solve_with_kernel`],
    /// [`Registry::solve_with_dual`]).
    pub solved_by: Option<SolvedBy>,
    /// How a problem file's entry of it is added to the problem.
    #[cfg(feature = "solve")]
    pub solve: Option<crate::problem_assembly::AddFn>,
    /// How it is added to the Schur-complement solver's problem and how
    /// that solver linearizes it, when it was registered for it
    /// ([`Registry::solve_with_schur`], [`Registry::solve_with_schur_each`]).
    #[cfg(feature = "solve")]
    pub schur: Option<(crate::schur_assembly::SchurAddFn, factor_schur::Linearized)>,
}

/// How `solve` linearizes a factor ([`FactorEntry::solved_by`]).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum SolvedBy {
    /// Its generated kernel in apex-solver's chart
    /// (`#[factor(kernel = …, hosts(apex))]`), or dual numbers under
    /// `solve --kernels dual`.
    Kernel,
    /// Dual numbers in apex-solver's chart.
    Dual,
}

/// How a [`FactorEntry`] evaluates: checked `variables` and `constants`
/// objects and the requested method → the linearization and the method used.
pub type LinearizeFn =
    fn(&Object, &Object, Method) -> Result<(DynLinearization, Method), RegistryError>;

impl FactorEntry {
    /// The entry of factor `F`.
    pub fn of<F: Factor>() -> Self {
        FactorEntry {
            name: F::NAME,
            residual_dim: F::RESIDUAL_DIM,
            variables: F::variables,
            fields: F::fields,
            kernel: F::KERNEL,
            linearize: |variables, constants, method| {
                let factor: F = decode(variables, constants)?;
                Ok(linearize(&factor, method)?)
            },
            solved_by: None,
            #[cfg(feature = "solve")]
            solve: None,
            #[cfg(feature = "solve")]
            schur: None,
        }
    }

    /// The fields of `variables` (`true`) or `constants` (`false`), each
    /// with its JSON shape.
    pub fn json_fields(&self, variables: bool) -> Vec<(&'static str, String)> {
        (self.fields)()
            .into_iter()
            .filter(|field| field.variable.is_some() == variables)
            .map(|field| (field.name, json_shape(&field.input_layout)))
            .collect()
    }
}

/// The factors of a command line, in the order `list` shows them, the
/// kernels `generate` writes and `check` compares, and the crate they go to.
///
/// ```
/// use slamjac_registry::Registry;
/// use slam_factors::{BetweenFactor, PointReprojection};
///
/// let registry = Registry::new()
///     .with::<PointReprojection>()
///     .with_kernel::<BetweenFactor>();
/// let names: Vec<&str> = registry.factors().iter().map(|f| f.name).collect();
/// assert_eq!(names, ["point_reprojection", "between"]);
/// assert_eq!(registry.specs().len(), 1); // only `between` is generated
/// ```
#[derive(Debug, Clone, Default)]
pub struct Registry {
    factors: Vec<FactorEntry>,
    specs: Vec<KernelSpec>,
    kernel_crate: Option<KernelCrate>,
}

impl Registry {
    /// No factors, no kernel crate.
    pub fn new() -> Self {
        Registry::default()
    }

    /// Adds factor `F` to `list` and `eval` (its kernel, if the factor names
    /// one, is what `eval --method generated` runs); once only.
    pub fn with<F: Factor>(mut self) -> Self {
        self.entry::<F>();
        self
    }

    /// Adds factor `F` (as [`Registry::with`]) and lets `solve` read it
    /// from problem files, linearized by its generated kernel in
    /// apex-solver's chart: the factor names a kernel crate with
    /// `#[factor(kernel = …, hosts(apex))]`, and its spec has the host
    /// (`KernelSpec::of::<F>().with_host(HostSpec::of::<F, Apex>())`).
    /// `solve` works in a binary built with `slamjac`'s feature `solve`
    /// (this crate's feature `solve`).
    pub fn solve_with_kernel<F: HostKernel<Apex> + 'static>(mut self) -> Self {
        let entry = self.entry::<F>();
        entry.solved_by = Some(SolvedBy::Kernel);
        #[cfg(feature = "solve")]
        {
            entry.solve = Some(crate::problem_assembly::add_kernel::<F>);
        }
        self
    }

    /// Adds factor `F` as [`Registry::solve_with_kernel`] does, and lets
    /// `solve` put it in the Schur-complement solver's problem (crate
    /// `factor-schur`, the default for a problem file whose factors all
    /// have it): its kernel crate generates its fused normal equations
    /// (`KernelSpec::with_normal_equations()`) and is built with its
    /// `lanes` feature. Its variables are then held in their types' stored
    /// scalars and retracted by their own manifolds, not apex-solver's; a
    /// file whose factors are not all registered so goes to apex-solver
    /// (`--solver auto`, saying why) or is refused (`--solver schur`).
    /// A factor on a variable whose own manifold is not the one to solve
    /// on (a free 6-vector such as the shipped `PluckerLine`) must not be
    /// registered so: `slamjac`'s own registry solves
    /// `plucker_line_reprojection` as `line_reprojection`, its line in the
    /// orthonormal chart.
    /// Only in a build with `slamjac`'s feature `solve` (this crate's).
    #[cfg(feature = "solve")]
    pub fn solve_with_schur<F>(self) -> Self
    where
        F: HostKernel<Apex> + factor_core::WithKernel + Send + Sync + 'static,
        F::Kernel: factor_lanes::NormalKernel<factor_schur::problem::Lane>
            + factor_lanes::NormalKernel<f64>,
    {
        self.solve_with_kernel::<F>().solve_with_schur_by::<F>(
            crate::schur_assembly::add_schur::<F>,
            factor_schur::Linearized::Batch,
        )
    }

    /// Factor `F`, registered for problem files already, put in the
    /// Schur-complement solver's problem by `add`, linearized as
    /// `linearized` says (`slamjac`'s own registry puts
    /// `plucker_line_reprojection` there by
    /// [`add_plucker_line`](crate::schur_assembly::add_plucker_line)).
    #[cfg(feature = "solve")]
    pub fn solve_with_schur_by<F: Factor>(
        mut self,
        add: crate::schur_assembly::SchurAddFn,
        linearized: factor_schur::Linearized,
    ) -> Self {
        self.entry::<F>().schur = Some((add, linearized));
        self
    }

    /// Lets `solve` put factor `F`, registered for problem files already
    /// ([`Registry::solve_with_kernel`] or [`Registry::solve_with_dual`]),
    /// in the Schur-complement solver's problem (crate `factor-schur`),
    /// linearized one factor at a time: through its generated kernel where
    /// it has one, else by dual numbers, its whitened Jacobians formed into
    /// the normal blocks (no fused kernel needed). As with
    /// [`Registry::solve_with_schur`], its variables are then retracted by
    /// their own manifolds, so a type whose own manifold is not the one to
    /// solve on (the shipped `PluckerLine`) must not be registered so.
    /// Only in a build with `slamjac`'s feature `solve` (this crate's).
    ///
    /// # Panics
    ///
    /// If `F` is not registered for problem files yet.
    #[cfg(feature = "solve")]
    pub fn solve_with_schur_each<F: Factor + Send + Sync + 'static>(mut self) -> Self {
        let entry = self.entry::<F>();
        assert!(
            entry.solve.is_some(),
            "{} is not registered for problem files (solve_with_kernel or solve_with_dual)",
            F::NAME
        );
        self.solve_with_schur_by::<F>(
            crate::schur_assembly::add_each::<F>,
            factor_schur::Linearized::per_factor::<F>(factor_schur::Jacobians::Kernel),
        )
    }

    /// Adds factor `F` (as [`Registry::with`]) and lets `solve` read it
    /// from problem files, linearized by dual numbers in apex-solver's
    /// chart: any derived factor whose variables' types map onto apex's
    /// manifolds (`factor_core::host::HostMap<Apex>`; the guide's "Solver
    /// charts"), no kernel needed.
    pub fn solve_with_dual<F: HostFactor<Apex> + 'static>(mut self) -> Self {
        let entry = self.entry::<F>();
        entry.solved_by = Some(SolvedBy::Dual);
        #[cfg(feature = "solve")]
        {
            entry.solve = Some(crate::problem_assembly::add_dual::<F>);
        }
        self
    }

    /// Factor `F`'s entry, added at the end when it is not yet registered.
    fn entry<F: Factor>(&mut self) -> &mut FactorEntry {
        let index = match self.factors.iter().position(|f| f.name == F::NAME) {
            Some(index) => index,
            None => {
                self.factors.push(FactorEntry::of::<F>());
                self.factors.len() - 1
            }
        };
        &mut self.factors[index]
    }

    /// Adds factor `F` to `list` and `eval`, and its kernel
    /// ([`KernelSpec::of`]) to what `generate` writes and `check` compares.
    pub fn with_kernel<F: Factor>(self) -> Self {
        self.with::<F>().with_spec(KernelSpec::of::<F>())
    }

    /// Adds a kernel to what `generate` writes and `check` compares, as
    /// `spec` describes it ([`KernelSpec::with_source`],
    /// [`KernelSpec::with_normal_equations`]); it replaces a spec of the
    /// same name given before (each kernel is written once).
    pub fn with_spec(mut self, spec: KernelSpec) -> Self {
        match self.specs.iter_mut().find(|s| s.name == spec.name) {
            Some(given) => *given = spec,
            None => self.specs.push(spec),
        }
        self
    }

    /// The crate `generate` writes and `check` compares.
    pub fn with_kernel_crate(mut self, kernel_crate: KernelCrate) -> Self {
        self.kernel_crate = Some(kernel_crate);
        self
    }

    /// Every registered factor, in registration order.
    pub fn factors(&self) -> &[FactorEntry] {
        &self.factors
    }

    /// Every kernel `generate` writes, in registration order.
    pub fn specs(&self) -> &[KernelSpec] {
        &self.specs
    }

    /// The kernel `generate` writes for the factor called `name`, if any.
    pub fn spec(&self, name: &str) -> Option<&KernelSpec> {
        self.specs.iter().find(|spec| spec.name == name)
    }

    /// The crate `generate` writes and `check` compares, if any.
    pub fn kernel_crate(&self) -> Option<&KernelCrate> {
        self.kernel_crate.as_ref()
    }

    /// The factor called `name`; the error (at field path `path`) lists the
    /// known ones.
    pub fn find(&self, name: &str, path: &str) -> Result<&FactorEntry, InputError> {
        self.factors.iter().find(|f| f.name == name).ok_or_else(|| {
            let known: Vec<&str> = self.factors.iter().map(|f| f.name).collect();
            InputError::new(
                path,
                format!(
                    "unknown factor {}; known factors: {}",
                    quoted(name),
                    known.join(", ")
                ),
            )
        })
    }
}

/// The crate of generated kernels that `generate` writes and `check`
/// compares.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct KernelCrate {
    /// The package name in its `Cargo.toml`, which makes a directory the
    /// kernel crate (any other directory is refused).
    pub package: &'static str,
    /// Its directory when `--out`/`--dir` is not given; usually beside the
    /// command line's crate: `concat!(env!("CARGO_MANIFEST_DIR"), "/../my-kernels")`.
    pub dir: &'static str,
    /// What its files say about where they come from: the commands that
    /// write and check it.
    pub provenance: Provenance,
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn factors_are_listed_and_found_in_registration_order() {
        use slam_factors::{BetweenFactor, PointReprojection};
        let registry = Registry::new()
            .with::<PointReprojection>()
            .with_kernel::<BetweenFactor>();
        let names: Vec<&str> = registry.factors().iter().map(|f| f.name).collect();
        assert_eq!(names, ["point_reprojection", "between"]);
        assert_eq!(registry.find("between", "factor").unwrap().name, "between");
        assert!(registry.spec("point_reprojection").is_none());
        assert_eq!(registry.spec("between").unwrap().name, "between");
        assert!(registry.kernel_crate().is_none());
    }
}
