//! SVG plots with plotters: coordinates and inputs over time, contact modes per contact.

use std::path::Path;

use plotters::prelude::*;

use crate::files::trajectory_csv::Trajectory;
use crate::report::modes::ContactMode;

/// A plotting failure (plotters' error, as text).
pub type PlotError = String;

const PALETTE: [RGBColor; 10] = [
    RGBColor(31, 119, 180),
    RGBColor(255, 127, 14),
    RGBColor(44, 160, 44),
    RGBColor(214, 39, 40),
    RGBColor(148, 103, 189),
    RGBColor(140, 86, 75),
    RGBColor(227, 119, 194),
    RGBColor(127, 127, 127),
    RGBColor(188, 189, 34),
    RGBColor(23, 190, 207),
];

/// Largest magnitude drawn: plotters computes tick marks from the axis range, and an
/// infinite range (or one too wide to subtract) makes it loop forever.
const PLOT_LIMIT: f64 = 1e100;

/// `v` as drawn: a finite value clamped to ±[`PLOT_LIMIT`]; none for NaN or ±∞.
fn plottable(v: f64) -> Option<f64> {
    v.is_finite().then(|| v.clamp(-PLOT_LIMIT, PLOT_LIMIT))
}

/// The padded axis range of the plottable `values` (never empty, always finite).
fn range(values: impl Iterator<Item = f64>) -> (f64, f64) {
    let (lo, hi) = values
        .filter_map(plottable)
        .fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), v| {
            (a.min(v), b.max(v))
        });
    if !lo.is_finite() {
        return (-1.0, 1.0);
    }
    let pad = ((hi - lo) * 0.05)
        .max(1e-6)
        .max(lo.abs().max(hi.abs()) * 1e-9);
    (lo - pad, hi + pad)
}

/// Draws named series `(label, points)` as lines into an SVG file.
pub fn line_plot(
    path: &Path,
    title: &str,
    x_label: &str,
    y_label: &str,
    series: &[(String, Vec<(f64, f64)>)],
) -> Result<(), PlotError> {
    let e = |e: &dyn std::fmt::Display| e.to_string();
    let height = 420 + 18 * series.len() as u32;
    let root = SVGBackend::new(path, (900, height)).into_drawing_area();
    root.fill(&WHITE).map_err(|x| e(&x))?;
    let (x0, x1) = range(series.iter().flat_map(|s| s.1.iter().map(|p| p.0)));
    let (y0, y1) = range(series.iter().flat_map(|s| s.1.iter().map(|p| p.1)));
    let mut chart = ChartBuilder::on(&root)
        .caption(title, ("sans-serif", 20))
        .margin(12)
        .x_label_area_size(40)
        .y_label_area_size(60)
        .build_cartesian_2d(x0..x1, y0..y1)
        .map_err(|x| e(&x))?;
    chart
        .configure_mesh()
        .x_desc(x_label)
        .y_desc(y_label)
        .draw()
        .map_err(|x| e(&x))?;
    for (i, (label, points)) in series.iter().enumerate() {
        let color = PALETTE[i % PALETTE.len()];
        chart
            .draw_series(LineSeries::new(
                points
                    .iter()
                    .filter_map(|&(x, y)| Some((plottable(x)?, plottable(y)?))),
                color.stroke_width(2),
            ))
            .map_err(|x| e(&x))?
            .label(label.as_str())
            .legend(move |(x, y)| {
                PathElement::new(vec![(x, y), (x + 18, y)], color.stroke_width(2))
            });
    }
    legend_and_present(&mut chart, &root)
}

/// Draws the series' legend in the upper right corner and writes the SVG: the last step of
/// every line chart vito draws (here and in the studies).
pub(crate) fn legend_and_present<'a, CT: plotters::coord::CoordTranslate>(
    chart: &mut ChartContext<'a, SVGBackend<'a>, CT>,
    root: &DrawingArea<SVGBackend<'a>, plotters::coord::Shift>,
) -> Result<(), PlotError> {
    let e = |e: &dyn std::fmt::Display| e.to_string();
    chart
        .configure_series_labels()
        .background_style(WHITE.mix(0.8))
        .border_style(BLACK)
        .position(SeriesLabelPosition::UpperRight)
        .draw()
        .map_err(|x| e(&x))?;
    root.present().map_err(|x| e(&x))
}

