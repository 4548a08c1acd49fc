//! Whether the residuals of a least-squares problem determine its free
//! variables, to first order at the given values: the directions of the
//! variables' tangent spaces along which no whitened residual changes (the
//! null space of `JᵀJ`), which Levenberg–Marquardt's damping would hide —
//! it drifts along them and reports a result (issue 28: `synth-plp --kinds
//! planes` solved to an ATE of 3 421 m). A gauge left free (no variable
//! fixed, or the scale of a problem measured in pixels only) and a rank
//! deficiency (a camera that sees two planes only, a point seen once) are
//! both such directions.
//!
//! The normal matrix `H = JᵀJ` is formed block by block (a block per pair
//! of variables some factor joins), each coordinate scaled to a unit
//! diagonal (a coordinate no factor measures is a direction at once), and
//! eliminated variable by variable, the least connected first (landmarks
//! before the cameras that see them, a pose chain along the chain): the
//! Schur complement of each variable's diagonal block onto its neighbours.
//! A direction of a diagonal block whose eigenvalue is at most
//! [`TOLERANCE`] is left uncoupled by the others (`H` is positive
//! semi-definite) and is a direction of the null space; back-substitution
//! through the earlier eliminations gives it over every variable, which
//! [`Deficiency`] names.

use std::collections::{BTreeMap, BinaryHeap};
use std::fmt;

use factor_core::{Factor, FactorError};
use nalgebra::{DMatrix, DVector};

use crate::method::{Method, linearize};

/// The eigenvalue, of a normal matrix scaled to a unit diagonal, at or
/// below which a direction counts as undetermined: far above rounding
/// (about 1e-13 for the problems here), far below what any measurement
/// that determines a direction contributes.
pub const TOLERANCE: f64 = 1e-9;

/// The tolerance at the solution of a solve that did not converge: a
/// direction determined this weakly (a residual change of about 3e-4 of
/// the rows' own sensitivities) is where the solve drifts, and names why
/// it did not converge. Measured: `synth-plp --cameras 4` (two walls
/// rotated parallel, a camera translating along them) 8.9e-9 at the 100th
/// iteration; the default rooms of seeds 1–40, which converge, 4.2e-6 to
/// 8.2e-4 (the smallest eigenvalue of any block as it is eliminated).
pub const DRIFT_TOLERANCE: f64 = 1e-7;

/// A free variable, as messages name it.
#[derive(Debug, Clone)]
pub struct Variable {
    /// Its name (`c5`).
    pub name: String,
    /// The names of its tangent coordinates, in column order (`δρ_x`).
    pub columns: Vec<String>,
}

impl Variable {
    /// `name`, a variable whose tangent is described as `tangent` and has
    /// `dim` coordinates ([`tangent_columns`]).
    pub fn new(name: impl Into<String>, tangent: &str, dim: usize) -> Self {
        Variable {
            name: name.into(),
            columns: tangent_columns(tangent, dim),
        }
    }
}

/// `factor`'s Jacobian blocks in its variables' own tangents, one per
/// variable in declaration order, whitened by its square-root information
/// `s` (`S J`): what [`Normal::add`] takes of a factor. Linearized as
/// `Method::Generated` does (dual numbers for a factor without a kernel).
///
/// # Errors
///
/// The factor's validation, or a non-finite Jacobian.
pub fn whitened_blocks<F: Factor>(
    factor: &F,
    s: &DMatrix<f64>,
) -> Result<Vec<DMatrix<f64>>, FactorError> {
    let (linearization, _) = linearize(factor, Method::Generated)?;
    Ok(linearization.jacobians.iter().map(|j| s * j).collect())
}

/// The names of the `dim` coordinates of a tangent described as `tangent`:
/// its `columns [a, b, …]`, or `δ[k]` where it lists none.
pub fn tangent_columns(tangent: &str, dim: usize) -> Vec<String> {
    // `columns [a, b]` or `columns δξ = [a, b]`.
    let listed: Vec<String> = tangent
        .split_once("columns ")
        .and_then(|(_, rest)| rest.split_once('['))
        .and_then(|(_, rest)| rest.split_once(']'))
        .map(|(list, _)| list.split(", ").map(str::to_owned).collect())
        .unwrap_or_default();
    if listed.len() == dim {
        listed
    } else {
        (0..dim).map(|k| format!("δ[{k}]")).collect()
    }
}

