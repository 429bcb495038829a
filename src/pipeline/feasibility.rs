//! What `vito check` shows about whether a problem can be solved, before solving it.

use crate::problem::ProblemSpec;
use crate::transcription::{MechanicsDerivatives, Transcription};

/// One contact's distance to the terrain at the first and last knot of the initial guess
/// (length units; negative below the terrain).
#[derive(Debug, Clone, PartialEq)]
pub struct ContactClearance {
    /// The contact's name.
    pub name: String,
    /// φ at the first knot (the initial pose).
    pub first: f64,
    /// φ at the last knot of the initial guess.
    pub last: f64,
}

/// What `vito check` shows about whether a problem can be solved, before solving it.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct Feasibility {
    /// Per contact, its distance to the terrain at the first and last knot.
    pub clearances: Vec<ContactClearance>,
    /// Plain-language warnings (a contact below the terrain, a floating robot with no
    /// contacts or no inputs, a pitch near ±π/2).
    pub warnings: Vec<String>,
}

/// How far below the terrain (length units) a contact may start before `check` warns: more
/// than round-off of a pose placed on it.
const BELOW_TERRAIN: f64 = 1e-9;

/// How close to ±π/2 a floating base's pitch may come before `check` warns (rad): the
/// roll–pitch–yaw angles are singular there.
const PITCH_MARGIN: f64 = 0.2;

/// The feasibility report of a built NLP: clearances from its initial guess, warnings from
/// its bounds and the problem.
pub fn feasibility<M: MechanicsDerivatives>(
    spec: &ProblemSpec,
    nlp: &Transcription<M>,
) -> Feasibility {
    let layout = nlp.layout();
    let x = nlp.initial_point();
    let mech = nlp.mechanics();
    let terrain = &nlp.context().contact.terrain;
    let last = layout.knots - 1;
    let distance = |i: usize, k: usize| {
        crate::contact::signed_distance(terrain, &mech.contact_position(i, &x[layout.q(k)]))
    };
    let mut report = Feasibility::default();
    for (i, contact) in spec.contacts.iter().enumerate() {
        let clearance = ContactClearance {
            name: contact.name.clone(),
            first: distance(i, 0),
            last: distance(i, last),
        };
        // Below round-off of a pose placed exactly on the terrain.
        if clearance.first < -BELOW_TERRAIN {
            report.warnings.push(format!(
                "contact `{}` starts {:.3e} below the terrain (at the first knot): the \
                 problem is infeasible unless the slack absorbs it; raise the base in \
                 [initial] q",
                contact.name, -clearance.first
            ));
        }
        report.clearances.push(clearance);
    }
    let base = spec.robot.base;
    if base != crate::model::BaseType::Fixed {
        if spec.contacts.is_empty() {
            report.warnings.push(
                "the robot has a free base but no contacts: nothing holds it up, it falls; \
                 add [contacts] (from_urdf or [[contacts.point]])"
                    .into(),
            );
        }
        if layout.m == 0 {
            report.warnings.push(
                "the robot has a free base but no inputs: it can only fall or tumble; \
                 see [inputs] actuated"
                    .into(),
            );
        }
    }
    if base == crate::model::BaseType::Floating
        && let Some(pitch) = mech
            .coordinate_names()
            .iter()
            .position(|n| n == "base_pitch")
    {
        let near = |v: f64| v.is_finite() && v.abs() >= std::f64::consts::FRAC_PI_2 - PITCH_MARGIN;
        let (lower, upper) = nlp.variable_bounds();
        let bounded = (0..layout.knots)
            .map(|k| layout.q(k).start + pitch)
            // A fixed coordinate (lower = upper) is a pose, reported below.
            .find(|&j| lower[j] < upper[j] && (near(lower[j]) || near(upper[j])));
        if let Some(j) = bounded {
            report.warnings.push(format!(
                "a bound on base_pitch ([{}, {}]) comes within {PITCH_MARGIN} rad of ±π/2, \
                 where roll–pitch–yaw angles are singular; bound |base_pitch| further from π/2",
                lower[j], upper[j]
            ));
        }
        if let Some(k) = (0..layout.knots).find(|&k| near(x[layout.q(k).start + pitch])) {
            report.warnings.push(format!(
                "the initial guess's base_pitch {} at knot {} is within {PITCH_MARGIN} rad of \
                 ±π/2, where roll–pitch–yaw angles are singular",
                x[layout.q(k).start + pitch],
                k + 1
            ));
        }
    }
    report
}
