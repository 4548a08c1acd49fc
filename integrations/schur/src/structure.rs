//! The structure of the reduced system, computed once per problem: which
//! variables are reduced (kept), eliminated or fixed, the fill-reducing
//! order of the reduced ones, the sparsity of the Schur complement `S` as a
//! lower-triangular compressed-column matrix laid out by blocks, where each
//! eliminated variable's cross blocks live, and where each factor's
//! normal-equation blocks go.
//!
//! # The layout of `S`
//!
//! The reduced variables are numbered in the order of an approximate
//! minimum degree ordering of their block graph (faer's AMD, on the blocks,
//! as Ceres orders its reduced camera system), so that the Cholesky
//! factorization needs no permutation. `S` keeps its lower triangle,
//! column by column; block column `v` holds its diagonal block's lower
//! triangle and then, in increasing order, the blocks `(u, v)`, `u > v`, of
//! the reduced variables that share a factor or an eliminated variable with
//! `v`. Every scalar column of a block column has the same rows below the
//! diagonal block, so an entry's index is computed, not searched: see
//! [`BlockCsc::diagonal`] and [`BlockCsc::below`].

use faer::dyn_stack::{MemBuffer, MemStack};
use faer::sparse::SymbolicSparseColMatRef;
use faer::sparse::linalg::amd;

use crate::SchurError;
use crate::problem::Problem;

/// A variable's part in the solve.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(crate) enum Role {
    /// Kept in the reduced system, as its block `block` (in elimination
    /// order).
    Reduced { block: u32 },
    /// Eliminated, as eliminated variable `index`.
    Eliminated { index: u32 },
    /// Held at its value.
    Fixed,
}

/// The lower triangle of the reduced system, by blocks (module
/// documentation).
#[derive(Debug, Clone, Default)]
pub(crate) struct BlockCsc {
    /// Each block's tangent dimension.
    pub(crate) dims: Vec<usize>,
    /// Each block's first scalar row (and column).
    pub(crate) offsets: Vec<usize>,
    /// The index of each block column's first entry.
    column_start: Vec<usize>,
    /// The rows below each block column's diagonal block.
    rows_below: Vec<usize>,
    /// Each block column's blocks below the diagonal: `(u, prefix)`, `prefix`
    /// the rows of the blocks above `u` in that column (below the diagonal),
    /// by increasing `u`; column `v`'s are `below_blocks[below_start[v]..below_start[v + 1]]`.
    below_blocks: Vec<(u32, u32)>,
    below_start: Vec<usize>,
    /// The scalar compressed-column structure, for faer.
    pub(crate) col_ptr: Vec<usize>,
    pub(crate) row_idx: Vec<usize>,
}

impl BlockCsc {
    /// The scalar dimension.
    pub(crate) fn dim(&self) -> usize {
        self.offsets.last().copied().unwrap_or(0) + self.dims.last().copied().unwrap_or(0)
    }

    /// The number of stored entries.
    pub(crate) fn len(&self) -> usize {
        self.row_idx.len()
    }

    /// The index of the first stored entry of scalar column `b` of block
    /// column `v` (its diagonal entry).
    #[inline]
    fn column(&self, v: usize, b: usize) -> usize {
        // Column b' stores d − b' entries of the diagonal block and every
        // row below it.
        let d = self.dims[v];
        self.column_start[v] + b * (d + self.rows_below[v]) - b * b.saturating_sub(1) / 2
    }

    /// Entry `(a, b)`, `a ≥ b`, of diagonal block `v`.
    #[inline]
    pub(crate) fn diagonal(&self, v: usize, a: usize, b: usize) -> usize {
        debug_assert!(a >= b && a < self.dims[v]);
        self.column(v, b) + (a - b)
    }

    /// Entry `(a, b)` of block `(u, v)`, `u > v`, whose rows start at
    /// `prefix` below column `v`'s diagonal block.
    #[inline]
    pub(crate) fn below(&self, v: usize, prefix: u32, a: usize, b: usize) -> usize {
        self.column(v, b) + (self.dims[v] - b) + prefix as usize + a
    }

