//! The run-time-against-error figures (`time_vs_error`, `slab_time_vs_error`):
//! a grid of log-log panels of relMSE against CPU seconds, one curve per
//! technique, with a shared legend.

use plotters::prelude::*;
use std::path::Path;

/// One panel: its caption and, per technique, the measured `(seconds, relMSE)`
/// points (those not both positive are left out).
pub struct Panel {
    pub caption: String,
    pub curves: Vec<Vec<(f64, f64)>>,
}

/// The figure's layout and labels.
pub struct Layout<'a> {
    /// Technique names, in the order of each panel's curves.
    pub names: &'a [&'a str],
    pub colors: &'a [RGBColor],
    /// Panels per row.
    pub cols: usize,
    /// Size of one panel in pixels.
    pub panel: (u32, u32),
    /// Horizontal distance between legend entries in pixels.
    pub legend_step: i32,
    pub x_desc: &'a str,
}

/// Writes the panels as an SVG to `path`: a legend row, then the panels row
/// by row; each panel's axes span its points' range (×0.8 … ×1.25 in time,
/// ×0.5 … ×2 in relMSE).
pub fn svg(
    path: &Path,
    layout: &Layout,
    panels: &[Panel],
) -> Result<(), Box<dyn std::error::Error>> {
    let rows = panels.len().div_ceil(layout.cols);
    let (w, h) = layout.panel;
    let root =
        SVGBackend::new(path, (w * layout.cols as u32, h * rows as u32 + 40)).into_drawing_area();
    root.fill(&WHITE)?;
    let (legend, grid) = root.split_vertically(40);
    for (i, name) in layout.names.iter().enumerate() {
        let x = 20 + layout.legend_step * i as i32;
        let color = layout.colors[i];
        legend.draw(&PathElement::new(
            vec![(x, 20), (x + 30, 20)],
            color.stroke_width(3),
        ))?;
        legend.draw(&Text::new(
            name.to_string(),
            (x + 38, 12),
            ("sans-serif", 16),
        ))?;
    }
    for (panel, area) in panels
        .iter()
        .zip(grid.split_evenly((rows, layout.cols)).iter())
    {
        let curves: Vec<Vec<(f64, f64)>> = panel
            .curves
            .iter()
            .map(|c| {
                c.iter()
                    .copied()
                    .filter(|p| p.0 > 0.0 && p.1 > 0.0)
                    .collect()
            })
            .collect();
        let all = curves.iter().flatten();
        let (t0, t1) = all
            .clone()
            .fold((f64::MAX, f64::MIN), |a, p| (a.0.min(p.0), a.1.max(p.0)));
        let (r0, r1) = all.fold((f64::MAX, f64::MIN), |a, p| (a.0.min(p.1), a.1.max(p.1)));
        let mut chart = ChartBuilder::on(area)
            .caption(&panel.caption, ("sans-serif", 14))
            .margin(6)
            .x_label_area_size(28)
            .y_label_area_size(48)
            .build_cartesian_2d(
                (t0 * 0.8..t1 * 1.25).log_scale(),
                (r0 * 0.5..r1 * 2.0).log_scale(),
            )?;
        chart
            .configure_mesh()
            .x_desc(layout.x_desc)
            .y_desc("relMSE")
            .x_labels(4)
            .y_labels(5)
            .x_label_formatter(&|x| format!("{x:.0e}"))
            .y_label_formatter(&|y| format!("{y:.0e}"))
            .label_style(("sans-serif", 10))
            .draw()?;
        for (pts, &color) in curves.iter().zip(layout.colors) {
            chart.draw_series(LineSeries::new(pts.clone(), color.stroke_width(2)))?;
            chart.draw_series(pts.iter().map(|&p| Circle::new(p, 2, color.filled())))?;
        }
    }
    root.present()?;
    Ok(())
}