/// The normal matrix of a problem being assembled, block by block.
#[derive(Debug)]
pub struct Normal {
    variables: Vec<Variable>,
    /// Per variable: its diagonal block and its off-diagonal blocks by
    /// neighbour (`H_vw`, rows of `v`, columns of `w`).
    diagonal: Vec<DMatrix<f64>>,
    off: Vec<BTreeMap<usize, DMatrix<f64>>>,
}

/// The undetermined directions of a problem.
#[derive(Debug, Clone)]
pub struct Deficiency {
    /// How many independent directions there are.
    pub count: usize,
    /// The first directions found, each over the variables it moves (by
    /// index into the variables, with the move in their coordinates, the
    /// whole of unit norm), largest moves first.
    pub directions: Vec<Vec<(usize, DVector<f64>)>>,
    /// The variables, to name them.
    variables: Vec<Variable>,
    /// The values linearized at, as messages name them.
    values: &'static str,
    /// The tolerance it was found with ([`TOLERANCE`] or
    /// [`DRIFT_TOLERANCE`]).
    tolerance: f64,
}

/// How many directions a [`Deficiency`] spells out.
const SHOWN_DIRECTIONS: usize = 2;
/// How many variables a direction names.
const SHOWN_VARIABLES: usize = 4;
/// A variable moving less than this (of a direction of unit norm) is not
/// named.
const NEGLIGIBLE: f64 = 1e-3;

/// One elimination, kept for back-substitution: the variable, the
/// pseudo-inverse of its diagonal block, and its blocks to the neighbours
/// left at the time.
struct Elimination {
    variable: usize,
    pseudo_inverse: DMatrix<f64>,
    neighbours: Vec<(usize, DMatrix<f64>)>,
}

impl Normal {
    /// An empty normal matrix over `variables` (the free ones).
    pub fn new(variables: Vec<Variable>) -> Self {
        let diagonal = variables
            .iter()
            .map(|v| DMatrix::zeros(v.columns.len(), v.columns.len()))
            .collect();
        let off = variables.iter().map(|_| BTreeMap::new()).collect();
        Normal {
            variables,
            diagonal,
            off,
        }
    }

    /// Adds a factor's whitened Jacobian blocks on free variables, `(index,
    /// rows × tangent)`, all with the same rows.
    ///
    /// Each row is scaled to unit norm first (`unit_rows`): the null space
    /// of `J` does not depend on the rows' weights, and a measurement
    /// weighted 1e8 times its neighbours' (σ = 1e-4 among σ = 1) would
    /// otherwise make the directions only they determine look undetermined
    /// beside its own on the unit diagonal.
    pub fn add(&mut self, mut blocks: Vec<(usize, DMatrix<f64>)>) {
        unit_rows(&mut blocks);
        for (i, (a, ja)) in blocks.iter().enumerate() {
            self.diagonal[*a].gemm_tr(1.0, ja, ja, 1.0);
            for (b, jb) in &blocks[i + 1..] {
                // H_ab += J_aᵀ J_b and H_ba += J_bᵀ J_a, in place.
                accumulate(&mut self.off[*a], *b, 1.0, ja, jb);
                accumulate(&mut self.off[*b], *a, 1.0, jb, ja);
            }
        }
    }

    /// The undetermined directions, if there are any (see the module
    /// documentation).
    pub fn deficiency(self) -> Option<Deficiency> {
        self.deficiency_within(TOLERANCE)
    }

