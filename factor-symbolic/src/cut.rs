//! Minimum vertex cuts between the tangent inputs and the residual.
//!
//! Every path from a tangent coordinate `δₖ` to a residual entry passes
//! through a cut `c`, so the chain rule `∂r/∂δ = ∂r/∂c · ∂c/∂δ` holds with
//! `c` held as independent variables in the first factor. A hand derivation
//! cuts at the camera-frame point or line (`∂r/∂X_c · ∂X_c/∂ξ`, document 000
//! (4)–(5), (10)–(12)): a handful of values, all of the residual's nonlinear
//! work above them (shared by every tangent column) and the simple action of
//! the perturbation below. Cuts are found here by max-flow (unit vertex
//! capacities, Edmonds–Karp), narrowest first; the residual entries
//! themselves are never part of one, since cutting there is no chain rule at
//! all. Which cut pays off is not decided here: [`crate::trace`]
//! compiles each candidate and keeps the cheapest.

use std::collections::{HashMap, HashSet, VecDeque};

use crate::graph::{Expr, node};

/// Successive cuts between `sources` and `outputs`, nearest the sources
/// first among the narrowest: the first is the minimum cut nearest the
/// sources; each next one is the minimum cut nearest the sources once every
/// node of the cuts before it is forbidden. At most `limit` cuts, each sorted
/// by id. No cut contains an output or consists of sources only (that would
/// be no chain rule at all; such a cut is skipped, and the search goes on
/// past it).
///
/// Forbidding a cut moves the next one up or down the graph: for a point
/// projected as `fᵤ X/Z`, the narrowest cut is the two products `fᵤ X Z⁻¹`,
/// `f_v Y Z⁻¹` (the residual itself, nearly), and the next is the
/// camera-frame point `(X, Y, Z)`, the cut of document 000 (2)–(4).
pub fn minimum_cuts(outputs: &[Expr], sources: &[Expr], limit: usize) -> Vec<Vec<Expr>> {
    let mut forbidden = HashSet::new();
    let mut cuts = Vec::new();
    // The sources can be a minimum cut once: they are forbidden like any
    // other, but not a candidate.
    for _ in 0..=limit {
        let Some(cut) = Network::build(outputs, sources, &forbidden).and_then(Network::cut) else {
            break;
        };
        forbidden.extend(cut.iter().copied());
        if !cut.iter().all(|c| sources.contains(c)) {
            cuts.push(cut);
        }
        if cuts.len() == limit {
            break;
        }
    }
    cuts
}

const INFINITE: u32 = u32::MAX / 2;

/// The split-vertex flow network: node `v` of the DAG becomes `2v` (in) and
/// `2v + 1` (out) joined by its capacity; data edges child → parent are
/// infinite; the super source feeds every source, every output feeds the
/// super sink. Outputs and forbidden nodes have infinite capacity.
struct Network {
    /// DAG nodes that depend on a source, in id order.
    nodes: Vec<Expr>,
    /// Residual capacities, `edges[2i]` forward and `edges[2i + 1]` backward.
    edges: Vec<(usize, u32)>,
    /// Edge indices leaving each network vertex.
    adjacent: Vec<Vec<usize>>,
    source: usize,
    sink: usize,
}

impl Network {
    fn build(outputs: &[Expr], sources: &[Expr], forbidden: &HashSet<Expr>) -> Option<Network> {
        // Nodes below the outputs, children before parents (ids are
        // topological), then those that depend on a source.
        let mut below = Vec::new();
        let mut seen = HashSet::new();
        let mut stack: Vec<Expr> = outputs.to_vec();
        while let Some(e) = stack.pop() {
            if seen.insert(e) {
                stack.extend(node(e).children());
                below.push(e);
            }
        }
        below.sort();
        let mut dependent: HashMap<Expr, usize> = HashMap::new();
        let mut nodes = Vec::new();
        let mut children = Vec::new();
        for &e in &below {
            let kids: Vec<usize> = node(e)
                .children()
                .iter()
                .filter_map(|c| dependent.get(c).copied())
                .collect();
            if sources.contains(&e) || !kids.is_empty() {
                dependent.insert(e, nodes.len());
                nodes.push(e);
                children.push(kids);
            }
        }
        if !outputs.iter().any(|o| dependent.contains_key(o)) {
            return None;
        }
        let (source, sink) = (2 * nodes.len(), 2 * nodes.len() + 1);
        let mut network = Network {
            nodes,
            edges: Vec::new(),
            adjacent: vec![Vec::new(); 2 * dependent.len() + 2],
            source,
            sink,
        };
        for (i, kids) in children.iter().enumerate() {
            let e = network.nodes[i];
            let is_output = outputs.contains(&e);
            let capacity = if is_output || forbidden.contains(&e) {
                INFINITE
            } else {
                1
            };
            network.add(2 * i, 2 * i + 1, capacity);
            for &k in kids {
                network.add(2 * k + 1, 2 * i, INFINITE);
            }
            if sources.contains(&e) {
                network.add(source, 2 * i, INFINITE);
            }
            if is_output {
                network.add(2 * i + 1, sink, INFINITE);
            }
        }
        Some(network)
    }

