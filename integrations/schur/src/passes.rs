//! The solver's passes over every factor and variable, split among the
//! threads by a [`Partition`]: evaluating the cost, linearizing into the
//! normal equations, and retracting the variables by a step.

use std::time::Duration;

use rayon::prelude::*;
use slam_problems::Robust;

use crate::group::{Rejected, Values};
use crate::partition::{Partition, split_at_bounds};
use crate::problem::Problem;
use crate::robust;
use crate::schur::{Normal, StepBuffers};
use crate::sink::Sink;
use crate::structure::{Role, Structure};

/// `Σ ½ ρ(‖rᵢ‖²)` at `values`, each factor's `‖rᵢ‖²` kept in `squared` (one
/// vector per group, in its factors' order): NaN when a factor rejects its
/// configuration (counted in the returned record).
pub(crate) fn evaluate(
    problem: &Problem,
    values: Values<'_>,
    partition: &Partition,
    squared: &mut [Vec<f64>],
) -> (f64, Rejected) {
    // Every group's non-empty pieces, one task each.
    let mut work = Vec::new();
    for (g, (group, squared)) in problem.groups.iter().zip(squared).enumerate() {
        let cuts = partition.pieces(g);
        for (t, piece) in split_at_bounds(squared, &cuts).into_iter().enumerate() {
            if !piece.is_empty() {
                work.push((group, cuts[t]..cuts[t + 1], piece));
            }
        }
    }
    let results = each(work, |(group, range, piece)| {
        let mut rejected = Rejected::default();
        let losses = &group.losses()[range.clone()];
        group.evaluate(range, values, piece, &mut rejected);
        let cost: f64 = piece
            .iter()
            .zip(losses)
            .map(|(&s, own)| 0.5 * robust::loss(own.or(problem.robust), s))
            .sum();
        (cost, rejected)
    });
    let mut cost = 0.0;
    let mut rejected = Rejected::default();
    for (c, r) in results {
        cost += c;
        rejected.merge(r);
    }
    (cost, rejected)
}

/// `f` of every task, in order: on rayon's threads, or on this one when
/// there is one task or one thread (a task handed to the pool wakes a
/// worker and puts this thread to sleep, which on a loaded machine costs
/// milliseconds per pass).
fn each<T: Send, R: Send>(tasks: Vec<T>, f: impl Fn(T) -> R + Send + Sync) -> Vec<R> {
    if tasks.len() <= 1 || rayon::current_num_threads() <= 1 {
        tasks.into_iter().map(f).collect()
    } else {
        tasks.into_par_iter().map(f).collect()
    }
}

/// The IRLS weights `ρ'(‖Sᵢ rᵢ‖²)` of a group's factors (each its own
/// loss, or the problem's `robust`), or `None` (all 1) when every factor
/// is plain least squares.
fn weights(robust: Option<Robust>, losses: &[Option<Robust>], squared: &[f64]) -> Option<Vec<f64>> {
    if robust.is_none() && losses.iter().all(Option::is_none) {
        return None;
    }
    Some(
        squared
            .par_iter()
            .zip(losses)
            .map(|(&s, own)| robust::weight(own.or(robust), s))
            .collect(),
    )
}

/// The normal equations at `values` into `normal`, each factor weighted by
/// its loss at `squared`; returns the time the threads spent in the batch
/// kernels, summed.
pub(crate) fn linearize(
    problem: &Problem,
    values: Values<'_>,
    structure: &Structure,
    partition: &Partition,
    squared: &[Vec<f64>],
    normal: &mut Normal,
) -> Duration {
    let el = &structure.eliminated;
    let bounds = &partition.eliminated;
    let parts = partition.parts();
    let at = |offsets: &[usize]| -> Vec<usize> { bounds.iter().map(|&b| offsets[b]).collect() };
    let weights: Vec<Option<Vec<f64>>> = squared
        .iter()
        .zip(&problem.groups)
        .map(|(s, group)| weights(problem.robust, group.losses(), s))
        .collect();
    // The eliminated variables' data are zeroed as they are reached.
    normal.u.fill(0.0);
    normal.diagonal.fill(0.0);
    normal.g_reduced.fill(0.0);
    let mut copies: Vec<(Vec<f64>, Vec<f64>, Vec<f64>)> = (1..parts)
        .map(|_| {
            (
                vec![0.0; normal.u.len()],
                vec![0.0; normal.diagonal.len()],
                vec![0.0; normal.g_reduced.len()],
            )
        })
        .collect();
    let mut reduced: Vec<(&mut [f64], &mut [f64], &mut [f64])> = vec![(
        &mut normal.u[..],
        &mut normal.diagonal[..],
        &mut normal.g_reduced[..],
    )];
    reduced.extend(
        copies
            .iter_mut()
            .map(|(u, d, g)| (&mut u[..], &mut d[..], &mut g[..])),
    );
    let g = split_at_bounds(&mut normal.g_eliminated, &at(&el.tangent));
    let v = split_at_bounds(&mut normal.v, &at(&el.packed));
    let w = split_at_bounds(&mut normal.w, &at(&el.cross));
    let work: Vec<_> = reduced
        .into_iter()
        .zip(g)
        .zip(v)
        .zip(w)
        .enumerate()
        .collect();
    let kernels: Duration = each(
        work,
        |(t, ((((u, diagonal, g_reduced), g_eliminated), v), w))| {
            let mut sink = Sink {
                u,
                diagonal,
                g_reduced,
                first: bounds[t],
                g_eliminated,
                v,
                w,
                cleared: bounds[t],
                kernels: Duration::ZERO,
            };
            for (g, (group, weights)) in problem.groups.iter().zip(&weights).enumerate() {
                for range in partition.ranges(g, t) {
                    let weights = weights.as_ref().map(|w| &w[range.clone()]);
                    group.linearize(range, values, weights, structure, &mut sink);
                }
            }
            if bounds[t + 1] > bounds[t] {
                sink.clear_through(bounds[t + 1] - 1, structure);
            }
            sink.kernels
        },
    )
    .into_iter()
    .sum();
    for (u, diagonal, g) in &copies {
        normal.u.par_iter_mut().zip(u).for_each(|(a, b)| *a += b);
        for (a, b) in normal.diagonal.iter_mut().zip(diagonal) {
            *a += b;
        }
        for (a, b) in normal.g_reduced.iter_mut().zip(g) {
            *a += b;
        }
    }
    structure.csc.fold_diagonal(&normal.diagonal, &mut normal.u);
    kernels
}

