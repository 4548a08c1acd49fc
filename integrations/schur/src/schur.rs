//! The damped Gauss–Newton step by the Schur complement.
//!
//! With the reduced variables `r` and the eliminated ones `e`, the normal
//! equations `(H + λD) δ = −g` are
//!
//! ```text
//! [ U + λD_r    W       ] [δ_r]     [g_r]
//! [ Wᵀ          V + λD_e] [δ_e] = − [g_e]
//! ```
//!
//! with `V` block diagonal (no factor joins two eliminated variables) and
//! `D = clamp(diag H, low, high)` ([`Damped`]: Ceres' and apex-solver's
//! Levenberg–Marquardt scaling with their bounds `[1e-6, 1e32]`, or
//! Levenberg's uniform `D = I` with `low = high = 1`). Eliminating each
//! `δ_e`:
//!
//! ```text
//! S = U + λD_r − Σ_e W_e V*_e⁻¹ W_eᵀ,    S δ_r = −g_r + Σ_e W_e V*_e⁻¹ g_e,
//! δ_e = V*_e⁻¹ (−g_e − W_eᵀ δ_r),        V*_e = V_e + λD_e = L_e L_eᵀ.
//! ```
//!
//! Per eliminated variable, with `Z_r = W_re L_e⁻ᵀ` (its rows are `L_e⁻¹`
//! applied to the rows of `W_re`) and `y = L_e⁻¹ g_e`, the update of block
//! `(u, v)` of `S` is `−Z_u Z_vᵀ` and that of the right-hand side
//! `Z_r y`: one small triangular solve per row, then dot products of
//! length `d_e`. The eliminated variables are split among the threads,
//! each adding into its own copy of `S` (the first thread into `S`
//! itself), summed at the end.

use factor_minimizer::{Damped, Prediction};
use rayon::prelude::*;

use crate::csc::BlockCsc;
use crate::partition::{Partition, split_at_bounds};
use crate::structure::{Eliminated, MAX_ELIMINATED, Structure};

/// The normal equations `Jᵀ w J`, `Jᵀ w r` at the current values, in the
/// layout of [`Structure`].
#[derive(Debug, Clone, Default)]
pub(crate) struct Normal {
    /// `U` in the structure of `S`.
    pub(crate) u: Vec<f64>,
    /// Its diagonal blocks whole, as the linearization accumulates them
    /// before they are folded into `u`.
    pub(crate) diagonal: Vec<f64>,
    pub(crate) g_reduced: Vec<f64>,
    /// Each `V_e`, packed upper triangle.
    pub(crate) v: Vec<f64>,
    pub(crate) g_eliminated: Vec<f64>,
    /// Each eliminated variable's cross blocks `W_re`.
    pub(crate) w: Vec<f64>,
}

impl Normal {
    pub(crate) fn zeros(structure: &Structure) -> Self {
        let el = &structure.eliminated;
        Normal {
            u: vec![0.0; structure.csc.len()],
            diagonal: vec![0.0; *structure.csc.dense.last().unwrap_or(&0)],
            g_reduced: vec![0.0; structure.csc.dim()],
            v: vec![0.0; *el.packed.last().unwrap_or(&0)],
            g_eliminated: vec![0.0; *el.tangent.last().unwrap_or(&0)],
            w: vec![0.0; *el.cross.last().unwrap_or(&0)],
        }
    }

    /// `(H_jj, g_j)` over the free coordinates, in the order of
    /// `g_reduced` then `g_eliminated`.
    pub(crate) fn diagonal_and_gradient<'a>(
        &'a self,
        structure: &'a Structure,
    ) -> impl Iterator<Item = (f64, f64)> + 'a {
        let (csc, el) = (&structure.csc, &structure.eliminated);
        let reduced = csc
            .dims
            .iter()
            .enumerate()
            .flat_map(move |(v, &d)| (0..d).map(move |a| self.u[csc.diagonal(v, a, a)]));
        let eliminated = el
            .tangent
            .windows(2)
            .zip(&el.packed)
            .flat_map(move |(t, &at)| {
                let d = t[1] - t[0];
                (0..d).map(move |a| self.v[at + packed(d, a, a)])
            });
        let gradient = self.g_reduced.iter().chain(&self.g_eliminated).copied();
        reduced.chain(eliminated).zip(gradient)
    }
}