    fn add(&mut self, from: usize, to: usize, capacity: u32) {
        self.adjacent[from].push(self.edges.len());
        self.edges.push((to, capacity));
        self.adjacent[to].push(self.edges.len());
        self.edges.push((from, 0));
    }

    /// Saturates the network; `None` when the flow is unbounded (an output
    /// is itself a source, so no cut avoids the outputs).
    fn saturate(&mut self) -> Option<()> {
        let mut total: u64 = 0;
        while let Some(path) = self.augmenting_path() {
            let bottleneck = path.iter().map(|&i| self.edges[i].1).min()?;
            if bottleneck >= INFINITE {
                return None;
            }
            for &i in &path {
                self.edges[i].1 -= bottleneck;
                self.edges[i ^ 1].1 += bottleneck;
            }
            total += u64::from(bottleneck);
            if total >= u64::from(INFINITE) {
                return None;
            }
        }
        Some(())
    }

    /// Edge indices of a shortest source → sink path with residual capacity.
    fn augmenting_path(&self) -> Option<Vec<usize>> {
        let mut via = vec![usize::MAX; self.adjacent.len()];
        let mut queue = VecDeque::from([self.source]);
        while let Some(v) = queue.pop_front() {
            for &i in &self.adjacent[v] {
                let (w, capacity) = self.edges[i];
                if capacity > 0 && w != self.source && via[w] == usize::MAX {
                    via[w] = i;
                    if w == self.sink {
                        let mut path = Vec::new();
                        let mut at = w;
                        while at != self.source {
                            path.push(via[at]);
                            at = self.edges[via[at] ^ 1].0;
                        }
                        return Some(path);
                    }
                    queue.push_back(w);
                }
            }
        }
        None
    }

    /// Network vertices reachable from `start` along residual capacity.
    fn reachable(&self, start: usize) -> Vec<bool> {
        let mut seen = vec![false; self.adjacent.len()];
        seen[start] = true;
        let mut queue = VecDeque::from([start]);
        while let Some(v) = queue.pop_front() {
            for &i in &self.adjacent[v] {
                let (w, capacity) = self.edges[i];
                if capacity > 0 && !seen[w] {
                    seen[w] = true;
                    queue.push_back(w);
                }
            }
        }
        seen
    }

    /// The minimum cut nearest the source: the saturated vertices whose in
    /// side the source still reaches. `None` when the flow is unbounded.
    fn cut(mut self) -> Option<Vec<Expr>> {
        self.saturate()?;
        let from_source = self.reachable(self.source);
        Some(
            (0..self.nodes.len())
                .filter(|&i| from_source[2 * i] && !from_source[2 * i + 1])
                .map(|i| self.nodes[i])
                .collect(),
        )
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::Tracer;

    /// `c = a + b`, `d = x·c`, `r = [√d, sin d + x]` with sources `a, b`:
    /// the cuts are `{c}`, then `{d}`, then none (only the outputs remain).
    #[test]
    fn cuts_move_from_the_sources_towards_the_outputs() {
        let _tracer = Tracer::new();
        let (a, b, x) = (Expr::input(0), Expr::input(1), Expr::input(2));
        let c = a + b;
        let d = x * c;
        let r = [d.sqrt(), d.sin() + x];
        assert_eq!(minimum_cuts(&r, &[a, b], 4), vec![vec![c], vec![d]]);
    }

    /// With two sources on two independent paths, the sources themselves
    /// are the first minimum cut: skipped, and the search goes on up the
    /// paths. A residual made directly of the sources has no cut.
    #[test]
    fn the_sources_are_never_a_candidate() {
        let _tracer = Tracer::new();
        let (a, b, x) = (Expr::input(0), Expr::input(1), Expr::input(2));
        let (s, t) = (a + x, b + x);
        let (p, q) = (s.sin(), t.sqrt());
        let r = [(p + q).cos(), (p * q).sqrt()];
        let sorted = |mut v: Vec<Expr>| {
            v.sort();
            v
        };
        assert_eq!(
            minimum_cuts(&r, &[a, b], 2),
            vec![sorted(vec![s, t]), sorted(vec![p, q])]
        );
        assert!(minimum_cuts(&[a * b], &[a, b], 4).is_empty());
    }
}
