//! The elimination of a scaled normal matrix ([`Blocks`]) variable by
//! variable: the least connected first ([`fresh`]: the least degree, among
//! equal degrees the highest index), or in the order and structure an
//! earlier elimination of the same factors found ([`replay`] of its
//! [`Plan`]: the order depends on the structure alone, so the same factors
//! at other values are eliminated alike, without the search). Each step
//! takes the Schur complement of the variable's diagonal block onto its
//! neighbours; the directions of the block with an eigenvalue at most the
//! tolerance are candidates for the null space, back-substituted through
//! the earlier steps by [`Eliminated::lift`].

use std::collections::{BTreeMap, BinaryHeap};
use std::ops::Range;

use nalgebra::{DMatrix, DVector};

use super::blocks::{Blocks, add_product, transpose};

/// The order and the structure of an elimination, made by
/// [`Normal::deficiency_planned`](super::Normal::deficiency_planned) and
/// followed by a [`Normal::planned`](super::Normal::planned) over the same
/// variables.
#[derive(Debug, Clone)]
pub struct Plan {
    steps: Vec<Step>,
    /// Each step's neighbours left at the time, with their pair's block.
    neighbours: Vec<(usize, usize)>,
    /// The blocks of each step's pairs of neighbours, in the order updated.
    pairs: Vec<usize>,
    /// The structure before the eliminations ([`Blocks::off`]), to lay a
    /// matrix of the same factors out alike (`Normal::planned`).
    pub(super) off: Vec<Vec<(usize, usize)>>,
    /// The dimensions of the variables it was made over.
    pub(super) dims: Vec<usize>,
    /// The length of the blocks' values before the eliminations (the
    /// matrix itself) and after (with the blocks they created).
    pub(super) before: usize,
    pub(super) after: usize,
}

/// One step of a [`Plan`]: the variable and its ranges of the plan's
/// `neighbours` and `pairs`.
#[derive(Debug, Clone)]
struct Step {
    variable: usize,
    neighbours: Range<usize>,
    pairs: Range<usize>,
}

/// An elimination done: its plan and what its steps found.
pub(super) struct Eliminated {
    pub(super) plan: Plan,
    pub(super) found: Found,
}

/// What the steps of an elimination found: each step's pseudo-inverse of
/// its diagonal block, and the candidate null directions, each as
/// (variable, direction in its scaled coordinates, how many steps preceded
/// it).
#[derive(Default)]
pub(super) struct Found {
    pseudo_inverses: Vec<DMatrix<f64>>,
    pub(super) null: Vec<(usize, DVector<f64>, usize)>,
}

/// Room for one step: per neighbour `a` of the variable `v` eliminated,
/// `H_va` and `(P H_va)ᵀ` (column-major) end to end, where each starts, and
/// one `H_av`.
#[derive(Default)]
struct Scratch {
    h_v: Vec<f64>,
    p_h_v: Vec<f64>,
    starts: Vec<usize>,
    h_av: Vec<f64>,
}

