//! A smoothed step in the ground: `[[terrain.step]]`.

use serde::Deserialize;

use super::{Requirement, TerrainFeature, along};
use crate::autodiff::Scalar;

/// A smoothed step in the ground: the height rises by `rise` across the line s = `edge`,
/// where s = x cos ψ + y sin ψ is the distance along the horizontal direction `heading` ψ
/// (degrees from world +x towards +y; 0: the edge runs along y and the ground rises along +x):
/// H = rise · ½ (1 + tanh((s − edge)/width)). C∞, so Newton steps can cross it. Its fields
/// are the problem file's `[[terrain.step]]` entry (`edge_x` is accepted for `edge`).
///
/// The LittleDog step of littledog-step is `Step { edge: 0.25, rise: 0.11, width: 0.005,
/// heading: 0.0 }` (metres). A negative `rise` makes a step down.
#[derive(Debug, Clone, Copy, PartialEq, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Step {
    /// Distance of the edge from the origin along `heading` (the height is half-way up
    /// there), in robot length units.
    #[serde(alias = "edge_x")]
    pub edge: f64,
    /// Height gained across the edge, in length units.
    pub rise: f64,
    /// Smoothing length w > 0: 10–90 % of the rise lies within ±1.1·w of the edge.
    pub width: f64,
    /// Direction the ground rises towards [deg], from world +x towards +y (default 0).
    #[serde(default)]
    pub heading: f64,
}

impl Step {
    /// A step rising along +x across x = `edge`.
    pub fn along_x(edge: f64, rise: f64, width: f64) -> Step {
        Step {
            edge,
            rise,
            width,
            heading: 0.0,
        }
    }
}

impl TerrainFeature for Step {
    const NAME: &'static str = "step";

    /// rise · ½ (1 + tanh((s − edge)/width)).
    fn height<D: Scalar>(&self, x: D, y: D) -> D {
        let s = (along(self.heading, x, y) - D::from(self.edge)) / D::from(self.width);
        (s.tanh() + D::from(1.0)) * D::from(0.5 * self.rise)
    }

    fn heading(&self) -> Option<f64> {
        Some(self.heading)
    }

    fn edges(&self) -> Vec<(f64, f64)> {
        vec![(self.edge, self.width)]
    }

    fn requirements(&self) -> Vec<(&'static str, f64, Requirement)> {
        vec![
            ("edge", self.edge, Requirement::Finite),
            ("rise", self.rise, Requirement::Finite),
            ("width", self.width, Requirement::Positive),
            ("heading", self.heading, Requirement::Finite),
        ]
    }
}
