//! The SVG of one metric over the grid: the first axis along x (its values when they are
//! numbers, else their positions), one line per combination of the other axes' values
//! through its solved points only. A point that did not solve (relaxed, not solved, timed
//! out, interrupted, failed, pending) is a marker of its own class, never joined to a line;
//! one without a value sits on a strip below the plot. Each marker is an SVG element with
//! `class="marker <class>"`, and the legend lists every class drawn.

use std::fmt::Write;
use std::path::Path;

use crate::sweep::{Row, RunStatus, SweepError, Table};
use crate::transcription::SolveVerdict;

/// How a grid point's result is drawn.
#[derive(Debug, Clone, Copy, PartialEq, Eq, PartialOrd, Ord)]
pub enum PointClass {
    /// Finished and solved: on its series' line.
    Solved,
    /// Finished at Ipopt's optimum with the contact model relaxed (`relaxed_contact`).
    Relaxed,
    /// Finished without an optimum (a failure status, an iteration limit).
    NotSolved,
    /// Stopped at the time limit.
    Timeout,
    /// Stopped by a signal.
    Interrupted,
    /// Ended without a summary.
    Failed,
    /// Not run.
    Pending,
}

impl PointClass {
    /// Every class, in legend order.
    pub const ALL: [PointClass; 7] = [
        PointClass::Solved,
        PointClass::Relaxed,
        PointClass::NotSolved,
        PointClass::Timeout,
        PointClass::Interrupted,
        PointClass::Failed,
        PointClass::Pending,
    ];

    /// The class of a row.
    pub fn of(row: &Row) -> PointClass {
        match row.status {
            RunStatus::Finished => {
                match row
                    .solver_status
                    .as_deref()
                    .and_then(SolveVerdict::from_name)
                {
                    Some(SolveVerdict::Solved(_)) => PointClass::Solved,
                    Some(SolveVerdict::RelaxedContact) => PointClass::Relaxed,
                    _ => PointClass::NotSolved,
                }
            }
            RunStatus::Timeout => PointClass::Timeout,
            RunStatus::Interrupted => PointClass::Interrupted,
            RunStatus::Failed => PointClass::Failed,
            RunStatus::Pending => PointClass::Pending,
        }
    }

    /// The SVG class name (`solved`, `relaxed`, `not_solved`, `timeout`, `interrupted`,
    /// `failed`, `pending`).
    pub fn name(self) -> &'static str {
        match self {
            PointClass::Solved => "solved",
            PointClass::Relaxed => "relaxed",
            PointClass::NotSolved => "not_solved",
            PointClass::Timeout => "timeout",
            PointClass::Interrupted => "interrupted",
            PointClass::Failed => "failed",
            PointClass::Pending => "pending",
        }
    }

    /// The legend's words.
    fn legend(self) -> &'static str {
        match self {
            PointClass::Solved => "solved (joined per line)",
            PointClass::Relaxed => "relaxed_contact: not solved",
            PointClass::NotSolved => "not solved (Ipopt failed)",
            PointClass::Timeout => "timeout: stopped at the time limit",
            PointClass::Interrupted => "interrupted: stopped by a signal",
            PointClass::Failed => "failed: no result",
            PointClass::Pending => "pending: not run",
        }
    }

    /// The marker's colour.
    fn colour(self) -> &'static str {
        match self {
            PointClass::Solved => "#2a6fb0",
            PointClass::Relaxed => "#b35c00",
            PointClass::NotSolved | PointClass::Failed => "#c0392b",
            PointClass::Timeout => "#7b3fa0",
            PointClass::Interrupted | PointClass::Pending => "#777777",
        }
    }

    /// The marker centred at (x, y): a filled circle for a solved point (in its line's
    /// colour), a hollow diamond, a cross, a triangle or a square for the others.
    fn marker(self, x: f64, y: f64, line_colour: &str) -> String {
        let class = self.name();
        let c = self.colour();
        match self {
            PointClass::Solved => format!(
                r#"<circle class="marker {class}" cx="{x:.1}" cy="{y:.1}" r="3.5" fill="{line_colour}"/>"#
            ),
            PointClass::Relaxed => format!(
                r#"<path class="marker {class}" d="M{x:.1},{:.1} L{:.1},{y:.1} L{x:.1},{:.1} L{:.1},{y:.1} Z" fill="white" stroke="{c}" stroke-width="2"/>"#,
                y - 6.0,
                x + 6.0,
                y + 6.0,
                x - 6.0
            ),
            PointClass::NotSolved | PointClass::Failed => format!(
                r#"<path class="marker {class}" d="M{:.1},{:.1} L{:.1},{:.1} M{:.1},{:.1} L{:.1},{:.1}" stroke="{c}" stroke-width="2.5"/>"#,
                x - 5.0,
                y - 5.0,
                x + 5.0,
                y + 5.0,
                x - 5.0,
                y + 5.0,
                x + 5.0,
                y - 5.0
            ),
            PointClass::Timeout | PointClass::Interrupted => format!(
                r#"<path class="marker {class}" d="M{x:.1},{:.1} L{:.1},{:.1} L{:.1},{:.1} Z" fill="white" stroke="{c}" stroke-width="2"/>"#,
                y - 6.0,
                x + 6.0,
                y + 5.0,
                x - 6.0,
                y + 5.0
            ),
            PointClass::Pending => format!(
                r#"<rect class="marker {class}" x="{:.1}" y="{:.1}" width="9" height="9" fill="white" stroke="{c}" stroke-width="1.5"/>"#,
                x - 4.5,
                y - 4.5
            ),
        }
    }
}

