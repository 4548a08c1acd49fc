//! `slamjac solve` (its Schur-complement path, and apex-solver's with
//! `--solver apex`) against Ceres 2.1 (SPARSE_SCHUR, CHOLMOD, the peer of
//! `bench-peers/ceres_ba`) on synthetic bundle adjustment, whole processes
//! timed side by side.
//!
//! ```sh
//! bash bench-peers/ceres_ba/run.sh            # builds everything, then runs this
//! cargo bench --manifest-path integrations/schur/Cargo.toml --bench versus_ceres -- \
//!     --slamjac target/release/slamjac --ceres bench-peers/out/ceres_ba \
//!     [--sizes 1000,10000,100000,1000000] [--visibility ring,local] [--threads 1,2] \
//!     [--rounds 3] [--apex-max 100000] [--files data/Balbianello.out] [--out bench-peers/out/ba] \
//!     [--markdown FILE.md] [--svg FILE.svg]
//! ```
//!
//! Each data file of `--files` is measured as it is; then for each
//! visibility (`synth-bal --visibility`) and size (observations: five views
//! per point; cameras 10, 100, 500 and 2000 at 10³ to 10⁶, else
//! `n^(2/3) / 5`; seed 0, no outliers, σ = 1 px) the problem is written
//! once, then each round runs every solver once, in an order that rotates
//! from round to round: `slamjac solve` (Schur path) and Ceres on each
//! number of threads (`RAYON_NUM_THREADS`, Ceres' `--threads`), and
//! apex-solver's path (`slamjac solve --solver apex`, all threads) up to
//! `--apex-max` observations. Each run is a whole process: its wall time
//! from spawn to exit (reading the file included) and its peak resident
//! memory (`/usr/bin/time`'s `%M`). Reported: medians over the rounds, the median of the
//! per-round ratios of our time to Ceres', each side's final cost
//! (`½ Σ ‖r‖²`) and iterations, and the load average before and after.

use std::fmt::Write as _;
use std::path::{Path, PathBuf};
use std::process::Command;

use clap::Parser;
use factor_testing::rounds::{fail, load_average, median};
use plotters::prelude::*;

/// The command line (`cargo bench` adds `--bench`; an option given twice
/// takes its last value, so that `run.sh`'s defaults can be overridden).
#[derive(Parser)]
#[command(args_override_self = true)]
struct Args {
    /// `slamjac`, built with `--features solve`.
    #[arg(long)]
    slamjac: PathBuf,
    /// The Ceres peer (`bench-peers/ceres_ba/build.sh` prints its path).
    #[arg(long)]
    ceres: PathBuf,
    /// Problem sizes, in observations.
    #[arg(
        long,
        value_delimiter = ',',
        default_value = "1000,10000,100000,1000000"
    )]
    sizes: Vec<usize>,
    /// `ring` and/or `local` (`synth-bal --visibility`).
    #[arg(long, value_delimiter = ',', default_value = "ring,local")]
    visibility: Vec<String>,
    /// Thread counts for this solver and Ceres.
    #[arg(long, value_delimiter = ',', default_value = "1,2")]
    threads: Vec<usize>,
    /// Rounds per size.
    #[arg(long, default_value_t = 3)]
    rounds: usize,
    /// The largest size apex-solver's path runs at.
    #[arg(long, default_value_t = 100_000)]
    apex_max: usize,
    /// Ceres' function tolerance: `slamjac solve`'s (its relative cost
    /// decrease, `factor_minimizer::SolveOptions::default`), so that both
    /// stop by the same criterion.
    #[arg(long, default_value_t = 1e-8)]
    cost_tolerance: f64,
    /// Data files (BAL or Bundler) measured too, before the synthetic
    /// problems (in the table, not the plot).
    #[arg(long, value_delimiter = ',')]
    files: Vec<PathBuf>,
    /// Where the problems are written.
    #[arg(long, default_value = "bench-peers/out/ba")]
    out: PathBuf,
    /// Write the tables here too.
    #[arg(long)]
    markdown: Option<PathBuf>,
    /// Write the plot here (SVG).
    #[arg(long)]
    svg: Option<PathBuf>,
    #[arg(long, hide = true)]
    bench: bool,
}

/// A solver run the same way each round.
#[derive(Debug, Clone, PartialEq)]
enum Solver {
    Ours(usize),
    Ceres(usize),
    Apex,
}

impl Solver {
    fn name(&self) -> String {
        match self {
            Solver::Ours(t) => format!("slamjac, {t} thread{}", if *t == 1 { "" } else { "s" }),
            Solver::Ceres(t) => format!("Ceres, {t} thread{}", if *t == 1 { "" } else { "s" }),
            Solver::Apex => "apex-solver's path".to_owned(),
        }
    }
}

