//! [`Partition`]: how the threads share the factors and the eliminated
//! variables.

use std::ops::Range;

use crate::structure::Structure;

/// The least work a thread takes, in factors linearized by the fused
/// batch kernels (about 60 ns each): on less, waking threads and merging
/// their copies of `S` costs more than it saves.
const MIN_PART: usize = 16_384;

/// The ranges of eliminated variables and of each group's factors that
/// the threads each take (at most `threads`). A group's factors are sorted
/// by their eliminated variable, those with none last (the tail): each part
/// takes a contiguous range of the sorted ones, of about equal factor
/// counts and cut between eliminated variables (so that no two threads
/// write one eliminated variable's blocks), and an equal share of the tail
/// (which writes only into the reduced system, of which each thread has a
/// copy): problems with little or nothing to eliminate (pose graphs, g2o's
/// graphs of lines seen from every pose) are shared too.
#[derive(Debug, Clone)]
pub(crate) struct Partition {
    /// `parts + 1` bounds on the eliminated variables.
    pub(crate) eliminated: Vec<usize>,
    /// Per group, `parts + 1` bounds on its factors with an eliminated
    /// variable (the last one where its tail starts).
    pub(crate) factors: Vec<Vec<usize>>,
    /// Per group, `parts + 1` bounds on its tail, from where it starts to
    /// the group's end.
    pub(crate) tail: Vec<Vec<usize>>,
}

impl Partition {
    /// The partition for `threads` threads, each group's factors weighing
    /// `cost` (in batch-kernel factors: [`crate::Linearized::relative_cost`]).
    pub(crate) fn new(structure: &Structure, cost: &[usize], threads: usize) -> Self {
        let work: usize = structure
            .factor_eliminated
            .iter()
            .zip(cost)
            .map(|(of, c)| of.len() * c)
            .sum();
        Partition::split(structure, threads.clamp(1, work.div_ceil(MIN_PART).max(1)))
    }

    /// `parts` parts of about equal factor counts.
    fn split(structure: &Structure, parts: usize) -> Self {
        let ne = structure.eliminated.len();
        // Factors per eliminated variable, over every group.
        let mut weight = vec![0usize; ne];
        for of in &structure.factor_eliminated {
            for &e in of {
                if let Some(w) = weight.get_mut(e as usize) {
                    *w += 1;
                }
            }
        }
        let total: usize = weight.iter().sum();
        let parts = parts.max(1);
        let mut bounds = vec![0];
        let mut running = 0;
        for (e, w) in weight.iter().enumerate() {
            if bounds.len() < parts && running >= total * bounds.len() / parts {
                bounds.push(e);
            }
            running += w;
        }
        while bounds.len() < parts {
            bounds.push(ne);
        }
        bounds.push(ne);
        let (mut factors, mut tail) = (Vec::new(), Vec::new());
        for of in &structure.factor_eliminated {
            let start = of.partition_point(|&e| (e as usize) < ne);
            let mut cut: Vec<usize> = bounds[..parts]
                .iter()
                .map(|&b| of.partition_point(|&e| (e as usize) < b))
                .collect();
            cut[0] = 0;
            cut.push(start);
            factors.push(cut);
            let left = of.len() - start;
            tail.push((0..=parts).map(|t| start + left * t / parts).collect());
        }
        Partition {
            eliminated: bounds,
            factors,
            tail,
        }
    }

    /// The partition into `parts` parts whatever the size (for tests of
    /// the threads' copies on small problems).
    #[cfg(test)]
    pub(crate) fn forced(structure: &Structure, parts: usize) -> Self {
        Partition::split(structure, parts)
    }

    /// Part `t`'s factors of group `g`: a range with eliminated variables
    /// and a range of the tail.
    pub(crate) fn ranges(&self, g: usize, t: usize) -> [Range<usize>; 2] {
        let (cut, tail) = (&self.factors[g], &self.tail[g]);
        [cut[t]..cut[t + 1], tail[t]..tail[t + 1]]
    }

    /// Group `g`'s factors in `2 × parts` contiguous pieces, in order: the
    /// parts' ranges with eliminated variables, then their shares of the
    /// tail (for passes that write one output per factor).
    pub(crate) fn pieces(&self, g: usize) -> Vec<usize> {
        let (cut, tail) = (&self.factors[g], &self.tail[g]);
        cut[..cut.len() - 1].iter().chain(tail).copied().collect()
    }

    /// The number of parts.
    pub(crate) fn parts(&self) -> usize {
        self.eliminated.len() - 1
    }
}

/// Splits `data` into the pieces `bounds` (increasing indices from 0)
/// delimit.
pub(crate) fn split_at_bounds<'a, T>(mut data: &'a mut [T], bounds: &[usize]) -> Vec<&'a mut [T]> {
    let mut parts = Vec::with_capacity(bounds.len().saturating_sub(1));
    for w in bounds.windows(2) {
        let (head, tail) = data.split_at_mut(w[1] - w[0]);
        parts.push(head);
        data = tail;
    }
    parts
}
