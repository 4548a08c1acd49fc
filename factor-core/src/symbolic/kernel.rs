//! A factor traced into symbolic residual and Jacobian expressions.
//!
//! The residual is traced at the first-order retraction of every variable by
//! a symbolic stacked tangent `δ` (inputs after the factor's own scalars),
//! differentiated exactly w.r.t. each coordinate of `δ`, and `δ = 0` is
//! substituted. Only the first-order part of a retraction reaches the
//! derivative, so no retraction branch is traced; the residual's own
//! branches are kept, each arm differentiated.
//!
//! The Jacobian is formed the cheapest of several exact ways: each entry
//! differentiated as a whole, or the chain rule through one of the
//! successive minimum vertex cuts between `δ` and the residual
//! ([`crate::symbolic::cut`]), `∂r/∂δ = ∂r/∂c · ∂c/∂δ` with `∂r/∂c` shared
//! by every tangent column, as a hand derivation through the camera-frame
//! point or line does. Each candidate is compiled with the residual
//! ([`crate::symbolic::optimize::compile`]) and the one with the fewest
//! operations is kept (the direct form on a tie). On the document factors
//! this cuts the Plücker-line kernel from 378 to 268 operations and the
//! orthonormal line kernel from 493 to 393.

use std::collections::HashMap;

use crate::factor::{Factor, FieldInfo, VariableInfo};
use crate::symbolic::calculus::{derivative, substitute};
use crate::symbolic::cut::minimum_cuts;
use crate::symbolic::graph::{Expr, Graph, Tracer};
use crate::symbolic::optimize::compile;

/// One variable's Jacobian block.
#[derive(Debug, Clone)]
pub struct JacobianBlock {
    /// The variable.
    pub variable: VariableInfo,
    /// `residual_dim × tangent_dim` entries, row-major.
    pub entries: Vec<Expr>,
}

/// Residual and Jacobian expressions of a factor over its input scalars.
#[derive(Debug, Clone)]
pub struct SymbolicKernel {
    /// The factor's name.
    pub name: &'static str,
    /// The graph every expression below lives in.
    pub graph: Graph,
    /// Input fields in order; field `k` occupies the next `scalars` inputs.
    pub fields: Vec<FieldInfo>,
    /// The residual.
    pub residual: Vec<Expr>,
    /// One block per variable.
    pub blocks: Vec<JacobianBlock>,
    /// How the blocks' entries were formed.
    pub jacobian_form: JacobianForm,
}

impl SymbolicKernel {
    /// Number of input scalars.
    pub fn input_len(&self) -> usize {
        self.fields.iter().map(|f| f.scalars).sum()
    }
}

/// Traces `template`'s factor type. The values in `template` are not used,
/// only its structure: every stored scalar becomes an input. The Jacobian
/// blocks are the cheapest of the exact forms (see the module docs).
pub fn trace<F: Factor>(template: &F) -> SymbolicKernel {
    let tracer = Tracer::new();
    let fields = F::fields();
    let Traced {
        residual: traced,
        delta,
        input_len,
        at_zero,
    } = trace_at_tangent(template, &mut |_| {});
    let mut substituted = HashMap::new();
    let residual: Vec<Expr> = traced
        .iter()
        .map(|r| substitute(*r, &at_zero, &mut substituted))
        .collect();
    let (columns, jacobian_form) =
        cheapest_columns(&tracer, &traced, &residual, &delta, &at_zero, input_len);
    let mut offset = 0;
    let blocks = F::variables()
        .into_iter()
        .map(|variable| {
            let columns = &columns[offset..offset + variable.tangent_dim];
            offset += variable.tangent_dim;
            let entries = (0..traced.len())
                .flat_map(|row| columns.iter().map(move |column| column[row]))
                .collect();
            JacobianBlock { variable, entries }
        })
        .collect();
    SymbolicKernel {
        name: F::NAME,
        graph: tracer.finish(),
        fields,
        residual,
        blocks,
        jacobian_form,
    }
}

/// A residual traced at the first-order retraction by a symbolic tangent.
struct Traced {
    /// The residual over the inputs and `δ`.
    residual: Vec<Expr>,
    /// The tangent symbols, inputs after the factor's own scalars.
    delta: Vec<Expr>,
    /// Number of the factor's own input scalars.
    input_len: u32,
    /// `δ ↦ 0`.
    at_zero: HashMap<Expr, Expr>,
}

