//! A contact's terrain coordinates K(q) = κ(p(q)) = [φ, t_1 (, t_2)] and their derivatives in
//! q, composed from the point's jet ([`MechanicsDerivatives::contact_jet`]: analytic for URDF models)
//! and forward AD of κ over the three components of p. Every contact block's chain-rule
//! derivatives are built from these, so no dual number goes through the kinematic chain.

use nalgebra::{DMatrix, DMatrixViewMut, Matrix3, Vector3};

use super::ContactModel;
use super::{signed_distance, tangential_coordinates};
use crate::autodiff::Scalar;
use crate::autodiff::{
    ScalarFunction, ThirdOrder, gradient_hessian_into, gradient_hessian_third_into,
};
use crate::discrete::MechanicsDerivatives;
use crate::model::PointJet;

/// κ_k(p): the k-th terrain coordinate (0: signed distance, 1 + d: tangential d) of a point.
struct TerrainCoordinate<'a> {
    model: &'a ContactModel,
    component: usize,
}

impl ScalarFunction for TerrainCoordinate<'_> {
    fn dim(&self) -> usize {
        3
    }
    fn eval<D: Scalar>(&self, p: &[D]) -> D {
        let p = [p[0], p[1], p[2]];
        if self.component == 0 {
            return signed_distance(&self.model.terrain, &p);
        }
        let mut t = [D::from(0.0); 2];
        tangential_coordinates(self.model.basis, &self.model.terrain, &p, &mut t);
        t[self.component - 1]
    }
}

/// K(q) and its derivatives at one configuration.
pub(crate) struct ContactGeometry<'a> {
    model: &'a ContactModel,
    n: usize,
    jet: PointJet,
    /// Rows of K: 1 + tangents.
    rows: usize,
    /// κ_k(p).
    value: [f64; 3],
    /// ∇κ_k(p).
    gradient: [Vector3<f64>; 3],
    /// ∇²κ_k(p).
    hessian: [Matrix3<f64>; 3],
}

impl<'a> ContactGeometry<'a> {
    /// Derivatives of K at q up to `order` (1 to 3: the third is contracted on demand by
    /// [`ContactGeometry::third`], which needs order 3).
    pub(crate) fn new<M: MechanicsDerivatives>(
        mech: &M,
        model: &'a ContactModel,
        contact: usize,
        q: &[f64],
        order: usize,
    ) -> Self {
        Self::with_jet(mech, model, contact, q, order, PointJet::default())
    }

    /// [`ContactGeometry::new`] with the point jet written into `jet`'s storage (one a
    /// previous geometry gave back by [`ContactGeometry::into_jet`]); the same numbers.
    pub(crate) fn with_jet<M: MechanicsDerivatives>(
        mech: &M,
        model: &'a ContactModel,
        contact: usize,
        q: &[f64],
        order: usize,
        mut jet: PointJet,
    ) -> Self {
        mech.contact_jet_into(contact, q, order, &mut jet);
        let rows = 1 + model.nd() / 2;
        let mut value = [0.0; 3];
        let mut gradient = [Vector3::zeros(); 3];
        let mut hessian = [Matrix3::zeros(); 3];
        let (mut g, mut h) = ([0.0; 3], DMatrix::zeros(3, 3));
        for k in 0..rows {
            // One tile of three inputs: κ is a function of p alone.
            let f = TerrainCoordinate {
                model,
                component: k,
            };
            value[k] = gradient_hessian_into::<3, _>(&f, &jet.position, &mut g, &mut h);
            gradient[k] = Vector3::from(g);
            hessian[k] = Matrix3::from_column_slice(h.as_slice());
        }
        ContactGeometry {
            model,
            n: q.len(),
            jet,
            rows,
            value,
            gradient,
            hessian,
        }
    }

    /// The point jet, for [`ContactGeometry::with_jet`] to reuse its storage.
    pub(crate) fn into_jet(self) -> PointJet {
        self.jet
    }

    /// Coordinates n.
    pub(super) fn n(&self) -> usize {
        self.n
    }