    /// The prefix of block `(u, v)`, `u > v`, if it is stored.
    pub(crate) fn prefix(&self, u: usize, v: usize) -> Option<u32> {
        let blocks = &self.below_blocks[self.below_start[v]..self.below_start[v + 1]];
        blocks
            .binary_search_by_key(&(u as u32), |&(row, _)| row)
            .ok()
            .map(|k| blocks[k].1)
    }

    /// `Σ_v xᵀ S x` over the symmetric matrix whose lower triangle is
    /// `values`.
    pub(crate) fn quadratic_form(&self, values: &[f64], x: &[f64]) -> f64 {
        let mut total = 0.0;
        for column in 0..self.col_ptr.len().saturating_sub(1) {
            let xc = x[column];
            let entries = self.col_ptr[column]..self.col_ptr[column + 1];
            for (&row, value) in self.row_idx[entries.clone()].iter().zip(&values[entries]) {
                let term = value * x[row] * xc;
                total += if row == column { term } else { 2.0 * term };
            }
        }
        total
    }

    /// The structure of blocks `dims` whose block columns hold the blocks
    /// `below[v]` (increasing) under their diagonal.
    fn new(dims: Vec<usize>, below: &[Vec<u32>]) -> Self {
        let mut offsets = Vec::with_capacity(dims.len());
        let mut n = 0;
        for d in &dims {
            offsets.push(n);
            n += d;
        }
        let mut csc = BlockCsc {
            dims,
            offsets,
            column_start: Vec::with_capacity(below.len()),
            rows_below: Vec::with_capacity(below.len()),
            below_blocks: Vec::new(),
            below_start: vec![0],
            col_ptr: vec![0],
            row_idx: Vec::new(),
        };
        for (v, rows) in below.iter().enumerate() {
            let mut prefix = 0;
            for &u in rows {
                csc.below_blocks.push((u, prefix as u32));
                prefix += csc.dims[u as usize];
            }
            csc.below_start.push(csc.below_blocks.len());
            csc.rows_below.push(prefix);
            csc.column_start.push(csc.row_idx.len());
            let (offset, d) = (csc.offsets[v], csc.dims[v]);
            for b in 0..d {
                csc.row_idx.extend(offset + b..offset + d);
                for &u in rows {
                    let start = csc.offsets[u as usize];
                    csc.row_idx.extend(start..start + csc.dims[u as usize]);
                }
                csc.col_ptr.push(csc.row_idx.len());
            }
        }
        csc
    }
}

/// Where each eliminated variable's data lives: its tangent (gradient and
/// step), its packed block `V` (upper triangle, row by row; its Cholesky
/// factor likewise), its cross blocks `W_re = J_rᵀ J_e` with the reduced
/// variables `r` it shares factors with (`d_r × d_e`, row-major, one after
/// the other in the order of `reduced`), and the prefixes of the blocks of
/// `S` its elimination updates.
#[derive(Debug, Clone, Default)]
pub(crate) struct Eliminated {
    /// Tangent offsets (one more than the variables: the total at the end).
    pub(crate) tangent: Vec<usize>,
    /// Packed `V` offsets.
    pub(crate) packed: Vec<usize>,
    /// Cross-block offsets.
    pub(crate) cross: Vec<usize>,
    /// Each one's reduced neighbours (block indices, increasing):
    /// `reduced[reduced_start[e]..reduced_start[e + 1]]`.
    pub(crate) reduced_start: Vec<usize>,
    pub(crate) reduced: Vec<u32>,
    /// For each pair `i > j` of its reduced neighbours (in the order
    /// `(1, 0), (2, 0), (2, 1), (3, 0), …`), the prefix of block
    /// `(reduced[i], reduced[j])` in `S`: `prefixes[pair_start[e]..]`.
    pub(crate) pair_start: Vec<usize>,
    pub(crate) prefixes: Vec<u32>,
}

