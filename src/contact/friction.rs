//! Friction directions: which world tangential coordinates the friction impulses act along.

use num_dual::Dual64;

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
    /// The one rule for the friction basis of a robot: planar when the base is planar, or when
    /// no contact point can move along world y (a planar robot built from a fixed base and
    /// sliders, like SPEC's hopper); spatial otherwise. The y-rates of every contact
    /// (`contact_position(contact, q)`, length units) are checked along every coordinate at two
    /// configurations near `q0`.
    pub fn detect(
        base: BaseType,
        q0: &[f64],
        num_contacts: usize,
        contact_position: impl Fn(usize, &[Dual64]) -> [Dual64; 3],
    ) -> FrictionBasis {
        if base == BaseType::Planar {
            return FrictionBasis::Planar;
        }
        let n = q0.len();
        for shift in [0.0, 0.3] {
            for c in 0..n {
                let q: Vec<Dual64> = (0..n)
                    .map(|k| {
                        let value = q0[k] + shift * (1.0 + k as f64 * 0.37);
                        Dual64::new(value, if k == c { 1.0 } else { 0.0 })
                    })
                    .collect();
                for i in 0..num_contacts {
                    if contact_position(i, &q)[1].eps.abs() > 1e-12 {
                        return FrictionBasis::Spatial;
                    }
                }
            }
        }
        FrictionBasis::Planar
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

    /// A point on a link swinging about world x moves along y; one sliding along x and z
    /// does not.
    fn swinging<D: Scalar>(q: &[D]) -> [D; 3] {
        [D::from(0.0), q[0].sin(), -q[0].cos()]
    }
    fn sliding<D: Scalar>(q: &[D]) -> [D; 3] {
        [q[0], D::from(0.0), q[1]]
    }

    #[test]
    fn detect_gives_planar_only_when_no_contact_moves_along_y() {
        let q0 = [0.2, 0.5];
        let planar = FrictionBasis::detect(BaseType::Fixed, &q0, 1, |_, q| sliding(q));
        assert_eq!(planar.num_directions(), 2);
        let spatial = FrictionBasis::detect(BaseType::Fixed, &q0, 1, |_, q| swinging(q));
        assert_eq!(spatial.num_directions(), 4);
        // Hanging straight down (q = 0) the y-rate is cos 0 = 1 already; at q0 = π/2 it
        // vanishes, and the second configuration finds it.
        let vertical = [std::f64::consts::FRAC_PI_2, 0.0];
        let shifted = FrictionBasis::detect(BaseType::Floating, &vertical, 1, |_, q| swinging(q));
        assert_eq!(shifted, FrictionBasis::Spatial);
        // A planar base is planar whatever its contacts do.
        let base = FrictionBasis::detect(BaseType::Planar, &q0, 1, |_, q| swinging(q));
        assert_eq!(base, FrictionBasis::Planar);
        let mut t = [0.0; 2];
        tangential_coordinates::<f64>(FrictionBasis::Spatial, &[1.0, 2.0, 3.0], &mut t);
        assert_eq!(t, [1.0, 2.0]);
    }
}
