//! How `eval` computes the Jacobians ([`Method`]) and the one function that
//! linearizes any factor with a method ([`linearize`]), used by every
//! registered factor's entry.

use factor_core::{DynLinearization, Factor, FactorError, NumericLinearize};

/// How the Jacobians are computed.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
#[cfg_attr(feature = "clap", derive(clap::ValueEnum))]
pub enum Method {
    /// The factor's generated kernel, as its crate was built with it (the
    /// checked-in `generated/` for slamjac's factors, your kernel crate for
    /// your own; straight-line code, exact to rounding); dual numbers for a
    /// factor without one in this build.
    #[default]
    Generated,
    /// Dual numbers (num-dual) through the generic residual: exact.
    Dual,
    /// Numerical differentiation through each variable's exact retraction
    /// (Ridders' extrapolation of central differences, steps chosen per
    /// coordinate): an independent reference, each block within about 1e-7
    /// of the exact Jacobian; exit 1 when its error estimate does not reach
    /// that.
    Numeric,
}

impl Method {
    /// The name used on the command line and in the output.
    pub fn as_str(self) -> &'static str {
        match self {
            Method::Generated => "generated",
            Method::Dual => "dual",
            Method::Numeric => "numeric",
        }
    }
}

/// Validates `factor` and linearizes it with `method`; a degenerate
/// configuration or a non-finite output is an error. Returns the method
/// actually used: [`Method::Generated`] falls back to [`Method::Dual`] for a
/// factor without a generated kernel (or a build without the `kernels`
/// feature).
pub fn linearize<F: Factor>(
    factor: &F,
    method: Method,
) -> Result<(DynLinearization, Method), FactorError> {
    factor.validate()?;
    let (linearization, used) = match method {
        Method::Generated => match factor.linearize_generated_dyn() {
            Some(result) => (result?, Method::Generated),
            None => (factor.linearize_dual_dyn()?, Method::Dual),
        },
        Method::Dual => (factor.linearize_dual_dyn()?, Method::Dual),
        Method::Numeric => (factor.linearize_numeric_dyn()?, Method::Numeric),
    };
    let variables = F::variables();
    let names: Vec<&str> = variables.iter().map(|v| v.name).collect();
    Ok((linearization.ensure_finite(F::NAME, &names)?, used))
}
