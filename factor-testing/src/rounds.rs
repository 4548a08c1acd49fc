//! Timing methods side by side on a shared machine: in each round every
//! method runs once, in an order that rotates from round to round, so that a
//! burst of load from another process falls on all of them alike; the
//! medians over the rounds are reported. With each wall time goes the
//! process's CPU time over it, which tells how many cores a method had: a
//! method on 2 threads that got about 1 core's worth shared the machine.

use std::time::Instant;

use ::cpu_time::ProcessTime;

/// A method to time: `reps` back-to-back runs of it (whole batches).
pub type Method<'a> = Box<dyn FnMut(usize) + 'a>;

/// What [`alternate`] measured, `[method][round]`.
pub struct Times {
    /// Wall time of one run (seconds), the mean of the round's runs.
    pub wall: Vec<Vec<f64>>,
    /// The process's CPU time over the same runs, per run (seconds).
    pub cpu: Vec<Vec<f64>>,
}

impl Times {
    /// The median over the rounds of method `k`'s CPU time over its wall
    /// time: the cores it had (about 1 for one thread on an idle machine).
    pub fn cores(&self, k: usize) -> f64 {
        median_ratio(&self.cpu[k], &self.wall[k])
    }
}

/// The times of `reps` back-to-back runs of each method in each of
/// `rounds` rounds, per run. Every method runs once before the first round
/// (warm-up: caches, page faults, rayon's threads).
pub fn alternate(methods: &mut [Method<'_>], rounds: usize, reps: usize) -> Times {
    let mut times = Times {
        wall: vec![Vec::with_capacity(rounds); methods.len()],
        cpu: vec![Vec::with_capacity(rounds); methods.len()],
    };
    for method in methods.iter_mut() {
        method(1);
    }
    for round in 0..rounds {
        for k in 0..methods.len() {
            let i = (k + round) % methods.len();
            let (start, cpu) = (Instant::now(), ProcessTime::now());
            methods[i](reps);
            let per_run = |seconds: f64| seconds / reps as f64;
            times.wall[i].push(per_run(start.elapsed().as_secs_f64()));
            times.cpu[i].push(per_run(cpu.elapsed().as_secs_f64()));
        }
    }
    times
}

/// The median of `values` (the upper one of an even count).
pub fn median(values: &[f64]) -> f64 {
    let mut sorted = values.to_vec();
    sorted.sort_by(f64::total_cmp);
    sorted.get(sorted.len() / 2).copied().unwrap_or(f64::NAN)
}

/// The median over rounds of `a[round] / b[round]`: a ratio measured side
/// by side in each round.
pub fn median_ratio(a: &[f64], b: &[f64]) -> f64 {
    let ratios: Vec<f64> = a.iter().zip(b).map(|(x, y)| x / y).collect();
    median(&ratios)
}

/// The machine's load average over 1, 5 and 15 minutes (`/proc/loadavg`),
/// to print beside the figures: this machine is shared.
pub fn load_average() -> String {
    std::fs::read_to_string("/proc/loadavg")
        .map(|s| s.split_whitespace().take(3).collect::<Vec<_>>().join(" "))
        .unwrap_or_else(|_| "unknown".into())
}

/// Ends a benchmark with `message` on one line and exit code 2.
pub fn fail(message: &str) -> ! {
    eprintln!("error: {message}");
    std::process::exit(2)
}

/// A count above 0, for a benchmark's command line (a `clap` value parser).
pub fn positive_count(text: &str) -> Result<usize, String> {
    match text.parse() {
        Ok(n) if n > 0 => Ok(n),
        _ => Err(format!("`{text}` is not a count above 0")),
    }
}
