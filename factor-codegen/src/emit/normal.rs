//! The fused normal-equation kernel ([`crate::normal`]), its `NORMAL_SHAPE`
//! and its slice entry.

use proc_macro2::{Ident, Literal, TokenStream};
use quote::{format_ident, quote};

use super::body::{Signature, body};
use super::jacobian::allow_unused_fields;
use super::{ModuleParts, field_idents, field_inputs, field_sizes};
use crate::kernel::SymbolicKernel;
use crate::lower::LoweredKernel;
use crate::normal::pairs;
use crate::schedule::Schedule;

/// The optional outputs' names: `g_<variable>` in variable order, then
/// `h_<a>_<b>` in Hessian block order.
pub fn output_idents(kernel: &SymbolicKernel) -> Vec<Ident> {
    let names: Vec<&str> = kernel.blocks.iter().map(|b| b.variable.name).collect();
    let mut idents: Vec<Ident> = names.iter().map(|v| format_ident!("g_{v}")).collect();
    idents.extend(
        pairs(names.len())
            .into_iter()
            .map(|(i, j)| format_ident!("h_{}_{}", names[i], names[j])),
    );
    idents
}

/// The normal-equation kernel, `NORMAL_SHAPE` and `<name>_normal_slices`.
pub fn items(parts: &ModuleParts, lowered: &LoweredKernel, schedule: &Schedule) -> TokenStream {
    let kernel = parts.kernel;
    let normal = format_ident!("{}_normal", parts.spec.name);
    let normal_slices = format_ident!("{}_normal_slices", parts.spec.name);
    let fields = field_idents(kernel);
    let sizes = field_sizes(kernel);
    let outputs = output_idents(kernel);
    let output_sizes: Vec<Literal> = lowered
        .blocks
        .iter()
        .map(|b| Literal::usize_unsuffixed(b.len()))
        .collect();
    let unused = allow_unused_fields(parts, lowered);
    let doc = format!(
        " The cost `½ w rᵀr` of `{}` with weight `w = weight` and, for each `Some` argument, \
         its block of the normal equations: the gradient blocks `g_v = J_vᵀ w r` and the \
         blocks `h_a_b = J_aᵀ w J_b` of the Gauss–Newton matrix's upper triangle (a diagonal \
         block as its upper triangle, row by row). The same inputs as [`{}`]; see the module \
         documentation for the layouts.",
        parts.spec.source_type, parts.spec.name
    );
    let mut inputs = field_inputs(kernel);
    inputs.push(quote!(weight));
    let body = body(
        lowered,
        schedule,
        &Signature {
            inputs,
            always: vec![quote!(*cost)],
            optional: &outputs,
        },
    );
    let variables = kernel.blocks.len();
    let (gradient, hessian) = outputs.split_at(variables);
    let (gradient_sizes, hessian_sizes) = output_sizes.split_at(variables);
    let slices_doc = format!(
        " [`{normal}`] over slices: `inputs` holds one slice per field, `gradient` one entry \
         per variable and `hessian` one per pair of variables `a ≤ b` in the order of \
         [`NORMAL_SHAPE`] (`None` for a block not wanted). Returns `false`, computing nothing, \
         when the number or the length of a slice differs from [`NORMAL_SHAPE`]."
    );
    let tangents = kernel
        .blocks
        .iter()
        .map(|b| Literal::usize_unsuffixed(b.variable.tangent_dim));
    quote! {
        #[doc = #doc]
        #unused
        #[inline(always)]
        pub fn #normal<T: Real>(
            #(#fields: &[T; #sizes],)*
            weight: T,
            cost: &mut T,
            #(#outputs: Option<&mut [T; #output_sizes]>,)*
        ) {
            #body
        }

        /// The lengths of the normal-equation kernel's arrays: each field's
        /// stored scalars, each variable's gradient block, each Hessian block.
        pub const NORMAL_SHAPE: NormalShape = NormalShape {
            inputs: &[#(#sizes),*],
            tangents: &[#(#tangents),*],
            gradient: &[#(#gradient_sizes),*],
            hessian: &[#(#hessian_sizes),*],
        };

        #[doc = #slices_doc]
        #[inline]
        pub fn #normal_slices<T: Real>(
            inputs: &[&[T]],
            weight: T,
            cost: &mut T,
            gradient: &mut [Option<&mut [T]>],
            hessian: &mut [Option<&mut [T]>],
        ) -> bool {
            let [#(#fields),*] = inputs else {
                return false;
            };
            let (#(Ok(#fields),)*) = (
                #(<&[T; #sizes]>::try_from(*#fields),)*
            ) else {
                return false;
            };
            let [#(#gradient),*] = gradient else {
                return false;
            };
            let [#(#hessian),*] = hessian else {
                return false;
            };
            #(
                let #gradient = match #gradient.as_deref_mut().map(<&mut [T; #gradient_sizes]>::try_from) {
                    None => None,
                    Some(Ok(block)) => Some(block),
                    Some(Err(_)) => return false,
                };
            )*
            #(
                let #hessian = match #hessian.as_deref_mut().map(<&mut [T; #hessian_sizes]>::try_from) {
                    None => None,
                    Some(Ok(block)) => Some(block),
                    Some(Err(_)) => return false,
                };
            )*
            self::#normal(#(#fields,)* weight, cost, #(#outputs),*);
            true
        }
    }
}
