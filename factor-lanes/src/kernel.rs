//! [`Kernel`] and [`NormalKernel`]: a generated kernel over any number type
//! of its crate's `Real`, as a batch evaluator (crate `factor-batch`) calls
//! it, with its inputs and outputs each in one fixed-size [`Array`].
//!
//! A generated crate built with its `lanes` feature implements them for the
//! marker type `Kernel` of every kernel module (`point_reprojection::Kernel`),
//! for every `T` that implements the crate's `Real` (`f64`, `f32` and, through
//! [`impl_real!`](crate::impl_real), the lane types); `#[derive(Factor)]`
//! names that marker in `factor_core::WithKernel::Kernel`. The arrays have
//! the kernel's lengths as types, so an evaluator that inlines the kernel
//! keeps its inputs and outputs in registers.

/// A fixed-size array of numbers: the input and output buffers of a
/// [`Kernel`] (implemented for every `[T; N]`).
pub trait Array<T>: Copy + AsRef<[T]> + AsMut<[T]> {
    /// The number of elements.
    const LEN: usize;
    /// Every element `value`.
    fn splat(value: T) -> Self;
}

impl<T: Copy, const N: usize> Array<T> for [T; N] {
    const LEN: usize = N;

    #[inline(always)]
    fn splat(value: T) -> Self {
        [value; N]
    }
}

/// A generated residual-and-Jacobian kernel over the number type `T`.
#[diagnostic::on_unimplemented(
    message = "`{Self}` is not a kernel over `{T}`",
    note = "a generated kernel crate implements `factor_lanes::Kernel` with its `lanes` feature: \
            enable it where the crate is a dependency (`features = [\"lanes\"]`)"
)]
pub trait Kernel<T: Copy> {
    /// Every field's stored scalars, concatenated in declaration order.
    type Inputs: Array<T>;
    /// The residual, then each variable's Jacobian block (row-major,
    /// residual rows × tangent columns), concatenated in declaration order.
    type Outputs: Array<T>;
    /// Each field's stored scalars, in declaration order.
    const FIELDS: &'static [usize];
    /// The residual's length.
    const RESIDUAL: usize;
    /// Each variable's tangent dimension, in declaration order.
    const TANGENTS: &'static [usize];

    /// Writes the residual and each Jacobian block `k` with `blocks[k]`
    /// true into `outputs`; the blocks of the others (variables held fixed,
    /// or beyond `blocks`) are left as they were, and the work only they
    /// need is skipped.
    fn linearize(inputs: &Self::Inputs, outputs: &mut Self::Outputs, blocks: &[bool]);
}

/// A generated kernel of the Gauss–Newton normal equations of one factor,
/// fused with its Jacobian kernel: for a per-factor weight `w`, the cost
/// `½ w rᵀr`, each gradient block `Jᵢᵀ w r` and the upper triangle of the
/// Gauss–Newton matrix `JᵀwJ`, block by block.
#[diagnostic::on_unimplemented(
    message = "`{Self}` has no normal-equation kernel over `{T}`",
    note = "generate it with `KernelSpec::with_normal_equations()` and enable the kernel \
            crate's `lanes` feature"
)]
pub trait NormalKernel<T: Copy>: Kernel<T> {
    /// The cost, then each variable's gradient block `Jᵢᵀ w r` in
    /// declaration order, then the Hessian blocks `Jᵢᵀ w Jⱼ` for the pairs
    /// `i ≤ j` in the order `(0, 0), (0, 1), …, (0, n−1), (1, 1), …`: a
    /// diagonal block as its upper triangle row by row (`a ≤ b`), an
    /// off-diagonal one whole, row-major (`Dᵢ × Dⱼ`).
    type NormalOutputs: Array<T>;

    /// Writes the cost, the gradient block of each variable `k` with
    /// `free[k]` true, and the Hessian block of each pair of such variables
    /// into `outputs`; the other blocks are left as they were, and the work
    /// only they need is skipped.
    fn normal(inputs: &Self::Inputs, weight: T, outputs: &mut Self::NormalOutputs, free: &[bool]);
}
