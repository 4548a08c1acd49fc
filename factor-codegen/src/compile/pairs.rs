//! Which live ops hold each operand pair, kept up to date as ops are
//! rewritten, so the most frequent pair is found without going over every
//! op again after each extraction (which made the rewrites quadratic).

use std::cmp::Reverse;
use std::collections::{BTreeSet, HashMap};
use std::hash::Hash;

use factor_symbolic::graph::Real;

use super::ops::Op;

#[derive(Clone)]
pub(super) struct PairIndex<P> {
    /// The ops holding each pair (an op holds a pair once), in no order.
    holders: HashMap<P, Vec<usize>>,
    /// The pairs two ops or more hold: the most held first, then the
    /// smallest (canonical operand order: deterministic).
    ranked: BTreeSet<(Reverse<usize>, P)>,
}

impl<P> Default for PairIndex<P> {
    fn default() -> Self {
        PairIndex {
            holders: HashMap::new(),
            ranked: BTreeSet::new(),
        }
    }
}

impl<P: Copy + Ord + Hash> PairIndex<P> {
    /// Records that `op`, which held the sorted pairs `old`, now holds the
    /// sorted pairs `new`: only the pairs that differ are touched (a
    /// rewrite changes few of a large op's pairs).
    pub(super) fn update(&mut self, op: usize, old: &[P], new: &[P]) {
        let (mut i, mut j) = (0, 0);
        loop {
            match (old.get(i), new.get(j)) {
                (None, None) => break,
                (Some(o), Some(n)) if o == n => {
                    i += 1;
                    j += 1;
                }
                (Some(o), Some(n)) if n < o => {
                    self.insert(*n, op);
                    j += 1;
                }
                (Some(o), _) => {
                    self.remove(*o, op);
                    i += 1;
                }
                (None, Some(n)) => {
                    self.insert(*n, op);
                    j += 1;
                }
            }
        }
    }

    /// Records that `op` holds `pair`.
    fn insert(&mut self, pair: P, op: usize) {
        let holders = self.holders.entry(pair).or_default();
        holders.push(op);
        let n = holders.len();
        self.rerank(pair, n - 1, n);
    }

    /// Records that `op` no longer holds `pair`.
    fn remove(&mut self, pair: P, op: usize) {
        let holders = self.holders.get_mut(&pair).expect("an indexed pair");
        let i = holders
            .iter()
            .position(|h| *h == op)
            .expect("an indexed holder");
        holders.swap_remove(i);
        let n = holders.len();
        if n == 0 {
            self.holders.remove(&pair);
        }
        self.rerank(pair, n + 1, n);
    }

    fn rerank(&mut self, pair: P, before: usize, after: usize) {
        if before >= 2 {
            self.ranked.remove(&(Reverse(before), pair));
        }
        if after >= 2 {
            self.ranked.insert((Reverse(after), pair));
        }
    }

    /// The pair held by the most ops, at least two; among equally frequent
    /// ones the smallest.
    pub(super) fn most_frequent(&self) -> Option<P> {
        self.ranked.first().map(|(_, pair)| *pair)
    }

    /// The ops holding `pair`, in no order.
    pub(super) fn holders(&self, pair: &P) -> &[usize] {
        self.holders.get(pair).map_or(&[], Vec::as_slice)
    }
}

/// A product's operand pair `a · b` (`a ≤ b`).
pub(super) type ProductPair = (usize, usize);

/// A sum's term pair `a + r · b` (`a < b`, `r`'s bits), up to a common
/// coefficient.
pub(super) type SumPair = (usize, usize, u64);

/// The distinct pairs an op holds, sorted: a product's operand pairs, a
/// sum's term pairs.
pub(super) fn pairs_of(op: &Op) -> (Vec<ProductPair>, Vec<SumPair>) {
    match op {
        Op::Product { factors, .. } => (
            distinct_pairs(factors.len(), |i, j| (factors[i], factors[j])),
            Vec::new(),
        ),
        Op::Sum { terms, .. } => (
            Vec::new(),
            distinct_pairs(terms.len(), |i, j| {
                let ratio = Real::new(terms[j].1 / terms[i].1);
                (terms[i].0, terms[j].0, ratio.bits())
            }),
        ),
        Op::Leaf(_) | Op::Recip(_) => (Vec::new(), Vec::new()),
    }
}

/// The distinct values of `pair(i, j)` over `i < j < n`, sorted (an
/// operation counts a pair once however often it holds it).
fn distinct_pairs<P: Ord>(n: usize, pair: impl Fn(usize, usize) -> P) -> Vec<P> {
    let mut pairs: Vec<P> = (0..n)
        .flat_map(|i| (i + 1..n).map(move |j| (i, j)))
        .map(|(i, j)| pair(i, j))
        .collect();
    pairs.sort_unstable();
    pairs.dedup();
    pairs
}
