//! The terrain: a ground plane, flat or tilted ([`Slope`]), plus smoothed steps along x on
//! flat ground, as a height map z = H(x, y). Each kind of
//! feature is one file here: a type whose serde fields are its problem-file entry, with its
//! height and its checks ([`TerrainFeature`]). A new kind: its file, a field of [`Terrain`]
//! and of the `[terrain]` section (`problem/schema.rs`), one line in `problem/validate/terrain.rs`.

mod slope;
mod step;

pub use slope::{MAX_SLOPE_ANGLE, Slope, TiltedGround, sin_cos_degrees};
pub use step::Step;

use crate::autodiff::Scalar;

/// One kind of terrain feature: its height over the ground and the checks of its numbers.
/// The type's serde fields are its problem-file entry (`[[terrain.<NAME>]]`).
pub trait TerrainFeature {
    /// Its key in `[terrain]`.
    const NAME: &'static str;
    /// The height it adds at world x (length units).
    fn height<D: Scalar>(&self, x: D) -> D;
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
}

/// The terrain: the ground through z = `ground_height` at the origin, flat or tilted by a
/// slope, plus smoothed steps on flat ground (heights add up; validation refuses steps on
/// a slope).
#[derive(Debug, Clone, PartialEq, Default)]
pub struct Terrain {
    /// World z of the ground at x = y = 0 (and far to the left of every step).
    pub ground_height: f64,
    /// Smoothed steps along world x, added to the ground height.
    pub steps: Vec<Step>,
    /// The ground's tilt, with the contact frame of the plane (None: flat, normal +z).
    pub slope: Option<TiltedGround>,
}

impl Terrain {
    /// Flat ground at z = 0.
    pub fn flat() -> Terrain {
        Terrain::default()
    }

    /// Terrain height H(x) along world x at y = 0 (length units): the ground and its steps;
    /// [`Terrain::height_at`] adds the slope's part in y.
    pub fn height<D: Scalar>(&self, x: D) -> D {
        let mut height = D::from(self.ground_height);
        if let Some(slope) = &self.slope {
            height += x * D::from(slope.gradient.0);
        }
        // Each kind's features in turn.
        for step in &self.steps {
            height += step.height(x);
        }
        height
    }

    /// Terrain height H(x, y) at a world point (length units).
    pub fn height_at(&self, x: f64, y: f64) -> f64 {
        let height = self.height(x);
        match &self.slope {
            Some(slope) => height + slope.gradient.1 * y,
            None => height,
        }
    }

    /// The contact frame of the ground [t₁, t₂, n] (world unit vectors): the slope's
    /// ([`Slope::frame`]), else world x, y and z. On a step's face the planner still uses
    /// world x and y and the vertical distance.
    pub fn frame(&self) -> [[f64; 3]; 3] {
        match &self.slope {
            Some(slope) => slope.frame,
            None => [[1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]],
        }
    }

    /// The slope's height change per unit world y (0 without one).
    pub fn slope_y(&self) -> f64 {
        self.slope.map_or(0.0, |s| s.gradient.1)
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
            slope: None,
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
        // 10–90 % of the rise within ±5.5 mm of the edge (docs/reference-problems.md).
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
