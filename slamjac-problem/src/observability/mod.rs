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

mod blocks;
mod elimination;

use std::collections::BTreeMap;
use std::fmt;

use nalgebra::{DMatrix, DVector};

use self::blocks::{Blocks, add_product, transpose};
pub use self::elimination::Plan;

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
    blocks: Blocks,
    /// Room for a factor's blocks column-major ([`Normal::add_rows`]).
    columns: Vec<f64>,
    /// The plan of an earlier check of the same factors, its layout the
    /// blocks' ([`Normal::planned`]); `stale` once a factor joined a pair
    /// it did not have.
    plan: Option<Plan>,
    stale: bool,
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

impl Normal {
    /// An empty normal matrix over `variables` (the free ones).
    pub fn new(variables: Vec<Variable>) -> Self {
        let dims = variables.iter().map(|v| v.columns.len()).collect();
        Normal {
            variables,
            blocks: Blocks::new(dims),
            columns: Vec::new(),
            plan: None,
            stale: false,
        }
    }

    /// An empty normal matrix over `variables`, laid out as `plan` (made
    /// by [`Normal::deficiency_planned`]) says, to be eliminated as it
    /// says: the same factors are to be added (on the same variables, at
    /// other values). Where a factor joins a pair the plan does not have,
    /// or `variables` are not those of the plan (their number or
    /// dimensions), the elimination is searched for anew.
    pub fn planned(variables: Vec<Variable>, mut plan: Plan) -> Self {
        let dims: Vec<usize> = variables.iter().map(|v| v.columns.len()).collect();
        if dims != plan.dims {
            return Normal::new(variables);
        }
        let blocks = Blocks::laid_out(dims, std::mem::take(&mut plan.off), plan.after);
        Normal {
            variables,
            blocks,
            columns: Vec::new(),
            plan: Some(plan),
            stale: false,
        }
    }

    /// Adds a factor's whitened Jacobian blocks on free variables, `(index,
    /// rows × tangent)`, all with the same rows ([`Normal::add_rows`]).
    pub fn add(&mut self, blocks: Vec<(usize, DMatrix<f64>)>) {
        let rows = blocks.first().map_or(0, |(_, j)| j.nrows());
        let variables: Vec<usize> = blocks.iter().map(|(v, _)| *v).collect();
        let mut jacobian = vec![0.0; blocks.iter().map(|(_, j)| j.len()).sum()];
        let mut start = 0;
        for (_, j) in &blocks {
            transpose(j.as_slice(), rows, &mut jacobian[start..start + j.len()]);
            start += j.len();
        }
        self.add_rows(rows, &variables, &mut jacobian);
    }

