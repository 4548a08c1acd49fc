//! `linearize_generated`: the linearization through a generated kernel
//! (`#[factor(kernel = path)]`), a function of the generated crate
//! `fn<T: Real>(&[T; N₁], …, &mut [T; dim], Option<&mut [T; dim·D₁]>, …)`
//! taking every field flattened in `MapScalars` order.

use proc_macro2::TokenStream;
use quote::{format_ident, quote, quote_spanned};
use syn::Path;
use syn::spanned::Spanned;

use super::Context;

/// The kernel's path as written, without spaces, for documentation.
pub fn path_text(path: &Path) -> String {
    quote!(#path).to_string().replace(' ', "")
}

/// `impl Foo<f64> { linearize_generated }`, or nothing without a kernel.
pub fn emit(cx: &Context) -> TokenStream {
    let Some(kernel) = &cx.model.kernel else {
        return TokenStream::new();
    };
    let krate = &cx.krate;
    let nalgebra = &cx.nalgebra;
    let ident = &cx.model.ident;
    let dim = &cx.dim;
    let linearization = cx.model.linearization_ident();
    let inputs: Vec<_> = cx
        .model
        .fields
        .iter()
        .map(|f| format_ident!("__in_{}", f.ident))
        .collect();
    let flatten = cx
        .model
        .fields
        .iter()
        .zip(&inputs)
        .enumerate()
        .map(|(i, (field, input))| {
            let name = &field.ident;
            quote! {
                let mut #input = [0.0_f64; <#ident<f64>>::__FACTOR_SCALARS[#i]];
                {
                    let mut slots = #input.iter_mut();
                    let _ = #krate::MapScalars::map_scalars(&self.#name, &mut |s: f64| {
                        if let ::core::option::Option::Some(slot) = slots.next() {
                            *slot = s;
                        }
                        s
                    });
                }
            }
        });
    let blocks: Vec<_> = cx.variables.iter().map(|v| v.ident).collect();
    let outputs: Vec<_> = cx
        .variables
        .iter()
        .map(|v| format_ident!("__d_{}", v.ident))
        .collect();
    let block_dims: Vec<_> = cx.variables.iter().map(|v| cx.dim_f64(v)).collect();
    // A typed binding: a kernel with the wrong signature is reported at its
    // path, with the expected `fn` type.
    let scalars = (0..cx.model.fields.len()).map(|i| quote!(<#ident<f64>>::__FACTOR_SCALARS[#i]));
    let block_dims_again = block_dims.clone();
    let kernel_type = quote! {
        fn(
            #(&[f64; #scalars],)*
            &mut [f64; #dim],
            #(::core::option::Option<&mut [f64; #dim * #block_dims_again]>,)*
        )
    };
    let kernel = quote_spanned!(kernel.span()=> #kernel);
    let doc = format!(
        "Residual and Jacobian blocks through the generated kernel \
         [`{0}`]({0}): straight-line code with every entry unrolled and common \
         subexpressions shared, exact to rounding like \
         [`linearize_dual`](Self::linearize_dual).\n\n\
         # Errors\n\n\
         The validation's error, or \
         [`FactorError::NonFinite`](::factor_core::FactorError::NonFinite) naming the first \
         non-finite output.",
        path_text(cx.model.kernel.as_ref().expect("checked above"))
    );
    quote! {
        impl #ident<f64> {
            #[doc = #doc]
            pub fn linearize_generated(
                &self,
            ) -> ::core::result::Result<#linearization, #krate::FactorError> {
                <Self as #krate::Factor>::validate(self)?;
                #(#flatten)*
                let mut __residual = [0.0_f64; #dim];
                #(
                    let mut #outputs = [0.0_f64; #dim * #block_dims];
                )*
                let kernel: #kernel_type = #kernel;
                kernel(
                    #(&#inputs,)*
                    &mut __residual,
                    #(::core::option::Option::Some(&mut #outputs),)*
                );
                #linearization {
                    residual: #nalgebra::SVector::<f64, #dim>::from_column_slice(&__residual),
                    #(
                        #blocks: #nalgebra::SMatrix::<f64, #dim, { #block_dims }>::from_row_slice(
                            &#outputs,
                        ),
                    )*
                }
                .ensure_finite()
            }
        }
    }
}
