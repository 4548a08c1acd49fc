//! Stage 2: rewrites that share work. Common pairs are extracted greedily,
//! the most frequent first, until no pair occurs twice: operand pairs `a·b`
//! across all products, and term pairs `a + r·b` (up to a common
//! coefficient) across all sums, the classic pairwise common-subexpression
//! heuristic (canonical operand order makes it deterministic). Distributive
//! factoring `Σ cᵢ f gᵢ = f · Σ cᵢ gᵢ` is tried by some strategies.

use std::collections::BTreeMap;

use factor_symbolic::graph::Real;

use super::Phase;
use super::ops::{Compiler, Op};

impl Compiler<'_> {
    /// Runs `phase`'s rewrites until none applies: factoring first (for the
    /// factoring phases), then the most frequent product pair, then the most
    /// frequent sum pair, one at a time.
    pub(super) fn rewrite(&mut self, phase: Phase) {
        let factoring = phase != Phase::Pairs;
        let shared = phase == Phase::FactorShared;
        // What `factor_sum` found factorless, it found for one `shared`.
        self.forget_factorless();
        while (factoring && self.factor_sum(shared))
            || self.extract_product_pair()
            || self.extract_sum_pair()
        {}
    }

    /// Factors the most common factor out of the first live sum that has
    /// one, among its product terms (only single-use ones unless `shared`):
    /// `Σ cᵢ f gᵢ = f · Σ cᵢ gᵢ` saves a multiplication per term beyond the
    /// first.
    pub(super) fn factor_sum(&mut self, shared: bool) -> bool {
        let mut held = Vec::new();
        let mut found = None;
        for op in 0..self.ops.len() {
            if !self.is_live(op) || self.factorless(op) {
                continue;
            }
            match self.common_factor(op, shared, &mut held) {
                Some(f) => {
                    found = Some((op, f));
                    break;
                }
                None => self.set_factorless(op),
            }
        }
        let Some((op, f)) = found else {
            return false;
        };
        let Op::Sum { constant, terms } = self.ops[op].clone() else {
            unreachable!("a common factor is found in sums only");
        };
        let split: Vec<Option<(f64, Vec<usize>)>> = terms
            .iter()
            .map(|(t, _)| {
                self.term_factors(t, shared)
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
        self.replace(
            op,
            Op::Sum {
                constant,
                terms: outer,
            },
        );
        true
    }

    /// A sum's term as `coefficient · Π factors` if factoring may split it:
    /// a product only this sum uses (any product when `shared`), or any
    /// other op as its own single factor; `None` for a product that stays
    /// whole.
    fn term_factors<'a>(&'a self, term: &'a usize, shared: bool) -> Option<(f64, &'a [usize])> {
        match &self.ops[*term] {
            Op::Product {
                coefficient,
                factors,
            } if shared || self.uses[*term] == 1 => Some((*coefficient, factors)),
            Op::Product { .. } => None,
            _ => Some((1.0, std::slice::from_ref(term))),
        }
    }

    /// The factor most of the sum `op`'s splittable terms hold, if two do
    /// (a term counts it once; factor lists are sorted), the smallest among
    /// equally frequent ones. `held` is scratch space.
    fn common_factor(&self, op: usize, shared: bool, held: &mut Vec<usize>) -> Option<usize> {
        let Op::Sum { terms, .. } = &self.ops[op] else {
            return None;
        };
        held.clear();
        for (t, _) in terms {
            if let Some((_, factors)) = self.term_factors(t, shared) {
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
    pub(super) fn extract_product_pair(&mut self) -> bool {
        let Some((a, b)) = self.product_pairs.most_frequent() else {
            return false;
        };
        let pair = self.push(Op::Product {
            coefficient: 1.0,
            factors: vec![a, b],
        });
        let holders: Vec<usize> = self.product_pairs.holders(&(a, b)).to_vec();
        for op in holders {
            if op == pair {
                continue;
            }
            let Op::Product {
                coefficient,
                factors,
            } = &self.ops[op]
            else {
                unreachable!("only products hold operand pairs");
            };
            // One `a` and one `b` out (two `a`s for a square), the pair in.
            let mut next = factors.clone();
            for x in [a, b] {
                let i = next.iter().position(|f| *f == x).expect("a held pair");
                next.remove(i);
            }
            next.push(pair);
            next.sort_unstable();
            let coefficient = *coefficient;
            self.replace(
                op,
                Op::Product {
                    coefficient,
                    factors: next,
                },
            );
        }
        true
    }

    /// Extracts the most frequent term pair `a + r·b` of the live sums.
    pub(super) fn extract_sum_pair(&mut self) -> bool {
        let Some((a, b, ratio_bits)) = self.sum_pairs.most_frequent() else {
            return false;
        };
        let ratio = f64::from_bits(ratio_bits);
        let pair = self.push(Op::Sum {
            constant: 0.0,
            terms: vec![(a, 1.0), (b, ratio)],
        });
        // A sum whose first `a` and first `b` are `r` apart holds the pair
        // `(a, b, r)` when `a ≠ b`. A pair `(a, a, 1)` is held only by a sum
        // with a term twice (an extracted pair that was a term already), but
        // every live sum with the term `a` is rewritten: all are looked at.
        let candidates = if a == b {
            self.live()
        } else {
            self.sum_pairs.holders(&(a, b, ratio_bits)).to_vec()
        };
        for op in candidates {
            if op == pair {
                continue;
            }
            let Op::Sum { constant, terms } = &self.ops[op] else {
                continue;
            };
            let ia = terms.iter().position(|(t, _)| *t == a);
            let ib = terms.iter().position(|(t, _)| *t == b);
            if let (Some(ia), Some(ib)) = (ia, ib) {
                let ca = terms[ia].1;
                if Real::new(terms[ib].1 / ca) == Real::new(ratio) {
                    let mut terms = terms.clone();
                    terms.retain(|(t, _)| *t != a && *t != b);
                    terms.push((pair, ca));
                    terms.sort_unstable_by_key(|(t, _)| *t);
                    let constant = *constant;
                    self.replace(op, Op::Sum { constant, terms });
                }
            }
        }
        true
    }
}
