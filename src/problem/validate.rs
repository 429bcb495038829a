//! Problem file → checked [`ProblemSpec`]: TOML parsing with `--set` overrides, name
//! resolution against the robot, and every check a user can fail, each error naming the
//! file, line and field (and the nearest valid name for a typo).

#![warn(missing_docs)]

use std::path::{Path, PathBuf};

use sha2::{Digest, Sha256};

use crate::contact::{Step, Terrain};
use crate::model::BaseType;
use crate::problem::error::list_names;
use crate::problem::schema::*;
use crate::problem::source::{line_of_offset, line_of_path, nearest, path_at_offset};
use crate::problem::{
    ContactSpec, CoordinateBound, CostTerm, HessianMode, InitialGuess, Integrator, Interval,
    KnotSet, Location, OptionValue, Periodicity, ProblemError, ProblemSpec, RobotInfo, RobotSpec,
    SlackContinuation, SlackMode, TimeSteps, WarmStart,
};

/// A `--set key.path=value` override, as given and as parsed.
#[derive(Debug, Clone, PartialEq)]
pub struct Override {
    /// TOML path, e.g. `slack.weight` or `cost[0].time_weighted`.
    pub path: String,
    /// The value as a TOML value (a bare word that is not TOML becomes a string).
    pub value: toml::Value,
}

impl Override {
    /// Parses `key.path=value`.
    pub fn parse(arg: &str) -> Result<Override, ProblemError> {
        let err = |message: &str| ProblemError::Override {
            arg: arg.to_owned(),
            message: message.to_owned(),
        };
        let (path, raw) = arg
            .split_once('=')
            .ok_or_else(|| err("expected key.path=value"))?;
        let path = path.trim();
        if path.is_empty() {
            return Err(err("the key path is empty"));
        }
        let raw = raw.trim();
        let value = match toml::from_str::<toml::Table>(&format!("v = {raw}")) {
            Ok(mut t) => t.remove("v").ok_or_else(|| err("no value"))?,
            Err(_) => toml::Value::String(raw.to_owned()),
        };
        if matches!(value, toml::Value::Table(_)) {
            return Err(err("only scalar and array values can be set"));
        }
        Ok(Override {
            path: path.to_owned(),
            value,
        })
    }

    fn apply(&self, root: &mut toml::Table) -> Result<(), ProblemError> {
        let err = |message: String| ProblemError::Override {
            arg: format!("{}={}", self.path, self.value),
            message,
        };
        let parts: Vec<&str> = self.path.split('.').collect();
        let mut table = root;
        for (i, part) in parts.iter().enumerate() {
            let (key, index) = match part.split_once('[') {
                Some((k, rest)) => {
                    let idx: usize = rest
                        .trim_end_matches(']')
                        .parse()
                        .map_err(|_| err(format!("bad index in `{part}`")))?;
                    (k, Some(idx))
                }
                None => (*part, None),
            };
            let last = i + 1 == parts.len();
            match (index, last) {
                (None, true) => {
                    table.insert(key.to_owned(), self.value.clone());
                    return Ok(());
                }
                (None, false) => {
                    let entry = table
                        .entry(key.to_owned())
                        .or_insert_with(|| toml::Value::Table(toml::Table::new()));
                    table = entry
                        .as_table_mut()
                        .ok_or_else(|| err(format!("`{key}` is not a table")))?;
                }
                (Some(idx), _) => {
                    let array = table
                        .get_mut(key)
                        .and_then(|v| v.as_array_mut())
                        .ok_or_else(|| err(format!("`{key}` is not an array in the file")))?;
                    let len = array.len();
                    let element = array.get_mut(idx).ok_or_else(|| {
                        err(format!(
                            "`{key}` has {len} elements, index {idx} is out of range"
                        ))
                    })?;
                    if last {
                        *element = self.value.clone();
                        return Ok(());
                    }
                    table = element
                        .as_table_mut()
                        .ok_or_else(|| err(format!("`{key}[{idx}]` is not a table")))?;
                }
            }
        }
        Ok(())
    }
}

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
    /// Output directory from the file (`output.dir`), if any.
    pub output_dir: Option<PathBuf>,
    /// Length, mass and time unit names (from `robot.units`; SI by default).
    pub units: Units,
    /// Free text from the file.
    pub description: Option<String>,
    /// The goal pose q_goal (the centre of the q_N box; q_1 when the file has none).
    pub goal: Vec<f64>,
}

impl LoadedProblem {
    /// An error about `field` (a TOML path such as `solver.ipopt.tol`) located in the
    /// problem file, for checks made after loading (e.g. by Ipopt).
    pub fn field_error(&self, field: &str, message: impl Into<String>) -> ProblemError {
        let ctx = Context {
            file: self.file.clone(),
            text: std::fs::read_to_string(&self.file).unwrap_or_default(),
            overridden: self.parameters.iter().map(|(p, _)| p.clone()).collect(),
        };
        ctx.invalid(field, message)
    }
}

/// Unit names for labels in outputs.
#[derive(Debug, Clone, PartialEq)]
pub struct Units {
    /// Length unit, e.g. `m`.
    pub length: String,
    /// Mass unit, e.g. `kg`.
    pub mass: String,
    /// Time unit, e.g. `s`.
    pub time: String,
}

