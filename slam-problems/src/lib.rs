//! The solver-independent vocabulary of slamjac's estimation problems,
//! shared by the solvers: crate `factor-schur` (Levenberg–Marquardt with
//! the landmarks eliminated by a Schur complement, the path of `slamjac
//! solve`) and crate `factor-apex` (the apex-solver adapter, which
//! re-exports these items at their old paths), and by `slamjac` itself.
//!
//! - [`Robust`]: a robust loss on every block (`huber:δ`, `cauchy:δ`,
//!   [`ROBUST_SCALES`]); each solver evaluates it its own way;
//! - [`Kernels`]: whether factors are linearized through their generated
//!   kernels or by dual numbers;
//! - the data sets of crate `slam-data` as this project's factors, each
//!   solver keying the variables its own way: [`bundle`] (BAL, Bundler),
//!   [`stereo`] (KITTI VO), [`pose_graph`] (g2o, EDGE3), [`g2o_edges`]
//!   (g2o's graphs of lines, planes and points); each factor named in
//!   errors as the readers count, and a solution written back in the
//!   input's format; [`nothing_to_solve`] and [`reprojection_errors`] of a
//!   data set;
//! - [`ProblemError`]: why a data set's factors cannot be built (each
//!   solver's build error wraps it in one variant).
//!
//! Nothing here depends on a solver (neither apex-solver nor faer): a
//! build of the Schur-complement solver does not build apex-solver.

pub mod bundle;
mod error;
pub mod g2o_edges;
mod kernels;
pub mod pose_graph;
mod robust;
pub mod stereo;

pub use error::ProblemError;
pub use kernels::Kernels;
pub use robust::{ROBUST_SCALES, Robust};

/// Why `data` has nothing to solve, if it has not: no observation or no
/// edge makes a cost that is identically 0, with no step to take, and a
/// g2o graph whose `FIX` lines hold every vertex has no value to estimate.
pub fn nothing_to_solve(data: &slam_data::Problem) -> Option<String> {
    let what = match data {
        slam_data::Problem::G2o(_)
        | slam_data::Problem::Edge3(_)
        | slam_data::Problem::G2oAddons(_) => "edges",
        _ => "observations",
    };
    if data.measurements() == 0 {
        return Some(format!("nothing to solve: the problem has no {what}"));
    }
    if let slam_data::Problem::G2oAddons(graph) = data {
        let fixed: std::collections::HashSet<usize> = graph.fixed.iter().copied().collect();
        let vertices = graph.poses.iter().map(|v| v.id);
        let vertices = vertices
            .chain(graph.lines.iter().map(|v| v.id))
            .chain(graph.planes.iter().map(|v| v.id))
            .chain(graph.points.iter().map(|v| v.id));
        if vertices.clone().all(|id| fixed.contains(&id)) {
            return Some(format!(
                "nothing to solve: the FIX lines hold every one of the {} vertices",
                vertices.count()
            ));
        }
    }
    None
}

/// The reprojection error of each observation (pixels: `‖predicted −
/// observed‖`, two coordinates for BAL and Bundler, `[u_L, u_R, v]` for
/// stereo) at the problem's values, through this project's factors; `None`
/// for a pose graph (with or without lines and planes). An observation degenerate at these values is NaN.
pub fn reprojection_errors(data: &slam_data::Problem) -> Option<Vec<f64>> {
    match data {
        slam_data::Problem::Bal(bal) => Some(bundle::reprojection_errors(bal)),
        slam_data::Problem::Bundler(bundler) => {
            Some(bundle::reprojection_errors(&bundler.to_bal()))
        }
        slam_data::Problem::KittiVo(vo) => Some(stereo::reprojection_errors(vo)),
        slam_data::Problem::G2o(_)
        | slam_data::Problem::Edge3(_)
        | slam_data::Problem::G2oAddons(_) => None,
    }
}