impl Eliminated {
    /// The number of eliminated variables.
    pub(crate) fn len(&self) -> usize {
        self.tangent.len().saturating_sub(1)
    }

    /// The tangent dimension of eliminated variable `e`.
    pub(crate) fn dim(&self, e: usize) -> usize {
        self.tangent[e + 1] - self.tangent[e]
    }

    /// Its reduced neighbours.
    pub(crate) fn neighbours(&self, e: usize) -> &[u32] {
        &self.reduced[self.reduced_start[e]..self.reduced_start[e + 1]]
    }
}

/// The largest tangent of an eliminated variable (a point or landmark has
/// 3, a line 4, a plane 3).
pub(crate) const MAX_ELIMINATED: usize = 6;
/// The most variables a factor may have.
pub(crate) const MAX_SLOTS: usize = 8;
/// The most stored scalars a factor may have.
pub(crate) const MAX_SCALARS: usize = 128;

/// Everything about the problem's shape the solve needs.
#[derive(Debug, Clone, Default)]
pub(crate) struct Structure {
    /// Each variable's role.
    pub(crate) roles: Vec<Role>,
    /// The variable of each reduced block.
    pub(crate) block_variable: Vec<u32>,
    /// The variable of each eliminated index.
    pub(crate) eliminated_variable: Vec<u32>,
    pub(crate) csc: BlockCsc,
    pub(crate) eliminated: Eliminated,
    /// Per group, each factor's eliminated variable (`u32::MAX` for none),
    /// the factors in increasing order of it.
    pub(crate) factor_eliminated: Vec<Vec<u32>>,
}

/// `Ok(x as u32)`, or the problem is too large for the solver's indices.
fn index(x: usize, what: &str) -> Result<u32, SchurError> {
    u32::try_from(x).map_err(|_| SchurError::TooLarge(format!("{what}: {x} is 2³² or more")))
}