/// `‖(a, b, …)‖` of the concatenated `parts`, of any magnitude: each part's
/// norm scaled by its largest entry (`scaled_norm`), so that a gradient of
/// 1e165 (a measurement weighted by σ = 1e-80) is not reported infinite.
pub(crate) fn norm(parts: &[&[f64]]) -> f64 {
    parts
        .iter()
        .map(|part| factor_core::linalg::scaled_norm(&nalgebra::DVectorView::from(*part)))
        .fold(0.0, f64::hypot)
}

/// The work buffers of the step: `S`, its right-hand side (then `δ_r`),
/// each `L_e` (packed like `V`) and `δ_e`.
#[derive(Debug, Clone, Default)]
pub(crate) struct StepBuffers {
    pub(crate) s: Vec<f64>,
    pub(crate) reduced: Vec<f64>,
    pub(crate) factors: Vec<f64>,
    pub(crate) eliminated: Vec<f64>,
}

impl StepBuffers {
    pub(crate) fn new(normal: &Normal) -> Self {
        StepBuffers {
            s: vec![0.0; normal.u.len()],
            reduced: vec![0.0; normal.g_reduced.len()],
            factors: vec![0.0; normal.v.len()],
            eliminated: vec![0.0; normal.g_eliminated.len()],
        }
    }
}

/// The index of entry `(a, b)`, `a ≤ b`, of a packed upper triangle of
/// dimension `d` (row by row).
#[inline]
fn packed(d: usize, a: usize, b: usize) -> usize {
    a * d - a * a.saturating_sub(1) / 2 - a + b
}

/// The Cholesky factor `L` (full `d × d`, lower) of `V + λ D` (`damped`),
/// `V` packed; `None` if it is not positive definite.
fn damped_cholesky(
    v: &[f64],
    d: usize,
    damped: Damped,
) -> Option<[f64; MAX_ELIMINATED * MAX_ELIMINATED]> {
    let mut l = [0.0; MAX_ELIMINATED * MAX_ELIMINATED];
    for i in 0..d {
        for j in 0..=i {
            let mut x = v[packed(d, j, i)];
            if i == j {
                x += damped.of(x);
            }
            for k in 0..j {
                x -= l[i * d + k] * l[j * d + k];
            }
            if i == j {
                if x.is_nan() || x <= 0.0 {
                    return None;
                }
                l[i * d + i] = x.sqrt();
            } else {
                l[i * d + j] = x / l[j * d + j];
            }
        }
    }
    Some(l)
}

/// `x ← L⁻¹ x`.
#[inline]
fn forward(l: &[f64], d: usize, x: &mut [f64]) {
    for i in 0..d {
        let mut s = x[i];
        for k in 0..i {
            s -= l[i * d + k] * x[k];
        }
        x[i] = s / l[i * d + i];
    }
}

/// `x ← L⁻ᵀ x`.
#[inline]
fn backward(l: &[f64], d: usize, x: &mut [f64]) {
    for i in (0..d).rev() {
        let mut s = x[i];
        for k in i + 1..d {
            s -= l[k * d + i] * x[k];
        }
        x[i] = s / l[i * d + i];
    }
}

/// The per-thread scratch of [`eliminate`]: `Z` column-major (`d_e`
/// columns of the rows next to the variable) and one column of `Z Zᵀ`.
#[derive(Default)]
struct Scratch {
    z: Vec<f64>,
    column: Vec<f64>,
}

