//! `slamjac track FILE.json`: the tracking front-end of the documents'
//! point-line-plane problems. Each frame's pose is solved alone against a
//! fixed map, frame after frame, each frame started at the previous
//! frame's estimate; the per-frame time and the drift are reported, for
//! one or several sets of measurement kinds side by side.
//!
//! ```text
//! slamjac track FILE.json [--kinds K]... [--map truth|values] [--max-iterations N]
//!               [--plot FILE.svg] [--output FILE.json]
//! ```
//!
//! - The sequence (`slamjac_solve::track_sequence`, re-exported as
//!   [`sequence`]): the file's `Se3` variables are the
//!   frames, in the order the file lists them (`synth-plp` writes `c0, c1,
//!   …` in trajectory order); the observations are the factors of one pose
//!   against one landmark, with the file's noise models; the map is every
//!   other variable, held fixed at its `truth` (`--map truth`, the default:
//!   a map known exactly, so that the errors are the tracker's alone) or at
//!   its `value` (`--map values`, e.g. what `solve --output` estimated).
//! - Frame 0 starts at its true pose (the anchor), each next frame at the
//!   previous frame's estimate. Each frame is solved by crate
//!   `factor-tracking`: the one Levenberg–Marquardt of every solver
//!   (crate `factor-minimizer`, `solve`'s criteria) on the dense 6 × 6
//!   normal equations, every observation linearized by its factor's
//!   generated kernel (the pose's block only), until a criterion is met
//!   or `--max-iterations` (default 20). Observations undefined at the
//!   initial pose (a landmark behind the previous frame's camera) are
//!   deferred: the pose is solved without them first, then with all.
//! - `--kinds`, repeatable: the measurement sets compared, each tracked
//!   over the whole sequence (default: `points`, then
//!   `points,lines,planes`). The report prints them side by side: the
//!   observations per frame; the time per frame (median, 95th percentile,
//!   max, in µs, the solve alone: one thread, the observations already
//!   read); the iterations; the errors against the truth (the camera
//!   centre's distance, the rotation's angle) per frame (median, max), of
//!   the final frame (the drift), and the RMS over the frames (the ATE,
//!   with no alignment: frame 0 is anchored at the truth).
//! - `--plot FILE.svg`: the translation and rotation error per frame, a
//!   line per measurement set. `--output FILE.json`: the file with its
//!   poses' values replaced by the last measurement set's estimates.
//!
//! Errors: a frame with no observation of a measurement set, or whose
//! observations do not determine its pose (fewer than six independent
//! residuals), or an observation undefined at the frame's initial pose
//! (a point behind the camera), or whose pose does not converge within
//! `--max-iterations` (the verdict says how it stopped; a map point at the
//! camera centre stalls every step: named when it is undefined at the last
//! estimate) stops the run naming
//! the frame and the file's factor (exit 1), as does an estimate whose
//! error against the truth is not finite; the file is read and checked as
//! `solve` reads and checks it (`slamjac_problem::checks`: the same file gets the
//! same error from both, exit 2), and a missing truth, a factor other than
//! one pose against one landmark or a robust loss is exit 2 too.

mod plot;
mod report;
pub use slamjac_solve::track_sequence as sequence;

use std::path::PathBuf;
use std::time::Instant;

use factor_core::Storage;
use factor_core::lie::Se3;
use factor_tracking::{Options, PoseError, PoseProblem, SolveOptions};
use slamjac_io::Role;

use crate::error::CliError;
use crate::outputs;
use crate::synth_plp::Kinds;
pub use sequence::MapSource;
use sequence::{Frame, Sequence};

/// What `track` was asked for.
#[derive(Debug, Clone)]
pub struct TrackArgs {
    /// The problem file.
    pub file: PathBuf,
    /// The measurement sets, each tracked over the sequence.
    pub kinds: Vec<Kinds>,
    /// Where the map comes from.
    pub map: MapSource,
    /// The most iterations per frame.
    pub max_iterations: usize,
    /// Where to write the SVG plot.
    pub plot: Option<PathBuf>,
    /// Where to write the problem file with the tracked poses.
    pub output: Option<PathBuf>,
}

/// One frame tracked.
#[derive(Debug, Clone, Copy)]
pub struct Tracked {
    /// Its observations of the measurement set.
    pub observations: usize,
    /// The solve's wall time, seconds.
    pub seconds: f64,
    /// Iterations.
    pub iterations: usize,
    /// Whether the solve converged.
    pub converged: bool,
    /// Observations undefined at the initial pose, deferred to a second
    /// solve ([`factor_tracking::PoseSolution::deferred`]).
    pub deferred: usize,
    /// The estimate.
    pub pose: Se3<f64>,
    /// Its camera centre's distance to the true one.
    pub translation: f64,
    /// Its rotation's angle to the true one, degrees.
    pub rotation: f64,
}

