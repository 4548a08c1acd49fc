//! The normal blocks of factors from their residuals and Jacobians (the
//! per-lane Jacobian kernel's outputs under a full noise model, or a
//! per-factor group's): `r` and each `J` whitened by the factor's
//! square-root information `S` first, then `Jᵢᵀ w S r`-style blocks formed
//! as the fused kernels lay theirs out (`factor_lanes::NormalKernel`), so
//! that the same scatter adds them ([`crate::noise`] says when).

use factor_batch::{JacobianColumns, pairs};

use crate::noise::Whitening;

/// The gradient blocks and the Hessian blocks (pairs `i ≤ j` in
/// [`pairs`] order: a diagonal block's upper triangle row by row, an
/// off-diagonal one row-major) of the `n` factors of `outputs`, factors
/// `first..first + n` of `whitening`, whitened by their `S` and weighted by
/// `w` (1 when `None`). Each block is its columns end to end, `n` entries
/// per column.
pub(crate) fn normal_columns(
    outputs: &JacobianColumns<f64>,
    tangents: &[usize],
    whitening: &Whitening,
    first: usize,
    w: Option<&[f64]>,
) -> (Vec<Vec<f64>>, Vec<Vec<f64>>) {
    let n = outputs.residual.len();
    let dim = outputs.residual.width();
    let pairs = pairs(tangents.len());
    let mut gradient: Vec<Vec<f64>> = tangents.iter().map(|d| vec![0.0; d * n]).collect();
    let mut hessian: Vec<Vec<f64>> = pairs
        .iter()
        .map(|&(i, j)| {
            let width = if i == j {
                tangents[i] * (tangents[i] + 1) / 2
            } else {
                tangents[i] * tangents[j]
            };
            vec![0.0; width * n]
        })
        .collect();
    let residual: Vec<&[f64]> = outputs.residual.columns().collect();
    let blocks: Vec<Vec<&[f64]>> = outputs
        .blocks
        .iter()
        .map(|b| {
            b.as_ref()
                .expect("every block computed")
                .columns()
                .collect()
        })
        .collect();
    let mut sr = vec![0.0; dim];
    let mut s = vec![0.0; dim * dim];
    // S Jₖ, row-major (dim × dₖ), per variable.
    let mut sj: Vec<Vec<f64>> = tangents.iter().map(|d| vec![0.0; dim * d]).collect();
    for row in 0..n {
        whitening.matrix_into(first + row, dim, &mut s);
        let weight = w.map_or(1.0, |w| w[row]);
        for (a, x) in sr.iter_mut().enumerate() {
            *x = (0..dim).map(|b| s[a * dim + b] * residual[b][row]).sum();
        }
        for ((sj, block), &d) in sj.iter_mut().zip(&blocks).zip(tangents) {
            for a in 0..dim {
                for c in 0..d {
                    sj[a * d + c] = (0..dim)
                        .map(|b| s[a * dim + b] * block[b * d + c][row])
                        .sum();
                }
            }
        }
        // Entry `(a, b)` of `(S Jᵢ)ᵀ w (S Jⱼ)`.
        let product = |i: usize, a: usize, j: usize, b: usize| -> f64 {
            let (di, dj) = (tangents[i], tangents[j]);
            weight
                * (0..dim)
                    .map(|r| sj[i][r * di + a] * sj[j][r * dj + b])
                    .sum::<f64>()
        };
        for (k, g) in gradient.iter_mut().enumerate() {
            let d = tangents[k];
            for a in 0..d {
                g[a * n + row] = weight * (0..dim).map(|r| sj[k][r * d + a] * sr[r]).sum::<f64>();
            }
        }
        for (h, &(i, j)) in hessian.iter_mut().zip(&pairs) {
            let mut column = 0;
            for a in 0..tangents[i] {
                let from = if i == j { a } else { 0 };
                for b in from..tangents[j] {
                    h[column * n + row] = product(i, a, j, b);
                    column += 1;
                }
            }
        }
    }
    (gradient, hessian)
}