/// Eliminates variables `range` from the system into `s` (which holds `U +
/// λD_r`, or zeros for a thread's copy) and `rhs`, keeping each `L_e`
/// (packed) in `factors` (the range's slice); `false` if some `V*_e` is not
/// positive definite.
///
/// Per variable, `Z = W L⁻ᵀ` is formed column by column (`W`'s rows are
/// those of its cross blocks, stacked), then each column `b` of the lower
/// triangle of `Z Zᵀ` in turn, `d_e` products of contiguous columns, and
/// subtracted from `S` block by block: in block column `v`, column `b` of
/// the diagonal block and of each block below it are contiguous runs.
#[allow(clippy::too_many_arguments)]
#[inline(always)]
fn eliminate_body(
    range: std::ops::Range<usize>,
    damped: Damped,
    normal: &Normal,
    csc: &BlockCsc,
    el: &Eliminated,
    s: &mut [f64],
    rhs: &mut [f64],
    factors: &mut [f64],
) -> bool {
    let factor_base = el.packed[range.start];
    let mut scratch = Scratch::default();
    for e in range {
        let d = el.dim(e);
        let v = &normal.v[el.packed[e]..el.packed[e + 1]];
        let Some(l) = damped_cholesky(v, d, damped) else {
            return false;
        };
        let stored = &mut factors[el.packed[e] - factor_base..el.packed[e + 1] - factor_base];
        let mut c = 0;
        for i in 0..d {
            for j in 0..=i {
                stored[c] = l[i * d + j];
                c += 1;
            }
        }
        let blocks = el.neighbours(e);
        let w = &normal.w[el.cross[e]..el.cross[e + 1]];
        let rows = w.len() / d.max(1);
        // Z column k = (W column k − Σ_{m<k} L_km Z column m) / L_kk.
        scratch.z.resize(rows * d, 0.0);
        for k in 0..d {
            let (done, rest) = scratch.z.split_at_mut(k * rows);
            let zk = &mut rest[..rows];
            for (a, x) in zk.iter_mut().enumerate() {
                *x = w[a * d + k];
            }
            for m in 0..k {
                let lkm = l[k * d + m];
                for (x, y) in zk.iter_mut().zip(&done[m * rows..(m + 1) * rows]) {
                    *x -= lkm * y;
                }
            }
            let inverse = 1.0 / l[k * d + k];
            for x in zk.iter_mut() {
                *x *= inverse;
            }
        }
        let z = &scratch.z;
        // The right-hand side: + Z L⁻¹ g_e.
        let mut y = [0.0; MAX_ELIMINATED];
        for (t, g) in y
            .iter_mut()
            .zip(&normal.g_eliminated[el.tangent[e]..el.tangent[e + 1]])
        {
            *t = *g;
        }
        forward(&l, d, &mut y[..d]);
        scratch.column.clear();
        scratch.column.resize(rows, 0.0);
        for (k, yk) in y[..d].iter().enumerate() {
            for (t, x) in scratch.column.iter_mut().zip(&z[k * rows..(k + 1) * rows]) {
                *t += x * yk;
            }
        }
        let mut start = 0;
        for &r in blocks {
            let (o, dr) = (csc.offsets[r as usize], csc.dims[r as usize]);
            for (t, x) in rhs[o..o + dr]
                .iter_mut()
                .zip(&scratch.column[start..start + dr])
            {
                *t += x;
            }
            start += dr;
        }
        // S −= Z Zᵀ, column by column of its lower triangle.
        let prefixes = &el.prefixes[el.pair_start[e]..el.pair_start[e + 1]];
        let mut start_j = 0;
        for (j, &v) in blocks.iter().enumerate() {
            let (ov, dv) = (csc.offsets[v as usize], csc.dims[v as usize]);
            for b in 0..dv {
                let top = start_j + b;
                let column = &mut scratch.column[top..rows];
                if d == 3 {
                    // Points and landmarks: the three products in one pass.
                    let (z0, z1, z2) = (
                        &z[top..rows],
                        &z[rows + top..2 * rows],
                        &z[2 * rows + top..],
                    );
                    let (c0, c1, c2) = (z0[0], z1[0], z2[0]);
                    for (((t, x0), x1), x2) in column.iter_mut().zip(z0).zip(z1).zip(z2) {
                        *t = x0 * c0 + x1 * c1 + x2 * c2;
                    }
                } else {
                    let z0 = &z[top..rows];
                    let c0 = z0[0];
                    for (t, x) in column.iter_mut().zip(z0) {
                        *t = x * c0;
                    }
                    for k in 1..d {
                        let zk = &z[k * rows + top..(k + 1) * rows];
                        let c = zk[0];
                        for (t, x) in column.iter_mut().zip(zk) {
                            *t += x * c;
                        }
                    }
                }
                // The diagonal block's rows b.., then each block below.
                let base = csc.col_ptr[ov + b];
                subtract(&mut s[base..base + dv - b], &column[..dv - b]);
                let mut at = dv - b;
                // Blocks i > j of this variable: pair (i, j) is number
                // i(i − 1)/2 + j among the prefixes.
                let below = csc.below(v as usize, 0, 0, b);
                for (i, &u) in blocks.iter().enumerate().skip(j + 1) {
                    let du = csc.dims[u as usize];
                    let run = below + prefixes[i * (i - 1) / 2 + j] as usize;
                    subtract(&mut s[run..run + du], &column[at..at + du]);
                    at += du;
                }
            }
            start_j += dv;
        }
    }
    true
}

