//! A study's result: RMS error per knot count and method (mean and standard deviation over
//! runs), its CSV `knots,method,rms_mean,rms_std` and its SVG (mean with ±std bars, like the
//! paper's figures), and the log-log slope of error against knot count.

use std::fmt::Write as _;
use std::path::Path;

use plotters::prelude::*;

use super::StudyError;
use crate::discrete::Integrator;

/// The methods a study compares, in table order: the paper's two (first order first), then
/// the higher-order Galerkin members. A method is the [`Integrator`] that implements it.
pub const METHODS: [Integrator; 4] = [
    Integrator::Euler,
    Integrator::Midpoint,
    Integrator::Galerkin4,
    Integrator::Galerkin6,
];

/// The paper's two methods, first order first.
pub const PAPER_METHODS: [Integrator; 2] = [Integrator::Euler, Integrator::Midpoint];

/// How a study names and draws an integrator.
pub trait StudyMethod {
    /// The CSV's name of the method: the paper's two by the paper's names (`first_order`,
    /// `variational`), the others by their integrator's.
    fn study_name(self) -> &'static str;
    /// Its label in plots.
    fn study_label(self) -> &'static str;
    /// Its plot colour.
    fn study_colour(self) -> RGBColor;
}

impl StudyMethod for Integrator {
    fn study_name(self) -> &'static str {
        match self {
            Integrator::Euler => "first_order",
            Integrator::Midpoint => "variational",
            Integrator::Galerkin4 => "galerkin4",
            Integrator::Galerkin6 => "galerkin6",
        }
    }

    fn study_label(self) -> &'static str {
        match self {
            Integrator::Euler => "first order",
            Integrator::Midpoint => "variational (midpoint)",
            Integrator::Galerkin4 => "galerkin4",
            Integrator::Galerkin6 => "galerkin6",
        }
    }

    fn study_colour(self) -> RGBColor {
        match self {
            Integrator::Euler => RGBColor(200, 60, 40),
            Integrator::Midpoint => RGBColor(40, 90, 200),
            Integrator::Galerkin4 => RGBColor(30, 150, 70),
            Integrator::Galerkin6 => RGBColor(140, 60, 170),
        }
    }
}

/// The sort key of a study's rows and records: knot counts ascending, then the methods in
/// [`METHODS`] order (first order first).
pub fn table_order(knots: usize, method: Integrator) -> (usize, usize) {
    let index = METHODS.iter().position(|&m| m == method).unwrap_or(0);
    (knots, index)
}

/// One knot count and method.
#[derive(Debug, Clone, PartialEq)]
pub struct StudyRow {
    /// Knot count K (K − 1 steps over the horizon).
    pub knots: usize,
    /// The method.
    pub method: Integrator,
    /// RMS error per run (seed or plan), in the order run.
    pub runs: Vec<f64>,
}

impl StudyRow {
    /// Mean over runs.
    pub fn mean(&self) -> f64 {
        self.runs.iter().sum::<f64>() / self.runs.len().max(1) as f64
    }

    /// Population standard deviation over runs.
    pub fn std(&self) -> f64 {
        let m = self.mean();
        let var = self.runs.iter().map(|x| (x - m) * (x - m)).sum::<f64>()
            / self.runs.len().max(1) as f64;
        var.sqrt()
    }
}

/// A study's rows, knot counts ascending, first order before variational at each.
#[derive(Debug, Clone, PartialEq, Default)]
pub struct StudyTable {
    /// The rows.
    pub rows: Vec<StudyRow>,
}

impl StudyTable {
    /// Adds one run's error to the row of (knots, method), which it creates if missing.
    pub fn add_run(&mut self, knots: usize, method: Integrator, rms: f64) {
        match self
            .rows
            .iter_mut()
            .find(|r| r.knots == knots && r.method == method)
        {
            Some(row) => row.runs.push(rms),
            None => self.rows.push(StudyRow {
                knots,
                method,
                runs: vec![rms],
            }),
        }
    }

    /// The methods in the table, in [`METHODS`] order.
    pub fn methods(&self) -> Vec<Integrator> {
        METHODS
            .into_iter()
            .filter(|&m| self.rows.iter().any(|r| r.method == m))
            .collect()
    }

    /// Puts the rows in the table's order: knot counts ascending, first order first.
    pub fn sort(&mut self) {
        self.rows.sort_by_key(|r| table_order(r.knots, r.method));
    }

    /// The row of (knots, method).
    pub fn row(&self, knots: usize, method: Integrator) -> Option<&StudyRow> {
        self.rows
            .iter()
            .find(|r| r.knots == knots && r.method == method)
    }

    /// (knots, mean) of one method, knot counts ascending.
    pub fn means(&self, method: Integrator) -> Vec<(f64, f64)> {
        self.rows
            .iter()
            .filter(|r| r.method == method)
            .map(|r| (r.knots as f64, r.mean()))
            .collect()
    }

    /// The CSV: `knots,method,rms_mean,rms_std`, one line per row.
    pub fn csv(&self) -> String {
        let mut s = String::from("knots,method,rms_mean,rms_std\n");
        for r in &self.rows {
            // Infallible: writing to a String.
            let _ = writeln!(
                s,
                "{},{},{:.6e},{:.6e}",
                r.knots,
                r.method.study_name(),
                r.mean(),
                r.std()
            );
        }
        s
    }

