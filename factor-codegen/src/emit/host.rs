//! The kernels in host solvers' charts (`<name>_<host>`, [`crate::host`]):
//! the factor's inputs with each variable as its host parts' parameter
//! arrays, one column-major block per host part.

use proc_macro2::{Literal, TokenStream};
use quote::{format_ident, quote};

use super::jacobian::{KernelFunction, function_and_shape};
use crate::host::{HostSource, HostTrace};
use crate::lower::LoweredKernel;
use crate::schedule::Schedule;

/// One host kernel to emit.
pub struct HostParts<'a> {
    /// The trace in the host's chart.
    pub trace: &'a HostTrace,
    /// Its program.
    pub lowered: &'a LoweredKernel,
    /// Its schedule.
    pub schedule: &'a Schedule,
}

/// `<name>_<host>`, `SHAPE_<HOST>` and `<name>_<host>_host`.
pub fn items(name: &str, source_type: &str, host: &HostParts) -> TokenStream {
    let trace = host.trace;
    let function = function_and_shape(&KernelFunction {
        name: format_ident!("{name}_{}", trace.host),
        shape: format_ident!("SHAPE_{}", trace.host.to_uppercase()),
        doc: vec![
            format!(
                " The residual of `{source_type}` and, for each `Some` block argument, its \
                 column-major block in {}'s chart, from the host's parameter arrays.",
                trace.solver
            ),
            String::new(),
            " Consecutive blocks tile the host's column-major Jacobian. See the module \
             documentation (\"Host charts\") for the inputs and the tangents."
                .to_string(),
        ],
        shape_doc: format!(
            " The lengths of [`{name}_{}`]'s arrays: each input, the residual, each block \
             (column-major).",
            trace.host
        ),
        inputs: trace
            .inputs
            .iter()
            .map(|i| (format_ident!("{}", i.name), i.scalars))
            .collect(),
        blocks: trace
            .blocks
            .iter()
            .map(|b| {
                (
                    format_ident!("{}", b.name),
                    host.lowered.residual.len() * b.columns,
                )
            })
            .collect(),
        kernel: &trace.kernel,
        lowered: host.lowered,
        schedule: host.schedule,
    });
    let entry = host_entry(name, host);
    quote! {
        #function

        #entry
    }
}

/// `pub fn <name>_<host>_host(stored, parts, residual, jacobian) -> bool`:
/// the kernel over what a solver holds (the factor's stored scalars, one
/// parameter slice per host part, the whole column-major Jacobian), lengths
/// checked.
fn host_entry(name: &str, host: &HostParts) -> TokenStream {
    let trace = host.trace;
    let function = format_ident!("{name}_{}", trace.host);
    let entry = format_ident!("{name}_{}_host", trace.host);
    let rows = host.lowered.residual.len();
    let r = Literal::usize_unsuffixed(rows);
    let stored = Literal::usize_unsuffixed(trace.stored);
    let parts: Vec<_> = (0..trace.blocks.len())
        .map(|k| format_ident!("part_{k}"))
        .collect();
    let inputs: Vec<TokenStream> = trace
        .inputs
        .iter()
        .map(|input| {
            let n = Literal::usize_unsuffixed(input.scalars);
            match &input.source {
                HostSource::Stored(range) => {
                    let (a, b) = (
                        Literal::usize_unsuffixed(range.start),
                        Literal::usize_unsuffixed(range.end),
                    );
                    quote!(<&[T; #n]>::try_from(&stored[#a..#b]))
                }
                HostSource::Part(k) => {
                    let part = &parts[*k];
                    quote!(<&[T; #n]>::try_from(*#part))
                }
            }
        })
        .collect();
    let names: Vec<_> = (0..inputs.len())
        .map(|k| format_ident!("input_{k}"))
        .collect();
    let blocks: Vec<_> = trace
        .blocks
        .iter()
        .map(|b| format_ident!("{}", b.name))
        .collect();
    let sizes: Vec<Literal> = trace
        .blocks
        .iter()
        .map(|b| Literal::usize_unsuffixed(rows * b.columns))
        .collect();
    let total = Literal::usize_unsuffixed(trace.blocks.iter().map(|b| rows * b.columns).sum());
    let nones = blocks.iter().map(|_| quote!(None));
    let doc = format!(
        " [`{function}`] over what a solver holds: `stored`, the factor's {} stored scalars \
         (its constants are read, its variables' are not), `parts`, one parameter slice per \
         host part, and `jacobian`, the whole column-major Jacobian ({rows} rows, the parts' \
         columns in order) or `None`. Returns `false`, computing nothing, when a length \
         differs from [`SHAPE_{}`].",
        trace.stored,
        trace.host.to_uppercase()
    );
    quote! {
        #[doc = #doc]
        #[inline]
        pub fn #entry<T: Real>(
            stored: &[T],
            parts: &[&[T]],
            residual: &mut [T],
            jacobian: Option<&mut [T]>,
        ) -> bool {
            let ([#(#parts),*], #stored) = (parts, stored.len()) else {
                return false;
            };
            let (#(Ok(#names),)* Ok(residual)) = (
                #(#inputs,)*
                <&mut [T; #r]>::try_from(residual),
            ) else {
                return false;
            };
            match jacobian.map(<&mut [T; #total]>::try_from) {
                None => self::#function(#(#names,)* residual, #(#nones),*),
                Some(Ok(jacobian)) => {
                    let rest = &mut jacobian[..];
                    #(
                        let Some((#blocks, rest)) = rest.split_first_chunk_mut::<#sizes>() else {
                            return false;
                        };
                    )*
                    let _ = rest;
                    self::#function(#(#names,)* residual, #(Some(#blocks)),*)
                }
                Some(Err(_)) => return false,
            }
            true
        }
    }
}

/// The header's section on the host kernels.
pub fn header_section(name: &str, hosts: &[HostParts]) -> Vec<String> {
    let mut lines = Vec::new();
    if hosts.is_empty() {
        return lines;
    }
    lines.extend([
        String::new(),
        "# Host charts".to_string(),
        String::new(),
        "The same residual in a host solver's chart and parameter layout: each variable is its \
         host parts' parameter arrays (as the host stores them), each block the derivative \
         w.r.t. one host part's tangent under the host's own retraction, column-major (residual \
         rows × the part's columns, column after column), so that consecutive blocks tile the \
         host's column-major Jacobian. Exact whatever chart the factor was written in (no \
         adjoint at run time)."
            .to_string(),
    ]);
    for host in hosts {
        let trace = host.trace;
        let r = host.lowered.residual.len();
        lines.extend([
            String::new(),
            format!("`{name}_{}` ({}):", trace.host, trace.solver),
            String::new(),
        ]);
        for input in &trace.inputs {
            let role = match input.source {
                HostSource::Part(_) => "variable",
                HostSource::Stored(_) => "constant",
            };
            lines.push(format!(
                "- `{}: [T; {}]` ({role}): {}",
                input.name, input.scalars, input.holds
            ));
        }
        lines.push(format!("- `residual: [T; {r}]`"));
        for block in &trace.blocks {
            lines.push(format!(
                "- `{}: [T; {}]`: {r} × {} column-major, {}; tangent: {}",
                block.name,
                r * block.columns,
                block.columns,
                block.manifold,
                block.tangent
            ));
        }
    }
    lines
}