impl Structure {
    /// The structure of `problem`; reorders each group's factors by their
    /// eliminated variable and stores each factor's block targets in it.
    ///
    /// # Errors
    ///
    /// [`SchurError::NotSchur`] for a factor on two eliminated variables,
    /// [`SchurError::TooLarge`] for an eliminated tangent above
    /// [`MAX_ELIMINATED`] or indices beyond `u32`.
    pub(crate) fn build(problem: &mut Problem) -> Result<Structure, SchurError> {
        let mut s = Structure::default();
        // Roles, in the order of the variables (reduced blocks and
        // eliminated indices renumbered below).
        let (mut reduced, mut eliminated) = (0u32, 0u32);
        for (id, v) in problem.variables.iter().enumerate() {
            // A variable no factor names stays as it is.
            let Some(chart) = v.chart.as_ref() else {
                s.roles.push(Role::Fixed);
                continue;
            };
            s.roles.push(if v.fixed {
                Role::Fixed
            } else if v.eliminated {
                if chart.tangent > MAX_ELIMINATED {
                    return Err(SchurError::TooLarge(format!(
                        "variable {id}: an eliminated variable's tangent has at most \
                         {MAX_ELIMINATED} dimensions, not {}",
                        chart.tangent
                    )));
                }
                s.eliminated_variable.push(id as u32);
                eliminated += 1;
                Role::Eliminated {
                    index: eliminated - 1,
                }
            } else {
                reduced += 1;
                Role::Reduced { block: reduced - 1 }
            });
        }
        let tangent_of = |id: u32| {
            problem.variables[id as usize]
                .chart
                .as_ref()
                .map_or(0, |c| c.tangent)
        };
        // Each factor's eliminated variable (or none).
        let mut factor_eliminated = Vec::with_capacity(problem.groups.len());
        for group in &problem.groups {
            let k = group.slots();
            let mut of = Vec::with_capacity(group.len());
            for (i, ids) in group.variable_ids().chunks_exact(k).enumerate() {
                let mut found = u32::MAX;
                for &id in ids {
                    if let Role::Eliminated { index } = s.roles[id as usize] {
                        if found != u32::MAX {
                            return Err(SchurError::NotSchur {
                                factor: group.name(),
                                index: i,
                            });
                        }
                        found = index;
                    }
                }
                of.push(found);
            }
            factor_eliminated.push(of);
        }
        // Each eliminated variable's reduced neighbours (by variable id for
        // now), and the cliques of the block graph: those neighbour sets,
        // and the reduced variables of each factor with no eliminated one.
        let ne = eliminated as usize;
        let mut neighbours: Vec<Vec<u32>> = vec![Vec::new(); ne];
        let mut cliques: Vec<Vec<u32>> = Vec::new();
        for (group, of) in problem.groups.iter().zip(&factor_eliminated) {
            let k = group.slots();
            for (ids, &e) in group.variable_ids().chunks_exact(k).zip(of) {
                let kept = ids
                    .iter()
                    .copied()
                    .filter(|&id| matches!(s.roles[id as usize], Role::Reduced { .. }));
                if e == u32::MAX {
                    cliques.push(kept.collect());
                } else {
                    neighbours[e as usize].extend(kept);
                }
            }
        }
        // The fill-reducing order of the reduced variables.
        let reduced_ids: Vec<u32> = (0..s.roles.len() as u32)
            .filter(|&id| matches!(s.roles[id as usize], Role::Reduced { .. }))
            .collect();
        let node_of = |id: u32| match s.roles[id as usize] {
            Role::Reduced { block } => block as usize,
            _ => usize::MAX,
        };
        let graph = block_graph(
            reduced_ids.len(),
            neighbours.iter().chain(&cliques),
            &node_of,
        );
        let position = amd_positions(&graph)?;
        s.block_variable = vec![0; reduced_ids.len()];
        for (&id, &p) in reduced_ids.iter().zip(&position) {
            s.roles[id as usize] = Role::Reduced { block: p };
            s.block_variable[p as usize] = id;
        }
        let block_of = |id: u32| match s.roles[id as usize] {
            Role::Reduced { block } => block,
            _ => u32::MAX,
        };
        // Each eliminated variable's neighbours as blocks, increasing; the
        // eliminated variables renumbered by their first neighbour, so
        // that consecutive ones update nearby blocks of S.
        let mut neighbours: Vec<Vec<u32>> = neighbours
            .into_iter()
            .map(|list| {
                let mut blocks: Vec<u32> = list.into_iter().map(block_of).collect();
                blocks.sort_unstable();
                blocks.dedup();
                blocks
            })
            .collect();
        let mut order: Vec<usize> = (0..ne).collect();
        order.sort_by_key(|&e| neighbours[e].first().copied().unwrap_or(u32::MAX));
        let mut renumber = vec![0u32; ne];
        for (new, &old) in order.iter().enumerate() {
            renumber[old] = new as u32;
        }
        s.eliminated_variable = order
            .iter()
            .map(|&old| s.eliminated_variable[old])
            .collect();
        for (e, &id) in s.eliminated_variable.iter().enumerate() {
            s.roles[id as usize] = Role::Eliminated { index: e as u32 };
        }
        let mut taken: Vec<Vec<u32>> = order
            .iter()
            .map(|&old| std::mem::take(&mut neighbours[old]))
            .collect();
        std::mem::swap(&mut neighbours, &mut taken);
        // Factors sorted by their (renumbered) eliminated variable.
        for (group, of) in problem.groups.iter_mut().zip(factor_eliminated) {
            let of: Vec<u32> = of
                .into_iter()
                .map(|e| {
                    if e == u32::MAX {
                        e
                    } else {
                        renumber[e as usize]
                    }
                })
                .collect();
            let mut order: Vec<usize> = (0..of.len()).collect();
            order.sort_by_key(|&i| of[i]);
            group.reorder(&order);
            s.factor_eliminated
                .push(order.iter().map(|&i| of[i]).collect());
        }
        // The blocks below each diagonal block, in the new order.
        let mut below: Vec<Vec<u32>> = vec![Vec::new(); reduced_ids.len()];
        for (old, adjacent) in graph.iter().enumerate() {
            let v = position[old];
            below[v as usize].extend(
                adjacent
                    .iter()
                    .map(|&u| position[u as usize])
                    .filter(|&u| u > v),
            );
        }
        for rows in &mut below {
            rows.sort_unstable();
        }
        let dims = s.block_variable.iter().map(|&id| tangent_of(id)).collect();
        s.csc = BlockCsc::new(dims, &below);
        index(s.csc.len(), "entries of the reduced system")?;
        // The eliminated variables' layout.
        let el = &mut s.eliminated;
        let (mut t, mut p, mut c, mut pairs) = (0, 0, 0, 0);
        el.reduced_start.push(0);
        el.pair_start.push(0);
        for (e, blocks) in neighbours.iter().enumerate() {
            let d = tangent_of(s.eliminated_variable[e]);
            el.tangent.push(t);
            el.packed.push(p);
            el.cross.push(c);
            t += d;
            p += d * (d + 1) / 2;
            c += blocks
                .iter()
                .map(|&b| s.csc.dims[b as usize] * d)
                .sum::<usize>();
            for i in 1..blocks.len() {
                for j in 0..i {
                    let prefix = s
                        .csc
                        .prefix(blocks[i] as usize, blocks[j] as usize)
                        .expect("neighbours of one eliminated variable are adjacent");
                    el.prefixes.push(prefix);
                }
            }
            pairs += blocks.len() * blocks.len().saturating_sub(1) / 2;
            el.reduced.extend(blocks);
            el.reduced_start.push(el.reduced.len());
            el.pair_start.push(pairs);
        }
        el.tangent.push(t);
        el.packed.push(p);
        el.cross.push(c);
        index(c, "entries of the cross blocks")?;
        // Each factor's targets, pair by pair.
        for (group, of) in problem.groups.iter_mut().zip(&s.factor_eliminated) {
            let k = group.slots();
            let mut targets = Vec::with_capacity(group.len() * k * (k - 1) / 2);
            for (ids, &e) in group.variable_ids().chunks_exact(k).zip(of) {
                for a in 0..k {
                    for b in a + 1..k {
                        targets.push(s.target(ids[a], ids[b], e)?);
                    }
                }
            }
            group.set_targets(targets);
        }
        Ok(s)
    }

