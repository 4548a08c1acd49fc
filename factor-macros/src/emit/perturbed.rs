//! The generic residual at a perturbed configuration: the one function that
//! dual numbers (and a symbolic tracer) differentiate.

use proc_macro2::TokenStream;
use quote::{quote, quote_spanned};
use syn::spanned::Spanned;

use super::Context;

/// `Foo::<S>::perturbed_residual` and the private call of the residual
/// function that checks its signature.
pub fn emit(cx: &Context) -> TokenStream {
    let krate = &cx.krate;
    let nalgebra = &cx.nalgebra;
    let ident = &cx.model.ident;
    let scalar = &cx.model.scalar;
    let dim = &cx.dim;
    let (impl_generics, ty_generics, where_clause) = cx.generics.split_for_impl();
    let fields = cx.model.fields.iter().map(|field| {
        let (name, ty) = (&field.ident, &field.ty);
        match cx.variable(field) {
            Some(v) => {
                let (offset, dim, side) = (cx.offset_generic(v), cx.dim_generic(v), &v.side_tokens);
                quote_spanned! {ty.span()=>
                    #name: <#ty as #krate::Manifold<#scalar>>::retract_first_order(
                        &self.#name,
                        &delta[#offset..#offset + #dim],
                        #side,
                    )
                }
            }
            None => quote_spanned!(ty.span()=> #name: ::core::clone::Clone::clone(&self.#name)),
        }
    });
    // The field types are named in the residual's call, so that one that
    // does not resolve (reported at the type) marks the call erroneous:
    // rustc then does not add that the residual's scalar cannot be inferred
    // (the struct's parameter is unconstrained when no field type resolves).
    let types = cx.model.fields.iter().map(|field| &field.ty);
    let residual_fn = &cx.model.residual;
    let span = residual_fn.span();
    let private = quote!(#krate::__private);
    let arg =
        quote_spanned!(span=> #private::residual_arg::<Self, #scalar, _, _, _>(factor, signature));
    let checked =
        quote_spanned!(span=> #private::residual_value::<Self, #scalar, _, _, _>(value, signature));
    let residual_fn = quote_spanned!(span=> #residual_fn);
    let value = quote_spanned!(dim.span()=> value);
    let doc = format!(
        "The residual with every variable retracted by its slice of `delta`, to first \
         order ([`Manifold::retract_first_order`](::factor_core::Manifold::retract_first_order)) \
         on its perturbation side. `delta` stacks the variables' tangents in declaration \
         order ({}); its length is `{ident}::<f64>::TANGENT_DIM`.\n\n\
         Its derivative at `delta = 0` is the Jacobian: `linearize_dual` evaluates it on \
         dual numbers.\n\n# Panics\n\nIf `delta` has the wrong length.",
        cx.variable_list(),
    );
    quote! {
        impl #impl_generics #ident #ty_generics #where_clause {
            #[doc = #doc]
            pub fn perturbed_residual(&self, delta: &[#scalar]) -> #nalgebra::SVector<#scalar, #dim> {
                ::core::assert_eq!(
                    delta.len(),
                    Self::__FACTOR_TANGENT_DIM,
                    "`delta` stacks the tangents of every variable of the factor",
                );
                let perturbed = #ident { #(#fields,)* };
                Self::__factor_residual(&perturbed)
            }

            /// The residual function of `#[factor(residual = ...)]`, called at one
            /// place so that a residual not generic over the scalar is reported
            /// once, at the function's path (`factor_core`'s `ResidualOf` says
            /// how to write it), and a wrong dimension at `dim`.
            fn __factor_residual(factor: &Self) -> #nalgebra::SVector<#scalar, #dim> {
                let _: ::core::marker::PhantomData<(#(#types,)*)> = ::core::marker::PhantomData;
                let signature = ::core::marker::PhantomData;
                let arg = #arg;
                let value = #residual_fn(arg);
                let value = #checked;
                #value
            }
        }
    }
}
