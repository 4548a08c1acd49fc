//! One generated module as Rust tokens, formatted by `prettyplease`.
//!
//! The module holds, in order:
//!
//! - the kernel (module `jacobian`),
//!   `pub fn <name><T: Real>(<field>: &[T; N], …, residual: &mut [T; R],
//!   d_<variable>: Option<&mut [T; R·D]>, …)`, fields in declaration order
//!   and Jacobians row-major; `SHAPE`, the array lengths it was generated
//!   for (which `#[derive(Factor)]` compares with the factor at compile
//!   time); and `<name>_slices`, the kernel over slices, which checks their
//!   lengths against `SHAPE` (the entry point of the derive and of solvers,
//!   whose parameter blocks are slices);
//! - when the spec asks for it, the fused normal-equation kernel
//!   (module `normal`), `<name>_normal`, with `NORMAL_SHAPE` and
//!   `<name>_normal_slices`;
//! - the marker type `Kernel` and, behind the crate's `lanes` feature, its
//!   `factor_lanes` trait implementations (module `lanes`).
//!
//! Each function's body is its [`crate::schedule::Schedule`] (module `body`).
//! The module header (module `header`) documents all of it.

mod body;
pub(crate) mod header;
mod host;
mod jacobian;
mod lanes;
mod normal;

use proc_macro2::{Ident, Literal, TokenStream};
use quote::{format_ident, quote};

use crate::error::CodegenError;
use crate::kernel::SymbolicKernel;
use crate::lower::LoweredKernel;
use crate::schedule::Schedule;
use crate::spec::{KernelSpec, Provenance};

pub use host::HostParts;

/// What one module is emitted from.
#[derive(Clone, Copy)]
pub struct ModuleParts<'a> {
    /// The traced factor.
    pub kernel: &'a SymbolicKernel,
    /// What to generate.
    pub spec: &'a KernelSpec,
    /// The generator the header names.
    pub provenance: &'a Provenance,
    /// The residual-and-Jacobian program.
    pub lowered: &'a LoweredKernel,
    /// Its schedule.
    pub schedule: &'a Schedule,
    /// The normal-equation program ([`crate::normal`]) and its schedule,
    /// when the spec asks for it.
    pub normal: Option<(&'a LoweredKernel, &'a Schedule)>,
    /// The kernels in host charts ([`crate::host`]).
    pub hosts: &'a [HostParts<'a>],
}

/// Lints the generated code trips by construction: one argument per field,
/// literals such as `3.141592653589793` that are not meant as `π`, and a
/// shared group exporting the value its last statement computes.
fn module_allows() -> TokenStream {
    quote! {
        #![allow(clippy::too_many_arguments, clippy::approx_constant, clippy::let_and_return)]
    }
}

/// How each input scalar is read by a function taking one array per field:
/// `pose[3]`.
fn field_inputs(kernel: &SymbolicKernel) -> Vec<TokenStream> {
    let sizes: Vec<usize> = kernel.fields.iter().map(|f| f.scalars).collect();
    indexed_inputs(&field_idents(kernel), &sizes)
}

/// How each input scalar is read by a function taking the arrays `names`
/// of `sizes` scalars: `pose[3]`.
fn indexed_inputs(names: &[Ident], sizes: &[usize]) -> Vec<TokenStream> {
    names
        .iter()
        .zip(sizes)
        .flat_map(|(ident, n)| {
            (0..*n).map(move |k| {
                let k = Literal::usize_unsuffixed(k);
                quote!(#ident[#k])
            })
        })
        .collect()
}

/// The fields' names, in declaration order.
fn field_idents(kernel: &SymbolicKernel) -> Vec<Ident> {
    kernel
        .fields
        .iter()
        .map(|f| format_ident!("{}", f.name))
        .collect()
}

/// The fields' scalar counts as literals, in declaration order.
fn field_sizes(kernel: &SymbolicKernel) -> Vec<Literal> {
    kernel
        .fields
        .iter()
        .map(|f| Literal::usize_unsuffixed(f.scalars))
        .collect()
}

/// The names of the Jacobian arguments, `d_<variable>`.
pub fn jacobian_idents(kernel: &SymbolicKernel) -> Vec<Ident> {
    kernel
        .blocks
        .iter()
        .map(|b| format_ident!("d_{}", b.variable.name))
        .collect()
}

/// Rejects fields whose names would collide with the generated ones: those
/// of the kernel, and with `normal` those of the normal-equation kernel.
fn check_names(kernel: &SymbolicKernel, normal: bool) -> Result<(), CodegenError> {
    let mut taken: Vec<String> = jacobian_idents(kernel)
        .iter()
        .map(ToString::to_string)
        .collect();
    let mut reserved = vec!["residual", "T", "inputs", "blocks"];
    if normal {
        taken.extend(
            normal::output_idents(kernel)
                .iter()
                .map(ToString::to_string),
        );
        reserved.extend(["weight", "cost", "gradient", "hessian"]);
    }
    for field in &kernel.fields {
        let name = field.name;
        let local = name.len() > 1
            && name.starts_with('v')
            && name[1..].bytes().all(|b| b.is_ascii_digit());
        if local || reserved.contains(&name) || taken.iter().any(|j| j == name) {
            return Err(CodegenError::NameCollision {
                kernel: kernel.name,
                field: name,
            });
        }
    }
    Ok(())
}

/// The formatted source of one module; its header names the provenance's
/// commands and conventions.
///
/// # Errors
///
/// [`CodegenError::NameCollision`] when a field's name is one the module
/// uses for itself.
pub fn module_source(parts: &ModuleParts) -> Result<String, CodegenError> {
    check_names(parts.kernel, parts.normal.is_some())?;
    let header = header::header(parts).into_iter().map(|line| {
        if line.is_empty() {
            line
        } else {
            format!(" {line}")
        }
    });
    let allows = module_allows();
    let jacobian = jacobian::items(parts);
    let normal = parts
        .normal
        .map(|(lowered, schedule)| normal::items(parts, lowered, schedule));
    let normal_shape = normal.as_ref().map(|_| quote!(, NormalShape));
    let hosts = parts
        .hosts
        .iter()
        .map(|h| host::items(parts.spec.name, parts.spec.source_type, h));
    let lanes = lanes::items(parts);
    let tokens = quote! {
        #(#![doc = #header])*
        #allows

        use crate::{Real, Shape #normal_shape};

        #jacobian
        #normal
        #(#hosts)*
        #lanes
    };
    // prettyplease puts no blank lines between the header, the lints, the
    // imports and the items; one each reads better.
    let imports = match normal_shape {
        Some(_) => "use crate::{Real, Shape, NormalShape};",
        None => "use crate::{Real, Shape};",
    };
    Ok(format_tokens(tokens)
        .replacen("\n#![allow(", "\n\n#![allow(", 1)
        .replacen(
            &format!("]\n{imports}\n"),
            &format!("]\n\n{imports}\n\n"),
            1,
        )
        .replace("\n}\n/// ", "\n}\n\n/// ")
        .replace("\n};\n/// ", "\n};\n\n/// ")
        .replace("\n}\n#[cfg(", "\n}\n\n#[cfg(")
        .replace(";\n#[cfg(", ";\n\n#[cfg("))
}

/// Parses `tokens` as a file and pretty-prints it.
///
/// # Panics
///
/// If the tokens are not a valid file (a bug of the emitter).
pub fn format_tokens(tokens: TokenStream) -> String {
    let file: syn::File = syn::parse2(tokens).expect("the emitter produces a valid Rust file");
    prettyplease::unparse(&file)
}
