//! Where one thread's linearization writes ([`Sink`]): the normal blocks of
//! a chunk of factors, laid out as the fused kernels lay theirs out, added
//! by their variables' roles into the reduced blocks, the eliminated
//! variables' blocks and the cross blocks.

use std::time::Duration;

use crate::structure::{Role, Structure};

/// Where one thread's linearization writes: its own accumulators of the
/// reduced blocks (`u`: the entries of `S`'s structure off the diagonal
/// blocks, `diagonal`: the diagonal blocks whole, where a factor's entries
/// go at fixed strides, `g_reduced`: the reduced gradient), and the slices of the eliminated variables' data of
/// its range, which starts at eliminated variable `first`.
pub(crate) struct Sink<'a> {
    pub(crate) u: &'a mut [f64],
    /// The diagonal blocks of `U`, each kept whole (`BlockCsc::dense`).
    pub(crate) diagonal: &'a mut [f64],
    pub(crate) g_reduced: &'a mut [f64],
    pub(crate) first: usize,
    pub(crate) g_eliminated: &'a mut [f64],
    pub(crate) v: &'a mut [f64],
    pub(crate) w: &'a mut [f64],
    /// The first eliminated variable whose data are not zeroed yet.
    pub(crate) cleared: usize,
    /// Time spent in the batch kernels.
    pub(crate) kernels: Duration,
}

impl Sink<'_> {
    /// Zeroes the data of the eliminated variables of this range up to
    /// `e` not zeroed yet: each variable's blocks are zeroed as its first
    /// factor's are added, while they are in the cache.
    #[inline]
    pub(crate) fn clear_through(&mut self, e: usize, structure: &Structure) {
        if e < self.cleared {
            return;
        }
        let el = &structure.eliminated;
        let (from, to) = (self.cleared, e + 1);
        let f = self.first;
        self.g_eliminated[el.tangent[from] - el.tangent[f]..el.tangent[to] - el.tangent[f]]
            .fill(0.0);
        self.v[el.packed[from] - el.packed[f]..el.packed[to] - el.packed[f]].fill(0.0);
        self.w[el.cross[from] - el.cross[f]..el.cross[to] - el.cross[f]].fill(0.0);
        self.cleared = to;
    }

    /// Adds a factor's gradient block (`g[a][row]`) of a variable with
    /// `role`.
    #[inline]
    pub(crate) fn add_gradient(
        &mut self,
        role: Role,
        g: &[&[f64]],
        row: usize,
        structure: &Structure,
    ) {
        let target = match role {
            Role::Reduced { block, offset } => {
                let o = structure.csc.offsets[block as usize] + offset as usize;
                &mut self.g_reduced[o..o + g.len()]
            }
            Role::Eliminated { index } => {
                let el = &structure.eliminated;
                let o = el.tangent[index as usize] - el.tangent[self.first];
                &mut self.g_eliminated[o..o + g.len()]
            }
            Role::Fixed => return,
        };
        for (t, column) in target.iter_mut().zip(g) {
            *t += column[row];
        }
    }

    /// Adds a factor's diagonal Hessian block of a variable with `role` and
    /// tangent dimension `d`: the kernel's upper triangle (`a ≤ b`) row by
    /// row.
    #[inline]
    pub(crate) fn add_diagonal(
        &mut self,
        role: Role,
        d: usize,
        h: &[&[f64]],
        row: usize,
        structure: &Structure,
    ) {
        match role {
            // Rows a of the kernel's upper triangle, into the whole block.
            Role::Reduced { block, offset } => {
                let csc = &structure.csc;
                let (b, o) = (block as usize, offset as usize);
                let db = csc.dims[b];
                let whole = &mut self.diagonal[csc.dense[b]..csc.dense[b + 1]];
                let mut c = 0;
                for a in 0..d {
                    let at = (o + a) * db + o + a;
                    for (t, column) in whole[at..at + d - a].iter_mut().zip(&h[c..c + d - a]) {
                        *t += column[row];
                    }
                    c += d - a;
                }
            }
            // V is packed as the kernel packs it.
            Role::Eliminated { index } => {
                let el = &structure.eliminated;
                let o = el.packed[index as usize] - el.packed[self.first];
                for (t, column) in self.v[o..o + h.len()].iter_mut().zip(h) {
                    *t += column[row];
                }
            }
            Role::Fixed => {}
        }
    }

    /// Adds a factor's off-diagonal Hessian block `J_iᵀ J_j` (`d_i × d_j`,
    /// row-major) of variables with roles `i` and `j`, at `target`
    /// ([`Structure`]: the block's prefix in `S`, or the cross block's
    /// offset).
    #[inline]
    pub(crate) fn add_pair(
        &mut self,
        (i, di): (Role, usize),
        (j, dj): (Role, usize),
        target: u32,
        h: &[&[f64]],
        row: usize,
        structure: &Structure,
    ) {
        let csc = &structure.csc;
        match (i, j) {
            // Both in one block: J_iᵀ J_j at their offsets in the whole
            // diagonal block.
            (
                Role::Reduced {
                    block: bi,
                    offset: oi,
                },
                Role::Reduced {
                    block: bj,
                    offset: oj,
                },
            ) if bi == bj => {
                let b = bi as usize;
                let db = csc.dims[b];
                let whole = &mut self.diagonal[csc.dense[b]..csc.dense[b + 1]];
                for a in 0..di {
                    let at = (oi as usize + a) * db + oj as usize;
                    for (t, column) in whole[at..at + dj].iter_mut().zip(&h[a * dj..(a + 1) * dj]) {
                        *t += column[row];
                    }
                }
            }
            // Block (u, v), u > v, of S holds J_uᵀ J_v at the variables'
            // offsets: the kernel's block when u is slot i's, else its
            // transpose.
            (
                Role::Reduced {
                    block: bi,
                    offset: oi,
                },
                Role::Reduced {
                    block: bj,
                    offset: oj,
                },
            ) => {
                let (oi, oj) = (oi as usize, oj as usize);
                for a in 0..di {
                    for b in 0..dj {
                        let index = if bi > bj {
                            csc.below(bj as usize, target, oi + a, oj + b)
                        } else {
                            csc.below(bi as usize, target, oj + b, oi + a)
                        };
                        self.u[index] += h[a * dj + b][row];
                    }
                }
            }
            // W_re (d_r × d_e, row-major) is J_rᵀ J_e: the kernel's block
            // when the reduced variable is slot i, else its transpose.
            (Role::Reduced { .. }, Role::Eliminated { index: e })
            | (Role::Eliminated { index: e }, Role::Reduced { .. }) => {
                let el = &structure.eliminated;
                let o = el.cross[e as usize] - el.cross[self.first] + target as usize;
                let w = &mut self.w[o..o + di * dj];
                if matches!(i, Role::Reduced { .. }) {
                    for (t, column) in w.iter_mut().zip(h) {
                        *t += column[row];
                    }
                } else {
                    for a in 0..di {
                        for b in 0..dj {
                            w[b * di + a] += h[a * dj + b][row];
                        }
                    }
                }
            }
            _ => {}
        }
    }
}
