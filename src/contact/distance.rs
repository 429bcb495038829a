//! Signed distance of a point to the terrain.

use super::Terrain;
use crate::autodiff::Scalar;

/// Signed distance φ = p_z − H(p_x) of a world point `p` (length units) to the terrain:
/// positive above, zero on, negative below the surface.
///
/// This is the vertical distance to the height map, not the Euclidean one: on the flat
/// parts they agree and the surface normal is exactly +z (littledog-step, docs/reference-problems.md).
///
/// On a [`crate::contact::Slope`] it is the distance along the plane's unit normal n,
/// n·(p − o) with o = (0, 0, ground height): exact.
pub fn signed_distance<D: Scalar>(terrain: &Terrain, p: &[D; 3]) -> D {
    if let Some(slope) = &terrain.slope {
        let [_, _, n] = slope.frame;
        return p[0] * D::from(n[0])
            + p[1] * D::from(n[1])
            + (p[2] - D::from(terrain.ground_height)) * D::from(n[2]);
    }
    p[2] - terrain.height(p[0])
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::contact::Step;

    #[test]
    fn flat_ground_distance_is_height_above_ground() {
        let terrain = Terrain {
            ground_height: 0.1,
            steps: vec![],
            slope: None,
        };
        assert!((signed_distance::<f64>(&terrain, &[3.0, -2.0, 0.35]) - 0.25).abs() < 1e-15);
        assert!((signed_distance::<f64>(&terrain, &[3.0, -2.0, 0.05]) + 0.05).abs() < 1e-15);
    }

    #[test]
    fn step_distance_far_past_the_edge_is_height_above_the_top() {
        let terrain = Terrain {
            ground_height: 0.0,
            steps: vec![Step {
                edge_x: 0.25,
                rise: 0.11,
                width: 0.005,
            }],
            slope: None,
        };
        assert!((signed_distance::<f64>(&terrain, &[0.5, 0.0, 0.2]) - 0.09).abs() < 1e-12);
        assert!((signed_distance::<f64>(&terrain, &[0.0, 0.0, 0.2]) - 0.2).abs() < 1e-12);
    }
}