impl Units {
    /// Force unit name: N in SI, else mass·length/time².
    pub fn force(&self) -> String {
        if self.is_si() {
            "N".into()
        } else {
            format!("{}·{}/{}²", self.mass, self.length, self.time)
        }
    }
    fn is_si(&self) -> bool {
        self.length == "m" && self.mass == "kg" && self.time == "s"
    }
}

/// Reads, overrides and checks a problem file.
pub fn load(path: &Path, overrides: &[Override]) -> Result<LoadedProblem, ProblemError> {
    let bytes = std::fs::read(path).map_err(|source| ProblemError::Io {
        path: path.to_owned(),
        source,
    })?;
    let sha256: String = Sha256::digest(&bytes)
        .iter()
        .map(|b| format!("{b:02x}"))
        .collect();
    let text = String::from_utf8(bytes).map_err(|_| ProblemError::Invalid {
        at: Box::new(Location {
            file: path.to_owned(),
            line: None,
            field: String::new(),
            from_override: false,
        }),
        message: "the file is not UTF-8 text".into(),
    })?;
    let ctx = Context {
        file: path.to_owned(),
        text: text.clone(),
        overridden: overrides.iter().map(|o| o.path.clone()).collect(),
    };
    let raw: ProblemFile = if overrides.is_empty() {
        toml::from_str(&text).map_err(|e| ctx.serde_error(&e, &text))?
    } else {
        let mut table: toml::Table =
            toml::from_str(&text).map_err(|e| ctx.serde_error(&e, &text))?;
        for o in overrides {
            o.apply(&mut table)?;
        }
        let rewritten = toml::to_string(&table).map_err(|e| ProblemError::Override {
            arg: String::new(),
            message: e.to_string(),
        })?;
        toml::from_str(&rewritten).map_err(|e| ctx.serde_error(&e, &rewritten))?
    };
    let mut loaded = check(&ctx, raw)?;
    loaded.sha256 = sha256;
    loaded.parameters = overrides
        .iter()
        .map(|o| (o.path.clone(), o.value.to_string()))
        .collect();
    Ok(loaded)
}

/// The file being checked, for locating fields.
struct Context {
    file: PathBuf,
    text: String,
    overridden: Vec<String>,
}

impl Context {
    fn at(&self, field: &str) -> Box<Location> {
        let from_override = self
            .overridden
            .iter()
            .any(|o| field == o || field.starts_with(&format!("{o}.")));
        Box::new(Location {
            file: self.file.clone(),
            line: if from_override {
                None
            } else {
                line_of_path(&self.text, field).or_else(|| parent_line(&self.text, field))
            },
            field: field.to_owned(),
            from_override,
        })
    }

    fn invalid(&self, field: &str, message: impl Into<String>) -> ProblemError {
        ProblemError::Invalid {
            at: self.at(field),
            message: message.into(),
        }
    }

    fn unknown_name(
        &self,
        field: &str,
        kind: &'static str,
        name: &str,
        valid: &[String],
    ) -> ProblemError {
        ProblemError::UnknownName {
            at: self.at(field),
            kind,
            name: name.to_owned(),
            suggestion: nearest(name, valid.iter().map(String::as_str)),
            valid: list_names(valid, 24),
        }
    }

    /// Turns a TOML/serde error on `parsed` (the file, or the file with overrides) into
    /// a located error; unknown keys get the nearest valid key.
    fn serde_error(&self, e: &toml::de::Error, parsed: &str) -> ProblemError {
        let message = e.message().trim().to_owned();
        let span = e.span();
        let field = span
            .clone()
            .map(|s| path_at_offset(parsed, s.start))
            .unwrap_or_default();
        let mut at = if field.is_empty() {
            Box::new(Location {
                file: self.file.clone(),
                line: span
                    .map(|s| line_of_offset(parsed, s.start))
                    .filter(|_| parsed == self.text),
                field: String::new(),
                from_override: false,
            })
        } else {
            self.at(&field)
        };
        if at.line.is_none() && parsed == self.text {
            at.line = e.span().map(|s| line_of_offset(parsed, s.start));
        }
        for prefix in ["unknown field `", "unknown variant `"] {
            if let Some(rest) = message.strip_prefix(prefix) {
                let key = rest.split('`').next().unwrap_or_default().to_owned();
                let expected: Vec<String> = rest
                    .split_once("expected")
                    .map(|(_, list)| {
                        list.split('`')
                            .skip(1)
                            .step_by(2)
                            .map(str::to_owned)
                            .collect()
                    })
                    .unwrap_or_default();
                return ProblemError::UnknownKey {
                    at,
                    what: if prefix.contains("variant") {
                        "value"
                    } else {
                        "key"
                    },
                    suggestion: nearest(&key, expected.iter().map(String::as_str)),
                    key,
                    valid: list_names(&expected, 40),
                };
            }
        }
        if e.span().is_some() && message_is_syntax(&message) {
            return ProblemError::Syntax { at, message };
        }
        ProblemError::Invalid { at, message }
    }
}

