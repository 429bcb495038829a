//! What a researcher reads: trajectory CSV, summary JSON, SVG plots (written atomically),
//! and the regression record of solved costs.

#![warn(missing_docs)]

mod csv;
mod golden;
mod metrics;
mod modes;
mod outdir;
pub(crate) mod plot;
mod simulation;
mod summary;

pub use csv::*;
pub use golden::*;
pub use metrics::{MetricInputs, metric_unit, metric_value, metrics_json};
pub use modes::*;
pub use outdir::*;
pub use plot::{
    Panel, PlotError, contact_modes_svg, coordinates_svg, inputs_svg, line_plot, panel_plot,
};
pub use simulation::{SimulationColumns, simulation_summary_json};
pub use summary::*;

use std::path::{Path, PathBuf};

use crate::problem::CoordinateKind;
use crate::problem::{LoadedProblem, RobotInfo, Units};
use crate::transcription::Solution;

/// Why outputs could not be written.
#[derive(Debug, thiserror::Error)]
pub enum ReportError {
    /// A file or directory could not be written.
    #[error("cannot write output directory {path}: {source}")]
    Io {
        /// The file or directory.
        path: PathBuf,
        /// The operating-system error.
        source: std::io::Error,
    },
    /// The output directory may not or cannot be replaced.
    #[error(transparent)]
    Output(#[from] OutputDirError),
    /// The animation could not be made.
    #[error(transparent)]
    View(#[from] crate::view::ViewError),
    /// A plot could not be drawn or written.
    #[error("cannot draw {path}: {source}")]
    Plot {
        /// The plot file.
        path: PathBuf,
        /// Why.
        source: PlotError,
    },
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

/// Per coordinate, the title of its panel in `coordinates.svg`: `base position [m]` and
/// `base orientation [rad]` for the base's coordinates, else its limb (the base's child link
/// it moves) and unit, from the problem's robot (by coordinate name alone when the robot
/// cannot be loaded).
pub fn coordinate_panels(problem: &LoadedProblem, units: &[String]) -> Vec<String> {
    let limbs = crate::transcription::ModelMechanics::load(&problem.spec)
        .ok()
        .map(|m| crate::model::coordinate_limbs(m.model()));
    problem
        .robot
        .coordinates
        .iter()
        .enumerate()
        .map(|(j, name)| {
            let unit = units.get(j).map_or("", String::as_str);
            match limbs.as_ref().map(|l| l.get(j).cloned().flatten()) {
                Some(None) => match problem.robot.coordinate_kinds.get(j) {
                    Some(CoordinateKind::Angular) => format!("base orientation [{unit}]"),
                    _ => format!("base position [{unit}]"),
                },
                Some(Some(limb)) => format!("{limb} [{unit}]"),
                None => format!("{name} [{unit}]"),
            }
        })
        .collect()
}

/// The line telling which plots were not written because they would be empty (a robot
/// without inputs gets no `inputs.svg`, a problem without contacts no `contact_modes.svg`);
/// none when every plot was written.
pub fn plots_not_written(inputs: usize, contacts: usize) -> Option<String> {
    let mut missing = Vec::new();
    if inputs == 0 {
        missing.push("no inputs.svg (the robot has no inputs)");
    }
    if contacts == 0 {
        missing.push("no contact_modes.svg (the problem has no contacts)");
    }
    (!missing.is_empty()).then(|| missing.join("; "))
}

/// Writes `trajectory.csv`, `summary.json` and the three plots into `staged` (which may
/// already hold Ipopt's log), then commits it: an existing target is replaced only once
/// everything is written.
pub fn write_outputs(
    staged: StagedDir,
    problem: &LoadedProblem,
    solution: &Solution,
) -> Result<PathBuf, ReportError> {
    let summary = summary_json(problem, solution);
    if !solution.levels.is_empty() {
        let path = staged.path().join("levels.svg");
        plot::levels_svg(&path, &solution.levels).map_err(|source| ReportError::Plot {
            path: staged.target().join("levels.svg"),
            source,
        })?;
    }
    write_trajectory_outputs(staged, problem, &solution_trajectory(solution), &summary)
}

/// Writes a trajectory (a solution's or a simulation's) as `trajectory.csv`, its `summary`
/// as `summary.json`, the plots and `animation.html` into `staged`, then commits it: an existing target
/// is replaced only once everything is written.
pub fn write_trajectory_outputs(
    staged: StagedDir,
    problem: &LoadedProblem,
    trajectory: &Trajectory<'_>,
    summary: &serde_json::Value,
) -> Result<PathBuf, ReportError> {
    let io = |path: &Path| {
        let path = path.to_owned();
        move |source| ReportError::Io { path, source }
    };
    let target = staged.target().to_owned();
    let dir = staged.path().to_owned();
    let units = column_units(&problem.robot, &problem.units);
    let csv_path = dir.join("trajectory.csv");
    std::fs::write(
        &csv_path,
        crate::files::trajectory_csv::write_trajectory(trajectory, &units),
    )
    .map_err(io(&csv_path))?;
    let mut summary = summary.clone();
    if let Some(copy) = copy_problem(&dir, problem).map_err(io(&dir.join(PROBLEM_COPY)))? {
        summary["problem_copy"] = copy;
    }
    let summary = &summary;
    let json_path = dir.join("summary.json");
    let text = serde_json::to_string_pretty(summary).unwrap_or_default();
    std::fs::write(&json_path, text + "\n").map_err(io(&json_path))?;
    let plot_err = |name: &str| {
        let path = target.join(name);
        move |source| ReportError::Plot { path, source }
    };
    coordinates_svg(
        &dir.join("coordinates.svg"),
        trajectory,
        &units.time,
        &coordinate_panels(problem, &units.coordinates),
        &units.coordinates,
    )
    .map_err(plot_err("coordinates.svg"))?;
    // No empty plots: a robot without inputs has no inputs.svg, one without contacts no
    // contact_modes.svg.
    if !trajectory.input_names.is_empty() {
        inputs_svg(
            &dir.join("inputs.svg"),
            trajectory,
            &units.time,
            &units.inputs,
        )
        .map_err(plot_err("inputs.svg"))?;
    }
    if !trajectory.contact_names.is_empty() {
        let friction: Vec<f64> = problem.spec.contacts.iter().map(|c| c.friction).collect();
        let modes = contact_modes(trajectory, &friction);
        contact_modes_svg(
            &dir.join("contact_modes.svg"),
            trajectory,
            &modes,
            &units.time,
        )
        .map_err(plot_err("contact_modes.svg"))?;
    }
    crate::view::write_animation(&dir, problem, trajectory, summary)?;
    Ok(staged.commit()?)
}

/// The folder of a result that holds copies of its problem file and robot URDF, so that
/// `vito view` can draw the result wherever the folder is copied.
pub const PROBLEM_COPY: &str = "problem";

/// Copies the problem file and its URDF into `dir/problem/` and returns the summary's
/// `problem_copy` (`file`, `urdf`: paths relative to the result folder); None when the
/// problem has no file on disk (nothing to copy). Each copy is written under the name the
/// summary records: the file's own name, any bytes of it that are not UTF-8 replaced by
/// U+FFFD (JSON holds only text), so that the recorded name always finds the copy.
fn copy_problem(dir: &Path, problem: &LoadedProblem) -> std::io::Result<Option<serde_json::Value>> {
    let (Some(file_name), Some(urdf_name)) =
        (problem.file.file_name(), problem.robot.urdf.file_name())
    else {
        return Ok(None);
    };
    let (file_name, urdf_name) = (file_name.to_string_lossy(), urdf_name.to_string_lossy());
    if file_name == urdf_name || !problem.file.is_file() || !problem.robot.urdf.is_file() {
        return Ok(None);
    }
    let copy = dir.join(PROBLEM_COPY);
    std::fs::create_dir(&copy)?;
    let limit = crate::files::input::MAX_TEXT_BYTES;
    for (from, name) in [
        (&problem.file, &file_name),
        (&problem.robot.urdf, &urdf_name),
    ] {
        let text = crate::files::input::read_regular_text(from, limit)?;
        std::fs::write(copy.join(name.as_ref()), text)?;
    }
    Ok(Some(serde_json::json!({
        "file": format!("{PROBLEM_COPY}/{file_name}"),
        "urdf": format!("{PROBLEM_COPY}/{urdf_name}"),
    })))
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::ipopt::Status;
    use crate::transcription::NlpSize;

    /// A hand-made two-contact planar solution with 4 knots.
    pub(crate) fn sample_solution() -> Solution {
        Solution {
            status: Status::SolveSucceeded,
            objective: 1.25,
            objective_terms: vec![
                ("state_tracking".into(), 1.0),
                ("slack_penalty".into(), 0.25),
            ],
            iterations: 17,
            wall_time_s: 0.5,
            callback_time_s: 0.2,
            callback_split: Default::default(),
            ipopt_time_s: 0.3,
            size: NlpSize {
                n_variables: 40,
                n_constraints: 30,
                nnz_jacobian: 200,
                nnz_hessian: 90,
            },
            coordinate_names: vec!["x".into(), "theta".into()],
            input_names: vec!["theta".into()],
            contact_names: vec!["toe".into(), "heel".into()],
            friction_directions: 2,
            times: vec![0.0, 0.1, 0.2, 0.3],
            time_steps: vec![0.1; 3],
            q: vec![
                vec![0.0, 0.0],
                vec![0.1, 0.2],
                vec![0.2, 0.3],
                vec![0.3, 0.25],
            ],
            v: vec![
                vec![0.0, 0.0],
                vec![1.0, 2.0],
                vec![1.0, 1.0],
                vec![1.0, -0.5],
            ],
            u: vec![vec![1.0], vec![-2.0], vec![0.5]],
            // toe: flight, stick, slide; heel: stick, flight, flight.
            normal_impulse: vec![vec![0.0, 2.0], vec![1.0, 1e-7], vec![1.0, 0.0]],
            friction_impulse: vec![
                vec![vec![0.0, 0.0], vec![0.5, 0.0]],
                vec![vec![0.2, 0.1], vec![0.0, 0.0]],
                vec![vec![0.0, 1.0], vec![0.0, 0.0]],
            ],
            signed_distance: vec![
                vec![0.0, 0.0],
                vec![0.1, 0.0],
                vec![0.0, 0.05],
                vec![0.0, 0.2],
            ],
            world_impulse: Vec::new(),
            // The toe moves back 0.05 on the first interval, the heel only forwards.
            contact_positions: [[0.0, -0.05, 0.1, 0.2], [0.0, 0.1, 0.2, 0.3]].iter().fold(
                vec![Vec::new(); 4],
                |mut knots, xs| {
                    for (k, &x) in xs.iter().enumerate() {
                        knots[k].push([x, 0.0, 0.0]);
                    }
                    knots
                },
            ),
            slack: vec![vec![1e-9], vec![2e-9], vec![3e-9]],
            max_slack: 3e-9,
            slack_peak: Some(crate::transcription::SlackPeak {
                interval: 2,
                contact: None,
                slack: 3e-9,
                hidden: false,
            }),
            slack_tolerance: crate::transcription::DEFAULT_SLACK_TOLERANCE,
            max_complementarity: 1e-9,
            max_constraint_violation: 1e-10,
            worst_rows: Vec::new(),
            slack_weight: 100.0,
            solves: 1,
            starts: Vec::new(),
            best_start: 0,
            polish: None,
            carried_modes: None,
            continuation: Vec::new(),
            simulation_start: None,
            levels: Vec::new(),
        }
    }

    #[test]
    fn modes_follow_the_stated_thresholds() {
        let modes = contact_modes(&solution_trajectory(&sample_solution()), &[1.0, 1.0]);
        use ContactMode::*;
        assert_eq!(
            modes,
            vec![
                vec![Flight, Stick],
                vec![Stick, Flight],
                vec![Slide, Flight]
            ]
        );
    }

    #[test]
    fn csv_has_a_row_per_knot_and_reads_back() {
        let s = sample_solution();
        let units = ColumnUnits::x_theta_sample();
        let text = trajectory_csv(&s, &units);
        let header = text.lines().next().unwrap();
        assert!(header.starts_with("time [s],x [m],theta [rad],x_dot [m/s],theta_dot [rad/s],u_theta [N·m],toe_normal [N·s],toe_friction_+x [N·s],toe_friction_-x [N·s],toe_fx [N·s],toe_fy [N·s],toe_fz [N·s],toe_distance [m],"));
        assert!(header.ends_with(",slack"));
        let table = read_csv(&text).unwrap();
        assert_eq!(table.rows(), 4);
        assert_eq!(table.column("theta").unwrap(), vec![0.0, 0.2, 0.3, 0.25]);
        let u = table.column("u_theta").unwrap();
        assert_eq!(&u[..3], &[1.0, -2.0, 0.5]);
        assert!(u[3].is_nan());
        assert_eq!(table.column("heel_normal").unwrap()[0], 2.0);
    }
}

#[cfg(test)]
mod output_tests {
    use super::*;

    /// The sample solution widened to the hopper's names (4 coordinates, 2 inputs, 1 contact).
    fn hopper_like() -> Solution {
        let mut s = tests::sample_solution();
        s.coordinate_names = ["x", "z", "theta", "r"].map(String::from).to_vec();
        s.input_names = vec!["theta".into(), "r".into()];
        s.contact_names = vec!["foot_contact".into()];
        s.q = (0..4)
            .map(|k| vec![0.1 * k as f64, 0.5, 0.01 * k as f64, 0.5])
            .collect();
        s.v = vec![vec![0.0; 4]; 4];
        s.u = vec![vec![1.0, 2.0]; 3];
        s.normal_impulse = vec![vec![1.0]; 3];
        s.friction_impulse = vec![vec![vec![0.1, 0.0]]; 3];
        s.signed_distance = vec![vec![0.0]; 4];
        s.contact_positions = vec![vec![[0.0; 3]]; 4];
        s
    }

    /// Non-finite and huge values (an overflowing horizon, a diverged iterate) are left out
    /// of the plots or clamped, so drawing ends (plotters loops on an infinite axis).
    #[test]
    fn plots_of_non_finite_data_finish() {
        let mut s = hopper_like();
        s.times = vec![0.0, 1e307, f64::INFINITY, f64::NAN];
        s.q[1][0] = f64::NAN;
        s.q[2][1] = -1e308;
        s.q[3][2] = 1e308;
        s.u[0][0] = f64::NEG_INFINITY;
        let t = solution_trajectory(&s);
        let modes = contact_modes(&t, &[0.8]);
        let dir = tempfile::tempdir().unwrap();
        coordinates_svg(&dir.path().join("q.svg"), &t, "s", &[], &[]).unwrap();
        inputs_svg(&dir.path().join("u.svg"), &t, "s", &[]).unwrap();
        contact_modes_svg(&dir.path().join("m.svg"), &t, &modes, "s").unwrap();
        let text = std::fs::read_to_string(dir.path().join("q.svg")).unwrap();
        assert!(text.contains("<svg") && !text.contains("NaN"), "{text}");
    }

    /// A robot without inputs gets no (empty) inputs.svg; without contacts no
    /// contact_modes.svg.
    #[test]
    fn no_empty_plots_without_inputs_or_contacts() {
        let problem_file = Path::new(env!("CARGO_MANIFEST_DIR")).join("problems/hopper_2d.toml");
        let problem = crate::problem::load(&problem_file, &[]).unwrap();
        let mut s = hopper_like();
        s.input_names.clear();
        s.u = vec![Vec::new(); 3];
        let summary = summary_json(&problem, &s);
        let dir = tempfile::tempdir().unwrap();
        let target = dir.path().join("out");
        let checked = OutputTarget::check(&target, &[]).unwrap();
        let mut t = solution_trajectory(&s);
        let written =
            write_trajectory_outputs(checked.stage().unwrap(), &problem, &t, &summary).unwrap();
        assert!(!written.join("inputs.svg").exists());
        assert!(written.join("contact_modes.svg").exists());
        let no_contacts: Vec<String> = Vec::new();
        t.contact_names = &no_contacts;
        let target = dir.path().join("out2");
        let checked = OutputTarget::check(&target, &[]).unwrap();
        let written =
            write_trajectory_outputs(checked.stage().unwrap(), &problem, &t, &summary).unwrap();
        assert!(!written.join("contact_modes.svg").exists());
        assert!(written.join("coordinates.svg").exists());
    }

    #[test]
    fn outputs_are_complete_and_agree() {
        let problem_file = Path::new(env!("CARGO_MANIFEST_DIR")).join("problems/hopper_2d.toml");
        let problem = crate::problem::load(&problem_file, &[]).unwrap();
        let s = hopper_like();
        let dir = tempfile::tempdir().unwrap();
        let target = dir.path().join("out");
        std::fs::create_dir(&target).unwrap();
        std::fs::write(target.join("stale.txt"), "old").unwrap();
        // Not vito's: refused and left alone. Once marked as vito's, it is replaced whole.
        assert!(OutputTarget::check(&target, &[]).is_err());
        assert!(target.join("stale.txt").exists());
        // A marker without vito's list of what it wrote: the file beside it is not vito's.
        std::fs::write(target.join(MARKER), "").unwrap();
        let refused = OutputTarget::check(&target, &[]).unwrap_err().to_string();
        assert!(refused.contains("`stale.txt`"), "{refused}");
        std::fs::remove_file(target.join("stale.txt")).unwrap();
        let checked = OutputTarget::check(&target, &[]).unwrap();
        let written = write_outputs(checked.stage().unwrap(), &problem, &s).unwrap();
        assert_eq!(written, target);
        // vito's own results, listed in the marker, are replaceable; a file added later is
        // not deleted: the directory is refused, naming it.
        OutputTarget::check(&target, &[]).unwrap();
        std::fs::write(target.join("notes.txt"), "mine").unwrap();
        let refused = OutputTarget::check(&target, &[]).unwrap_err().to_string();
        assert!(
            refused.contains("holds 1 entry that vito did not write (`notes.txt`"),
            "{refused}"
        );
        std::fs::remove_file(target.join("notes.txt")).unwrap();
        assert!(target.join("animation.html").exists());
        for svg in ["coordinates.svg", "inputs.svg", "contact_modes.svg"] {
            let text = std::fs::read_to_string(target.join(svg)).unwrap();
            assert!(text.contains("<svg"), "{svg} is not an SVG");
        }
        let summary: serde_json::Value =
            serde_json::from_str(&std::fs::read_to_string(target.join("summary.json")).unwrap())
                .unwrap();
        for key in [
            "status",
            "objective",
            "iterations",
            "wall_time_s",
            "callback_time_s",
            "ipopt_time_s",
            "max_slack",
            "max_complementarity",
            "n_variables",
            "n_constraints",
            "nnz_jacobian",
            "nnz_hessian",
            "problem",
            "parameters",
            "vito_version",
            "ipopt_version",
        ] {
            assert!(summary.get(key).is_some(), "summary.json lacks `{key}`");
        }
        assert_eq!(summary["status"], "solve_succeeded");
        assert_eq!(summary["objective"], 1.25);
        assert_eq!(summary["ipopt_version"], crate::ipopt::VERSION);
        let table =
            read_csv(&std::fs::read_to_string(target.join("trajectory.csv")).unwrap()).unwrap();
        assert_eq!(table.rows(), s.times.len());
        for name in ["x", "z", "theta", "r"] {
            let last = *table.column(name).unwrap().last().unwrap();
            assert_eq!(summary["final_q"][name].as_f64().unwrap(), last);
        }
        assert_eq!(
            table.column("time").unwrap().last().copied(),
            summary["total_time"].as_f64()
        );
    }
}