/// `s −= x`, entry by entry; a run of six (a pose's block column) as one
/// fixed-size operation, without a loop's bookkeeping per run.
#[inline(always)]
fn subtract(s: &mut [f64], x: &[f64]) {
    if let (Ok(s), Ok(x)) = (<&mut [f64; 6]>::try_from(&mut *s), <&[f64; 6]>::try_from(x)) {
        for (t, y) in s.iter_mut().zip(x) {
            *t -= y;
        }
        return;
    }
    for (t, y) in s.iter_mut().zip(x) {
        *t -= y;
    }
}

/// [`eliminate_body`] compiled for AVX2 (its products of columns are
/// loops the compiler vectorises for the instruction set).
///
/// # Safety
///
/// The CPU must have AVX2 and FMA.
#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx2,fma")]
#[allow(clippy::too_many_arguments)]
unsafe fn eliminate_avx2(
    range: std::ops::Range<usize>,
    damped: Damped,
    normal: &Normal,
    csc: &BlockCsc,
    el: &Eliminated,
    s: &mut [f64],
    rhs: &mut [f64],
    factors: &mut [f64],
) -> bool {
    eliminate_body(range, damped, normal, csc, el, s, rhs, factors)
}

/// [`eliminate_body`] compiled for AVX-512.
///
/// # Safety
///
/// The CPU must have AVX-512 F, DQ and VL, AVX2 and FMA.
#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx512f,avx512dq,avx512vl,avx2,fma")]
#[allow(clippy::too_many_arguments)]
unsafe fn eliminate_avx512(
    range: std::ops::Range<usize>,
    damped: Damped,
    normal: &Normal,
    csc: &BlockCsc,
    el: &Eliminated,
    s: &mut [f64],
    rhs: &mut [f64],
    factors: &mut [f64],
) -> bool {
    eliminate_body(range, damped, normal, csc, el, s, rhs, factors)
}

/// [`eliminate_body`] compiled for the best instruction set of the CPU
/// (as `factor_batch` chooses its batch loop's).
#[allow(clippy::too_many_arguments)]
fn eliminate(
    range: std::ops::Range<usize>,
    damped: Damped,
    normal: &Normal,
    csc: &BlockCsc,
    el: &Eliminated,
    s: &mut [f64],
    rhs: &mut [f64],
    factors: &mut [f64],
) -> bool {
    match factor_batch::detected() {
        #[cfg(target_arch = "x86_64")]
        // SAFETY: the CPU has AVX-512 F, DQ, VL, AVX2 and FMA (detected).
        factor_batch::Isa::Avx512 => unsafe {
            eliminate_avx512(range, damped, normal, csc, el, s, rhs, factors)
        },
        #[cfg(target_arch = "x86_64")]
        // SAFETY: the CPU has AVX2 and FMA (detected).
        factor_batch::Isa::Avx2 => unsafe {
            eliminate_avx2(range, damped, normal, csc, el, s, rhs, factors)
        },
        _ => eliminate_body(range, damped, normal, csc, el, s, rhs, factors),
    }
}

