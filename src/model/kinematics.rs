//! Forward kinematics: world poses of frames and world positions of points.

use super::{LinkId, Model, Scalar};

/// World pose of a link: (rotation R, row-major, mapping link axes to world; origin p).
pub fn link_pose<D: Scalar>(model: &Model, link: LinkId, q: &[D]) -> ([[D; 3]; 3], [D; 3]) {
    let _ = (model, link, q);
    unimplemented!("link_pose")
}

/// World position of `point` (given in the `link` frame) at configuration `q` (length `nq`).
pub fn point_position<D: Scalar>(model: &Model, link: LinkId, point: &[f64; 3], q: &[D]) -> [D; 3] {
    let _ = (model, link, point, q);
    unimplemented!("point_position")
}
