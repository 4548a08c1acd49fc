//! A kernel's function body from its [`Schedule`]: one `let` per
//! instruction, inputs read where they are used and literals written
//! `T::constant(2.0)` with round-trip precision; the unconditional outputs
//! stored after the unconditional statements, statements shared by several
//! optional outputs inside `if a.is_some() || b.is_some() { … }`, and each
//! optional output's own statements and stores inside
//! `if let Some(a) = a { … }`.

use std::collections::HashMap;

use proc_macro2::{Ident, Literal, Span, TokenStream};
use quote::{format_ident, quote};

use crate::ir::{Instr, Value};
use crate::lower::LoweredKernel;
use crate::schedule::{Group, Schedule};

/// `T::constant(c)` with `c` printed so that it parses back to the same `f64`.
pub fn literal(c: f64) -> TokenStream {
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

/// What a body reads and writes.
pub struct Signature<'a> {
    /// How input `i` is read (`pose[3]`, `weight`).
    pub inputs: Vec<TokenStream>,
    /// Where each unconditional output (the program's `residual` values) is
    /// stored (`residual[0]`, `*cost`).
    pub always: Vec<TokenStream>,
    /// The optional outputs (the program's `blocks`), each an
    /// `Option<&mut [T; N]>` argument.
    pub optional: &'a [Ident],
}

/// The function body's builder: names values as they are defined.
struct Body<'a> {
    lowered: &'a LoweredKernel,
    inputs: &'a [TokenStream],
    names: HashMap<Value, Ident>,
}

impl Body<'_> {
    /// An operand: a name, an input or a literal.
    fn operand(&self, v: Value) -> TokenStream {
        match self.lowered.instrs[v.0 as usize] {
            Instr::Input(i) => self.inputs[i as usize].clone(),
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

/// The statements of `lowered` in the order of `schedule`, reading and
/// writing as `signature` says.
pub fn body(lowered: &LoweredKernel, schedule: &Schedule, signature: &Signature) -> TokenStream {
    let optional = signature.optional;
    let mut body = Body {
        lowered,
        inputs: &signature.inputs,
        names: HashMap::new(),
    };
    let always = body.statements(&schedule.always);
    let always_stores: Vec<TokenStream> = signature
        .always
        .iter()
        .zip(&lowered.residual)
        .map(|(target, v)| {
            let value = body.operand(*v);
            quote!(#target = #value;)
        })
        .collect();
    let shared: Vec<TokenStream> = schedule
        .shared
        .iter()
        .map(|group| {
            let statements = body.statements(group);
            let requested = group.blocks.iter().map(|k| &optional[*k]);
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
        .zip(optional)
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
        #(#always_stores)*
        #(#shared)*
        #(#blocks)*
    }
}