    /// Adds a factor's whitened Jacobian on the free `variables`:
    /// `jacobian` holds their blocks end to end, each `rows` × the
    /// variable's dimension, row-major.
    ///
    /// Each row is scaled to unit norm first, in place (`unit_rows`): the
    /// null space of `J` does not depend on the rows' weights, and a
    /// measurement weighted 1e8 times its neighbours' (σ = 1e-4 among
    /// σ = 1) would otherwise make the directions only they determine look
    /// undetermined beside its own on the unit diagonal.
    pub fn add_rows(&mut self, rows: usize, variables: &[usize], jacobian: &mut [f64]) {
        let h = &mut self.blocks;
        let dims: Vec<usize> = variables.iter().map(|v| h.dims[*v]).collect();
        unit_rows(rows, &dims, jacobian);
        // Each block column-major too (its transpose as stored), end to
        // end: a row-major block is its transpose column-major.
        let columns = &mut self.columns;
        columns.resize(jacobian.len(), 0.0);
        let mut starts = Vec::with_capacity(dims.len());
        let mut start = 0;
        for d in &dims {
            let end = start + rows * d;
            transpose(&jacobian[start..end], *d, &mut columns[start..end]);
            starts.push(start..end);
            start = end;
        }
        for (i, &a) in variables.iter().enumerate() {
            let (ja_t, ja) = (&jacobian[starts[i].clone()], &columns[starts[i].clone()]);
            let at = h.diagonal(a);
            add_product(&mut h.values[at..], 1.0, ja_t, ja, dims[i]);
            for (k, &b) in variables.iter().enumerate().skip(i + 1) {
                let (jb_t, jb) = (&jacobian[starts[k].clone()], &columns[starts[k].clone()]);
                if a == b {
                    // One variable given twice: both products on its
                    // diagonal.
                    add_product(&mut h.values[at..], 1.0, ja_t, jb, dims[i]);
                    add_product(&mut h.values[at..], 1.0, jb_t, ja, dims[i]);
                    continue;
                }
                // H_ab += J_aᵀ J_b, stored as the lower index's rows.
                let (low_t, high, height) = if a < b {
                    (ja_t, jb, dims[i])
                } else {
                    (jb_t, ja, dims[k])
                };
                let (pair, created) = h.pair(a, b);
                self.stale |= created && self.plan.is_some();
                add_product(&mut h.values[pair..], 1.0, low_t, high, height);
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
    pub fn deficiency_within(self, tolerance: f64) -> Option<Deficiency> {
        self.deficiency_planned(tolerance).0
    }

    /// [`Normal::deficiency_within`], and the plan of the elimination: the
    /// order and structure a check of the same factors at other values
    /// repeats ([`Normal::planned`]).
    pub fn deficiency_planned(mut self, tolerance: f64) -> (Option<Deficiency>, Plan) {
        let plan = self.plan.take().filter(|_| !self.stale);
        let mut original = Vec::new();
        if plan.is_none() {
            // The blocks laid out in the order of the first eliminations
            // (the least connected first, which the eliminations of
            // variables of no common neighbour, landmarks', keep).
            let h = &mut self.blocks;
            let mut order: Vec<usize> = (0..h.dims.len()).collect();
            order.sort_by_key(|&v| (h.off[v].len(), std::cmp::Reverse(v)));
            original = h.repack(&order);
        }
        let scales = self.scale();
        // The scaled matrix, for the candidates' test (in the memory the
        // old layout leaves): the blocks the eliminations create come
        // after its end.
        let before = plan.as_ref().map_or(self.blocks.values.len(), |p| p.before);
        original.clear();
        original.extend_from_slice(&self.blocks.values[..before]);
        let eliminated = match plan {
            Some(plan) => elimination::replay(&mut self.blocks, plan, tolerance),
            None => elimination::fresh(&mut self.blocks, tolerance),
        };
        // Each candidate is checked against the matrix itself: rounding in
        // the eliminations can leave a block nearly singular where `H` is
        // not (`xᵀ H x` of a true null direction is at most the tolerance).
        let h = &self.blocks;
        let null: Vec<BTreeMap<usize, DVector<f64>>> = eliminated
            .found
            .null
            .iter()
            .map(|(v, u, step)| eliminated.lift(h, *step, *v, u.clone()))
            .filter(|x| eliminated.curvature(h, &original, x) <= tolerance)
            .collect();
        let plan = eliminated.plan;
        if null.is_empty() {
            return (None, plan);
        }
        let count = null.len();
        let directions = null
            .into_iter()
            .take(SHOWN_DIRECTIONS)
            .map(|x| Self::direction(x, &scales))
            .collect();
        let deficiency = Deficiency {
            count,
            directions,
            variables: self.variables,
            values: "the initial values",
            tolerance,
        };
        (Some(deficiency), plan)
    }

    /// Scales every coordinate to a unit diagonal; returns the scales (a
    /// coordinate no factor measures keeps a zero diagonal, and its scale
    /// 1: it is a null direction of its block).
    fn scale(&mut self) -> Vec<DVector<f64>> {
        let h = &self.blocks;
        let scales: Vec<DVector<f64>> = (0..h.dims.len())
            .map(|v| {
                let (d, at) = (h.dims[v], h.diagonal(v));
                DVector::from_fn(d, |i, _| {
                    let x = h.values[at + i * (d + 1)];
                    if x > 0.0 { 1.0 / x.sqrt() } else { 1.0 }
                })
            })
            .collect();
        self.blocks.scale(&scales);
        scales
    }

    /// A null direction over every variable (scaled coordinates,
    /// back-substituted), unscaled, of unit norm, its moves largest first.
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

/// Scales each row of a factor's blocks (`rows` × each of `dims`,
/// row-major, end to end in `jacobian`) to unit norm over the blocks, in
/// place; a row shorter than [`ROW_FLOOR`] times the factor's longest is
/// scaled as if it were that long, so that a row of rounding (a component
/// the free variables do not move) stays negligible.
fn unit_rows(rows: usize, dims: &[usize], jacobian: &mut [f64]) {
    let mut norms = vec![0.0_f64; rows];
    let mut start = 0;
    for d in dims {
        for (r, norm) in norms.iter_mut().enumerate() {
            let row = start + r * d..start + (r + 1) * d;
            *norm = norm.hypot(scaled_norm(&jacobian[row]));
        }
        start += rows * d;
    }
    let longest = norms.iter().copied().fold(0.0, f64::max);
    let mut start = 0;
    for d in dims {
        for (r, norm) in norms.iter().enumerate() {
            let norm = norm.max(ROW_FLOOR * longest);
            if norm > 0.0 && norm.is_finite() {
                for x in &mut jacobian[start + r * d..start + (r + 1) * d] {
                    *x /= norm;
                }
            }
        }
        start += rows * d;
    }
}

/// `‖v‖` of any magnitude: its largest magnitude times the norm of `v`
/// divided by it (as `factor_core::linalg::scaled_norm`).
fn scaled_norm(v: &[f64]) -> f64 {
    let largest = v.iter().fold(0.0_f64, |m, x| m.max(x.abs()));
    if largest > 0.0 && largest.is_finite() {
        largest * v.iter().map(|x| (x / largest).powi(2)).sum::<f64>().sqrt()
    } else {
        largest
    }
}

/// The shortest row, relative to its factor's longest, that [`unit_rows`]
/// scales to unit norm: far above rounding, below any ratio of two noise
/// levels in one factor that a file would give.
const ROW_FLOOR: f64 = 1.0;

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

    /// A check planned by an earlier one of the same factors eliminates
    /// as a fresh check at the new values does: the same directions, bit
    /// for bit. A factor joining a pair the plan lacks makes it search
    /// anew, as a fresh check of those factors does.
    #[test]
    fn a_plan_repeats_the_elimination_at_other_values() {
        // A ring of 2-D points measured by their differences (scaled by
        // `at`), the first pinned along x: y is free; `extra` joins 0 and 5.
        let n = 12;
        let variables = || {
            (0..n)
                .map(|k| variable(&format!("p{k}"), 2))
                .collect::<Vec<_>>()
        };
        let add = |normal: &mut Normal, at: f64, extra: bool| {
            for k in 0..n {
                let weight = DMatrix::from_row_slice(2, 2, &[1.0 + at * k as f64, at, 0.0, 1.0]);
                normal.add(vec![(k, weight.clone()), ((k + 1) % n, -weight)]);
            }
            normal.add(vec![(0, DMatrix::from_row_slice(1, 2, &[1.0, 0.0]))]);
            if extra {
                let identity = DMatrix::<f64>::identity(2, 2);
                normal.add(vec![(0, identity.clone()), (5, -identity)]);
            }
        };
        let mut first = Normal::new(variables());
        add(&mut first, 0.3, false);
        let (found, plan) = first.deficiency_planned(TOLERANCE);
        assert_eq!(found.map(|d| d.count), Some(1));
        for extra in [false, true] {
            let mut fresh = Normal::new(variables());
            add(&mut fresh, 0.7, extra);
            let expected = fresh.deficiency().expect("y free");
            let mut planned = Normal::planned(variables(), plan.clone());
            add(&mut planned, 0.7, extra);
            assert_eq!(planned.stale, extra);
            let found = planned.deficiency().expect("y free");
            assert_eq!(found.count, expected.count);
            assert_eq!(found.directions, expected.directions, "extra pair: {extra}");
        }
        // A plan of other variables (one fewer, or another dimension) is not
        // followed: the check searches anew and finds what a fresh one finds.
        for others in [
            (0..n - 1)
                .map(|k| variable(&format!("p{k}"), 2))
                .collect::<Vec<_>>(),
            (0..n)
                .map(|k| variable(&format!("p{k}"), if k == 3 { 3 } else { 2 }))
                .collect(),
        ] {
            let mut planned = Normal::planned(others.clone(), plan.clone());
            assert!(planned.plan.is_none());
            let mut fresh = Normal::new(others);
            for normal in [&mut planned, &mut fresh] {
                normal.add(vec![(0, DMatrix::from_row_slice(1, 2, &[1.0, 0.0]))]);
            }
            assert_eq!(
                planned.deficiency().map(|d| (d.count, d.directions)),
                fresh.deficiency().map(|d| (d.count, d.directions))
            );
        }
    }
}
