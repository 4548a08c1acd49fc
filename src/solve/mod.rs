//! `slamjac solve`: a real estimation problem (BAL, Bundler, g2o, EDGE3,
//! KITTI stereo VO) optimized by Levenberg–Marquardt, its factors written
//! once with the derive and linearized by their generated kernels (or, with
//! `--kernels dual`, by dual numbers).
//!
//! Two solvers, chosen by [`SolverChoice`]:
//!
//! - every data set (bundle adjustment, stereo VO, g2o's line, plane and
//!   point graphs: landmarks to eliminate; g2o and EDGE3 pose graphs:
//!   nothing to eliminate) goes by default to crate `factor-schur` (module
//!   `schur`): the landmarks eliminated by a Schur complement formed
//!   straight from the fused normal-equation kernels in lane batches (or,
//!   for factors without them and under `--kernels dual`, from each
//!   factor's Jacobians), the reduced system solved by faer's Cholesky;
//! - a problem file whose factors all have fused normal-equation kernels
//!   (`Registry::solve_with_schur`) goes there too (`slamjac_solve::schur_file`,
//!   which chooses the variables to eliminate); one it cannot take goes to
//!   apex-solver with the reason printed, or is refused with
//!   `--solver schur`;
//! - a problem file the Schur solver cannot take, and any problem with
//!   `--solver apex`, go to apex-solver through the generic adapter of
//!   crate `factor-apex` (module `apex`; g2o graphs with `--factors
//!   documents` there on apex-solver's inverse pose).
//!
//! Both print the same header, iteration lines and summary:
//!
//! - [`progress`]: a line per iteration (and a progress bar on long runs);
//! - [`report`]: the header and the final summary;
//! - [`plot`]: the SVG of the cost per iteration and, for reprojection
//!   problems, the histogram of reprojection errors before and after.
//!
//! [`track`] is `slamjac track`: pose-only tracking of a problem file's
//! frames against its fixed map (crate `factor-tracking`).
//!
//! Exit codes follow [`crate::error`]: 2 for a malformed file or option, 1
//! for a problem that is degenerate at its initial values or a solve that
//! stops on a failure.

mod apex;
pub mod plot;
pub mod progress;
pub mod report;
mod schur;
mod schur_file;
pub mod track;

use std::path::{Path, PathBuf};

/// The ground truth of a solve and a solution's errors against it, read by
/// `slamjac-problem`.
pub use slamjac_problem::{file_truth, truth};
use slamjac_solve::graph_checks;
/// The problem file: its format, read and built for apex-solver
/// (`slamjac_solve::problem_file`).
pub use slamjac_solve::problem_file;

use factor_minimizer::Verdict;
use slam_data::Format;
use slam_problems::g2o_edges::LandmarkFactors;
use slam_problems::{Kernels, Robust};
use slamjac_io::Role;

use crate::error::CliError;
use crate::outputs;
use crate::registry::Registry;

/// Which solver `solve` uses.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum SolverChoice {
    /// The Schur-complement solver where it applies (BAL, Bundler, KITTI
    /// VO, g2o and EDGE3 pose graphs, problem files of factors with fused
    /// normal-equation kernels, with the generated kernels), apex-solver
    /// elsewhere.
    #[default]
    Auto,
    /// The Schur-complement solver (crate `factor-schur`).
    Schur,
    /// apex-solver (crate `factor-apex`).
    Apex,
}

