//! The friction directions D_i(q) and the tangential-velocity rows ±P_i(qb)(qb − qa)/h + ψe − η
//! of a contact, the spin part of a rolling sphere's friction impulse, and their derivatives
//! (chain rule for a sliding point, generic forward AD for a rolling sphere).

use nalgebra::DMatrix;
use num_dual::Dual;

use super::{ContactGeometry, ContactModel, tangential_coordinates};
use crate::autodiff::Scalar;
use crate::autodiff::{VectorFunction, jacobian, weighted_hessian};
use crate::discrete::{Mechanics, MechanicsDerivatives, difference_velocity};

/// Tangential velocity D_i(q)·q̇ of contact `i` at q moving with q̇ into `out` (length
/// tangents): the friction directions D_i are defined here, for the NLP and the simulator.
/// For a point, the rate of its tangential coordinates (a forward directional derivative
/// of its position); for a rolling sphere, that of its lowest material point, which adds
/// the spin columns ([`Mechanics::contact_spin_columns`]).
fn tangential_rates<D: Scalar, M: Mechanics>(
    mech: &M,
    model: &ContactModel,
    contact: usize,
    q: &[D],
    qdot: &[D],
    out: &mut [D],
) {
    let moving: Vec<Dual<D>> = q.iter().zip(qdot).map(|(&a, &b)| Dual::new(a, b)).collect();
    let p = mech.contact_position(contact, &moving);
    let mut t = [Dual::from_re(D::from(0.0)); 2];
    tangential_coordinates(model.basis, &model.terrain, &p, &mut t);
    for (o, ti) in out.iter_mut().zip(t) {
        *o = ti.eps;
    }
    for (i, column) in mech.contact_spin_columns(contact, q) {
        let mut s = [D::from(0.0); 2];
        tangential_coordinates(model.basis, &model.terrain, &column, &mut s);
        for (o, si) in out.iter_mut().zip(s) {
            *o += si * qdot[i];
        }
    }
}

/// ±P_i(qb)(qb − qa)/h, the nonlinear part of the tangential-velocity rows;
/// z = [qa; qb; h], out length nd ([+D·q̇; −D·q̇]).
pub fn tangential_rate<D: Scalar, M: Mechanics>(
    mech: &M,
    model: &ContactModel,
    contact: usize,
    z: &[D],
    out: &mut [D],
) {
    let n = mech.nq();
    let nt = model.nd() / 2;
    let (qa, qb, h) = (&z[..n], &z[n..2 * n], z[2 * n]);
    let qdot = difference_velocity(qa, qb, h);
    let mut rate = [D::from(0.0); 2];
    tangential_rates(mech, model, contact, qb, &qdot, &mut rate[..nt]);
    for d in 0..nt {
        out[d] = rate[d];
        out[d + nt] = -rate[d];
    }
}

/// ψ e − η, the linear part of the tangential-velocity rows; z = [ψ; η (nd)].
pub fn tangential_slack<D: Scalar>(z: &[D], out: &mut [D]) {
    for (o, &eta) in out.iter_mut().zip(&z[1..]) {
        *o = z[0] - eta;
    }
}

/// The spin part of a rolling contact's friction impulse, Σ_d (β⁺_d − β⁻_d)·S_dᵀ with S_d
/// the tangential components of the spin columns (D_d = ∂t_d/∂q + S_d), into `out` (length
/// n); z = [q; c; β]. [`super::contact_work`]'s gradient holds the rest of Nᵀc + Pᵀβ.
pub fn spin_friction<D: Scalar, M: Mechanics>(
    mech: &M,
    model: &ContactModel,
    contact: usize,
    z: &[D],
    out: &mut [D],
) {
    let (n, nd) = (mech.nq(), model.nd());
    let nt = nd / 2;
    let beta = &z[n + 1..n + 1 + nd];
    out.fill(D::from(0.0));
    for (i, column) in mech.contact_spin_columns(contact, &z[..n]) {
        let mut s = [D::from(0.0); 2];
        tangential_coordinates(model.basis, &model.terrain, &column, &mut s);
        for d in 0..nt {
            out[i] += (beta[d] - beta[d + nt]) * s[d];
        }
    }
}