/// Errors of the TOML grammar rather than of the schema.
fn message_is_syntax(message: &str) -> bool {
    !(message.starts_with("missing field")
        || message.starts_with("invalid type")
        || message.starts_with("invalid value")
        || message.starts_with("invalid length")
        || message.starts_with("data did not match"))
}

/// Line of the nearest enclosing path that is in the file (for fields that are missing).
fn parent_line(text: &str, field: &str) -> Option<usize> {
    let mut path = field;
    while let Some(cut) = path.rfind(['.', '[']) {
        path = &path[..cut];
        if let Some(line) = line_of_path(text, path) {
            return Some(line);
        }
    }
    None
}

fn finite(ctx: &Context, field: &str, v: f64) -> Result<f64, ProblemError> {
    if v.is_finite() {
        Ok(v)
    } else {
        Err(ctx.invalid(field, format!("must be a finite number, got {v}")))
    }
}

fn positive(ctx: &Context, field: &str, v: f64) -> Result<f64, ProblemError> {
    if v.is_finite() && v > 0.0 {
        Ok(v)
    } else {
        Err(ctx.invalid(field, format!("must be a finite number > 0, got {v}")))
    }
}

/// Resolves a vector over `names`: an array must have the full length; a table names
/// entries (plus `default`), and missing entries come from `fallback`, else it is an error.
fn resolve(
    ctx: &Context,
    field: &str,
    kind: &'static str,
    names: &[String],
    vector: &NamedVector,
    fallback: Option<&[f64]>,
) -> Result<Vec<f64>, ProblemError> {
    match vector {
        NamedVector::Array(values) => {
            if values.len() != names.len() {
                return Err(ctx.invalid(
                    field,
                    format!(
                        "has {} values but the robot has {} {kind}s ({}); give one per {kind} or use a table by name",
                        values.len(),
                        names.len(),
                        list_names(names, 24)
                    ),
                ));
            }
            for (i, v) in values.iter().enumerate() {
                finite(ctx, &format!("{field}[{i}]"), *v)?;
            }
            Ok(values.clone())
        }
        NamedVector::Table(entries) => {
            let default = entries.iter().find(|(k, _)| k == "default").map(|e| e.1);
            let mut out: Vec<Option<f64>> = match (default, fallback) {
                (Some(d), _) => vec![Some(d); names.len()],
                (None, Some(f)) => f.iter().copied().map(Some).collect(),
                (None, None) => vec![None; names.len()],
            };
            for (name, value) in entries {
                let entry_field = format!("{field}.{name}");
                finite(ctx, &entry_field, *value)?;
                if name == "default" {
                    continue;
                }
                let i = names
                    .iter()
                    .position(|n| n == name)
                    .ok_or_else(|| ctx.unknown_name(&entry_field, kind, name, names))?;
                out[i] = Some(*value);
            }
            let missing: Vec<&String> = names
                .iter()
                .zip(&out)
                .filter(|(_, v)| v.is_none())
                .map(|(n, _)| n)
                .collect();
            if !missing.is_empty() {
                return Err(ctx.invalid(
                    field,
                    format!(
                        "no value for the {kind}s {}; name them or add `default = ...`",
                        list_names(&missing, 24)
                    ),
                ));
            }
            Ok(out.into_iter().map(|v| v.unwrap_or(0.0)).collect())
        }
    }
}

/// SI: m, kg, s.
fn si_units() -> Units {
    Units {
        length: "m".into(),
        mass: "kg".into(),
        time: "s".into(),
    }
}

fn parse_units(ctx: &Context, units: Option<&str>) -> Result<Units, ProblemError> {
    let si = si_units();
    match units.map(str::trim) {
        None | Some("SI") | Some("si") => Ok(si),
        Some(text) => {
            let parts: Vec<&str> = text.split_whitespace().collect();
            if parts.len() != 3 {
                return Err(ctx.invalid(
                    "robot.units",
                    format!("expected \"SI\" or three unit names \"length mass time\" (e.g. \"mm g ms\"), got \"{text}\""),
                ));
            }
            Ok(Units {
                length: parts[0].into(),
                mass: parts[1].into(),
                time: parts[2].into(),
            })
        }
    }
}

