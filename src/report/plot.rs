//! SVG plots with plotters: coordinates and inputs over time, contact modes per contact.

use std::path::Path;

use plotters::coord::ranged1d::AsRangedCoord;
use plotters::prelude::*;
use plotters_backend::DrawingErrorKind;

use crate::files::trajectory_csv::Trajectory;
use crate::report::modes::ContactMode;
use crate::transcription::GridLevel;

/// Why a plot was not written.
#[derive(Debug, thiserror::Error)]
pub enum PlotError {
    /// The file could not be written (a full disk, a file-size limit, …).
    #[error("{0}")]
    Io(#[from] std::io::Error),
    /// plotters could not draw it (its message).
    #[error("{0}")]
    Draw(String),
}

impl From<DrawingAreaErrorKind<std::io::Error>> for PlotError {
    /// The SVG backend's error is the writing of its file; plotters' own (layout, fonts) is
    /// its message.
    fn from(e: DrawingAreaErrorKind<std::io::Error>) -> Self {
        match e {
            DrawingAreaErrorKind::BackendError(DrawingErrorKind::DrawingError(io)) => {
                PlotError::Io(io)
            }
            other => PlotError::Draw(other.to_string()),
        }
    }
}

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

/// A tick's label on an axis spanning `span`: as many decimals as the span needs (none on an
/// axis of knots), in scientific notation on a span below 1e-3 or values from 1e5 (a slack
/// of 0 to 1e-6 reads "2.0e-7", not "0.0").
fn tick_label(value: f64, span: f64, largest: f64) -> String {
    if value == 0.0 {
        return "0".to_owned();
    }
    if span < 1e-3 || largest >= 1e5 {
        return format!("{value:.1e}");
    }
    let decimals = (1.0 - span.log10().floor()).clamp(0.0, 6.0) as usize;
    format!("{value:.decimals$}")
}

/// Draws named series `(label, points)` as lines into an SVG file (one panel, its legend
/// beside it).
pub fn line_plot(
    path: &Path,
    title: &str,
    x_label: &str,
    y_label: &str,
    series: &[(String, Vec<(f64, f64)>)],
) -> Result<(), PlotError> {
    panel_plot(
        path,
        x_label,
        &[Panel {
            title: title.to_owned(),
            y_label: y_label.to_owned(),
            series: series.to_vec(),
        }],
    )
}

/// A study chart's drawing area and its chart over the axes `X` × `Y`.
pub(crate) type StudyChart<'a, X, Y> = (
    DrawingArea<SVGBackend<'a>, plotters::coord::Shift>,
    ChartContext<'a, SVGBackend<'a>, Cartesian2d<X, Y>>,
);

/// The studies' line chart: an 800 × 480 SVG at `path` filled white, its caption and axes
/// over `x` and `y`. The caller draws the mesh and the series, then
/// [`legend_and_present`] with the drawing area returned beside the chart.
pub(crate) fn study_chart<'a, X: AsRangedCoord, Y: AsRangedCoord>(
    path: &'a Path,
    title: &str,
    x: X,
    y: Y,
) -> Result<StudyChart<'a, X::CoordDescType, Y::CoordDescType>, PlotError> {
    let root = SVGBackend::new(path, (800, 480)).into_drawing_area();
    root.fill(&WHITE)?;
    let chart = ChartBuilder::on(&root)
        .caption(title, ("sans-serif", 20))
        .margin(12)
        .x_label_area_size(40)
        .y_label_area_size(70)
        .build_cartesian_2d(x, y)?;
    Ok((root, chart))
}

/// Draws the series' legend in the upper right corner and writes the SVG: the last step of
/// the studies' line charts (the plots here put their legends beside the plot instead).
pub(crate) fn legend_and_present<'a, CT: plotters::coord::CoordTranslate>(
    chart: &mut ChartContext<'a, SVGBackend<'a>, CT>,
    root: &DrawingArea<SVGBackend<'a>, plotters::coord::Shift>,
) -> Result<(), PlotError> {
    chart
        .configure_series_labels()
        .background_style(WHITE.mix(0.8))
        .border_style(BLACK)
        .position(SeriesLabelPosition::UpperRight)
        .draw()?;
    Ok(root.present()?)
}

