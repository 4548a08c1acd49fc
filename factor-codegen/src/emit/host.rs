//! The kernels in host solvers' charts (`<name>_<host>`, [`crate::host`]):
//! the factor's inputs with each variable as its host parts' parameter
//! arrays, one column-major block per host part.

use proc_macro2::TokenStream;
use quote::format_ident;

use super::jacobian::{KernelFunction, function_items};
use crate::host::HostTrace;
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

/// `<name>_<host>`, `SHAPE_<HOST>` and `<name>_<host>_slices`.
pub fn items(name: &str, source_type: &str, host: &HostParts) -> TokenStream {
    let trace = host.trace;
    function_items(&KernelFunction {
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
    })
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
            let role = if input.variable {
                "variable"
            } else {
                "constant"
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