/// Eliminates every variable of `h`, the least connected first.
pub(super) fn fresh(h: &mut Blocks, tolerance: f64) -> Eliminated {
    let n = h.dims.len();
    let mut plan = Plan {
        off: h.off.clone(),
        dims: h.dims.clone(),
        before: h.values.len(),
        steps: Vec::new(),
        neighbours: Vec::new(),
        pairs: Vec::new(),
        after: 0,
    };
    let mut found = Found::default();
    let mut done = vec![false; n];
    // Each variable's neighbours not eliminated yet (an eliminated one
    // stays in the lists, marked `done`).
    let mut degree: Vec<usize> = h.off.iter().map(Vec::len).collect();
    let mut queue: BinaryHeap<(std::cmp::Reverse<usize>, usize)> =
        (0..n).map(|v| (std::cmp::Reverse(degree[v]), v)).collect();
    let mut scratch = Scratch::default();
    while let Some((std::cmp::Reverse(d), v)) = queue.pop() {
        if done[v] {
            continue;
        }
        if d != degree[v] {
            queue.push((std::cmp::Reverse(degree[v]), v));
            continue;
        }
        done[v] = true;
        let start = plan.neighbours.len();
        plan.neighbours.extend(
            std::mem::take(&mut h.off[v])
                .into_iter()
                .filter(|(a, _)| !done[*a]),
        );
        let neighbours = &plan.neighbours[start..];
        for &(a, _) in neighbours {
            degree[a] -= 1;
        }
        // The pairs of each neighbour with the later ones, found by
        // galloping along its list (created where new).
        let pairs_start = plan.pairs.len();
        let (mut row, mut from) = (usize::MAX, 0);
        let pairs = &mut plan.pairs;
        step(
            h,
            v,
            neighbours,
            tolerance,
            &mut scratch,
            &mut found,
            |h, i, a, b| {
                if i != row {
                    (row, from) = (i, 0);
                }
                let (pair, created, k) = h.pair_from(a, b, from);
                from = k;
                if created {
                    degree[a] += 1;
                    degree[b] += 1;
                }
                pairs.push(pair);
                pair
            },
        );
        for &(a, _) in neighbours {
            queue.push((std::cmp::Reverse(degree[a]), a));
        }
        plan.steps.push(Step {
            variable: v,
            neighbours: start..plan.neighbours.len(),
            pairs: pairs_start..plan.pairs.len(),
        });
    }
    plan.after = h.values.len();
    Eliminated { plan, found }
}

/// Eliminates every variable of `h` as `plan` says (`h` laid out as it
/// was, [`Blocks::laid_out`]).
pub(super) fn replay(h: &mut Blocks, plan: Plan, tolerance: f64) -> Eliminated {
    let mut found = Found::default();
    let mut scratch = Scratch::default();
    for s in &plan.steps {
        let neighbours = &plan.neighbours[s.neighbours.clone()];
        let mut pairs = plan.pairs[s.pairs.clone()].iter();
        step(
            h,
            s.variable,
            neighbours,
            tolerance,
            &mut scratch,
            &mut found,
            |_, _, _, _| *pairs.next().expect("the plan holds each step's pairs"),
        );
    }
    Eliminated { plan, found }
}

/// Eliminates `v`, whose neighbours are `neighbours`, into `found`: its
/// diagonal block split (its pseudo-inverse `P` kept, its null directions
/// recorded), then `H_aa −= (P H_va)ᵀ H_va` and, for each later neighbour
/// `b`, `H_ab −= (P H_va)ᵀ H_vb` in place, the block of the pair of
/// neighbours `i < j` (`a`, `b`) at `pair(h, i, a, b)`.
fn step(
    h: &mut Blocks,
    v: usize,
    neighbours: &[(usize, usize)],
    tolerance: f64,
    scratch: &mut Scratch,
    found: &mut Found,
    mut pair: impl FnMut(&mut Blocks, usize, usize, usize) -> usize,
) {
    let dv = h.dims[v];
    let at = h.diagonal(v);
    let diagonal = DMatrix::from_column_slice(dv, dv, &h.values[at..at + dv * dv]);
    let (pseudo_inverse, directions) = split(&diagonal, tolerance);
    let steps = found.pseudo_inverses.len();
    found
        .null
        .extend(directions.into_iter().map(|u| (v, u, steps)));
    let Scratch {
        h_v,
        p_h_v,
        starts,
        h_av,
    } = scratch;
    h_v.clear();
    p_h_v.clear();
    starts.clear();
    for &(a, at) in neighbours {
        let (start, da) = (h_v.len(), h.dims[a]);
        starts.push(start);
        h_v.resize(start + dv * da, 0.0);
        h.rows_of(&h.values, v, a, at, &mut h_v[start..]);
        // (P H_va)ᵀ = H_av P (P symmetric).
        h_av.resize(dv * da, 0.0);
        transpose(&h_v[start..], dv, h_av);
        p_h_v.resize(start + dv * da, 0.0);
        add_product(
            &mut p_h_v[start..],
            1.0,
            h_av,
            pseudo_inverse.as_slice(),
            da,
        );
    }
    for (i, &(a, _)) in neighbours.iter().enumerate() {
        let (start, da) = (starts[i], h.dims[a]);
        let (h_va, p_h_va) = (&h_v[start..start + dv * da], &p_h_v[start..start + dv * da]);
        let at = h.diagonal(a);
        add_product(&mut h.values[at..], -1.0, p_h_va, h_va, da);
        for (j, &(b, _)) in neighbours.iter().enumerate().skip(i + 1) {
            let h_vb = &h_v[starts[j]..starts[j] + dv * h.dims[b]];
            let at = pair(h, i, a, b);
            add_product(&mut h.values[at..], -1.0, p_h_va, h_vb, da);
        }
    }
    found.pseudo_inverses.push(pseudo_inverse);
}

