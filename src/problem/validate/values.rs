//! Checks of single values and of vectors given by name, shared by the sections.

use super::context::Context;
use crate::problem::ProblemError;
use crate::problem::error::list_names;
use crate::problem::schema::NamedVector;

pub(super) fn finite(ctx: &Context, field: &str, v: f64) -> Result<f64, ProblemError> {
    if v.is_finite() {
        Ok(v)
    } else {
        Err(ctx.invalid(field, format!("must be a finite number, got {v}")))
    }
}

pub(super) fn positive(ctx: &Context, field: &str, v: f64) -> Result<f64, ProblemError> {
    if v.is_finite() && v > 0.0 {
        Ok(v)
    } else {
        Err(ctx.invalid(field, format!("must be a finite number > 0, got {v}")))
    }
}

pub(crate) fn nonnegative(ctx: &Context, field: &str, v: f64) -> Result<f64, ProblemError> {
    if v.is_finite() && v >= 0.0 {
        Ok(v)
    } else {
        Err(ctx.invalid(field, format!("must be a finite number ≥ 0, got {v}")))
    }
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