/// What `solve` was asked for.
#[derive(Debug, Clone)]
pub struct SolveArgs {
    /// The data file (for KITTI VO, any of its three files).
    pub file: PathBuf,
    /// The format, or detected from the file.
    pub format: Option<Format>,
    /// Generated kernels or dual numbers.
    pub kernels: Kernels,
    /// Which solver.
    pub solver: SolverChoice,
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

/// Refuses, before any work, an output (`--output`, each of the three
/// files of a KITTI VO output, `--plot`) that names one of the files
/// `read` or another output, or that cannot be written. The files read are
/// those named and those read implicitly: the ground truth beside a g2o
/// graph ([`truth::file`]).
fn check_files(args: &SolveArgs, read: &[PathBuf]) -> Result<(), CliError> {
    let format = args.format.or_else(|| Format::from_name(&args.file));
    let written = match &args.output {
        Some(path) => slam_data::Problem::files_written(path, format)?,
        None => Vec::new(),
    };
    let mut inputs: Vec<Role<'_>> = read.iter().map(|p| Role::new("the input", p)).collect();
    let truth = truth::file(&args.file, format, args.truth.as_deref());
    if let Some((path, role)) = &truth {
        inputs.push(Role::new(role, path));
    }
    let mut outputs: Vec<Role<'_>> = written.iter().map(|p| Role::new("--output", p)).collect();
    if let Some(plot) = &args.plot {
        outputs.push(Role::new("--plot", plot));
    }
    outputs::check(&inputs, &outputs)
}

/// Checks the output paths, then reads, builds, solves and reports; prints
/// the header and a line per iteration as they come and returns the
/// summary. Outputs are written to temporary files renamed into place,
/// and only after a solve that did not fail.
///
/// # Errors
///
/// [`CliError::Usage`] for an output that names an input or another
/// output, or cannot be written (before anything is read), and for an
/// option the problem cannot honour (`--solver schur` where there are no
/// landmarks to eliminate, `--factors documents` or `--truth` on anything
/// but a g2o line and plane graph: before the solve);
/// [`CliError::Data`] for a file that cannot be read or written,
/// [`CliError::Usage`] for data that cannot make a problem, and
/// [`CliError::Solve`] for a problem degenerate at its initial values or a
/// solve that stopped on a failure (the summary is printed first).
pub fn run(args: &SolveArgs) -> Result<String, CliError> {
    if args.format.is_none() && args.file.extension().is_some_and(|e| e == "json") {
        refuse_data_options(args)?;
        return run_problem_file(args, &crate::kernels::shipped());
    }
    let format = args.format.or_else(|| Format::from_name(&args.file));
    check_files(args, &slam_data::Problem::files_read(&args.file, format)?)?;
    let data = slam_data::Problem::read(&args.file, args.format)?;
    let lines_and_planes = matches!(data, slam_data::Problem::G2oAddons(_));
    if args.landmarks == LandmarkFactors::Documents && !lines_and_planes {
        return Err(CliError::Usage(at(
            &args.file,
            "--factors documents: only for g2o line and plane graphs",
        )));
    }
    if let Some(path) = &args.truth
        && !lines_and_planes
    {
        return Err(CliError::Usage(format!(
            "--truth {}: ground truth is read for g2o line and plane graphs only",
            path.display()
        )));
    }
    if let Some(empty) = slam_problems::nothing_to_solve(&data) {
        return Err(CliError::Usage(at(&args.file, empty)));
    }
    let truth = truth::Truth::read(&args.file, format, args.truth.as_deref(), &data)?;
    if let slam_data::Problem::G2oAddons(graph) = &data {
        graph_checks::check_initial(&args.file, graph)?;
    }
    if args.solver != SolverChoice::Apex {
        schur::run(args, &data, truth.as_ref())
    } else {
        apex::run(args, &data, truth.as_ref())
    }
}

/// Refuses the options of `solve` that only data files have, given with a
/// problem file: it names its own factors and carries its own truth.
fn refuse_data_options(args: &SolveArgs) -> Result<(), CliError> {
    let refused = if args.landmarks == LandmarkFactors::Documents {
        Some(
            "--factors documents: only for g2o line and plane graphs; a problem file names \
             its factors",
        )
    } else if args.truth.is_some() {
        Some("--truth: a problem file carries its own truth (its `truth` object)")
    } else {
        None
    };
    refused.map_or(Ok(()), |why| Err(CliError::Usage(at(&args.file, why))))
}

/// Solves the problem file `args.file` ([`problem_file`]) of the factors
/// `registry` registered for `solve`: through the Schur-complement solver
/// when it can take the file (`schur_file`) unless `--solver apex`, else
/// through apex-solver, saying why; errors and output as [`run`].
///
/// # Errors
///
/// As [`run`]; an entry naming a factor the registry does not solve is
/// [`CliError::Input`] at its field path; `--solver schur` on a file the
/// Schur-complement solver cannot take is [`CliError::Usage`].
pub fn run_problem_file(args: &SolveArgs, registry: &Registry) -> Result<String, CliError> {
    check_files(args, std::slice::from_ref(&args.file))?;
    if args.solver != SolverChoice::Apex {
        match schur_file::run(args, registry)? {
            Ok(summary) => return Ok(summary),
            Err(why) if args.solver == SolverChoice::Schur => {
                return Err(CliError::Usage(at(
                    &args.file,
                    format!(
                        "--solver schur cannot take this problem file: {why} (use --solver apex)"
                    ),
                )));
            }
            Err(why) => progress::print(&format!(
                "{}: solved by apex-solver: the Schur-complement solver cannot take it ({why})",
                slamjac_problem::field_path::shown_path(&args.file)
            )),
        }
    }
    apex::run_problem_file(args, registry)
}

/// Drops `value` on a thread of its own: the problem built from a problem
/// file keeps some hundred thousand small allocations (each factor's
/// scalars, variables and noise), which the caller need not wait to free
/// (at the end of `slamjac solve` the process exits first; 8 ms for the
/// 100-camera room). Where no thread can be started, it is dropped here.
fn drop_later<T: Send + 'static>(value: T) {
    let _ = std::thread::Builder::new().spawn(move || drop(value));
}

