//! Contact physics: terrain, signed distance, friction directions, and the contact rows with
//! their closed-form derivatives, shared by the NLP (`crate::transcription` places them into
//! its rows) and the forward simulator (`crate::sim` solves them step by step).
//!
//! A contact is a point fixed on a link; the mechanics give its world position p(q) and this
//! module turns p into the signed distance φ (positive above the terrain) and the tangential
//! coordinates whose gradients are the friction directions D. The value functions are generic
//! over [`crate::autodiff::Scalar`]; their derivatives are composed by the chain rule from the
//! point's jet and forward AD of φ and t over p alone ([`ContactGeometry`]).
//!
//! Where things are: `terrain` (the height map and its features), `surface` (the contact
//! frame of the surface: φ and the tangential coordinates of a point), `friction` (the
//! friction basis), `model` (the contact constants of a problem), `geometry`
//! (K(q) = [φ, t] and its derivatives in q), and the rows, each a function of its inputs z:
//! `gap` (φ and −cφ), `work` (the impulse J(q)ᵀλ as the gradient of the contact work),
//! `tangential` (tangential velocity and a rolling sphere's spin friction), `complementarity`
//! (the friction cone and the complementarity products: [`Products`], the one definition the
//! rows, the penalty form and the solution's and simulator's reports use).

mod complementarity;
mod friction;
mod gap;
mod geometry;
mod model;
mod surface;
mod tangential;
mod terrain;
mod work;

pub use complementarity::FACTOR_FLOOR;
pub(crate) use complementarity::{
    Own, Partner, Products, complementarity, complementarity_hessian, complementarity_jacobian,
    cone, friction_cone, gap_product,
};
pub use friction::FrictionBasis;
pub(crate) use gap::{
    contact_gap, distance, distance_hessian, distance_hessian_in, distance_jacobian,
    distance_jacobian_in, distance_with_gradient,
};
pub(crate) use geometry::ContactGeometry;
pub use model::ContactModel;
pub use surface::{
    interval_world_impulses, signed_distance, surface_frame, tangential_coordinates, world_impulse,
};
pub(crate) use tangential::{
    spin_friction, spin_friction_jacobian, tangential_rate, tangential_rate_hessian,
    tangential_rate_hessian_in, tangential_rate_jacobian, tangential_rate_jacobian_in,
    tangential_slack,
};
pub(crate) use terrain::along;
pub use terrain::{
    Block, HeightMap, HeightMapEntry, HeightMapError, MAX_HEIGHT_MAP_LINES, MAX_SLOPE_ANGLE,
    MAX_STAIRS, Requirement, Shape, Slope, Stairs, Step, Terrain, TerrainFeature, TiltedGround,
    sin_cos_degrees,
};
pub(crate) use work::{
    contact_work, contact_work_contracted_in, contact_work_gradient, contact_work_hessian,
    contact_work_hessian_in, contact_work_third,
};
