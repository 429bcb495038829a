//! `[terrain]`: the ground and the features on it, each checked by its own requirements;
//! a height map's file read next to the problem.

use super::context::Context;
use super::values::{finite, positive};
use std::path::Path;
use std::sync::Arc;

use crate::contact::{
    HeightMap, MAX_SLOPE_ANGLE, Requirement, Terrain, TerrainFeature, TiltedGround, sin_cos_degrees,
};
use crate::files::input::{MAX_TEXT_BYTES, read_regular_text};
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
    check_features(ctx, &section.stairs)?;
    check_features(ctx, &section.block)?;
    let terrain = Terrain {
        ground_height: finite(
            ctx,
            "terrain.ground_height",
            section.ground_height.unwrap_or(0.0),
        )?,
        steps: section.step.clone(),
        stairs: section.stairs.clone(),
        blocks: section.block.clone(),
        height_map: check_height_map(ctx, raw)?.map(Arc::new),
        slope: check_slope(ctx, raw, robot)?,
    };
    if robot.moves_in_xz_plane {
        check_planar_headings(ctx, raw)?;
    }
    if !terrain.is_flat()
        && let Some(sphere) = contacts.iter().find(|c| c.radius > 0.0)
    {
        return Err(ctx.invalid(
            "terrain",
            format!(
                "contact `{}` is a sphere (radius {}), whose contact point is taken straight below its centre: spheres are supported on flat ground only; use a point contact (radius 0)",
                sphere.name, sphere.radius
            ),
        ));
    }
    Ok(terrain)
}

/// Checks every `[[terrain.<kind>]]` entry against its requirements, naming the field.
fn check_features<F: TerrainFeature>(ctx: &Context, features: &[F]) -> Result<(), ProblemError> {
    for (i, feature) in features.iter().enumerate() {
        check_requirements(
            ctx,
            &format!("terrain.{}[{i}]", F::NAME),
            feature.requirements(),
        )?;
    }
    Ok(())
}

/// Checks the numbers of one entry (`prefix`.key) against what they must be.
fn check_requirements(
    ctx: &Context,
    prefix: &str,
    requirements: Vec<(&'static str, f64, Requirement)>,
) -> Result<(), ProblemError> {
    for (key, value, requirement) in requirements {
        let field = format!("{prefix}.{key}");
        match requirement {
            Requirement::Finite => finite(ctx, &field, value)?,
            Requirement::Positive => positive(ctx, &field, value)?,
            Requirement::Count(max) => {
                if !(1.0..=f64::from(max)).contains(&value) {
                    return Err(ctx.invalid(
                        &field,
                        format!("must be a whole number from 1 to {max}, got {value}"),
                    ));
                }
                value
            }
        };
    }
    Ok(())
}

/// A planar robot's ground may vary along x only: steps and stairs with heading 0 or 180.
fn check_planar_headings(ctx: &Context, raw: &ProblemFile) -> Result<(), ProblemError> {
    let headings = raw
        .terrain
        .step
        .iter()
        .map(|s| ("step", s.heading))
        .chain(raw.terrain.stairs.iter().map(|s| ("stairs", s.heading)));
    for (i, (kind, heading)) in headings.enumerate() {
        if sin_cos_degrees(heading).0 != 0.0 {
            let index = if kind == "step" {
                i
            } else {
                i - raw.terrain.step.len()
            };
            return Err(ctx.invalid(
                &format!("terrain.{kind}[{index}].heading"),
                format!(
                    "this robot moves in the x–z plane, so its ground may only vary along x: use heading 0 or 180, got {heading}"
                ),
            ));
        }
    }
    Ok(())
}

/// `[terrain.height_map]`: its numbers, and its file (next to the problem) read and parsed.
fn check_height_map(ctx: &Context, raw: &ProblemFile) -> Result<Option<HeightMap>, ProblemError> {
    let Some(entry) = &raw.terrain.height_map else {
        return Ok(None);
    };
    check_requirements(ctx, "terrain.height_map", entry.requirements())?;
    let dir = ctx.file.parent().unwrap_or(Path::new(""));
    let path = dir.join(&entry.file);
    let text = read_regular_text(&path, MAX_TEXT_BYTES).map_err(|e| {
        ctx.invalid(
            "terrain.height_map.file",
            format!("cannot read {}: {e}", path.display()),
        )
    })?;
    HeightMap::parse(entry.clone(), &text)
        .map(Some)
        .map_err(|e| {
            ctx.invalid(
                "terrain.height_map.file",
                format!("{}: {e}", path.display()),
            )
        })
}

/// `[terrain.slope]`: its numbers in range, and nothing it cannot carry: features on it, or
/// a planar robot on a plane that tilts across its x–z plane.
fn check_slope(
    ctx: &Context,
    raw: &ProblemFile,
    robot: &RobotInfo,
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
    let t = &raw.terrain;
    if !(t.step.is_empty() && t.stairs.is_empty() && t.block.is_empty() && t.height_map.is_none()) {
        return Err(ctx.invalid(
            "terrain.slope",
            "features on a slope are not supported: remove [terrain.slope], or the steps, stairs, blocks and height map (a height map can hold a tilted ground with its features)",
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
    Ok(Some(slope.ground()))
}
