//! Reading a problem file: its bytes and hash, the `--set` overrides, the TOML grammar, then
//! the checks of [`super::validate`], into a [`LoadedProblem`].

#![warn(missing_docs)]

use std::path::{Path, PathBuf};
use std::sync::atomic::{AtomicUsize, Ordering};

use sha2::{Digest, Sha256};

use crate::files::input::{MAX_TEXT_BYTES, read_regular_file, read_regular_text};
use crate::problem::family;

use crate::problem::schema::ProblemFile;
use crate::problem::validate::{Context, check};
use crate::problem::{Location, Override, ProblemError, ProblemSpec, RobotInfo, Units};

/// A checked problem with what outputs need to say where it came from.
#[derive(Debug, Clone)]
pub struct LoadedProblem {
    /// The checked problem the transcription solves.
    pub spec: ProblemSpec,
    /// Names, limits and units of the robot.
    pub robot: RobotInfo,
    /// Problem file as given.
    pub file: PathBuf,
    /// SHA-256 of the problem file's bytes (hex).
    pub sha256: String,
    /// The `--set` overrides applied, as `path = value` strings.
    pub parameters: Vec<(String, String)>,
    /// A family's `[parameters]`: each declared parameter's value, overrides applied
    /// (empty for a file that declares none).
    pub family_parameters: crate::problem::family::Parameters,
    /// Output directory from the file (`output.dir`), if any.
    pub output_dir: Option<PathBuf>,
    /// Length, mass and time unit names (from `robot.units`; SI by default).
    pub units: Units,
    /// Free text from the file.
    pub description: Option<String>,
    /// The goal pose q_goal (the centre of the q_N box; q_1 when the file has none).
    pub goal: Vec<f64>,
    /// `[tracking] gains`: PD gains for simulations that track a trajectory.
    pub tracking_gains: Vec<crate::problem::TrackingGain>,
    /// `[tracking] feedback`: where the PD reads the state.
    pub tracking_feedback: crate::problem::TrackingFeedback,
}

impl LoadedProblem {
    /// An error about `field` (a TOML path such as `solver.ipopt.tol`) located in the
    /// problem file, for checks made after loading (e.g. by Ipopt).
    pub fn field_error(&self, field: &str, message: impl Into<String>) -> ProblemError {
        let ctx = Context {
            file: self.file.clone(),
            text: read_regular_text(&self.file, MAX_TEXT_BYTES).unwrap_or_default(),
            overridden: self.parameters.iter().map(|(p, _)| p.clone()).collect(),
            urdf_text: None,
        };
        ctx.invalid(field, message)
    }
}

/// Problem files this process has been asked to load ([`load`], [`load_from_str`]), whether
/// they loaded or not.
static LOADS: AtomicUsize = AtomicUsize::new(0);

/// How many problem files this process has been asked to load so far: the work a caller's
/// set-up did (a sweep's checks load a few per axis, not one per value).
pub fn loads() -> usize {
    LOADS.load(Ordering::Relaxed)
}

/// Reads, overrides and checks a problem file (a regular file; see [`crate::files::input`]).
pub fn load(path: &Path, overrides: &[Override]) -> Result<LoadedProblem, ProblemError> {
    LOADS.fetch_add(1, Ordering::Relaxed);
    let bytes = read_regular_file(path, MAX_TEXT_BYTES).map_err(|source| ProblemError::Io {
        path: path.to_owned(),
        source,
    })?;
    let text = String::from_utf8(bytes).map_err(|_| ProblemError::Invalid {
        at: Box::new(Location {
            file: path.to_owned(),
            line: None,
            field: String::new(),
            from_override: false,
        }),
        message: "the file is not UTF-8 text".into(),
    })?;
    check_text(path, text, None, overrides)
}

/// [`load`] for a problem file's text in memory, with its robot's URDF text (whatever
/// `robot.urdf` names): what the fuzzer checks without touching the disk. `path` names the
/// file in messages.
pub fn load_from_str(
    path: &Path,
    text: &str,
    urdf: &str,
    overrides: &[Override],
) -> Result<LoadedProblem, ProblemError> {
    LOADS.fetch_add(1, Ordering::Relaxed);
    check_text(path, text.to_owned(), Some(urdf.to_owned()), overrides)
}

