//! The linearization through a generated kernel (`#[factor(kernel = path)]`).
//!
//! `path` names a kernel function of a crate written by the code generator;
//! its module also holds `SHAPE` (the array lengths it was generated for:
//! each field's stored scalars, the residual, each Jacobian block) and
//! `<name>_slices`, the same kernel over slices that checks their lengths.
//! The derive calls the slice entry, so a kernel generated for another
//! layout of the factor is never a type error; instead a constant compares
//! `SHAPE` with the factor's own layout and fails the build with a message
//! that says the kernel is stale and how to regenerate it. A change that
//! keeps the layout (a sign in the residual) is caught in debug builds: the
//! first linearizations of each factor type compare the kernel with dual
//! numbers and report a stale one as `FactorError::StaleKernel`
//! (`factor_core::kernel` documents why there). The module's
//! marker type `Kernel` becomes the factor's `WithKernel::Kernel`, the entry
//! of batch evaluators (crate `factor-batch`).

use proc_macro2::TokenStream;
use quote::{format_ident, quote, quote_spanned};
use syn::Path;
use syn::spanned::Spanned;

use super::Context;

/// The kernel's path as written, without spaces, for documentation.
pub fn path_text(path: &Path) -> String {
    quote!(#path).to_string().replace(' ', "")
}

/// `path` with its last segment replaced by `last`: an item of the kernel's
/// module.
pub(super) fn sibling(path: &Path, last: &syn::Ident) -> Path {
    let mut sibling = path.clone();
    if let Some(segment) = sibling.segments.last_mut() {
        segment.ident = last.clone();
        segment.arguments = syn::PathArguments::None;
    }
    sibling
}

/// How the messages of a stale kernel say to regenerate it: the
/// `regenerate` command of the attribute, or where to find one.
pub(super) fn regenerate_text(cx: &Context) -> String {
    match &cx.model.regenerate {
        Some(command) => format!("regenerate it with `{command}`"),
        None => "regenerate the crate that holds it with the generator that wrote it (named in \
                 its module header), built without the feature that compiles the kernels"
            .to_owned(),
    }
}

/// The error of a stale kernel, for the linearizations' documentation.
const STALE_ERROR: &str = "In a debug build, \
    [`FactorError::StaleKernel`](::factor_core::FactorError::StaleKernel) when one of the first \
    linearizations of this factor type found the kernel disagreeing with dual numbers through \
    the current definition: it is stale (see `factor_core::kernel`).";

/// `impl Foo<f64> { linearize_generated_into, linearize_generated }`,
/// `impl WithKernel` naming the kernel module's marker type `Kernel`, and the
/// compile-time check that the kernel is current, or nothing without a kernel.
pub fn emit(cx: &Context) -> TokenStream {
    let Some(kernel) = &cx.model.kernel else {
        return TokenStream::new();
    };
    let krate = &cx.krate;
    let nalgebra = &cx.nalgebra;
    let ident = &cx.model.ident;
    let dim = &cx.dim;
    let linearization = cx.model.linearization_ident();
    let kernel_text = path_text(kernel);
    let span = kernel.span();
    let last = kernel
        .segments
        .last()
        .map_or_else(|| format_ident!("kernel"), |s| s.ident.clone());
    let shape = sibling(kernel, &format_ident!("SHAPE", span = span));
    let slices = sibling(kernel, &format_ident!("{}_slices", last, span = span));
    let marker = sibling(kernel, &format_ident!("Kernel", span = span));

    let field_count = cx.model.fields.len();
    let scalars: Vec<_> = (0..field_count)
        .map(|i| quote!(<#ident<f64>>::__FACTOR_SCALARS[#i]))
        .collect();
    // Each field's slice of the stored scalars: `stored[a..a + n]`, `a` the
    // sum of the earlier fields' counts.
    let slices_of_stored: Vec<_> = (0..field_count)
        .map(|i| {
            let earlier = &scalars[..i];
            let n = &scalars[i];
            quote!(&stored[(0usize #(+ #earlier)*)..(0usize #(+ #earlier)*) + #n])
        })
        .collect();
    let blocks: Vec<_> = cx.variables.iter().map(|v| v.ident).collect();
    let block_dims: Vec<_> = cx.variables.iter().map(|v| cx.dim_f64(v)).collect();
    let block_indices: Vec<usize> = (0..blocks.len()).collect();
    let outputs: Vec<_> = (0..blocks.len())
        .map(|k| format_ident!("__d_{}", k))
        .collect();
    let locals: Vec<_> = (0..blocks.len())
        .map(|k| format_ident!("__values_{}", k))
        .collect();
    let block_count = blocks.len();
    let scalar_count = quote!(<#ident<f64> as #krate::Storage<f64>>::SCALARS);
    let lengths = format!(
        "{{}}: the residual has {rows} entries, and the Jacobians one entry per variable \
         ({block_count}), each block {rows} × the variable's tangent dimension",
        rows = dim.base10_digits()
    );

    let regenerate = regenerate_text(cx);
    let stale = format!(
        "the generated kernel `{kernel_text}` does not match `{ident}`: it was generated for \
         another layout of the factor (a field, its storage or a tangent changed since); \
         {regenerate}"
    );
    // The residual dimension without the span of `dim = …`: clippy reads
    // `dim * D` at that span as a missing comma in the attribute.
    let rows = syn::LitInt::new(dim.base10_digits(), proc_macro2::Span::call_site());
    let check = quote_spanned! {span=>
        const _: () = {
            let generated = #shape;
            let current = generated.residual == #rows
                && #krate::__private::same_shape(generated.inputs, &[#(#scalars),*])
                && #krate::__private::same_shape(generated.blocks, &[#(#rows * #block_dims),*]);
            if !current {
                ::core::panic!(#stale);
            }
        };
    };
    let into_doc = format!(
        "Residual and the requested Jacobian blocks through the generated kernel \
         [`{kernel_text}`]({kernel_text}), written into the caller's storage with no \
         allocation: `residual` has {dim} entries, `jacobians[k]` is `Some(block)` (row-major, \
         {dim} × variable `k`'s tangent dimension) or `None` for a variable held fixed, whose \
         block is not computed (nor the work only it needs).\n\n\
         # Errors\n\n\
         The validation's error, or \
         [`FactorError::NonFinite`](::factor_core::FactorError::NonFinite) naming the first \
         non-finite output (the outputs then hold unspecified values). {STALE_ERROR}\n\n\
         # Panics\n\n\
         If `residual`, `jacobians` or a block has the wrong length."
    );
    let doc = format!(
        "Residual and Jacobian blocks through the generated kernel \
         [`{kernel_text}`]({kernel_text}): straight-line code with every entry unrolled and \
         common subexpressions shared, exact to rounding like \
         [`linearize_dual`](Self::linearize_dual).\n\n\
         # Errors\n\n\
         As [`linearize_generated_into`](Self::linearize_generated_into)."
    );
    quote! {
        #check

        impl #krate::WithKernel for #ident<f64> {
            type Kernel = #marker;
        }

        impl #ident<f64> {
            #[doc = #into_doc]
            pub fn linearize_generated_into(
                &self,
                residual: &mut [f64],
                jacobians: &mut [::core::option::Option<&mut [f64]>],
            ) -> ::core::result::Result<(), #krate::FactorError> {
                let mut stored = [0.0_f64; <Self as #krate::Storage<f64>>::SCALARS];
                #krate::Storage::write_scalars(self, &mut stored);
                Self::__factor_kernel(&stored, residual, jacobians, ::core::option::Option::Some(self))
            }

            /// [`Self::__factor_kernel`] out of line, for the stored-scalar
            /// entries (`linearize_generated_into` inlines it: through a
            /// call, the between factor's took 20% longer).
            fn __factor_kernel_stored(
                stored: &[f64],
                residual: &mut [f64],
                jacobians: &mut [::core::option::Option<&mut [f64]>],
                factor: ::core::option::Option<&Self>,
            ) -> ::core::result::Result<(), #krate::FactorError> {
                Self::__factor_kernel(stored, residual, jacobians, factor)
            }

            /// The generated kernel on the factor stored as `stored`, then
            /// the validation of `factor` (the same factor) when given, then
            /// the check that every output is finite: the
            /// linearizations through the kernel. The kernel runs first (it
            /// never panics: on an invalid configuration its outputs are
            /// discarded).
            #[inline(always)]
            fn __factor_kernel(
                stored: &[f64],
                residual: &mut [f64],
                jacobians: &mut [::core::option::Option<&mut [f64]>],
                factor: ::core::option::Option<&Self>,
            ) -> ::core::result::Result<(), #krate::FactorError> {
                let ::core::result::Result::Ok(stored) = <&[f64; #scalar_count]>::try_from(stored) else {
                    ::core::panic!(
                        "{}: the factor stores {} scalars, not {}",
                        <Self as #krate::Factor>::NAME,
                        #scalar_count,
                        stored.len(),
                    );
                };
                #[cfg(debug_assertions)]
                Self::__factor_check_kernel(stored)?;
                let fits = residual.len() == #dim
                    && jacobians.len() == #block_count
                    #(&& jacobians[#block_indices]
                        .as_deref()
                        .is_none_or(|block| block.len() == #dim * #block_dims))*;
                ::core::assert!(fits, #lengths, <Self as #krate::Factor>::NAME);
                let every = match jacobians {
                    [#(::core::option::Option::Some(#outputs)),*]
                        if const { #krate::__private::in_registers(&[#rows #(, #rows * #block_dims)*]) } =>
                    ::core::option::Option::Some(
                        Self::__factor_kernel_every(stored, residual, #(#outputs),*),
                    ),
                    _ => {
                        Self::__factor_kernel_some(stored, residual, jacobians);
                        ::core::option::Option::None
                    }
                };
                if let ::core::option::Option::Some(factor) = factor {
                    <Self as #krate::Factor>::validate(factor)?;
                }
                // Without the local arrays (a block held fixed, or too many
                // outputs) the outputs are tested in memory after the
                // validation, which gives the kernel's stores time to land
                // before they are loaded: one branch-free test of every
                // output at its known length.
                let finite = every.unwrap_or_else(|| {
                    #krate::__private::all_finite_of::<#rows>(residual)
                        #(& jacobians[#block_indices]
                            .as_deref()
                            .is_none_or(#krate::__private::all_finite_of::<{ #rows * #block_dims }>))*
                });
                if finite {
                    return ::core::result::Result::Ok(());
                }
                match #krate::first_non_finite(residual, jacobians) {
                    ::core::option::Option::None => ::core::result::Result::Ok(()),
                    ::core::option::Option::Some(at) => ::core::result::Result::Err(
                        #krate::FactorError::non_finite_output::<Self>(at),
                    ),
                }
            }

            /// The kernel with every block requested, into local arrays that
            /// stay in registers (the kernel and its slice entry are inlined):
            /// the finiteness test reads the values there, not back from
            /// memory just after they were stored, and they are copied into
            /// the caller's storage after it. Whether every output is finite;
            /// `false` may also be a finite sum's overflow, which the caller
            /// rules out value by value.
            #[inline(always)]
            fn __factor_kernel_every(
                stored: &[f64; #scalar_count],
                residual: &mut [f64],
                #(#outputs: &mut [f64],)*
            ) -> bool {
                let mut values = [0.0_f64; #dim];
                #(
                    let mut #locals = [0.0_f64; #dim * #block_dims];
                )*
                Self::__factor_kernel_slices(
                    stored,
                    &mut values,
                    &mut [#(::core::option::Option::Some(&mut #locals[..])),*],
                );
                let finite = #krate::__private::OutputSum::EMPTY
                    .with(&values)
                    #(.with(&#locals))*
                    .is_finite();
                residual.copy_from_slice(&values);
                #(
                    #outputs.copy_from_slice(&#locals);
                )*
                finite
            }

            /// The kernel with some blocks not requested (or too many
            /// outputs for registers), straight into the caller's storage
            /// (out of line: every block requested is the path to keep
            /// short).
            #[inline(never)]
            fn __factor_kernel_some(
                stored: &[f64; #scalar_count],
                residual: &mut [f64],
                jacobians: &mut [::core::option::Option<&mut [f64]>],
            ) {
                Self::__factor_kernel_slices(stored, residual, jacobians);
            }

            /// The generated kernel's slice entry on the factor stored as
            /// `stored` (the callers check the outputs' lengths first).
            #[inline(always)]
            fn __factor_kernel_slices(
                stored: &[f64; #scalar_count],
                residual: &mut [f64],
                jacobians: &mut [::core::option::Option<&mut [f64]>],
            ) {
                let done = #slices(&[#(#slices_of_stored),*], residual, jacobians);
                ::core::assert!(done, #lengths, <Self as #krate::Factor>::NAME);
            }

            /// The generated kernel on the factor stored as `stored`, every
            /// block computed, its outputs not checked.
            fn __factor_kernel_all(stored: &[f64; #scalar_count]) -> #linearization {
                let mut residual = [0.0_f64; #dim];
                #(
                    let mut #outputs = [0.0_f64; #dim * #block_dims];
                )*
                Self::__factor_kernel_slices(
                    stored,
                    &mut residual,
                    &mut [#(::core::option::Option::Some(&mut #outputs[..])),*],
                );
                #linearization {
                    residual: #nalgebra::SVector::<f64, #dim>::from_column_slice(&residual),
                    #(
                        #blocks: #nalgebra::SMatrix::<f64, #dim, { #block_dims }>::from_row_slice(
                            &#outputs,
                        ),
                    )*
                }
            }

            /// Debug builds: the kernel against dual numbers through the current
            /// definition, on the first linearizations of this factor type, and
            /// every later one once it was found stale (`factor_core::kernel`,
            /// "A stale kernel never runs unnoticed").
            #[cfg(debug_assertions)]
            fn __factor_check_kernel(
                stored: &[f64; #scalar_count],
            ) -> ::core::result::Result<(), #krate::FactorError> {
                static WATCH: #krate::__private::KernelWatch = #krate::__private::KernelWatch::new();
                WATCH.check(|| {
                    let factor: Self = #krate::Storage::from_scalars(stored);
                    let dual = factor.linearize_dual().ok()?;
                    #krate::__private::kernel_stale::<Self>(
                        &Self::__factor_kernel_all(stored).to_dyn(),
                        &dual.to_dyn(),
                        #kernel_text,
                        #regenerate,
                    )
                })
            }

            #[doc = #doc]
            pub fn linearize_generated(
                &self,
            ) -> ::core::result::Result<#linearization, #krate::FactorError> {
                let mut stored = [0.0_f64; <Self as #krate::Storage<f64>>::SCALARS];
                #krate::Storage::write_scalars(self, &mut stored);
                #[cfg(debug_assertions)]
                Self::__factor_check_kernel(&stored)?;
                // The kernel first, as in `__factor_kernel`.
                let linearization = Self::__factor_kernel_all(&stored);
                <Self as #krate::Factor>::validate(self)?;
                linearization.ensure_finite()
            }
        }
    }
}
