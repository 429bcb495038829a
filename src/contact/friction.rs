//! Friction directions: which world tangential coordinates the friction impulses act along.

use crate::autodiff::Scalar;

/// The polyhedral friction cone's directions, fixed in the world.
///
/// With tangential coordinates t(q) (world x, and y when spatial) of a contact point, the
/// rows of D = ∂t/∂q are the friction directions, P = [D; −D], and the friction impulses
/// are ordered β = [+x, −x] (planar, nd = 2) or β = [+x, +y, −x, −y] (spatial, nd = 4).
/// These are exact tangents wherever the terrain normal is +z (flat ground, flat parts of
/// a step).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum FrictionBasis {
    /// One tangent direction, world x (planar robots moving in the x-z plane).
    Planar,
    /// Two tangent directions, world x and y.
    Spatial,
}

impl FrictionBasis {
    /// The one rule for the friction basis of a robot: planar (friction along world x, 2
    /// directions) for a model whose points all move in the x–z plane
    /// ([`crate::model::Model::moves_in_xz_plane`]: a planar base, or a fixed base with
    /// joints about y and slides within x–z, like the reference hopper); spatial (x and y, 4
    /// directions) for every robot that moves in 3D, fixed base or not.
    pub fn for_robot(moves_in_xz_plane: bool) -> FrictionBasis {
        if moves_in_xz_plane {
            FrictionBasis::Planar
        } else {
            FrictionBasis::Spatial
        }
    }

    /// Number of tangential coordinates (1 or 2).
    pub fn num_tangents(self) -> usize {
        match self {
            FrictionBasis::Planar => 1,
            FrictionBasis::Spatial => 2,
        }
    }

    /// Number of friction directions nd = 2 · tangents (each direction and its opposite).
    pub fn num_directions(self) -> usize {
        2 * self.num_tangents()
    }
}

/// Tangential coordinates of a world point: [p_x] (planar) or [p_x, p_y] (spatial), written
/// into `out` (length `basis.num_tangents()`).
pub fn tangential_coordinates<D: Scalar>(basis: FrictionBasis, p: &[D; 3], out: &mut [D]) {
    out[0] = p[0];
    if basis == FrictionBasis::Spatial {
        out[1] = p[1];
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn planar_models_get_two_directions_and_every_other_robot_four() {
        assert_eq!(FrictionBasis::for_robot(true).num_directions(), 2);
        assert_eq!(FrictionBasis::for_robot(false).num_directions(), 4);
        let mut t = [0.0; 2];
        tangential_coordinates::<f64>(FrictionBasis::Spatial, &[1.0, 2.0, 3.0], &mut t);
        assert_eq!(t, [1.0, 2.0]);
        tangential_coordinates::<f64>(FrictionBasis::Planar, &[4.0, 2.0, 3.0], &mut t);
        assert_eq!(t[0], 4.0);
    }
}
