//! `[terrain]`: flat ground and the features on it, each checked by its own requirements.

use super::context::Context;
use super::values::{finite, positive};
use crate::contact::{Requirement, Terrain, TerrainFeature};
use crate::problem::ProblemError;
use crate::problem::schema::ProblemFile;

pub(super) fn check_terrain(ctx: &Context, raw: &ProblemFile) -> Result<Terrain, ProblemError> {
    let section = &raw.terrain;
    check_features(ctx, &section.step)?;
    Ok(Terrain {
        ground_height: finite(
            ctx,
            "terrain.ground_height",
            section.ground_height.unwrap_or(0.0),
        )?,
        steps: section.step.clone(),
    })
}

/// Checks every `[[terrain.<kind>]]` entry against its requirements, naming the field.
fn check_features<F: TerrainFeature>(ctx: &Context, features: &[F]) -> Result<(), ProblemError> {
    for (i, feature) in features.iter().enumerate() {
        for (key, value, requirement) in feature.requirements() {
            let field = format!("terrain.{}[{i}].{key}", F::NAME);
            match requirement {
                Requirement::Finite => finite(ctx, &field, value)?,
                Requirement::Positive => positive(ctx, &field, value)?,
            };
        }
    }
    Ok(())
}
