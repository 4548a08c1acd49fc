//! The residual-and-Jacobian kernel, its `SHAPE` and its slice entry.

use proc_macro2::{Ident, Literal, TokenStream};
use quote::{format_ident, quote};

use super::body::{Signature, body};
use super::{ModuleParts, field_idents, indexed_inputs, jacobian_idents};
use crate::kernel::SymbolicKernel;
use crate::lower::LoweredKernel;
use crate::schedule::Schedule;

/// `#[allow(unused_variables)]` when some field is not read by `lowered`.
pub fn allow_unused_fields(parts: &ModuleParts, lowered: &LoweredKernel) -> Option<TokenStream> {
    allow_unused_inputs(parts.kernel, lowered)
}

/// `#[allow(unused_variables)]` when some input array of `kernel` is not
/// read by `lowered`.
pub fn allow_unused_inputs(
    kernel: &SymbolicKernel,
    lowered: &LoweredKernel,
) -> Option<TokenStream> {
    fields_read(kernel, lowered)
        .iter()
        .any(|r| !r)
        .then(|| quote!(#[allow(unused_variables)]))
}

/// Whether each field is read by the instructions `outputs` need, in
/// declaration order.
fn fields_read(kernel: &SymbolicKernel, lowered: &LoweredKernel) -> Vec<bool> {
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

/// A residual-and-Jacobian function with its shape constant and slice
/// entry: the factor's own kernel, or one in a host's layout.
pub struct KernelFunction<'a> {
    /// The function (`point_reprojection`, `point_reprojection_apex`).
    pub name: Ident,
    /// Its shape constant (`SHAPE`, `SHAPE_APEX`).
    pub shape: Ident,
    /// Its documentation, one line per element.
    pub doc: Vec<String>,
    /// The shape constant's documentation.
    pub shape_doc: String,
    /// The input arrays' names and lengths.
    pub inputs: Vec<(Ident, usize)>,
    /// The blocks' names and lengths.
    pub blocks: Vec<(Ident, usize)>,
    /// The traced kernel (for the inputs it reads).
    pub kernel: &'a SymbolicKernel,
    /// Its program.
    pub lowered: &'a LoweredKernel,
    /// Its schedule.
    pub schedule: &'a Schedule,
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
    let sizes = kernel.fields.iter().map(|f| f.scalars);
    function_items(&KernelFunction {
        name: format_ident!("{}", spec.name),
        shape: format_ident!("SHAPE"),
        doc: vec![
            format!(
                " The residual of `{}` and, for each `Some` Jacobian argument, its block.",
                spec.source_type
            ),
            String::new(),
            " Work needed only by Jacobian blocks passed as `None` is skipped. See the module \
             documentation for the input layouts and the tangents."
                .to_string(),
        ],
        shape_doc: " The lengths of the kernel's arrays: each field's stored scalars, the \
                    residual, each Jacobian block (row-major)."
            .to_string(),
        inputs: field_idents(kernel).into_iter().zip(sizes).collect(),
        blocks: jacobian_idents(kernel)
            .into_iter()
            .zip(kernel.blocks.iter().map(|b| b.entries.len()))
            .collect(),
        kernel,
        lowered,
        schedule,
    })
}

/// The function, its shape constant and its slice entry.
pub fn function_items(f: &KernelFunction) -> TokenStream {
    let function = function_and_shape(f);
    let (inputs, sizes): (Vec<Ident>, Vec<usize>) = f.inputs.iter().cloned().unzip();
    let (blocks, block_sizes): (Vec<Ident>, Vec<usize>) = f.blocks.iter().cloned().unzip();
    let literals =
        |n: &[usize]| -> Vec<Literal> { n.iter().map(|n| Literal::usize_unsuffixed(*n)).collect() };
    let slices = slices_fn(
        f,
        &inputs,
        &literals(&sizes),
        &blocks,
        &literals(&block_sizes),
    );
    quote! {
        #function

        #slices
    }
}

/// The function and its shape constant.
pub fn function_and_shape(f: &KernelFunction) -> TokenStream {
    let name = &f.name;
    let r = Literal::usize_unsuffixed(f.lowered.residual.len());
    let (inputs, sizes): (Vec<Ident>, Vec<usize>) = f.inputs.iter().cloned().unzip();
    let (blocks, block_sizes): (Vec<Ident>, Vec<usize>) = f.blocks.iter().cloned().unzip();
    let size_literals: Vec<Literal> = sizes
        .iter()
        .map(|n| Literal::usize_unsuffixed(*n))
        .collect();
    let block_literals: Vec<Literal> = block_sizes
        .iter()
        .map(|n| Literal::usize_unsuffixed(*n))
        .collect();
    let unused = allow_unused_inputs(f.kernel, f.lowered);
    let doc = &f.doc;
    let residual_targets = (0..f.lowered.residual.len())
        .map(|i| {
            let i = Literal::usize_unsuffixed(i);
            quote!(residual[#i])
        })
        .collect();
    let body = body(
        f.lowered,
        f.schedule,
        &Signature {
            inputs: indexed_inputs(&inputs, &sizes),
            always: residual_targets,
            optional: &blocks,
        },
    );
    let shape = &f.shape;
    let shape_doc = &f.shape_doc;
    quote! {
        #(#[doc = #doc])*
        #unused
        #[inline(always)]
        pub fn #name<T: Real>(
            #(#inputs: &[T; #size_literals],)*
            residual: &mut [T; #r],
            #(#blocks: Option<&mut [T; #block_literals]>,)*
        ) {
            #body
        }

        #[doc = #shape_doc]
        pub const #shape: Shape = Shape {
            inputs: &[#(#size_literals),*],
            residual: #r,
            blocks: &[#(#block_literals),*],
        };
    }
}

/// `pub fn <name>_slices`: the kernel over slices, lengths checked.
fn slices_fn(
    f: &KernelFunction,
    fields: &[Ident],
    sizes: &[Literal],
    jacobians: &[Ident],
    jacobian_sizes: &[Literal],
) -> TokenStream {
    let name = &f.name;
    let slices = format_ident!("{}_slices", name);
    let r = Literal::usize_unsuffixed(f.lowered.residual.len());
    let doc = format!(
        " [`{name}`] over slices: `inputs` holds one slice per input array, `blocks` one \
         entry per block (`None` for a block not wanted). Returns `false`, computing \
         nothing, when the number or the length of a slice differs from [`{}`].",
        f.shape
    );
    // Inlined like the kernel: a caller passing arrays of the right lengths
    // (the derive's linearizations) then checks nothing at run time and
    // keeps the outputs in registers.
    quote! {
        #[doc = #doc]
        #[inline(always)]
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
