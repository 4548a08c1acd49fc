//! The structure of the reduced system, computed once per problem: which
//! variables are reduced (kept), eliminated or fixed; how the reduced ones
//! are grouped into blocks and ordered; the sparsity of the Schur
//! complement `S` ([`BlockCsc`]); where each eliminated variable's data
//! live; and where each factor's normal-equation blocks go.
//!
//! - **Blocks.** Reduced variables that appear in exactly the same factors
//!   (a BAL camera's pose and intrinsics) form one block of `S`, a
//!   supervariable, as a sparse Cholesky groups equal columns: the
//!   elimination then updates fewer, larger blocks. (Grouping variables
//!   that do not always meet would only store some zeros.)
//! - **Order.** The blocks are numbered in an approximate minimum degree
//!   order of their graph (faer's AMD, on blocks, as Ceres orders its
//!   reduced camera system), so that the Cholesky factorization needs no
//!   permutation; the eliminated variables by their first block, so that
//!   consecutive ones update nearby blocks of `S`; the factors of each type
//!   by their eliminated variable; and the eliminated variables' values
//!   are stored in that order, so that the passes read them in sequence.

use std::collections::HashMap;

use crate::csc::BlockCsc;
use crate::error::SchurError;
use crate::layout::{Topology, Variable};
use crate::ordering::{Lists, adjacency, amd_positions};