    /// Writes `<stem>.csv`, `<stem>_runs.csv` (every run's error) and `<stem>.svg` into `dir`.
    pub fn write(
        &self,
        dir: &Path,
        stem: &str,
        title: &str,
        y_label: &str,
    ) -> Result<(), StudyError> {
        let csv = dir.join(format!("{stem}.csv"));
        crate::files::output::write_atomic(&csv, self.csv().as_bytes())
            .map_err(StudyError::write(&csv))?;
        let mut runs = String::from("knots,method,run,rms\n");
        for r in &self.rows {
            for (i, x) in r.runs.iter().enumerate() {
                let _ = writeln!(runs, "{},{},{i},{x:.6e}", r.knots, r.method.study_name());
            }
        }
        let runs_path = dir.join(format!("{stem}_runs.csv"));
        crate::files::output::write_atomic(&runs_path, runs.as_bytes())
            .map_err(StudyError::write(&runs_path))?;
        let svg = dir.join(format!("{stem}.svg"));
        crate::files::output::write_atomic_with(&svg, |staged| self.svg(staged, title, y_label))
            .map_err(StudyError::plot(&svg))?;
        Ok(())
    }

    /// Mean per knot count with ±std bars, one colour per method (the paper's figures).
    fn svg(&self, path: &Path, title: &str, y_label: &str) -> Result<(), crate::report::PlotError> {
        let finite = |x: &f64| x.is_finite();
        let x_max = self.rows.iter().map(|r| r.knots).max().unwrap_or(2) as f64 + 1.0;
        let x_min = (self.rows.iter().map(|r| r.knots).min().unwrap_or(1) as f64 - 1.0).max(0.0);
        let y_max = self
            .rows
            .iter()
            .map(|r| r.mean() + r.std())
            .filter(finite)
            .fold(0.0_f64, f64::max)
            * 1.05;
        let y_max = if y_max > 0.0 { y_max } else { 1.0 };
        let (root, mut chart) =
            crate::report::plot::study_chart(path, title, x_min..x_max, 0.0..y_max)?;
        chart
            .configure_mesh()
            .x_desc("knot points")
            .y_desc(y_label)
            .draw()?;
        let methods = self.methods();
        for (index, &method) in methods.iter().enumerate() {
            // Bars side by side at each knot count, 0.16 apart.
            let offset = 0.16 * (index as f64 - (methods.len() as f64 - 1.0) / 2.0);
            let colour = method.study_colour();
            let rows: Vec<&StudyRow> = self.rows.iter().filter(|r| r.method == method).collect();
            let points: Vec<(f64, f64)> = rows
                .iter()
                .map(|r| (r.knots as f64 + offset, r.mean()))
                .filter(|p| p.1.is_finite())
                .collect();
            let label = method.study_label();
            chart
                .draw_series(LineSeries::new(points.clone(), colour.stroke_width(2)))?
                .label(label)
                .legend(move |(x, y)| {
                    PathElement::new(vec![(x, y), (x + 18, y)], colour.stroke_width(2))
                });
            chart.draw_series(points.iter().map(|&p| Circle::new(p, 3, colour.filled())))?;
            chart.draw_series(rows.iter().filter(|r| r.mean().is_finite()).map(|r| {
                let x = r.knots as f64 + offset;
                let (m, s) = (r.mean(), r.std());
                PathElement::new(
                    vec![(x, (m - s).max(0.0)), (x, m + s)],
                    colour.stroke_width(1),
                )
            }))?;
        }
        crate::report::plot::legend_and_present(&mut chart, &root)
    }
}

/// The least-squares slope of log(error) against log(knots): the observed order of
/// convergence with knot count (negative when the error falls). None for fewer than two
/// positive points.
pub fn log_log_slope(points: &[(f64, f64)]) -> Option<f64> {
    let logs: Vec<(f64, f64)> = points
        .iter()
        .filter(|(x, y)| *x > 0.0 && *y > 0.0 && y.is_finite())
        .map(|(x, y)| (x.ln(), y.ln()))
        .collect();
    if logs.len() < 2 {
        return None;
    }
    let n = logs.len() as f64;
    let (mx, my) = (
        logs.iter().map(|p| p.0).sum::<f64>() / n,
        logs.iter().map(|p| p.1).sum::<f64>() / n,
    );
    let sxy: f64 = logs.iter().map(|p| (p.0 - mx) * (p.1 - my)).sum();
    let sxx: f64 = logs.iter().map(|p| (p.0 - mx) * (p.0 - mx)).sum();
    (sxx > 0.0).then(|| sxy / sxx)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Errors ∝ K^−2 give slope −2; the CSV has one line per row in the documented columns.
    #[test]
    fn slope_of_a_power_law_and_csv_columns() {
        let points: Vec<(f64, f64)> = (3..10).map(|k| (k as f64, 5.0 / (k * k) as f64)).collect();
        let slope = log_log_slope(&points).unwrap();
        assert!((slope + 2.0).abs() < 1e-12, "{slope}");
        let table = StudyTable {
            rows: vec![StudyRow {
                knots: 3,
                method: Integrator::Midpoint,
                runs: vec![1.0, 3.0],
            }],
        };
        assert_eq!(
            table.csv(),
            "knots,method,rms_mean,rms_std\n3,variational,2.000000e0,1.000000e0\n"
        );
    }
}