    /// The directions determined no more than `tolerance` ([`TOLERANCE`],
    /// or [`DRIFT_TOLERANCE`] after a solve that did not converge).
    pub fn deficiency_within(mut self, tolerance: f64) -> Option<Deficiency> {
        let scales = self.scale();
        let original = Blocks {
            diagonal: self.diagonal.clone(),
            off: self.off.clone(),
        };
        let mut eliminated = Vec::with_capacity(self.variables.len());
        // Null directions, each as (variable, direction in its scaled
        // coordinates, how many eliminations preceded it).
        let mut null: Vec<(usize, DVector<f64>, usize)> = Vec::new();
        let mut done = vec![false; self.variables.len()];
        let mut queue: BinaryHeap<(std::cmp::Reverse<usize>, usize)> = (0..self.variables.len())
            .map(|v| (std::cmp::Reverse(self.off[v].len()), v))
            .collect();
        while let Some((std::cmp::Reverse(degree), v)) = queue.pop() {
            if done[v] {
                continue;
            }
            if degree != self.off[v].len() {
                queue.push((std::cmp::Reverse(self.off[v].len()), v));
                continue;
            }
            done[v] = true;
            let (pseudo_inverse, directions) = split(&self.diagonal[v], tolerance);
            for u in directions {
                null.push((v, u, eliminated.len()));
            }
            let neighbours: Vec<(usize, DMatrix<f64>)> =
                std::mem::take(&mut self.off[v]).into_iter().collect();
            for (i, (a, h_va)) in neighbours.iter().enumerate() {
                self.off[*a].remove(&v);
                // `P H_va` (P symmetric): H_aa −= H_vaᵀ P H_va, and for
                // each later neighbour H_ab −= (P H_va)ᵀ H_vb, H_ba its
                // transpose, in place.
                let p_h_va = &pseudo_inverse * h_va;
                self.diagonal[*a].gemm_tr(-1.0, h_va, &p_h_va, 1.0);
                for (b, h_vb) in &neighbours[i + 1..] {
                    accumulate(&mut self.off[*a], *b, -1.0, &p_h_va, h_vb);
                    accumulate(&mut self.off[*b], *a, -1.0, h_vb, &p_h_va);
                }
            }
            for (a, _) in &neighbours {
                queue.push((std::cmp::Reverse(self.off[*a].len()), *a));
            }
            eliminated.push(Elimination {
                variable: v,
                pseudo_inverse,
                neighbours,
            });
        }
        // Each candidate is checked against the matrix itself: rounding in
        // the eliminations can leave a block nearly singular where `H` is
        // not (`xᵀ H x` of a true null direction is at most the tolerance).
        let null: Vec<BTreeMap<usize, DVector<f64>>> = null
            .into_iter()
            .map(|(v, u, step)| lift(&eliminated[..step], v, u))
            .filter(|x| original.curvature(x) <= tolerance)
            .collect();
        if null.is_empty() {
            return None;
        }
        let count = null.len();
        let directions = null
            .into_iter()
            .take(SHOWN_DIRECTIONS)
            .map(|x| Self::direction(x, &scales))
            .collect();
        Some(Deficiency {
            count,
            directions,
            variables: self.variables,
            values: "the initial values",
            tolerance,
        })
    }

    /// Scales every coordinate to a unit diagonal; returns the scales (a
    /// coordinate no factor measures keeps a zero diagonal, and its scale
    /// 1: it is a null direction of its block).
    fn scale(&mut self) -> Vec<DVector<f64>> {
        let scales: Vec<DVector<f64>> = self
            .diagonal
            .iter()
            .map(|d| {
                d.diagonal()
                    .map(|x| if x > 0.0 { 1.0 / x.sqrt() } else { 1.0 })
            })
            .collect();
        for (v, d) in self.diagonal.iter_mut().enumerate() {
            scale_block(d, &scales[v], &scales[v]);
        }
        for (v, off) in self.off.iter_mut().enumerate() {
            for (w, h) in off.iter_mut() {
                scale_block(h, &scales[v], &scales[*w]);
            }
        }
        scales
    }

    /// A null direction over every variable (scaled coordinates,
    /// [`lift`]), unscaled, of unit norm, its moves largest first.
    fn direction(
        x: BTreeMap<usize, DVector<f64>>,
        scales: &[DVector<f64>],
    ) -> Vec<(usize, DVector<f64>)> {
        let mut moves: Vec<(usize, DVector<f64>)> = x
            .into_iter()
            .map(|(w, xw)| (w, xw.component_mul(&scales[w])))
            .collect();
        let norm = moves
            .iter()
            .map(|(_, m)| m.norm_squared())
            .sum::<f64>()
            .sqrt();
        for (_, m) in &mut moves {
            *m /= norm;
        }
        moves.retain(|(_, m)| m.norm() >= NEGLIGIBLE);
        moves.sort_by(|a, b| b.1.norm().total_cmp(&a.1.norm()));
        moves
    }
}

