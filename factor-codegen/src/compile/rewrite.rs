//! Stage 2: rewrites that share work. Common pairs are extracted greedily,
//! the most frequent first, until no pair occurs twice: operand pairs `a·b`
//! across all products, and term pairs `a + r·b` (up to a common
//! coefficient) across all sums, the classic pairwise common-subexpression
//! heuristic (canonical operand order makes it deterministic). Distributive
//! factoring `Σ cᵢ f gᵢ = f · Σ cᵢ gᵢ` is tried by some strategies.

use std::collections::BTreeMap;

use factor_symbolic::graph::Real;

use super::ops::{Compiler, Op};

impl Compiler<'_> {
    /// Factors the most common factor out of the first live sum that has
    /// one, among its product terms (only single-use ones unless `shared`):
    /// `Σ cᵢ f gᵢ = f · Σ cᵢ gᵢ` saves a multiplication per term beyond the
    /// first.
    pub(super) fn factor_sum(&mut self, live: &[usize], shared: bool) -> bool {
        let uses = self.use_counts(live);
        let mut held = Vec::new();
        let Some((op, f)) = live
            .iter()
            .find_map(|&op| Some((op, self.common_factor(op, &uses, shared, &mut held)?)))
        else {
            return false;
        };
        let Op::Sum { constant, terms } = self.ops[op].clone() else {
            unreachable!("a common factor is found in sums only");
        };
        let split: Vec<Option<(f64, Vec<usize>)>> = terms
            .iter()
            .map(|(t, _)| {
                self.term_factors(t, &uses, shared)
                    .map(|(k, factors)| (k, factors.to_vec()))
            })
            .collect();
        let mut inner_constant = 0.0;
        let mut inner: BTreeMap<usize, f64> = BTreeMap::new();
        let mut outer: Vec<(usize, f64)> = Vec::new();
        for ((t, c), parts) in terms.iter().zip(split) {
            match parts {
                Some((k, mut factors)) if factors.contains(&f) => {
                    let i = factors.iter().position(|x| *x == f).expect("contains");
                    factors.remove(i);
                    match self.product(k, factors) {
                        Some(cofactor) => *inner.entry(cofactor).or_insert(0.0) += c,
                        None => inner_constant += c * k,
                    }
                }
                _ => outer.push((*t, *c)),
            }
        }
        let mut inner: Vec<(usize, f64)> = inner.into_iter().filter(|(_, c)| *c != 0.0).collect();
        // A sum whose terms are all negative would cost a negation: carry
        // its sign out to this sum's coefficient instead.
        let sign = if inner.iter().all(|(_, c)| *c < 0.0) && inner_constant <= 0.0 {
            -1.0
        } else {
            1.0
        };
        inner.iter_mut().for_each(|(_, c)| *c *= sign);
        let inner_sum = self.push(Op::Sum {
            constant: inner_constant * sign,
            terms: inner,
        });
        let factored = self.push(Op::Product {
            coefficient: 1.0,
            factors: {
                let mut v = vec![f, inner_sum];
                v.sort_unstable();
                v
            },
        });
        outer.push((factored, sign));
        outer.sort_unstable_by_key(|(t, _)| *t);
        self.ops[op] = Op::Sum {
            constant,
            terms: outer,
        };
        true
    }

    /// A sum's term as `coefficient · Π factors` if factoring may split it:
    /// a product only this sum uses (any product when `shared`), or any
    /// other op as its own single factor; `None` for a product that stays
    /// whole.
    fn term_factors<'a>(
        &'a self,
        term: &'a usize,
        uses: &[usize],
        shared: bool,
    ) -> Option<(f64, &'a [usize])> {
        match &self.ops[*term] {
            Op::Product {
                coefficient,
                factors,
            } if shared || uses[*term] == 1 => Some((*coefficient, factors)),
            Op::Product { .. } => None,
            _ => Some((1.0, std::slice::from_ref(term))),
        }
    }

    /// The factor most of the sum `op`'s splittable terms hold, if two do
    /// (a term counts it once; factor lists are sorted), the smallest among
    /// equally frequent ones. `held` is scratch space.
    fn common_factor(
        &self,
        op: usize,
        uses: &[usize],
        shared: bool,
        held: &mut Vec<usize>,
    ) -> Option<usize> {
        let Op::Sum { terms, .. } = &self.ops[op] else {
            return None;
        };
        held.clear();
        for (t, _) in terms {
            if let Some((_, factors)) = self.term_factors(t, uses, shared) {
                held.extend(factors.chunk_by(|a, b| a == b).map(|run| run[0]));
            }
        }
        held.sort_unstable();
        held.chunk_by(|a, b| a == b)
            .filter(|run| run.len() >= 2)
            .max_by_key(|run| (run.len(), std::cmp::Reverse(run[0])))
            .map(|run| run[0])
    }

    /// Extracts the most frequent operand pair of the live products.
    pub(super) fn extract_product_pair(&mut self, live: &[usize]) -> bool {
        let mut pairs = Vec::new();
        for &op in live {
            if let Op::Product { factors, .. } = &self.ops[op] {
                pairs.extend(distinct_pairs(factors.len(), |i, j| {
                    (factors[i], factors[j])
                }));
            }
        }
        let Some((a, b)) = most_frequent(pairs) else {
            return false;
        };
        let pair = self.push(Op::Product {
            coefficient: 1.0,
            factors: vec![a, b],
        });
        for &op in live {
            if op == pair {
                continue;
            }
            if let Op::Product { factors, .. } = &mut self.ops[op] {
                {
                    if let Some(i) = factors.iter().position(|f| *f == a) {
                        let rest: Vec<usize> = factors
                            .iter()
                            .enumerate()
                            .filter(|(k, _)| *k != i)
                            .map(|(_, f)| *f)
                            .collect();
                        if let Some(j) = rest.iter().position(|f| *f == b) {
                            let mut next: Vec<usize> = rest
                                .iter()
                                .enumerate()
                                .filter(|(k, _)| *k != j)
                                .map(|(_, f)| *f)
                                .collect();
                            next.push(pair);
                            next.sort_unstable();
                            *factors = next;
                        }
                    }
                }
            }
        }
        true
    }

    /// Extracts the most frequent term pair `a + r·b` of the live sums.
    pub(super) fn extract_sum_pair(&mut self, live: &[usize]) -> bool {
        let mut pairs = Vec::new();
        for &op in live {
            if let Op::Sum { terms, .. } = &self.ops[op] {
                pairs.extend(distinct_pairs(terms.len(), |i, j| {
                    let ratio = Real::new(terms[j].1 / terms[i].1);
                    (terms[i].0, terms[j].0, ratio.bits())
                }));
            }
        }
        let Some((a, b, ratio_bits)) = most_frequent(pairs) else {
            return false;
        };
        let ratio = f64::from_bits(ratio_bits);
        let pair = self.push(Op::Sum {
            constant: 0.0,
            terms: vec![(a, 1.0), (b, ratio)],
        });
        for &op in live {
            if op == pair {
                continue;
            }
            if let Op::Sum { terms, .. } = &mut self.ops[op] {
                let ia = terms.iter().position(|(t, _)| *t == a);
                let ib = terms.iter().position(|(t, _)| *t == b);
                if let (Some(ia), Some(ib)) = (ia, ib) {
                    let ca = terms[ia].1;
                    if Real::new(terms[ib].1 / ca) == Real::new(ratio) {
                        terms.retain(|(t, _)| *t != a && *t != b);
                        terms.push((pair, ca));
                        terms.sort_unstable_by_key(|(t, _)| *t);
                    }
                }
            }
        }
        true
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

/// The pair held by the most operations, at least two; among equally
/// frequent ones the smallest (canonical operand order: deterministic).
/// Sorting and counting runs is the same choice as a map from pair to count,
/// without a map's insertions, the generator's largest cost.
fn most_frequent<P: Ord + Copy>(mut pairs: Vec<P>) -> Option<P> {
    pairs.sort_unstable();
    let mut best: Option<(usize, P)> = None;
    for run in pairs.chunk_by(|a, b| a == b) {
        if run.len() >= 2 && best.is_none_or(|(n, _)| run.len() > n) {
            best = Some((run.len(), run[0]));
        }
    }
    best.map(|(_, pair)| pair)
}