/// `δ_e = V*_e⁻¹ (−g_e − W_eᵀ δ_r)` for variables `range` into `step` (the
/// range's slice); returns `Σ_e δ_eᵀ W_eᵀ δ_r` and `Σ_e δ_eᵀ V_e δ_e` (the
/// undamped `V`), for the model's decrease.
fn back_substitute(
    range: std::ops::Range<usize>,
    normal: &Normal,
    csc: &BlockCsc,
    el: &Eliminated,
    factors: &[f64],
    reduced: &[f64],
    step: &mut [f64],
) -> (f64, f64) {
    let base = el.tangent[range.start];
    let (mut cross, mut quadratic) = (0.0, 0.0);
    for e in range {
        let d = el.dim(e);
        // Wᵀ δ_r.
        let mut wt = [0.0; MAX_ELIMINATED];
        let mut at = el.cross[e];
        for &r in el.neighbours(e) {
            let (o, dr) = (csc.offsets[r as usize], csc.dims[r as usize]);
            for a in 0..dr {
                let x = reduced[o + a];
                for (b, t) in wt[..d].iter_mut().enumerate() {
                    *t += normal.w[at + a * d + b] * x;
                }
            }
            at += dr * d;
        }
        let mut l = [0.0; MAX_ELIMINATED * MAX_ELIMINATED];
        let mut c = el.packed[e];
        for i in 0..d {
            for j in 0..=i {
                l[i * d + j] = factors[c];
                c += 1;
            }
        }
        let g = &normal.g_eliminated[el.tangent[e]..el.tangent[e + 1]];
        let mut x = [0.0; MAX_ELIMINATED];
        for k in 0..d {
            x[k] = -g[k] - wt[k];
        }
        forward(&l, d, &mut x[..d]);
        backward(&l, d, &mut x[..d]);
        step[el.tangent[e] - base..el.tangent[e + 1] - base].copy_from_slice(&x[..d]);
        let v = &normal.v[el.packed[e]..el.packed[e + 1]];
        for a in 0..d {
            cross += x[a] * wt[a];
            for b in 0..d {
                quadratic += x[a] * v[packed(d, a.min(b), a.max(b))] * x[b];
            }
        }
    }
    (cross, quadratic)
}

/// The times of a step's parts.
#[derive(Debug, Clone, Copy, Default)]
pub(crate) struct StepTimes {
    pub(crate) eliminate: std::time::Duration,
    pub(crate) factorize: std::time::Duration,
    pub(crate) back_substitute: std::time::Duration,
}

