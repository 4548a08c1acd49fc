//! A line per solver iteration on standard output, and on a terminal a
//! progress bar (standard error) once a solve has run for a second.

use std::io::{IsTerminal, Write};
use std::time::{Duration, Instant};

use factor_minimizer::Iteration;
use indicatif::{ProgressBar, ProgressDrawTarget, ProgressStyle};

/// How long a solve runs before its progress bar appears.
const BAR_AFTER: Duration = Duration::from_secs(1);
/// Problems with this many blocks show their bar from the start (their
/// first iteration alone takes seconds).
const LARGE: usize = 100_000;

/// Prints `text` (and a newline) on standard output; a closed pipe is ignored.
pub fn print(text: &str) {
    let _ = writeln!(std::io::stdout().lock(), "{text}");
}

/// The column heads of [`line()`].
pub const HEAD: &str = "iter           cost  rel.decrease      damping  step      rho   linearize       solve    evaluate";

/// One iteration: cost, relative decrease, damping λ, whether the step was
/// accepted, its quality ρ, and the wall time of the linearization pass,
/// the linear solve (with the rest of the iteration) and the step's
/// evaluation pass.
pub fn line(it: &Iteration) -> String {
    let optional = |x: Option<f64>| x.map_or_else(|| "-".to_owned(), |x| format!("{x:.2e}"));
    format!(
        "{:>4} {:>14.8e} {:>13.3e} {:>12} {:>5} {:>8} {:>11} {:>11} {:>11}",
        it.index,
        it.cost,
        it.relative_decrease,
        optional(it.damping),
        if it.accepted { "ok" } else { "rej" },
        it.step_quality
            .map_or_else(|| "-".to_owned(), |r| format!("{r:.3}")),
        duration(it.linearization),
        duration(it.solve),
        duration(it.evaluation),
    )
}

/// `12.3 ms`, `1.25 s`, `850 µs`.
pub fn duration(d: Duration) -> String {
    let s = d.as_secs_f64();
    if s >= 1.0 {
        format!("{s:.2} s")
    } else if s >= 1e-3 {
        format!("{:.2} ms", s * 1e3)
    } else {
        format!("{:.0} µs", s * 1e6)
    }
}

/// Draws `bar` on standard error, if that is a terminal.
fn show(bar: &ProgressBar) {
    if std::io::stderr().is_terminal() {
        bar.set_draw_target(ProgressDrawTarget::stderr());
        bar.enable_steady_tick(Duration::from_millis(200));
    }
}

/// The iteration lines and the bar of one solve.
pub struct Progress {
    bar: ProgressBar,
}

impl Progress {
    /// Progress of a solve of at most `max_iterations` over `blocks` blocks.
    pub fn new(max_iterations: usize, blocks: usize) -> Self {
        let bar = ProgressBar::with_draw_target(
            Some(max_iterations as u64),
            ProgressDrawTarget::hidden(),
        );
        bar.set_style(
            ProgressStyle::with_template(
                "{spinner} iteration {pos}/{len} [{elapsed_precise}] {wide_bar} {msg}",
            )
            .unwrap_or_else(|_| ProgressStyle::default_bar()),
        );
        bar.set_message(format!("{blocks} blocks"));
        if blocks >= LARGE {
            show(&bar);
        }
        print(HEAD);
        Progress { bar }
    }

    /// The solver's callback: prints each iteration's line and moves the
    /// bar, showing it once the solve has run for a few seconds
    /// (`BAR_AFTER`) on a terminal.
    pub fn callback(&mut self) -> impl FnMut(&Iteration) + Send + 'static {
        let bar = self.bar.clone();
        let start = Instant::now();
        let mut hidden = bar.is_hidden();
        move |it: &Iteration| {
            bar.suspend(|| print(&line(it)));
            bar.set_position(it.index as u64 + 1);
            bar.set_message(format!("cost {:.6e}", it.cost));
            if hidden && start.elapsed() >= BAR_AFTER {
                show(&bar);
                hidden = false;
            }
        }
    }

    /// Removes the bar.
    pub fn finish(&self) {
        self.bar.finish_and_clear();
    }
}