/// One combination of the other axes' values: its solved points (the line) and the rest.
struct Series {
    label: String,
    /// (x, y) of solved points, sorted by x.
    line: Vec<(f64, f64)>,
    /// (x, value if any, class) of every other point.
    others: Vec<(f64, Option<f64>, PointClass)>,
    /// `(x, lowest, highest)` objective of the starts that solved, at solved points with
    /// several (`--starts K`; only when the metric is the objective).
    band: Vec<(f64, f64, f64)>,
}

/// Line colours, one per series.
const PALETTE: [&str; 8] = [
    "#2a6fb0", "#2e8b57", "#8c564b", "#1f9ea8", "#5b5ea6", "#9a6a00", "#d1477a", "#4d4d4d",
];

/// What the plot draws, gathered from the table.
struct PlotData {
    series: Vec<Series>,
    x_label: String,
    /// Rows with a value (solved or not).
    plotted: usize,
}

fn plot_data(table: &Table, metric: &str) -> PlotData {
    let first = &table.grid.axes[0];
    let numeric: Option<Vec<f64>> = first.values.iter().map(|v| v.parse().ok()).collect();
    let x_of = |value: &str| -> f64 {
        let position = first.values.iter().position(|v| v == value).unwrap_or(0);
        numeric.as_ref().map_or(position as f64, |xs| xs[position])
    };
    let mut series: Vec<Series> = Vec::new();
    let mut plotted = 0;
    for row in &table.rows {
        let y = row.metric(metric).filter(|y| y.is_finite());
        plotted += usize::from(y.is_some());
        let label: Vec<String> = row.values[1..]
            .iter()
            .map(|(k, v)| format!("{k} = {v}"))
            .collect();
        let label = if label.is_empty() {
            metric.to_owned()
        } else {
            label.join(", ")
        };
        let index = match series.iter().position(|s| s.label == label) {
            Some(i) => i,
            None => {
                series.push(Series {
                    label,
                    line: Vec::new(),
                    others: Vec::new(),
                    band: Vec::new(),
                });
                series.len() - 1
            }
        };
        let x = x_of(&row.values[0].1);
        let starts = &row.start_objectives;
        if metric == "objective" && starts.len() > 1 && PointClass::of(row) == PointClass::Solved {
            let (lo, hi) = starts
                .iter()
                .fold((f64::MAX, f64::MIN), |(a, b), &v| (a.min(v), b.max(v)));
            if lo.is_finite() && hi.is_finite() {
                series[index].band.push((x, lo, hi));
            }
        }
        match (PointClass::of(row), y) {
            (PointClass::Solved, Some(y)) => series[index].line.push((x, y)),
            // A solved run without this metric has nothing to draw.
            (PointClass::Solved, None) => {}
            (class, y) => series[index].others.push((x, y, class)),
        }
    }
    for s in &mut series {
        s.line.sort_by(|a, b| a.0.total_cmp(&b.0));
        s.band.sort_by(|a, b| a.0.total_cmp(&b.0));
    }
    let x_label = if numeric.is_some() {
        first.key.clone()
    } else {
        format!("{} (position in the list)", first.key)
    };
    PlotData {
        series,
        x_label,
        plotted,
    }
}

