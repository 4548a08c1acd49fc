//! The throughput plot: factors per second against the batch size, one
//! panel per factor, one line per method, both axes logarithmic (log10 of
//! the values plotted, labelled with the values). SVG, text drawn by the
//! viewer: no font or system library is needed.

use std::path::Path;

use plotters::prelude::*;

/// One panel: its title, the batch sizes and each method's name and
/// factors per second at those sizes.
pub struct Panel {
    /// The panel's title.
    pub title: String,
    /// The batch sizes (the x axis).
    pub sizes: Vec<usize>,
    /// Each method's name and throughput (factors/s) at each size.
    pub series: Vec<(String, Vec<f64>)>,
}

/// Width and height of each panel, pixels.
const SIZE: (u32, u32) = (620, 440);

/// Writes `panels` side by side to `path`.
pub fn write(path: &Path, panels: &[Panel]) -> Result<(), String> {
    let fail =
        |e: &dyn std::fmt::Display| format!("{}: cannot write the plot: {e}", path.display());
    let root = SVGBackend::new(path, (SIZE.0 * panels.len() as u32, SIZE.1)).into_drawing_area();
    root.fill(&WHITE).map_err(|e| fail(&e))?;
    for (area, panel) in root.split_evenly((1, panels.len())).iter().zip(panels) {
        draw(area, panel).map_err(|e| fail(&e))?;
    }
    root.present().map_err(|e| fail(&e))
}

type Area<'a> = DrawingArea<SVGBackend<'a>, plotters::coord::Shift>;
type DrawResult<'a> =
    Result<(), DrawingAreaErrorKind<<SVGBackend<'a> as DrawingBackend>::ErrorType>>;

const COLORS: [RGBColor; 6] = [BLACK, BLUE, RED, GREEN, MAGENTA, CYAN];

fn draw<'a>(area: &Area<'a>, panel: &Panel) -> DrawResult<'a> {
    let x = |n: usize| (n as f64).log10();
    let ys = panel
        .series
        .iter()
        .flat_map(|(_, v)| v.iter().map(|y| y.log10()));
    let (low, high) = ys.fold((f64::INFINITY, f64::NEG_INFINITY), |(l, h), y| {
        (l.min(y), h.max(y))
    });
    let (x0, x1) = (
        x(*panel.sizes.first().unwrap_or(&1)),
        x(*panel.sizes.last().unwrap_or(&10)),
    );
    let mut chart = ChartBuilder::on(area)
        .caption(&panel.title, ("sans-serif", 20))
        .margin(12)
        .x_label_area_size(40)
        .y_label_area_size(70)
        // Room below the lines for the legend.
        .build_cartesian_2d(x0 - 0.1..x1 + 0.1, low - 0.5..high + 0.1)?;
    chart
        .configure_mesh()
        .light_line_style(TRANSPARENT)
        .x_desc("factors per batch")
        .y_desc("factors per second")
        .x_label_formatter(&|v| format!("{:.0e}", 10f64.powf(*v)))
        .y_label_formatter(&|v| format!("{:.1e}", 10f64.powf(*v)))
        .draw()?;
    for ((name, values), color) in panel.series.iter().zip(COLORS.iter().cycle()) {
        let points: Vec<(f64, f64)> = panel
            .sizes
            .iter()
            .zip(values)
            .map(|(n, y)| (x(*n), y.log10()))
            .collect();
        chart
            .draw_series(LineSeries::new(
                points.iter().copied(),
                color.stroke_width(2),
            ))?
            .label(name.as_str())
            .legend(move |(x, y)| PathElement::new([(x, y), (x + 16, y)], color.stroke_width(2)));
        chart.draw_series(points.iter().map(|p| Circle::new(*p, 3, color.filled())))?;
    }
    chart
        .configure_series_labels()
        .position(SeriesLabelPosition::LowerRight)
        .background_style(WHITE.mix(0.8))
        .border_style(BLACK)
        .draw()
}
