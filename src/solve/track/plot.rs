//! `track --plot FILE.svg`: the translation and the rotation error of each
//! frame against the truth, a line per measurement set. SVG only, text
//! drawn by the viewer.

use std::path::Path;

use plotters::prelude::*;

use super::Tracked;
use crate::error::CliError;
use crate::synth_plp::Kinds;

/// Width and height of each panel, pixels.
const PANEL: (u32, u32) = (640, 440);
/// A colour per measurement set, in order (then again).
const COLOURS: [RGBColor; 4] = [RED, BLUE, GREEN, MAGENTA];

/// The plot as SVG text (written by the caller to `path`, named in errors).
///
/// # Errors
///
/// [`CliError::Usage`] naming the file when it cannot be drawn.
pub fn svg(path: &Path, runs: &[(Kinds, Vec<Tracked>)]) -> Result<String, CliError> {
    let fail = |e: &dyn std::fmt::Display| {
        CliError::Usage(format!("{}: cannot draw the plot: {e}", path.display()))
    };
    let mut text = String::new();
    {
        let root = SVGBackend::with_string(&mut text, (PANEL.0 * 2, PANEL.1)).into_drawing_area();
        root.fill(&WHITE).map_err(|e| fail(&e))?;
        let areas = root.split_evenly((1, 2));
        panel(
            &areas[0],
            runs,
            "translation error per frame",
            "camera centre error (m)",
            |t| t.translation,
        )
        .map_err(|e| fail(&e))?;
        panel(
            &areas[1],
            runs,
            "rotation error per frame",
            "rotation error (°)",
            |t| t.rotation,
        )
        .map_err(|e| fail(&e))?;
        root.present().map_err(|e| fail(&e))?;
    }
    Ok(text)
}

type Area<'a> = DrawingArea<SVGBackend<'a>, plotters::coord::Shift>;
type DrawResult<'a> =
    Result<(), DrawingAreaErrorKind<<SVGBackend<'a> as DrawingBackend>::ErrorType>>;

/// `error` of every frame, a line per measurement set, from 0.
fn panel<'a>(
    area: &Area<'a>,
    runs: &[(Kinds, Vec<Tracked>)],
    caption: &str,
    axis: &str,
    error: fn(&Tracked) -> f64,
) -> DrawResult<'a> {
    let frames = runs.iter().map(|(_, t)| t.len()).max().unwrap_or(1);
    let top = runs
        .iter()
        .flat_map(|(_, t)| t.iter().map(error))
        .filter(|e| e.is_finite())
        .fold(0.0, f64::max);
    let top = if top > 0.0 { top * 1.08 } else { 1.0 };
    let mut chart = ChartBuilder::on(area)
        .caption(caption, ("sans-serif", 20))
        .margin(12)
        .x_label_area_size(40)
        .y_label_area_size(70)
        .build_cartesian_2d(0..frames.max(2) - 1, 0.0..top)?;
    chart
        .configure_mesh()
        .light_line_style(TRANSPARENT)
        .x_desc("frame")
        .y_desc(axis)
        .draw()?;
    for (k, (kinds, tracked)) in runs.iter().enumerate() {
        let colour = COLOURS[k % COLOURS.len()];
        chart
            .draw_series(LineSeries::new(
                tracked.iter().enumerate().map(|(i, t)| (i, error(t))),
                colour.stroke_width(2),
            ))?
            .label(kinds.to_string())
            .legend(move |(x, y)| PathElement::new([(x, y), (x + 16, y)], colour.stroke_width(2)));
    }
    chart
        .configure_series_labels()
        .position(SeriesLabelPosition::UpperLeft)
        .background_style(WHITE.mix(0.8))
        .border_style(BLACK)
        .draw()
}
