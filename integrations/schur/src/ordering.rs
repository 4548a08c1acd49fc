//! Lists of indices end to end ([`Lists`]), the graph of the reduced
//! blocks, and its fill-reducing order (faer's approximate minimum degree).

use faer::dyn_stack::{MemBuffer, MemStack};
use faer::sparse::SymbolicSparseColMatRef;
use faer::sparse::linalg::amd;

use crate::error::SchurError;

/// Lists of indices, end to end: list `l` is `items[start[l]..start[l + 1]]`.
#[derive(Debug, Clone, Default, PartialEq, Eq)]
pub(crate) struct Lists {
    pub(crate) start: Vec<usize>,
    pub(crate) items: Vec<u32>,
}

impl Lists {
    /// `n` lists of the items of `pairs()`, `(list, item)`, each sorted and
    /// without repeats (`pairs` is called twice: to count, then to fill).
    pub(crate) fn from_pairs<I: Iterator<Item = (usize, u32)>>(
        n: usize,
        pairs: impl Fn() -> I,
    ) -> Self {
        let mut count = vec![0usize; n + 1];
        for (l, _) in pairs() {
            count[l + 1] += 1;
        }
        for l in 0..n {
            count[l + 1] += count[l];
        }
        let mut next = count.clone();
        let mut items = vec![0u32; count[n]];
        for (l, x) in pairs() {
            items[next[l]] = x;
            next[l] += 1;
        }
        let mut start = Vec::with_capacity(n + 1);
        start.push(0);
        let mut kept = 0;
        for l in 0..n {
            items[count[l]..count[l + 1]].sort_unstable();
            for k in count[l]..count[l + 1] {
                if k == count[l] || items[k] != items[k - 1] {
                    items[kept] = items[k];
                    kept += 1;
                }
            }
            start.push(kept);
        }
        items.truncate(kept);
        Lists { start, items }
    }

    /// The number of lists.
    pub(crate) fn len(&self) -> usize {
        self.start.len().saturating_sub(1)
    }

    /// List `l`.
    pub(crate) fn list(&self, l: usize) -> &[u32] {
        &self.items[self.start[l]..self.start[l + 1]]
    }

    /// Each list's items mapped by `f`, each list sorted again.
    pub(crate) fn map(&self, f: impl Fn(u32) -> u32) -> Self {
        let mut items: Vec<u32> = self.items.iter().map(|&x| f(x)).collect();
        for l in 0..self.len() {
            items[self.start[l]..self.start[l + 1]].sort_unstable();
        }
        Lists {
            start: self.start.clone(),
            items,
        }
    }
}

/// The adjacency of the graph on `n` nodes whose edges join every two
/// members of each clique, each list increasing, without the node itself.
/// Each node's neighbours are gathered once each (marked as met), so that
/// a pair in many cliques (two cameras seeing many landmarks) costs no
/// sort of its repeats.
pub(crate) fn adjacency(n: usize, cliques: &Lists) -> Lists {
    let member_of = Lists::from_pairs(n, || {
        (0..cliques.len())
            .flat_map(|c| cliques.list(c).iter().map(move |&u| (u as usize, c as u32)))
    });
    // The last node each node was met as a neighbour of.
    let mut met = vec![usize::MAX; n];
    let mut start = Vec::with_capacity(n + 1);
    let mut items = Vec::new();
    start.push(0);
    for u in 0..n {
        let first = items.len();
        for &c in member_of.list(u) {
            for &v in cliques.list(c as usize) {
                if v as usize != u && met[v as usize] != u {
                    met[v as usize] = u;
                    items.push(v);
                }
            }
        }
        items[first..].sort_unstable();
        start.push(items.len());
    }
    Lists { start, items }
}

/// Each node's position in an approximate minimum degree ordering of the
/// graph `adjacency`.
pub(crate) fn amd_positions(adjacency: &Lists) -> Result<Vec<u32>, SchurError> {
    let n = adjacency.len();
    let col_ptr = &adjacency.start;
    let row_idx: Vec<usize> = adjacency.items.iter().map(|&v| v as usize).collect();
    let pattern = SymbolicSparseColMatRef::new_checked(n, n, col_ptr, None, &row_idx);
    let (mut perm, mut inverse) = (vec![0usize; n], vec![0usize; n]);
    let mut memory = MemBuffer::new(amd::order_scratch::<usize>(n, row_idx.len()));
    amd::order(
        &mut perm,
        &mut inverse,
        pattern,
        amd::Control::default(),
        MemStack::new(&mut memory),
    )
    .map_err(|e| SchurError::TooLarge(format!("ordering the reduced system: {e:?}")))?;
    // `perm[k]` is the node eliminated k-th; `inverse` its position.
    inverse
        .into_iter()
        .map(|p| u32::try_from(p).map_err(|_| SchurError::TooLarge("2³² blocks or more".into())))
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn lists_are_sorted_without_repeats_and_graphs_join_clique_members() {
        let pairs = [(1, 5), (0, 2), (1, 3), (1, 5), (3, 0)];
        let lists = Lists::from_pairs(4, || pairs.iter().copied());
        assert_eq!(lists.len(), 4);
        assert_eq!(
            (0..4).map(|l| lists.list(l).to_vec()).collect::<Vec<_>>(),
            [vec![2], vec![3, 5], vec![], vec![0]]
        );
        let cliques = Lists::from_pairs(2, || [(0, 0), (0, 2), (1, 2), (1, 3), (1, 1)].into_iter());
        let graph = adjacency(4, &cliques);
        assert_eq!(
            (0..4).map(|u| graph.list(u).to_vec()).collect::<Vec<_>>(),
            [vec![2], vec![2, 3], vec![0, 1, 3], vec![1, 2]]
        );
        let mut positions = amd_positions(&graph).unwrap();
        positions.sort_unstable();
        assert_eq!(positions, [0, 1, 2, 3]);
    }
}