/// Jacobian (nd × (2n + 1)) of [`tangential_rate`] at z = [qa; qb; h] by the chain rule:
/// with v = (qb − qa)/h and D = ∂t/∂q at qb, row d is [−D_d/h, (∂²t_d/∂q²)v + D_d/h,
/// −D_d·v/h] (rows d + nt negated).
pub fn tangential_rate_jacobian<M: MechanicsDerivatives>(
    mech: &M,
    model: &ContactModel,
    contact: usize,
    z: &[f64],
) -> DMatrix<f64> {
    if mech.contact_rolls(contact) {
        return rolling_rate_derivatives(mech, model, contact, z, None);
    }
    let n = mech.nq();
    let geometry = ContactGeometry::new(mech, model, contact, &z[n..2 * n], 2);
    tangential_rate_jacobian_in(&geometry, z)
}

/// [`tangential_rate_jacobian`] of a sliding (non-rolling) contact from its geometry at qb
/// (order ≥ 2).
pub(crate) fn tangential_rate_jacobian_in(geometry: &ContactGeometry, z: &[f64]) -> DMatrix<f64> {
    let n = geometry.n();
    let nt = geometry.model().nd() / 2;
    let (qa, qb, h) = (&z[..n], &z[n..2 * n], z[2 * n]);
    let v = difference_velocity(qa, qb, h);
    let (jacobian, directional) = (geometry.jacobian(), geometry.directional(&v));
    let mut out = DMatrix::zeros(2 * nt, 2 * n + 1);
    for d in 0..nt {
        let (jac, hv) = (jacobian.row(1 + d), directional.row(1 + d));
        let rate = jac.dot(&nalgebra::RowDVector::from_row_slice(&v));
        for sign_row in [(1.0, d), (-1.0, d + nt)] {
            let (sign, r) = sign_row;
            for c in 0..n {
                out[(r, c)] = -sign * jac[c] / h;
                out[(r, n + c)] = sign * (hv[c] + jac[c] / h);
            }
            out[(r, 2 * n)] = -sign * rate / h;
        }
    }
    out
}

/// Σ_r w_r ∇²(rate_r) of [`tangential_rate`] at z = [qa; qb; h] ((2n + 1)², symmetric) by the
/// chain rule. With a = w_d − w_{d+nt}, s(q) = aᵀt(q), G = ∇s, H = ∇²s, T = ∇²(∇s·v) at qb:
/// qb–qa −H/h, qb–qb T + 2H/h, h–qa G/h², h–qb −Hv/h − G/h², h–h 2G·v/h² (qa–qa zero).
pub fn tangential_rate_hessian<M: MechanicsDerivatives>(
    mech: &M,
    model: &ContactModel,
    contact: usize,
    z: &[f64],
    w: &[f64],
) -> DMatrix<f64> {
    if mech.contact_rolls(contact) {
        return rolling_rate_derivatives(mech, model, contact, z, Some(w));
    }
    let n = mech.nq();
    let geometry = ContactGeometry::new(mech, model, contact, &z[n..2 * n], 3);
    tangential_rate_hessian_in(&geometry, z, w)
}