impl Eliminated {
    /// The steps, each with its variable, pseudo-inverse and neighbours.
    fn steps(
        &self,
    ) -> impl DoubleEndedIterator<Item = (usize, &DMatrix<f64>, &[(usize, usize)])> + ExactSizeIterator
    {
        self.plan
            .steps
            .iter()
            .zip(&self.found.pseudo_inverses)
            .map(|(step, p)| {
                (
                    step.variable,
                    p,
                    &self.plan.neighbours[step.neighbours.clone()],
                )
            })
    }

    /// The null direction found at `v` after `step` steps (direction `u`,
    /// scaled coordinates) over every variable: zero on those eliminated
    /// after `v`, back-substituted through the earlier steps (their blocks
    /// in `h`, which no later step changes).
    pub(super) fn lift(
        &self,
        h: &Blocks,
        step: usize,
        v: usize,
        u: DVector<f64>,
    ) -> BTreeMap<usize, DVector<f64>> {
        let mut x: BTreeMap<usize, DVector<f64>> = BTreeMap::from([(v, u)]);
        for (w, pseudo_inverse, neighbours) in self.steps().take(step).rev() {
            let mut sum = DVector::zeros(pseudo_inverse.nrows());
            for &(a, pair) in neighbours {
                if let Some(xa) = x.get(&a) {
                    sum += block(h, &h.values, w, a, pair) * xa;
                }
            }
            x.insert(w, -(pseudo_inverse * sum));
        }
        x
    }

    /// `xᵀ H x / xᵀ x` for the direction `x` (by variable; absent ones
    /// zero), `H` the scaled matrix `original` (laid out as `h`): its
    /// pairs are those of the steps' neighbours (each pair is one of them,
    /// at the first of its two eliminations) whose blocks lie within it.
    pub(super) fn curvature(
        &self,
        h: &Blocks,
        original: &[f64],
        x: &BTreeMap<usize, DVector<f64>>,
    ) -> f64 {
        let mut quadratic = 0.0;
        for (v, xv) in x {
            let (d, at) = (h.dims[*v], h.diagonal(*v));
            let diagonal = DMatrix::from_column_slice(d, d, &original[at..at + d * d]);
            quadratic += xv.dot(&(diagonal * xv));
        }
        for (v, _, neighbours) in self.steps() {
            let Some(xv) = x.get(&v) else {
                continue;
            };
            for &(a, pair) in neighbours {
                if let Some(xa) = x.get(&a)
                    && pair < original.len()
                {
                    quadratic += 2.0 * xv.dot(&(block(h, original, v, a, pair) * xa));
                }
            }
        }
        quadratic / x.values().map(DVector::norm_squared).sum::<f64>()
    }
}

/// `H_vw` (the rows of `v`) of the pair's block at `pair` in `values`
/// (the blocks' values, or a copy of them).
fn block(h: &Blocks, values: &[f64], v: usize, w: usize, pair: usize) -> DMatrix<f64> {
    let mut block = DMatrix::zeros(h.dims[v], h.dims[w]);
    h.rows_of(values, v, w, pair, block.as_mut_slice());
    block
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