fn check(ctx: &Context, raw: ProblemFile) -> Result<LoadedProblem, ProblemError> {
    let name = raw.name.clone().unwrap_or_else(|| {
        ctx.file
            .file_stem()
            .map(|s| s.to_string_lossy().into_owned())
            .unwrap_or_else(|| "problem".into())
    });
    let units = parse_units(ctx, raw.robot.units.as_deref())?;

    // Robot.
    let base = match raw.robot.base {
        BaseName::Fixed => BaseType::Fixed,
        BaseName::Planar => BaseType::Planar,
        BaseName::Floating => BaseType::Floating,
    };
    let dir = ctx.file.parent().unwrap_or(Path::new(""));
    let urdf = dir.join(&raw.robot.urdf);
    if !urdf.is_file() {
        return Err(ctx.invalid(
            "robot.urdf",
            format!(
                "URDF file {} does not exist (paths are relative to the problem file)",
                urdf.display()
            ),
        ));
    }
    let robot = RobotInfo::read(&urdf, base).map_err(|source| ProblemError::Robot {
        at: ctx.at("robot.urdf"),
        source,
    })?;
    let gravity = match raw.robot.gravity {
        Some(g) => {
            for (i, v) in g.iter().enumerate() {
                finite(ctx, &format!("robot.gravity[{i}]"), *v)?;
            }
            g
        }
        None if raw.robot.units.is_some() && units != si_units() => {
            return Err(ctx.invalid(
                "robot.gravity",
                format!(
                    "the robot uses units `{} {} {}`: give gravity in them (e.g. [0, 0, -9.81e-3] for mm/ms²)",
                    units.length, units.mass, units.time
                ),
            ));
        }
        None => [0.0, 0.0, -9.81],
    };
    let n = robot.coordinates.len();
    let m = robot.inputs.len();
    if n == 0 {
        return Err(ctx.invalid(
            "robot.base",
            "the robot has no coordinates: a fixed base and no moving joints; choose `planar` or `floating`",
        ));
    }

    // Contacts.
    let contacts = check_contacts(ctx, &raw.contacts, &robot)?;

    // Terrain.
    let mut steps = Vec::new();
    for (i, s) in raw.terrain.step.iter().enumerate() {
        let f = |k: &str| format!("terrain.step[{i}].{k}");
        steps.push(Step {
            edge_x: finite(ctx, &f("edge_x"), s.edge_x)?,
            rise: finite(ctx, &f("rise"), s.rise)?,
            width: positive(ctx, &f("width"), s.width)?,
        });
    }
    let terrain = Terrain {
        ground_height: finite(
            ctx,
            "terrain.ground_height",
            raw.terrain.ground_height.unwrap_or(0.0),
        )?,
        steps,
    };

    // Horizon.
    if raw.horizon.knots < 2 {
        return Err(ctx.invalid(
            "horizon.knots",
            format!("must be at least 2, got {}", raw.horizon.knots),
        ));
    }
    let knots = raw.horizon.knots as usize;
    let time_steps = match (raw.horizon.time_step, raw.horizon.total_time) {
        (Some(h), None) => TimeSteps::Fixed(positive(ctx, "horizon.time_step", h)?),
        (None, Some([t_min, t_max])) => {
            positive(ctx, "horizon.total_time[0]", t_min)?;
            positive(ctx, "horizon.total_time[1]", t_max)?;
            if t_min > t_max {
                return Err(ctx.invalid(
                    "horizon.total_time",
                    format!("the window [{t_min}, {t_max}] is empty: give [min, max]"),
                ));
            }
            TimeSteps::FreeEqual { t_min, t_max }
        }
        (Some(_), Some(_)) => {
            return Err(ctx.invalid(
                "horizon.total_time",
                "give either `time_step` (fixed steps) or `total_time = [min, max]` (free equal steps), not both",
            ));
        }
        (None, None) => {
            return Err(ctx.invalid(
                "horizon",
                "give `time_step` (fixed steps) or `total_time = [min, max]` (free equal steps)",
            ));
        }
    };

    // Initial and final conditions.
    let coords = &robot.coordinates;
    let q_initial = resolve(ctx, "initial.q", "coordinate", coords, &raw.initial.q, None)?;
    let v_initial = match &raw.initial.v {
        None | Some(VelocitySpec::Zero) => Some(vec![0.0; n]),
        Some(VelocitySpec::Free) => None,
        Some(VelocitySpec::Vector(v)) => Some(resolve(
            ctx,
            "initial.v",
            "coordinate",
            coords,
            v,
            Some(&vec![0.0; n]),
        )?),
    };
    let goal = match &raw.final_.q {
        Some(q) => resolve(ctx, "final.q", "coordinate", coords, q, Some(&q_initial))?,
        None => q_initial.clone(),
    };
    let tolerance = raw.final_.tolerance.unwrap_or(0.0);
    if !(tolerance.is_finite() && tolerance >= 0.0) {
        return Err(ctx.invalid("final.tolerance", format!("must be ≥ 0, got {tolerance}")));
    }
    let q_final_free = raw.final_.free.unwrap_or(false) || raw.final_.q.is_none();
    if q_final_free && raw.final_.tolerance.is_some() {
        return Err(ctx.invalid(
            "final.tolerance",
            "applies to a goal `final.q`, but q_N is free here",
        ));
    }
    let q_final = if q_final_free {
        vec![Interval::FREE; n]
    } else {
        goal.iter()
            .map(|&g| Interval {
                lower: g - tolerance,
                upper: g + tolerance,
            })
            .collect()
    };

    // Bounds.
    let mut bounds = Vec::new();
    for (i, b) in raw.bounds.iter().enumerate() {
        let field = format!("bounds[{i}]");
        let coordinate = robot.coordinate_index(&b.coordinate).ok_or_else(|| {
            ctx.unknown_name(
                &format!("{field}.coordinate"),
                "coordinate",
                &b.coordinate,
                coords,
            )
        })?;
        let knots_set = match &b.knots {
            None => KnotSet::All,
            Some(KnotsName::Named(s)) => match s.as_str() {
                "all" => KnotSet::All,
                "interior" => KnotSet::Interior,
                "first" => KnotSet::First,
                "last" => KnotSet::Last,
                other => {
                    let valid = ["all", "interior", "first", "last"].map(String::from);
                    return Err(ctx.unknown_name(
                        &format!("{field}.knots"),
                        "knot set",
                        other,
                        &valid,
                    ));
                }
            },
            Some(KnotsName::List(list)) => {
                let mut out = Vec::new();
                for &k in list {
                    if k < 0 || k as usize >= knots {
                        return Err(ctx.invalid(
                            &format!("{field}.knots"),
                            format!("knot {k} is outside 0..{} (knots are 0-based)", knots - 1),
                        ));
                    }
                    out.push(k as usize);
                }
                KnotSet::List(out)
            }
        };
        let lower = b.lower.unwrap_or(f64::NEG_INFINITY);
        let upper = b.upper.unwrap_or(f64::INFINITY);
        if lower.is_nan() || upper.is_nan() || lower > upper {
            return Err(ctx.invalid(&field, format!("empty bound [{lower}, {upper}]")));
        }
        if b.lower.is_none() && b.upper.is_none() {
            return Err(ctx.invalid(&field, "give `lower`, `upper` or both"));
        }
        bounds.push(CoordinateBound {
            coordinate,
            knots: knots_set,
            bound: Interval { lower, upper },
        });
    }
    let joint_limits = raw.robot.joint_limits.unwrap_or(true);

    // Inputs.
    let mut input_bounds: Vec<Interval> = if raw.inputs.effort_limits.unwrap_or(true) {
        robot
            .effort_limits
            .iter()
            .map(|&e| Interval {
                lower: -e,
                upper: e,
            })
            .collect()
    } else {
        vec![Interval::FREE; m]
    };
    for (input, [lower, upper]) in &raw.inputs.bounds {
        let field = format!("inputs.bounds.{input}");
        let j = robot
            .input_index(input)
            .ok_or_else(|| ctx.unknown_name(&field, "input", input, &robot.inputs))?;
        if lower.is_nan() || upper.is_nan() || lower > upper {
            return Err(ctx.invalid(&field, format!("empty bound [{lower}, {upper}]")));
        }
        input_bounds[j] = Interval {
            lower: *lower,
            upper: *upper,
        };
    }

    // Costs.
    let mut costs = Vec::new();
    let zeros_n = vec![0.0; n];
    for (i, c) in raw.cost.iter().enumerate() {
        let f = |k: &str| format!("cost[{i}].{k}");
        let term = match c {
            CostEntry::StateTracking {
                q_target,
                v_target,
                q_weights,
                v_weights,
                time_weighted,
            } => CostTerm::StateTracking {
                q_target: match q_target {
                    Some(t) => resolve(ctx, &f("q_target"), "coordinate", coords, t, Some(&goal))?,
                    None => goal.clone(),
                },
                v_target: match v_target {
                    Some(t) => {
                        resolve(ctx, &f("v_target"), "coordinate", coords, t, Some(&zeros_n))?
                    }
                    None => zeros_n.clone(),
                },
                q_weights: weights(ctx, &f("q_weights"), coords, "coordinate", q_weights)?,
                v_weights: match v_weights {
                    Some(w) => weights(ctx, &f("v_weights"), coords, "coordinate", w)?,
                    None => zeros_n.clone(),
                },
                time_weighted: time_weighted.unwrap_or(true),
            },
            CostEntry::Input {
                weights: w,
                time_weighted,
            } => CostTerm::Input {
                weights: weights(ctx, &f("weights"), &robot.inputs, "input", w)?,
                time_weighted: time_weighted.unwrap_or(true),
            },
            CostEntry::InputRate { weights: w } => CostTerm::InputRate {
                weights: weights(ctx, &f("weights"), &robot.inputs, "input", w)?,
            },
            CostEntry::ConfigurationDifference { weights: w } => {
                CostTerm::ConfigurationDifference {
                    weights: weights(ctx, &f("weights"), coords, "coordinate", w)?,
                }
            }
            CostEntry::FinalState {
                q_target,
                weights: w,
            } => CostTerm::FinalState {
                q_target: match q_target {
                    Some(t) => resolve(ctx, &f("q_target"), "coordinate", coords, t, Some(&goal))?,
                    None => goal.clone(),
                },
                weights: weights(ctx, &f("weights"), coords, "coordinate", w)?,
            },
            CostEntry::Time { weight } => CostTerm::Time {
                weight: nonnegative(ctx, &f("weight"), *weight)?,
            },
        };
        costs.push(term);
    }

    // Slack.
    let slack_weight = positive(ctx, "slack.weight", raw.slack.weight)?;
    let slack_mode = match raw.slack.mode.as_deref() {
        None | Some("per_interval") => SlackMode::PerInterval,
        Some("per_contact") => SlackMode::PerContact,
        Some(other) => {
            let valid = ["per_interval", "per_contact"].map(String::from);
            return Err(ctx.unknown_name("slack.mode", "slack mode", other, &valid));
        }
    };

    let max_slip_speed = raw
        .contacts
        .max_slip_speed
        .map(|v| positive(ctx, "contacts.max_slip_speed", v))
        .transpose()?;
    let slack_continuation = match raw.slack.target {
        None => {
            for (field, given) in [
                ("slack.growth", raw.slack.growth.is_some()),
                ("slack.rounds", raw.slack.rounds.is_some()),
            ] {
                if given {
                    return Err(ctx.invalid(
                        field,
                        "has no effect without `slack.target`; give the target slack too",
                    ));
                }
            }
            None
        }
        Some(target) => {
            let growth = raw.slack.growth.unwrap_or(10.0);
            if !(growth > 1.0 && growth.is_finite()) {
                return Err(ctx.invalid(
                    "slack.growth",
                    format!(
                        "must be a number above 1 (the weight's factor per solve), got {growth}"
                    ),
                ));
            }
            Some(SlackContinuation {
                target: positive(ctx, "slack.target", target)?,
                growth,
                rounds: raw.slack.rounds.unwrap_or(3),
            })
        }
    };

    // Periodicity.
    let mut periodic = Vec::new();
    for (i, p) in raw.periodic.iter().enumerate() {
        let field = format!("periodic[{i}].coordinate");
        let coordinate = robot
            .coordinate_index(&p.coordinate)
            .ok_or_else(|| ctx.unknown_name(&field, "coordinate", &p.coordinate, coords))?;
        periodic.push(Periodicity {
            coordinate,
            position: p.position.unwrap_or(true),
            offset: finite(
                ctx,
                &format!("periodic[{i}].offset"),
                p.offset.unwrap_or(0.0),
            )?,
            velocity: p.velocity.unwrap_or(false),
        });
    }

    // Initial guess.
    let initial_guess = match (&raw.initial_guess.warm_start, &raw.initial_guess.to) {
        (Some(_), Some(_)) => {
            return Err(ctx.invalid(
                "initial_guess.warm_start",
                "give either `warm_start` or `to`, not both",
            ));
        }
        (Some(csv), None) => InitialGuess::WarmStart(read_warm_start(ctx, &dir.join(csv), &robot)?),
        (None, to) => InitialGuess::Linear {
            from: q_initial.clone(),
            to: match to {
                None | Some(GuessTarget::Final) => goal.clone(),
                Some(GuessTarget::Initial) => q_initial.clone(),
                Some(GuessTarget::Pose(p)) => resolve(
                    ctx,
                    "initial_guess.to",
                    "coordinate",
                    coords,
                    p,
                    Some(&q_initial),
                )?,
            },
        },
    };

    // Solver.
    let integrator = match raw.solver.integrator.as_deref() {
        None | Some("midpoint") => Integrator::Midpoint,
        Some("euler") => Integrator::Euler,
        Some(other) => {
            let valid = ["midpoint", "euler"].map(String::from);
            return Err(ctx.unknown_name("solver.integrator", "integrator", other, &valid));
        }
    };
    let hessian = match raw.solver.hessian.as_deref() {
        None | Some("exact") => HessianMode::Exact,
        Some("lbfgs") => HessianMode::Lbfgs,
        Some(other) => {
            let valid = ["exact", "lbfgs"].map(String::from);
            return Err(ctx.unknown_name("solver.hessian", "Hessian mode", other, &valid));
        }
    };
    let mut solver_options = Vec::new();
    for (key, value) in &raw.solver.ipopt {
        let field = format!("solver.ipopt.{key}");
        let v = match value {
            toml::Value::String(s) => OptionValue::Str(s.clone()),
            toml::Value::Integer(i) => OptionValue::Int(*i),
            toml::Value::Float(x) => OptionValue::Num(*x),
            _ => {
                return Err(ctx.invalid(
                    &field,
                    "an Ipopt option is a string, an integer or a number",
                ));
            }
        };
        if key == "linear_solver" && matches!(&v, OptionValue::Str(s) if s != "mumps") {
            return Err(ctx.invalid(
                &field,
                "only `mumps` is available in Debian's Ipopt (HSL solvers make it exit or fail)",
            ));
        }
        solver_options.push((key.clone(), v));
    }

    check_bounds_feasible(
        ctx,
        &robot,
        knots,
        joint_limits,
        &bounds,
        &q_initial,
        &q_final,
    )?;

    let spec = ProblemSpec {
        name,
        robot: RobotSpec {
            urdf,
            base,
            gravity,
        },
        contacts,
        terrain,
        knots,
        time_steps,
        integrator,
        slack_weight,
        slack_mode,
        slack_continuation,
        max_slip_speed,
        q_initial,
        v_initial,
        q_final,
        bounds,
        joint_limits,
        input_bounds,
        costs,
        periodic,
        initial_guess,
        hessian,
        solver_options,
    };
    Ok(LoadedProblem {
        spec,
        robot,
        file: ctx.file.clone(),
        sha256: String::new(),
        parameters: Vec::new(),
        output_dir: raw.output.dir.map(PathBuf::from),
        units,
        description: raw.description,
        goal,
    })
}