/// One process's measurements.
#[derive(Debug, Clone, Copy)]
struct Run {
    wall: f64,
    peak_mib: f64,
    final_cost: f64,
    iterations: usize,
}

/// The cameras of a problem of `n` observations.
fn cameras(n: usize) -> usize {
    match n {
        1_000 => 10,
        10_000 => 100,
        100_000 => 500,
        1_000_000 => 2_000,
        _ => ((n as f64).powf(2.0 / 3.0) / 5.0).round().max(10.0) as usize,
    }
}

/// The value after `key` in `text`, up to a delimiter.
fn after<'a>(text: &'a str, key: &str) -> Option<&'a str> {
    let rest = &text[text.find(key)? + key.len()..];
    Some(rest[..rest.find([',', ' ', '\n', '}', '(']).unwrap_or(rest.len())].trim_matches('"'))
}

/// Runs `command` (under `/usr/bin/time`, for its peak memory), returning
/// its measurements: the wall time from spawning it to its exit.
fn run(mut command: Command, solver: &Solver) -> Run {
    let start = std::time::Instant::now();
    let output = command
        .output()
        .unwrap_or_else(|e| fail(&format!("{solver:?}: {e}")));
    let wall = start.elapsed().as_secs_f64();
    let (stdout, stderr) = (
        String::from_utf8_lossy(&output.stdout),
        String::from_utf8_lossy(&output.stderr),
    );
    if !output.status.success() {
        fail(&format!("{solver:?} failed:\n{stdout}\n{stderr}"));
    }
    // `/usr/bin/time -f "peak %M"`: the last line of standard error.
    let peak_kib: f64 = stderr
        .lines()
        .rev()
        .find_map(|l| l.strip_prefix("peak "))
        .and_then(|x| x.trim().parse().ok())
        .unwrap_or(f64::NAN);
    let number = |key: &str| after(&stdout, key).and_then(|x| x.parse::<f64>().ok());
    let (final_cost, iterations) = match solver {
        Solver::Ceres(_) => (number("\"final_cost\": "), number("\"iterations\": ")),
        _ => (number("final "), number(" after ")),
    };
    Run {
        wall,
        peak_mib: peak_kib / 1024.0,
        final_cost: final_cost.unwrap_or(f64::NAN),
        iterations: iterations.map_or(0, |i| i as usize),
    }
}

/// The command of one run of `solver` on `file`.
///
/// Every solver gets the same iteration limit, Ceres' `ba` default of 100
/// (`slamjac solve`'s default is 500).
fn command(args: &Args, solver: &Solver, file: &Path) -> Command {
    let mut c = Command::new("/usr/bin/time");
    c.args(["-f", "peak %M"]);
    let limit = ["--max-iterations", "100"];
    match solver {
        Solver::Ours(t) => {
            c.arg(&args.slamjac).arg("solve").arg(file).args(limit);
            c.env("RAYON_NUM_THREADS", t.to_string());
        }
        Solver::Apex => {
            c.arg(&args.slamjac)
                .arg("solve")
                .arg(file)
                .args(["--solver", "apex"])
                .args(limit);
        }
        Solver::Ceres(t) => {
            c.arg(&args.ceres).arg(file).args(limit).args([
                "--threads",
                &t.to_string(),
                "--function-tolerance",
                &args.cost_tolerance.to_string(),
            ]);
        }
    }
    c
}

/// Every round's runs of every solver at one size.
struct Measured {
    /// `ring` or `local` (synthetic problems), `data` (a data file).
    visibility: String,
    observations: usize,
    /// The table's first column: observations (cameras), or the file's name.
    label: String,
    solvers: Vec<Solver>,
    runs: Vec<Vec<Run>>,
}

impl Measured {
    fn median(&self, k: usize, f: impl Fn(&Run) -> f64) -> f64 {
        median(&self.runs[k].iter().map(f).collect::<Vec<_>>())
    }

    fn index(&self, solver: &Solver) -> Option<usize> {
        self.solvers.iter().position(|s| s == solver)
    }

    /// The median over the rounds of `a`'s time over `b`'s.
    fn ratio(&self, a: usize, b: usize) -> f64 {
        let ratios: Vec<f64> = self.runs[a]
            .iter()
            .zip(&self.runs[b])
            .map(|(x, y)| x.wall / y.wall)
            .collect();
        median(&ratios)
    }
}

