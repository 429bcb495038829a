//! [`Mechanics`] for a URDF [`Model`]: the midpoint (or rectangle-rule) discrete Lagrangian
//! from the model's energies, inputs and damping in Fd, contacts resolved by link name.

use super::{Mechanics, TranscriptionError};
use crate::model::{
    LinkId, Model, Scalar, generalized_input_force, generalized_momentum, kinetic_energy,
    loop_residual, point_position, potential_energy,
};
use crate::problem::{ContactSpec, Integrator, Interval, ProblemSpec};

/// A URDF model with the problem's contact points resolved to links.
#[derive(Debug)]
pub struct ModelMechanics {
    model: Model,
    contacts: Vec<(LinkId, [f64; 3])>,
}

impl ModelMechanics {
    /// Resolve each contact's link by name; the error names the contact and the link.
    pub fn new(model: Model, contacts: &[ContactSpec]) -> Result<Self, TranscriptionError> {
        let mut resolved = Vec::with_capacity(contacts.len());
        for (k, c) in contacts.iter().enumerate() {
            let link = model
                .link_index(&c.link)
                .ok_or_else(|| TranscriptionError::Invalid {
                    field: format!("contacts[{k}].link"),
                    message: format!(
                        "contact `{}` names link `{}`, which the URDF does not have (links: {})",
                        c.name,
                        c.link,
                        model.link_names().join(", ")
                    ),
                })?;
            resolved.push((link, c.point));
        }
        Ok(ModelMechanics {
            model,
            contacts: resolved,
        })
    }

    /// Load the robot of `spec` from its URDF (base and gravity from the spec) with the
    /// spec's contacts.
    pub fn load(spec: &ProblemSpec) -> Result<Self, TranscriptionError> {
        let mut model = Model::from_urdf_file(&spec.robot.urdf, spec.robot.base)?;
        model.set_gravity(spec.robot.gravity);
        ModelMechanics::new(model, &spec.contacts)
    }

    /// The model.
    pub fn model(&self) -> &Model {
        &self.model
    }

    /// The point the integrator evaluates position-dependent terms at.
    fn eval_point<D: Scalar>(integrator: Integrator, qa: &[D], qb: &[D]) -> Vec<D> {
        match integrator {
            Integrator::Midpoint => qa
                .iter()
                .zip(qb)
                .map(|(&a, &b)| (a + b) * D::from(0.5))
                .collect(),
            Integrator::Euler => qa.to_vec(),
        }
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
    fn coordinate_limits(&self) -> Vec<Interval> {
        self.model
            .coordinate_limits()
            .iter()
            .map(|&(lower, upper)| Interval { lower, upper })
            .collect()
    }
    fn coordinate_names(&self) -> Vec<String> {
        self.model.coordinate_names().to_vec()
    }
    fn input_names(&self) -> Vec<String> {
        self.model.input_names().to_vec()
    }
    fn has_discrete_force(&self) -> bool {
        !self.model.input_names().is_empty() || self.model.damping().iter().any(|&d| d != 0.0)
    }
    fn discrete_lagrangian<D: Scalar>(
        &self,
        integrator: Integrator,
        qa: &[D],
        qb: &[D],
        h: D,
    ) -> D {
        match integrator {
            Integrator::Midpoint => crate::discrete::ld(&self.model, qa, qb, h),
            Integrator::Euler => {
                // Rectangle rule h·L(qa, (qb − qa)/h): the variational form of
                // semi-implicit (symplectic) Euler, first order.
                let v: Vec<D> = qa.iter().zip(qb).map(|(&a, &b)| (b - a) / h).collect();
                (kinetic_energy(&self.model, qa, &v) - potential_energy(&self.model, qa)) * h
            }
        }
    }
    fn discrete_force<D: Scalar>(
        &self,
        integrator: Integrator,
        qa: &[D],
        qb: &[D],
        u: &[D],
        h: D,
        out: &mut [D],
    ) {
        let q = Self::eval_point(integrator, qa, qb);
        let force = if u.is_empty() {
            vec![D::from(0.0); qa.len()]
        } else {
            generalized_input_force(&self.model, &q, u)
        };
        let damping = self.model.damping();
        for i in 0..out.len() {
            out[i] = force[i] * h - (qb[i] - qa[i]) * D::from(damping[i]);
        }
    }
    fn momentum<D: Scalar>(&self, q: &[D], v: &[D], out: &mut [D]) {
        out.copy_from_slice(&generalized_momentum(&self.model, q, v));
    }
    fn contact_position<D: Scalar>(&self, contact: usize, q: &[D]) -> [D; 3] {
        let (link, point) = &self.contacts[contact];
        point_position(&self.model, *link, point, q)
    }
    fn loop_residual<D: Scalar>(&self, q: &[D], out: &mut [D]) {
        out.copy_from_slice(&loop_residual(&self.model, q));
    }
}