/// `h ← diag(rows) · h · diag(columns)`, in place.
fn scale_block(h: &mut DMatrix<f64>, rows: &DVector<f64>, columns: &DVector<f64>) {
    for (j, mut column) in h.column_iter_mut().enumerate() {
        for (x, r) in column.iter_mut().zip(rows.iter()) {
            *x = *x * r * columns[j];
        }
    }
}

/// Scales each row of a factor's blocks (all with the same rows) to unit
/// norm over the blocks, in place; a row shorter than [`ROW_FLOOR`] times
/// the factor's longest is scaled as if it were that long, so that a row of
/// rounding (a component the free variables do not move) stays negligible.
fn unit_rows(blocks: &mut [(usize, DMatrix<f64>)]) {
    let rows = blocks.first().map_or(0, |(_, j)| j.nrows());
    let norms: Vec<f64> = (0..rows)
        .map(|r| {
            blocks
                .iter()
                .map(|(_, j)| factor_core::linalg::scaled_norm(&j.row(r)))
                .fold(0.0, f64::hypot)
        })
        .collect();
    let longest = norms.iter().copied().fold(0.0, f64::max);
    for (_, j) in blocks.iter_mut() {
        for (r, norm) in norms.iter().enumerate() {
            let norm = norm.max(ROW_FLOOR * longest);
            if norm > 0.0 && norm.is_finite() {
                j.row_mut(r).unscale_mut(norm);
            }
        }
    }
}

/// The shortest row, relative to its factor's longest, that [`unit_rows`]
/// scales to unit norm: far above rounding, below any ratio of two noise
/// levels in one factor that a file would give.
const ROW_FLOOR: f64 = 1.0;

/// `off[at] += alpha · xᵀ y`, the block created (zero) if new.
fn accumulate(
    off: &mut BTreeMap<usize, DMatrix<f64>>,
    at: usize,
    alpha: f64,
    x: &DMatrix<f64>,
    y: &DMatrix<f64>,
) {
    off.entry(at)
        .or_insert_with(|| DMatrix::zeros(x.ncols(), y.ncols()))
        .gemm_tr(alpha, x, y, 1.0);
}

/// The blocks of a normal matrix (scaled), kept to check candidates.
struct Blocks {
    diagonal: Vec<DMatrix<f64>>,
    off: Vec<BTreeMap<usize, DMatrix<f64>>>,
}

impl Blocks {
    /// `xᵀ H x / xᵀ x` for the direction `x` (by variable; absent ones
    /// zero).
    fn curvature(&self, x: &BTreeMap<usize, DVector<f64>>) -> f64 {
        let mut quadratic = 0.0;
        for (v, xv) in x {
            quadratic += xv.dot(&(&self.diagonal[*v] * xv));
            for (w, h) in &self.off[*v] {
                if let Some(xw) = x.get(w) {
                    quadratic += xv.dot(&(h * xw));
                }
            }
        }
        quadratic / x.values().map(DVector::norm_squared).sum::<f64>()
    }
}

/// The null direction found at `v` (direction `u`, scaled coordinates)
/// over every variable: zero on those eliminated after `v`,
/// back-substituted through the `earlier` eliminations.
fn lift(earlier: &[Elimination], v: usize, u: DVector<f64>) -> BTreeMap<usize, DVector<f64>> {
    let mut x: BTreeMap<usize, DVector<f64>> = BTreeMap::from([(v, u)]);
    for step in earlier.iter().rev() {
        let mut sum = DVector::zeros(step.pseudo_inverse.nrows());
        for (a, h_va) in &step.neighbours {
            if let Some(xa) = x.get(a) {
                sum += h_va * xa;
            }
        }
        x.insert(step.variable, -(&step.pseudo_inverse * sum));
    }
    x
}