fn table(measured: &[Measured], threads: &[usize]) -> String {
    let mut out = String::new();
    for visibility in ["data", "ring", "local"] {
        let rows: Vec<&Measured> = measured
            .iter()
            .filter(|m| m.visibility == visibility)
            .collect();
        if rows.is_empty() {
            continue;
        }
        let (title, first) = match visibility {
            "data" => ("data files".to_owned(), "file"),
            _ => (format!("{visibility} visibility"), "observations (cameras)"),
        };
        let _ = writeln!(out, "\n**{title}**\n");
        let mut head = format!("| {first} |");
        let mut rule = "| --- |".to_owned();
        for t in threads {
            let _ = write!(
                head,
                " {t} thread{}: slamjac / Ceres (s) | ratio | peak memory, slamjac / Ceres (MiB) |",
                if *t == 1 { "" } else { "s" }
            );
            rule.push_str(" --- | --- | --- |");
        }
        head.push_str(" apex-solver's path: s, MiB | final cost: slamjac vs Ceres (relative) | iterations: slamjac / Ceres |");
        rule.push_str(" --- | --- | --- |");
        let _ = writeln!(out, "{head}\n{rule}");
        for m in rows {
            let mut line = format!("| {} |", m.label);
            for &t in threads {
                let (Some(a), Some(b)) = (m.index(&Solver::Ours(t)), m.index(&Solver::Ceres(t)))
                else {
                    continue;
                };
                let _ = write!(
                    line,
                    " {:.3} / {:.3} | {:.2} | {:.0} / {:.0} |",
                    m.median(a, |r| r.wall),
                    m.median(b, |r| r.wall),
                    m.ratio(a, b),
                    m.median(a, |r| r.peak_mib),
                    m.median(b, |r| r.peak_mib)
                );
            }
            match m.index(&Solver::Apex) {
                Some(k) => {
                    let _ = write!(
                        line,
                        " {:.2}, {:.0} |",
                        m.median(k, |r| r.wall),
                        m.median(k, |r| r.peak_mib)
                    );
                }
                None => line.push_str(" — |"),
            }
            let (a, b) = (
                m.index(&Solver::Ours(threads[0])),
                m.index(&Solver::Ceres(threads[0])),
            );
            if let (Some(a), Some(b)) = (a, b) {
                let (ours, ceres) = (m.runs[a][0], m.runs[b][0]);
                let _ = write!(
                    line,
                    " {:+.1e} | {} / {} |",
                    (ours.final_cost - ceres.final_cost) / ceres.final_cost,
                    ours.iterations,
                    ceres.iterations
                );
            }
            let _ = writeln!(out, "{line}");
        }
    }
    out
}

/// Time and peak memory against the size, log–log: one panel each, per
/// visibility; a line per solver.
fn plot(path: &Path, measured: &[Measured]) -> Result<(), Box<dyn std::error::Error>> {
    let visibilities: Vec<&str> = ["ring", "local"]
        .into_iter()
        .filter(|v| measured.iter().any(|m| m.visibility == *v))
        .collect();
    let root = SVGBackend::new(path, (1200, 440 * visibilities.len() as u32)).into_drawing_area();
    root.fill(&WHITE)?;
    let panels = root.split_evenly((visibilities.len(), 2));
    let solvers: Vec<Solver> = measured
        .first()
        .map(|m| m.solvers.clone())
        .unwrap_or_default();
    let colours = [RED, BLUE, MAGENTA, GREEN, BLACK, CYAN];
    for (row, visibility) in visibilities.iter().enumerate() {
        let rows: Vec<&Measured> = measured
            .iter()
            .filter(|m| m.visibility == *visibility)
            .collect();
        for (column, (what, value)) in [
            ("wall time (s)", (|r: &Run| r.wall) as fn(&Run) -> f64),
            ("peak memory (MiB)", |r: &Run| r.peak_mib),
        ]
        .into_iter()
        .enumerate()
        {
            let series: Vec<(String, Vec<(f64, f64)>)> = solvers
                .iter()
                .map(|s| {
                    let points = rows
                        .iter()
                        .filter_map(|m| {
                            m.index(s).map(|k| {
                                ((m.observations as f64).log10(), m.median(k, value).log10())
                            })
                        })
                        .collect();
                    (s.name(), points)
                })
                .collect();
            let all: Vec<(f64, f64)> = series.iter().flat_map(|(_, p)| p.iter().copied()).collect();
            let (x0, x1) = all
                .iter()
                .fold((f64::MAX, f64::MIN), |(a, b), p| (a.min(p.0), b.max(p.0)));
            let (y0, y1) = all
                .iter()
                .fold((f64::MAX, f64::MIN), |(a, b), p| (a.min(p.1), b.max(p.1)));
            let area = &panels[row * 2 + column];
            let mut chart = ChartBuilder::on(area)
                .caption(
                    format!("{what}, {visibility} visibility"),
                    ("sans-serif", 18),
                )
                .margin(12)
                .x_label_area_size(40)
                .y_label_area_size(60)
                .build_cartesian_2d((x0 - 0.1)..(x1 + 0.1), (y0 - 0.2)..(y1 + 0.2))?;
            chart
                .configure_mesh()
                .x_desc("observations")
                .y_desc(what)
                .x_label_formatter(&|x| format!("{:.0e}", 10f64.powf(*x)))
                .y_label_formatter(&|y| format!("{:.3}", 10f64.powf(*y)))
                .draw()?;
            for ((name, points), colour) in series.into_iter().zip(colours.iter().cycle()) {
                let style = colour.stroke_width(2);
                chart
                    .draw_series(LineSeries::new(points.clone(), style))?
                    .label(name)
                    .legend(move |(x, y)| PathElement::new(vec![(x, y), (x + 16, y)], style));
                chart.draw_series(
                    points
                        .into_iter()
                        .map(|p| Circle::new(p, 3, colour.filled())),
                )?;
            }
            chart
                .configure_series_labels()
                .position(SeriesLabelPosition::UpperLeft)
                .background_style(WHITE.mix(0.8))
                .border_style(BLACK)
                .draw()?;
        }
    }
    root.present()?;
    Ok(())
}