/// The camera-centre distance and the rotation angle (degrees) of `pose`
/// from `truth`, world-to-camera poses.
fn errors(pose: &Se3<f64>, truth: &Se3<f64>) -> (f64, f64) {
    let centre = |p: &Se3<f64>| -p.rotation.inverse_rotate(&p.translation);
    let rotation = pose.rotation.compose(&truth.rotation.inverse()).log();
    (
        (centre(pose) - centre(truth)).norm(),
        rotation.norm().to_degrees(),
    )
}

/// The frame's failure, naming it and the file's factor at fault.
fn frame_error(
    args: &TrackArgs,
    at: usize,
    frame: &Frame,
    error: PoseError,
    factors: &[usize],
) -> CliError {
    let what = match error {
        PoseError::Observation { observation, error } => {
            format!("factors[{}]: {error}", factors[observation])
        }
        other => other.to_string(),
    };
    CliError::Solve(format!(
        "{}: frame {at} ({}): {what}",
        args.file.display(),
        frame.name
    ))
}

/// Tracks the sequence with the observations of `kinds`.
fn track(args: &TrackArgs, sequence: &Sequence, kinds: &Kinds) -> Result<Vec<Tracked>, CliError> {
    let defaults = Options::default();
    let options = Options {
        solve: SolveOptions {
            max_iterations: args.max_iterations,
            ..defaults.solve
        },
        ..defaults
    };
    let mut tracked: Vec<Tracked> = Vec::with_capacity(sequence.frames.len());
    for (at, frame) in sequence.frames.iter().enumerate() {
        let mut problem = PoseProblem::new();
        let mut factors = Vec::new();
        for o in frame.observations.iter().filter(|o| o.kind.in_kinds(kinds)) {
            o.add_to(&mut problem)
                .map_err(|e| frame_error(args, at, frame, e, &[o.factor]))?;
            factors.push(o.factor);
        }
        if problem.is_empty() {
            return Err(CliError::Solve(format!(
                "{}: frame {at} ({}): no observations of {kinds}",
                args.file.display(),
                frame.name
            )));
        }
        let initial = tracked.last().map_or(frame.truth, |t| t.pose);
        let start = Instant::now();
        let solution = problem.solve(&initial, &options);
        let seconds = start.elapsed().as_secs_f64();
        let solution = solution.map_err(|e| frame_error(args, at, frame, e, &factors))?;
        if !solution.verdict.is_converged() {
            // An observation undefined near the estimate (a map point at the
            // camera centre) stalls the steps: named where it is one.
            let why = match (solution.refused, problem.normal(&solution.pose)) {
                (Some(observation), _) => {
                    format!("; factors[{}] refused the steps", factors[observation])
                }
                (None, Err(PoseError::Observation { observation, error })) => format!(
                    "; factors[{}] is undefined at the last estimate: {error}",
                    factors[observation]
                ),
                _ => String::new(),
            };
            return Err(CliError::Solve(format!(
                "{}: frame {at} ({}): the pose did not converge in {} iterations ({}){why}; \
                 nothing reported",
                args.file.display(),
                frame.name,
                solution.iterations,
                solution.verdict
            )));
        }
        let (translation, rotation) = errors(&solution.pose, &frame.truth);
        if !(translation.is_finite() && rotation.is_finite()) {
            return Err(CliError::Solve(format!(
                "{}: frame {at} ({}): the estimate is too far from the truth to measure its error",
                args.file.display(),
                frame.name
            )));
        }
        tracked.push(Tracked {
            observations: problem.len(),
            seconds,
            iterations: solution.iterations,
            converged: solution.verdict.is_converged(),
            deferred: solution.deferred,
            pose: solution.pose,
            translation,
            rotation,
        });
    }
    Ok(tracked)
}

/// Checks the outputs, reads the file, tracks it once per measurement set
/// and writes the plot and the output; returns the report.
///
/// # Errors
///
/// [`CliError::Usage`] for an output that names the input or the other
/// output (before anything is read) or cannot be written; a malformed file
/// ([`sequence::read`], exit 2); a frame that cannot be tracked (exit 1).
pub fn run(args: &TrackArgs) -> Result<String, CliError> {
    let mut written = Vec::new();
    if let Some(path) = &args.plot {
        written.push(Role::new("--plot", path));
    }
    if let Some(path) = &args.output {
        written.push(Role::new("--output", path));
    }
    outputs::check(&[Role::new("the input", &args.file)], &written)?;
    let sequence = sequence::read(&args.file, args.map)?;
    let runs = args
        .kinds
        .iter()
        .map(|kinds| Ok((*kinds, track(args, &sequence, kinds)?)))
        .collect::<Result<Vec<_>, CliError>>()?;
    if let Some(path) = &args.plot {
        outputs::write(path, plot::svg(path, &runs)?)?;
    }
    if let (Some(path), Some((_, last))) = (&args.output, runs.last()) {
        let mut json = sequence.json.root().to_value();
        for (frame, t) in sequence.frames.iter().zip(last) {
            let s = t.pose.to_scalars();
            json["variables"][&frame.name]["value"] =
                serde_json::json!({"rotation": &s[..4], "translation": &s[4..]});
        }
        outputs::write(path, crate::pretty::to_string(&json) + "\n")?;
    }
    Ok(report::text(args, &sequence, &runs))
}