/// One panel of a small-multiples figure: its title, its y-axis label and its series.
pub struct Panel {
    /// Title, e.g. `base position [m]`.
    pub title: String,
    /// Y-axis label (the unit).
    pub y_label: String,
    /// Named series `(label, points)`.
    pub series: Vec<(String, Vec<(f64, f64)>)>,
}

/// Figure width, and where each panel's legend column starts: the legend sits beside the
/// plotting area, never on it.
const FIGURE_WIDTH: u32 = 900;
/// X at which the legend column starts.
pub const LEGEND_X: u32 = 700;
const LEGEND_ROW: u32 = 18;

/// Draws `panels` stacked, one chart each, sharing the time axis label, into an SVG file;
/// each panel's legend is drawn in a column to the right of its plotting area.
pub fn panel_plot(path: &Path, x_label: &str, panels: &[Panel]) -> Result<(), PlotError> {
    let heights: Vec<u32> = panels
        .iter()
        .map(|p| (70 + LEGEND_ROW * p.series.len() as u32).max(230))
        .collect();
    let height = heights.iter().sum::<u32>().max(1);
    let root = SVGBackend::new(path, (FIGURE_WIDTH, height)).into_drawing_area();
    root.fill(&WHITE)?;
    let (x0, x1) = range(
        panels
            .iter()
            .flat_map(|p| p.series.iter().flat_map(|s| s.1.iter().map(|p| p.0))),
    );
    let mut rest = root.clone();
    for (panel, &h) in panels.iter().zip(&heights) {
        let (area, below) = rest.split_vertically(h);
        rest = below;
        let (plot_area, legend_area) = area.split_horizontally(LEGEND_X);
        let (y0, y1) = range(panel.series.iter().flat_map(|s| s.1.iter().map(|p| p.1)));
        let mut chart = ChartBuilder::on(&plot_area)
            .caption(&panel.title, ("sans-serif", 17))
            .margin(10)
            .x_label_area_size(36)
            .y_label_area_size(64)
            .build_cartesian_2d(x0..x1, y0..y1)?;
        let x_label_of = |v: &f64| tick_label(*v, x1 - x0, x0.abs().max(x1.abs()));
        let y_label_of = |v: &f64| tick_label(*v, y1 - y0, y0.abs().max(y1.abs()));
        chart
            .configure_mesh()
            .x_desc(x_label)
            .y_desc(panel.y_label.as_str())
            .x_label_formatter(&x_label_of)
            .y_label_formatter(&y_label_of)
            .draw()?;
        for (i, (label, points)) in panel.series.iter().enumerate() {
            let color = PALETTE[i % PALETTE.len()];
            chart.draw_series(LineSeries::new(
                points
                    .iter()
                    .filter_map(|&(x, y)| Some((plottable(x)?, plottable(y)?))),
                color.stroke_width(2),
            ))?;
            let y = 40 + LEGEND_ROW as i32 * i as i32;
            legend_area.draw(&PathElement::new(
                vec![(8, y), (28, y)],
                color.stroke_width(2),
            ))?;
            legend_area.draw(&Text::new(
                label.clone(),
                (34, y - 7),
                ("sans-serif", 13).into_font(),
            ))?;
        }
    }
    Ok(root.present()?)
}

/// Coordinates q_k over time as small multiples: `panels[j]` names the panel of coordinate
/// j (its group and unit, e.g. `base position [m]`, `front_left_hip [rad]`), panels in the
/// order they first appear, `units[j]` its unit.
pub fn coordinates_svg(
    path: &Path,
    s: &Trajectory<'_>,
    time_unit: &str,
    panels: &[String],
    units: &[String],
) -> Result<(), PlotError> {
    let mut out: Vec<Panel> = Vec::new();
    for (j, name) in s.coordinate_names.iter().enumerate() {
        let title = panels.get(j).cloned().unwrap_or_else(|| name.clone());
        let series = (
            name.clone(),
            s.times.iter().zip(s.q).map(|(&t, q)| (t, q[j])).collect(),
        );
        match out.iter_mut().find(|p| p.title == title) {
            Some(panel) => panel.series.push(series),
            None => out.push(Panel {
                title,
                y_label: format!("q [{}]", units.get(j).map_or("", String::as_str)),
                series: vec![series],
            }),
        }
    }
    panel_plot(path, &format!("time [{time_unit}]"), &out)
}

