//! `slamjac`: evaluate SLAM factors and their exact tangent-space Jacobians.
//!
//! ```text
//! slamjac eval FILE [--method generated|dual|numeric]   # FILE may be `-` for stdin
//! slamjac list [--json]
//! slamjac generate [--out DIR]   # rewrite generated/ from the factor definitions
//! slamjac check [--dir DIR]      # exit 1 when generated/ is stale
//! slamjac solve FILE [--format F] [--kernels generated|dual] [--solver auto|schur|apex]
//!               [--max-iterations N] [--factors g2o|documents] [--truth FILE]
//!               [--robust huber:δ|cauchy:δ] [--output FILE] [--plot FILE.svg]   # feature `solve`
//! slamjac track FILE.json [--kinds K]... [--map truth|values] [--max-iterations N]
//!               [--plot FILE.svg] [--output FILE.json]   # feature `solve`
//! slamjac synth-bal --cameras N --points M [--views V] [--visibility ring|local] [--seed S]
//!                   [--outliers F] [--noise σ] --output FILE
//! slamjac synth-plp [--seed S] [--cameras N] [--points P] [--lines L]
//!                   [--kinds points,lines,planes] --output FILE.json
//! slamjac audit [--samples N] [--markdown F] [--json F] [--allow-unread]  # the shipped documents
//! slamjac audit DOC.md --symbols DOC.toml [--samples N] [...]             # a document, from its text
//! ```
//!
//! Exit codes: 0 success; 1 degenerate geometry, a non-finite result, or
//! stale generated files; 2 rejected input or a usage error. Errors are one
//! line on stderr, `error: <field path>: <what>`, with unusual keys quoted
//! and escaped (`variables["a\nb"]`) and long names cut after 64 characters.
//! `eval` reads at most 16 MiB of UTF-8 and rejects duplicate keys. Where
//! `generate` and `check` work: see `slamjac::generate`.

use std::path::PathBuf;
use std::process::ExitCode;

use clap::{Parser, Subcommand, ValueEnum};
use slamjac::cli::{self, CommandLine, FactorCommand};
use slamjac::usage;
use slamjac::{CliError, audit, audit_text, init, kernels, synth, synth_plp};

#[derive(Debug, Parser)]
#[command(
    name = "slamjac",
    version,
    about = "Exact tangent-space Jacobians of SLAM factors",
    after_help = cli::AFTER_HELP
)]
struct Cli {
    #[command(subcommand)]
    command: Command,
}