/// Traces `factor`'s residual (inside an active [`Tracer`]) with each stored
/// scalar as the next input, passing its value to `value`.
fn trace_at_tangent<F: Factor>(factor: &F, value: &mut dyn FnMut(f64)) -> Traced {
    let input_len: usize = F::fields().iter().map(|f| f.scalars).sum();
    let input_len = u32::try_from(input_len).expect("fewer than 2³² inputs");
    let delta: Vec<Expr> = (0..F::TANGENT_DIM as u32)
        .map(|j| Expr::input(input_len + j))
        .collect();
    let mut next = 0;
    let residual = factor.trace_residual(
        &mut |v| {
            value(v);
            next += 1;
            Expr::input(next - 1)
        },
        &delta,
    );
    let at_zero = delta.iter().map(|d| (*d, Expr::constant(0.0))).collect();
    Traced {
        residual,
        delta,
        input_len,
        at_zero,
    }
}

/// How the Jacobian entries were formed.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum JacobianForm {
    /// Each entry differentiated as a whole.
    Direct,
    /// By the chain rule through a cut of `width` intermediate values
    /// ([`crate::symbolic::cut`]): `∂r/∂δ = ∂r/∂c · ∂c/∂δ`.
    Chained {
        /// The number of values in the cut.
        width: usize,
    },
}

/// At most this many cuts are tried.
const CUTS_TRIED: usize = 4;

/// The cheapest Jacobian columns (`∂r/∂δₖ` at `δ = 0`, one column over the
/// residual rows per tangent coordinate): the direct derivative, or the chain
/// rule through one of the successive minimum cuts, whichever compiles
/// together with `residual` to the fewest operations (the direct form on a
/// tie). All are exact and equal; they differ in how much work they share.
fn cheapest_columns(
    tracer: &Tracer,
    traced: &[Expr],
    residual: &[Expr],
    delta: &[Expr],
    at_zero: &HashMap<Expr, Expr>,
    input_len: u32,
) -> (Vec<Vec<Expr>>, JacobianForm) {
    let mut substituted = HashMap::new();
    let mut candidates = vec![(
        direct_columns(traced, delta, at_zero, &mut substituted),
        JacobianForm::Direct,
    )];
    for cut in minimum_cuts(traced, delta, CUTS_TRIED) {
        let base = input_len + delta.len() as u32;
        let columns = chained_columns(traced, delta, at_zero, &mut substituted, &cut, base);
        candidates.push((columns, JacobianForm::Chained { width: cut.len() }));
    }
    // The candidates compile independently (the graph is a snapshot), one
    // thread each.
    let graph = tracer.graph();
    let costs: Vec<usize> = std::thread::scope(|scope| {
        let workers: Vec<_> = candidates
            .iter()
            .map(|(columns, _)| {
                let outputs: Vec<Expr> = residual
                    .iter()
                    .chain(columns.iter().flatten())
                    .copied()
                    .collect();
                let graph = &graph;
                scope.spawn(move || {
                    let (program, values) = compile(graph, &outputs);
                    program.counts(&values).total()
                })
            })
            .collect();
        workers
            .into_iter()
            .map(|w| w.join().expect("compilation does not panic"))
            .collect()
    });
    candidates
        .into_iter()
        .zip(costs)
        .min_by_key(|(_, cost)| *cost)
        .map(|(candidate, _)| candidate)
        .expect("the direct form is a candidate")
}

/// `∂r/∂δₖ` at `δ = 0`, each entry differentiated as a whole.
fn direct_columns(
    traced: &[Expr],
    delta: &[Expr],
    at_zero: &HashMap<Expr, Expr>,
    substituted: &mut HashMap<Expr, Expr>,
) -> Vec<Vec<Expr>> {
    delta
        .iter()
        .map(|&d| {
            let mut memo = HashMap::new();
            traced
                .iter()
                .map(|r| substitute(derivative(*r, d, &mut memo), at_zero, substituted))
                .collect()
        })
        .collect()
}

