//! The observability check of a g2o line, plane and point graph, as a
//! problem file has it ([`slamjac_problem::observability`]): at the
//! initial values and at the solution, the directions of the free vertices (those not on
//! a `FIX` line) that no edge's whitened Jacobian determines — a graph
//! without its `FIX` line (a gauge left free), a vertex no edge joins, a
//! pose held only by a prior that weighs its height alone.
//!
//! Each edge is linearized as `--kernels generated` does (its generated
//! kernel where it has one, dual numbers otherwise), at the vertices'
//! values, in its variables' own tangents; the first free vertex of each
//! kind names the tangent's coordinates.

use std::collections::HashMap;

use factor_core::Factor;
use factor_minimizer::Verdict;
use nalgebra::DMatrix;
use slam_data::G2oGraph;
use slam_problems::g2o_edges::{self, G2oEdge, G2oFactor, Vertices};
use slamjac_problem::observability::{
    DRIFT_TOLERANCE, Deficiency, Normal, TOLERANCE, Variable, tangent_columns,
};

use slamjac_registry::method::{Method, linearize};

use crate::error::SolveError;

/// Refuses `graph` at its initial values when its edges leave a direction
/// of its free vertices undetermined (exit 1, nothing solved).
///
/// # Errors
///
/// [`SolveError::Usage`] for a graph whose vertices or edges cannot be
/// built, [`SolveError::Solve`] naming the undetermined directions.
pub fn check_initial(file: &std::path::Path, graph: &G2oGraph) -> Result<(), SolveError> {
    let at = |what: String| format!("{}: {what}", file.display());
    let vertices = Vertices::read(graph).map_err(|e| SolveError::Usage(at(e.to_string())))?;
    match deficiency(graph, &vertices, TOLERANCE).map_err(|e| SolveError::Usage(at(e)))? {
        Some(d) => Err(SolveError::Solve(at(format!(
            "{d}; nothing solved: hold more vertices fixed (a FIX line) or add edges"
        )))),
        None => Ok(()),
    }
}

/// The same check at the solution `solved` of the graph `initial`, which
/// the solve ended with `verdict`: the reason to refuse it, if any.
///
/// After a converged solve within [`TOLERANCE`]. After one that stopped
/// unconverged within [`DRIFT_TOLERANCE`] (a direction determined that
/// weakly is where the solve drifted), unless the initial values already
/// determined a direction that weakly: `line3d.g2o` does at its file's
/// values and at its optimum, and a solve stopped by the iteration limit
/// has not drifted for that.
pub fn check_solution(
    initial: &G2oGraph,
    solved: &G2oGraph,
    verdict: &Verdict,
) -> Result<(), String> {
    let vertices = Vertices::read(solved).map_err(|e| e.to_string())?;
    let strict = || deficiency(solved, &vertices, TOLERANCE);
    let found = if verdict.is_converged() {
        strict()?
    } else {
        match deficiency(solved, &vertices, DRIFT_TOLERANCE)? {
            Some(drift) => {
                let at_start = Vertices::read(initial).map_err(|e| e.to_string())?;
                if deficiency(initial, &at_start, DRIFT_TOLERANCE)?.is_some() {
                    strict()?
                } else {
                    Some(drift)
                }
            }
            None => None,
        }
    };
    found.map_or(Ok(()), |d| Err(d.at("the solution").to_string()))
}

/// The free vertices' directions `graph`'s edges do not determine at the
/// values `vertices` holds, within `tolerance` (`observability::TOLERANCE`,
/// or the drift tolerance at the solution of a solve that did not
/// converge); `None` when every direction is determined.
///
/// # Errors
///
/// An edge that cannot be built at these values (`g2o_edges::edges`), a
/// free vertex no edge joins.
fn deficiency(
    graph: &G2oGraph,
    vertices: &Vertices,
    tolerance: f64,
) -> Result<Option<Deficiency>, String> {
    let edges = g2o_edges::edges(graph, vertices).map_err(|e| e.to_string())?;
    let free = |id: &usize| !graph.fixed.contains(id);
    let mut ids: Vec<(usize, &'static str)> = Vec::new();
    ids.extend(vertices.poses.iter().map(|(id, _)| (*id, "pose")));
    ids.extend(vertices.lines.iter().map(|(id, _)| (*id, "line")));
    ids.extend(vertices.planes.iter().map(|(id, _)| (*id, "plane")));
    ids.extend(vertices.points.iter().map(|(id, _)| (*id, "point")));
    ids.retain(|(id, _)| free(id));
    let index: HashMap<usize, usize> = ids
        .iter()
        .enumerate()
        .map(|(k, (id, _))| (*id, k))
        .collect();
    // Each free vertex's tangent coordinates, from the first edge on it.
    let mut columns: Vec<Option<Vec<String>>> = vec![None; ids.len()];
    let mut rows = Vec::with_capacity(edges.len());
    for edge in &edges {
        let blocks = match &edge.factor {
            G2oFactor::Pose(f) => whitened(f, edge),
            G2oFactor::Line(f) => whitened(f, edge),
            G2oFactor::Plane(f) => whitened(f, edge),
            G2oFactor::Point(f) => whitened(f, edge),
            G2oFactor::Prior(f) => whitened(f, edge),
        };
        // An edge degenerate here: the solve refuses it (or refused it).
        let Some((blocks, tangents)) = blocks else {
            continue;
        };
        let mut on_free = Vec::with_capacity(blocks.len());
        for ((id, block), tangent) in edge.vertices.iter().zip(blocks).zip(tangents) {
            if let Some(&k) = index.get(id) {
                columns[k].get_or_insert(tangent);
                on_free.push((k, block));
            }
        }
        rows.push(on_free);
    }
    let variables = ids
        .iter()
        .zip(columns)
        .map(|(&(id, kind), columns)| {
            columns
                .map(|columns| Variable {
                    name: format!("{kind} {id}"),
                    columns,
                })
                .ok_or_else(|| format!("{kind} vertex {id}: no edge joins it"))
        })
        .collect::<Result<Vec<_>, _>>()?;
    let mut normal = Normal::new(variables);
    for blocks in rows {
        normal.add(blocks);
    }
    Ok(normal.deficiency_within(tolerance))
}

/// An edge's whitened Jacobian blocks `S J`, one per variable, and each
/// variable's tangent coordinates.
type Whitened = (Vec<DMatrix<f64>>, Vec<Vec<String>>);

/// `edge`'s [`Whitened`] blocks, or `None` where it cannot be linearized
/// (its validation, or a non-finite Jacobian). Linearized as
/// `Method::Generated` does (dual numbers for a factor without a kernel).
fn whitened<F: Factor>(factor: &F, edge: &G2oEdge) -> Option<Whitened> {
    let (linearization, _) = linearize(factor, Method::Generated).ok()?;
    let s = edge.noise.sqrt_information(F::RESIDUAL_DIM);
    let blocks = linearization.jacobians.iter().map(|j| &s * j).collect();
    let tangents = F::variables()
        .iter()
        .map(|v| tangent_columns(v.tangent, v.tangent_dim))
        .collect();
    Some((blocks, tangents))
}