fn main() {
    let args = Args::parse();
    std::fs::create_dir_all(&args.out)
        .unwrap_or_else(|e| fail(&format!("{}: {e}", args.out.display())));
    let load_before = load_average();
    let mut problems: Vec<(String, usize, String, PathBuf)> = args
        .files
        .iter()
        .map(|f| {
            let name = f.file_name().map_or_else(
                || f.display().to_string(),
                |n| n.to_string_lossy().into_owned(),
            );
            ("data".to_owned(), 0, name, f.clone())
        })
        .collect();
    for visibility in &args.visibility {
        for &n in &args.sizes {
            let (c, points) = (cameras(n), n.div_ceil(5));
            let file = args.out.join(format!("{visibility}-{n}.txt"));
            if !file.exists() {
                let status = Command::new(&args.slamjac)
                    .args([
                        "synth-bal",
                        "--cameras",
                        &c.to_string(),
                        "--points",
                        &points.to_string(),
                    ])
                    .args([
                        "--seed",
                        "0",
                        "--outliers",
                        "0",
                        "--visibility",
                        visibility,
                        "--output",
                    ])
                    .arg(&file)
                    .status()
                    .unwrap_or_else(|e| fail(&e.to_string()));
                if !status.success() {
                    fail(&format!("synth-bal failed for {}", file.display()));
                }
            }
            problems.push((visibility.clone(), n, format!("{n} ({c})"), file));
        }
    }
    let mut measured = Vec::new();
    for (visibility, n, label, file) in problems {
        let mut solvers: Vec<Solver> = Vec::new();
        for &t in &args.threads {
            solvers.push(Solver::Ours(t));
            solvers.push(Solver::Ceres(t));
        }
        if n <= args.apex_max {
            solvers.push(Solver::Apex);
        }
        let mut runs = vec![Vec::new(); solvers.len()];
        for round in 0..args.rounds {
            for k in 0..solvers.len() {
                let k = (k + round) % solvers.len();
                let r = run(command(&args, &solvers[k], &file), &solvers[k]);
                eprintln!(
                    "{visibility} {label}: round {round}: {}: {:.3} s, {:.0} MiB, cost {:.12e}, {} iterations",
                    solvers[k].name(),
                    r.wall,
                    r.peak_mib,
                    r.final_cost,
                    r.iterations
                );
                runs[k].push(r);
            }
        }
        measured.push(Measured {
            visibility,
            observations: n,
            label,
            solvers,
            runs,
        });
    }
    let mut text = table(&measured, &args.threads);
    let _ = writeln!(
        text,
        "\nMedians of {} alternating rounds; load average before: {load_before}; after: {}.",
        args.rounds,
        load_average()
    );
    println!("{text}");
    if let Some(path) = &args.markdown {
        std::fs::write(path, &text).unwrap_or_else(|e| fail(&format!("{}: {e}", path.display())));
    }
    if let Some(path) = &args.svg {
        plot(path, &measured).unwrap_or_else(|e| fail(&format!("{}: {e}", path.display())));
    }
}
