//! `--plot FILE.svg`: the cost at each iteration (log scale; rejected steps
//! marked), and for reprojection problems the histogram of reprojection
//! errors before and after the solve. SVG only, text drawn by the viewer:
//! no font or system library is needed.

use std::path::Path;

use factor_minimizer::Iteration;
use plotters::prelude::*;

use crate::error::CliError;

/// Width and height of each panel, pixels.
const PANEL: (u32, u32) = (640, 440);
/// Bins of the error histogram.
const BINS: usize = 40;

/// The plot as SVG text (written by the caller to `path`, named in errors).
///
/// # Errors
///
/// [`CliError::Usage`] naming the file when it cannot be drawn.
pub fn svg(
    path: &Path,
    initial_cost: f64,
    history: &[Iteration],
    errors: Option<(&[f64], &[f64])>,
) -> Result<String, CliError> {
    let fail = |e: &dyn std::fmt::Display| {
        CliError::Usage(format!("{}: cannot draw the plot: {e}", path.display()))
    };
    let panels = if errors.is_some() { 2 } else { 1 };
    let mut text = String::new();
    {
        let root =
            SVGBackend::with_string(&mut text, (PANEL.0 * panels, PANEL.1)).into_drawing_area();
        root.fill(&WHITE).map_err(|e| fail(&e))?;
        let areas = root.split_evenly((1, panels as usize));
        costs(&areas[0], initial_cost, history).map_err(|e| fail(&e))?;
        if let (Some((before, after)), Some(area)) = (errors, areas.get(1)) {
            histogram(area, before, after).map_err(|e| fail(&e))?;
        }
        root.present().map_err(|e| fail(&e))?;
    }
    Ok(text)
}

type Area<'a> = DrawingArea<SVGBackend<'a>, plotters::coord::Shift>;
type DrawResult<'a> =
    Result<(), DrawingAreaErrorKind<<SVGBackend<'a> as DrawingBackend>::ErrorType>>;

/// Cost after each iteration, iteration 0 being the initial values, on a
/// logarithmic axis (`log10` of the cost plotted, labelled with the cost).
fn costs<'a>(area: &Area<'a>, initial_cost: f64, history: &[Iteration]) -> DrawResult<'a> {
    let points: Vec<(usize, f64, bool)> = std::iter::once((0, initial_cost, true))
        .chain(
            history
                .iter()
                .map(|it| (it.index + 1, it.cost, it.accepted)),
        )
        .filter(|(_, c, _)| c.is_finite() && *c > 0.0)
        .map(|(i, c, a)| (i, c.log10(), a))
        .collect();
    let (low, high) = points
        .iter()
        .fold((f64::INFINITY, f64::NEG_INFINITY), |(l, h), (_, c, _)| {
            (l.min(*c), h.max(*c))
        });
    let pad = ((high - low) * 0.08).max(0.02);
    let (low, high) = if low.is_finite() {
        (low - pad, high + pad)
    } else {
        (0.0, 1.0)
    };
    let mut chart = ChartBuilder::on(area)
        .caption("cost per iteration", ("sans-serif", 20))
        .margin(12)
        .x_label_area_size(40)
        .y_label_area_size(80)
        .build_cartesian_2d(0..points.len().max(2), low..high)?;
    chart
        .configure_mesh()
        .light_line_style(TRANSPARENT)
        .x_desc("iteration (0: initial values)")
        .y_desc("cost ½Σρ(‖r‖²), log scale")
        .y_labels(8)
        .y_label_formatter(&|y| format!("{:.4e}", 10f64.powf(*y)))
        .draw()?;
    let accepted: Vec<(usize, f64)> = points
        .iter()
        .filter(|(_, _, a)| *a)
        .map(|(i, c, _)| (*i, *c))
        .collect();
    chart
        .draw_series(LineSeries::new(
            accepted.iter().copied(),
            BLUE.stroke_width(2),
        ))?
        .label("accepted")
        .legend(|(x, y)| PathElement::new([(x, y), (x + 16, y)], BLUE.stroke_width(2)));
    chart.draw_series(accepted.iter().map(|p| Circle::new(*p, 3, BLUE.filled())))?;
    chart
        .draw_series(
            points
                .iter()
                .filter(|(_, _, a)| !*a)
                .map(|(i, c, _)| Cross::new((*i, *c), 4, RED.stroke_width(2))),
        )?
        .label("rejected step")
        .legend(|(x, y)| Cross::new((x + 8, y), 4, RED.stroke_width(2)));
    chart
        .configure_series_labels()
        .position(SeriesLabelPosition::UpperRight)
        .background_style(WHITE.mix(0.8))
        .border_style(BLACK)
        .draw()
}

/// Histograms of the errors before (red) and after (blue), over
/// `[0, 99th percentile of both]`, larger errors in the last bin.
fn histogram<'a>(area: &Area<'a>, before: &[f64], after: &[f64]) -> DrawResult<'a> {
    let mut all: Vec<f64> = before
        .iter()
        .chain(after)
        .copied()
        .filter(|e| e.is_finite())
        .collect();
    all.sort_by(f64::total_cmp);
    let top = all
        .get((all.len() * 99 / 100).min(all.len().saturating_sub(1)))
        .copied()
        .filter(|t| *t > 0.0)
        .unwrap_or(1.0);
    let width = top / BINS as f64;
    let counts = |errors: &[f64]| {
        let mut bins = vec![0usize; BINS];
        for e in errors.iter().filter(|e| e.is_finite()) {
            bins[((e / width) as usize).min(BINS - 1)] += 1;
        }
        bins
    };
    let (b, a) = (counts(before), counts(after));
    let peak = b.iter().chain(&a).copied().max().unwrap_or(1).max(1);
    let mut chart = ChartBuilder::on(area)
        .caption("reprojection error (px)", ("sans-serif", 20))
        .margin(12)
        .x_label_area_size(40)
        .y_label_area_size(60)
        .build_cartesian_2d(0.0..top, 0..peak + peak / 10 + 1)?;
    chart
        .configure_mesh()
        .light_line_style(TRANSPARENT)
        .x_desc("‖predicted − observed‖, px (last bin: beyond)")
        .y_desc("observations")
        .draw()?;
    for (bins, colour, label) in [(&b, RED, "before"), (&a, BLUE, "after")] {
        chart
            .draw_series(bins.iter().enumerate().map(|(k, n)| {
                let x0 = k as f64 * width;
                Rectangle::new([(x0, 0), (x0 + width, *n)], colour.mix(0.35).filled())
            }))?
            .label(label)
            .legend(move |(x, y)| {
                Rectangle::new([(x, y - 5), (x + 12, y + 5)], colour.mix(0.35).filled())
            });
    }
    chart
        .configure_series_labels()
        .position(SeriesLabelPosition::UpperRight)
        .background_style(WHITE.mix(0.8))
        .border_style(BLACK)
        .draw()
}
