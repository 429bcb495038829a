//! The SVG of one metric over the grid: the first axis along x (its values when they are
//! numbers, else their positions), one line per combination of the other axes' values.

use std::path::Path;

use crate::report::line_plot;
use crate::sweep::{SweepError, Table};

/// Draws `metric` (a column such as `objective` or a metric name) over the grid into `path`
/// (written beside and renamed, so a reader never sees half a plot). Returns the number of
/// rows that had a value.
pub fn metric_svg(table: &Table, metric: &str, path: &Path) -> Result<usize, SweepError> {
    let first = &table.grid.axes[0];
    let numeric: Option<Vec<f64>> = first.values.iter().map(|v| v.parse().ok()).collect();
    let x_of = |value: &str| -> f64 {
        let position = first.values.iter().position(|v| v == value).unwrap_or(0);
        numeric.as_ref().map_or(position as f64, |xs| xs[position])
    };
    let mut series: Vec<(String, Vec<(f64, f64)>)> = Vec::new();
    let mut plotted = 0;
    for row in &table.rows {
        let Some(y) = row.metric(metric).filter(|y| y.is_finite()) else {
            continue;
        };
        plotted += 1;
        let label: Vec<String> = row.values[1..]
            .iter()
            .map(|(k, v)| format!("{k} = {v}"))
            .collect();
        let label = if label.is_empty() {
            metric.to_owned()
        } else {
            label.join(", ")
        };
        let point = (x_of(&row.values[0].1), y);
        match series.iter_mut().find(|(l, _)| *l == label) {
            Some((_, points)) => points.push(point),
            None => series.push((label, vec![point])),
        }
    }
    for (_, points) in &mut series {
        points.sort_by(|a, b| a.0.total_cmp(&b.0));
    }
    let x_label = if numeric.is_some() {
        first.key.clone()
    } else {
        format!("{} (position in the list)", first.key)
    };
    crate::files::output::write_atomic_with(path, |staged| {
        line_plot(
            staged,
            &format!("{metric} over the sweep of {}", table.problem),
            &x_label,
            metric,
            &series,
        )
    })
    .map_err(|message| SweepError::Plot {
        path: path.to_owned(),
        message,
    })?;
    Ok(plotted)
}
