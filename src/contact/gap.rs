//! The normal rows: a contact's signed distance φ_i(q) and the c·φ complementarity product
//! −c_i φ_i(q), with their chain-rule derivatives.

use nalgebra::{DMatrix, DVector};

use super::{ContactGeometry, ContactModel, gap_product, signed_distance};
use crate::autodiff::Scalar;
use crate::discrete::{Mechanics, MechanicsDerivatives};

/// φ_i(q); z = [q].
pub fn distance<D: Scalar, M: Mechanics>(
    mech: &M,
    model: &ContactModel,
    contact: usize,
    z: &[D],
) -> D {
    signed_distance(
        &model.terrain,
        &mech.contact_position(contact, &z[..mech.nq()]),
    )
}

/// −c_i φ_i(q) ([`gap_product`] of −c_i), the only product of the complementarity rows that
/// depends on q; z = [q; c_i], out length 1 (added into the c·φ row).
pub fn contact_gap<D: Scalar, M: Mechanics>(
    mech: &M,
    model: &ContactModel,
    contact: usize,
    z: &[D],
) -> D {
    gap_product(-z[mech.nq()], distance(mech, model, contact, z))
}

/// Jacobian of φ_i(q) ([`distance`], 1 × n) or of −c_i φ_i(q) ([`contact_gap`], 1 × (n + 1),
/// z = [q; c_i]) by the chain rule.
pub fn distance_jacobian<M: MechanicsDerivatives>(
    mech: &M,
    model: &ContactModel,
    contact: usize,
    z: &[f64],
    gap: bool,
) -> DMatrix<f64> {
    let geometry = ContactGeometry::new(mech, model, contact, &z[..mech.nq()], 1);
    distance_jacobian_in(&geometry, z, gap)
}

/// φ_i(q) and its gradient ∇φ_i (n × 1) from one point jet: the c entry of
/// [`super::contact_work_gradient`] and the q–c column of [`super::contact_work_hessian`], to
/// the bit, without the rest of either (the simulator's contact scaling, active set and
/// pivoting step).
pub fn distance_with_gradient<M: MechanicsDerivatives>(
    mech: &M,
    model: &ContactModel,
    contact: usize,
    q: &[f64],
) -> (f64, DVector<f64>) {
    let geometry = ContactGeometry::new(mech, model, contact, &q[..mech.nq()], 1);
    let gradient = geometry.jacobian().row(0).transpose();
    (geometry.value()[0], gradient)
}

/// [`distance_jacobian`] from the contact's geometry at q (order ≥ 1).
pub(crate) fn distance_jacobian_in(
    geometry: &ContactGeometry,
    z: &[f64],
    gap: bool,
) -> DMatrix<f64> {
    let n = geometry.n();
    let grad = geometry.gradient(&[1.0, 0.0, 0.0]);
    if !gap {
        return DMatrix::from_row_slice(1, n, &grad);
    }
    let c = z[n];
    let mut out = DMatrix::zeros(1, n + 1);
    for i in 0..n {
        out[(0, i)] = -c * grad[i];
    }
    out[(0, n)] = -geometry.value()[0];
    out
}

/// w·∇²φ_i (n × n) or w·∇²(−c_i φ_i) ((n + 1)²) by the chain rule; see [`distance_jacobian`].
pub fn distance_hessian<M: MechanicsDerivatives>(
    mech: &M,
    model: &ContactModel,
    contact: usize,
    z: &[f64],
    w: f64,
    gap: bool,
) -> DMatrix<f64> {
    let geometry = ContactGeometry::new(mech, model, contact, &z[..mech.nq()], 2);
    distance_hessian_in(&geometry, z, w, gap)
}

/// [`distance_hessian`] from the contact's geometry at q (order ≥ 2).
pub(crate) fn distance_hessian_in(
    geometry: &ContactGeometry,
    z: &[f64],
    w: f64,
    gap: bool,
) -> DMatrix<f64> {
    let n = geometry.n();
    if !gap {
        return geometry.hessian(&[w, 0.0, 0.0]);
    }
    let c = z[n];
    let mut out = DMatrix::zeros(n + 1, n + 1);
    geometry.add_hessian(&[-w * c, 0.0, 0.0], &mut out.view_mut((0, 0), (n, n)));
    let grad = geometry.gradient(&[-w, 0.0, 0.0]);
    for i in 0..n {
        out[(i, n)] = grad[i];
        out[(n, i)] = grad[i];
    }
    out
}