    /// The contact model it was built with.
    pub(super) fn model(&self) -> &'a ContactModel {
        self.model
    }

    /// K(q) (length `rows`; the rest zero).
    pub(super) fn value(&self) -> [f64; 3] {
        self.value
    }

    fn first(&self, a: usize) -> Vector3<f64> {
        Vector3::from(self.jet.first[a])
    }

    fn second(&self, a: usize, b: usize) -> Vector3<f64> {
        Vector3::from(self.jet.second[a * self.jet.len() + b])
    }

    /// The direction in chain coordinates.
    fn local(&self, dir: &[f64]) -> Vec<f64> {
        self.jet.coords.iter().map(|&i| dir[i]).collect()
    }

    /// ṗ = P1·d for a direction d in chain coordinates.
    fn point_rate(&self, d: &[f64]) -> Vector3<f64> {
        let mut pdot = Vector3::zeros();
        for (a, &da) in d.iter().enumerate() {
            pdot += da * self.first(a);
        }
        pdot
    }

    /// Q_a = Σ_b d_b ∇²p[a, b] for chain coordinate a and a direction d in chain coordinates.
    fn second_along(&self, a: usize, d: &[f64]) -> Vector3<f64> {
        (0..self.jet.len()).fold(Vector3::zeros(), |acc, b| acc + d[b] * self.second(a, b))
    }

    fn weighted(&self, w: &[f64]) -> (Vector3<f64>, Matrix3<f64>) {
        let mut g = Vector3::zeros();
        let mut h = Matrix3::zeros();
        for (k, &wk) in w.iter().enumerate().take(self.rows) {
            g += wk * self.gradient[k];
            h += wk * self.hessian[k];
        }
        (g, h)
    }

    /// ∂K/∂q, rows × n.
    pub(super) fn jacobian(&self) -> DMatrix<f64> {
        let mut out = DMatrix::zeros(self.rows, self.n);
        for (a, &i) in self.jet.coords.iter().enumerate() {
            let pa = self.first(a);
            for k in 0..self.rows {
                out[(k, i)] += self.gradient[k].dot(&pa);
            }
        }
        out
    }

    /// Σ_k w_k ∇²K_k (n × n; needs order ≥ 2): P1ᵀ H_w P1 + Σ_m (g_w)_m ∇²p_m.
    pub(super) fn hessian(&self, w: &[f64]) -> DMatrix<f64> {
        let mut out = DMatrix::zeros(self.n, self.n);
        self.add_hessian(w, &mut out.view_mut((0, 0), (self.n, self.n)));
        out
    }

    /// Adds [`ContactGeometry::hessian`] into the n × n `out` (a block of the caller's
    /// matrix, so that no n × n temporary is formed); only the chain's coordinates are
    /// touched.
    pub(super) fn add_hessian(&self, w: &[f64], out: &mut DMatrixViewMut<f64>) {
        let (gw, hw) = self.weighted(w);
        let c = self.jet.len();
        for a in 0..c {
            let hpa = hw * self.first(a);
            for b in 0..c {
                let v = hpa.dot(&self.first(b)) + gw.dot(&self.second(a, b));
                out[(self.jet.coords[a], self.jet.coords[b])] += v;
            }
        }
    }

    /// Rows (∇²K_k)·dir, rows × n (needs order ≥ 2), in chain coordinates: with ṗ = P1·dir
    /// and Q_a = Σ_b dir_b ∇²p[a, b], entry (k, q_a) is P_a·(∇²κ_k ṗ) + ∇κ_k·Q_a.
    pub(super) fn directional(&self, dir: &[f64]) -> DMatrix<f64> {
        let c = self.jet.len();
        let d = self.local(dir);
        let pdot = self.point_rate(&d);
        let hp = self.hessian.map(|h| h * pdot);
        let mut out = DMatrix::zeros(self.rows, self.n);
        for a in 0..c {
            let pa = self.first(a);
            let qa = self.second_along(a, &d);
            for k in 0..self.rows {
                out[(k, self.jet.coords[a])] += pa.dot(&hp[k]) + self.gradient[k].dot(&qa);
            }
        }
        out
    }

    /// ∇²(∇(Σ_k w_k K_k)·dir) (n × n; needs order 3). With s = wᵀκ, ṗ = P1·dir,
    /// Q_a = ∂(P1·dir)/∂q_a and S = ∂²(P1·dir)/∂q²:
    /// (P1ᵀ ∇³s[ṗ] P1) + Σ_r (∇²s ṗ)_r ∇²p_r + P1ᵀ ∇²s Q + Qᵀ ∇²s P1 + Σ_m (∇s)_m S_m.
    /// Added into the n × n `out` (a block of the caller's matrix); only the chain's
    /// coordinates are touched.
    pub(super) fn add_third(&self, w: &[f64], dir: &[f64], out: &mut DMatrixViewMut<f64>) {
        let c = self.jet.len();
        let d = self.local(dir);
        let pdot = self.point_rate(&d);
        // ∇s, ∇²s and ∇³s contracted with ṗ, all in p.
        let mut gw = Vector3::zeros();
        let mut hw = Matrix3::zeros();
        let mut tw = Matrix3::zeros();
        // One buffer for the rows (each pass overwrites it).
        let mut s = ThirdOrder::zeros(3);
        for (k, &wk) in w.iter().enumerate().take(self.rows) {
            if wk == 0.0 {
                continue;
            }
            let f = TerrainCoordinate {
                model: self.model,
                component: k,
            };
            gradient_hessian_third_into::<3, _>(&f, &self.jet.position, pdot.as_slice(), &mut s);
            gw += wk * Vector3::from_column_slice(&s.gradient);
            hw += wk * Matrix3::from_column_slice(s.hessian.as_slice());
            tw += wk * Matrix3::from_column_slice(s.contracted.as_slice());
        }
        let q: Vec<Vector3<f64>> = (0..c).map(|a| self.second_along(a, &d)).collect();
        let hp = hw * pdot;
        for a in 0..c {
            let (pa, qa) = (self.first(a), q[a]);
            let (tpa, hpa, hqa) = (tw * pa, hw * pa, hw * qa);
            for b in 0..c {
                let (pb, qb) = (self.first(b), q[b]);
                let base = (a * c + b) * c;
                let s = (0..c).fold(Vector3::zeros(), |acc, e| {
                    acc + d[e] * Vector3::from(self.jet.third[base + e])
                });
                let v = tpa.dot(&pb)
                    + hp.dot(&self.second(a, b))
                    + hpa.dot(&qb)
                    + hqa.dot(&pb)
                    + gw.dot(&s);
                out[(self.jet.coords[a], self.jet.coords[b])] += v;
            }
        }
    }

    /// Σ_k w_k ∇K_k (length n).
    pub(super) fn gradient(&self, w: &[f64]) -> Vec<f64> {
        let (gw, _) = self.weighted(w);
        let mut out = vec![0.0; self.n];
        for (a, &i) in self.jet.coords.iter().enumerate() {
            out[i] += gw.dot(&self.first(a));
        }
        out
    }
}