/// The pseudo-inverse of the symmetric block `d` on its determined
/// directions, and its undetermined ones (eigenvalue at most
/// `tolerance`).
fn split(d: &DMatrix<f64>, tolerance: f64) -> (DMatrix<f64>, Vec<DVector<f64>>) {
    let n = d.nrows();
    let eigen = nalgebra::SymmetricEigen::new(d.clone());
    let mut pseudo_inverse = DMatrix::zeros(n, n);
    let mut null = Vec::new();
    for (k, lambda) in eigen.eigenvalues.iter().enumerate() {
        let u = eigen.eigenvectors.column(k).into_owned();
        if *lambda > tolerance {
            pseudo_inverse += &u * u.transpose() / *lambda;
        } else {
            null.push(u);
        }
    }
    (pseudo_inverse, null)
}

impl fmt::Display for Deficiency {
    /// One line: how many directions, and what the first ones move.
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        let (plural, verb) = if self.count == 1 {
            ("", "s")
        } else {
            ("s", "")
        };
        if self.tolerance > TOLERANCE {
            write!(
                f,
                "not observable: {} direction{plural} of the free variables change{verb} every \
                 residual by less than 3e-4 of its sensitivity at {}, where the solve stopped \
                 unconverged: it drifts along them (a gauge left free, or too few measurements)",
                self.count, self.values,
            )?;
        } else {
            write!(
                f,
                "not observable: {} direction{plural} of the free variables leave{verb} every \
                 residual unchanged to first order at {} (a gauge left free, or too few \
                 measurements)",
                self.count, self.values,
            )?;
        }
        for (k, direction) in self.directions.iter().enumerate() {
            let moves: Vec<String> = direction
                .iter()
                .take(SHOWN_VARIABLES)
                .map(|(v, m)| self.shown(*v, m))
                .collect();
            let more = direction.len().saturating_sub(SHOWN_VARIABLES);
            write!(
                f,
                "; {} moves {}{}",
                if k == 0 { "one" } else { "another" },
                moves.join(", "),
                if more > 0 {
                    format!(
                        " and {more} more variable{}",
                        if more == 1 { "" } else { "s" }
                    )
                } else {
                    String::new()
                }
            )?;
        }
        Ok(())
    }
}

impl Deficiency {
    /// The same, found at `values` (`the true values`; by default `the
    /// initial values`).
    pub fn at(mut self, values: &'static str) -> Self {
        self.values = values;
        self
    }