/// Whether a knot set holds knot `k` of `knots`.
fn knot_in(set: &KnotSet, k: usize, knots: usize) -> bool {
    match set {
        KnotSet::All => true,
        KnotSet::Interior => k > 0 && k + 1 < knots,
        KnotSet::First => k == 0,
        KnotSet::Last => k + 1 == knots,
        KnotSet::List(list) => list.contains(&k),
    }
}

/// Every knot of every coordinate must have a non-empty box (joint limits ∩ bounds ∩ the
/// fixed q_1 ∩ the q_N goal box), or Ipopt would be handed an infeasible problem.
#[allow(clippy::too_many_arguments)]
fn check_bounds_feasible(
    ctx: &Context,
    robot: &RobotInfo,
    knots: usize,
    joint_limits: bool,
    bounds: &[CoordinateBound],
    q_initial: &[f64],
    q_final: &[Interval],
) -> Result<(), ProblemError> {
    const SLACK: f64 = 1e-12;
    for (j, name) in robot.coordinates.iter().enumerate() {
        for k in [0, knots - 1].into_iter().chain(1..knots.saturating_sub(1)) {
            let mut lower = f64::NEG_INFINITY;
            let mut upper = f64::INFINITY;
            let mut parts = Vec::new();
            let mut culprit = None;
            if joint_limits {
                let l = robot.coordinate_limits[j];
                if l.lower.is_finite() || l.upper.is_finite() {
                    lower = lower.max(l.lower);
                    upper = upper.min(l.upper);
                    parts.push(format!("URDF limits [{}, {}]", l.lower, l.upper));
                }
            }
            for (i, b) in bounds.iter().enumerate() {
                if b.coordinate == j && knot_in(&b.knots, k, knots) {
                    lower = lower.max(b.bound.lower);
                    upper = upper.min(b.bound.upper);
                    parts.push(format!(
                        "bounds[{i}] [{}, {}]",
                        b.bound.lower, b.bound.upper
                    ));
                    culprit = Some(format!("bounds[{i}]"));
                }
            }
            let field = if k == 0 {
                if q_initial[j] < lower - SLACK || q_initial[j] > upper + SLACK {
                    return Err(ctx.invalid(
                        &format!("initial.q.{name}"),
                        format!(
                            "q_1 {name} = {} is outside {} (set joint_limits = false or change the pose)",
                            q_initial[j],
                            parts.join(" ∩ ")
                        ),
                    ));
                }
                continue;
            } else if k + 1 == knots {
                let f = q_final[j];
                if f.lower.is_finite() || f.upper.is_finite() {
                    lower = lower.max(f.lower);
                    upper = upper.min(f.upper);
                    parts.push(format!("final [{}, {}]", f.lower, f.upper));
                    format!("final.q.{name}")
                } else {
                    culprit
                        .clone()
                        .unwrap_or_else(|| "robot.joint_limits".into())
                }
            } else {
                culprit
                    .clone()
                    .unwrap_or_else(|| "robot.joint_limits".into())
            };
            if lower > upper + SLACK {
                return Err(ctx.invalid(
                    &field,
                    format!(
                        "coordinate `{name}` has no feasible value at knot {k}: {} is empty",
                        parts.join(" ∩ ")
                    ),
                ));
            }
        }
    }
    Ok(())
}

