//! The header printed before a solve and the summary after it.

use std::path::Path;
use std::time::Duration;

use factor_core::Factor;
use factor_minimizer::{Iteration, Verdict};
use slam_factors::{
    G2oLineEdge, G2oPlaneEdge, G2oPointEdge, G2oPriorEdge, G2oSe3Edge, LineObservation, PlaneFactor,
};
use slam_problems::Kernels;
use slam_problems::g2o_edges::LandmarkFactors;
use slamjac_problem::field_path::shown_path;

use super::SolveArgs;
use super::progress::duration;

/// What the header says of the problem built, whichever solver has it.
#[derive(Debug, Clone)]
pub struct Setup {
    /// The residual blocks (observations or edges).
    pub blocks: usize,
    /// The solver, in words (after "Levenberg–Marquardt").
    pub solver: String,
    /// The cost at the initial values.
    pub initial_cost: f64,
}

/// What the summary says of a finished solve, whichever solver ran it.
#[derive(Debug, Clone)]
pub struct Finished<'a> {
    /// How it ended.
    pub verdict: Verdict,
    /// Iterations run.
    pub iterations: usize,
    /// Wall time of the solve (set-up included).
    pub elapsed: Duration,
    /// The costs at the initial values and at the solution.
    pub initial_cost: f64,
    pub final_cost: f64,
    /// Each iteration's report.
    pub history: &'a [Iteration],
    /// The residual blocks.
    pub blocks: usize,
    /// Evaluations a factor rejected, and the first one's message.
    pub rejected: usize,
    pub first_rejection: Option<&'a str>,
    /// Lines of the solver's own (its time's breakdown), if any.
    pub extra: Vec<String>,
}

/// The sizes, factor and gauge of a bundle-adjustment problem (BAL or
/// Bundler), in words.
fn bundle_adjustment(
    cameras: usize,
    points: usize,
    observations: usize,
) -> (String, String, &'static str) {
    (
        format!("{cameras} cameras, {points} points, {observations} observations"),
        "snavely_reprojection".into(),
        "camera 0's pose fixed (the scale is left to the damping)",
    )
}

/// The vertices and edges of a g2o graph, by kind; points and priors only
/// when it has them.
fn g2o_graph_sizes(g: &slam_data::G2oGraph) -> String {
    let mut sizes = format!(
        "{} poses, {} lines, {} planes",
        g.poses.len(),
        g.lines.len(),
        g.planes.len()
    );
    if !g.points.is_empty() {
        sizes += &format!(", {} points", g.points.len());
    }
    sizes += &format!(
        "; {} pose edges, {} line edges, {} plane edges",
        g.pose_edges.len(),
        g.line_edges.len(),
        g.plane_edges.len()
    );
    if !g.point_edges.is_empty() {
        sizes += &format!(", {} point edges", g.point_edges.len());
    }
    if !g.priors.is_empty() {
        sizes += &format!(", {} priors", g.priors.len());
    }
    sizes
}

/// The factors of a g2o graph's edges, those it has, in words.
fn g2o_factors(g: &slam_data::G2oGraph, landmarks: LandmarkFactors) -> String {
    let documents = landmarks == LandmarkFactors::Documents;
    let names: Vec<&str> = [
        (g.pose_edges.len(), G2oSe3Edge::NAME),
        (
            g.line_edges.len(),
            if documents {
                LineObservation::NAME
            } else {
                G2oLineEdge::NAME
            },
        ),
        (
            g.plane_edges.len(),
            if documents {
                PlaneFactor::NAME
            } else {
                G2oPlaneEdge::NAME
            },
        ),
        (g.point_edges.len(), G2oPointEdge::NAME),
        (g.priors.len(), G2oPriorEdge::NAME),
    ]
    .into_iter()
    .filter(|(count, _)| *count > 0)
    .map(|(_, name)| name)
    .collect();
    let errors = if documents {
        "the documents' line and plane factors, g2o's other errors"
    } else {
        "g2o's errors; cost = χ²/2"
    };
    format!("{} ({errors})", names.join(", "))
}

/// What the problem is, in words: sizes, factors, kernels, gauge, solver.
pub fn header(file: &Path, data: &slam_data::Problem, setup: &Setup, args: &SolveArgs) -> String {
    let (sizes, factor, gauge) = match data {
        slam_data::Problem::Bal(p) => {
            bundle_adjustment(p.cameras.len(), p.points.len(), p.observations.len())
        }
        slam_data::Problem::Bundler(p) => {
            bundle_adjustment(p.cameras.len(), p.points.len(), p.observations.len())
        }
        slam_data::Problem::G2o(g) | slam_data::Problem::Edge3(g) => (
            if g.vertices.is_empty() {
                format!(
                    "{} edges, no vertices (poses chained from the odometry)",
                    g.edges.len()
                )
            } else {
                format!("{} poses, {} edges", g.vertices.len(), g.edges.len())
            },
            "between".into(),
            "the first pose fixed",
        ),
        slam_data::Problem::G2oAddons(g) => (
            g2o_graph_sizes(g),
            g2o_factors(g, args.landmarks),
            "the file's FIX vertices",
        ),
        slam_data::Problem::KittiVo(vo) => (
            format!(
                "{} poses, {} landmarks, {} stereo observations",
                vo.poses.len(),
                vo.initial_landmarks().len(),
                vo.observations.len()
            ),
            "stereo_reprojection".into(),
            "the first pose fixed",
        ),
    };
    let robust = args
        .robust
        .map_or_else(|| "least squares".to_owned(), |r| format!("robust {r}"));
    // g2o's line, plane, point and prior edges have no kernel.
    let kernels = match (data, args.kernels) {
        (slam_data::Problem::G2oAddons(_), Kernels::Generated) => {
            "generated kernels where a factor has one, dual numbers for g2o's other edges".into()
        }
        (_, kernels) => format!("{} kernels", kernels.name()),
    };
    format!(
        "{} ({}): {sizes}\n{} {factor} blocks, {kernels}, {robust}; gauge: {gauge}; \
         Levenberg–Marquardt {}; initial cost {:.10e}",
        shown_path(file),
        data.format(),
        setup.blocks,
        setup.solver,
        setup.initial_cost
    )
}