#[derive(Debug, Subcommand)]
enum Command {
    /// `eval`, `list`, `generate` and `check` of the shipped factors, as
    /// any registry's command line has them (`slamjac::cli`).
    #[command(flatten)]
    Factors(FactorCommand),
    /// Write a new project for factors of your own into DIR: a Cargo
    /// workspace with the factor crate (one example factor), its kernel
    /// crate and its command line (`list`, `eval`, `generate`, `check`),
    /// depending on this checkout by path, and the profile entries that
    /// make generation fast in debug builds.
    Init {
        /// The project's directory: new or empty.
        dir: PathBuf,
        /// The project's name: the crates `NAME-factors`, `NAME-kernels`
        /// and `NAME-cli` (binary `NAME`) [default: DIR's name].
        #[arg(long)]
        name: Option<String>,
    },
    /// Audit hand-derived formulas against the toolchain's derivatives,
    /// straight from a document's text: without a DOCUMENT, the two
    /// specification documents shipped in `documents/`; with a DOCUMENT
    /// and --symbols, that Markdown/LaTeX document (the corpus of
    /// `documents/corpus/` is audited so). Exit 1 when a verdict is not the
    /// one the symbols file expects; exit 2 when a claim cannot be read
    /// (unless --allow-unread).
    #[command(allow_negative_numbers = true)]
    Audit {
        /// A Markdown/LaTeX document to audit from its text (needs
        /// --symbols); without it, the shipped documents are audited.
        #[arg(value_name = "DOCUMENT", requires = "symbols")]
        document: Option<PathBuf>,
        /// The symbols file (TOML) giving the document's symbols their
        /// meaning and stating what each audited equation claims.
        #[arg(long, value_name = "FILE", requires = "document")]
        symbols: Option<PathBuf>,
        /// Sampled points per formula, 1 to 100000.
        #[arg(long, default_value_t = 100)]
        samples: usize,
        /// Also write a Markdown report here.
        #[arg(long, value_name = "FILE")]
        markdown: Option<PathBuf>,
        /// Also write a JSON report here (one entry per formula).
        #[arg(long, value_name = "FILE")]
        json: Option<PathBuf>,
        /// Audit what can be read: claims that cannot be read (listed with
        /// the notation or symbol at fault) do not fail the run.
        #[arg(long)]
        allow_unread: bool,
    },
    /// Solve a real estimation problem by Levenberg–Marquardt, its factors
    /// linearized by their generated kernels: bundle adjustment (BAL,
    /// Bundler: camera 0's pose fixed), pose graphs (g2o, EDGE3: the first
    /// pose fixed), stereo visual odometry (KITTI VO files: the first pose
    /// fixed), g2o's line and plane graphs (the FIX vertices fixed), and
    /// problem files of any registered factors (`*.json`); every data set
    /// and problem files of factors with fused normal-equation kernels by
    /// slamjac's Schur-complement solver (the landmarks eliminated), other
    /// problem files by apex-solver. Prints a line per iteration and a summary.
    /// Needs
    /// the feature `solve` (`cargo run --release --features solve -- solve FILE`).
    #[command(allow_negative_numbers = true)]
    Solve {
        #[command(flatten)]
        problem: cli::SolveCommand,
        /// The format [default: from the file name, `.txt` from its content].
        #[arg(long, value_parser = parse_format)]
        format: Option<slam_data::Format>,
        /// Which solver: `schur` (landmarks eliminated by a Schur complement
        /// fed by the fused normal-equation kernels, or by each factor's
        /// Jacobians where it has none and with `--kernels dual`; every
        /// data set, problem files of factors with fused kernels), `apex`
        /// (apex-solver, any problem), or `auto` (`schur` where it applies,
        /// else `apex`).
        #[arg(long, value_enum, default_value_t)]
        solver: SolverFlag,
        /// The factors of the lines and planes of a g2o line and plane
        /// graph: g2o's own errors (the cost is g2o's χ²/2) or the
        /// documents' orthonormal-line and quaternion-plane factors.
        #[arg(long, value_enum, default_value_t)]
        factors: LandmarkChoice,
        /// Ground truth to report errors against (a g2o line and plane
        /// graph) [default: STEM_truth.g2o beside the file, if it exists].
        #[arg(long, value_name = "FILE")]
        truth: Option<PathBuf>,
    },
    /// Track a problem file's poses frame after frame against its fixed map
    /// (every landmark held at its truth, or at its value with --map
    /// values): each frame's pose solved alone by pose-only
    /// Levenberg–Marquardt from the previous frame's estimate (frame 0 from
    /// its truth), its point, line and plane observations linearized by the
    /// generated kernels. Prints the time per frame and the errors against
    /// the truth (per frame, final frame, ATE) for each --kinds side by side.
    /// Needs the feature `solve`.
    Track {
        /// The problem file (`synth-plp` writes one); its `truth` is needed.
        file: PathBuf,
        /// The measurements used, comma-separated; repeat to compare
        /// several sets side by side [default: `points`, then
        /// `points,lines,planes`].
        #[arg(long, default_values = ["points", "points,lines,planes"])]
        kinds: Vec<synth_plp::Kinds>,
        /// The fixed map: each landmark's `truth` or its `value`.
        #[arg(long, value_enum, default_value_t)]
        map: MapChoice,
        /// The most iterations per frame.
        #[arg(long, default_value_t = 20, value_parser = clap::value_parser!(u64).range(1..=1000))]
        max_iterations: u64,
        /// Write an SVG plot here: the translation and rotation error per
        /// frame, a line per --kinds.
        #[arg(long, value_name = "FILE.svg")]
        plot: Option<PathBuf>,
        /// Write the problem file here with its poses at the last --kinds'
        /// estimates.
        #[arg(long, value_name = "FILE.json")]
        output: Option<PathBuf>,
    },
    /// Write a seeded synthetic bundle-adjustment problem as a BAL file:
    /// cameras on a ring looking at a ball of points, Gaussian pixel noise,
    /// uniform outliers, perturbed initial values. The file is streamed:
    /// only the cameras are held in memory.
    #[command(allow_negative_numbers = true)]
    SynthBal {
        /// Cameras (2 to 1000000).
        #[arg(long)]
        cameras: usize,
        /// Points.
        #[arg(long)]
        points: usize,
        /// Cameras that see each point.
        #[arg(long, default_value_t = 5)]
        views: usize,
        /// Which cameras see a point: `ring` (spread over 60° of the ring,
        /// points in the central ball) or `local` (consecutive cameras,
        /// points near them, as in a reconstruction from a sequence).
        #[arg(long, value_enum, default_value_t)]
        visibility: VisibilityFlag,
        /// Seed of the random generator.
        #[arg(long, default_value_t = 0)]
        seed: u64,
        /// Fraction of observations that are outliers, uniform in the image.
        #[arg(long, default_value_t = 0.05)]
        outliers: f64,
        /// Pixel noise of the inliers (standard deviation, px).
        #[arg(long, default_value_t = 1.0)]
        noise: f64,
        /// The BAL file to write.
        #[arg(long, value_name = "FILE")]
        output: PathBuf,
    },
    /// Write a seeded point-line-plane room as a problem file of the
    /// documents' factors (point and orthonormal-line reprojections, the
    /// quaternion plane) with its ground truth, for `solve FILE.json`:
    /// pixel noise of 1 px, cameras c0 and c1 fixed at their true poses.
    SynthPlp {
        /// Seed of the random generator.
        #[arg(long, default_value_t = 0)]
        seed: u64,
        /// Cameras (2 to 200).
        #[arg(long, default_value_t = 15, value_parser = clap::value_parser!(u64).range(2..=200))]
        cameras: u64,
        /// Points, up to 10000 (two thirds on the planes, the rest in the
        /// room).
        #[arg(long, default_value_t = 300, value_parser = clap::value_parser!(u64).range(0..=10_000))]
        points: u64,
        /// Lines, up to 1000 (the 12 box edges first, then 2 doors, then
        /// wall segments).
        #[arg(long, default_value_t = 30, value_parser = clap::value_parser!(u64).range(0..=1000))]
        lines: u64,
        /// The measurements written, comma-separated.
        #[arg(long, default_value = "points,lines,planes")]
        kinds: synth_plp::Kinds,
        /// The problem file to write.
        #[arg(long, value_name = "FILE.json")]
        output: PathBuf,
    },
}