fn nonnegative(ctx: &Context, field: &str, v: f64) -> Result<f64, ProblemError> {
    if v.is_finite() && v >= 0.0 {
        Ok(v)
    } else {
        Err(ctx.invalid(field, format!("must be a finite number ≥ 0, got {v}")))
    }
}

fn weights(
    ctx: &Context,
    field: &str,
    names: &[String],
    kind: &'static str,
    w: &NamedVector,
) -> Result<Vec<f64>, ProblemError> {
    let values = resolve(ctx, field, kind, names, w, None)?;
    if let Some((i, v)) = values.iter().enumerate().find(|(_, v)| **v < 0.0) {
        return Err(ctx.invalid(
            field,
            format!("weight of `{}` is {v}; weights must be ≥ 0", names[i]),
        ));
    }
    Ok(values)
}

fn check_contacts(
    ctx: &Context,
    section: &ContactsSection,
    robot: &RobotInfo,
) -> Result<Vec<ContactSpec>, ProblemError> {
    let default_friction = nonnegative(ctx, "contacts.friction", section.friction.unwrap_or(1.0))?;
    let selection = section
        .from_urdf
        .clone()
        .unwrap_or(if section.point.is_empty() {
            ContactSelection::All
        } else {
            ContactSelection::None
        });
    let mut contacts: Vec<ContactSpec> = Vec::new();
    let urdf_names: Vec<String> = robot.contacts.iter().map(|c| c.name.clone()).collect();
    let from_urdf = |c: &crate::problem::UrdfContact| ContactSpec {
        name: c.name.clone(),
        link: c.link.clone(),
        point: c.point,
        friction: default_friction,
    };
    match &selection {
        ContactSelection::All => contacts.extend(robot.contacts.iter().map(from_urdf)),
        ContactSelection::None => {}
        ContactSelection::Names(names) => {
            for (i, name) in names.iter().enumerate() {
                let c = robot
                    .contacts
                    .iter()
                    .find(|c| &c.name == name)
                    .ok_or_else(|| {
                        ctx.unknown_name(
                            &format!("contacts.from_urdf[{i}]"),
                            "URDF contact",
                            name,
                            &urdf_names,
                        )
                    })?;
                contacts.push(from_urdf(c));
            }
        }
    }
    for (i, p) in section.point.iter().enumerate() {
        let f = |k: &str| format!("contacts.point[{i}].{k}");
        if !robot.links.contains(&p.link) {
            return Err(ctx.unknown_name(&f("link"), "link", &p.link, &robot.links));
        }
        for (j, v) in p.point.iter().enumerate() {
            finite(ctx, &format!("{}[{j}]", f("point")), *v)?;
        }
        contacts.push(ContactSpec {
            name: p.name.clone(),
            link: p.link.clone(),
            point: p.point,
            friction: match p.friction {
                Some(mu) => nonnegative(ctx, &f("friction"), mu)?,
                None => default_friction,
            },
        });
    }
    for (i, c) in contacts.iter().enumerate() {
        if contacts[..i].iter().any(|d| d.name == c.name) {
            return Err(ctx.invalid(
                "contacts",
                format!(
                    "two contacts are named `{}`; contact names must be unique",
                    c.name
                ),
            ));
        }
    }
    let names: Vec<String> = contacts.iter().map(|c| c.name.clone()).collect();
    for (name, mu) in &section.friction_by_name {
        let field = format!("contacts.friction_by_name.{name}");
        let mu = nonnegative(ctx, &field, *mu)?;
        let c = contacts
            .iter_mut()
            .find(|c| &c.name == name)
            .ok_or_else(|| ctx.unknown_name(&field, "contact", name, &names))?;
        c.friction = mu;
    }
    Ok(contacts)
}

