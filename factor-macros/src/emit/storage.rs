//! `impl<S: Scalar> Storage<S> for Foo<S>`: the factor stored as its fields'
//! scalars in declaration order, written by users field by field.

use proc_macro2::TokenStream;
use quote::{quote, quote_spanned};
use syn::spanned::Spanned;

use super::Context;

/// The `Storage` impl of the factor struct.
pub fn emit(cx: &Context) -> TokenStream {
    let krate = &cx.krate;
    let ident = &cx.model.ident;
    let scalar = &cx.model.scalar;
    let (impl_generics, ty_generics, where_clause) = cx.generics.split_for_impl();
    // Every use of a field type's `Storage`, and every call of one of its
    // functions, is spanned at the type (`Context::storage_item`).
    let item = |ty: &syn::Type, item: &str| cx.storage_item(ty, item);
    let counts = cx
        .model
        .fields
        .iter()
        .map(|field| item(&field.ty, "SCALARS"));
    let layout_of = |method: &str| {
        let parts = cx.model.fields.iter().map(|field| {
            let (name, layout) = (field.ident.to_string(), item(&field.ty, method));
            quote_spanned!(field.ty.span()=> (#name, #layout()))
        });
        quote!(#krate::Layout::Record(::std::vec![#(#parts),*]))
    };
    let layout = layout_of("layout");
    let input_layout = layout_of("input_layout");
    let mapped = cx.model.fields.iter().map(|field| {
        let (name, ty) = (&field.ident, &field.ty);
        let map = item(ty, "map_scalars");
        quote_spanned!(ty.span()=> #name: #map(&self.#name, f))
    });
    let read = cx.model.fields.iter().map(|field| {
        let (name, read) = (&field.ident, item(&field.ty, "read_scalars"));
        quote_spanned!(field.ty.span()=> #name: #read(next))
    });
    let from_input = cx.model.fields.iter().map(|field| {
        let name = field.ident.to_string();
        let (layout, convert) = (
            item(&field.ty, "input_layout"),
            item(&field.ty, "from_input"),
        );
        let (count, converted) = (
            quote_spanned!(field.ty.span()=> #layout().scalars()),
            quote_spanned!(field.ty.span()=> #convert(part)),
        );
        quote! {
            let count = #count;
            let (part, rest) = input.split_at(count);
            input = rest;
            stored.extend(#converted.map_err(|e| e.within(#name))?);
        }
    });
    quote! {
        #[automatically_derived]
        impl #impl_generics #krate::Storage<#scalar> for #ident #ty_generics #where_clause {
            type With<__T: #krate::Scalar> = #ident<__T>;
            const SCALARS: usize = 0usize #(+ #counts)*;
            fn layout() -> #krate::Layout {
                #layout
            }
            fn map_scalars<__T: #krate::Scalar>(
                &self,
                f: &mut impl ::core::ops::FnMut(#scalar) -> __T,
            ) -> #ident<__T> {
                #ident { #(#mapped,)* }
            }
            fn read_scalars(next: &mut impl ::core::ops::FnMut() -> #scalar) -> Self {
                #ident { #(#read,)* }
            }
            fn input_layout() -> #krate::Layout {
                #input_layout
            }
            fn from_input(
                input: &[f64],
            ) -> ::core::result::Result<::std::vec::Vec<f64>, #krate::StorageError> {
                let mut input = input;
                let mut stored = ::std::vec::Vec::with_capacity(Self::SCALARS);
                #(#from_input)*
                ::core::result::Result::Ok(stored)
            }
        }
    }
}