    /// Where the off-diagonal normal-equation block of variables `a` and `b`
    /// of a factor whose eliminated variable is `e` goes: the prefix of
    /// block `(a, b)` of `S` (both reduced), the offset of the cross block
    /// relative to `e`'s (one reduced, one eliminated), or `u32::MAX`
    /// (either fixed).
    fn target(&self, a: u32, b: u32, e: u32) -> Result<u32, SchurError> {
        let el = &self.eliminated;
        Ok(match (self.roles[a as usize], self.roles[b as usize]) {
            (Role::Reduced { block: u }, Role::Reduced { block: v }) => {
                let (u, v) = (u.max(v), u.min(v));
                self.csc
                    .prefix(u as usize, v as usize)
                    .expect("variables of one factor are adjacent")
            }
            (Role::Reduced { block }, Role::Eliminated { .. })
            | (Role::Eliminated { .. }, Role::Reduced { block }) => {
                let e = e as usize;
                let d = el.dim(e);
                let mut offset = 0;
                for &r in el.neighbours(e) {
                    if r == block {
                        break;
                    }
                    offset += self.csc.dims[r as usize] * d;
                }
                index(offset, "a cross-block offset")?
            }
            _ => u32::MAX,
        })
    }
}

/// The adjacency of the block graph on `n` nodes whose edges join every two
/// members of each clique (variable ids mapped to nodes by `node`), each
/// list increasing, without the node itself.
fn block_graph<'a>(
    n: usize,
    cliques: impl Iterator<Item = &'a Vec<u32>> + Clone,
    node: &impl Fn(u32) -> usize,
) -> Vec<Vec<u32>> {
    // Which cliques hold each node, then each node's neighbours marked once.
    let mut member_of: Vec<Vec<u32>> = vec![Vec::new(); n];
    let cliques: Vec<&Vec<u32>> = cliques.collect();
    for (c, clique) in cliques.iter().enumerate() {
        for &id in clique.iter() {
            member_of[node(id)].push(c as u32);
        }
    }
    let mut mark = vec![u32::MAX; n];
    let mut adjacency = Vec::with_capacity(n);
    for (u, cliques_of_u) in member_of.iter().enumerate() {
        let mut list = Vec::new();
        mark[u] = u as u32;
        for &c in cliques_of_u {
            for &id in cliques[c as usize].iter() {
                let v = node(id);
                if mark[v] != u as u32 {
                    mark[v] = u as u32;
                    list.push(v as u32);
                }
            }
        }
        list.sort_unstable();
        adjacency.push(list);
    }
    adjacency
}