/// `∂r/∂δₖ` at `δ = 0` as `Σⱼ ∂r̃/∂zⱼ · ∂cⱼ/∂δₖ`, where `r̃` is `r` with the
/// cut nodes `c` replaced by fresh symbols `z` (inputs from `base` on), its
/// derivatives taken at `z = c(0)`.
fn chained_columns(
    traced: &[Expr],
    delta: &[Expr],
    at_zero: &HashMap<Expr, Expr>,
    substituted: &mut HashMap<Expr, Expr>,
    cut: &[Expr],
    base: u32,
) -> Vec<Vec<Expr>> {
    let z: Vec<Expr> = (0..cut.len() as u32)
        .map(|j| Expr::input(base + j))
        .collect();
    let to_z: HashMap<Expr, Expr> = cut.iter().copied().zip(z.iter().copied()).collect();
    let mut memo = HashMap::new();
    let reduced: Vec<Expr> = traced
        .iter()
        .map(|r| substitute(*r, &to_z, &mut memo))
        .collect();
    let from_z: HashMap<Expr, Expr> = z
        .iter()
        .zip(cut)
        .map(|(zj, c)| (*zj, substitute(*c, at_zero, substituted)))
        .collect();
    // ∂r̃/∂zⱼ at z = c(0), one vector over the rows per cut node.
    let mut back = HashMap::new();
    let outer: Vec<Vec<Expr>> = z
        .iter()
        .map(|&zj| {
            let mut memo = HashMap::new();
            reduced
                .iter()
                .map(|r| substitute(derivative(*r, zj, &mut memo), &from_z, &mut back))
                .collect()
        })
        .collect();
    delta
        .iter()
        .map(|&d| {
            let mut memo = HashMap::new();
            let inner: Vec<Expr> = cut
                .iter()
                .map(|c| substitute(derivative(*c, d, &mut memo), at_zero, substituted))
                .collect();
            (0..traced.len())
                .map(|row| {
                    outer
                        .iter()
                        .zip(&inner)
                        .fold(Expr::constant(0.0), |acc, (g, dc)| acc + g[row] * *dc)
                })
                .collect()
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::symbolic::evaluate::evaluate;
    use crate::testing::samples::Sampler;

    /// Every candidate cut of every document factor gives the direct
    /// columns' values, at 20 sampled configurations each: the chain rule
    /// through a cut is exact, whichever cut is chosen.
    fn chained_equals_direct<F: Factor>(make: fn(&mut Sampler) -> F) {
        let mut sampler = Sampler::new(7);
        for _ in 0..20 {
            let factor = make(&mut sampler);
            let tracer = Tracer::new();
            let mut values = Vec::new();
            let Traced {
                residual: traced,
                delta,
                input_len,
                at_zero,
            } = trace_at_tangent(&factor, &mut |v| values.push(v));
            let mut substituted = HashMap::new();
            let direct = direct_columns(&traced, &delta, &at_zero, &mut substituted);
            let cuts = minimum_cuts(&traced, &delta, CUTS_TRIED);
            assert!(!cuts.is_empty(), "{}: no cut found", F::NAME);
            let chained: Vec<Vec<Vec<Expr>>> = cuts
                .iter()
                .map(|cut| {
                    let base = input_len + delta.len() as u32;
                    chained_columns(&traced, &delta, &at_zero, &mut substituted, cut, base)
                })
                .collect();
            let graph = tracer.finish();
            let flat = |columns: &[Vec<Expr>]| -> Vec<f64> {
                let outputs: Vec<Expr> = columns.iter().flatten().copied().collect();
                evaluate(&graph, &values, &outputs)
            };
            let expected = flat(&direct);
            let scale = expected.iter().fold(1.0_f64, |m, x| m.max(x.abs()));
            for (cut, columns) in cuts.iter().zip(&chained) {
                for (a, b) in flat(columns).iter().zip(&expected) {
                    assert!(
                        (a - b).abs() <= 1e-12 * scale,
                        "{} through a cut of {}: {a} vs {b}",
                        F::NAME,
                        cut.len()
                    );
                }
            }
        }
    }

    #[test]
    fn the_chain_rule_through_every_cut_is_exact() {
        chained_equals_direct(Sampler::point_reprojection);
        chained_equals_direct(Sampler::line_reprojection);
        chained_equals_direct(Sampler::plucker_line_reprojection);
        chained_equals_direct(Sampler::plane);
        chained_equals_direct(Sampler::free_line);
    }
}