/// `--solver`: which solver `solve` uses.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, ValueEnum)]
enum SolverFlag {
    /// The Schur-complement solver where it applies, else apex-solver.
    #[default]
    Auto,
    /// The Schur-complement solver (every data set, problem files of
    /// factors with fused kernels).
    Schur,
    /// apex-solver.
    Apex,
}

/// `track --map`: where the fixed map's values come from.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, ValueEnum)]
enum MapChoice {
    /// Each landmark's `truth` (a map known exactly).
    #[default]
    Truth,
    /// Each landmark's `value` (e.g. the map `solve --output` estimated).
    Values,
}

/// `synth-bal --visibility`.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, ValueEnum)]
enum VisibilityFlag {
    /// Views spread over about 60° of the ring.
    #[default]
    Ring,
    /// Consecutive cameras, points near them.
    Local,
}

/// `--factors`: which factors measure the lines and planes of a g2o graph.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, ValueEnum)]
enum LandmarkChoice {
    /// g2o's own error definitions.
    #[default]
    G2o,
    /// The documents' line and plane factors.
    Documents,
}

fn parse_format(name: &str) -> Result<slam_data::Format, String> {
    name.parse()
        .map_err(|e: slam_data::UnknownFormat| e.to_string())
}

/// `slamjac solve`: `problem` and the options only data files have.
#[cfg(feature = "solve")]
fn solve(
    problem: &cli::SolveCommand,
    format: Option<slam_data::Format>,
    solver: SolverFlag,
    factors: LandmarkChoice,
    truth: Option<PathBuf>,
) -> Result<String, CliError> {
    use slam_problems::g2o_edges::LandmarkFactors;
    use slamjac::solve::{SolveArgs, SolverChoice};
    slamjac::solve::run(&SolveArgs {
        format,
        solver: match solver {
            SolverFlag::Auto => SolverChoice::Auto,
            SolverFlag::Schur => SolverChoice::Schur,
            SolverFlag::Apex => SolverChoice::Apex,
        },
        landmarks: match factors {
            LandmarkChoice::G2o => LandmarkFactors::G2o,
            LandmarkChoice::Documents => LandmarkFactors::Documents,
        },
        truth,
        ..problem.args()?
    })
}

