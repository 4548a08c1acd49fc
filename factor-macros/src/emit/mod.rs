//! Code generation from a validated [`FactorModel`]. Each submodule emits one
//! group of items; [`Context`] holds what they share.
//!
//! Every use of a field type's traits (`Manifold`, `Storage`, `Clone`)
//! sits in code generic over the scalar and is spanned at that field type, so
//! a type lacking one is reported once, at the type. Code for the `f64`
//! instance only calls into the generic impls.

mod evaluate;
mod factor_impl;
mod host;
mod kernel;
mod layout;
mod linearization;
mod perturbed;
mod storage;

use proc_macro2::TokenStream;
use quote::quote;
use syn::{Generics, LitInt};

use crate::model::FactorModel;
use layout::Variable;

/// Everything the emitters share: the model, common paths and the variables.
struct Context<'a> {
    model: &'a FactorModel,
    /// `::factor_core`.
    krate: TokenStream,
    /// `::factor_core::__private::nalgebra`.
    nalgebra: TokenStream,
    /// The struct's generics with `Scalar` added to the scalar's bounds.
    generics: Generics,
    /// The residual dimension as an unsuffixed literal at the `dim` span.
    dim: LitInt,
    /// The variables in declaration order.
    variables: Vec<Variable<'a>>,
}

/// All generated items for one factor.
pub fn expand(model: &FactorModel) -> TokenStream {
    let krate = quote!(::factor_core);
    let mut generics = model.generics.clone();
    for param in generics.type_params_mut() {
        param.bounds.push(syn::parse_quote!(::factor_core::Scalar));
    }
    let cx = Context {
        model,
        nalgebra: quote!(#krate::__private::nalgebra),
        variables: layout::variables(model, &krate),
        krate,
        generics,
        dim: LitInt::new(model.dim.base10_digits(), model.dim.span()),
    };
    let items = [
        layout::emit(&cx),
        storage::emit(&cx),
        perturbed::emit(&cx),
        linearization::emit(&cx),
        evaluate::emit(&cx),
        kernel::emit(&cx),
        factor_impl::emit(&cx),
        host::emit(&cx),
    ];
    quote!(#(#items)*)
}

impl Context<'_> {
    /// `` `a`, `b` ``: the variables' names for generated documentation.
    fn variable_list(&self) -> String {
        let names: Vec<String> = self
            .variables
            .iter()
            .map(|v| format!("`{}`", v.ident))
            .collect();
        names.join(", ")
    }
}
