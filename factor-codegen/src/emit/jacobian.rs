//! The residual-and-Jacobian kernel, its `SHAPE` and its slice entry.

use proc_macro2::{Ident, Literal, TokenStream};
use quote::{format_ident, quote};

use super::body::{Signature, body};
use super::{ModuleParts, field_idents, field_inputs, field_sizes, jacobian_idents};
use crate::lower::LoweredKernel;

/// `#[allow(unused_variables)]` when some field is not read by `lowered`.
pub fn allow_unused_fields(parts: &ModuleParts, lowered: &LoweredKernel) -> Option<TokenStream> {
    fields_read(parts, lowered)
        .iter()
        .any(|r| !r)
        .then(|| quote!(#[allow(unused_variables)]))
}

/// Whether each field is read by the instructions `outputs` need, in
/// declaration order.
fn fields_read(parts: &ModuleParts, lowered: &LoweredKernel) -> Vec<bool> {
    let kernel = parts.kernel;
    let field_of: Vec<usize> = kernel
        .fields
        .iter()
        .enumerate()
        .flat_map(|(k, f)| std::iter::repeat_n(k, f.scalars))
        .collect();
    let mut read = vec![false; kernel.fields.len()];
    let live = lowered.live(&lowered.outputs());
    for (instr, live) in lowered.instrs.iter().zip(live) {
        if let (crate::ir::Instr::Input(i), true) = (instr, live)
            && let Some(&field) = field_of.get(*i as usize)
        {
            read[field] = true;
        }
    }
    read
}

/// The kernel, `SHAPE` and `<name>_slices`.
pub fn items(parts: &ModuleParts) -> TokenStream {
    let ModuleParts {
        kernel,
        spec,
        lowered,
        schedule,
        ..
    } = *parts;
    let name = format_ident!("{}", spec.name);
    let r = Literal::usize_unsuffixed(lowered.residual.len());
    let fields = field_idents(kernel);
    let sizes = field_sizes(kernel);
    let jacobians = jacobian_idents(kernel);
    let jacobian_sizes: Vec<Literal> = kernel
        .blocks
        .iter()
        .map(|b| Literal::usize_unsuffixed(b.entries.len()))
        .collect();
    let unused = allow_unused_fields(parts, lowered);
    let doc = [
        format!(
            " The residual of `{}` and, for each `Some` Jacobian argument, its block.",
            spec.source_type
        ),
        String::new(),
        " Work needed only by Jacobian blocks passed as `None` is skipped. See the module \
         documentation for the input layouts and the tangents."
            .to_string(),
    ];
    let residual_targets = (0..lowered.residual.len())
        .map(|i| {
            let i = Literal::usize_unsuffixed(i);
            quote!(residual[#i])
        })
        .collect();
    let body = body(
        lowered,
        schedule,
        &Signature {
            inputs: field_inputs(kernel),
            always: residual_targets,
            optional: &jacobians,
        },
    );
    let shape = shape_const(parts);
    let slices = slices_fn(parts, &fields, &sizes, &jacobians, &jacobian_sizes);
    quote! {
        #(#[doc = #doc])*
        #unused
        #[inline(always)]
        pub fn #name<T: Real>(
            #(#fields: &[T; #sizes],)*
            residual: &mut [T; #r],
            #(#jacobians: Option<&mut [T; #jacobian_sizes]>,)*
        ) {
            #body
        }

        #shape

        #slices
    }
}

/// `pub const SHAPE: Shape`: the array lengths the kernel takes.
fn shape_const(parts: &ModuleParts) -> TokenStream {
    let kernel = parts.kernel;
    let inputs = kernel
        .fields
        .iter()
        .map(|f| Literal::usize_unsuffixed(f.scalars));
    let residual = Literal::usize_unsuffixed(parts.lowered.residual.len());
    let blocks = kernel
        .blocks
        .iter()
        .map(|b| Literal::usize_unsuffixed(b.entries.len()));
    quote! {
        /// The lengths of the kernel's arrays: each field's stored scalars, the
        /// residual, each Jacobian block (row-major).
        pub const SHAPE: Shape = Shape {
            inputs: &[#(#inputs),*],
            residual: #residual,
            blocks: &[#(#blocks),*],
        };
    }
}

/// `pub fn <name>_slices`: the kernel over slices, lengths checked.
fn slices_fn(
    parts: &ModuleParts,
    fields: &[Ident],
    sizes: &[Literal],
    jacobians: &[Ident],
    jacobian_sizes: &[Literal],
) -> TokenStream {
    let name = format_ident!("{}", parts.spec.name);
    let slices = format_ident!("{}_slices", parts.spec.name);
    let r = Literal::usize_unsuffixed(parts.lowered.residual.len());
    let doc = format!(
        " [`{0}`] over slices: `inputs` holds one slice per field, `blocks` one \
         entry per variable (`None` for a block not wanted). Returns `false`, computing \
         nothing, when the number or the length of a slice differs from [`SHAPE`].",
        parts.spec.name
    );
    quote! {
        #[doc = #doc]
        #[inline]
        pub fn #slices<T: Real>(
            inputs: &[&[T]],
            residual: &mut [T],
            blocks: &mut [Option<&mut [T]>],
        ) -> bool {
            let [#(#fields),*] = inputs else {
                return false;
            };
            let (#(Ok(#fields),)* Ok(residual)) = (
                #(<&[T; #sizes]>::try_from(*#fields),)*
                <&mut [T; #r]>::try_from(residual),
            ) else {
                return false;
            };
            let [#(#jacobians),*] = blocks else {
                return false;
            };
            #(
                let #jacobians = match #jacobians.as_deref_mut().map(<&mut [T; #jacobian_sizes]>::try_from) {
                    None => None,
                    Some(Ok(block)) => Some(block),
                    Some(Err(_)) => return false,
                };
            )*
            self::#name(#(#fields,)* residual, #(#jacobians),*);
            true
        }
    }
}
