//! The terrain: a flat ground plus smoothed steps, as a height map z = H(x). Each kind of
//! feature is a type with its own height (a new kind: its type here, a field of [`Terrain`],
//! its `[terrain]` schema entry).

use crate::scalar::Scalar;

/// A smoothed step in the ground: the height rises by `rise` across x = `edge_x`,
/// H(x) = rise · ½ (1 + tanh((x − edge_x)/width)). C∞, so Newton steps can cross it.
///
/// SPEC.md's LittleDog step is `Step { edge_x: 0.25, rise: 0.11, width: 0.005 }`
/// (metres). A negative `rise` makes a step down.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Step {
    /// World x of the edge (the height is half-way up here), in robot length units.
    pub edge_x: f64,
    /// Height gained across the edge, in length units.
    pub rise: f64,
    /// Smoothing length w > 0: 10–90 % of the rise lies within ±1.1·w of the edge.
    pub width: f64,
}

impl Step {
    /// The height this step adds at world x: rise · ½ (1 + tanh((x − edge_x)/width)).
    pub fn height<D: Scalar>(&self, x: D) -> D {
        let s = (x - D::from(self.edge_x)) / D::from(self.width);
        (s.tanh() + D::from(1.0)) * D::from(0.5 * self.rise)
    }
}

/// The terrain: flat ground at `ground_height` plus smoothed steps (heights add up).
#[derive(Debug, Clone, PartialEq, Default)]
pub struct Terrain {
    /// World z of the flat ground far to the left of every step.
    pub ground_height: f64,
    /// Smoothed steps along world x, added to the ground height.
    pub steps: Vec<Step>,
}

impl Terrain {
    /// Flat ground at z = 0.
    pub fn flat() -> Terrain {
        Terrain::default()
    }

    /// Terrain height H(x) at world x (length units).
    pub fn height<D: Scalar>(&self, x: D) -> D {
        let mut height = D::from(self.ground_height);
        for step in &self.steps {
            height += step.height(x);
        }
        height
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use num_dual::{Dual64, first_derivative};

    fn littledog() -> Terrain {
        Terrain {
            ground_height: 0.0,
            steps: vec![Step {
                edge_x: 0.25,
                rise: 0.11,
                width: 0.005,
            }],
        }
    }

    #[test]
    fn step_height_matches_the_closed_form() {
        let terrain = littledog();
        for x in [-1.0, 0.0, 0.245, 0.25, 0.2555, 0.3, 1.0] {
            let expected = 0.11 * 0.5 * (1.0 + ((x - 0.25) / 0.005_f64).tanh());
            assert!((terrain.height::<f64>(x) - expected).abs() < 1e-15);
        }
        assert!((terrain.height::<f64>(0.25) - 0.055).abs() < 1e-15);
        // 10–90 % of the rise within ±5.5 mm of the edge (SPEC.md).
        assert!(terrain.height::<f64>(0.25 - 0.0055) < 0.11 * 0.1);
        assert!(terrain.height::<f64>(0.25 + 0.0055) > 0.11 * 0.9);
    }

    #[test]
    fn step_slope_matches_the_closed_form() {
        let terrain = littledog();
        let x = 0.252;
        let (_, slope) = first_derivative(|x: Dual64| terrain.height(x), x);
        let sech2 = 1.0 - ((x - 0.25) / 0.005_f64).tanh().powi(2);
        assert!((slope - 0.11 * 0.5 * sech2 / 0.005).abs() < 1e-12);
    }
}