/// The finite errors, in order.
fn finite(errors: &[f64]) -> Vec<f64> {
    errors.iter().copied().filter(|e| e.is_finite()).collect()
}

/// `sqrt(mean(e²))` over the finite errors, in words (`0.4209 px`), and
/// how many there are.
fn rms(errors: &[f64]) -> (String, usize) {
    let finite = finite(errors);
    if finite.is_empty() {
        return ("not finite".to_owned(), 0);
    }
    let sum: f64 = finite.iter().map(|e| e * e).sum();
    (
        format!("{:.4} px", (sum / finite.len() as f64).sqrt()),
        finite.len(),
    )
}

/// The median of the finite errors, in words (`0.3102 px`): unlike the RMS,
/// it is not dominated by a few outliers.
fn median(errors: &[f64]) -> String {
    let mut finite = finite(errors);
    if finite.is_empty() {
        return "not finite".to_owned();
    }
    finite.sort_by(f64::total_cmp);
    let n = finite.len();
    let m = if n % 2 == 1 {
        finite[n / 2]
    } else {
        0.5 * (finite[n / 2 - 1] + finite[n / 2])
    };
    format!("{m:.4} px")
}

/// The summary: verdict, costs, RMS and median reprojection errors, where the time
/// went, rejected evaluations, peak memory, files written.
pub fn summary(
    outcome: &Finished<'_>,
    errors: Option<(&[f64], &[f64])>,
    output: Option<&Path>,
    plot: Option<&Path>,
) -> String {
    let verdict = outcome.verdict.to_string();
    let change = if outcome.initial_cost > 0.0 && outcome.final_cost.is_finite() {
        format!(
            " ({:+.3}%)",
            100.0 * (outcome.final_cost - outcome.initial_cost) / outcome.initial_cost
        )
    } else {
        String::new()
    };
    let mut lines = vec![
        format!(
            "summary: {verdict} after {} iteration{} in {}",
            outcome.iterations,
            if outcome.iterations == 1 { "" } else { "s" },
            duration(outcome.elapsed)
        ),
        format!(
            "  cost: initial {:.12e}, final {:.12e}{change}",
            outcome.initial_cost, outcome.final_cost
        ),
    ];
    if let Some((before, after)) = errors {
        let ((b, _), (a, n)) = (rms(before), rms(after));
        lines.push(format!(
            "  RMS reprojection error: {b} initially, {a} finally ({n} of {} observations)",
            after.len()
        ));
        lines.push(format!(
            "  median reprojection error: {} initially, {} finally",
            median(before),
            median(after)
        ));
    }
    // Passes that linearized (the Schur path keeps the last linearization
    // through a rejected step).
    let passes = outcome
        .history
        .iter()
        .filter(|it| !it.linearization.is_zero())
        .count()
        .max(1);
    let linearization: std::time::Duration =
        outcome.history.iter().map(|it| it.linearization).sum();
    let solves: std::time::Duration = outcome.history.iter().map(|it| it.solve).sum();
    let evaluations: std::time::Duration = outcome.history.iter().map(|it| it.evaluation).sum();
    let per_block =
        linearization.as_secs_f64() / passes as f64 / outcome.blocks.max(1) as f64 * 1e9;
    lines.push(format!(
        "  time: linearization {} ({per_block:.0} ns per block per pass), linear solves and \
         updates {}, step evaluations {}",
        duration(linearization),
        duration(solves),
        duration(evaluations)
    ));
    lines.extend(outcome.extra.iter().cloned());
    if outcome.rejected > 0 {
        lines.push(format!(
            "  rejected evaluations: {} trial steps met a degenerate configuration \
             (the step was rejected); first: {}",
            outcome.rejected,
            outcome.first_rejection.unwrap_or("?")
        ));
    }
    if let Some(bytes) = peak_memory() {
        lines.push(format!(
            "  peak memory: {:.1} MiB",
            bytes as f64 / 1048576.0
        ));
    }
    if let Some(path) = output {
        lines.push(format!("  wrote {}", shown_path(path)));
    }
    if let Some(path) = plot {
        lines.push(format!("  plot {}", shown_path(path)));
    }
    lines.join("\n")
}

/// The process's peak resident memory (Linux: `VmHWM` of
/// `/proc/self/status`); `None` elsewhere.
pub fn peak_memory() -> Option<u64> {
    let status = std::fs::read_to_string("/proc/self/status").ok()?;
    let line = status.lines().find(|l| l.starts_with("VmHWM:"))?;
    let kib: u64 = line.split_whitespace().nth(1)?.parse().ok()?;
    Some(kib * 1024)
}

#[cfg(test)]
mod tests {
    use super::{median, rms};

    #[test]
    fn median_and_rms_skip_non_finite_errors() {
        assert_eq!(median(&[3.0, f64::NAN, 1.0, 2.0]), "2.0000 px");
        assert_eq!(median(&[4.0, 1.0, 2.0, 100.0]), "3.0000 px");
        assert_eq!(median(&[f64::INFINITY]), "not finite");
        assert_eq!(rms(&[3.0, 4.0, f64::NAN]), ("3.5355 px".to_owned(), 2));
    }
}
