//! [`Mechanics`] for a URDF [`Model`]: the midpoint discrete Lagrangian from the model's
//! energies, inputs and damping in Fd, the Euler residual from its inverse dynamics, and
//! [`MechanicsDerivatives`] by the model's adjoint (Ld) and chain formulas (contact jets).

use nalgebra::DMatrix;

use super::{
    GroupSweeps, LdBuffers, Mechanics, MechanicsDerivatives, midpoint_gradient_hessian,
    midpoint_gradient_hessian_grouped, midpoint_ld_gradient, midpoint_third_order_columns,
    midpoint_third_order_grouped,
};
use crate::autodiff::Scalar;
use crate::autodiff::{SymmetricGroups, ThirdOrder};
use crate::model::{
    LinkId, LoopJet, Model, PointJet, generalized_momentum, link_angular_jacobian, link_pose,
    loop_closure_jets, loop_residual, point_jet_into, point_position,
};

/// A contact resolved to its link: a sphere (radius 0: a point) fixed on the link.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ContactSphere {
    /// The link.
    pub link: LinkId,
    /// The centre in the link frame (length units).
    pub centre: [f64; 3],
    /// The radius (length units).
    pub radius: f64,
}

impl ContactSphere {
    /// A point contact (radius 0).
    pub fn point(link: LinkId, centre: [f64; 3]) -> Self {
        ContactSphere {
            link,
            centre,
            radius: 0.0,
        }
    }
}

/// A URDF model with the problem's contacts resolved to links.
#[derive(Debug)]
pub struct ModelMechanics {
    model: Model,
    contacts: Vec<ContactSphere>,
}

impl ModelMechanics {
    /// The model with its contacts, in the problem's contact order.
    pub fn with_contacts(model: Model, contacts: Vec<ContactSphere>) -> Self {
        ModelMechanics { model, contacts }
    }

    /// The model.
    pub fn model(&self) -> &Model {
        &self.model
    }
}

impl Mechanics for ModelMechanics {
    fn nq(&self) -> usize {
        self.model.nq()
    }
    fn nu(&self) -> usize {
        self.model.input_names().len()
    }
    fn num_loop_constraints(&self) -> usize {
        self.model.num_loop_constraints()
    }
    fn num_contacts(&self) -> usize {
        self.contacts.len()
    }
    fn coordinate_limits(&self) -> Vec<(f64, f64)> {
        self.model.coordinate_limits().to_vec()
    }
    fn coordinate_names(&self) -> Vec<String> {
        self.model.coordinate_names().to_vec()
    }
    fn input_names(&self) -> Vec<String> {
        self.model.input_names().to_vec()
    }
    fn moves_in_xz_plane(&self) -> bool {
        self.model.moves_in_xz_plane()
    }
    fn weight(&self) -> Option<f64> {
        let g = self.model.gravity();
        Some(self.model.total_mass() * (g[0] * g[0] + g[1] * g[1] + g[2] * g[2]).sqrt())
    }
    fn has_discrete_force(&self) -> bool {
        !self.model.input_names().is_empty() || self.model.damping().iter().any(|&d| d != 0.0)
    }
    fn discrete_lagrangian<D: Scalar>(&self, qa: &[D], qb: &[D], h: D) -> D {
        crate::discrete::ld(&self.model, qa, qb, h)
    }
    fn discrete_force<D: Scalar>(&self, qa: &[D], qb: &[D], u: &[D], h: D, out: &mut [D]) {
        out.copy_from_slice(&crate::discrete::discrete_force(&self.model, qa, qb, u, h));
    }
    fn euler_residual<D: Scalar>(
        &self,
        v_k: &[D],
        q_k: &[D],
        q_next: &[D],
        h: D,
        u: &[D],
        out: &mut [D],
    ) {
        out.copy_from_slice(&crate::discrete::euler_residual(
            &self.model,
            v_k,
            q_k,
            q_next,
            h,
            u,
        ));
    }
    fn momentum<D: Scalar>(&self, q: &[D], v: &[D], out: &mut [D]) {
        out.copy_from_slice(&generalized_momentum(&self.model, q, v));
    }
    /// A sphere's lowest point, centre − r·ẑ: the terrain's normal is +z wherever the
    /// signed distance is exact (it is the vertical distance, `contact::signed_distance`),
    /// so φ is the centre's distance minus r. This point moves with the centre; friction
    /// acts at the lowest *material* point, whose velocity adds the spin term
    /// ([`Mechanics::contact_spin_columns`]), so that friction turns the sphere.
    fn contact_position<D: Scalar>(&self, contact: usize, q: &[D]) -> [D; 3] {
        let c = &self.contacts[contact];
        let mut p = point_position(&self.model, c.link, &c.centre, q);
        if c.radius != 0.0 {
            p[2] -= D::from(c.radius);
        }
        p
    }
    fn link_pose<D: Scalar>(&self, link: usize, q: &[D]) -> Option<([[D; 3]; 3], [D; 3])> {
        (link < self.model.link_names().len()).then(|| link_pose(&self.model, LinkId(link), q))
    }
    fn contact_rolls(&self, contact: usize) -> bool {
        self.contacts[contact].radius != 0.0
    }
    /// r·ẑ × ∂ω/∂q̇ = r·(−∂ω_y/∂q̇, ∂ω_x/∂q̇, 0) per coordinate on the link's path.
    fn contact_spin_columns<D: Scalar>(&self, contact: usize, q: &[D]) -> Vec<(usize, [D; 3])> {
        let c = &self.contacts[contact];
        if c.radius == 0.0 {
            return Vec::new();
        }
        let r = D::from(c.radius);
        link_angular_jacobian(&self.model, c.link, q)
            .into_iter()
            .map(|(i, w)| (i, [-(r * w[1]), r * w[0], D::from(0.0)]))
            .collect()
    }
    fn loop_residual<D: Scalar>(&self, q: &[D], out: &mut [D]) {
        out.copy_from_slice(&loop_residual(&self.model, q));
    }
}