/// The end of a problem file's solve, either path's: a failed solve
/// refused, then the `check` of the solution, the `truth` errors, the
/// plot, the file `written` back with the solution (built for `--output`
/// only) and the summary. Nothing is written after a failure.
fn finish_file(
    args: &SolveArgs,
    finished: &report::Finished<'_>,
    check: impl FnOnce() -> Result<(), String>,
    truth: Option<Result<String, String>>,
    written: impl FnOnce() -> serde_json::Value,
) -> Result<String, CliError> {
    if let Verdict::Failed(why) = &finished.verdict {
        return Err(CliError::Solve(at(
            &args.file,
            format!("the solve stopped on a failure: {why}; no output written"),
        )));
    }
    let refused =
        |why: String| CliError::Solve(at(&args.file, format!("{why}; no output written")));
    check().map_err(refused)?;
    let truth = truth.transpose().map_err(refused)?;
    if let Some(path) = &args.plot {
        let svg = plot::svg(path, finished.initial_cost, finished.history, None)?;
        outputs::write(path, svg)?;
    }
    if let Some(path) = &args.output {
        outputs::write(path, crate::pretty::to_string(&written()) + "\n")?;
    }
    let mut summary = report::summary(finished, None, args.output.as_deref(), args.plot.as_deref());
    if let Some(errors) = truth {
        summary.push('\n');
        summary.push_str(&errors);
    }
    Ok(summary)
}

/// The end of either path: the verdict, the errors against the ground
/// truth where there is one ([`truth`]), the plot, the output file and the
/// summary, with the reprojection errors of the `initial` problem and of
/// the `solved` one. Nothing is written after a failed solve, or when the
/// errors against the truth cannot be measured.
fn finish(
    args: &SolveArgs,
    initial: &slam_data::Problem,
    solved: &slam_data::Problem,
    truth: Option<&truth::Truth>,
    finished: &report::Finished<'_>,
) -> Result<String, CliError> {
    let before = slam_problems::reprojection_errors(initial);
    let after = slam_problems::reprojection_errors(solved);
    let errors = before.as_deref().zip(after.as_deref());
    if let Verdict::Failed(why) = &finished.verdict {
        progress::print(&report::summary(finished, errors, None, None));
        return Err(CliError::Solve(at(
            &args.file,
            format!("the solve stopped on a failure: {why}; no output written"),
        )));
    }
    let refused =
        |why: String| CliError::Solve(at(&args.file, format!("{why}; no output written")));
    if let (slam_data::Problem::G2oAddons(initial), slam_data::Problem::G2oAddons(graph)) =
        (initial, solved)
    {
        graph_checks::check_solution(initial, graph, &finished.verdict).map_err(refused)?;
    }
    let truth = truth
        .map(|truth| truth.describe(solved))
        .transpose()
        .map_err(refused)?;
    if let Some(path) = &args.plot {
        outputs::write(
            path,
            plot::svg(path, finished.initial_cost, finished.history, errors)?,
        )?;
    }
    if let Some(path) = &args.output {
        solved.write(path)?;
    }
    let mut summary = report::summary(
        finished,
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
