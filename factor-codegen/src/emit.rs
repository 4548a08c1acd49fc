//! One generated module as Rust tokens, formatted by `prettyplease`.
//!
//! The module holds the kernel,
//! `pub fn <name><T: Real>(<field>: &[T; N], …, residual: &mut [T; R],
//! d_<variable>: Option<&mut [T; R·D]>, …)`, fields in declaration order and
//! Jacobians row-major; `SHAPE`, the array lengths it was generated for
//! (which `#[derive(Factor)]` compares with the factor at compile time); and
//! `<name>_slices`, the kernel over slices, which checks their lengths
//! against `SHAPE` (the entry point of the derive and of solvers, whose
//! parameter blocks are slices). The kernel's body is the [`Schedule`]: one `let` per
//! instruction, inputs read in place (`pose[3]`) and literals written
//! `T::constant(2.0)` with round-trip precision, the residual stored after
//! the unconditional statements, statements shared by several blocks inside
//! `if d_a.is_some() || d_b.is_some() { … }`, and each block's own
//! statements and stores inside `if let Some(d_a) = d_a { … }`.

use std::collections::HashMap;

use proc_macro2::{Ident, Literal, Span, TokenStream};
use quote::{format_ident, quote};

use crate::error::CodegenError;
use crate::ir::{Instr, OpCounts, Value};
use crate::kernel::{JacobianForm, SymbolicKernel};
use crate::lower::LoweredKernel;
use crate::schedule::{Group, Schedule};
use crate::spec::{KernelSpec, Provenance};

/// Lints the generated code trips by construction: one argument per field,
/// literals such as `3.141592653589793` that are not meant as `π`, and a
/// shared group exporting the value its last statement computes.
fn module_allows() -> TokenStream {
    quote! {
        #![allow(clippy::too_many_arguments, clippy::approx_constant, clippy::let_and_return)]
    }
}

/// Where input scalar `i` is read: field `.0`, element `.1`.
fn input_slots(kernel: &SymbolicKernel) -> Vec<(Ident, usize)> {
    let mut slots = Vec::with_capacity(kernel.input_len());
    for field in &kernel.fields {
        let ident = format_ident!("{}", field.name);
        slots.extend((0..field.scalars).map(|k| (ident.clone(), k)));
    }
    slots
}