/// Each node's position in an approximate minimum degree ordering of the
/// graph `adjacency` (faer's AMD).
fn amd_positions(adjacency: &[Vec<u32>]) -> Result<Vec<u32>, SchurError> {
    let n = adjacency.len();
    let mut col_ptr = Vec::with_capacity(n + 1);
    let mut row_idx = Vec::new();
    col_ptr.push(0usize);
    for list in adjacency {
        row_idx.extend(list.iter().map(|&v| v as usize));
        col_ptr.push(row_idx.len());
    }
    let pattern = SymbolicSparseColMatRef::new_checked(n, n, &col_ptr, None, &row_idx);
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
        .map(|p| index(p, "a block position"))
        .collect()
}

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

#[cfg(test)]
mod tests {
    use super::*;

    /// Three blocks (dims 2, 1, 3): column 0 has blocks 1 and 2 below it,
    /// column 1 block 2, column 2 none. Every entry's computed index is its
    /// place in the scalar structure.
    #[test]
    fn entries_are_found_where_the_scalar_structure_has_them() {
        let csc = BlockCsc::new(vec![2, 1, 3], &[vec![1, 2], vec![2], vec![]]);
        assert_eq!(csc.dim(), 6);
        let entry = |row: usize, column: usize| {
            (csc.col_ptr[column]..csc.col_ptr[column + 1])
                .find(|&k| csc.row_idx[k] == row)
                .expect("stored")
        };
        for v in 0..3 {
            let (o, d) = (csc.offsets[v], csc.dims[v]);
            for b in 0..d {
                for a in b..d {
                    assert_eq!(csc.diagonal(v, a, b), entry(o + a, o + b));
                }
                for &(u, prefix) in &csc.below_blocks[csc.below_start[v]..csc.below_start[v + 1]] {
                    assert_eq!(csc.prefix(u as usize, v), Some(prefix));
                    let ou = csc.offsets[u as usize];
                    for a in 0..csc.dims[u as usize] {
                        assert_eq!(csc.below(v, prefix, a, b), entry(ou + a, o + b));
                    }
                }
            }
        }
        assert_eq!(csc.prefix(0, 1), None);
        // xᵀSx of the symmetric matrix with every stored entry 1 in its
        // lower triangle and x = 1: diagonal entries once, the others twice.
        let ones = vec![1.0; csc.len()];
        let diagonal = 6.0;
        assert_eq!(
            csc.quadratic_form(&ones, &[1.0; 6]),
            2.0 * csc.len() as f64 - diagonal
        );
    }

    #[test]
    fn graphs_join_the_members_of_each_clique() {
        let cliques = [vec![0, 2], vec![2, 3, 1]];
        let graph = block_graph(4, cliques.iter(), &|id| id as usize);
        assert_eq!(graph, [vec![2], vec![2, 3], vec![0, 1, 3], vec![1, 2]]);
        let positions = amd_positions(&graph).unwrap();
        let mut sorted = positions.clone();
        sorted.sort_unstable();
        assert_eq!(sorted, [0, 1, 2, 3]);
    }
}
