//! The Gauss–Newton normal equations of one factor, fused with its Jacobian.
//!
//! For a per-factor weight `w` (an extra input after the factor's own
//! scalars), the outputs are the cost `½ w rᵀr`, each variable's gradient
//! block `gᵢ = Jᵢᵀ w r`, and the upper triangle of `JᵀwJ` block by block:
//! `Hᵢᵢ` (its upper triangle, `a ≤ b`) and `Hᵢⱼ = Jᵢᵀ w Jⱼ` for `i < j`.
//! They are appended to the lowered residual-and-Jacobian program
//! ([`crate::lower`]), so every value of the residual and the Jacobian is
//! computed once and shared by all of them, and no Jacobian entry is
//! stored: the weighted block `w Jⱼ` is formed once and reused by the
//! gradient and every Hessian block it enters. Known zeros of the Jacobian
//! drop their terms, and a negated entry enters its sums as a subtraction
//! (the negation itself is not computed).

use factor_symbolic::graph::Real;

use crate::ir::{Instr, Program, Value};
use crate::lower::LoweredKernel;

/// The most variables of a factor with a normal-equation kernel: its `n`
/// gradient and `n(n+1)/2` Hessian blocks are scheduled as at most 63
/// optional outputs ([`crate::schedule`]).
pub const MAX_VARIABLES: usize = 9;

/// A value times ±1, or a known zero.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum Term {
    /// Exactly zero.
    Zero,
    /// `value` or `−value`.
    Signed { value: Value, negated: bool },
}

/// Builds the normal equations on top of a lowered kernel's program.
struct Builder {
    program: Program,
}

impl Builder {
    fn constant(&mut self, c: f64) -> Value {
        self.program.push(Instr::Const(Real::new(c)))
    }

    /// `v` as a term: literals and negations unwrapped.
    fn term(&mut self, v: Value) -> Term {
        match self.program.instrs[v.0 as usize] {
            Instr::Const(c) if c.get() == 0.0 => Term::Zero,
            Instr::Const(c) if c.get() < 0.0 => Term::Signed {
                value: self.constant(-c.get()),
                negated: true,
            },
            Instr::Neg(x) => Term::Signed {
                value: x,
                negated: true,
            },
            _ => Term::Signed {
                value: v,
                negated: false,
            },
        }
    }

    fn is_one(&self, v: Value) -> bool {
        matches!(self.program.instrs[v.0 as usize], Instr::Const(c) if c.get() == 1.0)
    }

    /// `a · b`, signs collected and factors of one dropped.
    fn mul(&mut self, a: Term, b: Term) -> Term {
        let (
            Term::Signed {
                value: x,
                negated: nx,
            },
            Term::Signed {
                value: y,
                negated: ny,
            },
        ) = (a, b)
        else {
            return Term::Zero;
        };
        let value = if self.is_one(x) {
            y
        } else if self.is_one(y) {
            x
        } else {
            self.program.push(Instr::Mul(x, y))
        };
        Term::Signed {
            value,
            negated: nx != ny,
        }
    }

    /// `Σ terms` as one value: zeros dropped, negated terms subtracted from
    /// a positive one (one negation when all are negated).
    fn sum(&mut self, terms: &[Term]) -> Value {
        let signed: Vec<(Value, bool)> = terms
            .iter()
            .filter_map(|t| match *t {
                Term::Zero => None,
                Term::Signed { value, negated } => Some((value, negated)),
            })
            .collect();
        let Some(first) = signed.iter().position(|(_, negated)| !negated) else {
            // All negated (or none at all): `−(Σ |terms|)`.
            let Some((&(head, _), rest)) = signed.split_first() else {
                return self.constant(0.0);
            };
            let total = rest
                .iter()
                .fold(head, |acc, (v, _)| self.program.push(Instr::Add(acc, *v)));
            return self.program.push(Instr::Neg(total));
        };
        let mut acc = signed[first].0;
        for (k, (v, negated)) in signed.iter().enumerate() {
            if k != first {
                acc = self.program.push(if *negated {
                    Instr::Sub(acc, *v)
                } else {
                    Instr::Add(acc, *v)
                });
            }
        }
        acc
    }
}

/// The pairs `(i, j)`, `i ≤ j < n`, in Hessian block order.
pub fn pairs(n: usize) -> Vec<(usize, usize)> {
    (0..n).flat_map(|i| (i..n).map(move |j| (i, j))).collect()
}

