//! The mechanics of a problem's URDF robot: the model loaded with the problem's base and
//! gravity, its contacts resolved by link name.

use super::TranscriptionError;
use crate::discrete::{ContactSphere, ModelMechanics};
use crate::model::Model;
use crate::problem::{ContactSpec, ProblemSpec};

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
            resolved.push(ContactSphere {
                link,
                centre: c.point,
                radius: c.radius,
            });
        }
        Ok(ModelMechanics::with_contacts(model, resolved))
    }

    /// Load the robot of `spec` from its URDF (base and gravity from the spec) with the
    /// spec's contacts.
    pub fn load(spec: &ProblemSpec) -> Result<Self, TranscriptionError> {
        let mut model = Model::from_urdf_file(&spec.robot.urdf, spec.robot.base)?;
        model.set_gravity(spec.robot.gravity);
        model
            .actuate(&spec.robot.actuation)
            .map_err(|e| TranscriptionError::Invalid {
                field: "inputs.actuated".into(),
                message: e.to_string(),
            })?;
        ModelMechanics::new(model, &spec.contacts)
    }
}
