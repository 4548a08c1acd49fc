//! How a problem's factors are linearized: asked for per factor type
//! ([`Jacobians`], `Problem::add_linearized`), and as reported
//! ([`Linearized`], `Problem::linearized`).

use factor_core::Factor;
use slam_problems::Kernels;

/// How a factor added by [`Problem::add_linearized`](crate::Problem::add_linearized) is differentiated.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Jacobians {
    /// The factor's own `linearize_stored_validated_into` (the values
    /// were validated when evaluated): its generated kernel where it has
    /// one (`#[factor(kernel = …)]`), dual numbers otherwise.
    Kernel,
    /// Dual numbers, whether or not the factor has a kernel.
    Dual,
}

impl From<Kernels> for Jacobians {
    /// What `--kernels` asks of a factor added one at a time: its kernel
    /// (`Generated`, dual numbers where it has none) or dual numbers.
    fn from(kernels: Kernels) -> Self {
        match kernels {
            Kernels::Generated => Jacobians::Kernel,
            Kernels::Dual => Jacobians::Dual,
        }
    }
}

/// How the factors of a type are linearized, as [`Problem::linearized`](crate::Problem::linearized)
/// reports it.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Linearized {
    /// By the fused normal-equation kernels, in lane batches.
    Batch,
    /// By the factor's generated kernel, one factor at a time.
    Kernel,
    /// By dual numbers, one factor at a time.
    Dual,
}

impl Linearized {
    /// How a factor of type `F` added one at a time by `jacobians` is
    /// linearized: through its kernel only where it has one.
    pub fn per_factor<F: Factor>(jacobians: Jacobians) -> Self {
        match jacobians {
            Jacobians::Kernel if F::KERNEL.is_some() => Linearized::Kernel,
            _ => Linearized::Dual,
        }
    }

    /// The work of linearizing one factor, in factors of the fused batch
    /// kernels (about 60 ns each for bundle adjustment), for sharing the
    /// factors among threads: one at a time through its kernel about 8
    /// times that (the whitening and the scatter per factor), by dual
    /// numbers about 50 (g2o's plane edges: 3.4 µs per block and pass).
    pub fn relative_cost(self) -> usize {
        match self {
            Linearized::Batch => 1,
            Linearized::Kernel => 8,
            Linearized::Dual => 50,
        }
    }

    /// In words, for a solve's header.
    pub fn describe(self) -> &'static str {
        match self {
            Linearized::Batch => "fused normal-equation kernels on 4×f64 lanes",
            Linearized::Kernel => "its generated kernel, one factor at a time",
            Linearized::Dual => "dual numbers, one factor at a time",
        }
    }
}
