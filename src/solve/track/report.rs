//! The report of `track`: a column per measurement set.

use super::sequence::{MapSource, Sequence};
use super::{TrackArgs, Tracked};
use crate::synth_plp::Kinds;

/// The value at quantile `q` of `values` (nearest rank: the smallest value
/// with at least `q` of them at or below it).
fn quantile(values: &[f64], q: f64) -> f64 {
    let mut sorted = values.to_vec();
    sorted.sort_by(f64::total_cmp);
    let rank = ((q * sorted.len() as f64).ceil() as usize).clamp(1, sorted.len());
    sorted[rank - 1]
}

/// The lower median.
fn median(values: &[f64]) -> f64 {
    quantile(values, 0.5)
}

fn max(values: &[f64]) -> f64 {
    values.iter().copied().fold(f64::NEG_INFINITY, f64::max)
}

/// A figure of a measurement set's frames, in words.
type Figure = fn(&[Tracked]) -> String;

/// The report: what was tracked, then a row per figure and a column per
/// measurement set.
pub fn text(args: &TrackArgs, sequence: &Sequence, runs: &[(Kinds, Vec<Tracked>)]) -> String {
    let [points, lines, planes] = sequence.map;
    let map = match args.map {
        MapSource::Truth => "the file's truth",
        MapSource::Values => "the file's values",
    };
    let mut out = format!(
        "tracked {}: {} frames against a fixed map at {map} ({points} points, {lines} lines, \
         {planes} planes); frame 0 from its truth, each next frame from the previous estimate\n",
        args.file.display(),
        sequence.frames.len(),
    );
    let rows: [(&str, Figure); 10] = [
        ("measurements", |_| String::new()),
        ("observations per frame: median (min–max)", |t| {
            let n: Vec<f64> = t.iter().map(|t| t.observations as f64).collect();
            format!("{} ({}–{})", median(&n), quantile(&n, 0.0), max(&n))
        }),
        ("time per frame (µs): median / p95 / max", |t| {
            let s: Vec<f64> = t.iter().map(|t| t.seconds * 1e6).collect();
            format!(
                "{:.0} / {:.0} / {:.0}",
                median(&s),
                quantile(&s, 0.95),
                max(&s)
            )
        }),
        ("iterations per frame: mean / max", |t| {
            let i: Vec<f64> = t.iter().map(|t| t.iterations as f64).collect();
            format!(
                "{:.2} / {}",
                i.iter().sum::<f64>() / i.len() as f64,
                max(&i)
            )
        }),
        ("frames converged", |t| {
            format!("{} / {}", t.iter().filter(|t| t.converged).count(), t.len())
        }),
        ("observations deferred (undefined at the start)", |t| {
            let frames = t.iter().filter(|t| t.deferred > 0).count();
            let total: usize = t.iter().map(|t| t.deferred).sum();
            format!("{total} in {frames} frames")
        }),
        ("translation error (m): median / max", |t| {
            let e: Vec<f64> = t.iter().map(|t| t.translation).collect();
            format!("{:.5} / {:.5}", median(&e), max(&e))
        }),
        ("rotation error (°): median / max", |t| {
            let e: Vec<f64> = t.iter().map(|t| t.rotation).collect();
            format!("{:.4} / {:.4}", median(&e), max(&e))
        }),
        ("final frame: translation (m), rotation (°)", |t| {
            let last = t.last().expect("a frame at least");
            format!("{:.5}, {:.4}", last.translation, last.rotation)
        }),
        ("ATE RMSE, no alignment (m)", |t| {
            let sum: f64 = t.iter().map(|t| t.translation * t.translation).sum();
            format!("{:.5}", (sum / t.len() as f64).sqrt())
        }),
    ];
    for (k, (label, figure)) in rows.iter().enumerate() {
        out.push_str(&format!("  {label:<48}"));
        for (kinds, tracked) in runs {
            let cell = if k == 0 {
                kinds.to_string()
            } else {
                figure(tracked)
            };
            out.push_str(&format!("  {cell:<24}"));
        }
        let trimmed = out.trim_end().len();
        out.truncate(trimmed);
        out.push('\n');
    }
    if let Some(path) = &args.plot {
        out.push_str(&format!("  plot: {}\n", path.display()));
    }
    if let Some(path) = &args.output {
        out.push_str(&format!("  output: {}\n", path.display()));
    }
    out.trim_end().to_owned()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn quantiles_are_nearest_ranks() {
        let v = [5.0, 1.0, 4.0, 2.0, 3.0];
        assert_eq!(median(&v), 3.0);
        assert_eq!(quantile(&v, 0.0), 1.0);
        assert_eq!(quantile(&v, 0.95), 5.0);
        assert_eq!(quantile(&v, 0.8), 4.0);
        assert_eq!(max(&v), 5.0);
    }
}