fn check_text(
    path: &Path,
    text: String,
    urdf_text: Option<String>,
    overrides: &[Override],
) -> Result<LoadedProblem, ProblemError> {
    let sha256: String = Sha256::digest(text.as_bytes())
        .iter()
        .map(|b| format!("{b:02x}"))
        .collect();
    // Overrides of declared parameters may name them bare (`--set stride_hz=10`).
    let given = overrides;
    let overrides = family_overrides(path, &text, overrides)?;
    let ctx = Context {
        file: path.to_owned(),
        text: text.clone(),
        overridden: overrides.iter().map(|o| o.path.clone()).collect(),
        urdf_text,
    };
    let mut table: toml::Table = toml::from_str(&text).map_err(|e| ctx.serde_error(&e, &text))?;
    let mut parameters = family::Parameters::new();
    let raw: ProblemFile = if overrides.is_empty()
        && !table.contains_key(family::PARAMETERS)
        && !family::has_expressions(&table)
    {
        // The file as written: errors point at its own lines and spans.
        toml::from_str(&text).map_err(|e| ctx.serde_error(&e, &text))?
    } else {
        for o in &overrides {
            o.apply(&mut table)?;
            remove_alternative(&mut table, &o.path);
        }
        let family_error = |e: family::FamilyError| ctx.invalid(&e.field, e.message);
        parameters = family::take_parameters(&mut table).map_err(family_error)?;
        family::evaluate_expressions(&mut table, &parameters).map_err(family_error)?;
        let rewritten = toml::to_string(&table).map_err(|e| ProblemError::Override {
            arg: String::new(),
            message: e.to_string(),
        })?;
        toml::from_str(&rewritten).map_err(|e| ctx.serde_error(&e, &rewritten))?
    };
    let mut loaded = check(&ctx, raw)?;
    let regridded = given.iter().any(|o| o.path.starts_with("horizon."));
    if regridded {
        // The slack numbers are stated at the file's own grid: the file with every override
        // but the horizon's.
        let own: Vec<Override> = given
            .iter()
            .filter(|o| !o.path.starts_with("horizon."))
            .cloned()
            .collect();
        // A file whose own grid does not load (one too large for memory, made small by the
        // override) has no grid to state them at: they stay as written.
        if let Ok(file) = check_text(path, ctx.text.clone(), ctx.urdf_text.clone(), &own) {
            loaded.spec.rescale_slack_to(&file.spec);
        }
    }
    loaded.sha256 = sha256;
    loaded.family_parameters = parameters;
    loaded.parameters = given
        .iter()
        .map(|o| (o.path.clone(), o.value.to_string()))
        .collect();
    Ok(loaded)
}

/// Keys of which a file gives one or the other: overriding one removes the other from the
/// file's table, so `--set initial_guess.warm_start=prev.csv` works on a file with `to`.
const ALTERNATIVES: [(&str, &str, &str); 4] = [
    ("initial_guess", "warm_start", "to"),
    ("initial_guess", "warm_start", "simulation"),
    ("initial_guess", "to", "simulation"),
    ("horizon", "time_step", "total_time"),
];

fn remove_alternative(table: &mut toml::Table, path: &str) {
    for (section, a, b) in ALTERNATIVES {
        let other = if path == format!("{section}.{a}") {
            b
        } else if path == format!("{section}.{b}") {
            a
        } else {
            continue;
        };
        if let Some(t) = table.get_mut(section).and_then(|s| s.as_table_mut()) {
            t.remove(other);
        }
    }
}