#[cfg(not(feature = "solve"))]
fn solve(
    _problem: &cli::SolveCommand,
    _format: Option<slam_data::Format>,
    _solver: SolverFlag,
    _factors: LandmarkChoice,
    _truth: Option<PathBuf>,
) -> Result<String, CliError> {
    Err(CliError::Usage(cli::WITHOUT_SOLVE.into()))
}

#[cfg(feature = "solve")]
fn track(
    file: PathBuf,
    kinds: Vec<synth_plp::Kinds>,
    map: MapChoice,
    max_iterations: u64,
    plot: Option<PathBuf>,
    output: Option<PathBuf>,
) -> Result<String, CliError> {
    use slamjac::solve::track::{MapSource, TrackArgs, run};
    run(&TrackArgs {
        file,
        kinds,
        map: match map {
            MapChoice::Truth => MapSource::Truth,
            MapChoice::Values => MapSource::Values,
        },
        // Within the range above.
        max_iterations: max_iterations as usize,
        plot,
        output,
    })
}

#[cfg(not(feature = "solve"))]
fn track(
    _file: PathBuf,
    _kinds: Vec<synth_plp::Kinds>,
    _map: MapChoice,
    _max_iterations: u64,
    _plot: Option<PathBuf>,
    _output: Option<PathBuf>,
) -> Result<String, CliError> {
    Err(CliError::Usage(
        "track: this slamjac was built without the feature `solve`; build it with \
         `cargo run --release --features solve -- track FILE.json`"
            .into(),
    ))
}

fn main() -> ExitCode {
    slamjac_io::atomic::fail_writes_past_the_file_size_limit();
    let cli = match Cli::try_parse() {
        Ok(cli) => cli,
        Err(error) => return usage::print(&error, "slamjac"),
    };
    let output = match cli.command {
        Command::Factors(command) => kernels::shipped().execute(&command),
        Command::Init { dir, name } => init::run(&dir, name.as_deref()),
        Command::Audit {
            document: Some(document),
            symbols: Some(symbols),
            samples,
            markdown,
            json,
            allow_unread,
        } => audit_text::run(
            &document,
            &symbols,
            samples,
            markdown.as_deref(),
            json.as_deref(),
            allow_unread,
        ),
        Command::Audit {
            samples,
            markdown,
            json,
            allow_unread,
            ..
        } => audit::run(samples, markdown.as_deref(), json.as_deref(), allow_unread),
        Command::Solve {
            problem,
            format,
            solver,
            factors,
            truth,
        } => solve(&problem, format, solver, factors, truth),
        Command::Track {
            file,
            kinds,
            map,
            max_iterations,
            plot,
            output,
        } => track(file, kinds, map, max_iterations, plot, output),
        Command::SynthBal {
            cameras,
            points,
            views,
            visibility,
            seed,
            outliers,
            noise,
            output,
        } => synth::run(
            &synth::SynthArgs {
                cameras,
                points,
                views,
                visibility: match visibility {
                    VisibilityFlag::Ring => slam_data::synthetic::Visibility::Ring,
                    VisibilityFlag::Local => slam_data::synthetic::Visibility::Local,
                },
                seed,
                outliers,
                noise,
            },
            &output,
        ),
        Command::SynthPlp {
            seed,
            cameras,
            points,
            lines,
            kinds,
            output,
        } => synth_plp::run(
            // Within the ranges above.
            &synth_plp::RoomRequest {
                seed,
                cameras: cameras as usize,
                points: points as usize,
                lines: lines as usize,
                kinds,
            },
            &output,
        ),
    };
    cli::report(output)
}