/// A round step of about a fifth of `span`.
fn tick_step(span: f64) -> f64 {
    let raw = (span / 5.0).max(f64::MIN_POSITIVE);
    let e = 10f64.powf(raw.log10().floor());
    [1.0, 2.0, 5.0, 10.0]
        .into_iter()
        .map(|m| m * e)
        .find(|&s| s >= raw)
        .unwrap_or(10.0 * e)
}

/// `[lo, hi]` of `values` padded by 5 % (a unit around a single value).
fn padded(values: impl Iterator<Item = f64>) -> (f64, f64) {
    let (lo, hi) = values.fold((f64::MAX, f64::MIN), |(a, b), v| (a.min(v), b.max(v)));
    if lo > hi {
        return (0.0, 1.0);
    }
    if hi - lo <= 1e-12 * lo.abs().max(hi.abs()).max(1e-300) {
        let d = lo.abs().max(1.0) * 0.5;
        return (lo - d, hi + d);
    }
    let pad = 0.05 * (hi - lo);
    (lo - pad, hi + pad)
}

/// The SVG text of `metric` over the grid of `table`.
pub fn metric_svg_text(table: &Table, metric: &str) -> (String, usize) {
    let data = plot_data(table, metric);
    let metric_label = crate::files::names::xml_escape(metric);
    let (width, plot_w, left, top) = (900.0, 560.0, 80.0, 40.0);
    let plot_h = 300.0;
    // The strip for points without a value, below the plotting area.
    let strip_y = top + plot_h + 22.0;
    let xs = data.series.iter().flat_map(|s| {
        s.line
            .iter()
            .map(|p| p.0)
            .chain(s.others.iter().map(|p| p.0))
    });
    let (x0, x1) = padded(xs);
    let ys = data.series.iter().flat_map(|s| {
        s.line
            .iter()
            .map(|p| p.1)
            .chain(s.others.iter().filter_map(|p| p.1))
            .chain(s.band.iter().flat_map(|b| [b.1, b.2]))
    });
    let (y0, y1) = padded(ys);
    let sx = |x: f64| left + (x - x0) / (x1 - x0) * plot_w;
    let sy = |y: f64| top + (y1 - y) / (y1 - y0) * plot_h;
    let classes: Vec<PointClass> = PointClass::ALL
        .into_iter()
        .filter(|c| {
            data.series.iter().any(|s| {
                (*c == PointClass::Solved && !s.line.is_empty())
                    || s.others.iter().any(|o| o.2 == *c)
            })
        })
        .collect();
    let banded = data.series.iter().any(|s| !s.band.is_empty());
    let legend_rows = data.series.len() + classes.len() + 1 + usize::from(banded);
    let height = (strip_y + 60.0).max(top + 20.0 * legend_rows as f64 + 20.0);
    let mut svg = String::new();
    let _ = writeln!(
        svg,
        r#"<svg xmlns="http://www.w3.org/2000/svg" width="{width:.0}" height="{height:.0}" viewBox="0 0 {width:.0} {height:.0}" font-family="sans-serif" font-size="12">"#
    );
    let _ = writeln!(
        svg,
        r##"<rect width="100%" height="100%" fill="#ffffff"/><text x="{:.1}" y="22" text-anchor="middle" font-size="15">{metric_label} over the sweep of {}</text>"##,
        left + plot_w / 2.0,
        crate::files::names::xml_escape(&table.problem)
    );
    // Axes, grid and ticks.
    let _ = writeln!(
        svg,
        r##"<rect x="{left}" y="{top}" width="{plot_w}" height="{plot_h}" fill="none" stroke="#333"/>"##
    );
    let step = tick_step(y1 - y0);
    let mut y = (y0 / step).ceil() * step;
    while y <= y1 {
        let _ = writeln!(
            svg,
            r##"<line x1="{left}" y1="{0:.1}" x2="{1:.1}" y2="{0:.1}" stroke="#e3e3e3"/><text x="{2:.1}" y="{3:.1}" text-anchor="end">{4}</text>"##,
            sy(y),
            left + plot_w,
            left - 6.0,
            sy(y) + 4.0,
            format_tick(y, step)
        );
        y += step;
    }
    let step = tick_step(x1 - x0);
    let mut x = (x0 / step).ceil() * step;
    while x <= x1 {
        let _ = writeln!(
            svg,
            r##"<line x1="{0:.1}" y1="{top}" x2="{0:.1}" y2="{1:.1}" stroke="#e3e3e3"/><text x="{0:.1}" y="{2:.1}" text-anchor="middle">{3}</text>"##,
            sx(x),
            top + plot_h,
            strip_y + 26.0,
            format_tick(x, step)
        );
        x += step;
    }
    let _ = writeln!(
        svg,
        r##"<text x="{:.1}" y="{:.1}" text-anchor="middle">{}</text><text transform="translate(18 {:.1}) rotate(-90)" text-anchor="middle">{metric_label}</text>"##,
        left + plot_w / 2.0,
        strip_y + 44.0,
        crate::files::names::xml_escape(&data.x_label),
        top + plot_h / 2.0
    );
    let _ = writeln!(
        svg,
        r##"<text x="{:.1}" y="{:.1}" text-anchor="end" fill="#777">no value</text><line x1="{left}" y1="{strip_y:.1}" x2="{:.1}" y2="{strip_y:.1}" stroke="#bbb" stroke-dasharray="3 3"/>"##,
        left - 6.0,
        strip_y + 4.0,
        left + plot_w
    );
    // The starts' objectives: a shaded band between the lowest and highest at each solved
    // point, and a whisker per point, under the lines and markers.
    for (i, s) in data.series.iter().enumerate() {
        let colour = PALETTE[i % PALETTE.len()];
        if s.band.len() > 1 {
            let upper = s.band.iter().map(|&(x, _, hi)| (x, hi));
            let lower = s.band.iter().rev().map(|&(x, lo, _)| (x, lo));
            let points: Vec<String> = upper
                .chain(lower)
                .map(|(x, y)| format!("{:.1},{:.1}", sx(x), sy(y)))
                .collect();
            let _ = writeln!(
                svg,
                r#"<polygon class="band" points="{}" fill="{colour}" fill-opacity="0.15" stroke="none"/>"#,
                points.join(" ")
            );
        }
        for &(x, lo, hi) in &s.band {
            let _ = writeln!(
                svg,
                r#"<line class="whisker" x1="{0:.1}" y1="{1:.1}" x2="{0:.1}" y2="{2:.1}" stroke="{colour}" stroke-width="1" stroke-opacity="0.7"/>"#,
                sx(x),
                sy(lo),
                sy(hi)
            );
        }
    }
    for (i, s) in data.series.iter().enumerate() {
        let colour = PALETTE[i % PALETTE.len()];
        if s.line.len() > 1 {
            let points: Vec<String> = s
                .line
                .iter()
                .map(|&(x, y)| format!("{:.1},{:.1}", sx(x), sy(y)))
                .collect();
            let _ = writeln!(
                svg,
                r#"<polyline class="line" points="{}" fill="none" stroke="{colour}" stroke-width="1.8"/>"#,
                points.join(" ")
            );
        }
        for &(x, y) in &s.line {
            svg.push_str(&PointClass::Solved.marker(sx(x), sy(y), colour));
            svg.push('\n');
        }
        for &(x, y, class) in &s.others {
            svg.push_str(&class.marker(sx(x), y.map_or(strip_y, sy), colour));
            svg.push('\n');
        }
    }
    // The legend: one row per line, then one per marker class drawn.
    let lx = left + plot_w + 30.0;
    let mut ly = top + 8.0;
    for (i, s) in data.series.iter().enumerate() {
        let colour = PALETTE[i % PALETTE.len()];
        let _ = writeln!(
            svg,
            r#"<g class="legend series"><line x1="{lx:.1}" y1="{ly:.1}" x2="{:.1}" y2="{ly:.1}" stroke="{colour}" stroke-width="2"/><text x="{:.1}" y="{:.1}">{}</text></g>"#,
            lx + 22.0,
            lx + 28.0,
            ly + 4.0,
            crate::files::names::xml_escape(&s.label)
        );
        ly += 20.0;
    }
    if banded {
        let _ = writeln!(
            svg,
            r##"<g class="legend band"><rect x="{lx:.1}" y="{:.1}" width="22" height="10" fill="#555" fill-opacity="0.15"/><text x="{:.1}" y="{:.1}">objectives of the starts that solved</text></g>"##,
            ly - 5.0,
            lx + 28.0,
            ly + 4.0
        );
        ly += 20.0;
    }
    ly += 6.0;
    for class in classes {
        let _ = writeln!(
            svg,
            r#"<g class="legend {}">{}<text x="{:.1}" y="{:.1}">{}</text></g>"#,
            class.name(),
            class
                .marker(lx + 11.0, ly, "#555")
                .replacen("class=\"marker ", "class=\"key ", 1),
            lx + 28.0,
            ly + 4.0,
            class.legend()
        );
        ly += 20.0;
    }
    svg.push_str("</svg>\n");
    (svg, data.plotted)
}

