//! `vito study`: the accuracy studies (paper figures 5 and 6).

use std::path::{Path, PathBuf};

use vito::problem::load;
use vito::report;
use vito::study::StudyMethod;

use super::args::parse_overrides;
use super::error::CliError;

/// A progress bar counting runs (hidden when `quiet`).
pub(super) fn study_bar(quiet: bool, what: &str) -> indicatif::ProgressBar {
    let bar = if quiet {
        indicatif::ProgressBar::hidden()
    } else {
        indicatif::ProgressBar::new(0)
    };
    if let Ok(style) = indicatif::ProgressStyle::with_template(&format!(
        "{what} {{bar:40}} {{pos}}/{{len}} runs, ETA {{eta}}"
    )) {
        bar.set_style(style);
    }
    bar
}

/// Prints a study's table with each method's log-log slope of error against knot count.
pub(super) fn print_study(table: &vito::study::StudyTable) -> Result<(), CliError> {
    use vito::study::log_log_slope;
    let methods = table.methods();
    let mut header = String::from("knots");
    for m in &methods {
        header += &format!("  {:<26}", format!("{} mean ± std", m.study_name()));
    }
    out!("{}", header.trim_end());
    let mut knots: Vec<usize> = table.rows.iter().map(|r| r.knots).collect();
    knots.dedup();
    for k in knots {
        let mut line = format!("{k:>5}");
        for &m in &methods {
            let cell = table.row(k, m).map_or_else(String::new, |r| {
                format!("{:.4e} ± {:.2e}", r.mean(), r.std())
            });
            line += &format!("  {cell:<26}");
        }
        out!("{}", line.trim_end());
    }
    for m in methods {
        if let Some(slope) = log_log_slope(&table.means(m)) {
            out!("{:<12} log-log slope {slope:.3}", m.study_name());
        }
    }
    Ok(())
}

pub(super) fn brick_accuracy(
    file: &Path,
    study: &vito::study::brick::BrickAccuracy,
    out: &Path,
    quiet: bool,
) -> Result<u8, CliError> {
    study.check()?;
    let problem = load(file, &[])?;
    let protected = [problem.file.as_path(), problem.spec.robot.urdf.as_path()];
    let target = report::OutputTarget::check(out, &protected).map_err(report::ReportError::from)?;
    let bar = study_bar(quiet, "brick study");
    let table = study.run(&problem.spec, |done, total| {
        bar.set_length(total as u64);
        bar.set_position(done as u64);
    });
    bar.finish_and_clear();
    let table = table?;
    let staged = target.stage().map_err(report::ReportError::from)?;
    let title = format!(
        "Tumbling brick: RMS configuration error against the {} reference at {} steps/s",
        study.reference.study_label(),
        study.reference_rate
    );
    table.write(
        staged.path(),
        "brick_accuracy",
        &title,
        "RMS error (m, rad)",
    )?;
    let written = staged.commit().map_err(report::ReportError::from)?;
    print_study(&table)?;
    out!("written to {}", written.display());
    Ok(0)
}

