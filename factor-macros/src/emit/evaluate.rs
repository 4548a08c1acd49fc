//! The typed `f64` API: `TANGENT_DIM`, `residual`, and the dual-number
//! linearization (one pass over the stacked tangent, each variable seeded
//! through its chart).

use proc_macro2::TokenStream;
use quote::{quote, quote_spanned};
use syn::spanned::Spanned;

use super::Context;

/// `impl Foo<f64> { TANGENT_DIM, residual, linearize_dual, linearize }`.
pub fn emit(cx: &Context) -> TokenStream {
    let krate = &cx.krate;
    let nalgebra = &cx.nalgebra;
    let ident = &cx.model.ident;
    let scalar = &cx.model.scalar;
    let dim = &cx.dim;
    let linearization = cx.model.linearization_ident();
    let tangent_dim = cx.tangent_dim_f64();
    let tangent_doc = format!(
        "Tangent dimension of the factor: the sum of its variables' tangent dimensions, \
         stacked in declaration order ({}).",
        cx.variable_list()
    );
    let blocks: Vec<_> = cx.variables.iter().map(|v| v.ident).collect();
    let block_dims: Vec<_> = cx.variables.iter().map(|v| cx.dim_f64(v)).collect();
    let offsets: Vec<_> = cx.variables.iter().map(|v| cx.offset_f64(v)).collect();
    // The struct is lifted to constants through its `Storage` impl (so that a
    // field type that is not stored is reported there, once), then each
    // variable is seeded through its chart at its offset in the stacked
    // tangent; the constant copies of the variables are dead stores. The
    // seeding is generic over the scalar, like every other use of a field
    // type's traits (see `emit`), so that a variable that is not a manifold
    // is not reported again for `f64`; its tangent dimension, a const generic
    // argument, is given by this `f64` code.
    let dim_params: Vec<_> = cx
        .variables
        .iter()
        .map(|v| quote::format_ident!("__D{}", v.index))
        .collect();
    let seeded = cx.variables.iter().zip(&dim_params).map(|(v, dim)| {
        let (ty, side) = (v.ty, &v.side_tokens);
        // The field's name at the type too, so that the statement's errors
        // are reported at the type alone.
        let mut name = v.ident.clone();
        name.set_span(ty.span());
        let offset = cx.offset_generic(v);
        quote_spanned! {ty.span()=>
            lifted.#name = <#ty as #krate::Manifold<#scalar>>::seeded::<#dim, __N>(&self.#name, #side, #offset);
        }
    });
    let dual_doc = format!(
        "Residual and Jacobian blocks, exact to rounding, by one evaluation of the residual \
         on dual numbers ([`Dual`](::factor_core::dual::Dual)) carrying the derivative w.r.t. \
         the whole stacked tangent ({}) at once, on the stack: each variable is seeded \
         through its retraction ([`Manifold::seeded`](::factor_core::Manifold::seeded)), then \
         the residual runs once.\n\n\
         # Errors\n\n\
         The validation's error, or \
         [`FactorError::NonFinite`](::factor_core::FactorError::NonFinite) naming the first \
         non-finite output.",
        cx.variable_list()
    );
    let result = quote!(::core::result::Result);
    let error = quote!(#krate::FactorError);
    let (linearize_doc, linearize_body) = match &cx.model.kernel {
        Some(kernel) => (
            format!(
                "Residual and Jacobian blocks through the generated kernel `{}` \
                 ([`linearize_generated`](Self::linearize_generated)); \
                 [`linearize_dual`](Self::linearize_dual) gives the same by dual numbers.\n\n\
                 # Errors\n\n\
                 As [`linearize_dual`](Self::linearize_dual).",
                super::kernel::path_text(kernel)
            ),
            quote!(self.linearize_generated()),
        ),
        None => (
            "Residual and Jacobian blocks: [`linearize_dual`](Self::linearize_dual) (the \
             factor has no generated kernel; see `#[factor(kernel = ...)]`).\n\n\
             # Errors\n\n\
             As [`linearize_dual`](Self::linearize_dual)."
                .to_string(),
            quote!(self.linearize_dual()),
        ),
    };
    let (impl_generics, ty_generics, where_clause) = cx.generics.split_for_impl();
    quote! {
        impl #impl_generics #ident #ty_generics #where_clause {
            /// Each variable of `lifted`, the factor as dual-number constants,
            /// seeded through its chart at its offset in the stacked tangent of
            /// `N`; `__Dk` is the tangent dimension of the `k`-th variable.
            #[inline(always)]
            fn __factor_seed<const __N: usize, #(const #dim_params: usize),*>(
                &self,
                lifted: &mut #ident<#krate::dual::Dual<__N>>,
            ) where #scalar: ::core::convert::Into<f64> {
                #(#seeded)*
            }
        }

        impl #ident<f64> {
            #[doc = #tangent_doc]
            pub const TANGENT_DIM: usize = #tangent_dim;

            /// The residual, after [`Factor::validate`](::factor_core::Factor::validate).
            ///
            /// # Errors
            ///
            /// The validation's error, or [`FactorError::NonFinite`](::factor_core::FactorError::NonFinite)
            /// if the residual is not finite.
            pub fn residual(&self) -> #result<#nalgebra::SVector<f64, #dim>, #error> {
                <Self as #krate::Factor>::validate(self)?;
                let residual = Self::__factor_residual(self);
                if residual.iter().all(|x| x.is_finite()) {
                    #result::Ok(residual)
                } else {
                    #result::Err(#krate::FactorError::NonFinite {
                        factor: <Self as #krate::Factor>::NAME,
                        what: ::std::string::String::from("residual"),
                    })
                }
            }

            #[doc = #dual_doc]
            pub fn linearize_dual(&self) -> #result<#linearization, #error> {
                <Self as #krate::Factor>::validate(self)?;
                type __Dual = #krate::dual::Dual<{ #tangent_dim }>;
                let value = #ident::<__Dual>::__factor_residual(&self.__factor_seeded::<{ #tangent_dim }>());
                let (residual, jacobian) = Self::__factor_dual_parts(&value);
                #linearization {
                    residual,
                    #(
                        #blocks: jacobian
                            .fixed_view::<#dim, { #block_dims }>(0, #offsets)
                            .into_owned(),
                    )*
                }
                .ensure_finite()
            }

            #[doc = #linearize_doc]
            pub fn linearize(&self) -> #result<#linearization, #error> {
                #linearize_body
            }

            /// The factor over dual numbers with `N` derivative components: its
            /// constants with none, each variable seeded at its tangent's offset.
            #[inline(always)]
            fn __factor_seeded<const __N: usize>(&self) -> #ident<#krate::dual::Dual<__N>> {
                let mut lifted: #ident<#krate::dual::Dual<__N>> =
                    #krate::Storage::map_scalars(self, &mut #krate::dual::Dual::<__N>::constant);
                self.__factor_seed::<__N, #({ #block_dims }),*>(&mut lifted);
                lifted
            }

            /// Real parts and derivative parts (rows: residual entries) of a dual residual.
            #[inline(always)]
            fn __factor_dual_parts<const __N: usize>(
                value: &#nalgebra::SVector<#krate::dual::Dual<__N>, #dim>,
            ) -> (#nalgebra::SVector<f64, #dim>, #nalgebra::SMatrix<f64, #dim, __N>) {
                let jacobian = #nalgebra::SMatrix::<f64, #dim, __N>::from_fn(|row, col| {
                    value[row].eps[col]
                });
                (value.map(|x| x.re), jacobian)
            }
        }
    }
}