    /// `c5 along δρ_x 0.71, δρ_z −0.70`: a variable and its largest moves.
    fn shown(&self, v: usize, m: &DVector<f64>) -> String {
        let variable = &self.variables[v];
        let mut parts: Vec<(usize, f64)> = m.iter().copied().enumerate().collect();
        parts.sort_by(|a, b| b.1.abs().total_cmp(&a.1.abs()));
        let largest = parts[0].1.abs();
        let named: Vec<String> = parts
            .iter()
            .filter(|(_, x)| x.abs() >= 0.3 * largest)
            .take(3)
            .map(|(k, x)| format!("{} {x:.2}", variable.columns[*k]))
            .collect();
        format!("{} along {}", variable.name, named.join(" "))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn variable(name: &str, dim: usize) -> Variable {
        Variable {
            name: name.into(),
            columns: (0..dim).map(|k| format!("x{k}")).collect(),
        }
    }

    /// Two scalars measured only through their difference: the direction
    /// `[1, 1] / √2` moves both; measured alone too, none.
    #[test]
    fn a_difference_alone_leaves_the_sum_free() {
        let one = |x: f64| DMatrix::from_element(1, 1, x);
        let mut normal = Normal::new(vec![variable("a", 1), variable("b", 1)]);
        normal.add(vec![(0, one(1.0)), (1, one(-1.0))]);
        let deficiency = normal.deficiency().expect("a free direction");
        assert_eq!(deficiency.count, 1);
        let direction = &deficiency.directions[0];
        assert_eq!(direction.len(), 2);
        for (_, m) in direction {
            assert!((m[0].abs() - 0.5_f64.sqrt()).abs() < 1e-12, "{m}");
        }
        assert_eq!(direction[0].1[0], direction[1].1[0]);
        let message = deficiency.to_string();
        assert!(
            message.contains("1 direction of the free variables leaves"),
            "{message}"
        );
        assert!(message.contains("moves a along x0 "), "{message}");

        let mut normal = Normal::new(vec![variable("a", 1), variable("b", 1)]);
        normal.add(vec![(0, one(1.0)), (1, one(-1.0))]);
        normal.add(vec![(1, one(3.0))]);
        assert!(normal.deficiency().is_none());
    }

    /// A chain of 2-D points measured by their differences, the first
    /// measured alone in x only: the y of the whole chain is free, and is
    /// found whatever the order of elimination; an unmeasured coordinate
    /// is a direction too.
    #[test]
    fn a_chain_free_along_one_axis_is_found_over_every_link() {
        let n = 30;
        let mut normal = Normal::new((0..n).map(|k| variable(&format!("p{k}"), 2)).collect());
        let identity = DMatrix::<f64>::identity(2, 2) * 2.0;
        for k in 0..n - 1 {
            normal.add(vec![(k, identity.clone()), (k + 1, -identity.clone())]);
        }
        normal.add(vec![(0, DMatrix::from_row_slice(1, 2, &[5.0, 0.0]))]);
        let deficiency = normal.deficiency().expect("y free");
        assert_eq!(deficiency.count, 1);
        let direction = &deficiency.directions[0];
        assert_eq!(direction.len(), n);
        let each = 1.0 / (n as f64).sqrt();
        for (_, m) in direction {
            assert!(m[0].abs() < 1e-9, "{m}");
            assert!((m[1].abs() - each).abs() < 1e-9, "{m}");
        }

        let mut normal = Normal::new(vec![variable("q", 3)]);
        normal.add(vec![(
            0,
            DMatrix::from_row_slice(2, 3, &[1.0, 2.0, 0.0, 0.0, 1.0, 0.0]),
        )]);
        let deficiency = normal.deficiency().expect("z unmeasured");
        assert_eq!(deficiency.count, 1);
        assert!(
            deficiency.to_string().contains("q along x2 "),
            "{deficiency}"
        );
    }

    /// Scaling a block in place gives the bits of `diag(r) · h · diag(c)`.
    #[test]
    fn a_block_scaled_in_place_is_the_product_with_the_diagonals() {
        let h = DMatrix::from_fn(3, 2, |i, j| (i as f64 + 0.3).powi(3) - 1.7 * j as f64);
        let rows = DVector::from_column_slice(&[0.1, 3.7, 1e-5]);
        let columns = DVector::from_column_slice(&[2.3e4, 0.77]);
        let product = DMatrix::from_diagonal(&rows) * &h * DMatrix::from_diagonal(&columns);
        let mut scaled = h.clone();
        scale_block(&mut scaled, &rows, &columns);
        assert_eq!(scaled, product);
    }

    /// A point measured tightly (weight 1e4, σ = 1e-4) across a ray and
    /// loosely (weight 1) along it is determined, whatever the weights: the
    /// loose row moves `[−0.1, −0.1, 1]` by 0.05 of its length, which on a
    /// unit diagonal dominated by the tight rows was a curvature of about
    /// 1e-11, below the tolerance. A row of rounding (1e-17 of its factor's
    /// other row) is not scaled up to determine a direction.
    #[test]
    fn weights_do_not_decide_what_is_determined() {
        let tight = DMatrix::from_row_slice(2, 3, &[1.0, 0.0, 0.1, 0.0, 1.0, 0.1]) * 1e4;
        let loose = DMatrix::from_row_slice(1, 3, &[1.0, 0.0, 0.05]);
        for scale in [1.0, 1e-80, 1e80] {
            let mut normal = Normal::new(vec![variable("q", 3)]);
            normal.add(vec![(0, &tight * scale)]);
            normal.add(vec![(0, &loose * scale)]);
            assert!(normal.deficiency().is_none(), "scale {scale}");
        }

        // y − z measured, y + z only by the rounding row: still free.
        let mut normal = Normal::new(vec![variable("q", 3)]);
        normal.add(vec![(
            0,
            DMatrix::from_row_slice(2, 3, &[1.0, 0.0, 0.0, 0.0, 1e-17, 1e-17]),
        )]);
        normal.add(vec![(0, DMatrix::from_row_slice(1, 3, &[0.0, 1.0, -1.0]))]);
        assert_eq!(normal.deficiency().map(|d| d.count), Some(1));
    }
}