/// Solves `(H + λD) δ = −g` into `buffers.reduced` and
/// `buffers.eliminated`; `None` if it is not positive definite, else what
/// the undamped model predicts of the step.
pub(crate) fn step(
    damped: Damped,
    normal: &Normal,
    structure: &Structure,
    partition: &Partition,
    solver: &mut crate::reduced::ReducedSolver,
    buffers: &mut StepBuffers,
    times: &mut StepTimes,
) -> Option<Prediction> {
    let csc = &structure.csc;
    let el = &structure.eliminated;
    let clock = std::time::Instant::now();
    buffers.s.copy_from_slice(&normal.u);
    for (v, &d) in csc.dims.iter().enumerate() {
        for a in 0..d {
            let k = csc.diagonal(v, a, a);
            buffers.s[k] += damped.of(normal.u[k]);
        }
    }
    for (r, g) in buffers.reduced.iter_mut().zip(&normal.g_reduced) {
        *r = -g;
    }
    let bounds = &partition.eliminated;
    let packed_bounds: Vec<usize> = bounds.iter().map(|&b| el.packed[b]).collect();
    let parts = partition.parts();
    let ok = if parts == 1 {
        eliminate(
            0..el.len(),
            damped,
            normal,
            csc,
            el,
            &mut buffers.s,
            &mut buffers.reduced,
            &mut buffers.factors,
        )
    } else {
        let factor_parts = split_at_bounds(&mut buffers.factors, &packed_bounds);
        let mut copies: Vec<(Vec<f64>, Vec<f64>)> = (1..parts)
            .map(|_| (vec![0.0; buffers.s.len()], vec![0.0; buffers.reduced.len()]))
            .collect();
        let mut targets: Vec<(&mut [f64], &mut [f64])> =
            vec![(&mut buffers.s[..], &mut buffers.reduced[..])];
        targets.extend(copies.iter_mut().map(|(s, r)| (&mut s[..], &mut r[..])));
        let ok = targets
            .into_par_iter()
            .zip(factor_parts)
            .enumerate()
            .map(|(t, ((s, rhs), factors))| {
                eliminate(
                    bounds[t]..bounds[t + 1],
                    damped,
                    normal,
                    csc,
                    el,
                    s,
                    rhs,
                    factors,
                )
            })
            .collect::<Vec<bool>>()
            .into_iter()
            .all(|ok| ok);
        for (s, rhs) in &copies {
            buffers.s.par_iter_mut().zip(s).for_each(|(a, b)| *a += b);
            for (a, b) in buffers.reduced.iter_mut().zip(rhs) {
                *a += b;
            }
        }
        ok
    };
    times.eliminate += clock.elapsed();
    if !ok {
        return None;
    }
    let clock = std::time::Instant::now();
    if csc.dim() > 0 {
        if !solver.factorize(csc, &buffers.s) {
            times.factorize += clock.elapsed();
            return None;
        }
        solver.solve(&mut buffers.reduced);
    }
    times.factorize += clock.elapsed();
    let clock = std::time::Instant::now();
    let tangent_bounds: Vec<usize> = bounds.iter().map(|&b| el.tangent[b]).collect();
    let step_parts = split_at_bounds(&mut buffers.eliminated, &tangent_bounds);
    let (factors, reduced) = (&buffers.factors, &buffers.reduced);
    let (cross, quadratic) = step_parts
        .into_par_iter()
        .enumerate()
        .map(|(t, step)| {
            back_substitute(
                bounds[t]..bounds[t + 1],
                normal,
                csc,
                el,
                factors,
                reduced,
                step,
            )
        })
        .reduce(|| (0.0, 0.0), |a, b| (a.0 + b.0, a.1 + b.1));
    let g_delta: f64 = normal
        .g_reduced
        .iter()
        .zip(&buffers.reduced)
        .chain(normal.g_eliminated.iter().zip(&buffers.eliminated))
        .map(|(g, d)| g * d)
        .sum();
    let h_delta = csc.quadratic_form(&normal.u, &buffers.reduced) + 2.0 * cross + quadratic;
    times.back_substitute += clock.elapsed();
    Some(Prediction { g_delta, h_delta })
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Norms beyond `√f64::MAX` (a gradient of 1e200) are finite, and
    /// exact to rounding; zero parts and an empty list are zero.
    #[test]
    fn norms_of_any_magnitude_are_finite() {
        let big = norm(&[&[3e200, 0.0], &[4e200]]);
        assert!((big / 5e200 - 1.0).abs() < 1e-15, "{big:e}");
        let small = norm(&[&[3e-200], &[], &[4e-200]]);
        assert!((small / 5e-200 - 1.0).abs() < 1e-15, "{small:e}");
        assert_eq!(norm(&[&[0.0, 0.0]]), 0.0);
        assert_eq!(norm(&[]), 0.0);
        assert!(norm(&[&[f64::NAN]]).is_nan());
    }

    #[test]
    fn packed_upper_indices_run_row_by_row() {
        let mut expected = 0;
        for a in 0..4 {
            for b in a..4 {
                assert_eq!(packed(4, a, b), expected);
                expected += 1;
            }
        }
    }

    /// L Lᵀ reproduces the damped matrix, and the triangular solves invert it.
    #[test]
    fn small_cholesky_factors_the_damped_block() {
        // V = [[4, 1, 0], [1, 3, 1], [0, 1, 2]], packed upper.
        let v = [4.0, 1.0, 0.0, 3.0, 1.0, 2.0];
        let lambda = 0.5;
        let damped = Damped {
            lambda,
            bounds: (1e-6, 1e32),
        };
        let l = damped_cholesky(&v, 3, damped).unwrap();
        let full = |a: usize, b: usize| {
            let x = v[packed(3, a.min(b), a.max(b))];
            if a == b { x * (1.0 + lambda) } else { x }
        };
        for a in 0..3 {
            for b in 0..3 {
                let llt: f64 = (0..3).map(|k| l[a * 3 + k] * l[b * 3 + k]).sum();
                assert!((llt - full(a, b)).abs() < 1e-14, "{a} {b}");
            }
        }
        let mut x = [1.0, -2.0, 0.5];
        forward(&l, 3, &mut x);
        backward(&l, 3, &mut x);
        for a in 0..3 {
            let back: f64 = (0..3).map(|b| full(a, b) * x[b]).sum();
            assert!((back - [1.0, -2.0, 0.5][a]).abs() < 1e-14);
        }
        let undamped = Damped {
            lambda: 0.0,
            bounds: (1.0, 1.0),
        };
        assert!(damped_cholesky(&[-1.0], 1, undamped).is_none());
    }
}