/// Coordinates q_k over time, one line per coordinate.
pub fn coordinates_svg(path: &Path, s: &Trajectory<'_>, time_unit: &str) -> Result<(), PlotError> {
    let series: Vec<(String, Vec<(f64, f64)>)> = s
        .coordinate_names
        .iter()
        .enumerate()
        .map(|(j, name)| {
            (
                name.clone(),
                s.times.iter().zip(s.q).map(|(&t, q)| (t, q[j])).collect(),
            )
        })
        .collect();
    line_plot(
        path,
        "coordinates",
        &format!("time [{time_unit}]"),
        "q [m or rad]",
        &series,
    )
}

/// Inputs u_k over time, held constant over each interval (a staircase).
pub fn inputs_svg(path: &Path, s: &Trajectory<'_>, time_unit: &str) -> Result<(), PlotError> {
    let series: Vec<(String, Vec<(f64, f64)>)> = s
        .input_names
        .iter()
        .enumerate()
        .map(|(j, name)| {
            let mut points = Vec::new();
            for (k, u) in s.u.iter().enumerate() {
                if let (Some(&t0), Some(&t1)) = (s.times.get(k), s.times.get(k + 1)) {
                    points.push((t0, u[j]));
                    points.push((t1, u[j]));
                }
            }
            (name.clone(), points)
        })
        .collect();
    line_plot(
        path,
        "inputs",
        &format!("time [{time_unit}]"),
        "u [N or N·m]",
        &series,
    )
}

/// Colour of a mode bar.
fn mode_color(mode: ContactMode) -> RGBColor {
    match mode {
        ContactMode::Flight => RGBColor(235, 235, 235),
        ContactMode::Stick => RGBColor(31, 119, 180),
        ContactMode::Slide => RGBColor(255, 127, 14),
    }
}

/// Contact-mode sequence: one row per contact, one bar per interval coloured by mode.
pub fn contact_modes_svg(
    path: &Path,
    s: &Trajectory<'_>,
    modes: &[Vec<ContactMode>],
    time_unit: &str,
) -> Result<(), PlotError> {
    let e = |e: &dyn std::fmt::Display| e.to_string();
    let nc = s.contact_names.len();
    let height = 140 + 40 * nc.max(1) as u32;
    let root = SVGBackend::new(path, (900, height)).into_drawing_area();
    root.fill(&WHITE).map_err(|x| e(&x))?;
    let t_end = s
        .times
        .last()
        .and_then(|&t| plottable(t))
        .unwrap_or(1.0)
        .max(1e-9);
    let mut chart = ChartBuilder::on(&root)
        .caption(
            "contact modes (grey: flight, blue: stick, orange: slide)",
            ("sans-serif", 18),
        )
        .margin(12)
        .x_label_area_size(40)
        .y_label_area_size(160)
        .build_cartesian_2d(0.0..t_end, 0.0..nc.max(1) as f64)
        .map_err(|x| e(&x))?;
    let names = s.contact_names.to_vec();
    chart
        .configure_mesh()
        .disable_mesh()
        .x_desc(format!("time [{time_unit}]"))
        .y_labels(nc.max(1) * 2 + 1)
        .y_label_formatter(&|y: &f64| {
            let row = y.floor() as usize;
            let frac = y - y.floor();
            if (frac - 0.5).abs() < 1e-6 && row < names.len() {
                names[nc - 1 - row].clone()
            } else {
                String::new()
            }
        })
        .draw()
        .map_err(|x| e(&x))?;
    for (k, row) in modes.iter().enumerate() {
        let (Some(t0), Some(t1)) = (
            s.times.get(k).and_then(|&t| plottable(t)),
            s.times.get(k + 1).and_then(|&t| plottable(t)),
        ) else {
            continue;
        };
        for (i, &mode) in row.iter().enumerate() {
            let y = (nc - 1 - i) as f64;
            chart
                .draw_series(std::iter::once(Rectangle::new(
                    [(t0, y + 0.15), (t1, y + 0.85)],
                    mode_color(mode).filled(),
                )))
                .map_err(|x| e(&x))?;
        }
    }
    root.present().map_err(|x| e(&x))?;
    Ok(())
}
