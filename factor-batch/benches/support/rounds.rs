//! Timing methods side by side on a shared machine: in each round every
//! method runs once, in an order that rotates from round to round, so that a
//! burst of load from another process falls on all of them alike; the
//! medians over the rounds are reported.

use std::time::Instant;

/// A method to time: `reps` back-to-back runs of it (whole batches).
pub type Method<'a> = Box<dyn FnMut(usize) + 'a>;

/// The wall time (seconds) of one run of each method in each round:
/// `times[method][round]`, each the mean of `reps` back-to-back runs. Every
/// method runs once before the first round (warm-up: caches, page faults,
/// rayon's threads).
pub fn alternate(methods: &mut [Method<'_>], rounds: usize, reps: usize) -> Vec<Vec<f64>> {
    let mut times = vec![Vec::with_capacity(rounds); methods.len()];
    for method in methods.iter_mut() {
        method(1);
    }
    for round in 0..rounds {
        for k in 0..methods.len() {
            let i = (k + round) % methods.len();
            let start = Instant::now();
            methods[i](reps);
            times[i].push(start.elapsed().as_secs_f64() / reps as f64);
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