/// The normal equations the fused kernels assemble, and the step the Schur
/// complement takes, against a dense assembly of the same problem from
/// each factor's dual-number Jacobian (not the generated kernels) and a
/// dense Cholesky solve of the whole damped system.
#[cfg(test)]
mod dense {
    use factor_core::Factor;
    use nalgebra::{DMatrix, DVector};
    use slam_data::synthetic::{SyntheticConfig, generate};
    use slam_problems::Robust;
    use slam_problems::bundle::factor_of;

    use super::*;
    use crate::partition::Partition;
    use crate::passes;
    use crate::problems::{Keys, build};
    use crate::reduced::ReducedSolver;
    use crate::robust;
    use crate::structure::Role;

    /// 4 cameras (camera 0's pose fixed: 30 reduced coordinates), 24
    /// points seen 3 times each, 5% outliers, under Huber's loss.
    fn problem() -> (slam_data::BalProblem, crate::problems::Built) {
        let config = SyntheticConfig {
            cameras: 4,
            points: 24,
            views_per_point: 3,
            ..SyntheticConfig::with_observations(72, 3)
        };
        let bal = generate(&config).unwrap().problem;
        let built = build(
            &slam_data::Problem::Bal(bal.clone()),
            Some(Robust::Huber(2.0)),
            slam_problems::Kernels::Generated,
        )
        .unwrap();
        (bal, built)
    }

    /// `H = Σ Jᵀ ρ' J` and `g = Σ Jᵀ ρ' r` over the coordinates of
    /// `structure` (the reduced ones, then the eliminated ones).
    fn dense_system(
        bal: &slam_data::BalProblem,
        built: &crate::problems::Built,
        structure: &Structure,
    ) -> (DMatrix<f64>, DVector<f64>) {
        let Keys::Bundle(keys) = &built.keys else {
            unreachable!()
        };
        let n = structure.csc.dim();
        let total = n + structure.eliminated.tangent.last().unwrap();
        let coordinate = |id: crate::VariableId| match structure.roles
            [structure.internal[id.index()] as usize]
        {
            Role::Reduced { block, offset } => {
                Some(structure.csc.offsets[block as usize] + offset as usize)
            }
            Role::Eliminated { index } => Some(n + structure.eliminated.tangent[index as usize]),
            Role::Fixed => None,
        };
        let (mut h, mut g) = (DMatrix::zeros(total, total), DVector::zeros(total));
        for (k, o) in bal.observations.iter().enumerate() {
            let factor = factor_of(bal, k);
            let mut r = [0.0; 2];
            let (mut jp, mut ji, mut jx) = ([0.0; 12], [0.0; 6], [0.0; 6]);
            factor
                .linearize_dual_into(&mut r, &mut [Some(&mut jp), Some(&mut ji), Some(&mut jx)])
                .unwrap();
            let w = robust::weight(Some(Robust::Huber(2.0)), r[0] * r[0] + r[1] * r[1]);
            let ids = [
                keys.poses[o.camera],
                keys.intrinsics[o.camera],
                keys.points[o.point],
            ];
            let blocks: [(&[f64], usize); 3] = [(&jp, 6), (&ji, 3), (&jx, 3)];
            for (a, &(ja, da)) in ids.iter().zip(&blocks) {
                let Some(ca) = coordinate(*a) else { continue };
                for p in 0..da {
                    g[ca + p] += w * (ja[p] * r[0] + ja[da + p] * r[1]);
                    for (b, &(jb, db)) in ids.iter().zip(&blocks) {
                        let Some(cb) = coordinate(*b) else { continue };
                        for q in 0..db {
                            h[(ca + p, cb + q)] += w * (ja[p] * jb[q] + ja[da + p] * jb[db + q]);
                        }
                    }
                }
            }
        }
        (h, g)
    }

