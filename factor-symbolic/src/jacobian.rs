//! The Jacobian columns `∂r/∂δₖ` at `δ = 0` of a traced residual
//! ([`crate::trace`]), two exact ways: each entry differentiated as a whole
//! ([`direct_columns`]), or the chain rule through a vertex cut `c` between
//! `δ` and the residual ([`chained_columns`], [`crate::cut`]),
//! `∂r/∂δ = ∂r/∂c · ∂c/∂δ` with `∂r/∂c` shared by every tangent column, as a
//! hand derivation through the camera-frame point or line does.

use std::collections::HashMap;

use crate::calculus::{derivative, substitute};
use crate::graph::Expr;

/// `∂r/∂δₖ` at `δ = 0`, each entry differentiated as a whole.
pub fn direct_columns(
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
pub fn chained_columns(
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
