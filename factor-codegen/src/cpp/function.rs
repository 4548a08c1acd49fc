//! One C++ function template over plain arrays: a factor's kernel (its own,
//! or the ambient one), or one map of a chart.

use std::fmt::Write;

use super::body::{Signature, body};
use crate::ir::{self, Instr};
use crate::lower::LoweredKernel;
use crate::schedule::{Schedule, schedule};

/// A function to emit.
pub struct Function<'a> {
    /// Its name.
    pub name: String,
    /// Its documentation, one `///` line each.
    pub doc: Vec<String>,
    /// The input arrays' names and lengths, in order; the program's inputs
    /// are their scalars in that order.
    pub inputs: Vec<(String, usize)>,
    /// The unconditional output array (`residual`, `out`) and its length.
    pub output: (String, usize),
    /// The optional output arrays (Jacobian blocks), `nullptr` when not
    /// wanted: their names.
    pub optional: Vec<String>,
    /// The program: its `residual` values go to `output`, its `blocks` to
    /// `optional`.
    pub lowered: &'a LoweredKernel,
}

/// Whether each input array is read by the program's live instructions.
fn inputs_read(f: &Function) -> Vec<bool> {
    let array_of: Vec<usize> = f
        .inputs
        .iter()
        .enumerate()
        .flat_map(|(k, (_, n))| std::iter::repeat_n(k, *n))
        .collect();
    let mut read = vec![false; f.inputs.len()];
    let live = ir::live(&f.lowered.instrs, &f.lowered.outputs());
    for (instr, live) in f.lowered.instrs.iter().zip(live) {
        if let (Instr::Input(i), true) = (instr, live)
            && let Some(&array) = array_of.get(*i as usize)
        {
            read[array] = true;
        }
    }
    read
}

/// `template <typename T> inline void name(const T* a, …, T* out, T* d_…)`
/// and its body, after its documentation; inputs the program does not read
/// are `[[maybe_unused]]`.
pub fn function(f: &Function) -> String {
    let schedule: Schedule = schedule(f.lowered);
    let read = inputs_read(f);
    let mut parameters: Vec<String> = f
        .inputs
        .iter()
        .zip(&read)
        .map(|((name, _), read)| {
            let unused = if *read { "" } else { "[[maybe_unused]] " };
            format!("{unused}const T* {name}")
        })
        .collect();
    parameters.push(format!("T* {}", f.output.0));
    parameters.extend(f.optional.iter().map(|name| format!("T* {name}")));
    let inputs: Vec<String> = f
        .inputs
        .iter()
        .flat_map(|(name, n)| (0..*n).map(move |k| format!("{name}[{k}]")))
        .collect();
    let always: Vec<String> = (0..f.output.1)
        .map(|k| format!("{}[{k}]", f.output.0))
        .collect();
    let mut out = String::new();
    for line in &f.doc {
        if line.is_empty() {
            out.push_str("///\n");
        } else {
            let _ = writeln!(out, "/// {line}");
        }
    }
    let _ = writeln!(
        out,
        "template <typename T>\ninline void {}({}) {{",
        f.name,
        parameters.join(", ")
    );
    out.push_str(&body(
        f.lowered,
        &schedule,
        &Signature {
            inputs: &inputs,
            always: &always,
            optional: &f.optional,
        },
    ));
    out.push_str("}\n");
    out
}
