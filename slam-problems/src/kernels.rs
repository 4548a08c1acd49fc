//! [`Kernels`]: how a solver linearizes a factor.

/// How a factor is linearized: through its generated kernel, or by dual
/// numbers (the same factor, for comparison).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum Kernels {
    /// The factor's generated kernel.
    #[default]
    Generated,
    /// Dual numbers through the same trace: the same factor, for
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