/// `T::constant(c)` with `c` printed so that it parses back to the same `f64`.
fn literal(c: f64) -> TokenStream {
    if c.is_nan() {
        return quote!(T::constant(f64::NAN));
    }
    if c.is_infinite() {
        return if c > 0.0 {
            quote!(T::constant(f64::INFINITY))
        } else {
            quote!(T::constant(f64::NEG_INFINITY))
        };
    }
    let lit = syn::LitFloat::new(&format!("{:?}", c.abs()), Span::call_site());
    if c < 0.0 {
        quote!(T::constant(-#lit))
    } else {
        quote!(T::constant(#lit))
    }
}

/// The function body's builder: names values as they are defined.
struct Body<'a> {
    lowered: &'a LoweredKernel,
    inputs: Vec<(Ident, usize)>,
    names: HashMap<Value, Ident>,
}

impl Body<'_> {
    /// An operand: a name, an input element or a literal.
    fn operand(&self, v: Value) -> TokenStream {
        match self.lowered.instrs[v.0 as usize] {
            Instr::Input(i) => {
                let (field, k) = &self.inputs[i as usize];
                let k = Literal::usize_unsuffixed(*k);
                quote!(#field[#k])
            }
            Instr::Const(c) => literal(c.get()),
            _ => {
                let name = &self.names[&v];
                quote!(#name)
            }
        }
    }

    /// `T::f(a)`, a call of a one-argument method of `Real`.
    fn call(&self, f: &str, a: Value) -> TokenStream {
        let (f, a) = (format_ident!("{f}"), self.operand(a));
        quote!(T::#f(#a))
    }

    /// `let vN = …;`, naming `v` with the next free number.
    fn statement(&mut self, v: Value) -> TokenStream {
        let o = |body: &Self, v: Value| body.operand(v);
        let expr = match self.lowered.instrs[v.0 as usize] {
            Instr::Add(a, b) => {
                let (a, b) = (o(self, a), o(self, b));
                quote!(#a + #b)
            }
            Instr::Sub(a, b) => {
                let (a, b) = (o(self, a), o(self, b));
                quote!(#a - #b)
            }
            Instr::Mul(a, b) => {
                let (a, b) = (o(self, a), o(self, b));
                quote!(#a * #b)
            }
            Instr::Div(a, b) => {
                let (a, b) = (o(self, a), o(self, b));
                quote!(#a / #b)
            }
            Instr::Neg(a) => {
                let a = o(self, a);
                quote!(-#a)
            }
            Instr::Sqrt(a) => self.call("sqrt", a),
            Instr::Sin(a) => self.call("sin", a),
            Instr::Cos(a) => self.call("cos", a),
            Instr::Exp(a) => self.call("exp", a),
            Instr::Ln(a) => self.call("ln", a),
            Instr::Acos(a) => self.call("acos", a),
            Instr::Asin(a) => self.call("asin", a),
            Instr::Atan(a) => self.call("atan", a),
            Instr::Atan2(y, x) => {
                let (y, x) = (o(self, y), o(self, x));
                quote!(T::atan2(#y, #x))
            }
            Instr::Select {
                lhs,
                rhs,
                if_less,
                otherwise,
            } => {
                let (l, r) = (o(self, lhs), o(self, rhs));
                let (a, b) = (o(self, if_less), o(self, otherwise));
                quote!(T::select_lt(#l, #r, #a, #b))
            }
            Instr::Input(_) | Instr::Const(_) => unreachable!("not scheduled as statements"),
        };
        let name = format_ident!("v{}", self.names.len());
        self.names.insert(v, name.clone());
        quote!(let #name = #expr;)
    }

    fn statements(&mut self, group: &Group) -> Vec<TokenStream> {
        group.instrs.iter().map(|v| self.statement(*v)).collect()
    }

    /// `target[i] = value;` for every element.
    fn stores(&self, target: &Ident, values: &[Value]) -> Vec<TokenStream> {
        values
            .iter()
            .enumerate()
            .map(|(i, v)| {
                let (i, value) = (Literal::usize_unsuffixed(i), self.operand(*v));
                quote!(#target[#i] = #value;)
            })
            .collect()
    }
}

/// The names of the Jacobian arguments, `d_<variable>`.
pub fn jacobian_idents(kernel: &SymbolicKernel) -> Vec<Ident> {
    kernel
        .blocks
        .iter()
        .map(|b| format_ident!("d_{}", b.variable.name))
        .collect()
}

/// Rejects fields whose names would collide with the generated ones.
fn check_names(kernel: &SymbolicKernel) -> Result<(), CodegenError> {
    let jacobians: Vec<String> = jacobian_idents(kernel)
        .iter()
        .map(ToString::to_string)
        .collect();
    for field in &kernel.fields {
        let name = field.name;
        let local = name.len() > 1
            && name.starts_with('v')
            && name[1..].bytes().all(|b| b.is_ascii_digit());
        let reserved = ["residual", "T", "inputs", "blocks"];
        if local || reserved.contains(&name) || jacobians.iter().any(|j| j == name) {
            return Err(CodegenError::NameCollision {
                kernel: kernel.name,
                field: name,
            });
        }
    }
    Ok(())
}

/// The function's statements.
fn body(kernel: &SymbolicKernel, lowered: &LoweredKernel, schedule: &Schedule) -> TokenStream {
    let jacobians = jacobian_idents(kernel);
    let mut body = Body {
        lowered,
        inputs: input_slots(kernel),
        names: HashMap::new(),
    };
    let always = body.statements(&schedule.always);
    let residual = body.stores(&format_ident!("residual"), &lowered.residual);
    let shared: Vec<TokenStream> = schedule
        .shared
        .iter()
        .map(|group| {
            let statements = body.statements(group);
            let requested = group.blocks.iter().map(|k| &jacobians[*k]);
            let exports: Vec<TokenStream> =
                group.exports.iter().map(|v| body.operand(*v)).collect();
            let zeros = group.exports.iter().map(|_| literal(0.0));
            if exports.len() == 1 {
                let export = &exports[0];
                quote! {
                    let #export = if #(#requested.is_some())||* {
                        #(#statements)*
                        #export
                    } else {
                        T::constant(0.0)
                    };
                }
            } else {
                quote! {
                    let (#(#exports),*) = if #(#requested.is_some())||* {
                        #(#statements)*
                        (#(#exports),*)
                    } else {
                        (#(#zeros),*)
                    };
                }
            }
        })
        .collect();
    let blocks: Vec<TokenStream> = schedule
        .single
        .iter()
        .zip(&lowered.blocks)
        .zip(&jacobians)
        .map(|((group, values), d)| {
            let statements = body.statements(group);
            let stores = body.stores(d, values);
            quote! {
                if let Some(#d) = #d {
                    #(#statements)*
                    #(#stores)*
                }
            }
        })
        .collect();
    quote! {
        #(#always)*
        #(#residual)*
        #(#shared)*
        #(#blocks)*
    }
}

/// `| add | mul | … |` rows for a header.
fn counts_table(rows: &[(&str, OpCounts)]) -> Vec<String> {
    let mut lines = vec![
        "| outputs | add | mul | div | neg | sqrt | func | branch | total |".to_string(),
        "| --- | --- | --- | --- | --- | --- | --- | --- | --- |".to_string(),
    ];
    for (label, c) in rows {
        lines.push(format!(
            "| {label} | {} | {} | {} | {} | {} | {} | {} | {} |",
            c.add,
            c.mul,
            c.div,
            c.neg,
            c.sqrt,
            c.func,
            c.branch,
            c.total()
        ));
    }
    lines
}

/// `text` ending with a full stop (unless it ends with punctuation already).
fn sentence(text: &str) -> String {
    let text = text.trim();
    match text.chars().last() {
        Some('.' | ':' | '!' | '?') | None => text.to_owned(),
        Some(_) => format!("{text}."),
    }
}

/// The module header, one line per element.
fn header(
    kernel: &SymbolicKernel,
    spec: &KernelSpec,
    provenance: &Provenance,
    lowered: &LoweredKernel,
) -> Vec<String> {
    let r = lowered.residual.len();
    let mut lines = vec![
        format!(
            "`{}`: the residual and its Jacobian blocks, generated from `{}`.",
            spec.name, spec.source_type
        ),
        String::new(),
        format!("Source: {}", sentence(spec.source)),
        String::new(),
        format!(
            "Generated by `{}`; do not edit. `{}` fails when this file differs from what the \
             factor definitions produce.",
            provenance.generate, provenance.check
        ),
        String::new(),
        "# Inputs".to_string(),
        String::new(),
        "One array per field of the factor, in declaration order, each holding the field's \
         scalars as stored:"
            .to_string(),
        String::new(),
    ];
    for field in &kernel.fields {
        let role = match field.variable {
            Some(_) => "variable",
            None => "constant",
        };
        let doc = if field.doc.is_empty() {
            String::new()
        } else {
            format!(" — {}", sentence(field.doc))
        };
        lines.push(format!(
            "- `{}: [T; {}]` ({role}): `{}`{doc}",
            field.name, field.scalars, field.layout
        ));
    }
    lines.extend([
        String::new(),
        "# Outputs".to_string(),
        String::new(),
        format!("- `residual: [T; {r}]`"),
    ]);
    for block in &kernel.blocks {
        let v = &block.variable;
        lines.push(format!(
            "- `d_{}: [T; {}]`: `∂r/∂δ` w.r.t. `{}` (`{}`), {r} × {} row-major (residual rows × \
             tangent columns); tangent: {}",
            v.name,
            r * v.tangent_dim,
            v.name,
            v.type_name,
            v.tangent_dim,
            v.tangent
        ));
    }
    lines.extend([
        String::new(),
        provenance.conventions.to_string(),
        String::new(),
        match kernel.jacobian_form {
            JacobianForm::Direct => "Jacobian entries: each differentiated as a whole (no chain \
                                     rule through an intermediate was cheaper)."
                .to_string(),
            JacobianForm::Chained { width } => format!(
                "Jacobian entries: by the chain rule through {width} intermediate values that \
                 every path from the tangents to the residual crosses, `∂r/∂δ = ∂r/∂c · ∂c/∂δ` \
                 (the cheapest of the candidate cuts and the direct form)."
            ),
        },
        String::new(),
        "# Operation counts".to_string(),
        String::new(),
        "Every arithmetic instruction counts one (inputs and literals are free); `func` is \
         a math-library call (`sin`, `cos`, `atan2`, `exp`, `ln`, `acos`, `asin`, `atan`), \
         `branch` a `select_lt`."
            .to_string(),
        String::new(),
    ]);
    let mut rows = vec![("all", lowered.counts(&lowered.outputs()))];
    rows.push(("residual only", lowered.counts(&lowered.residual)));
    lines.extend(counts_table(&rows));
    lines
}

/// The formatted source of one module; its header names `provenance`'s
/// commands and conventions.
pub fn module_source(
    kernel: &SymbolicKernel,
    spec: &KernelSpec,
    provenance: &Provenance,
    lowered: &LoweredKernel,
    schedule: &Schedule,
) -> Result<String, CodegenError> {
    check_names(kernel)?;
    let name = format_ident!("{}", spec.name);
    let r = Literal::usize_unsuffixed(lowered.residual.len());
    let header = header(kernel, spec, provenance, lowered)
        .into_iter()
        .map(|line| {
            if line.is_empty() {
                line
            } else {
                format!(" {line}")
            }
        });
    let fields: Vec<Ident> = kernel
        .fields
        .iter()
        .map(|f| format_ident!("{}", f.name))
        .collect();
    let sizes = kernel
        .fields
        .iter()
        .map(|f| Literal::usize_unsuffixed(f.scalars));
    let jacobians = jacobian_idents(kernel);
    let jacobian_sizes = kernel
        .blocks
        .iter()
        .map(|b| Literal::usize_unsuffixed(b.entries.len()));
    let read: Vec<bool> = {
        let mut read = vec![false; kernel.fields.len()];
        let field_of: Vec<usize> = kernel
            .fields
            .iter()
            .enumerate()
            .flat_map(|(k, f)| std::iter::repeat_n(k, f.scalars))
            .collect();
        let live = lowered.live(&lowered.outputs());
        for (instr, live) in lowered.instrs.iter().zip(live) {
            if let (Instr::Input(i), true) = (instr, live) {
                read[field_of[*i as usize]] = true;
            }
        }
        read
    };
    let unused = read
        .iter()
        .any(|r| !r)
        .then(|| quote!(#[allow(unused_variables)]));
    let mut doc = vec![format!(
        " The residual of `{}` and, for each `Some` Jacobian argument, its block.",
        spec.source_type
    )];
    doc.push(String::new());
    doc.push(
        " Work needed only by Jacobian blocks passed as `None` is skipped. See the module \
         documentation for the input layouts and the tangents."
            .to_string(),
    );
    let body = body(kernel, lowered, schedule);
    let allows = module_allows();
    let shape = shape_const(kernel, lowered);
    let slices = slices_fn(kernel, spec, lowered);
    let tokens = quote! {
        #(#![doc = #header])*
        #allows

        use crate::{Real, Shape};

        #(#[doc = #doc])*
        #unused
        #[inline]
        pub fn #name<T: Real>(
            #(#fields: &[T; #sizes],)*
            residual: &mut [T; #r],
            #(#jacobians: Option<&mut [T; #jacobian_sizes]>,)*
        ) {
            #body
        }

        #shape

        #slices
    };
    // prettyplease puts no blank lines between the header, the lints, the
    // imports and the items; one each reads better.
    Ok(format_tokens(tokens)
        .replacen("\n#![allow(", "\n\n#![allow(", 1)
        .replacen(
            "]\nuse crate::{Real, Shape};\n",
            "]\n\nuse crate::{Real, Shape};\n\n",
            1,
        )
        .replace("\n}\n/// ", "\n}\n\n/// ")
        .replace("\n};\n/// ", "\n};\n\n/// "))
}

/// `pub const SHAPE: Shape`: the array lengths the kernel takes.
fn shape_const(kernel: &SymbolicKernel, lowered: &LoweredKernel) -> TokenStream {
    let inputs = kernel
        .fields
        .iter()
        .map(|f| Literal::usize_unsuffixed(f.scalars));
    let residual = Literal::usize_unsuffixed(lowered.residual.len());
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
fn slices_fn(kernel: &SymbolicKernel, spec: &KernelSpec, lowered: &LoweredKernel) -> TokenStream {
    let name = format_ident!("{}", spec.name);
    let slices = format_ident!("{}_slices", spec.name);
    let fields: Vec<Ident> = kernel
        .fields
        .iter()
        .map(|f| format_ident!("{}", f.name))
        .collect();
    let sizes = kernel
        .fields
        .iter()
        .map(|f| Literal::usize_unsuffixed(f.scalars));
    let jacobians = jacobian_idents(kernel);
    let jacobian_sizes = kernel
        .blocks
        .iter()
        .map(|b| Literal::usize_unsuffixed(b.entries.len()));
    let r = Literal::usize_unsuffixed(lowered.residual.len());
    let doc = format!(
        " [`{0}`] over slices: `inputs` holds one slice per field, `blocks` one \
         entry per variable (`None` for a block not wanted). Returns `false`, computing \
         nothing, when the number or the length of a slice differs from [`SHAPE`].",
        spec.name
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

/// Parses `tokens` as a file and pretty-prints it.
///
/// # Panics
///
/// If the tokens are not a valid file (a bug of the emitter).
pub fn format_tokens(tokens: TokenStream) -> String {
    let file: syn::File = syn::parse2(tokens).expect("the emitter produces a valid Rust file");
    prettyplease::unparse(&file)
}
