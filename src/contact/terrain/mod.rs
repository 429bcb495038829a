//! The terrain: a height map z = H(x, y) built from a ground plane, flat or tilted
//! ([`Slope`]), and features whose heights add up: smoothed steps and stairs along any
//! horizontal direction, blocks, and a height map read from a file. Each kind of feature is
//! one file here: a type whose serde fields are its problem-file entry, with its height and
//! its checks ([`TerrainFeature`]). A new kind: its file, a field of [`Terrain`] and of the
//! `[terrain]` section (`problem/schema.rs`), one line in `problem/validate/terrain.rs`.
//!
//! What the contact rows make of the surface (its normal, its tangents, the distance of a
//! point) is [`crate::contact::surface`]'s, from the terrain's [`Shape`].

mod block;
mod height_map;
mod slope;
mod stairs;
mod step;

use std::sync::Arc;

pub use block::Block;
pub use height_map::{HeightMap, HeightMapEntry, HeightMapError, MAX_HEIGHT_MAP_LINES};
pub use slope::{MAX_SLOPE_ANGLE, Slope, TiltedGround, sin_cos_degrees};
pub use stairs::{MAX_STAIRS, Stairs};
pub use step::Step;

use crate::autodiff::Scalar;

/// One kind of terrain feature: its height over the ground and the checks of its numbers.
/// The type's serde fields are its problem-file entry (`[[terrain.<NAME>]]`).
pub trait TerrainFeature {
    /// Its key in `[terrain]`.
    const NAME: &'static str;
    /// The height it adds at world (x, y) (length units).
    fn height<D: Scalar>(&self, x: D, y: D) -> D;
    /// The horizontal direction [deg] its height varies along, for a feature whose height is
    /// constant across it (a step, stairs); None for one that varies in both (a block).
    fn heading(&self) -> Option<f64>;
    /// Its edges as (distance along [`TerrainFeature::heading`], smoothing length), where a
    /// drawing samples its profile finely.
    fn edges(&self) -> Vec<(f64, f64)>;
    /// Each number of the entry with what it must satisfy, for validation to check and name.
    fn requirements(&self) -> Vec<(&'static str, f64, Requirement)>;
}

/// What a number of a terrain entry must be.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Requirement {
    /// Finite.
    Finite,
    /// Finite and > 0.
    Positive,
    /// A whole number from 1 to the bound.
    Count(u32),
}

/// The distance along the horizontal direction `heading` [deg]: x cos ψ + y sin ψ.
pub(crate) fn along<D: Scalar>(heading: f64, x: D, y: D) -> D {
    let (s, c) = sin_cos_degrees(heading);
    x * D::from(c) + y * D::from(s)
}

/// The terrain: the ground through z = `ground_height` at the origin, flat or tilted by a
/// slope, plus its features (heights add up; validation refuses features on a slope).
#[derive(Debug, Clone, PartialEq, Default)]
pub struct Terrain {
    /// World z of the ground at x = y = 0 (and far from every feature).
    pub ground_height: f64,
    /// Smoothed steps, each along its own heading.
    pub steps: Vec<Step>,
    /// Flights of stairs.
    pub stairs: Vec<Stairs>,
    /// Raised blocks.
    pub blocks: Vec<Block>,
    /// Heights from a file, added to the ground's.
    pub height_map: Option<Arc<HeightMap>>,
    /// The ground's tilt, with the contact frame of the plane (None: level).
    pub slope: Option<TiltedGround>,
}

/// How the terrain's surface varies, which decides how exactly its contact frame is known
/// ([`crate::contact::surface`]).
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Shape {
    /// Level ground: normal +z, tangents world x and y.
    Flat,
    /// A tilted plane ([`TiltedGround`]): its own constant frame.
    Plane(TiltedGround),
    /// Heights that vary along one horizontal direction only (steps and stairs sharing a
    /// heading, up to its reverse): the direction [deg].
    Profile(f64),
    /// Heights that vary in both horizontal directions (blocks, a height map, features of
    /// crossing headings).
    General,
}

impl Terrain {
    /// Flat ground at z = 0.
    pub fn flat() -> Terrain {
        Terrain::default()
    }

