//! What the generator refuses to generate.

/// A kernel or a crate of kernels that cannot be generated as asked.
#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error)]
#[non_exhaustive]
pub enum CodegenError {
    /// A field's name is one the kernel uses for itself.
    #[error(
        "kernel `{kernel}`: field `{field}` collides with a name of the generated kernel \
         (`residual`, `inputs`, `blocks`, `d_<variable>`, `v<n>`, `T`); \
         rename the field"
    )]
    NameCollision {
        /// The kernel.
        kernel: &'static str,
        /// The field.
        field: &'static str,
    },
    /// Two kernels of one crate have the same name (one module each).
    #[error("two kernels are named `{0}`; each kernel is a module of the crate")]
    DuplicateKernel(&'static str),
    /// A kernel is named like a file the crate writes for itself.
    #[error("a kernel cannot be named `{0}`: the generated crate's own `src/{0}.rs` has that name")]
    ReservedName(&'static str),
    /// A normal-equation kernel of too many variables.
    #[error(
        "kernel `{kernel}`: {variables} variables are too many for a normal-equation kernel \
         (at most {max}: its gradient and Hessian blocks are scheduled as at most 63 optional \
         outputs); generate it without `with_normal_equations()`",
        max = crate::normal::MAX_VARIABLES
    )]
    TooManyVariables {
        /// The kernel.
        kernel: &'static str,
        /// Its variables.
        variables: usize,
    },
    /// A crate of no kernels.
    #[error("a generated crate needs at least one kernel")]
    Empty,
}
