//! Friction directions: which world tangential coordinates the friction impulses act along.

/// The polyhedral friction cone's directions, fixed with the ground.
///
/// With tangential coordinates t(q) ([`super::tangential_coordinates`]: world x, and y when
/// spatial; on a slope the plane's tangents) of a contact point, the rows of D = ∂t/∂q are
/// the friction directions, P = [D; −D], and the friction impulses are ordered β = [+x, −x]
/// (planar, nd = 2) or β = [+x, +y, −x, −y] (spatial, nd = 4), x and y naming the plane's
/// directions above them on a slope. These are exact tangents on flat ground, on a slope, and
/// on the flat parts of a step; on a step's face they stay horizontal.
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

#[cfg(test)]
mod tests {
    use super::*;
    use crate::contact::{Terrain, tangential_coordinates};

    #[test]
    fn planar_models_get_two_directions_and_every_other_robot_four() {
        assert_eq!(FrictionBasis::for_robot(true).num_directions(), 2);
        assert_eq!(FrictionBasis::for_robot(false).num_directions(), 4);
        let mut t = [0.0; 2];
        tangential_coordinates::<f64>(
            FrictionBasis::Spatial,
            &Terrain::flat(),
            &[1.0, 2.0, 3.0],
            &mut t,
        );
        assert_eq!(t, [1.0, 2.0]);
        tangential_coordinates::<f64>(
            FrictionBasis::Planar,
            &Terrain::flat(),
            &[4.0, 2.0, 3.0],
            &mut t,
        );
        assert_eq!(t[0], 4.0);
    }
}
