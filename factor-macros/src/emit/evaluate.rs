//! The typed `f64` API: `TANGENT_DIM`, `residual`, and the dual-number
//! linearizations (one pass over all variables, or one pass per variable).

use proc_macro2::TokenStream;
use quote::quote;

use super::Context;

/// `impl Foo<f64> { TANGENT_DIM, residual, linearize_dual, linearize_dual_per_block, linearize }`.
pub fn emit(cx: &Context) -> TokenStream {
    let krate = &cx.krate;
    let nalgebra = &cx.nalgebra;
    let num_dual = &cx.num_dual;
    let ident = &cx.model.ident;
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
    // The first pass's real part is the residual; the other passes repeat it.
    let residual_block =
        (0..blocks.len()).map(|k| if k == 0 { quote!(residual) } else { quote!(_) });
    let dual_doc = format!(
        "Residual and Jacobian blocks, exact to rounding, by one evaluation of \
         [`{ident}::perturbed_residual`] on dual numbers carrying the derivative w.r.t. \
         every tangent coordinate at once.\n\n\
         [`linearize_dual_per_block`](Self::linearize_dual_per_block) gives the same result \
         with one narrower pass per variable. Which strategy is faster depends on the \
         factor and is measured by the benchmark; [`linearize`](Self::linearize) is the \
         entry point that uses the chosen one.\n\n\
         # Errors\n\n\
         The validation's error, or \
         [`FactorError::NonFinite`](::factor_core::FactorError::NonFinite) naming the first \
         non-finite output."
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
    quote! {
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
                const __N: usize = #tangent_dim;
                let delta: [#num_dual::DualSVec64<__N>; __N] = ::core::array::from_fn(|i| {
                    #num_dual::DualSVec64::<__N>::from_re(0.0).derivative(i)
                });
                let value = self.__factor_lift::<__N>().perturbed_residual(&delta);
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

            /// The same as [`linearize_dual`](Self::linearize_dual), with one evaluation per
            /// variable on dual numbers as wide as that variable's tangent (the other
            /// variables are not perturbed). Kept beside the single pass so the benchmark
            /// can measure which is faster.
            ///
            /// # Errors
            ///
            /// As [`linearize_dual`](Self::linearize_dual).
            pub fn linearize_dual_per_block(&self) -> #result<#linearization, #error> {
                <Self as #krate::Factor>::validate(self)?;
                const __N: usize = #tangent_dim;
                #(
                    let (#residual_block, #blocks) = {
                        const __M: usize = #block_dims;
                        let mut delta = [#num_dual::DualSVec64::<__M>::from_re(0.0); __N];
                        for (i, d) in delta[#offsets..#offsets + __M].iter_mut().enumerate() {
                            *d = d.derivative(i);
                        }
                        Self::__factor_dual_parts(&self.__factor_lift::<__M>().perturbed_residual(&delta))
                    };
                )*
                #linearization { residual, #(#blocks,)* }.ensure_finite()
            }

            #[doc = #linearize_doc]
            pub fn linearize(&self) -> #result<#linearization, #error> {
                #linearize_body
            }

            /// The factor over dual numbers with `M` derivative components, all zero.
            fn __factor_lift<const M: usize>(&self) -> #ident<#num_dual::DualSVec64<M>> {
                #krate::Storage::map_scalars(self, &mut #num_dual::DualSVec64::<M>::from_re)
            }

            /// Real parts and derivative parts (rows: residual entries) of a dual residual.
            fn __factor_dual_parts<const M: usize>(
                value: &#nalgebra::SVector<#num_dual::DualSVec64<M>, #dim>,
            ) -> (#nalgebra::SVector<f64, #dim>, #nalgebra::SMatrix<f64, #dim, M>) {
                let jacobian = #nalgebra::SMatrix::<f64, #dim, M>::from_fn(|row, col| {
                    value[row].eps.0.as_ref().map_or(0.0, |eps| eps[col])
                });
                (value.map(|x| x.re), jacobian)
            }
        }
    }
}
