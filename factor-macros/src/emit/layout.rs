//! The layout of the stacked tangent vector `δ = [δ_v₁, …, δ_vₙ]`: each
//! variable's tangent dimension and offset.
//!
//! They are private associated consts of the generic impl, the only place
//! that names `<Ty<S> as Manifold<S>>::DIM`; code for the `f64` instance reads
//! them as `<Foo<f64>>::__FACTOR_DIMS[k]`. So a field type that is not a
//! manifold is reported once, at the type, and never again for `f64`.

use proc_macro2::TokenStream;
use quote::{quote, quote_spanned};
use syn::spanned::Spanned;
use syn::{Ident, Type};

use super::Context;
use crate::attrs::Side;
use crate::model::FactorModel;

/// One variable of the factor.
pub struct Variable<'a> {
    /// The field's name.
    pub ident: &'a Ident,
    /// The field's type as written (over the scalar parameter).
    pub ty: &'a Type,
    /// The perturbation side.
    pub side: Side,
    /// `::factor_core::Perturbation::Left` or `::Right`.
    pub side_tokens: TokenStream,
    /// Position among the variables.
    pub index: usize,
}

/// The variables of `model` in declaration order.
pub fn variables<'a>(model: &'a FactorModel, krate: &TokenStream) -> Vec<Variable<'a>> {
    model
        .variables()
        .enumerate()
        .map(|(index, (field, side))| Variable {
            ident: &field.ident,
            ty: &field.ty,
            side,
            side_tokens: match side {
                Side::Left => quote!(#krate::Perturbation::Left),
                Side::Right => quote!(#krate::Perturbation::Right),
            },
            index,
        })
        .collect()
}

/// `impl<S: Scalar> Foo<S> { __FACTOR_DIMS, __FACTOR_OFFSETS, __FACTOR_SCALARS,
/// __FACTOR_TANGENT_DIM }`.
pub fn emit(cx: &Context) -> TokenStream {
    let krate = &cx.krate;
    let ident = &cx.model.ident;
    let scalar = &cx.model.scalar;
    let (impl_generics, ty_generics, where_clause) = cx.generics.split_for_impl();
    let count = cx.variables.len();
    let dims = cx.variables.iter().map(|v| {
        let ty = v.ty;
        quote_spanned!(ty.span()=> <#ty as #krate::Manifold<#scalar>>::DIM)
    });
    let field_count = cx.model.fields.len();
    let scalars = cx
        .model
        .fields
        .iter()
        .map(|field| cx.storage_item(&field.ty, "SCALARS"));
    let offsets = (0..count).map(|k| {
        let previous = 0..k;
        quote!(0usize #(+ Self::__FACTOR_DIMS[#previous])*)
    });
    quote! {
        impl #impl_generics #ident #ty_generics #where_clause {
            /// Tangent dimension of each variable, in declaration order.
            const __FACTOR_DIMS: [usize; #count] = [#(#dims),*];
            /// Offset of each variable's tangent in the stacked tangent vector.
            const __FACTOR_OFFSETS: [usize; #count] = [#(#offsets),*];
            /// Number of stored scalars of each field, in declaration order.
            const __FACTOR_SCALARS: [usize; #field_count] = [#(#scalars),*];
            /// Length of the stacked tangent vector.
            const __FACTOR_TANGENT_DIM: usize =
                Self::__FACTOR_OFFSETS[#count - 1] + Self::__FACTOR_DIMS[#count - 1];
        }
    }
}

impl Context<'_> {
    /// `variable`'s tangent dimension, in generic code.
    pub fn dim_generic(&self, variable: &Variable) -> TokenStream {
        let k = variable.index;
        quote!(Self::__FACTOR_DIMS[#k])
    }

    /// `variable`'s offset in the stacked tangent, in generic code.
    pub fn offset_generic(&self, variable: &Variable) -> TokenStream {
        let k = variable.index;
        quote!(Self::__FACTOR_OFFSETS[#k])
    }

    /// `variable`'s tangent dimension as a constant of the `f64` instance,
    /// usable as a const generic argument.
    pub fn dim_f64(&self, variable: &Variable) -> TokenStream {
        let (ident, k) = (&self.model.ident, variable.index);
        quote!(<#ident<f64>>::__FACTOR_DIMS[#k])
    }

    /// `variable`'s offset in the stacked tangent of the `f64` instance.
    pub fn offset_f64(&self, variable: &Variable) -> TokenStream {
        let (ident, k) = (&self.model.ident, variable.index);
        quote!(<#ident<f64>>::__FACTOR_OFFSETS[#k])
    }

    /// The stacked tangent's length for the `f64` instance.
    pub fn tangent_dim_f64(&self) -> TokenStream {
        let ident = &self.model.ident;
        quote!(<#ident<f64>>::__FACTOR_TANGENT_DIM)
    }

    /// `<ty as Storage<S>>::item`, every token spanned at the field type
    /// `ty`, so that a type that is not stored is reported there, once (a
    /// call of one of its functions spanned elsewhere is reported again
    /// there).
    pub fn storage_item(&self, ty: &syn::Type, item: &str) -> TokenStream {
        let (krate, scalar) = (&self.krate, &self.model.scalar);
        let item = syn::Ident::new(item, ty.span());
        quote_spanned!(ty.span()=> <#ty as #krate::Storage<#scalar>>::#item)
    }

    /// The layout of `field` if it is a variable.
    pub fn variable(&self, field: &crate::model::Field) -> Option<&Variable<'_>> {
        self.variables.iter().find(|v| v.ident == &field.ident)
    }
}
