//! `slamjac solve`: a real estimation problem (BAL, Bundler, g2o, EDGE3,
//! KITTI stereo VO) optimized by apex-solver's Levenberg–Marquardt, its
//! factors written once with the derive and linearized by their generated
//! kernels (or, with `--kernels dual`, by dual numbers), served through the
//! generic adapter of crate `factor-apex`.
//!
//! - [`progress`]: a line per iteration (and a progress bar on long runs);
//! - [`report`]: the header and the final summary;
//! - [`plot`]: the SVG of the cost per iteration and, for reprojection
//!   problems, the histogram of reprojection errors before and after.
//!
//! Exit codes follow [`crate::error`]: 2 for a malformed file or option, 1
//! for a problem that is degenerate at its initial values or a solve that
//! stops on a failure.

pub mod plot;
pub mod problem_file;
pub mod progress;
pub mod report;
pub mod truth;

use std::path::{Path, PathBuf};

use factor_apex::Kernels;
use factor_apex::problems::g2o_addons::{self, LandmarkFactors};
use factor_apex::problems::{self, BuildError, BuildOptions, FactorChoice, Robust};
use factor_apex::solve::{SolveOptions, Verdict, solve};
use slam_data::Format;

use crate::error::CliError;

/// What `solve` was asked for.
#[derive(Debug, Clone)]
pub struct SolveArgs {
    /// The data file (for KITTI VO, any of its three files).
    pub file: PathBuf,
    /// The format, or detected from the file.
    pub format: Option<Format>,
    /// Generated kernels or dual numbers.
    pub kernels: Kernels,
    /// The most iterations.
    pub max_iterations: usize,
    /// A robust loss on every block.
    pub robust: Option<Robust>,
    /// Where to write the optimized problem (in the input's format).
    pub output: Option<PathBuf>,
    /// Where to write the SVG plot.
    pub plot: Option<PathBuf>,
    /// The factors of the lines and planes of a g2o line and plane graph.
    pub landmarks: LandmarkFactors,
    /// The ground truth to report errors against (a g2o line and plane
    /// graph; by default `STEM_truth.g2o` beside the file, when it exists).
    pub truth: Option<PathBuf>,
}

/// `FILE: what` (made one printable line by [`CliError::one_line`]).
fn at(file: &Path, what: impl std::fmt::Display) -> String {
    format!("{}: {what}", file.display())
}

/// Reads, builds, solves and reports; prints the header and a line per
/// iteration as they come and returns the summary.
///
/// # Errors
///
/// [`CliError::Data`] for a file that cannot be read or written,
/// [`CliError::Usage`] for data that cannot make a problem, and
/// [`CliError::Solve`] for a problem degenerate at its initial values or a
/// solve that stopped on a failure (the summary is printed first).
pub fn run(args: &SolveArgs) -> Result<String, CliError> {
    let options = BuildOptions {
        factors: FactorChoice::Ours(args.kernels),
        robust: args.robust,
        keep_blocks: false,
    };
    if args.format.is_none() && args.file.extension().is_some_and(|e| e == "json") {
        return run_file(args, &options);
    }
    let data = slam_data::Problem::read(&args.file, args.format)?;
    let built = match (&data, args.landmarks) {
        (slam_data::Problem::G2oAddons(graph), landmarks) => {
            g2o_addons::build_with(graph, &options, landmarks)
        }
        (_, LandmarkFactors::G2o) => problems::build(&data, &options),
        (_, LandmarkFactors::Documents) => Err(BuildError::Unavailable(
            "--factors documents: only for g2o line and plane graphs".into(),
        )),
    };
    let mut built = built.map_err(|e| match e {
        BuildError::Data(_) | BuildError::Unavailable(_) => CliError::Usage(at(&args.file, e)),
        BuildError::Degenerate { .. } | BuildError::Solver(_) | BuildError::Adapter(_) => {
            CliError::Solve(at(&args.file, e))
        }
    })?;
    let before = problems::reprojection_errors(&data);
    progress::print(&report::header(&args.file, &data, &built, args));
    let options = SolveOptions {
        max_iterations: args.max_iterations,
        ..SolveOptions::default()
    };
    let mut progress = progress::Progress::new(args.max_iterations, built.blocks);
    let outcome = solve(&mut built, &options, progress.callback())
        .map_err(|e| CliError::Solve(at(&args.file, format!("the solve stopped: {e}"))))?;
    progress.finish();
    let solved = built.write_back(&data, &outcome.values);
    let after = problems::reprojection_errors(&solved);
    let errors = before.as_deref().zip(after.as_deref());
    let truth = truth::against(&args.file, args.truth.as_deref(), &data, &solved)?;
    if let Some(path) = &args.plot {
        plot::write(path, built.initial_cost, &outcome.history, errors)?;
    }
    let verdict = outcome.verdict();
    if let Verdict::Failed(why) = &verdict {
        progress::print(&report::summary(
            &built,
            &outcome,
            errors,
            None,
            args.plot.as_deref(),
        ));
        return Err(CliError::Solve(at(
            &args.file,
            format!("the solve stopped on a failure: {why}; no output written"),
        )));
    }
    if let Some(path) = &args.output {
        solved.write(path)?;
    }
    let mut summary = report::summary(
        &built,
        &outcome,
        errors,
        args.output.as_deref(),
        args.plot.as_deref(),
    );
    if let Some(truth) = truth {
        summary.push('\n');
        summary.push_str(&truth);
    }
    Ok(summary)
}

/// [`run`] for a problem file ([`problem_file`]).
fn run_file(args: &SolveArgs, options: &BuildOptions) -> Result<String, CliError> {
    let mut problem = problem_file::read(&args.file, options)?;
    let built = &mut problem.built;
    progress::print(&format!(
        "{} (problem file): {} blocks, {} kernels where generated (dual numbers otherwise); \
         Levenberg–Marquardt (apex-solver), {:?}; initial cost {:.10e}",
        args.file.display(),
        built.blocks,
        args.kernels.name(),
        built.linear_solver,
        built.initial_cost
    ));
    let solve_options = SolveOptions {
        max_iterations: args.max_iterations,
        ..SolveOptions::default()
    };
    let mut progress = progress::Progress::new(args.max_iterations, built.blocks);
    let outcome = solve(built, &solve_options, progress.callback())
        .map_err(|e| CliError::Solve(at(&args.file, format!("the solve stopped: {e}"))))?;
    progress.finish();
    if let Some(path) = &args.plot {
        plot::write(path, built.initial_cost, &outcome.history, None)?;
    }
    if let Verdict::Failed(why) = outcome.verdict() {
        return Err(CliError::Solve(at(
            &args.file,
            format!("the solve stopped on a failure: {why}; no output written"),
        )));
    }
    if let Some(path) = &args.output {
        let text = crate::pretty::to_string(&problem.written(&outcome.values));
        std::fs::write(path, text + "\n")
            .map_err(|e| CliError::Usage(at(path, format!("cannot write: {e}"))))?;
    }
    Ok(report::summary(
        &problem.built,
        &outcome,
        None,
        args.output.as_deref(),
        args.plot.as_deref(),
    ))
}
