//! A smoothed step in the ground: `[[terrain.step]]`.

use serde::Deserialize;

use super::{Requirement, TerrainFeature};
use crate::autodiff::Scalar;

/// A smoothed step in the ground: the height rises by `rise` across x = `edge_x`,
/// H(x) = rise · ½ (1 + tanh((x − edge_x)/width)). C∞, so Newton steps can cross it.
/// Its fields are the problem file's `[[terrain.step]]` entry.
///
/// The LittleDog step of littledog-step is `Step { edge_x: 0.25, rise: 0.11, width: 0.005 }`
/// (metres). A negative `rise` makes a step down.
#[derive(Debug, Clone, Copy, PartialEq, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Step {
    /// World x of the edge (the height is half-way up here), in robot length units.
    pub edge_x: f64,
    /// Height gained across the edge, in length units.
    pub rise: f64,
    /// Smoothing length w > 0: 10–90 % of the rise lies within ±1.1·w of the edge.
    pub width: f64,
}

impl TerrainFeature for Step {
    const NAME: &'static str = "step";

    /// rise · ½ (1 + tanh((x − edge_x)/width)).
    fn height<D: Scalar>(&self, x: D) -> D {
        let s = (x - D::from(self.edge_x)) / D::from(self.width);
        (s.tanh() + D::from(1.0)) * D::from(0.5 * self.rise)
    }

    fn requirements(&self) -> Vec<(&'static str, f64, Requirement)> {
        vec![
            ("edge_x", self.edge_x, Requirement::Finite),
            ("rise", self.rise, Requirement::Finite),
            ("width", self.width, Requirement::Positive),
        ]
    }
}