    /// Terrain height H(x, y) at a world point (length units): the ground and every feature.
    pub fn height<D: Scalar>(&self, x: D, y: D) -> D {
        let mut height = D::from(self.ground_height);
        if let Some(slope) = &self.slope {
            height += x * D::from(slope.gradient.0) + y * D::from(slope.gradient.1);
        }
        // Each kind's features in turn.
        for step in &self.steps {
            height += step.height(x, y);
        }
        for stairs in &self.stairs {
            height += stairs.height(x, y);
        }
        for block in &self.blocks {
            height += block.height(x, y);
        }
        if let Some(map) = &self.height_map {
            height += map.height(x, y);
        }
        height
    }

    /// [`Terrain::height`] at a world point in plain numbers.
    pub fn height_at(&self, x: f64, y: f64) -> f64 {
        self.height(x, y)
    }

    /// How its surface varies.
    pub fn shape(&self) -> Shape {
        let profiles = self
            .steps
            .iter()
            .map(TerrainFeature::heading)
            .chain(self.stairs.iter().map(TerrainFeature::heading));
        let varies_in_both = !self.blocks.is_empty() || self.height_map.is_some();
        let mut heading = None;
        for h in profiles.flatten() {
            match heading {
                None => heading = Some(h),
                // Parallel (the same direction or its reverse) or crossing.
                Some(first) if sin_cos_degrees(h - first).0 != 0.0 => return Shape::General,
                Some(_) => {}
            }
        }
        match (heading, self.slope, varies_in_both) {
            (None, None, false) => Shape::Flat,
            (None, Some(slope), false) => Shape::Plane(slope),
            (Some(h), None, false) => Shape::Profile(h),
            _ => Shape::General,
        }
    }

    /// Whether it is level ground with no feature.
    pub fn is_flat(&self) -> bool {
        self.shape() == Shape::Flat
    }

    /// Points along the horizontal direction `heading` [deg] where a drawing should sample
    /// the profile finely: around every edge of the features that vary along it.
    pub fn edges_along(&self, heading: f64) -> Vec<f64> {
        let features = self
            .steps
            .iter()
            .map(|s| (s.heading(), s.edges()))
            .chain(self.stairs.iter().map(|s| (s.heading(), s.edges())));
        let mut out = Vec::new();
        for (h, edges) in features {
            let Some(h) = h else { continue };
            // The feature's distance s' along its heading is ±s along `heading` when parallel.
            let (sin, cos) = sin_cos_degrees(h - heading);
            if sin != 0.0 {
                continue;
            }
            for (edge, width) in edges {
                for i in -8..=8 {
                    out.push(cos * (edge + width * 0.5 * f64::from(i)));
                }
            }
        }
        out
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use num_dual::{Dual64, first_derivative};

    fn littledog() -> Terrain {
        Terrain {
            ground_height: 0.0,
            steps: vec![Step::along_x(0.25, 0.11, 0.005)],
            ..Terrain::default()
        }
    }

    #[test]
    fn step_height_matches_the_closed_form() {
        let terrain = littledog();
        for x in [-1.0, 0.0, 0.245, 0.25, 0.2555, 0.3, 1.0] {
            let expected = 0.11 * 0.5 * (1.0 + ((x - 0.25) / 0.005_f64).tanh());
            assert!((terrain.height_at(x, 0.0) - expected).abs() < 1e-15);
        }
        assert!((terrain.height_at(0.25, 0.0) - 0.055).abs() < 1e-15);
        // 10–90 % of the rise within ±5.5 mm of the edge (docs/reference-problems.md).
        assert!(terrain.height_at(0.25 - 0.0055, 0.0) < 0.11 * 0.1);
        assert!(terrain.height_at(0.25 + 0.0055, 0.0) > 0.11 * 0.9);
    }

    #[test]
    fn step_slope_matches_the_closed_form() {
        let terrain = littledog();
        let x = 0.252;
        let (_, slope) = first_derivative(|x: Dual64| terrain.height(x, Dual64::from(0.0)), x);
        let sech2 = 1.0 - ((x - 0.25) / 0.005_f64).tanh().powi(2);
        assert!((slope - 0.11 * 0.5 * sech2 / 0.005).abs() < 1e-12);
    }
}
