//! Friction directions: which world tangential coordinates the friction impulses act along.

use crate::model::BaseType;
use crate::scalar::Scalar;

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
    /// The basis a robot with this base uses: planar for a planar base, spatial otherwise.
    pub fn for_base(base: BaseType) -> FrictionBasis {
        match base {
            BaseType::Planar => FrictionBasis::Planar,
            BaseType::Fixed | BaseType::Floating => FrictionBasis::Spatial,
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
    fn planar_base_gets_two_directions_and_floating_four() {
        assert_eq!(
            FrictionBasis::for_base(BaseType::Planar).num_directions(),
            2
        );
        assert_eq!(
            FrictionBasis::for_base(BaseType::Floating).num_directions(),
            4
        );
        let mut t = [0.0; 2];
        tangential_coordinates::<f64>(FrictionBasis::Spatial, &[1.0, 2.0, 3.0], &mut t);
        assert_eq!(t, [1.0, 2.0]);
    }
}