pub(super) fn tracking(
    file: &Path,
    set: &[String],
    study: &vito::study::tracking::Tracking,
    out: &Path,
    quiet: bool,
) -> Result<u8, CliError> {
    study.check()?;
    let overrides = parse_overrides(set)?;
    let problem = load(file, &overrides)?;
    let protected = [problem.file.as_path(), problem.spec.robot.urdf.as_path()];
    let target = report::OutputTarget::check(out, &protected).map_err(report::ReportError::from)?;
    let bar = study_bar(quiet, "tracking study");
    let table = study.run(file, &overrides, |done, total| {
        bar.set_length(total as u64);
        bar.set_position(done as u64);
    });
    bar.finish_and_clear();
    let result = table?;
    let table = &result.table;
    let staged = target.stage().map_err(report::ReportError::from)?;
    let plans_csv = staged.path().join("tracking_plans.csv");
    vito::files::output::write_atomic(&plans_csv, result.plans_csv().as_bytes())
        .map_err(CliError::io(&plans_csv))?;
    let plans_dir = staged.path().join("plans");
    std::fs::create_dir_all(&plans_dir).map_err(CliError::io(&plans_dir))?;
    for p in &result.plans {
        let path = plans_dir.join(vito::study::tracking::TrackingResult::plan_file_name(p));
        vito::files::output::write_atomic(&path, p.trajectory_csv.as_bytes())
            .map_err(CliError::io(&path))?;
    }
    for (measure, table) in result.tables() {
        table.write(
            staged.path(),
            measure.stem,
            &format!("{}: {}", problem.spec.name, measure.title),
            measure.y_label,
        )?;
    }
    vito::study::frontier::write_frontier(
        staged.path(),
        &result.plans,
        &format!(
            "{}: error at the knots against solve cost",
            problem.spec.name
        ),
    )?;
    let written = staged.commit().map_err(report::ReportError::from)?;
    print_study(table)?;
    out!("configuration alone:");
    print_study(&result.configuration)?;
    out!("driven joints alone (q and v):");
    print_study(&result.joints)?;
    for p in &result.plans {
        let at_knots = p
            .knot_error
            .map_or(String::new(), |e| format!(", error at the knots {e:.3e}"));
        out!(
            "plan {:>3} knots {:<12} objective {:.6e}, max slack {:.2e}, {} iterations, {} variables, {:.2} s, from {}: {}{at_knots}",
            p.knots,
            p.method.study_name(),
            p.objective,
            p.max_slack,
            p.iterations,
            p.variables,
            p.wall_time_s,
            p.start,
            p.outcome
        );
    }
    out!("written to {}", written.display());
    Ok(0)
}

pub(super) fn tracking_collect(
    dirs: &[PathBuf],
    max_deviation: f64,
    out: &Path,
) -> Result<u8, CliError> {
    if !(max_deviation.is_finite() && max_deviation > 0.0) {
        return Err(vito::study::StudyError::Invalid {
            field: "--max-deviation".into(),
            message: format!("{max_deviation} is not a positive number; give e.g. 0.5"),
        }
        .into());
    }
    // Each gait's directory must survive the output's replacement.
    let inputs: Vec<PathBuf> = dirs.iter().map(|d| d.join("tracking_runs.csv")).collect();
    let protected: Vec<&Path> = inputs.iter().map(PathBuf::as_path).collect();
    let target = report::OutputTarget::check(out, &protected).map_err(report::ReportError::from)?;
    let set = vito::study::collect::collect_tracking(dirs)?;
    let staged = target.stage().map_err(report::ReportError::from)?;
    let write = |name: &str, text: &str| {
        let path = staged.path().join(name);
        vito::files::output::write_atomic(&path, text.as_bytes()).map_err(CliError::io(&path))
    };
    write("tracking_plans.csv", &set.plans_csv())?;
    let gaits = dirs.len();
    for (measure, table) in &set.tables {
        table.write(
            staged.path(),
            measure.stem,
            &format!("{}, mean ± std over {gaits} gaits", measure.title),
            measure.y_label,
        )?;
    }
    let upright = set.upright(max_deviation);
    upright.write(
        staged.path(),
        "tracking_upright",
        &format!("RMS state error of the plans tracked within {max_deviation} of their plan"),
        vito::study::tracking::TRACKING_MEASURES[0].y_label,
    )?;
    let falls = set.falls(max_deviation);
    write(
        "tracking_falls.csv",
        &vito::study::collect::falls_csv(&falls),
    )?;
    let written = staged.commit().map_err(report::ReportError::from)?;
    if let Some(table) = set.table("tracking") {
        out!("state error over {gaits} gaits:");
        print_study(table)?;
    }
    out!("plans that left their plan by more than {max_deviation} (fell) of those tracked:");
    for f in &falls {
        let unrecorded = if f.unknown > 0 {
            format!(" ({} without a recorded deviation)", f.unknown)
        } else {
            String::new()
        };
        out!(
            "{:>5}  {:<12} {} of {}{unrecorded}",
            f.knots,
            f.method.study_name(),
            f.fell,
            f.tracked
        );
    }
    out!("state error of the plans that did not fall:");
    print_study(&upright)?;
    out!("written to {}", written.display());
    Ok(0)
}