/// A variable's part in the solve.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(crate) enum Role {
    /// Kept in the reduced system, in block `block` (in elimination order)
    /// from its tangent coordinate `offset` on.
    Reduced { block: u32, offset: u32 },
    /// Eliminated, as eliminated variable `index`.
    Eliminated { index: u32 },
    /// Held at its value.
    Fixed,
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
/// Everything about the problem's shape the solve needs.
#[derive(Debug, Clone, Default)]
pub(crate) struct Structure {
    /// Each variable's role, by its internal index.
    pub(crate) roles: Vec<Role>,
    /// The variables (their ids) by internal index: the order their values
    /// are stored in, every other variable first, then the eliminated ones
    /// in their order. The groups name variables by internal index.
    pub(crate) storage_order: Vec<u32>,
    /// Each variable's internal index, by id.
    pub(crate) internal: Vec<u32>,
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

/// A 64-bit mix of `x` (SplitMix64's finaliser), to sum into a set's hash.
fn mix(x: u64) -> u64 {
    let mut z = x.wrapping_add(0x9e37_79b9_7f4a_7c15);
    z = (z ^ (z >> 30)).wrapping_mul(0xbf58_476d_1ce4_e5b9);
    z = (z ^ (z >> 27)).wrapping_mul(0x94d0_49bb_1331_11eb);
    z ^ (z >> 31)
}

/// A stable counting sort of `0..keys.len()` by `keys` (below `buckets`;
/// `u32::MAX` sorts last).
fn order_by(keys: &[u32], buckets: usize) -> Vec<usize> {
    let bucket = |k: u32| (k as usize).min(buckets);
    let mut count = vec![0usize; buckets + 2];
    for &k in keys {
        count[bucket(k) + 1] += 1;
    }
    for b in 0..=buckets {
        count[b + 1] += count[b];
    }
    let mut order = vec![0; keys.len()];
    for (i, &k) in keys.iter().enumerate() {
        order[count[bucket(k)]] = i;
        count[bucket(k)] += 1;
    }
    order
}

impl Structure {
    /// The structure of the problem of `variables` (their stored scalars
    /// `values`) and factor `groups`; reorders each group's factors by their
    /// eliminated variable (naming their variables by internal index) and
    /// the variables' stored values, and stores each factor's block targets
    /// in its group.
    ///
    /// # Errors
    ///
    /// [`SchurError::NotSchur`] for a factor on two eliminated variables,
    /// [`SchurError::TooLarge`] for an eliminated tangent above
    /// [`MAX_ELIMINATED`] or indices beyond `u32`.
    pub(crate) fn build<G: Topology + ?Sized>(
        variables: &mut [Variable],
        values: &mut Vec<f64>,
        groups: &mut [Box<G>],
    ) -> Result<Structure, SchurError> {
        let nv = variables.len();
        let tangent: Vec<usize> = variables
            .iter()
            .map(|v| v.chart.map_or(0, |c| c.tangent))
            .collect();
        // Eliminated (numbered in id order for now) and kept variables; a
        // variable no factor names stays as it is.
        let mut eliminated_of = vec![u32::MAX; nv];
        let mut kept = vec![false; nv];
        let mut eliminated_ids = Vec::new();
        for (id, v) in variables.iter().enumerate() {
            if v.chart.is_none() || v.fixed {
                continue;
            }
            if v.eliminated {
                if tangent[id] > MAX_ELIMINATED {
                    return Err(SchurError::TooLarge(format!(
                        "variable {id}: an eliminated variable's tangent has at most \
                         {MAX_ELIMINATED} dimensions, not {}",
                        tangent[id]
                    )));
                }
                eliminated_of[id] = index(eliminated_ids.len(), "eliminated variables")?;
                eliminated_ids.push(id as u32);
            } else {
                kept[id] = true;
            }
        }
        let ne = eliminated_ids.len();
        // Each factor's eliminated variable, and each kept variable's
        // factors as a count and a hash of their indices.
        let mut factor_eliminated = Vec::with_capacity(groups.len());
        let mut signature = vec![(0u32, 0u64); nv];
        let mut global = 0u64;
        for group in groups.iter() {
            let k = group.slots();
            let mut of = Vec::with_capacity(group.len());
            for (i, ids) in group.variable_ids().chunks_exact(k).enumerate() {
                let mut found = u32::MAX;
                for &id in ids {
                    let id = id as usize;
                    if eliminated_of[id] != u32::MAX {
                        if found != u32::MAX {
                            return Err(SchurError::NotSchur {
                                factor: group.name(),
                                index: i,
                            });
                        }
                        found = eliminated_of[id];
                    } else if kept[id] {
                        signature[id].0 += 1;
                        signature[id].1 = signature[id].1.wrapping_add(mix(global));
                    }
                }
                of.push(found);
                global += 1;
            }
            factor_eliminated.push(of);
        }
        // Blocks: kept variables with the same factors, in id order.
        let mut block_of = vec![u32::MAX; nv];
        let mut offset_of = vec![0u32; nv];
        let mut block_dims: Vec<usize> = Vec::new();
        let mut by_signature = HashMap::new();
        for id in (0..nv).filter(|&id| kept[id]) {
            let b = *by_signature.entry(signature[id]).or_insert_with(|| {
                block_dims.push(0);
                block_dims.len() - 1
            });
            block_of[id] = index(b, "blocks")?;
            offset_of[id] = index(block_dims[b], "a block's dimension")?;
            block_dims[b] += tangent[id];
        }
        let nb = block_dims.len();
        // The cliques of the block graph: each eliminated variable's blocks,
        // and those of each factor with no eliminated variable.
        let each_factor = || {
            groups
                .iter()
                .zip(&factor_eliminated)
                .flat_map(|(group, of)| {
                    let k = group.slots();
                    group.variable_ids().chunks_exact(k).zip(of.iter().copied())
                })
        };
        let neighbours = Lists::from_pairs(ne, || {
            each_factor()
                .filter(|&(_, e)| e != u32::MAX)
                .flat_map(|(ids, e)| ids.iter().map(move |&id| (e as usize, id)))
                .filter(|&(_, id)| kept[id as usize])
                .map(|(e, id)| (e, block_of[id as usize]))
        });
        let loose: Vec<&[u32]> = each_factor()
            .filter(|&(_, e)| e == u32::MAX)
            .map(|(ids, _)| ids)
            .collect();
        let loose = Lists::from_pairs(loose.len(), || {
            loose
                .iter()
                .enumerate()
                .flat_map(|(f, ids)| ids.iter().map(move |&id| (f, id)))
                .filter(|&(_, id)| kept[id as usize])
                .map(|(f, id)| (f, block_of[id as usize]))
        });
        let cliques = Lists {
            start: neighbours
                .start
                .iter()
                .copied()
                .chain(loose.start[1..].iter().map(|&s| s + neighbours.items.len()))
                .collect(),
            items: [&neighbours.items[..], &loose.items[..]].concat(),
        };
        let graph = adjacency(nb, &cliques);
        // Blocks in a fill-reducing order.
        let position = amd_positions(&graph)?;
        let mut dims = vec![0; nb];
        for (b, &p) in position.iter().enumerate() {
            dims[p as usize] = block_dims[b];
        }
        let mut below: Vec<Vec<u32>> = vec![Vec::new(); nb];
        for (b, &v) in position.iter().enumerate() {
            let rows = &mut below[v as usize];
            rows.extend(
                graph
                    .list(b)
                    .iter()
                    .map(|&u| position[u as usize])
                    .filter(|&u| u > v),
            );
            rows.sort_unstable();
        }
        let csc = BlockCsc::new(dims, &below);
        index(csc.len(), "entries of the reduced system")?;
        // The eliminated variables ordered by their first block.
        let neighbours = neighbours.map(|b| position[b as usize]);
        let first: Vec<u32> = (0..ne)
            .map(|e| neighbours.list(e).first().copied().unwrap_or(u32::MAX))
            .collect();
        let order = order_by(&first, nb);
        let mut renumber = vec![0u32; ne];
        for (new, &old) in order.iter().enumerate() {
            renumber[old] = new as u32;
        }
        let mut roles = vec![Role::Fixed; nv];
        for id in 0..nv {
            if kept[id] {
                roles[id] = Role::Reduced {
                    block: position[block_of[id] as usize],
                    offset: offset_of[id],
                };
            } else if eliminated_of[id] != u32::MAX {
                roles[id] = Role::Eliminated {
                    index: renumber[eliminated_of[id] as usize],
                };
            }
        }
        // Internal indices: the values' storage order.
        let storage_order: Vec<u32> = (0..nv as u32)
            .filter(|&id| eliminated_of[id as usize] == u32::MAX)
            .chain(order.iter().map(|&old| eliminated_ids[old]))
            .collect();
        let mut internal = vec![0u32; nv];
        for (i, &id) in storage_order.iter().enumerate() {
            internal[id as usize] = i as u32;
        }
        let mut s = Structure {
            roles: storage_order.iter().map(|&id| roles[id as usize]).collect(),
            storage_order,
            internal,
            eliminated_variable: order.iter().map(|&old| eliminated_ids[old]).collect(),
            csc,
            eliminated: Eliminated::default(),
            factor_eliminated: Vec::with_capacity(groups.len()),
        };
        // Factors sorted by their (renumbered) eliminated variable.
        for (group, of) in groups.iter_mut().zip(factor_eliminated) {
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
            let order = order_by(&of, ne);
            group.reorder(&order, &s.internal);
            s.factor_eliminated
                .push(order.iter().map(|&i| of[i]).collect());
        }
        // The eliminated variables' layout.
        let el = &mut s.eliminated;
        let (mut t, mut p, mut c, mut pairs) = (0, 0, 0, 0);
        el.reduced_start.push(0);
        el.pair_start.push(0);
        for (e, &old) in order.iter().enumerate() {
            let d = tangent[s.eliminated_variable[e] as usize];
            let blocks = neighbours.list(old);
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
        for (group, of) in groups.iter_mut().zip(&s.factor_eliminated) {
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
        // The values in storage order.
        let mut stored = Vec::with_capacity(values.len());
        for &id in &s.storage_order {
            let v = &mut variables[id as usize];
            stored.extend_from_slice(&values[v.offset..v.offset + v.scalars]);
            v.offset = stored.len() - v.scalars;
        }
        *values = stored;
        Ok(s)
    }

    /// Where the off-diagonal normal-equation block of variables `a` and `b`
    /// of a factor whose eliminated variable is `e` goes: the prefix of
    /// block `(a, b)` of `S` (reduced, in different blocks), the offset of
    /// the cross block rows relative to `e`'s (one reduced, one
    /// eliminated), or `u32::MAX` (in one block, or either fixed).
    fn target(&self, a: u32, b: u32, e: u32) -> Result<u32, SchurError> {
        let el = &self.eliminated;
        Ok(match (self.roles[a as usize], self.roles[b as usize]) {
            (Role::Reduced { block: u, .. }, Role::Reduced { block: v, .. }) if u != v => {
                let (u, v) = (u.max(v), u.min(v));
                self.csc
                    .prefix(u as usize, v as usize)
                    .expect("variables of one factor are adjacent")
            }
            (Role::Reduced { block, offset }, Role::Eliminated { .. })
            | (Role::Eliminated { .. }, Role::Reduced { block, offset }) => {
                let e = e as usize;
                let d = el.dim(e);
                let mut at = offset as usize * d;
                for &r in el.neighbours(e) {
                    if r == block {
                        break;
                    }
                    at += self.csc.dims[r as usize] * d;
                }
                index(at, "a cross-block offset")?
            }
            _ => u32::MAX,
        })
    }
}