/// Inputs u_k over time, held constant over each interval (a staircase), one panel per
/// unit (`units[j]` is input j's).
pub fn inputs_svg(
    path: &Path,
    s: &Trajectory<'_>,
    time_unit: &str,
    units: &[String],
) -> Result<(), PlotError> {
    let mut out: Vec<Panel> = Vec::new();
    for (j, name) in s.input_names.iter().enumerate() {
        let mut points = Vec::new();
        for (k, u) in s.u.iter().enumerate() {
            if let (Some(&t0), Some(&t1)) = (s.times.get(k), s.times.get(k + 1)) {
                points.push((t0, u[j]));
                points.push((t1, u[j]));
            }
        }
        let unit = units.get(j).map_or("", String::as_str);
        let title = format!("inputs [{unit}]");
        match out.iter_mut().find(|p| p.title == title) {
            Some(panel) => panel.series.push((name.clone(), points)),
            None => out.push(Panel {
                title,
                y_label: format!("u [{unit}]"),
                series: vec![(name.clone(), points)],
            }),
        }
    }
    panel_plot(path, &format!("time [{time_unit}]"), &out)
}

/// A grid continuation's levels against their knots, one panel each for the objective, the
/// largest slack, the iterations, the wall time and how far q moved from the level below:
/// how the answer and its cost change as the grid refines.
pub fn levels_svg(path: &Path, levels: &[GridLevel]) -> Result<(), PlotError> {
    let series = |label: &str, value: &dyn Fn(&GridLevel) -> Option<f64>| {
        let points = levels
            .iter()
            .filter_map(|l| Some((l.knots as f64, value(l)?)))
            .collect();
        vec![(label.to_owned(), points)]
    };
    let panel = |title: &str, y_label: &str, series| Panel {
        title: title.to_owned(),
        y_label: y_label.to_owned(),
        series,
    };
    let panels = [
        panel(
            "objective per level",
            "objective",
            series("objective", &|l| Some(l.objective)),
        ),
        panel(
            "largest slack",
            "max slack",
            series(
                &format!(
                    "max slack (at most {:.1e})",
                    levels.iter().map(|l| l.max_slack).fold(0.0, f64::max)
                ),
                &|l| Some(l.max_slack),
            ),
        ),
        panel(
            "Ipopt iterations",
            "iterations",
            series("iterations", &|l| Some(l.iterations as f64)),
        ),
        panel(
            "wall time [s]",
            "time [s]",
            series("wall time", &|l| Some(l.wall_time_s)),
        ),
        panel(
            "largest |q − q of the level below| at its knots",
            "|Δq| [m or rad]",
            series("|Δq|", &|l| l.max_q_difference),
        ),
    ];
    panel_plot(path, "knots", &panels)
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
    let nc = s.contact_names.len();
    let height = 140 + 40 * nc.max(1) as u32;
    let root = SVGBackend::new(path, (900, height)).into_drawing_area();
    root.fill(&WHITE)?;
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
        .build_cartesian_2d(0.0..t_end, 0.0..nc.max(1) as f64)?;
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
        .draw()?;
    for (k, row) in modes.iter().enumerate() {
        let (Some(t0), Some(t1)) = (
            s.times.get(k).and_then(|&t| plottable(t)),
            s.times.get(k + 1).and_then(|&t| plottable(t)),
        ) else {
            continue;
        };
        for (i, &mode) in row.iter().enumerate() {
            let y = (nc - 1 - i) as f64;
            chart.draw_series(std::iter::once(Rectangle::new(
                [(t0, y + 0.15), (t1, y + 0.85)],
                mode_color(mode).filled(),
            )))?;
        }
    }
    root.present()?;
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Ticks read as numbers at every scale: knots without decimals, an objective near 6
    /// with one, a slack of zero to 1e-6 in scientific notation (not "0.0" at every tick),
    /// large values too.
    #[test]
    fn tick_labels_have_the_digits_their_axis_needs() {
        assert_eq!(tick_label(40.0, 140.0, 161.0), "40");
        assert_eq!(tick_label(6.3, 1.1, 6.9), "6.3");
        assert_eq!(tick_label(6.05, 0.2, 6.1), "6.05");
        assert_eq!(tick_label(2e-7, 2e-6, 1e-6), "2.0e-7");
        assert_eq!(tick_label(-4e-7, 2e-6, 1e-6), "-4.0e-7");
        assert_eq!(tick_label(0.0, 2e-6, 1e-6), "0");
        assert_eq!(tick_label(250000.0, 1e5, 3e5), "2.5e5");
    }

    /// Numbers of attribute `name` in an SVG element's text (`x="12"` → 12).
    fn attribute(element: &str, name: &str) -> Option<f64> {
        let start = element.find(&format!(" {name}=\""))? + name.len() + 3;
        element[start..].split('"').next()?.parse().ok()
    }

    /// LittleDog's 18 coordinates: base position, base orientation, then one panel per leg,
    /// each titled from the model; every legend entry lies right of every plotted point.
    #[test]
    fn littledog_coordinates_are_small_multiples_with_legends_beside_the_plots() {
        let root = Path::new(env!("CARGO_MANIFEST_DIR"));
        let problem =
            crate::problem::load(&root.join("problems/littledog_step.toml"), &[]).unwrap();
        let csv =
            std::fs::read_to_string(root.join("results/motion/littledog_step/trajectory.csv"))
                .unwrap();
        let recorded =
            crate::files::trajectory_csv::read_trajectory(&csv, &problem.robot.coordinates, &[])
                .unwrap();
        let v = vec![vec![0.0; problem.robot.coordinates.len()]; recorded.times.len()];
        let t = Trajectory {
            times: &recorded.times,
            coordinate_names: &problem.robot.coordinates,
            q: &recorded.q,
            v: &v,
            input_names: &[],
            u: &[],
            contact_names: &[],
            friction_directions: 0,
            normal_impulse: &[],
            friction_impulse: &[],
            world_impulse: &[],
            signed_distance: &[],
            contact_positions: &[],
            slack: &[],
        };
        let units = crate::report::column_units(&problem.robot, &problem.units);
        let panels = crate::report::coordinate_panels(&problem, &units.coordinates);
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("coordinates.svg");
        coordinates_svg(&path, &t, "s", &panels, &units.coordinates).unwrap();
        let svg = std::fs::read_to_string(&path).unwrap();

        let texts: Vec<(f64, String)> = svg
            .split("<text")
            .skip(1)
            .map(|e| {
                let x = attribute(e, "x").unwrap_or(f64::NAN);
                let body = e[e.find('>').unwrap() + 1..e.find("</text>").unwrap()]
                    .trim()
                    .to_owned();
                (x, body)
            })
            .collect();
        let titles: Vec<&str> = texts
            .iter()
            .map(|(_, s)| s.as_str())
            .filter(|s| s.starts_with("base ") || s.ends_with("_hip [rad]"))
            .collect();
        assert_eq!(
            titles,
            [
                "base position [m]",
                "base orientation [rad]",
                "front_left_hip [rad]",
                "front_right_hip [rad]",
                "back_left_hip [rad]",
                "back_right_hip [rad]",
            ]
        );
        // Legend entries (the coordinate names) beside the plots, every plotted point left.
        let legend_x: Vec<f64> = texts
            .iter()
            .filter(|(_, s)| problem.robot.coordinates.contains(s))
            .map(|(x, _)| *x)
            .collect();
        assert_eq!(legend_x.len(), 18);
        let legend_left = legend_x.iter().copied().fold(f64::MAX, f64::min);
        let plotted_right = svg
            .split("<polyline")
            .skip(1)
            .flat_map(|e| {
                let start = e.find("points=\"").unwrap() + 8;
                let points = e[start..].split('"').next().unwrap().to_owned();
                let xs: Vec<f64> = points
                    .split_whitespace()
                    .filter_map(|p| p.split(',').next()?.parse::<f64>().ok())
                    .collect();
                // Curves only: a legend's sample line has two points.
                if xs.len() > 2 { xs } else { Vec::new() }
            })
            .fold(f64::MIN, f64::max);
        assert!(plotted_right > 500.0, "{plotted_right}");
        assert!(
            legend_left > plotted_right + 20.0,
            "legend at x {legend_left}, curves reach x {plotted_right}"
        );
    }
}
