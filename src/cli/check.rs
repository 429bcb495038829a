//! `vito check`: the problem as the solver will build it, and the derivative check.

use std::path::Path;

use vito::pipeline;
use vito::problem::{TimeSteps, load};

use super::args::parse_overrides;
use super::error::CliError;
use super::output::print_model_warnings;

pub(super) fn check(file: &Path, set: &[String]) -> Result<u8, CliError> {
    let overrides = parse_overrides(set)?;
    let p = pipeline::load_checked(file, &overrides)?;
    print_model_warnings(&p.robot, !p.spec.contacts.is_empty());
    let s = &p.spec;
    let report = pipeline::check_report(s)?;
    let size = report.size;
    let horizon = match s.time_steps {
        TimeSteps::Fixed(h) => format!(
            "{} knots, fixed h = {h} {t} (T = {} {t})",
            s.knots,
            h * (s.knots - 1) as f64,
            t = p.units.time
        ),
        TimeSteps::FreeEqual { t_min, t_max } => format!(
            "{} knots, free equal steps, T in [{t_min}, {t_max}] {}",
            s.knots, p.units.time
        ),
    };
    out!("{}: ok ({})", file.display(), s.name);
    if let Some(d) = &p.description {
        out!("  {}", d.trim());
    }
    out!(
        "  robot:       {} ({} base)",
        s.robot.urdf.display(),
        s.robot.base.name()
    );
    out!(
        "  coordinates: {} ({})",
        p.robot.coordinates.len(),
        p.robot.coordinates.join(", ")
    );
    out!(
        "  inputs:      {} ({}), from {}",
        p.robot.inputs.len(),
        p.robot.inputs.join(", "),
        p.robot.actuation
    );
    let contacts: Vec<String> = s
        .contacts
        .iter()
        .map(|c| format!("{} (mu {})", c.name, c.friction))
        .collect();
    out!(
        "  contacts:    {} ({})",
        s.contacts.len(),
        contacts.join(", ")
    );
    out!("  horizon:     {horizon}");
    // The first solve's weight; a continuation raises it (a homotopy from a thousandth of
    // the file's `slack.weight`).
    let continuation = s.slack_continuation.map_or(String::new(), |c| {
        let tied = match c.tied_sigma {
            Some(_) => ", Ipopt's tolerances tied to the relaxation",
            None => "",
        };
        format!(
            ", then ×{} per solve while the largest slack exceeds {:e}, at most {} more{tied}",
            c.growth, c.target, c.rounds
        )
    });
    out!(
        "  costs:       {} terms, slack weight {}{continuation}",
        s.costs.len(),
        s.slack_weight
    );
    out!(
        "  solved when: Ipopt's optimum with every slack <= slack.tolerance {:e} (else relaxed_contact, exit 1)",
        s.slack_tolerance
    );
    out!(
        "  NLP size:    {} variables, {} constraints, nnz J {}, nnz H {} ({} friction directions per contact, {} loop-closure rows per interval)",
        size.n_variables,
        size.n_constraints,
        size.nnz_jacobian,
        size.nnz_hessian,
        report.friction_directions,
        report.loop_rows
    );
    let feasibility = &report.feasibility;
    if !feasibility.clearances.is_empty() {
        out!(
            "  distance to the terrain [{}], first / last knot of the initial guess:",
            p.units.length
        );
        for c in &feasibility.clearances {
            out!("    {:<20} {:>11.4e} / {:.4e}", c.name, c.first, c.last);
        }
    }
    for w in &feasibility.warnings {
        note!("warning: {w}");
    }
    Ok(0)
}

/// `vito check --derivatives`: the derivative check of the solver's NLP at the initial guess
/// or at a trajectory; prints the worst entries of each kind and every failure (up to 40).
pub(super) fn check_derivatives(
    file: &Path,
    set: &[String],
    at: Option<&Path>,
    seed: u64,
) -> Result<u8, CliError> {
    use vito::transcription::{DerivativeKind, EntryNames};
    let overrides = parse_overrides(set)?;
    let p = load(file, &overrides)?;
    let nlp = pipeline::build_nlp(&p.spec)?;
    let contacts: Vec<String> = p.spec.contacts.iter().map(|c| c.name.clone()).collect();
    let x = match at {
        None => nlp.initial_point().to_vec(),
        Some(path) => {
            let text =
                vito::files::input::read_regular_text(path, vito::files::input::MAX_TEXT_BYTES)
                    .map_err(|e| CliError::Input(format!("{}: {e}", path.display())))?;
            pipeline::trajectory_point::point_from_trajectory(&nlp, &p.robot, &contacts, &text)
                .map_err(|e| CliError::Input(format!("{}: {e}", path.display())))?
        }
    };
    if let Some(i) = x.iter().position(|v| !v.is_finite()) {
        return Err(CliError::Input(format!(
            "the point to check has a non-finite value at variable {i}"
        )));
    }
    let names = EntryNames {
        coordinates: &p.robot.coordinates,
        inputs: &p.robot.inputs,
        contacts: &contacts,
    };
    let check = nlp.check_derivatives(&x, seed);
    let point = at.map_or("the initial guess".to_string(), |a| a.display().to_string());
    out!(
        "{}: derivative check at {point} ({} entries compared, {} fixed variables left out, {} evaluations, multiplier seed {seed})",
        file.display(),
        check.entries.len(),
        check.fixed_variables,
        check.evaluations
    );
    out!(
        "  tolerance: |analytic - fd| <= 1e-4 max(|analytic|, |fd|) + 1e-6 max(1, |F(x)|), steps 1e-6 max(1, |x_j|)"
    );
    for (kind, label) in [
        (DerivativeKind::Gradient, "gradient"),
        (DerivativeKind::Jacobian, "jacobian"),
        (DerivativeKind::Hessian, "hessian"),
    ] {
        let entries: Vec<_> = check.entries.iter().filter(|e| e.kind == kind).collect();
        let failed = entries.iter().filter(|e| e.fails()).count();
        let outside = entries.iter().filter(|e| !e.declared && e.fails()).count();
        out!(
            "  {label}: {} nonzero entries, {failed} exceed tolerance ({outside} outside the declared structure); worst:",
            entries.len()
        );
        for e in entries.iter().take(3) {
            out!("    {}", nlp.describe_entry(e, names));
        }
    }
    let failures: Vec<_> = check.failures().collect();
    if failures.is_empty() {
        out!("  passed");
        return Ok(0);
    }
    out!("  FAILED: {} entries exceed tolerance:", failures.len());
    for e in failures.iter().take(40) {
        out!("    {}", nlp.describe_entry(e, names));
    }
    Ok(1)
}
