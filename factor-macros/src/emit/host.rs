//! Host charts (`factor_core::host`): the factor served to a solver in the
//! solver's own manifolds.
//!
//! - `impl<H: Host> HostFactor<H> for Foo<f64>`, bounded by every variable
//!   type's `HostMap<H>`: the dispatch from a variable's index to its
//!   type's mapping. A variable type without a mapping onto a host makes
//!   the factor not a `HostFactor` of that host; the bound is spanned at the
//!   type, and `HostMap`'s diagnostic says what to implement.
//! - For each host of `#[factor(hosts(…))]`, `impl HostKernel<H>` calling
//!   the generated `<kernel>_<host>_host`.

use proc_macro2::{Group, TokenStream, TokenTree};
use quote::{format_ident, quote, quote_spanned};
use syn::spanned::Spanned;

use super::Context;
use super::kernel::{path_text, regenerate_text, sibling};

/// `tokens` with every identifier `from` replaced by `f64`: a field type of
/// the generic struct at the `f64` instance (`Se3<S>` → `Se3<f64>`).
fn at_f64(tokens: TokenStream, from: &syn::Ident) -> TokenStream {
    tokens
        .into_iter()
        .map(|tree| match tree {
            TokenTree::Ident(ident) if ident == *from => {
                TokenTree::Ident(proc_macro2::Ident::new("f64", ident.span()))
            }
            TokenTree::Group(group) => {
                let mut replaced = Group::new(group.delimiter(), at_f64(group.stream(), from));
                replaced.set_span(group.span());
                TokenTree::Group(replaced)
            }
            other => other,
        })
        .collect()
}

/// The `HostFactor` impl and one `HostKernel` impl per host of `hosts(…)`.
pub fn emit(cx: &Context) -> TokenStream {
    let krate = &cx.krate;
    let host = quote!(#krate::host);
    let ident = &cx.model.ident;
    let types: Vec<TokenStream> = cx
        .variables
        .iter()
        .map(|v| {
            let ty = v.ty;
            at_f64(quote!(#ty), &cx.model.scalar)
        })
        .collect();
    let bounds = cx
        .variables
        .iter()
        .zip(&types)
        .map(|(v, ty)| quote_spanned!(v.ty.span()=> #ty: #host::HostMap<__H>));
    let indices: Vec<usize> = cx.variables.iter().map(|v| v.index).collect();
    let count = cx.variables.len();
    let out_of_range = quote! {
        ::core::panic!(
            "{}: variable index {} out of range; the factor has {} variables",
            <Self as #krate::Factor>::NAME,
            variable,
            #count,
        )
    };
    let kernels = cx.model.hosts.iter().map(|h| host_kernel(cx, h));
    let tangent_dim = cx.tangent_dim_f64();
    quote! {
        #[automatically_derived]
        impl<__H: #host::Host> #host::HostFactor<__H> for #ident<f64>
        where
            #(#bounds,)*
        {
            fn variable_type(variable: usize) -> ::core::any::TypeId {
                match variable {
                    #(#indices => ::core::any::TypeId::of::<#types>(),)*
                    _ => #out_of_range,
                }
            }

            fn host_parts(variable: usize) -> &'static [#host::HostPart<__H::Manifold>] {
                match variable {
                    #(#indices => <#types as #host::HostMap<__H>>::PARTS,)*
                    _ => #out_of_range,
                }
            }

            fn stored_from_host<__T: #krate::Scalar>(
                variable: usize,
                host: &[__T],
                stored: &mut [__T],
            ) {
                match variable {
                    #(#indices => <#types as #host::HostMap<__H>>::stored_from_host(host, stored),)*
                    _ => #out_of_range,
                }
            }

            fn host_from_stored(variable: usize, stored: &[f64], host: &mut [f64]) {
                match variable {
                    #(#indices => <#types as #host::HostMap<__H>>::host_from_stored(stored, host),)*
                    _ => #out_of_range,
                }
            }

            fn linearize_host_dual_pass(
                layout: &#host::HostLayout<__H::Manifold>,
                template: &[f64],
                parts: &[&[f64]],
                residual: &mut [f64],
                jacobian: ::core::option::Option<&mut [f64]>,
            ) -> ::core::result::Result<(), #krate::FactorError> {
                #host::dual_pass::<Self, __H, { #tangent_dim }>(layout, template, parts, residual, jacobian)
            }
        }

        #(#kernels)*
    }
}

/// `impl HostKernel<H>` through `<kernel>_<name>_host`, with a
/// compile-time check that the host type's `NAME` is the attribute's.
fn host_kernel(cx: &Context, h: &crate::attrs::HostAttr) -> TokenStream {
    let krate = &cx.krate;
    let ident = &cx.model.ident;
    let Some(kernel) = &cx.model.kernel else {
        return TokenStream::new();
    };
    let (name, host_type) = (&h.name, &h.host);
    let span = name.span();
    let last = kernel
        .segments
        .last()
        .map_or_else(|| format_ident!("kernel"), |s| s.ident.clone());
    let function = format_ident!("{}_{}", last, name, span = span);
    let entry = sibling(
        kernel,
        &format_ident!("{}_{}_host", last, name, span = span),
    );
    let text = path_text(&sibling(kernel, &function));
    let regenerate = regenerate_text(cx);
    let name_text = name.to_string();
    let mismatch = format!(
        "`hosts({name_text} = …)` names a host whose `Host::NAME` is not \"{name_text}\": the \
         kernel of a host is named `<kernel>_<Host::NAME>`"
    );
    quote_spanned! {span=>
        const _: () = {
            if !#krate::__private::same_str(<#host_type as #krate::host::Host>::NAME, #name_text) {
                ::core::panic!(#mismatch);
            }
        };

        #[automatically_derived]
        impl #krate::host::HostKernel<#host_type> for #ident<f64> {
            const HOST_KERNEL: &'static str = #text;

            fn host_kernel(
                stored: &[f64],
                parts: &[&[f64]],
                residual: &mut [f64],
                jacobian: ::core::option::Option<&mut [f64]>,
            ) -> bool {
                #entry(stored, parts, residual, jacobian)
            }

            // Debug builds: the kernel against dual numbers in the same chart
            // on the first calls, and every later one once it was found stale
            // (`factor_core::kernel`, "A stale kernel never runs unnoticed").
            #[cfg(debug_assertions)]
            fn check_host_kernel(
                stored: &[f64],
                parts: &[&[f64]],
                residual: &[f64],
                jacobian: ::core::option::Option<&[f64]>,
            ) -> ::core::result::Result<(), #krate::FactorError> {
                static WATCH: #krate::__private::KernelWatch = #krate::__private::KernelWatch::new();
                WATCH.check(|| {
                    #krate::__private::host_kernel_stale::<Self, #host_type>(
                        stored,
                        parts,
                        residual,
                        jacobian,
                        #text,
                        #regenerate,
                    )
                })
            }
        }
    }
}
