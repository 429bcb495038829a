//! Checks of single values and of vectors given by name, shared by the sections.

use super::context::Context;
use crate::problem::ProblemError;
use crate::problem::error::list_names;
use crate::problem::schema::NamedVector;

/// Largest magnitude of a number in a problem file (docs/problem-file.md, "Sane ranges"):
/// beyond it, squares and products downstream overflow or swamp the other terms.
pub(crate) const MAX_MAGNITUDE: f64 = 1e12;

/// Smallest positive step, width or weight (docs/problem-file.md, "Sane ranges"): below
/// it, quotients downstream overflow.
pub(crate) const MIN_POSITIVE: f64 = 1e-12;

pub(crate) fn finite(ctx: &Context, field: &str, v: f64) -> Result<f64, ProblemError> {
    if v.is_finite() && v.abs() <= MAX_MAGNITUDE {
        Ok(v)
    } else {
        Err(ctx.invalid(
            field,
            format!("must be a finite number of magnitude at most {MAX_MAGNITUDE:e}, got {v}"),
        ))
    }
}

pub(super) fn positive(ctx: &Context, field: &str, v: f64) -> Result<f64, ProblemError> {
    if v.is_finite() && (MIN_POSITIVE..=MAX_MAGNITUDE).contains(&v) {
        Ok(v)
    } else {
        Err(ctx.invalid(
            field,
            format!("must be a number in [{MIN_POSITIVE:e}, {MAX_MAGNITUDE:e}], got {v}"),
        ))
    }
}

pub(crate) fn nonnegative(ctx: &Context, field: &str, v: f64) -> Result<f64, ProblemError> {
    if v.is_finite() && (0.0..=MAX_MAGNITUDE).contains(&v) {
        Ok(v)
    } else {
        Err(ctx.invalid(
            field,
            format!("must be a number in [0, {MAX_MAGNITUDE:e}], got {v}"),
        ))
    }
}

/// A bound `[lower, upper]` where an infinite end means none: no NaN, no `lower = +inf` or
/// `upper = -inf`, finite ends within [`MAX_MAGNITUDE`], and `lower ≤ upper`.
pub(super) fn bound(
    ctx: &Context,
    field: &str,
    lower: f64,
    upper: f64,
) -> Result<crate::problem::Interval, ProblemError> {
    let end = |v: f64, infinite_ok: f64| v.is_nan() || (v.is_infinite() && v != infinite_ok);
    if end(lower, f64::NEG_INFINITY) || end(upper, f64::INFINITY) {
        return Err(ctx.invalid(
            field,
            format!(
                "bound [{lower}, {upper}] is not a range: give numbers (leave an end out, or \
                 write -inf/inf, for no bound on that side)"
            ),
        ));
    }
    for v in [lower, upper] {
        if v.is_finite() && v.abs() > MAX_MAGNITUDE {
            return Err(ctx.invalid(
                field,
                format!(
                    "bound end {v} exceeds {MAX_MAGNITUDE:e} in magnitude; leave the end out \
                     for no bound"
                ),
            ));
        }
    }
    if lower > upper {
        return Err(ctx.invalid(
            field,
            format!("empty bound [{lower}, {upper}]: lower must be ≤ upper"),
        ));
    }
    Ok(crate::problem::Interval { lower, upper })
}

/// A name the problem file defines (a contact's): not empty, at most 200 bytes, no control
/// or invisible formatting characters (they would reach the terminal, the CSV header and
/// directory names).
pub(super) fn plain_name<'a>(
    ctx: &Context,
    field: &str,
    name: &'a str,
) -> Result<&'a str, ProblemError> {
    let shown = crate::files::names::escape_controls(name);
    if name.is_empty() || name.len() > 200 {
        return Err(ctx.invalid(
            field,
            format!("must be 1 to 200 bytes long, got {} bytes", name.len()),
        ));
    }
    if name.chars().any(crate::files::names::is_hidden_char) {
        return Err(ctx.invalid(
            field,
            format!(
                "\"{shown}\" holds control or invisible formatting characters (such as a \
                 right-to-left override); use printable text"
            ),
        ));
    }
    Ok(name)
}

/// The problem's `name`, which names its output directory `out/<name>`: a plain file-name
/// component ([`plain_name`], and no `/`, not `.` or `..`).
pub(super) fn file_name_component<'a>(
    ctx: &Context,
    field: &str,
    name: &'a str,
) -> Result<&'a str, ProblemError> {
    plain_name(ctx, field, name)?;
    if name.contains('/') || name == "." || name == ".." {
        return Err(ctx.invalid(
            field,
            format!(
                "\"{name}\" is not a plain file name (it names the output directory \
                 out/<name>): no `/`, not `.` or `..`"
            ),
        ));
    }
    Ok(name)
}

/// Resolves a vector over `names`: an array must have the full length; a table names
/// entries (plus `default`), and missing entries come from `fallback`, else it is an error.
pub(crate) fn resolve(
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
