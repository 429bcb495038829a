//! A flight of stairs: `[[terrain.stairs]]`.

use serde::Deserialize;

use super::{Requirement, TerrainFeature, along};
use crate::autodiff::Scalar;

/// `count` smoothed steps of the same `rise`, their edges `run` apart along the horizontal
/// direction `heading` ψ (degrees from world +x towards +y), the first at distance `start`
/// along it: H = Σ_k rise · ½ (1 + tanh((s − start − k·run)/width)), s = x cos ψ + y sin ψ.
/// Its fields are the problem file's `[[terrain.stairs]]` entry.
#[derive(Debug, Clone, Copy, PartialEq, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Stairs {
    /// Distance of the first edge from the origin along `heading` [length].
    pub start: f64,
    /// Number of steps (1 to 100).
    pub count: u32,
    /// Height gained at each edge [length] (negative: stairs down).
    pub rise: f64,
    /// Tread depth: distance between successive edges [length], > 0.
    pub run: f64,
    /// Smoothing length of each edge [length], > 0 (as a step's `width`).
    pub width: f64,
    /// Direction the stairs climb towards [deg], from world +x towards +y (default 0).
    #[serde(default)]
    pub heading: f64,
}

/// Most steps a flight may have.
pub const MAX_STAIRS: u32 = 100;

impl TerrainFeature for Stairs {
    const NAME: &'static str = "stairs";

    fn height<D: Scalar>(&self, x: D, y: D) -> D {
        let s = along(self.heading, x, y);
        let mut sum = D::from(0.0);
        for k in 0..self.count {
            let edge = self.start + f64::from(k) * self.run;
            sum += ((s - D::from(edge)) / D::from(self.width)).tanh();
        }
        (sum + D::from(f64::from(self.count))) * D::from(0.5 * self.rise)
    }

    fn heading(&self) -> Option<f64> {
        Some(self.heading)
    }

    fn edges(&self) -> Vec<(f64, f64)> {
        (0..self.count)
            .map(|k| (self.start + f64::from(k) * self.run, self.width))
            .collect()
    }

    fn requirements(&self) -> Vec<(&'static str, f64, Requirement)> {
        vec![
            ("start", self.start, Requirement::Finite),
            (
                "count",
                f64::from(self.count),
                Requirement::Count(MAX_STAIRS),
            ),
            ("rise", self.rise, Requirement::Finite),
            ("run", self.run, Requirement::Positive),
            ("width", self.width, Requirement::Positive),
            ("heading", self.heading, Requirement::Finite),
        ]
    }
}
