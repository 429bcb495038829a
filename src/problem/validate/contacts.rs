//! `[contacts]`: the URDF's contact points and explicit ones, friction, the slip-speed bound,
//! the contact-mode block.

use super::context::Context;
use super::values::{finite, nonnegative, plain_name, positive};
use crate::problem::schema::{ContactSelection, ContactsSection, ProblemFile};
use crate::problem::{ContactSpec, ProblemError, RobotInfo};

pub(super) fn check_contacts(
    ctx: &Context,
    section: &ContactsSection,
    robot: &RobotInfo,
) -> Result<Vec<ContactSpec>, ProblemError> {
    let default_friction = nonnegative(ctx, "contacts.friction", section.friction.unwrap_or(1.0))?;
    let selection = section
        .from_urdf
        .clone()
        .unwrap_or(if section.point.is_empty() {
            ContactSelection::All
        } else {
            ContactSelection::None
        });
    let mut contacts: Vec<ContactSpec> = Vec::new();
    let urdf_names: Vec<String> = robot.contacts.iter().map(|c| c.name.clone()).collect();
    let from_urdf = |c: &crate::problem::UrdfContact| ContactSpec {
        name: c.name.clone(),
        link: c.link.clone(),
        point: c.point,
        radius: c.radius,
        friction: default_friction,
    };
    match &selection {
        ContactSelection::All => contacts.extend(robot.contacts.iter().map(from_urdf)),
        ContactSelection::None => {}
        ContactSelection::Names(names) => {
            for (i, name) in names.iter().enumerate() {
                let c = robot
                    .contacts
                    .iter()
                    .find(|c| &c.name == name)
                    .ok_or_else(|| {
                        ctx.unknown_name(
                            &format!("contacts.from_urdf[{i}]"),
                            "URDF contact",
                            name,
                            &urdf_names,
                        )
                    })?;
                contacts.push(from_urdf(c));
            }
        }
    }
    for (i, p) in section.point.iter().enumerate() {
        let f = |k: &str| format!("contacts.point[{i}].{k}");
        if !robot.links.contains(&p.link) {
            return Err(ctx.unknown_name(&f("link"), "link", &p.link, &robot.links));
        }
        for (j, v) in p.point.iter().enumerate() {
            finite(ctx, &format!("{}[{j}]", f("point")), *v)?;
        }
        plain_name(ctx, &f("name"), &p.name)?;
        contacts.push(ContactSpec {
            name: p.name.clone(),
            link: p.link.clone(),
            point: p.point,
            radius: match p.radius {
                Some(r) => nonnegative(ctx, &f("radius"), r)?,
                None => 0.0,
            },
            friction: match p.friction {
                Some(mu) => nonnegative(ctx, &f("friction"), mu)?,
                None => default_friction,
            },
        });
    }
    for (i, c) in contacts.iter().enumerate() {
        if contacts[..i].iter().any(|d| d.name == c.name) {
            return Err(ctx.invalid(
                "contacts",
                format!(
                    "two contacts are named `{}`; contact names must be unique",
                    c.name
                ),
            ));
        }
    }
    let names: Vec<String> = contacts.iter().map(|c| c.name.clone()).collect();
    for (name, mu) in &section.friction_by_name {
        let field = format!("contacts.friction_by_name.{name}");
        let mu = nonnegative(ctx, &field, *mu)?;
        let c = contacts
            .iter_mut()
            .find(|c| &c.name == name)
            .ok_or_else(|| ctx.unknown_name(&field, "contact", name, &names))?;
        c.friction = mu;
    }
    Ok(contacts)
}

/// `contacts.max_slip_speed`: an upper bound on every sliding speed, if given.
pub(super) fn check_max_slip_speed(
    ctx: &Context,
    raw: &ProblemFile,
) -> Result<Option<f64>, ProblemError> {
    raw.contacts
        .max_slip_speed
        .map(|v| positive(ctx, "contacts.max_slip_speed", v))
        .transpose()
}

/// `contacts.mode_block`: intervals per contact-mode block, 1 (the reference NLP) to the number
/// of intervals `knots − 1`.
pub(super) fn check_mode_block(
    ctx: &Context,
    raw: &ProblemFile,
    knots: usize,
) -> Result<usize, ProblemError> {
    let Some(m) = raw.contacts.mode_block else {
        return Ok(1);
    };
    let intervals = knots - 1;
    if m < 1 || m as u64 > intervals as u64 {
        return Err(ctx.invalid(
            "contacts.mode_block",
            format!(
                "must be a whole number of intervals from 1 (one contact mode per interval) \
                 to the horizon's {intervals} intervals, got {m}"
            ),
        ));
    }
    Ok(m as usize)
}
