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
    #[error(
        "a kernel cannot be named `{0}`: a file the generator writes for itself has that name \
         (`src/{0}.rs` of the crate, or `cpp/<namespace>/{0}.h` of its C++)"
    )]
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
    /// A variable whose chart Ceres cannot be given: its type has no
    /// inverse retraction.
    #[error(
        "kernel `{kernel}`: Ceres cannot take variable `{variable}` in its own chart: its type \
         `{type_name}` gives no `Manifold::local` (the inverse of its retraction, which a Ceres \
         `Manifold` needs as `Minus` and differentiates into `MinusJacobian`); implement \
         `local` for it (see the documentation of `factor_core::Manifold`), or generate the \
         factor without `with_ceres()`"
    )]
    NoLocal {
        /// The kernel.
        kernel: &'static str,
        /// The variable.
        variable: &'static str,
        /// Its type as the factor writes it.
        type_name: &'static str,
    },
    /// A factor Ceres cannot take at all.
    #[error("kernel `{kernel}`: {reason}")]
    NotForCeres {
        /// The kernel.
        kernel: &'static str,
        /// What is missing.
        reason: String,
    },
    /// A field named like a word the C++ emission uses or C++ reserves.
    #[error(
        "kernel `{kernel}`: field `{field}` cannot keep its name in C++: {what}; rename the field"
    )]
    CppName {
        /// The kernel.
        kernel: &'static str,
        /// The field.
        field: &'static str,
        /// Why it cannot be used.
        what: &'static str,
    },
    /// Two variable types whose charts would have one name.
    #[error(
        "two different charts are named `{0}` (two variable types of one name, or a chart \
         that changed between two factors); rename one of the types"
    )]
    ChartCollision(String),
}
