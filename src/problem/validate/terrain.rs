//! `[terrain]`: flat ground and smoothed steps.

use super::context::Context;
use super::values::{finite, positive};
use crate::contact::{Step, Terrain};
use crate::problem::ProblemError;
use crate::problem::schema::ProblemFile;

pub(super) fn check_terrain(ctx: &Context, raw: &ProblemFile) -> Result<Terrain, ProblemError> {
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
    Ok(terrain)
}
