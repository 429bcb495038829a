//! Terrain, signed distance and friction directions for point contacts.
//!
//! A contact is a point fixed on a link; the transcription asks the model for its world
//! position p(q) and this module turns p into the signed distance φ (positive above the
//! terrain) and the tangential coordinates whose gradients are the friction directions D.
//! Everything is generic over [`crate::scalar::Scalar`], so φ and D are differentiated by AD.

mod distance;
mod friction;
mod terrain;

pub use distance::signed_distance;
pub use friction::{FrictionBasis, tangential_coordinates};
pub use terrain::{Requirement, Step, Terrain, TerrainFeature};
