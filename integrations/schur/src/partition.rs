//! [`Partition`]: how the threads share the factors and the eliminated
//! variables.

use crate::structure::Structure;

/// The fewest factors a thread takes.
const MIN_PART: usize = 16_384;

/// The ranges of eliminated variables and of each group's factors that
/// the threads each take (at most `threads`): contiguous, of about equal factor counts,
/// cut between eliminated variables (so that no two threads write one
/// eliminated variable's blocks). Factors with no eliminated variable go
/// to the last part.
#[derive(Debug, Clone)]
pub(crate) struct Partition {
    /// `parts + 1` bounds on the eliminated variables.
    pub(crate) eliminated: Vec<usize>,
    /// Per group, `parts + 1` bounds on its factors.
    pub(crate) factors: Vec<Vec<usize>>,
}

impl Partition {
    pub(crate) fn new(structure: &Structure, threads: usize) -> Self {
        let total: usize = structure.factor_eliminated.iter().map(Vec::len).sum();
        // A thread's share is at least MIN_PART factors: on fewer, waking
        // threads and merging their copies of S costs more than it saves.
        Partition::split(structure, threads.clamp(1, total.div_ceil(MIN_PART).max(1)))
    }

    /// `parts` parts of about equal factor counts.
    fn split(structure: &Structure, parts: usize) -> Self {
        let ne = structure.eliminated.len();
        // Factors per eliminated variable, over every group.
        let mut weight = vec![0usize; ne + 1];
        for of in &structure.factor_eliminated {
            for &e in of {
                weight[(e as usize).min(ne)] += 1;
            }
        }
        let total: usize = weight.iter().sum();
        let parts = parts.max(1);
        let mut bounds = vec![0];
        let mut running = 0;
        for (e, w) in weight[..ne].iter().enumerate() {
            if bounds.len() < parts && running >= total * bounds.len() / parts {
                bounds.push(e);
            }
            running += w;
        }
        while bounds.len() < parts {
            bounds.push(ne);
        }
        bounds.push(ne);
        let factors = structure
            .factor_eliminated
            .iter()
            .map(|of| {
                let mut cut: Vec<usize> = bounds[..parts]
                    .iter()
                    .map(|&b| of.partition_point(|&e| (e as usize) < b))
                    .collect();
                cut[0] = 0;
                cut.push(of.len());
                cut
            })
            .collect();
        Partition {
            eliminated: bounds,
            factors,
        }
    }

    /// The partition into `parts` parts whatever the size (for tests of
    /// the threads' copies on small problems).
    #[cfg(test)]
    pub(crate) fn forced(structure: &Structure, parts: usize) -> Self {
        Partition::split(structure, parts)
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