/// The model's ½Fd = ½(h·B·u − D·(qb − qa)), B the constant selection of the input
/// coordinates and D the diagonal damping ([`crate::discrete::discrete_force`]), is linear in
/// (qa, qb) and bilinear in (u, h): its Jacobian and weighted Hessian are written out.
impl MechanicsDerivatives for ModelMechanics {
    fn half_force_jacobian(&self, z: &[f64]) -> Option<DMatrix<f64>> {
        let (n, m) = (self.model.nq(), self.model.input_coordinates().len());
        let h = z[2 * n + m];
        let mut jacobian = DMatrix::zeros(n, 2 * n + m + 1);
        for (c, &d) in self.model.damping().iter().enumerate() {
            jacobian[(c, c)] = 0.5 * d;
            jacobian[(c, n + c)] = -0.5 * d;
        }
        for (i, &c) in self.model.input_coordinates().iter().enumerate() {
            jacobian[(c, 2 * n + i)] += 0.5 * h;
            jacobian[(c, 2 * n + m)] += 0.5 * z[2 * n + i];
        }
        Some(jacobian)
    }
    fn half_force_hessian(&self, z: &[f64], w: &[f64]) -> Option<DMatrix<f64>> {
        let (n, m) = (self.model.nq(), self.model.input_coordinates().len());
        let mut hessian = DMatrix::zeros(z.len(), z.len());
        for (i, &c) in self.model.input_coordinates().iter().enumerate() {
            hessian[(2 * n + i, 2 * n + m)] += 0.5 * w[c];
            hessian[(2 * n + m, 2 * n + i)] += 0.5 * w[c];
        }
        Some(hessian)
    }
    fn contact_jet(&self, contact: usize, q: &[f64], order: usize) -> PointJet {
        let mut jet = PointJet::default();
        self.contact_jet_into(contact, q, order, &mut jet);
        jet
    }
    fn contact_jet_into(&self, contact: usize, q: &[f64], order: usize, jet: &mut PointJet) {
        let c = &self.contacts[contact];
        point_jet_into(&self.model, c.link, &c.centre, q, order, jet);
        // The lowest point moves with the centre: a constant offset, the same derivatives.
        jet.position[2] -= c.radius;
    }
    fn segment_gradient(&self, z: &[f64]) -> Vec<f64> {
        let n = self.model.nq();
        let (mut d1, mut d2) = (vec![0.0; n], vec![0.0; n]);
        let (_, dh) = midpoint_ld_gradient(
            &self.model,
            &z[..n],
            &z[n..2 * n],
            z[2 * n],
            &mut d1,
            &mut d2,
            &mut LdBuffers::default(),
        );
        d1.extend(d2);
        d1.push(dh);
        d1
    }
    fn segment_gradient_hessian(&self, z: &[f64]) -> (Vec<f64>, DMatrix<f64>) {
        let (_, gradient, hessian) = midpoint_gradient_hessian(&self.model, z);
        (gradient, hessian)
    }
    fn segment_third_order(&self, z: &[f64], dir: &[f64], columns: Option<&[bool]>) -> ThirdOrder {
        let mut out = ThirdOrder::zeros(z.len());
        midpoint_third_order_columns(&self.model, z, dir, columns, &mut out);
        out
    }
    fn segment_gradient_hessian_grouped(
        &self,
        z: &[f64],
        groups: &SymmetricGroups,
    ) -> (Vec<f64>, DMatrix<f64>) {
        midpoint_gradient_hessian_grouped(&self.model, z, groups, GroupSweeps::Lanes)
    }
    fn segment_third_order_grouped(
        &self,
        z: &[f64],
        dir: &[f64],
        groups: &SymmetricGroups,
    ) -> ThirdOrder {
        // One `Dual<Dual64>` sweep per group: the lanes' `Dual<MultiDual<K>>` sweep takes
        // fewer instructions but more time (BENCHMARKS.md, "Tried and dropped").
        midpoint_third_order_grouped(&self.model, z, dir, groups, GroupSweeps::PerGroup)
    }
    fn loop_jets(&self, q: &[f64], order: usize, along: &[f64]) -> Vec<LoopJet> {
        loop_closure_jets(&self.model, q, order, along)
    }
    fn translation_coordinates(&self) -> Vec<bool> {
        self.model.translation_coordinates()
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::autodiff::finite_differences::{jacobian as fd_jacobian, values};
    use crate::model::{BaseType, sample};

    /// The model's mechanics with the Euler residual left to the trait's default (built
    /// from Ld, the momentum and Fd), to check the override against it.
    struct Defaulted<'a>(&'a ModelMechanics);
    impl Mechanics for Defaulted<'_> {
        fn nq(&self) -> usize {
            self.0.nq()
        }
        fn nu(&self) -> usize {
            self.0.nu()
        }
        fn num_contacts(&self) -> usize {
            0
        }
        fn has_discrete_force(&self) -> bool {
            self.0.has_discrete_force()
        }
        fn moves_in_xz_plane(&self) -> bool {
            self.0.moves_in_xz_plane()
        }
        fn discrete_lagrangian<D: Scalar>(&self, qa: &[D], qb: &[D], h: D) -> D {
            self.0.discrete_lagrangian(qa, qb, h)
        }
        fn discrete_force<D: Scalar>(&self, qa: &[D], qb: &[D], u: &[D], h: D, out: &mut [D]) {
            self.0.discrete_force(qa, qb, u, h, out)
        }
        fn momentum<D: Scalar>(&self, q: &[D], v: &[D], out: &mut [D]) {
            self.0.momentum(q, v, out)
        }
        fn contact_position<D: Scalar>(&self, contact: usize, q: &[D]) -> [D; 3] {
            self.0.contact_position(contact, q)
        }
    }

    /// Inverse dynamics (override, through `discrete::euler_residual`) and the default from
    /// the midpoint Ld agree on a damped, actuated planar chain with a planar base and on a
    /// floating brick (3-D rotations, Coriolis terms).
    #[test]
    fn euler_residual_override_matches_the_default_from_ld() {
        let chain = sample::damped_chain(3);
        for (xml, base) in [
            (chain.as_str(), BaseType::Planar),
            (sample::brick(), BaseType::Floating),
        ] {
            let model = Model::from_urdf_str(xml, base).expect("sample loads");
            let mech = ModelMechanics::with_contacts(model, Vec::new());
            let (n, m) = (mech.nq(), mech.nu());
            let wave = |k: usize, s: f64| (0.7 * k as f64 + s).sin();
            let q_k: Vec<f64> = (0..n).map(|k| wave(k, 0.3)).collect();
            let q_next: Vec<f64> = (0..n).map(|k| q_k[k] + 0.04 * wave(k, 1.1)).collect();
            let v_k: Vec<f64> = (0..n).map(|k| 1.5 * wave(k, 2.0)).collect();
            let u: Vec<f64> = (0..m).map(|k| 2.0 * wave(k, 0.5)).collect();
            let h = 0.03;
            let (mut over, mut default) = (vec![0.0; n], vec![0.0; n]);
            mech.euler_residual(&v_k, &q_k, &q_next, h, &u, &mut over);
            Defaulted(&mech).euler_residual(&v_k, &q_k, &q_next, h, &u, &mut default);
            let scale = over.iter().fold(0.0_f64, |a, b| a.max(b.abs()));
            assert!(scale > 1e-2, "a trivial residual proves nothing: {over:?}");
            for (a, b) in over.iter().zip(&default) {
                assert!(
                    (a - b).abs() < 1e-12 * scale.max(1.0),
                    "{over:?} vs {default:?}"
                );
            }
        }
    }
    /// The closed-form Jacobian and weighted Hessian of ½Fd equal forward AD through
    /// `discrete_force` (to 1e-14 of the largest entry) and central differences (1e-7) on a
    /// damped, actuated planar chain at a point with nonzero inputs, step and velocity.
    #[test]
    fn half_force_closed_forms_match_ad_and_finite_differences() {
        use crate::autodiff::{jacobian, weighted_hessian};
        use crate::discrete::HalfForce;
        let chain = sample::damped_chain(3);
        let model = Model::from_urdf_str(&chain, BaseType::Planar).expect("sample loads");
        let mech = ModelMechanics::with_contacts(model, Vec::new());
        let (n, m) = (mech.nq(), mech.nu());
        assert!(m > 0 && mech.model.damping().iter().any(|&d| d > 0.0));
        let dim = 2 * n + m + 1;
        let wave = |k: usize, s: f64| (0.7 * k as f64 + s).sin();
        let mut z: Vec<f64> = (0..dim).map(|k| wave(k, 0.4)).collect();
        z[dim - 1] = 0.037;
        let w: Vec<f64> = (0..n).map(|k| 1.0 + wave(k, 1.3)).collect();
        let f = HalfForce { mech: &mech };
        let exact_j = mech.half_force_jacobian(&z).expect("closed form");
        let exact_h = mech.half_force_hessian(&z, &w).expect("closed form");
        let ad_j = jacobian(&f, &z).1;
        let ad_h = weighted_hessian(&f, &z, &w);
        assert!((&exact_j - &ad_j).amax() <= 1e-14 * ad_j.amax().max(1.0));
        assert!((&exact_h - &ad_h).amax() <= 1e-14 * ad_h.amax().max(1.0));
        assert!(exact_h.amax() > 0.1, "a zero Hessian proves nothing");
        let weighted_row = |z: &[f64]| -> Vec<f64> {
            let j = mech.half_force_jacobian(z).expect("closed form");
            (0..dim)
                .map(|c| (0..n).map(|r| w[r] * j[(r, c)]).sum())
                .collect()
        };
        let fd_j = fd_jacobian(|x| values(&f, x), &z, |_| 1e-6);
        let fd_h = fd_jacobian(weighted_row, &z, |_| 1e-6);
        for c in 0..dim {
            for r in 0..n {
                let fd = fd_j[(r, c)];
                assert!((exact_j[(r, c)] - fd).abs() < 1e-7, "J[{r}, {c}]");
            }
            for r in 0..dim {
                let fd = fd_h[(r, c)];
                assert!((exact_h[(r, c)] - fd).abs() < 1e-7, "H[{r}, {c}]");
            }
        }
    }
}