/// The normal equations of `kernel` (whose blocks have `tangents` columns
/// each) with the weight read from input `weight`: a program whose
/// `residual` is `[cost]` and whose `blocks` are the gradient blocks in
/// variable order, then the Hessian blocks in [`pairs`] order (diagonal ones
/// as their upper triangles, row by row).
pub fn lower_normal(kernel: &LoweredKernel, weight: u32, tangents: &[usize]) -> LoweredKernel {
    let mut b = Builder {
        program: Program::from_instrs(kernel.instrs.clone()),
    };
    let rows = kernel.residual.len();
    let w = b.program.push(Instr::Input(weight));
    let w = Term::Signed {
        value: w,
        negated: false,
    };
    let residual: Vec<Term> = kernel.residual.iter().map(|v| b.term(*v)).collect();
    let jacobian: Vec<Vec<Term>> = kernel
        .blocks
        .iter()
        .map(|block| block.iter().map(|v| b.term(*v)).collect())
        .collect();
    // `w J`, entry (r, a) of block k at `[k][r * tangents[k] + a]`.
    let weighted: Vec<Vec<Term>> = jacobian
        .iter()
        .map(|block| block.iter().map(|t| b.mul(w, *t)).collect())
        .collect();

    let squares: Vec<Term> = residual.iter().map(|r| b.mul(*r, *r)).collect();
    let squared_norm = b.sum(&squares);
    let squared_norm = b.term(squared_norm);
    let half = b.constant(0.5);
    let half = Term::Signed {
        value: half,
        negated: false,
    };
    let weighted_norm = b.mul(w, squared_norm);
    let cost = b.mul(half, weighted_norm);
    let cost = b.sum(&[cost]);

    let mut blocks = Vec::new();
    for (k, &d) in tangents.iter().enumerate() {
        let gradient = (0..d)
            .map(|a| {
                let terms: Vec<Term> = (0..rows)
                    .map(|r| b.mul(weighted[k][r * d + a], residual[r]))
                    .collect();
                b.sum(&terms)
            })
            .collect();
        blocks.push(gradient);
    }
    for (i, j) in pairs(tangents.len()) {
        let (di, dj) = (tangents[i], tangents[j]);
        let mut block = Vec::new();
        for a in 0..di {
            let first = if i == j { a } else { 0 };
            for c in first..dj {
                let terms: Vec<Term> = (0..rows)
                    .map(|r| b.mul(jacobian[i][r * di + a], weighted[j][r * dj + c]))
                    .collect();
                block.push(b.sum(&terms));
            }
        }
        blocks.push(block);
    }
    LoweredKernel {
        instrs: b.program.instrs,
        residual: vec![cost],
        blocks,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Inputs `a, b, c`; residual `[a·b, c]`; block 0 (1 column) `[−a, 0]`,
    /// block 1 (2 columns) `[[b, 1], [−c, a·b]]`.
    fn kernel() -> LoweredKernel {
        let instrs = vec![
            Instr::Input(0),                // 0 a
            Instr::Input(1),                // 1 b
            Instr::Input(2),                // 2 c
            Instr::Mul(Value(0), Value(1)), // 3 a·b
            Instr::Neg(Value(0)),           // 4 −a
            Instr::Const(Real::new(0.0)),   // 5
            Instr::Const(Real::new(1.0)),   // 6
            Instr::Neg(Value(2)),           // 7 −c
        ];
        LoweredKernel {
            instrs,
            residual: vec![Value(3), Value(2)],
            blocks: vec![
                vec![Value(4), Value(5)],
                vec![Value(1), Value(6), Value(7), Value(3)],
            ],
        }
    }

    #[test]
    fn the_outputs_are_the_weighted_normal_equations() {
        let normal = lower_normal(&kernel(), 3, &[1, 2]);
        let program = Program::from_instrs(normal.instrs.clone());
        let (a, b, c, w) = (1.5, -0.75, 2.25, 0.4);
        let outputs = program.evaluate(&[a, b, c, w], &normal.outputs());
        let r = [a * b, c];
        let j = [[-a, b, 1.0], [0.0, -c, a * b]];
        let mut expected = vec![0.5 * w * (r[0] * r[0] + r[1] * r[1])];
        expected.extend((0..3).map(|k| w * (j[0][k] * r[0] + j[1][k] * r[1])));
        let h = |p: usize, q: usize| w * (j[0][p] * j[0][q] + j[1][p] * j[1][q]);
        // (0, 0) upper triangle, (0, 1) 1 × 2, (1, 1) upper triangle.
        expected.extend([h(0, 0), h(0, 1), h(0, 2), h(1, 1), h(1, 2), h(2, 2)]);
        assert_eq!(outputs.len(), expected.len());
        for (k, (o, e)) in outputs.iter().zip(&expected).enumerate() {
            assert!(
                (o - e).abs() <= 1e-15 * e.abs().max(1.0),
                "output {k}: {o} vs {e}"
            );
        }
        assert_eq!(
            normal.blocks.iter().map(Vec::len).collect::<Vec<_>>(),
            [1, 2, 1, 2, 3]
        );
    }

    #[test]
    fn zeros_ones_and_negations_cost_nothing() {
        let kernel = kernel();
        let normal = lower_normal(&kernel, 3, &[1, 2]);
        // No `−a` or `−c` is computed: they enter as subtractions or signs.
        let live = normal.live(&normal.outputs());
        for (instr, live) in normal.instrs.iter().zip(live) {
            if live {
                assert!(
                    !matches!(instr, Instr::Mul(_, x) | Instr::Mul(x, _)
                        if matches!(normal.instrs[x.0 as usize], Instr::Const(_))
                            && !matches!(normal.instrs[x.0 as usize], Instr::Const(c) if c.get() == 0.5)),
                    "a product with a literal: {instr:?}"
                );
                assert!(!matches!(instr, Instr::Neg(x) if *x == Value(0) || *x == Value(2)));
            }
        }
    }

    #[test]
    fn pairs_are_upper_triangular_row_by_row() {
        assert_eq!(pairs(3), [(0, 0), (0, 1), (0, 2), (1, 1), (1, 2), (2, 2)]);
        assert!(pairs(0).is_empty());
    }
}
