//! `[terrain]`: flat ground and the features on it, each checked by its own requirements.

use super::context::Context;
use super::values::{finite, positive};
use crate::contact::{MAX_SLOPE_ANGLE, Requirement, Terrain, TerrainFeature, TiltedGround};
use crate::problem::ProblemError;
use crate::problem::schema::ProblemFile;
use crate::problem::{ContactSpec, RobotInfo};

pub(super) fn check_terrain(
    ctx: &Context,
    raw: &ProblemFile,
    robot: &RobotInfo,
    contacts: &[ContactSpec],
) -> Result<Terrain, ProblemError> {
    let section = &raw.terrain;
    check_features(ctx, &section.step)?;
    Ok(Terrain {
        ground_height: finite(
            ctx,
            "terrain.ground_height",
            section.ground_height.unwrap_or(0.0),
        )?,
        steps: section.step.clone(),
        slope: check_slope(ctx, raw, robot, contacts)?,
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

/// `[terrain.slope]`: its numbers in range, and nothing it cannot carry yet: steps on it, a
/// rolling sphere (whose lowest point is found along world z), or a planar robot on a plane
/// that tilts across its x–z plane.
fn check_slope(
    ctx: &Context,
    raw: &ProblemFile,
    robot: &RobotInfo,
    contacts: &[ContactSpec],
) -> Result<Option<TiltedGround>, ProblemError> {
    let Some(slope) = raw.terrain.slope else {
        return Ok(None);
    };
    for (key, value, _) in slope.requirements() {
        finite(ctx, &format!("terrain.slope.{key}"), value)?;
    }
    if !(0.0..=MAX_SLOPE_ANGLE).contains(&slope.angle) {
        return Err(ctx.invalid(
            "terrain.slope.angle",
            format!(
                "must be between 0 and {MAX_SLOPE_ANGLE} degrees (a tilt from the horizontal), got {}",
                slope.angle
            ),
        ));
    }
    if !raw.terrain.step.is_empty() {
        return Err(ctx.invalid(
            "terrain.slope",
            "steps on a slope are not supported: remove [[terrain.step]] or [terrain.slope]",
        ));
    }
    if robot.moves_in_xz_plane && slope.tilts_along_y() {
        return Err(ctx.invalid(
            "terrain.slope.heading",
            format!(
                "this robot moves in the x–z plane, so its ground may only fall along x: use heading 0 or 180, got {}",
                slope.heading
            ),
        ));
    }
    if let Some(sphere) = contacts.iter().find(|c| c.radius > 0.0) {
        return Err(ctx.invalid(
            "terrain.slope",
            format!(
                "contact `{}` is a sphere (radius {}), whose contact point is taken straight below its centre: spheres on a slope are not supported; use a point contact (radius 0)",
                sphere.name, sphere.radius
            ),
        ));
    }
    Ok(Some(slope.ground()))
}
