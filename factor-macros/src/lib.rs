//! `#[derive(Factor)]`: from a struct generic over the scalar and one generic
//! residual function, emit the typed evaluation and dual-number linearization
//! API and the [`factor_core::Factor`] implementation.
//!
//! The crate is organised like `serde_derive`: `model` parses and validates
//! the input into a small model (every misuse is a spanned compile error), and
//! `emit` turns the model into code. All generated paths go through
//! `::factor_core` and `::factor_core::__private::{nalgebra, num_dual}`, so a
//! user crate needs only `factor-core` as a dependency.
//!
//! [`factor_core::Factor`]: https://docs.rs/factor-core

mod attrs;
mod emit;
mod errors;
mod model;
mod naming;

use proc_macro::TokenStream;
use syn::{DeriveInput, parse_macro_input};

/// Derives a factor from a struct of constants and variables and a residual
/// function generic over the scalar.
///
/// The example is on the re-export a user derives through,
/// `factor_core::Factor` (and doctested there).
///
/// `#[factor(...)]` keys: `residual = path` (required; a function
/// `fn<S: Scalar>(&Foo<S>) -> SVector<S, dim>`), `dim = integer` (required, at
/// least 1), `validate = path` (optional; `fn(&Foo<f64>) -> Result<(),
/// FactorError>`), `name = "..."` (optional; defaults to the snake case of the
/// struct's name), `kernel = path` (optional; a generated kernel, see below),
/// `regenerate = "command"` (optional, with `kernel`: the command a stale
/// kernel's compile error names).
///
/// The struct has exactly one type parameter, the scalar, bounded by
/// `Scalar` alone (a comparison bound such as `PartialOrd`, rustc's hint
/// for `a < b` in a residual, is refused with a pointer to
/// `Scalar::select_lt`), and named fields. Every field implements `Clone`
/// and `Storage<S>` (constants are lifted to dual numbers too, so they are
/// written over the scalar: `weight: S`, not `weight: f64`, which is refused
/// at the `f64`); every variable also implements `Manifold<S>`, for every
/// scalar `S`. The first paragraph of the struct's and of each field's `///`
/// documentation is kept (`Factor::DESCRIPTION`, `FieldInfo::doc`). For
/// `Foo<S>` with variables `v₁ … vₙ` this emits:
///
/// - `impl<S: Scalar> Storage<S> for Foo<S>`: the fields' scalars in
///   declaration order, the layout a record of the fields' layouts, and a
///   user's input checked field by field;
/// - `Foo::<S>::perturbed_residual(&self, delta: &[S]) -> SVector<S, dim>`:
///   the residual with every variable retracted to first order by its slice of
///   `delta`, the function a tracer differentiates;
/// - `Foo::<f64>::TANGENT_DIM`, `residual()`, `linearize_dual()` (one pass of
///   the residual on `factor_core::dual::Dual` numbers as wide as the
///   stacked tangent, each variable seeded through `Manifold::seeded`) and
///   `linearize()`;
/// - `FooLinearization { residual, v₁, …, vₙ }` with one fixed-size Jacobian
///   block per variable, and `to_dyn()` / `ensure_finite()`;
/// - `impl Factor for Foo<f64>` (including `perturbed_residual_over`, the
///   residual over any scalar from the stored scalars, which the code
///   generator traces, and `linearize_into`, the allocation-free
///   linearization that skips the blocks of fixed variables).
///
/// With `kernel = path`, `path` names a kernel function of a crate written by
/// the code generator (`slamjac generate` for `factor-generated`, or a user's
/// generator): `fn(&[f64; N₁], …, &mut [f64; dim], Option<&mut [f64; dim·D₁]>,
/// …)`, one array per field in declaration order holding its stored scalars,
/// the residual, then one optional row-major block per variable. Its module
/// also holds `SHAPE` (the lengths it was generated for) and
/// `<name>_slices`, the same kernel over slices, which the derive calls, and
/// the marker type `Kernel`. The derive then also emits
/// `linearize_generated()` and `linearize_generated_into()`, makes
/// `linearize()` and `linearize_into()` go through them, sets
/// `Factor::KERNEL` and `Factor::linearize_generated_dyn`, and implements
/// `factor_core::WithKernel` with the marker as `Kernel` (the entry of the
/// batch evaluators of `factor-batch`). When `SHAPE` no longer matches the
/// factor (the kernel is stale), the build fails at `path` with a message
/// naming the `regenerate` command. A change that keeps the layout (a sign
/// in the residual) is caught at run time in debug builds: the first
/// linearizations of each factor type compare the kernel with dual numbers
/// and, when they disagree, return `FactorError::StaleKernel` naming the
/// command, then and at every later linearization of the type
/// (`factor_core::kernel` documents the checks).
#[proc_macro_derive(Factor, attributes(factor, variable))]
pub fn derive_factor(input: TokenStream) -> TokenStream {
    let input = parse_macro_input!(input as DeriveInput);
    model::FactorModel::from_input(&input)
        .map(|model| emit::expand(&model))
        .unwrap_or_else(syn::Error::into_compile_error)
        .into()
}
