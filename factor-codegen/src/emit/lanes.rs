//! The marker type `Kernel` and, behind the crate's `lanes` feature, its
//! `factor_lanes::Kernel` (and `factor_lanes::NormalKernel`)
//! implementations over every `T: Real`: the kernels with their inputs and
//! outputs each in one array, for batch evaluators.

use proc_macro2::{Ident, Literal, TokenStream};
use quote::{format_ident, quote};

use super::{ModuleParts, field_sizes, jacobian_idents};

/// `inputs[a], …, inputs[b − 1]` as one array expression per field.
fn field_arrays(parts: &ModuleParts) -> Vec<TokenStream> {
    let mut offset = 0;
    parts
        .kernel
        .fields
        .iter()
        .map(|f| {
            let indices = (offset..offset + f.scalars).map(Literal::usize_unsuffixed);
            offset += f.scalars;
            quote!(&[#(inputs[#indices]),*])
        })
        .collect()
}

/// `let Some((name, rest)) = rest.split_first_chunk_mut::<N>() else { return; };`
/// for each `(name, N)`, the first from `first` (the last one's rest
/// discarded).
fn split_outputs(first: &Ident, chunks: &[(Ident, usize)]) -> Vec<TokenStream> {
    chunks
        .iter()
        .enumerate()
        .map(|(k, (name, len))| {
            let from = if k == 0 { quote!(#first) } else { quote!(rest) };
            let rest = if k + 1 == chunks.len() {
                quote!(_)
            } else {
                quote!(rest)
            };
            let len = Literal::usize_unsuffixed(*len);
            quote! {
                let Some((#name, #rest)) = #from.split_first_chunk_mut::<#len>() else {
                    return;
                };
            }
        })
        .collect()
}

/// `flags[k] == true`, false beyond `flags`.
fn flag(flags: &Ident, k: usize) -> TokenStream {
    if k == 0 {
        quote!(matches!(#flags.first(), Some(true)))
    } else {
        let k = Literal::usize_unsuffixed(k);
        quote!(matches!(#flags.get(#k), Some(true)))
    }
}

/// The marker and its implementations.
pub fn items(parts: &ModuleParts) -> TokenStream {
    let kernel = parts.kernel;
    let name = format_ident!("{}", parts.spec.name);
    let lowered = parts.lowered;
    let input_len = Literal::usize_unsuffixed(kernel.input_len());
    let r = lowered.residual.len();
    let output_len =
        Literal::usize_unsuffixed(r + kernel.blocks.iter().map(|b| b.entries.len()).sum::<usize>());
    let field_sizes = field_sizes(kernel);
    let tangents: Vec<Literal> = kernel
        .blocks
        .iter()
        .map(|b| Literal::usize_unsuffixed(b.variable.tangent_dim))
        .collect();
    let residual = Literal::usize_unsuffixed(r);
    let arrays = field_arrays(parts);
    let jacobians = jacobian_idents(kernel);
    let mut chunks = vec![(format_ident!("residual"), r)];
    chunks.extend(
        jacobians
            .iter()
            .zip(&kernel.blocks)
            .map(|(d, b)| (d.clone(), b.entries.len())),
    );
    let splits = split_outputs(&format_ident!("outputs"), &chunks);
    let blocks = format_ident!("blocks");
    let requested = (0..jacobians.len()).map(|k| flag(&blocks, k));
    let normal_impl = parts.normal.map(|(normal, _)| {
        let normal_fn = format_ident!("{}_normal", parts.spec.name);
        let outputs = super::normal::output_idents(kernel);
        let chunks: Vec<(Ident, usize)> = outputs
            .iter()
            .zip(&normal.blocks)
            .map(|(o, b)| (o.clone(), b.len()))
            .collect();
        let normal_len = Literal::usize_unsuffixed(1 + chunks.iter().map(|c| c.1).sum::<usize>());
        let splits = split_outputs(&format_ident!("rest"), &chunks);
        let free = format_ident!("free");
        let n = kernel.blocks.len();
        let flags: Vec<Ident> = (0..n).map(|k| format_ident!("free_{}", k)).collect();
        let flag_values = (0..n).map(|k| flag(&free, k));
        let gradient_wanted = flags.iter().map(|f| quote!(#f));
        let hessian_wanted = crate::normal::pairs(n).into_iter().map(|(i, j)| {
            let (a, b) = (&flags[i], &flags[j]);
            if i == j { quote!(#a) } else { quote!((#a && #b)) }
        });
        let wanted: Vec<TokenStream> = gradient_wanted.chain(hessian_wanted).collect();
        let arrays = &arrays;
        quote! {
            #[cfg(feature = "lanes")]
            impl<T: Real> factor_lanes::NormalKernel<T> for Kernel {
                type NormalOutputs = [T; #normal_len];

                #[inline(always)]
                fn normal(inputs: &[T; #input_len], weight: T, outputs: &mut [T; #normal_len], free: &[bool]) {
                    #(let #flags = #flag_values;)*
                    let Some((cost, rest)) = outputs.split_first_mut() else {
                        return;
                    };
                    #(#splits)*
                    #normal_fn(
                        #(#arrays,)*
                        weight,
                        cost,
                        #(#wanted.then_some(#outputs),)*
                    );
                }
            }
        }
    });
    let doc = format!(
        " The kernels of this module as one type, for batch evaluators: with the crate's \
         `lanes` feature a `factor_lanes::Kernel`{} over every `T: Real`, which calls \
         [`{}`]{} inlined.",
        if parts.normal.is_some() {
            " and `factor_lanes::NormalKernel`"
        } else {
            ""
        },
        parts.spec.name,
        if parts.normal.is_some() {
            format!(" and [`{}_normal`]", parts.spec.name)
        } else {
            String::new()
        },
    );
    quote! {
        #[doc = #doc]
        #[derive(Debug, Clone, Copy, Default)]
        pub struct Kernel;

        #[cfg(feature = "lanes")]
        impl<T: Real> factor_lanes::Kernel<T> for Kernel {
            type Inputs = [T; #input_len];
            type Outputs = [T; #output_len];
            const FIELDS: &'static [usize] = &[#(#field_sizes),*];
            const RESIDUAL: usize = #residual;
            const TANGENTS: &'static [usize] = &[#(#tangents),*];

            #[inline(always)]
            fn linearize(inputs: &[T; #input_len], outputs: &mut [T; #output_len], blocks: &[bool]) {
                #(#splits)*
                #name(
                    #(#arrays,)*
                    residual,
                    #(#requested.then_some(#jacobians),)*
                );
            }
        }

        #normal_impl
    }
}
