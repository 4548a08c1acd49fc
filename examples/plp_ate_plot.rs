//! The figure of docs/guide/point-line-plane.md: the SE(3)-aligned ATE of
//! each seed of `synth-plp` rooms, per measurement set, with its median.
//!
//! ```text
//! cargo run --release --features solve --example plp_ate_plot -- OUT.svg points.txt points,lines.txt ...
//! ```
//!
//! Each input holds one line per seed, `ATE_SE3 ATE_SIM3 ROTATION` (the
//! loop of the guide writes them); its name without `.txt` labels its
//! column.

use std::path::Path;

use plotters::prelude::*;

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let (output, inputs) = args
        .split_first()
        .ok_or("usage: plp_ate_plot OUT.svg SET.txt...")?;
    let mut sets = Vec::new();
    for input in inputs {
        let text = std::fs::read_to_string(input)?;
        let ates = text
            .lines()
            .map(|l| {
                l.split_whitespace()
                    .next()
                    .unwrap_or_default()
                    .parse::<f64>()
            })
            .collect::<Result<Vec<f64>, _>>()?;
        let label = Path::new(input)
            .file_stem()
            .and_then(|s| s.to_str())
            .unwrap_or_default()
            .replace(',', " + ");
        sets.push((label, ates));
    }
    let top = sets
        .iter()
        .flat_map(|(_, a)| a.iter().copied())
        .fold(0.0, f64::max)
        * 1.1;
    let mut svg = String::new();
    {
        let root = SVGBackend::with_string(&mut svg, (720, 440)).into_drawing_area();
        root.fill(&WHITE)?;
        let mut chart = ChartBuilder::on(&root)
            .caption(
                "synth-plp rooms: SE(3)-aligned ATE per seed",
                ("sans-serif", 18),
            )
            .margin(12)
            .x_label_area_size(36)
            .y_label_area_size(60)
            .build_cartesian_2d(-0.5..sets.len() as f64 - 0.5, 0.0..top)?;
        let labels: Vec<String> = sets.iter().map(|(l, _)| l.clone()).collect();
        chart
            .configure_mesh()
            .disable_x_mesh()
            .x_labels(sets.len())
            .x_label_formatter(&|x| {
                let k = x.round();
                if (x - k).abs() < 1e-6 && k >= 0.0 {
                    labels.get(k as usize).cloned().unwrap_or_default()
                } else {
                    String::new()
                }
            })
            .y_desc("ATE (m)")
            .draw()?;
        for (k, (_, ates)) in sets.iter().enumerate() {
            let n = ates.len().max(1) as f64;
            chart.draw_series(ates.iter().enumerate().map(|(i, a)| {
                // Spread the seeds across the column so that they do not overlap.
                let x = k as f64 + 0.5 * (i as f64 / n - 0.5);
                Circle::new((x, *a), 3, BLUE.filled())
            }))?;
            let mut sorted = ates.clone();
            sorted.sort_by(f64::total_cmp);
            if !sorted.is_empty() {
                let median = (sorted[(sorted.len() - 1) / 2] + sorted[sorted.len() / 2]) / 2.0;
                let (a, b) = (k as f64 - 0.35, k as f64 + 0.35);
                chart.draw_series(LineSeries::new(
                    [(a, median), (b, median)],
                    RED.stroke_width(2),
                ))?;
            }
        }
        root.present()?;
    }
    std::fs::write(output, svg)?;
    Ok(())
}