    fn close(a: f64, b: f64, scale: f64) -> bool {
        (a - b).abs() <= 1e-9 * scale
    }

    #[test]
    fn fused_normal_equations_and_the_schur_step_match_a_dense_solve() {
        let (bal, mut built) = problem();
        let structure = built.problem.structure().unwrap();
        let (h, g) = dense_system(&bal, &built, &structure);
        let scale = h.abs().max();
        let n = structure.csc.dim();
        let el = &structure.eliminated;
        let problem = &built.problem;
        // On one thread and on three (each its own copy of U, summed).
        for threads in [1, 3] {
            let partition = Partition::forced(&structure, threads);
            let (cost, _, normal) = passes::at_values(problem, &structure, threads);
            assert!(cost.is_finite());
            // U: every stored entry of S's lower triangle, and nothing
            // outside the structure.
            let csc = &structure.csc;
            let mut stored = DMatrix::<f64>::zeros(n, n);
            for column in 0..n {
                for k in csc.col_ptr[column]..csc.col_ptr[column + 1] {
                    stored[(csc.row_idx[k], column)] = normal.u[k];
                }
            }
            for column in 0..n {
                for row in column..n {
                    assert!(
                        close(stored[(row, column)], h[(row, column)], scale),
                        "U ({row}, {column})"
                    );
                }
                assert!(close(normal.g_reduced[column], g[column], g.amax()));
            }
            for e in 0..el.len() {
                let (d, t) = (el.dim(e), n + el.tangent[e]);
                let mut c = el.packed[e];
                for a in 0..d {
                    assert!(close(
                        normal.g_eliminated[el.tangent[e] + a],
                        g[t + a],
                        g.amax()
                    ));
                    for b in a..d {
                        assert!(close(normal.v[c], h[(t + a, t + b)], scale), "V {e}");
                        c += 1;
                    }
                }
                let mut w = el.cross[e];
                for &r in el.neighbours(e) {
                    let o = csc.offsets[r as usize];
                    for a in 0..csc.dims[r as usize] {
                        for b in 0..d {
                            assert!(close(normal.w[w], h[(o + a, t + b)], scale), "W {e}");
                            w += 1;
                        }
                    }
                }
            }
            // The damped step against a dense Cholesky solve, with the
            // diagonal's scaling (Ceres' bounds) and uniformly (`λ I`).
            // The reduced system factorized sparse and dense alike.
            for ((lambda, low, high), dense) in [(1e-3, 1e-6, 1e32), (1e-2, 1.0, 1.0)]
                .into_iter()
                .flat_map(|d| [(d, false), (d, true)])
            {
                let mut damped = h.clone();
                for k in 0..damped.nrows() {
                    damped[(k, k)] += lambda * h[(k, k)].clamp(low, high);
                }
                let expected = damped.cholesky().unwrap().solve(&(-&g));
                let mut solver = if dense {
                    ReducedSolver::Dense {
                        matrix: faer::Mat::zeros(n, n),
                        llt: None,
                    }
                } else {
                    ReducedSolver::new(csc, partition.parts()).unwrap()
                };
                let mut buffers = StepBuffers::new(&normal);
                let mut times = StepTimes::default();
                let step = step(
                    Damped {
                        lambda,
                        bounds: (low, high),
                    },
                    &normal,
                    &structure,
                    &partition,
                    &mut solver,
                    &mut buffers,
                    &mut times,
                )
                .expect("positive definite");
                let got = DVector::from_iterator(
                    expected.len(),
                    buffers.reduced.iter().chain(&buffers.eliminated).copied(),
                );
                assert!(
                    (&got - &expected).amax() <= 1e-9 * expected.amax(),
                    "{got} vs {expected}"
                );
                assert!(close(
                    step.g_delta,
                    g.dot(&expected),
                    g.dot(&expected).abs()
                ));
                let hd = (&h * &expected).dot(&expected);
                assert!(close(step.h_delta, hd, hd));
            }
        }
    }
}
