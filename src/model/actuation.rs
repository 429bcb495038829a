//! Which joints take an input: the URDF's `<transmission>` elements, every movable joint, or
//! a list by name (`[inputs] actuated` of a problem file).

use std::fmt;

use super::Model;

/// The rule that picks the actuated joints.
#[derive(Debug, Clone, PartialEq, Eq, Default)]
pub enum Actuation {
    /// The URDF's transmissions when it has any, otherwise every movable joint.
    #[default]
    Default,
    /// One input per `<transmission>`, in document order.
    Transmissions,
    /// Every movable (non-base) joint, in coordinate order.
    AllJoints,
    /// These joints, in this order.
    Joints(Vec<String>),
}

/// The rule that applied, as `inspect`, `init` and `check` report it.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum AppliedActuation {
    /// From `<transmission>` elements.
    #[default]
    Transmissions,
    /// Every movable joint.
    AllJoints,
    /// A list of joints by name.
    Joints,
}

impl fmt::Display for AppliedActuation {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(match self {
            AppliedActuation::Transmissions => "the URDF's transmissions",
            AppliedActuation::AllJoints => "every movable joint",
            AppliedActuation::Joints => "the joints listed in [inputs] actuated",
        })
    }
}

/// A joint that can take an input: its coordinate, its effort limit (∞ without `<limit>`),
/// and whether a `<transmission>` drives it.
#[derive(Debug, Clone, PartialEq)]
pub(crate) struct Actuator {
    pub joint: String,
    pub coordinate: usize,
    pub effort: f64,
    /// Index of its `<transmission>` in document order, if any.
    pub transmission: Option<usize>,
}

/// A joint named in [`Actuation::Joints`] that cannot take an input.
#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error)]
#[error("joint `{joint}` cannot be actuated: it is not a movable joint of the robot")]
pub struct NotActuatable {
    /// The name given.
    pub joint: String,
}

impl Model {
    /// Chooses the inputs by `rule`.
    pub fn actuate(&mut self, rule: &Actuation) -> Result<(), NotActuatable> {
        let (chosen, applied) = match rule {
            Actuation::Default => self.default_actuators(),
            Actuation::Transmissions => (self.by_transmission(), AppliedActuation::Transmissions),
            Actuation::AllJoints => (self.actuators.clone(), AppliedActuation::AllJoints),
            Actuation::Joints(names) => (
                names
                    .iter()
                    .map(|name| {
                        self.actuators
                            .iter()
                            .find(|a| &a.joint == name)
                            .cloned()
                            .ok_or_else(|| NotActuatable {
                                joint: name.clone(),
                            })
                    })
                    .collect::<Result<_, _>>()?,
                AppliedActuation::Joints,
            ),
        };
        self.set_inputs(chosen, applied);
        Ok(())
    }

    /// Applies [`Actuation::Default`] (what loading does).
    pub(crate) fn actuate_by_default(&mut self) {
        let (chosen, applied) = self.default_actuators();
        self.set_inputs(chosen, applied);
    }

    /// The rule that chose the inputs.
    pub fn actuation(&self) -> AppliedActuation {
        self.actuation
    }

    /// The joints that can take an input (movable, not base coordinates), in coordinate order.
    pub fn actuatable_joints(&self) -> Vec<String> {
        self.actuators.iter().map(|a| a.joint.clone()).collect()
    }

    fn default_actuators(&self) -> (Vec<Actuator>, AppliedActuation) {
        if self.actuators.iter().any(|a| a.transmission.is_some()) {
            (self.by_transmission(), AppliedActuation::Transmissions)
        } else {
            (self.actuators.clone(), AppliedActuation::AllJoints)
        }
    }

    fn by_transmission(&self) -> Vec<Actuator> {
        let mut driven: Vec<&Actuator> = self
            .actuators
            .iter()
            .filter(|a| a.transmission.is_some())
            .collect();
        driven.sort_by_key(|a| a.transmission);
        driven.into_iter().cloned().collect()
    }

    fn set_inputs(&mut self, chosen: Vec<Actuator>, applied: AppliedActuation) {
        self.actuation = applied;
        self.input_names = chosen.iter().map(|a| a.joint.clone()).collect();
        self.input_coordinates = chosen.iter().map(|a| a.coordinate).collect();
        self.effort_limits = chosen.iter().map(|a| a.effort).collect();
    }
}
