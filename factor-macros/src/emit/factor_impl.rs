//! `impl Factor for Foo<f64>`: the uniform, dynamically sized view, with the
//! generic helpers it calls (the variables' descriptions, exact retraction).

use proc_macro2::TokenStream;
use quote::{quote, quote_spanned};
use syn::spanned::Spanned;

use super::Context;
use crate::naming;

/// The `Factor` impl of the `f64` instance and its generic helpers.
pub fn emit(cx: &Context) -> TokenStream {
    let krate = &cx.krate;
    let nalgebra = &cx.nalgebra;
    let ident = &cx.model.ident;
    let scalar = &cx.model.scalar;
    let name = &cx.model.name;
    let ident_text = ident.to_string();
    let description = &cx.model.doc;
    let dim = &cx.dim;
    let result = quote!(::core::result::Result);
    let error = quote!(#krate::FactorError);
    let (impl_generics, ty_generics, where_clause) = cx.generics.split_for_impl();
    let infos = cx.variables.iter().map(|v| {
        let (ty, side) = (v.ty, &v.side_tokens);
        let field = v.ident.to_string();
        // The scalar itself is named for what it is at the `f64` instance
        // (a problem file's `"type": "f64"`), not for the parameter (`S`).
        let is_scalar =
            matches!(ty, syn::Type::Path(p) if p.qself.is_none() && p.path.is_ident(scalar));
        let type_name = if is_scalar {
            "f64".to_owned()
        } else {
            naming::type_text(ty)
        };
        let tangent_dim = cx.dim_generic(v);
        let tangent =
            quote_spanned!(ty.span()=> <#ty as #krate::Manifold<#scalar>>::tangent_description);
        quote_spanned! {ty.span()=>
            #krate::VariableInfo {
                name: #field,
                type_name: #type_name,
                tangent_dim: #tangent_dim,
                perturbation: #side,
                tangent: #tangent(#side),
            }
        }
    });
    let fields = cx.model.fields.iter().map(|field| {
        let (name, ty) = (&field.ident, &field.ty);
        let clone = quote_spanned!(ty.span()=> ::core::clone::Clone::clone(&self.#name));
        match cx.variable(field) {
            Some(v) => {
                let (k, side) = (v.index, &v.side_tokens);
                let retract =
                    quote_spanned!(ty.span()=> <#ty as #krate::Manifold<#scalar>>::retract);
                quote!(#name: if index == #k { #retract(&self.#name, delta, #side) } else { #clone })
            }
            None => quote!(#name: #clone),
        }
    });
    // The types are named as everywhere else in the derive
    // (`<Ty as Manifold<S>>::…`), so that a type without the trait is one
    // error, not one per use.
    let charts = cx.variables.iter().map(|v| {
        let (ty, side, k) = (v.ty, &v.side_tokens, v.index);
        let manifold = quote_spanned!(ty.span()=> <#ty as #krate::Manifold<#scalar>>);
        let storage = quote_spanned!(ty.span()=> <#ty as #krate::Storage<#scalar>>);
        let map = quote!(#krate::manifold::ChartMap);
        quote_spanned! {ty.span()=>
            #k => {
                let value = #storage::from_scalars(point);
                match map {
                    #map::Retract => {
                        #storage::write_scalars(&#manifold::retract(&value, argument, #side), out)
                    }
                    #map::RetractFirstOrder => #storage::write_scalars(
                        &#manifold::retract_first_order(&value, argument, #side),
                        out,
                    ),
                    #map::Local => {
                        let other = #storage::from_scalars(argument);
                        #manifold::local(&value, &other, #side, out)?
                    }
                }
                #result::Ok(())
            }
        }
    });
    let validate = match &cx.model.validate {
        Some(path) => {
            let path = quote_spanned!(path.span()=> #path);
            quote! {
                let validate: fn(&Self) -> #result<(), #error> = #path;
                validate(self)
            }
        }
        None => quote!(#result::Ok(())),
    };
    let count = cx.variables.len();
    let field_infos = cx.model.fields.iter().map(|field| {
        let (field_name, doc) = (field.ident.to_string(), &field.doc);
        let ty = &field.ty;
        let item = |item: &str| cx.storage_item(ty, item);
        let (scalars, layout, input_layout, from_input) = (
            item("SCALARS"),
            item("layout"),
            item("input_layout"),
            item("from_input"),
        );
        let variable = match cx.variable(field) {
            Some(v) => {
                let k = v.index;
                quote!(::core::option::Option::Some(#k))
            }
            None => quote!(::core::option::Option::None),
        };
        quote_spanned! {ty.span()=>
            #krate::FieldInfo {
                name: #field_name,
                doc: #doc,
                scalars: #scalars,
                variable: #variable,
                layout: #layout(),
                input_layout: #input_layout(),
                from_input: #from_input,
            }
        }
    });
    let generated = cx.model.kernel.as_ref().map(|kernel| {
        let text = super::kernel::path_text(kernel);
        quote! {
            const KERNEL: ::core::option::Option<&'static str> =
                ::core::option::Option::Some(#text);

            fn linearize_generated_dyn(
                &self,
            ) -> ::core::option::Option<#result<#krate::DynLinearization, #error>> {
                ::core::option::Option::Some(
                    self.linearize_generated().map(|linearization| linearization.to_dyn()),
                )
            }
        }
    });
    let blocks: Vec<_> = cx.variables.iter().map(|v| v.ident).collect();
    let indices: Vec<usize> = cx.variables.iter().map(|v| v.index).collect();
    let linearize_into = match &cx.model.kernel {
        Some(_) => quote!(self.linearize_generated_into(residual, jacobians)),
        None => quote!(self.linearize_dual_into(residual, jacobians)),
    };
    let linearize_stored_into = match &cx.model.kernel {
        // The factor rebuilt before the kernel runs: measured faster than
        // after it (the between factor's path 11% slower so).
        Some(_) => quote! {
            let factor: Self = #krate::Storage::from_scalars(stored);
            Self::__factor_kernel_stored(
                stored,
                residual,
                jacobians,
                ::core::option::Option::Some(&factor),
            )
        },
        None => quote! {
            let factor: Self = #krate::Storage::from_scalars(stored);
            factor.linearize_dual_into(residual, jacobians)
        },
    };
    // Without a kernel the default (dual numbers, validation included):
    // theirs costs little beside the dual-number pass.
    let linearize_stored_validated_into = cx.model.kernel.as_ref().map(|_| {
        quote! {
            fn linearize_stored_validated_into(
                stored: &[f64],
                residual: &mut [f64],
                jacobians: &mut [::core::option::Option<&mut [f64]>],
            ) -> #result<(), #error> {
                Self::__factor_kernel_stored(
                    stored,
                    residual,
                    jacobians,
                    ::core::option::Option::None,
                )
            }
        }
    });
    // Through dual numbers every block is computed; the ones held fixed are
    // not written.
    let linearize_dual_into = quote! {
        ::core::assert_eq!(
            jacobians.len(),
            #count,
            "one Jacobian entry per variable",
        );
        let linearization = self.linearize_dual()?;
        residual.copy_from_slice(linearization.residual.as_slice());
        #(
            if let ::core::option::Option::Some(block) = jacobians[#indices].as_deref_mut() {
                block.copy_from_slice(linearization.#blocks.transpose().as_slice());
            }
        )*
        #result::Ok(())
    };
    quote! {
        impl #impl_generics #ident #ty_generics #where_clause {
            /// The variables as [`Factor::variables`](::factor_core::Factor::variables) reports them.
            fn __factor_variables() -> ::std::vec::Vec<#krate::VariableInfo> {
                ::std::vec![#(#infos),*]
            }

            /// The fields as [`Factor::fields`](::factor_core::Factor::fields) reports them.
            fn __factor_fields() -> ::std::vec::Vec<#krate::FieldInfo> {
                ::std::vec![#(#field_infos),*]
            }

            /// A copy with variable `index` retracted exactly by `delta`.
            fn __factor_retract(&self, index: usize, delta: &[#scalar]) -> Self {
                #ident { #(#fields,)* }
            }

            /// Variable `variable`'s chart, as [`Factor::chart_over`](::factor_core::Factor::chart_over).
            fn __factor_chart(
                variable: usize,
                map: #krate::manifold::ChartMap,
                point: &[#scalar],
                argument: &[#scalar],
                out: &mut [#scalar],
            ) -> #result<(), #krate::manifold::NoLocal> {
                match variable {
                    #(#charts)*
                    _ => ::core::panic!(
                        "{}: variable index {} out of range; the factor has {} variables",
                        #name,
                        variable,
                        #count,
                    ),
                }
            }
        }

        #[automatically_derived]
        impl #krate::Factor for #ident<f64> {
            const NAME: &'static str = #name;
            const TYPE_PATH: &'static str =
                ::core::concat!(::core::module_path!(), "::", #ident_text);
            const DESCRIPTION: &'static str = #description;
            const RESIDUAL_DIM: usize = #dim;
            const TANGENT_DIM: usize = <#ident<f64>>::__FACTOR_TANGENT_DIM;

            fn fields() -> ::std::vec::Vec<#krate::FieldInfo> {
                <#ident<f64>>::__factor_fields()
            }

            fn perturbed_residual_over<__T: #krate::Scalar>(
                stored: &[__T],
                delta: &[__T],
            ) -> ::std::vec::Vec<__T> {
                let factor: #ident<__T> = #krate::Storage::from_scalars(stored);
                factor.perturbed_residual(delta).iter().copied().collect()
            }

            fn residual_over_into<__T: #krate::Scalar>(stored: &[__T], out: &mut [__T]) {
                let factor: #ident<__T> = #krate::Storage::from_scalars(stored);
                out.copy_from_slice(#ident::<__T>::__factor_residual(&factor).as_slice());
            }

            fn variables() -> ::std::vec::Vec<#krate::VariableInfo> {
                Self::__factor_variables()
            }

            fn validate(&self) -> #result<(), #error> {
                #validate
            }

            fn residual_dyn(&self) -> #result<#nalgebra::DVector<f64>, #error> {
                self.residual()
                    .map(|residual| #nalgebra::DVector::from_column_slice(residual.as_slice()))
            }

            fn linearize_dual_dyn(&self) -> #result<#krate::DynLinearization, #error> {
                self.linearize_dual().map(|linearization| linearization.to_dyn())
            }

            #generated

            fn linearize_into(
                &self,
                residual: &mut [f64],
                jacobians: &mut [::core::option::Option<&mut [f64]>],
            ) -> #result<(), #error> {
                #linearize_into
            }

            fn linearize_dual_into(
                &self,
                residual: &mut [f64],
                jacobians: &mut [::core::option::Option<&mut [f64]>],
            ) -> #result<(), #error> {
                #linearize_dual_into
            }

            fn linearize_stored_into(
                stored: &[f64],
                residual: &mut [f64],
                jacobians: &mut [::core::option::Option<&mut [f64]>],
            ) -> #result<(), #error> {
                #linearize_stored_into
            }

            #linearize_stored_validated_into

            fn chart_over<__T: #krate::Scalar>(
                variable: usize,
                map: #krate::manifold::ChartMap,
                point: &[__T],
                argument: &[__T],
                out: &mut [__T],
            ) -> #result<(), #krate::manifold::NoLocal> {
                #ident::<__T>::__factor_chart(variable, map, point, argument, out)
            }

            fn with_retracted(&self, index: usize, delta: &[f64]) -> Self {
                ::core::assert!(
                    index < #count,
                    "{}: variable index {} out of range; the factor has {} variables",
                    <Self as #krate::Factor>::NAME,
                    index,
                    #count,
                );
                self.__factor_retract(index, delta)
            }
        }
    }
}