/// The overrides with bare names of declared parameters spelled `parameters.<name>`; a
/// `parameters.<name>` the file does not declare is an error (a typo would otherwise add a
/// parameter nothing reads).
fn family_overrides(
    path: &Path,
    text: &str,
    overrides: &[Override],
) -> Result<Vec<Override>, ProblemError> {
    let declared: Vec<String> = toml::from_str::<toml::Table>(text)
        .ok()
        .and_then(|t| {
            t.get(family::PARAMETERS)
                .and_then(|p| p.as_table())
                .cloned()
        })
        .map(|p| p.keys().cloned().collect())
        .unwrap_or_default();
    overrides
        .iter()
        .map(|o| {
            let prefix = format!("{}.", family::PARAMETERS);
            if declared.contains(&o.path) {
                Ok(Override {
                    path: format!("{prefix}{}", o.path),
                    value: o.value.clone(),
                })
            } else if let Some(name) = o.path.strip_prefix(&prefix) {
                if declared.iter().any(|d| d == name) {
                    Ok(o.clone())
                } else {
                    Err(ProblemError::Override {
                        arg: format!("{}={}", o.path, o.value),
                        message: format!(
                            "{} declares no parameter `{name}`{}",
                            path.display(),
                            if declared.is_empty() {
                                String::new()
                            } else {
                                format!(" (it declares: {})", declared.join(", "))
                            }
                        ),
                    })
                }
            } else {
                Ok(o.clone())
            }
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::contact::Step;
    use crate::problem::costs::{Input, StateTracking};
    use crate::problem::{CostTerm, InitialGuess, Interval, TimeSteps};

    fn problems_dir() -> PathBuf {
        Path::new(env!("CARGO_MANIFEST_DIR")).join("problems")
    }

    /// A temp directory holding `robots/hopper_2d.urdf`, for edited copies of the hopper.
    fn dir_with_hopper_urdf() -> tempfile::TempDir {
        let dir = tempfile::tempdir().unwrap();
        std::fs::create_dir(dir.path().join("robots")).unwrap();
        std::fs::copy(
            problems_dir().join("robots/hopper_2d.urdf"),
            dir.path().join("robots/hopper_2d.urdf"),
        )
        .unwrap();
        dir
    }

    fn hopper_text() -> String {
        std::fs::read_to_string(problems_dir().join("hopper_2d.toml")).unwrap()
    }

    /// The slack's tolerance and target are stated at the file's grid: asked for on a grid of
    /// an eighth of its step, the hopper (fixed steps) allows an eighth of the slack, Spring
    /// Flamingo (free steps, a homotopy) a quarter at four times its intervals; an override
    /// that leaves the grid alone, or sets it to the file's, leaves them alone, and the
    /// weight, a time integral's, never changes.
    #[test]
    fn the_slack_numbers_scale_with_the_step() {
        let set = |s: &[&str]| -> Vec<Override> {
            s.iter().map(|o| Override::parse(o).unwrap()).collect()
        };
        let hopper = problems_dir().join("hopper_2d.toml");
        let file = load(&hopper, &[]).unwrap().spec;
        let fine = load(
            &hopper,
            &set(&[
                "horizon.knots=161",
                "horizon.time_step=0.00625",
                "slack.tolerance=2e-4",
            ]),
        )
        .unwrap()
        .spec;
        assert_eq!(file.slack_tolerance, 1e-4);
        assert!(
            (fine.slack_tolerance - 2e-4 / 8.0).abs() < 1e-18,
            "{}",
            fine.slack_tolerance
        );
        assert_eq!(fine.slack_weight, file.slack_weight);
        let same = load(&hopper, &set(&["horizon.knots=21", "slack.weight=7"])).unwrap();
        assert_eq!(same.spec.slack_tolerance, 1e-4);
        // A file whose own grid is refused (far too large for memory) still loads at the grid
        // asked for, its tolerance as written.
        let dir = dir_with_hopper_urdf();
        let huge = dir.path().join("huge.toml");
        std::fs::write(
            &huge,
            hopper_text().replace("knots = 21", "knots = 2000000000"),
        )
        .unwrap();
        assert!(load(&huge, &[]).is_err());
        let small = load(
            &huge,
            &set(&["horizon.knots=41", "horizon.time_step=0.025"]),
        )
        .unwrap();
        assert_eq!(small.spec.slack_tolerance, 1e-4);

        let flamingo = problems_dir().join("spring_flamingo_walk.toml");
        let file = load(&flamingo, &[]).unwrap().spec;
        let fine = load(&flamingo, &set(&["horizon.knots=97"])).unwrap().spec;
        let ratio = fine.slack_tolerance / file.slack_tolerance;
        assert!((ratio - 0.25).abs() < 1e-12, "{ratio}");
        let (f, c) = (
            file.slack_continuation.unwrap(),
            fine.slack_continuation.unwrap(),
        );
        assert!((c.target / f.target - 0.25).abs() < 1e-12);
        assert_eq!(c.tied_sigma, f.tied_sigma);
    }

    #[test]
    fn hopper_file_is_spec_hopper() {
        let p = load(&problems_dir().join("hopper_2d.toml"), &[]).unwrap();
        let s = &p.spec;
        assert_eq!(s.name, "hopper-2d");
        assert_eq!(s.knots, 21);
        assert_eq!(s.time_steps, TimeSteps::Fixed(0.05));
        assert_eq!(s.q_initial, [0.0, 0.5, 0.0, 0.5]);
        assert_eq!(s.v_initial, Some(vec![0.0; 4]));
        let goal = [0.5, 0.5, 0.0, 0.5];
        for (b, g) in s.q_final.iter().zip(goal) {
            assert_eq!(*b, Interval::fixed(g));
        }
        assert_eq!(
            s.input_bounds[0],
            Interval {
                lower: -10.0,
                upper: 10.0
            }
        );
        assert_eq!(
            s.input_bounds[1],
            Interval {
                lower: -100.0,
                upper: 100.0
            }
        );
        assert_eq!(s.contacts.len(), 1);
        assert_eq!(s.contacts[0].friction, 0.8);
        assert_eq!(s.slack_weight, 100.0);
        assert_eq!(
            s.costs,
            vec![
                CostTerm::StateTracking(StateTracking {
                    q_target: goal.to_vec(),
                    v_target: vec![0.0; 4],
                    q_weights: vec![1.0; 4],
                    v_weights: vec![0.0; 4],
                    time_weighted: true,
                }),
                CostTerm::Input(Input {
                    weights: vec![0.1, 0.01],
                    time_weighted: true,
                }),
            ]
        );
        assert_eq!(
            s.initial_guess,
            InitialGuess::Linear {
                from: s.q_initial.clone(),
                to: goal.to_vec()
            }
        );
        assert_eq!(p.sha256.len(), 64);
    }

    #[test]
    fn spring_flamingo_weights_are_doubled_for_the_half() {
        let p = load(&problems_dir().join("spring_flamingo_walk.toml"), &[]).unwrap();
        let s = &p.spec;
        assert_eq!(
            s.time_steps,
            TimeSteps::FreeEqual {
                t_min: 0.5,
                t_max: 2.5
            }
        );
        let delta = std::f64::consts::FRAC_PI_2 - 1.57075;
        assert!((s.q_initial[5] - delta).abs() < 1e-15);
        assert_eq!(s.q_final[0], Interval::fixed(-0.9));
        assert_eq!(s.q_final[1], Interval::fixed(0.875));
        match &s.costs[0] {
            CostTerm::StateTracking(StateTracking {
                q_weights,
                v_weights,
                ..
            }) => {
                assert_eq!(q_weights, &vec![0.2; 9]);
                assert_eq!(v_weights, &vec![0.2; 9]);
            }
            other => panic!("expected state tracking, got {other:?}"),
        }
        assert_eq!(
            s.costs[1],
            CostTerm::Input(Input {
                weights: vec![2.0; 4],
                time_weighted: true
            })
        );
        assert_eq!(
            s.input_bounds,
            vec![
                Interval {
                    lower: -300.0,
                    upper: 300.0
                };
                4
            ]
        );
        assert_eq!(s.contacts.len(), 4);
        assert_eq!(s.contacts[0].point, [0.0, 0.0, 0.0]);
    }

    #[test]
    fn littledog_goal_is_a_box_and_terrain_has_the_step() {
        let p = load(&problems_dir().join("littledog_step.toml"), &[]).unwrap();
        let s = &p.spec;
        assert_eq!(s.q_final[0].lower, 0.45 - 0.01);
        assert_eq!(s.q_final[0].upper, 0.45 + 0.01);
        assert!((s.q_final[2].lower - 0.236).abs() < 1e-15);
        assert_eq!(s.terrain.steps, vec![Step::along_x(0.25, 0.11, 0.005)]);
        match &s.costs[0] {
            CostTerm::StateTracking(StateTracking {
                q_weights,
                q_target,
                ..
            }) => {
                assert_eq!(&q_weights[..7], &[0.0, 0.0, 0.0, 10.0, 10.0, 10.0, 5.0]);
                assert_eq!(q_weights[7], 1.0);
                assert_eq!(q_target[0], 0.45);
                assert_eq!(q_target[2], 0.246);
            }
            other => panic!("expected state tracking, got {other:?}"),
        }
        assert!(s.input_bounds.iter().all(|b| *b == Interval::FREE));
        // The explicit feet are the URDF's own zero-radius spheres, in the same order.
        assert_eq!(s.contacts.len(), 4);
        for (c, u) in s.contacts.iter().zip(&p.robot.contacts) {
            assert_eq!(
                (c.link.as_str(), c.point),
                (u.link.as_str(), u.point),
                "{}",
                c.name
            );
        }
        assert_eq!(s.contacts[3].name, "back_right_foot");
    }

    #[test]
    fn overrides_change_values_and_are_recorded() {
        let o = [Override::parse("contacts.friction=0.3").unwrap()];
        let p = load(&problems_dir().join("hopper_2d.toml"), &o).unwrap();
        assert_eq!(p.spec.contacts[0].friction, 0.3);
        assert_eq!(
            p.parameters,
            vec![("contacts.friction".to_owned(), "0.3".to_owned())]
        );
    }

    #[test]
    fn family_parameters_derive_fields_and_are_overridden() {
        let dir = dir_with_hopper_urdf();
        let text = hopper_text()
            .replace("friction = 0.8", "friction = \"= mu\"")
            .replace("knots = 21", "knots = \"= 2 * hops * 10 + 1\"")
            .replace("time_step = 0.05", "time_step = \"= 1 / (20 * hops)\"")
            + "\n[parameters]\nmu = 0.8\nhops = 1\n";
        let file = dir.path().join("p.toml");
        std::fs::write(&file, text).unwrap();
        let p = load(&file, &[]).unwrap();
        assert_eq!(p.spec.contacts[0].friction, 0.8);
        assert_eq!(p.spec.knots, 21);
        assert_eq!(p.spec.time_steps, TimeSteps::Fixed(0.05));

        let o = [
            Override::parse("mu=0.3").unwrap(),
            Override::parse("parameters.hops=2").unwrap(),
        ];
        let p = load(&file, &o).unwrap();
        assert_eq!(p.spec.contacts[0].friction, 0.3);
        assert_eq!(p.spec.knots, 41);
        assert_eq!(p.spec.time_steps, TimeSteps::Fixed(1.0 / 40.0));
        assert_eq!(p.parameters[0], ("mu".into(), "0.3".into()));
        assert_eq!(p.parameters[1], ("parameters.hops".into(), "2".into()));

        // An undeclared parameter, a non-number and a division by zero name what and where.
        let err = load(&file, &[Override::parse("parameters.muu=1").unwrap()])
            .unwrap_err()
            .to_string();
        assert!(err.contains("declares no parameter `muu`"), "{err}");
        let err = load(&file, &[Override::parse("mu=slippery").unwrap()])
            .unwrap_err()
            .to_string();
        assert!(
            err.contains("field `parameters.mu` (set with --set)") && err.contains("a number"),
            "{err}"
        );
        let err = load(&file, &[Override::parse("hops=0").unwrap()])
            .unwrap_err()
            .to_string();
        assert!(
            err.contains("p.toml:") && err.contains("field `horizon.time_step`"),
            "{err}"
        );
        assert!(err.contains("inf"), "{err}");
    }

    #[test]
    fn warm_start_reads_a_trajectory_csv_by_name() {
        let dir = dir_with_hopper_urdf();
        // Columns in another order than the model's, with units, and an empty last input cell.
        std::fs::write(
            dir.path().join("prev.csv"),
            "time [s],r [m],theta [rad],z [m],x [m],u_theta [N·m],u_r [N],slack\n\
             0,0.5,0,0.5,0,1.5,-2,0.01\n\
             0.5,0.45,0.1,0.6,0.25,0.5,3,0.01\n\
             1,0.5,0,0.5,0.5,,,\n",
        )
        .unwrap();
        let text = std::fs::read_to_string(problems_dir().join("hopper_2d.toml"))
            .unwrap()
            .replace("to = \"final\"", "warm_start = \"prev.csv\"");
        std::fs::write(dir.path().join("p.toml"), text).unwrap();
        let p = load(&dir.path().join("p.toml"), &[]).unwrap();
        let InitialGuess::WarmStart(w) = &p.spec.initial_guess else {
            panic!("expected a warm start, got {:?}", p.spec.initial_guess);
        };
        assert_eq!(w.times, [0.0, 0.5, 1.0]);
        assert_eq!(w.q[1], [0.25, 0.6, 0.1, 0.45]);
        assert_eq!(w.u, vec![vec![1.5, -2.0], vec![0.5, 3.0]]);

        // A missing coordinate column is an error naming the column and the file's line.
        std::fs::write(dir.path().join("prev.csv"), "time [s],x [m]\n0,0\n1,1\n").unwrap();
        let err = load(&dir.path().join("p.toml"), &[])
            .unwrap_err()
            .to_string();
        assert!(err.contains("field `initial_guess.warm_start`"), "{err}");
        assert!(err.contains("no column for coordinate `z`"), "{err}");
    }

    /// `[solver] scaling`: Ipopt's own by default, `"units"` by name; a misspelt name and an
    /// Ipopt option that would undo the units' scaling are errors naming their field.
    #[test]
    fn solver_scaling_is_checked() {
        use crate::problem::ScalingMode;
        let path = problems_dir().join("hopper_2d.toml");
        let load_with = |sets: &[&str]| {
            let o: Vec<Override> = sets.iter().map(|s| Override::parse(s).unwrap()).collect();
            load(&path, &o)
        };
        assert_eq!(load_with(&[]).unwrap().spec.scaling, ScalingMode::Ipopt);
        let units = load_with(&["solver.scaling=\"units\""]).unwrap();
        assert_eq!(units.spec.scaling, ScalingMode::Units);
        let err = load_with(&["solver.scaling=\"unit\""])
            .unwrap_err()
            .to_string();
        assert!(
            err.contains("solver.scaling") && err.contains("units"),
            "{err}"
        );
        let err = load_with(&[
            "solver.scaling=\"units\"",
            "solver.ipopt.nlp_scaling_method=\"gradient-based\"",
        ])
        .unwrap_err()
        .to_string();
        assert!(
            err.contains("field `solver.ipopt.nlp_scaling_method`") && err.contains("remove"),
            "{err}"
        );
        let explicit = load_with(&[
            "solver.scaling=\"units\"",
            "solver.ipopt.nlp_scaling_method=\"user-scaling\"",
        ]);
        assert!(explicit.is_ok());
    }

    #[test]
    fn other_units_need_explicit_gravity() {
        let dir = dir_with_hopper_urdf();
        let text = hopper_text().replace("gravity = [0.0, 0.0, -9.81]", "units = \"mm g ms\"");
        std::fs::write(dir.path().join("p.toml"), text).unwrap();
        let err = load(&dir.path().join("p.toml"), &[])
            .unwrap_err()
            .to_string();
        assert!(
            err.contains("field `robot.gravity`") && err.contains("mm g ms"),
            "{err}"
        );
        let o = [Override::parse("robot.gravity=[0, 0, -9.81e-3]").unwrap()];
        let p = load(&dir.path().join("p.toml"), &o).unwrap();
        assert_eq!(p.spec.robot.gravity, [0.0, 0.0, -9.81e-3]);
        assert_eq!(p.units.force(), "g·mm/ms²");
    }
}
