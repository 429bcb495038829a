//! Contact work c_i φ_i(q) + Σ_t (β⁺_it − β⁻_it) t_i(q), whose q-gradient is contact i's
//! share of the impulse J(q)ᵀλ in the discrete equations, with its chain-rule derivatives.

use nalgebra::{DMatrix, DMatrixViewMut};

use super::{ContactGeometry, ContactModel, signed_distance, tangential_coordinates};
use crate::autodiff::Scalar;
use crate::discrete::{Mechanics, MechanicsDerivatives};

/// c_i φ_i(q) + Σ_t (β⁺_it − β⁻_it) t_i(q) of one contact; z = [q; c_i; β_i (nd)].
/// Its gradient in q is contact i's share of J(q)ᵀλ = Nᵀc + Pᵀβ, P = [D; −D]; for a rolling
/// sphere, D adds the spin columns, whose share is [`super::spin_friction`].
pub fn contact_work<D: Scalar, M: Mechanics>(
    mech: &M,
    model: &ContactModel,
    contact: usize,
    z: &[D],
) -> D {
    let (n, nd) = (mech.nq(), model.nd());
    let nt = nd / 2;
    let p = mech.contact_position(contact, &z[..n]);
    let (c, beta) = (z[n], &z[n + 1..n + 1 + nd]);
    let mut work = c * signed_distance(&model.terrain, &p);
    let mut t = [D::from(0.0); 2];
    tangential_coordinates(model.basis, &model.terrain, &p, &mut t);
    for d in 0..nt {
        work += (beta[d] - beta[d + nt]) * t[d];
    }
    work
}

/// Gradient of [`contact_work`] over z = [q; c; β]: [Nᵀc + Pᵀβ share; φ; ±t_d], by the chain
/// rule from the point's first derivatives.
pub fn contact_work_gradient<M: MechanicsDerivatives>(
    mech: &M,
    model: &ContactModel,
    contact: usize,
    z: &[f64],
) -> Vec<f64> {
    let n = mech.nq();
    let nt = model.nd() / 2;
    let geometry = ContactGeometry::new(mech, model, contact, &z[..n], 1);
    let mut out = geometry.gradient(&work_weights(&geometry, z));
    let k = geometry.value();
    out.push(k[0]);
    for sign in [1.0, -1.0] {
        for d in 0..nt {
            out.push(sign * k[1 + d]);
        }
    }
    out
}

/// b = [c, β⁺ − β⁻] of contact work, the weights of K = [φ, t] in it.
fn work_weights(geometry: &ContactGeometry, z: &[f64]) -> [f64; 3] {
    let n = geometry.n();
    let nt = geometry.model().nd() / 2;
    let mut b = [z[n], 0.0, 0.0];
    for d in 0..nt {
        b[1 + d] = z[n + 1 + d] - z[n + 1 + d + nt];
    }
    b
}

/// Hessian of [`contact_work`] over z = [q; c; β] (the Jacobian of its DEL-row gradient) by the
/// chain rule: with b = [c, β⁺ − β⁻] and K = [φ, t], the q–q block is ∇²(bᵀK), the q–c column
/// ∇φ and the q–β⁺/β⁻ columns ±∇t_d (the function is linear in c and β).
pub fn contact_work_hessian<M: MechanicsDerivatives>(
    mech: &M,
    model: &ContactModel,
    contact: usize,
    z: &[f64],
) -> DMatrix<f64> {
    let geometry = ContactGeometry::new(mech, model, contact, &z[..mech.nq()], 2);
    contact_work_hessian_in(&geometry, z)
}

/// [`contact_work_hessian`] from the contact's geometry at q (order ≥ 2).
pub(crate) fn contact_work_hessian_in(geometry: &ContactGeometry, z: &[f64]) -> DMatrix<f64> {
    let b = work_weights(geometry, z);
    with_multiplier_columns(
        geometry,
        |qq| geometry.add_hessian(&b, qq),
        &geometry.jacobian(),
    )
}

/// [`contact_work_hessian`] and the third derivative of [`contact_work`] contracted with `dir`
/// (the DEL-row multipliers on q; the c and β entries of `dir` must be zero, as their
/// gradient components go to no row), both (n + 1 + nd)², symmetric. Returns `None` when
/// `dir` has a nonzero c or β entry.
pub fn contact_work_third<M: MechanicsDerivatives>(
    mech: &M,
    model: &ContactModel,
    contact: usize,
    z: &[f64],
    dir: &[f64],
) -> Option<(DMatrix<f64>, DMatrix<f64>)> {
    let n = mech.nq();
    if dir[n..].iter().any(|&d| d != 0.0) {
        return None;
    }
    let geometry = ContactGeometry::new(mech, model, contact, &z[..n], 3);
    contact_work_third_in(&geometry, z, dir)
}

/// [`contact_work_third`] from the contact's geometry at q (order 3).
pub(crate) fn contact_work_third_in(
    geometry: &ContactGeometry,
    z: &[f64],
    dir: &[f64],
) -> Option<(DMatrix<f64>, DMatrix<f64>)> {
    let contracted = contact_work_contracted_in(geometry, z, dir)?;
    Some((contact_work_hessian_in(geometry, z), contracted))
}

/// The third derivative of [`contact_work`] contracted with `dir` alone, from the geometry
/// at q (order 3): what the Lagrangian Hessian needs. `None` when `dir` has a nonzero c or
/// β entry (as [`contact_work_third`]).
pub(crate) fn contact_work_contracted_in(
    geometry: &ContactGeometry,
    z: &[f64],
    dir: &[f64],
) -> Option<DMatrix<f64>> {
    let n = geometry.n();
    if dir[n..].iter().any(|&d| d != 0.0) {
        return None;
    }
    let b = work_weights(geometry, z);
    Some(with_multiplier_columns(
        geometry,
        |qq| geometry.add_third(&b, &dir[..n], qq),
        &geometry.directional(&dir[..n]),
    ))
}

/// The (n + 1 + nd)² matrix whose q–q block `qq` adds into (zero before), with the q–c and
/// q–β entries from the rows of `rows` (∇K_k for the Hessian, (∇²K_k)·dir for the
/// contracted third derivative; sign ± for β⁺/β⁻).
fn with_multiplier_columns(
    geometry: &ContactGeometry,
    qq: impl FnOnce(&mut DMatrixViewMut<f64>),
    rows: &DMatrix<f64>,
) -> DMatrix<f64> {
    let (n, nd) = (geometry.n(), geometry.model().nd());
    let nt = nd / 2;
    let dim = n + 1 + nd;
    let mut m = DMatrix::zeros(dim, dim);
    qq(&mut m.view_mut((0, 0), (n, n)));
    let beta_columns =
        (0..nt).flat_map(|d| [(n + 1 + d, 1 + d, 1.0), (n + 1 + d + nt, 1 + d, -1.0)]);
    for (col, row_k, sign) in std::iter::once((n, 0, 1.0)).chain(beta_columns) {
        for i in 0..n {
            let g = sign * rows[(row_k, i)];
            m[(i, col)] = g;
            m[(col, i)] = g;
        }
    }
    m
}