/// Reads a `trajectory.csv` written by vito: the time column, one column per coordinate
/// (by name) and, when present, one per input.
fn read_warm_start(
    ctx: &Context,
    path: &Path,
    robot: &RobotInfo,
) -> Result<WarmStart, ProblemError> {
    let field = "initial_guess.warm_start";
    let err = |message: String| ProblemError::WarmStart {
        at: ctx.at(field),
        path: path.to_owned(),
        message,
    };
    let text = std::fs::read_to_string(path).map_err(|e| err(format!("cannot read it: {e}")))?;
    let recorded = crate::trajectory_csv::read_trajectory(&text, &robot.coordinates, &robot.inputs)
        .map_err(err)?;
    Ok(WarmStart {
        source: path.to_owned(),
        times: recorded.times,
        q: recorded.q,
        u: recorded.u,
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    fn problems_dir() -> PathBuf {
        Path::new(env!("CARGO_MANIFEST_DIR")).join("problems")
    }

    #[test]
    fn override_parses_toml_values_and_bare_words() {
        let o = Override::parse("slack.weight=1e3").unwrap();
        assert_eq!(o.path, "slack.weight");
        assert_eq!(o.value, toml::Value::Float(1000.0));
        let o = Override::parse("robot.base=planar").unwrap();
        assert_eq!(o.value, toml::Value::String("planar".into()));
        let o = Override::parse("horizon.total_time=[1, 2.5]").unwrap();
        assert!(o.value.is_array());
        assert!(Override::parse("no_equals_sign").is_err());
        assert!(Override::parse("a={b=1}").is_err());
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
                CostTerm::StateTracking {
                    q_target: goal.to_vec(),
                    v_target: vec![0.0; 4],
                    q_weights: vec![1.0; 4],
                    v_weights: vec![0.0; 4],
                    time_weighted: true,
                },
                CostTerm::Input {
                    weights: vec![0.1, 0.01],
                    time_weighted: true,
                },
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
            CostTerm::StateTracking {
                q_weights,
                v_weights,
                ..
            } => {
                assert_eq!(q_weights, &vec![0.2; 9]);
                assert_eq!(v_weights, &vec![0.2; 9]);
            }
            other => panic!("expected state tracking, got {other:?}"),
        }
        assert_eq!(
            s.costs[1],
            CostTerm::Input {
                weights: vec![2.0; 4],
                time_weighted: true
            }
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
        assert_eq!(
            s.terrain.steps,
            vec![Step {
                edge_x: 0.25,
                rise: 0.11,
                width: 0.005
            }]
        );
        match &s.costs[0] {
            CostTerm::StateTracking {
                q_weights,
                q_target,
                ..
            } => {
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
    fn warm_start_reads_a_trajectory_csv_by_name() {
        let dir = tempfile::tempdir().unwrap();
        std::fs::create_dir(dir.path().join("robots")).unwrap();
        std::fs::copy(
            problems_dir().join("robots/hopper_2d.urdf"),
            dir.path().join("robots/hopper_2d.urdf"),
        )
        .unwrap();
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

    #[test]
    fn other_units_need_explicit_gravity() {
        let dir = tempfile::tempdir().unwrap();
        std::fs::create_dir(dir.path().join("robots")).unwrap();
        std::fs::copy(
            problems_dir().join("robots/hopper_2d.urdf"),
            dir.path().join("robots/hopper_2d.urdf"),
        )
        .unwrap();
        let text = std::fs::read_to_string(problems_dir().join("hopper_2d.toml"))
            .unwrap()
            .replace("gravity = [0.0, 0.0, -9.81]", "units = \"mm g ms\"");
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
