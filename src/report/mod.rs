//! What a researcher reads: trajectory CSV, summary JSON, SVG plots (written atomically),
//! and the regression record of solved costs.

mod csv;
mod golden;
mod modes;
mod outdir;
mod plot;
mod summary;

pub use csv::*;
pub use golden::*;
pub use modes::*;
pub use outdir::*;
pub use plot::{contact_modes_svg, coordinates_svg, inputs_svg};
pub use summary::*;

use std::path::{Path, PathBuf};

use crate::problem::{LoadedProblem, RobotInfo, Units};
use crate::problem::CoordinateKind;
use crate::transcription::Solution;

/// Why outputs could not be written.
#[derive(Debug, thiserror::Error)]
pub enum ReportError {
    #[error("cannot write output directory {path}: {source}")]
    Io {
        path: PathBuf,
        source: std::io::Error,
    },
    #[error("cannot draw {path}: {message}")]
    Plot { path: PathBuf, message: String },
}

/// Column units for a robot in the given unit system.
pub fn column_units(robot: &RobotInfo, units: &Units) -> ColumnUnits {
    let angle_or_length = |k: &CoordinateKind| match k {
        CoordinateKind::Linear => units.length.clone(),
        CoordinateKind::Angular => "rad".to_owned(),
    };
    let force = units.force();
    ColumnUnits {
        time: units.time.clone(),
        length: units.length.clone(),
        coordinates: robot.coordinate_kinds.iter().map(angle_or_length).collect(),
        inputs: robot
            .input_kinds
            .iter()
            .map(|k| match k {
                CoordinateKind::Linear => force.clone(),
                CoordinateKind::Angular => format!("{force}·{}", units.length),
            })
            .collect(),
        impulse: format!("{force}·{}", units.time),
    }
}

/// Writes `trajectory.csv`, `summary.json` and the three plots into `target`, atomically:
/// an existing `target` is replaced only once everything is written.
pub fn write_outputs(
    target: &Path,
    problem: &LoadedProblem,
    solution: &Solution,
) -> Result<PathBuf, ReportError> {
    let io = |path: &Path| {
        let path = path.to_owned();
        move |source| ReportError::Io { path, source }
    };
    let staged = StagedDir::new(target).map_err(io(target))?;
    let dir = staged.path().to_owned();
    let units = column_units(&problem.robot, &problem.units);
    let csv_path = dir.join("trajectory.csv");
    std::fs::write(&csv_path, trajectory_csv(solution, &units)).map_err(io(&csv_path))?;
    let summary = summary_json(problem, solution);
    let json_path = dir.join("summary.json");
    let text = serde_json::to_string_pretty(&summary).unwrap_or_default();
    std::fs::write(&json_path, text + "\n").map_err(io(&json_path))?;
    let plot_err = |name: &str| {
        let path = target.join(name);
        move |message| ReportError::Plot { path, message }
    };
    coordinates_svg(&dir.join("coordinates.svg"), solution, &units.time)
        .map_err(plot_err("coordinates.svg"))?;
    inputs_svg(&dir.join("inputs.svg"), solution, &units.time).map_err(plot_err("inputs.svg"))?;
    let friction: Vec<f64> = problem.spec.contacts.iter().map(|c| c.friction).collect();
    let modes = contact_modes(solution, &friction);
    contact_modes_svg(&dir.join("contact_modes.svg"), solution, &modes, &units.time)
        .map_err(plot_err("contact_modes.svg"))?;
    staged.commit().map_err(io(target))
}