/// [`tangential_rate_hessian`] of a sliding (non-rolling) contact from its geometry at qb
/// (order 3).
pub(crate) fn tangential_rate_hessian_in(
    geometry: &ContactGeometry,
    z: &[f64],
    w: &[f64],
) -> DMatrix<f64> {
    let n = geometry.n();
    let nt = geometry.model().nd() / 2;
    let (qa, qb, h) = (&z[..n], &z[n..2 * n], z[2 * n]);
    let v = difference_velocity(qa, qb, h);
    let mut weights = [0.0; 3];
    for d in 0..nt {
        weights[1 + d] = w[d] - w[d + nt];
    }
    let g = geometry.gradient(&weights);
    let mut out = DMatrix::zeros(2 * n + 1, 2 * n + 1);
    // H and T go straight into the qb–qa and qb–qb blocks (no n × n temporaries); each
    // entry of H is read there before it is scaled in place.
    geometry.add_hessian(&weights, &mut out.view_mut((n, 0), (n, n)));
    geometry.add_third(&weights, &v, &mut out.view_mut((n, n), (n, n)));
    let hv = out.view((n, 0), (n, n)) * nalgebra::DVector::from_column_slice(&v);
    let gv: f64 = g.iter().zip(&v).map(|(a, b)| a * b).sum();
    let (h2, ih) = (h * h, 1.0 / h);
    for i in 0..n {
        for j in 0..n {
            let hs = out[(n + i, j)];
            out[(n + i, n + j)] += 2.0 * hs * ih;
            out[(n + i, j)] = -hs * ih;
            out[(j, n + i)] = -hs * ih;
        }
        out[(2 * n, i)] = g[i] / h2;
        out[(i, 2 * n)] = g[i] / h2;
        let hq = -hv[i] * ih - g[i] / h2;
        out[(2 * n, n + i)] = hq;
        out[(n + i, 2 * n)] = hq;
    }
    out[(2 * n, 2 * n)] = 2.0 * gv / h2;
    out
}

/// [`tangential_rate`] of one contact as an AD function of z = [qa; qb; h].
struct TangentialRate<'a, M> {
    mech: &'a M,
    model: &'a ContactModel,
    contact: usize,
}

impl<M: Mechanics> VectorFunction for TangentialRate<'_, M> {
    fn dim_in(&self) -> usize {
        2 * self.mech.nq() + 1
    }
    fn dim_out(&self) -> usize {
        self.model.nd()
    }
    fn eval<D: Scalar>(&self, z: &[D], out: &mut [D]) {
        tangential_rate(self.mech, self.model, self.contact, z, out);
    }
}

/// [`spin_friction`] of one contact as an AD function of z = [q; c; β].
struct SpinFriction<'a, M> {
    mech: &'a M,
    model: &'a ContactModel,
    contact: usize,
}

impl<M: Mechanics> VectorFunction for SpinFriction<'_, M> {
    fn dim_in(&self) -> usize {
        self.mech.nq() + 1 + self.model.nd()
    }
    fn dim_out(&self) -> usize {
        self.mech.nq()
    }
    fn eval<D: Scalar>(&self, z: &[D], out: &mut [D]) {
        spin_friction(self.mech, self.model, self.contact, z, out);
    }
}

/// Jacobian (and, with weights, Σ_r w_r ∇²(rate_r)) of a rolling contact's
/// [`tangential_rate`] by generic forward AD: its spin columns come from the kinematics
/// generic over the scalar, with no jets of their own.
fn rolling_rate_derivatives<M: Mechanics>(
    mech: &M,
    model: &ContactModel,
    contact: usize,
    z: &[f64],
    w: Option<&[f64]>,
) -> DMatrix<f64> {
    let f = TangentialRate {
        mech,
        model,
        contact,
    };
    match w {
        Some(w) => weighted_hessian(&f, z, w),
        None => jacobian(&f, z).1,
    }
}

/// The spin part of a rolling contact's friction impulse ([`spin_friction`]) and its Jacobian
/// over z = [q; c; β] (n × (n + 1 + nd)) by generic forward AD, for the simulator's knot rows.
pub fn spin_friction_jacobian<M: Mechanics>(
    mech: &M,
    model: &ContactModel,
    contact: usize,
    z: &[f64],
) -> (Vec<f64>, DMatrix<f64>) {
    let f = SpinFriction {
        mech,
        model,
        contact,
    };
    jacobian(&f, z)
}