/// A tick label: as few decimals as the step needs.
fn format_tick(v: f64, step: f64) -> String {
    let v = if v.abs() < step * 1e-9 { 0.0 } else { v };
    if v != 0.0 && (v.abs() >= 1e5 || v.abs() < 1e-3) {
        return format!("{v:.2e}");
    }
    let decimals = (-step.log10().floor()).clamp(0.0, 6.0) as usize;
    format!("{v:.decimals$}")
}

/// Draws `metric` (a column such as `objective` or a metric name) over the grid into `path`
/// (written beside and renamed, so a reader never sees half a plot). Returns the number of
/// rows that had a value.
pub fn metric_svg(table: &Table, metric: &str, path: &Path) -> Result<usize, SweepError> {
    let (svg, plotted) = metric_svg_text(table, metric);
    crate::files::output::write_atomic(path, svg.as_bytes()).map_err(|source| SweepError::Io {
        path: path.to_owned(),
        source,
    })?;
    Ok(plotted)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::sweep::{Axis, Grid};

    /// Markers by class, counted in the parsed SVG: `(class, in the plot, in the legend)`.
    fn markers(svg: &str) -> Vec<(String, usize, usize)> {
        let doc = roxmltree::Document::parse(svg).expect("the SVG parses as XML");
        PointClass::ALL
            .iter()
            .map(|c| {
                let count = |kind: &str| {
                    doc.descendants()
                        .filter(|n| {
                            n.attribute("class")
                                .is_some_and(|a| a.split(' ').eq([kind, c.name()]))
                        })
                        .count()
                };
                (c.name().to_owned(), count("marker"), count("key"))
            })
            .collect()
    }

    /// A grid of 2 × 4 points: on the first line three solved points, one relaxed (objective
    /// 130 beside 5.4); on the second one solved, a timeout with its iterate's objective, a
    /// failed run without a value and a point not run. Each unsolved point is a marker of its
    /// class, none on a line: the lines join exactly the solved points.
    #[test]
    fn unsolved_points_have_their_own_markers_and_stay_off_the_lines() {
        let grid = Grid::new(vec![
            Axis::parse("stride=1,2,3,4").unwrap(),
            Axis::parse("mu=0.5,1").unwrap(),
        ])
        .unwrap();
        let mut rows: Vec<Row> = grid
            .points()
            .map(|p| Row::pending(&p, String::new()))
            .collect();
        let mut set = |stride: &str, mu: &str, status: RunStatus, verdict: &str, y: Option<f64>| {
            let row = rows
                .iter_mut()
                .find(|r| r.values[0].1 == stride && r.values[1].1 == mu)
                .unwrap();
            row.status = status;
            row.solver_status = (!verdict.is_empty()).then(|| verdict.to_owned());
            row.objective = y;
        };
        let f = RunStatus::Finished;
        set("1", "0.5", f, "solve_succeeded", Some(5.4));
        set("2", "0.5", f, "solve_succeeded", Some(5.5));
        set("3", "0.5", f, "relaxed_contact", Some(130.0));
        set("4", "0.5", f, "solve_succeeded", Some(5.7));
        set("1", "1", f, "solved_to_acceptable_level", Some(6.0));
        set("2", "1", RunStatus::Timeout, "timeout", Some(9.0));
        set("3", "1", RunStatus::Failed, "", None);
        let table = crate::sweep::table::test_table(grid, rows);
        assert!(!table.all_solved());
        let (svg, plotted) = metric_svg_text(&table, "objective");
        assert_eq!(plotted, 6);
        let expect = |class: &str, plot: usize, legend: usize| (class.to_owned(), plot, legend);
        assert_eq!(
            markers(&svg),
            [
                expect("solved", 4, 1),
                expect("relaxed", 1, 1),
                expect("not_solved", 0, 0),
                expect("timeout", 1, 1),
                expect("interrupted", 0, 0),
                expect("failed", 1, 1),
                expect("pending", 1, 1),
            ]
        );
        // The lines: the first through its three solved points (x = 1, 2, 4), none through
        // the relaxed one at 130; the second line has one solved point, so no line.
        let doc = roxmltree::Document::parse(&svg).unwrap();
        let lines: Vec<usize> = doc
            .descendants()
            .filter(|n| n.attribute("class") == Some("line"))
            .map(|n| n.attribute("points").unwrap().split(' ').count())
            .collect();
        assert_eq!(lines, [3]);
        // The relaxed marker sits above every point of the line (larger objective, smaller
        // SVG y); the failed one on the no-value strip below the plot.
        let y_of = |class: &str| -> Vec<f64> {
            doc.descendants()
                .filter(|n| n.attribute("class") == Some(&format!("marker {class}")[..]))
                .map(|n| match n.attribute("cy") {
                    Some(cy) => cy.parse().unwrap(),
                    None => {
                        let d = n.attribute("d").unwrap();
                        let first = d[1..].split(' ').next().unwrap();
                        first.split(',').nth(1).unwrap().parse::<f64>().unwrap() + 6.0
                    }
                })
                .collect()
        };
        let solved = y_of("solved");
        assert!(y_of("relaxed")[0] < solved.iter().cloned().fold(f64::MAX, f64::min));
        let failed = y_of("failed")[0] - 1.0; // the cross's first corner is 5 px up
        assert!(failed > solved.iter().cloned().fold(f64::MIN, f64::max));
    }

    /// With several starts per point, the objective plot shades the band between each solved
    /// point's lowest and highest start objective and draws its whisker; a relaxed point's
    /// starts are not banded, and a metric other than the objective has no band.
    #[test]
    fn starts_draw_their_band_under_the_line() {
        let grid = Grid::new(vec![Axis::parse("mu=0.2,0.5,0.8").unwrap()]).unwrap();
        let mut rows: Vec<Row> = grid
            .points()
            .map(|p| Row::pending(&p, String::new()))
            .collect();
        let data = [
            ("solve_succeeded", 6.0, vec![6.0, 7.5, 9.0]),
            ("solve_succeeded", 6.5, vec![6.5, 6.6]),
            ("relaxed_contact", 100.0, vec![120.0, 140.0]),
        ];
        for (row, (verdict, objective, starts)) in rows.iter_mut().zip(data) {
            row.status = RunStatus::Finished;
            row.solver_status = Some(verdict.to_owned());
            row.objective = Some(objective);
            row.start_objectives = starts;
        }
        let table = crate::sweep::table::test_table(grid, rows);
        let (svg, _) = metric_svg_text(&table, "objective");
        let doc = roxmltree::Document::parse(&svg).unwrap();
        let of_class = |c: &str| {
            doc.descendants()
                .filter(|n| n.attribute("class") == Some(c))
                .collect::<Vec<_>>()
        };
        let whiskers: Vec<(f64, f64)> = of_class("whisker")
            .iter()
            .map(|n| {
                let y = |a: &str| n.attribute(a).unwrap().parse::<f64>().unwrap();
                (y("y1"), y("y2"))
            })
            .collect();
        assert_eq!(whiskers.len(), 2, "{svg}");
        // 6.0..9.0 spans more of the plot than 6.5..6.6, and both hang below the relaxed marker.
        let length = |w: (f64, f64)| (w.0 - w.1).abs();
        assert!(
            length(whiskers[0]) > 10.0 * length(whiskers[1]),
            "{whiskers:?}"
        );
        let band = of_class("band");
        assert_eq!(band.len(), 1);
        assert_eq!(band[0].attribute("points").unwrap().split(' ').count(), 4);
        assert_eq!(of_class("legend band").len(), 1);
        let (iterations, _) = metric_svg_text(&table, "iterations");
        assert!(!iterations.contains("whisker") && !iterations.contains("class=\"band\""));
    }
}
