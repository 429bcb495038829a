//! The accuracy-for-cost frontier of a tracking study's plans: each tracked plan's error at its
//! own knots ([`PlanRecord::knot_error`]) against what its solve cost (wall time, NLP
//! variables), one curve per method, so that a higher-order method's extra variables per
//! interval can be weighed against the knots it saves.

use std::fmt::Write as _;
use std::path::Path;

use plotters::prelude::*;

use super::StudyError;
use super::StudyMethod;
use super::tracking::PlanRecord;

/// What a frontier plot puts on its x axis.
type PlanMeasure = fn(&PlanRecord) -> f64;

/// The header of `tracking_frontier.csv`.
pub const FRONTIER_CSV_HEADER: &str =
    "knots,method,variables,iterations,wall_time_s,knot_error,objective";

/// `tracking_frontier.csv`: one line per tracked plan, in the plans' order.
pub fn frontier_csv(plans: &[PlanRecord]) -> String {
    let mut s = format!("{FRONTIER_CSV_HEADER}\n");
    for p in plans {
        let Some(error) = p.knot_error else { continue };
        // Infallible: writing to a String.
        let _ = writeln!(
            s,
            "{},{},{},{},{:.4},{:.6e},{:.10e}",
            p.knots,
            p.method.study_name(),
            p.variables,
            p.iterations,
            p.wall_time_s,
            error,
            p.objective
        );
    }
    s
}

/// Writes `tracking_frontier.csv`, `tracking_frontier_time.svg` (knot error against solve wall
/// time) and `tracking_frontier_size.svg` (against NLP variables) into `dir`, log-log.
pub fn write_frontier(dir: &Path, plans: &[PlanRecord], title: &str) -> Result<(), StudyError> {
    let csv = dir.join("tracking_frontier.csv");
    crate::files::output::write_atomic(&csv, frontier_csv(plans).as_bytes())
        .map_err(StudyError::write(&csv))?;
    let axes: [(&str, &str, PlanMeasure); 2] = [
        ("time", "solve wall time (s)", |p| p.wall_time_s),
        ("size", "NLP variables", |p| p.variables as f64),
    ];
    for (stem, x_label, x) in axes {
        let svg = dir.join(format!("tracking_frontier_{stem}.svg"));
        crate::files::output::write_atomic_with(&svg, |staged| {
            frontier_svg(staged, plans, title, x_label, x)
        })
        .map_err(StudyError::plot(&svg))?;
    }
    Ok(())
}

/// Error at the knots against `x` of each tracked plan, a line per method through its knot
/// counts.
fn frontier_svg(
    path: &Path,
    plans: &[PlanRecord],
    title: &str,
    x_label: &str,
    x: PlanMeasure,
) -> Result<(), crate::report::PlotError> {
    let points: Vec<(&PlanRecord, f64, f64)> = plans
        .iter()
        .filter_map(|p| Some((p, x(p), p.knot_error?)))
        .filter(|(_, a, b)| *a > 0.0 && *b > 0.0 && a.is_finite() && b.is_finite())
        .collect();
    let range = |values: &mut dyn Iterator<Item = f64>| {
        let (lo, hi) = values.fold((f64::INFINITY, 0.0_f64), |(lo, hi), v| {
            (lo.min(v), hi.max(v))
        });
        if lo.is_finite() && hi > 0.0 {
            (lo / 1.5, hi * 1.5)
        } else {
            (0.1, 10.0)
        }
    };
    let (x_lo, x_hi) = range(&mut points.iter().map(|p| p.1));
    let (y_lo, y_hi) = range(&mut points.iter().map(|p| p.2));
    let (root, mut chart) = crate::report::plot::study_chart(
        path,
        title,
        (x_lo..x_hi).log_scale(),
        (y_lo..y_hi).log_scale(),
    )?;
    chart
        .configure_mesh()
        .light_line_style(WHITE)
        .x_label_formatter(&|v| format!("{v:.3}"))
        .y_label_formatter(&|v| format!("{v:.1e}"))
        .x_desc(x_label)
        .y_desc("RMS configuration error at the plan's knots")
        .draw()?;
    let mut methods: Vec<_> = points.iter().map(|p| p.0.method).collect();
    methods.sort_by_key(|&m| super::table_order(0, m));
    methods.dedup();
    for method in methods {
        let colour = method.study_colour();
        let mut line: Vec<(usize, f64, f64)> = points
            .iter()
            .filter(|p| p.0.method == method)
            .map(|p| (p.0.knots, p.1, p.2))
            .collect();
        line.sort_by_key(|p| p.0);
        let xy: Vec<(f64, f64)> = line.iter().map(|p| (p.1, p.2)).collect();
        chart
            .draw_series(LineSeries::new(xy.clone(), colour.stroke_width(2)))?
            .label(method.study_label())
            .legend(move |(x, y)| {
                PathElement::new(vec![(x, y), (x + 18, y)], colour.stroke_width(2))
            });
        chart.draw_series(line.iter().map(|&(k, a, b)| {
            EmptyElement::at((a, b))
                + Circle::new((0, 0), 3, colour.filled())
                + Text::new(format!("K={k}"), (5, -12), ("sans-serif", 11))
        }))?;
    }
    crate::report::plot::legend_and_present(&mut chart, &root)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::discrete::Integrator;

    fn plan(knots: usize, method: Integrator, error: Option<f64>) -> PlanRecord {
        PlanRecord {
            knots,
            method,
            objective: 1.5,
            max_slack: 0.0,
            iterations: 40,
            variables: 100 * knots,
            wall_time_s: 0.25,
            knot_error: error,
            start: "guess".into(),
            trajectory_csv: String::new(),
            max_deviation: error,
            outcome: "tracked".into(),
        }
    }

    /// Tracked plans only, in the documented columns.
    #[test]
    fn frontier_csv_has_a_line_per_tracked_plan() {
        let plans = [
            plan(10, Integrator::Midpoint, Some(2e-3)),
            plan(10, Integrator::Galerkin4, None),
            plan(20, Integrator::Galerkin4, Some(1e-5)),
        ];
        assert_eq!(
            frontier_csv(&plans),
            format!(
                "{FRONTIER_CSV_HEADER}\n10,variational,1000,40,0.2500,2.000000e-3,1.5000000000e0\n\
                 20,galerkin4,2000,40,0.2500,1.000000e-5,1.5000000000e0\n"
            )
        );
    }
}
