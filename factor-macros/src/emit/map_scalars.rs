//! `impl<S: Scalar> MapScalars<S> for Foo<S>`: the factor lifted to another
//! scalar field by field, in declaration order.

use proc_macro2::TokenStream;
use quote::{quote, quote_spanned};
use syn::spanned::Spanned;

use super::Context;

/// The `MapScalars` impl of the factor struct.
pub fn emit(cx: &Context) -> TokenStream {
    let krate = &cx.krate;
    let ident = &cx.model.ident;
    let scalar = &cx.model.scalar;
    let (impl_generics, ty_generics, where_clause) = cx.generics.split_for_impl();
    let counts = cx.model.fields.iter().map(|field| {
        let ty = &field.ty;
        quote_spanned!(ty.span()=> <#ty as #krate::MapScalars<#scalar>>::SCALARS)
    });
    let mapped = cx.model.fields.iter().map(|field| {
        let (name, ty) = (&field.ident, &field.ty);
        quote_spanned! {ty.span()=>
            #name: <#ty as #krate::MapScalars<#scalar>>::map_scalars(&self.#name, f)
        }
    });
    quote! {
        #[automatically_derived]
        impl #impl_generics #krate::MapScalars<#scalar> for #ident #ty_generics #where_clause {
            type With<__T: #krate::Scalar> = #ident<__T>;
            const SCALARS: usize = 0usize #(+ #counts)*;
            fn map_scalars<__T: #krate::Scalar>(
                &self,
                f: &mut impl ::core::ops::FnMut(#scalar) -> __T,
            ) -> #ident<__T> {
                #ident { #(#mapped,)* }
            }
        }
    }
}