/// `candidate` ← `values` with every free variable retracted by its part of
/// the step in `buffers` (the fixed ones are left as they are in
/// `candidate`, which holds them already).
pub(crate) fn retract(
    problem: &Problem,
    structure: &Structure,
    buffers: &StepBuffers,
    values: &[f64],
    candidate: &mut [f64],
) {
    let variables = &problem.variables;
    let order = &structure.storage_order;
    let parts = rayon::current_num_threads().max(1);
    let per = order.len().div_ceil(parts).max(1);
    // Piece p holds the values of the variables order[p·per..(p + 1)·per].
    let bounds: Vec<usize> = (0..=parts)
        .map(|p| {
            order
                .get(p * per)
                .map_or(values.len(), |&id| variables[id as usize].offset)
        })
        .collect();
    let pieces = split_at_bounds(candidate, &bounds);
    each(pieces.into_iter().enumerate().collect(), |(p, piece)| {
        let base = bounds[p];
        for (i, &id) in order.iter().enumerate().skip(p * per).take(per) {
            let variable = &variables[id as usize];
            let delta = match structure.roles[i] {
                Role::Fixed => continue,
                Role::Reduced { block, offset } => {
                    let o = structure.csc.offsets[block as usize] + offset as usize;
                    &buffers.reduced[o..o + variable.chart.map_or(0, |c| c.tangent)]
                }
                Role::Eliminated { index } => {
                    let el = &structure.eliminated;
                    let e = index as usize;
                    &buffers.eliminated[el.tangent[e]..el.tangent[e + 1]]
                }
            };
            let chart = variable
                .chart
                .as_ref()
                .expect("every variable has a factor");
            let (from, to) = (variable.offset, variable.offset + variable.scalars);
            problem.groups[chart.group].retract(
                chart.slot,
                &values[from..to],
                delta,
                &mut piece[from - base..to - base],
            );
        }
    });
}

/// The cost, each factor's squared norm and the normal equations of
/// `problem` at its values, by the passes split into `parts` parts
/// whatever the problem's size (for tests of the threads' shares).
#[cfg(test)]
pub(crate) fn at_values(
    problem: &Problem,
    structure: &Structure,
    parts: usize,
) -> (f64, Vec<Vec<f64>>, Normal) {
    let offsets: Vec<usize> = structure
        .storage_order
        .iter()
        .map(|&id| problem.variables[id as usize].offset)
        .collect();
    let values = Values {
        scalars: &problem.values,
        offsets: &offsets,
    };
    let partition = Partition::forced(structure, parts);
    let mut squared: Vec<Vec<f64>> = problem.groups.iter().map(|g| vec![0.0; g.len()]).collect();
    let (cost, rejected) = evaluate(problem, values, &partition, &mut squared);
    assert_eq!(rejected.count, 0, "a factor rejects the values");
    let mut normal = Normal::zeros(structure);
    linearize(
        problem,
        values,
        structure,
        &partition,
        &squared,
        &mut normal,
    );
    (cost, squared, normal)
}

/// The passes split among threads give what one thread gives, on a g2o
/// graph whose lines (seen from every pose) stay in the reduced system, so
/// that every factor is in the tail the parts share.
#[cfg(test)]
mod tests {
    use std::path::Path;

    use super::*;
    use crate::problems::build;

    #[test]
    fn parts_sharing_the_tail_sum_to_one_threads_normal_equations() {
        let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../data/g2o-addons/line3d.g2o");
        let data = slam_data::Problem::read(&path, None).unwrap();
        let mut built = build(&data, None, slam_problems::Kernels::Generated).unwrap();
        let problem = &mut built.problem;
        let structure = problem.structure().unwrap();
        let (cost, squared, normal) = at_values(problem, &structure, 1);
        for parts in [2, 3] {
            let partition = Partition::forced(&structure, parts);
            // Every factor is in the tail, and every part has a share.
            for g in 0..problem.groups.len() {
                let [with, tail] = partition.ranges(g, parts - 1);
                assert!(with.is_empty() && !tail.is_empty(), "group {g}");
            }
            let (c, s, n) = at_values(problem, &structure, parts);
            let close = |a: &[f64], b: &[f64]| {
                let scale = b.iter().fold(0.0_f64, |m, x| m.max(x.abs()));
                a.iter().zip(b).all(|(x, y)| (x - y).abs() <= 1e-12 * scale)
            };
            assert!(
                (c - cost).abs() <= 1e-12 * cost,
                "{parts} parts: {c} vs {cost}"
            );
            assert_eq!(s, squared, "{parts} parts");
            assert!(close(&n.u, &normal.u), "{parts} parts: U");
            assert!(close(&n.g_reduced, &normal.g_reduced), "{parts} parts: g");
        }
    }
}
