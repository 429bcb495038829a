//! The contact model of a problem: the terrain, the friction basis and each contact's
//! friction coefficient, shared by the NLP's contact rows and the forward simulator.

use super::{FrictionBasis, Terrain};

/// The constants every contact row needs besides the robot's mechanics.
#[derive(Debug, Clone, PartialEq)]
pub struct ContactModel {
    /// Friction basis (nd = 2 planar, 4 spatial).
    pub basis: FrictionBasis,
    /// Friction coefficient per contact, in the robot's contact order.
    pub friction: Vec<f64>,
    /// Terrain of every contact.
    pub terrain: Terrain,
}

impl ContactModel {
    /// The model of a robot that moves in the x–z plane or not (the friction basis by its one
    /// rule, [`FrictionBasis::for_robot`]), with one friction coefficient per contact.
    pub fn new(moves_in_xz_plane: bool, friction: Vec<f64>, terrain: Terrain) -> ContactModel {
        ContactModel {
            basis: FrictionBasis::for_robot(moves_in_xz_plane),
            friction,
            terrain,
        }
    }

    /// Friction directions per contact.
    pub fn nd(&self) -> usize {
        self.basis.num_directions()
    }
}
