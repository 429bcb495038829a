//! A problem's world as a MuJoCo model (MJCF text, for the Python `vito.mujoco`): the robot
//! as vito reads it (its tree of rigid bodies with the lumped masses and inertias, joints
//! named by their coordinates, a `<mimic>` joint tied to its leader by an equality, springs and
//! dampers), the problem's contacts as spheres, its terrain (the ground plane, tilted when the
//! problem has a slope, and its steps as boxes), gravity, and one motor per input.
//!
//! The model's joints, in the order MuJoCo lists them, are vito's coordinates under other
//! names only for the base: a floating base is one body carrying slides x, y, z and hinges
//! about z, y, x (MuJoCo applies a body's joints in order, each about its axis in the frame
//! the ones before it left: Trans(x, y, z)·Rz(yaw)·Ry(pitch)·Rx(roll), vito's pose). Every
//! joint is named after its coordinate, so `qpos` maps to q by name.
//!
//! What is not vito's model: a point contact is a sphere of radius [`POINT_RADIUS`] metres (MuJoCo
//! collides geometries), so it stands that much higher; a step is a sharp box where vito's
//! is a tanh of width `width`; MuJoCo's contacts are soft (`solref` time constant twice the
//! time step) and its friction cone is the pyramid of four edges (vito's ±x, ±y directions).

use std::fmt::Write as _;

use crate::model::Model;
use crate::model::tree::Motion;
use crate::problem::LoadedProblem;
use crate::problem::units::{metres_per, seconds_per};
use crate::transcription::TranscriptionError;

/// The radius of a point contact's sphere, in metres.
pub const POINT_RADIUS: f64 = 1e-3;

/// Why a problem has no MuJoCo model.
#[derive(Debug, thiserror::Error)]
pub enum MujocoError {
    /// The robot could not be loaded.
    #[error("{0}")]
    Robot(#[from] TranscriptionError),
    /// A robot with loop closures (MuJoCo's equalities would over-constrain vito's planar
    /// closures).
    #[error(
        "the robot has loop closures ({0}); vito.mujoco models trees (and <mimic> joints) only"
    )]
    Loops(String),
    /// A time step that is not a positive number.
    #[error("the time step must be a positive number of seconds, got {0}")]
    TimeStep(f64),
    /// A terrain that is not drawn as planes and boxes.
    #[error(
        "the terrain has {0}; vito.mujoco builds flat ground, a slope, and steps and stairs along +x (heading 0) only"
    )]
    Terrain(&'static str),
}

/// A problem's MuJoCo model.
#[derive(Debug, Clone)]
pub struct MujocoModel {
    /// The MJCF text.
    pub xml: String,
    /// The coordinates that translate the robot along world axes (a floating base's x, y, z;
    /// a planar hopper's slider joints): where its base is.
    pub translation_coordinates: Vec<String>,
    /// The time step written, in the problem's time unit.
    pub timestep: f64,
}

/// Escapes text for an XML attribute value.
fn attr(text: &str) -> String {
    crate::files::names::xml_escape(text)
}

fn vec3(v: [f64; 3]) -> String {
    format!("{:?} {:?} {:?}", v[0], v[1], v[2])
}

const IDENTITY: [[f64; 3]; 3] = [[1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]];

/// The MJCF of `problem`'s world, stepped every `timestep_s` seconds.
pub fn mujoco_model(problem: &LoadedProblem, timestep_s: f64) -> Result<MujocoModel, MujocoError> {
    if !(timestep_s.is_finite() && timestep_s > 0.0) {
        return Err(MujocoError::TimeStep(timestep_s));
    }
    let spec = &problem.spec;
    let mech = crate::pipeline::mechanics(spec)?;
    let model = mech.model();
    if !model.loop_closures().is_empty() {
        let names: Vec<&str> = model
            .loop_closures()
            .iter()
            .map(|l| l.name.as_str())
            .collect();
        return Err(MujocoError::Loops(names.join(", ")));
    }
    let timestep = timestep_s / seconds_per(&problem.units.time);
    let metre = 1.0 / metres_per(&problem.units.length);
    let point_radius = POINT_RADIUS * metre;
    let mut xml = String::new();
    let g = spec.robot.gravity;
    let mass = model.total_mass().max(f64::MIN_POSITIVE);
    let _ = writeln!(xml, "<mujoco model=\"{}\">", attr(&spec.name));
    // The least mass and inertia MuJoCo takes for a moving body (a URDF's massless link with a
    // joint): a billionth of the robot's mass, and a trillionth of its mass times 1 m².
    let _ = writeln!(
        xml,
        "  <compiler angle=\"radian\" inertiafromgeom=\"false\" boundmass=\"{:?}\" \
         boundinertia=\"{:?}\"/>",
        mass * 1e-9,
        mass * 1e-12 * metre * metre,
    );
    let _ = writeln!(
        xml,
        "  <option timestep=\"{timestep:?}\" gravity=\"{}\" cone=\"pyramidal\" \
         integrator=\"implicitfast\"/>",
        vec3(g)
    );
    let _ = writeln!(
        xml,
        "  <default><geom condim=\"3\" solref=\"{:?} 1\"/></default>",
        2.0 * timestep
    );
    xml.push_str("  <worldbody>\n");
    terrain(&mut xml, problem, point_radius)?;
    let equalities = bodies(&mut xml, model, problem, point_radius);
    xml.push_str("  </worldbody>\n");
    if !equalities.is_empty() {
        xml.push_str("  <equality>\n");
        xml.push_str(&equalities);
        xml.push_str("  </equality>\n");
    }
    if !model.input_names().is_empty() {
        xml.push_str("  <actuator>\n");
        for (name, &c) in model.input_names().iter().zip(model.input_coordinates()) {
            let _ = writeln!(
                xml,
                "    <motor name=\"{}\" joint=\"{}\" gear=\"1\"/>",
                attr(name),
                attr(&model.coordinate_names()[c])
            );
        }
        xml.push_str("  </actuator>\n");
    }
    xml.push_str("</mujoco>\n");
    let translation_coordinates = model
        .translation_coordinates()
        .iter()
        .zip(model.coordinate_names())
        .filter(|(t, _)| **t)
        .map(|(_, n)| n.clone())
        .collect();
    Ok(MujocoModel {
        xml,
        translation_coordinates,
        timestep,
    })
}

/// The ground plane (tilted on a slope) and, for steps, one box per stretch of constant
/// height between their edges.
fn terrain(
    xml: &mut String,
    problem: &LoadedProblem,
    point_radius: f64,
) -> Result<(), MujocoError> {
    let t = &problem.spec.terrain;
    let plane = |xml: &mut String, z: f64, normal: [f64; 3]| {
        let _ = writeln!(
            xml,
            "    <geom name=\"ground\" type=\"plane\" size=\"0 0 1\" pos=\"0 0 {z:?}\" \
             zaxis=\"{}\" friction=\"0 0 0\" contype=\"0\" conaffinity=\"1\"/>",
            vec3(normal)
        );
    };
    if let Some(slope) = &t.slope {
        plane(xml, t.ground_height, slope.frame[2]);
        return Ok(());
    }
    if !t.blocks.is_empty() {
        return Err(MujocoError::Terrain("blocks"));
    }
    if t.height_map.is_some() {
        return Err(MujocoError::Terrain("a height map"));
    }
    let along_x = |heading: f64| heading.rem_euclid(360.0) == 0.0;
    if !t.steps.iter().all(|s| along_x(s.heading)) || !t.stairs.iter().all(|s| along_x(s.heading)) {
        return Err(MujocoError::Terrain(
            "steps or stairs along another heading",
        ));
    }
    let mut steps: Vec<(f64, f64)> = t.steps.iter().map(|s| (s.edge, s.rise)).collect();
    for flight in &t.stairs {
        steps.extend(
            (0..flight.count).map(|k| (flight.start + f64::from(k) * flight.run, flight.rise)),
        );
    }
    steps.sort_by(|a, b| a.0.total_cmp(&b.0));
    // (x from, x to, height above the ground) per stretch; the outer ones reach 100 m.
    let far = 100.0 * point_radius / POINT_RADIUS;
    let mut stretches = vec![(-far, steps.first().map_or(far, |s| s.0), 0.0)];
    let mut height = 0.0;
    for (i, &(edge, rise)) in steps.iter().enumerate() {
        height += rise;
        let end = steps.get(i + 1).map_or(far, |s| s.0);
        stretches.push((edge, end, height));
    }
    let lowest = stretches.iter().map(|s| s.2).fold(0.0, f64::min);
    plane(xml, t.ground_height + lowest, [0.0, 0.0, 1.0]);
    for (i, &(from, to, h)) in stretches.iter().enumerate() {
        if h <= lowest || to <= from {
            continue;
        }
        let half = [(to - from) / 2.0, far, (h - lowest) / 2.0];
        let centre = [(from + to) / 2.0, 0.0, t.ground_height + (h + lowest) / 2.0];
        let _ = writeln!(
            xml,
            "    <geom name=\"step{i}\" type=\"box\" size=\"{}\" pos=\"{}\" friction=\"0 0 0\" \
             contype=\"0\" conaffinity=\"1\"/>",
            vec3(half),
            vec3(centre)
        );
    }
    Ok(())
}

/// The robot's bodies, depth first (written without recursion: a URDF may be deep); returns
/// the `<mimic>` joints' equalities.
fn bodies(xml: &mut String, model: &Model, problem: &LoadedProblem, point_radius: f64) -> String {
    let frames = &model.frames;
    let mut children: Vec<Vec<usize>> = vec![Vec::new(); frames.len()];
    let mut roots = Vec::new();
    for (i, f) in frames.iter().enumerate() {
        match f.parent {
            Some(p) => children[p].push(i),
            None => roots.push(i),
        }
    }
    // Per frame: its first link (the body's name) and its contacts.
    let mut link_of: Vec<Option<&str>> = vec![None; frames.len()];
    for (name, placement) in model.link_names().iter().zip(&model.link_frame) {
        link_of[placement.frame].get_or_insert(name.as_str());
    }
    let mut contacts: Vec<Vec<String>> = vec![Vec::new(); frames.len()];
    for c in &problem.spec.contacts {
        let Some(link) = model.link_index(&c.link) else {
            continue;
        };
        let placement = &model.link_frame[link.index()];
        let radius = if c.radius > 0.0 {
            c.radius
        } else {
            point_radius
        };
        contacts[placement.frame].push(format!(
            "<geom name=\"{}\" type=\"sphere\" size=\"{radius:?}\" pos=\"{}\" \
             friction=\"{:?} 0.005 0.0001\" contype=\"1\" conaffinity=\"0\"/>",
            attr(&c.name),
            vec3(placement.point_in_frame(&c.point)),
            c.friction
        ));
    }
    let names = model.coordinate_names();
    let joint_name = |i: usize| match frames[i].mimic {
        None => names[frames[i].coordinate].clone(),
        Some(_) => format!("{}_mimic{i}", names[frames[i].coordinate]),
    };
    let mut equalities = String::new();
    // Frames still to open (`Some`) or bodies to close (`None`), with their depth.
    let mut stack: Vec<(Option<usize>, usize)> =
        roots.iter().rev().map(|&r| (Some(r), 2)).collect();
    while let Some((item, depth)) = stack.pop() {
        let pad = "  ".repeat(depth);
        let Some(first) = item else {
            let _ = writeln!(xml, "{pad}</body>");
            continue;
        };
        let f = &frames[first];
        let _ = write!(xml, "{pad}<body name=\"");
        // A massless frame whose one child sits at its origin shares the child's body.
        let mut chain = vec![first];
        let mut last = first;
        loop {
            let here = &frames[last];
            let next = match children[last].as_slice() {
                &[c] => c,
                _ => break,
            };
            let child = &frames[next];
            if here.mass != 0.0
                || !contacts[last].is_empty()
                || link_of[last].is_some()
                || child.translation != [0.0; 3]
                || child.rotation != IDENTITY
            {
                break;
            }
            chain.push(next);
            last = next;
        }
        // MuJoCo's own world body is `world`: a URDF's root link of that name is renamed.
        let name = match link_of[last] {
            Some("world") => "urdf_world".to_owned(),
            Some(link) => link.to_owned(),
            None => format!("frame{last}"),
        };
        let r = f.rotation;
        let _ = writeln!(
            xml,
            "{}\" pos=\"{}\" xyaxes=\"{:?} {:?} {:?} {:?} {:?} {:?}\">",
            attr(&name),
            vec3(f.translation),
            r[0][0],
            r[1][0],
            r[2][0],
            r[0][1],
            r[1][1],
            r[2][1]
        );
        for &i in &chain {
            let frame = &frames[i];
            let kind = match frame.motion {
                Motion::Fixed => continue,
                Motion::Revolute => "hinge",
                Motion::Prismatic => "slide",
            };
            let joint = joint_name(i);
            let mut extra = String::new();
            if frame.mimic.is_none() {
                let c = frame.coordinate;
                if model.damping()[c] != 0.0 {
                    let _ = write!(extra, " damping=\"{:?}\"", model.damping()[c]);
                }
                for s in model.springs().iter().filter(|s| s.coordinate == c) {
                    let _ = write!(
                        extra,
                        " stiffness=\"{:?}\" springref=\"{:?}\"",
                        s.stiffness, s.rest
                    );
                }
            }
            let _ = writeln!(
                xml,
                "{pad}  <joint name=\"{}\" type=\"{kind}\" axis=\"{}\"{extra}/>",
                attr(&joint),
                vec3(frame.axis)
            );
            if let Some(m) = frame.mimic {
                let _ = writeln!(
                    equalities,
                    "    <joint joint1=\"{}\" joint2=\"{}\" polycoef=\"{:?} {:?} 0 0 0\"/>",
                    attr(&joint),
                    attr(&names[frame.coordinate]),
                    m.offset,
                    m.multiplier
                );
            }
        }
        let body = &frames[last];
        if body.mass > 0.0 {
            let i = body.inertia;
            let _ = writeln!(
                xml,
                "{pad}  <inertial pos=\"{}\" mass=\"{:?}\" fullinertia=\"{:?} {:?} {:?} {:?} {:?} {:?}\"/>",
                vec3(body.com),
                body.mass,
                i[0][0],
                i[1][1],
                i[2][2],
                i[0][1],
                i[0][2],
                i[1][2]
            );
        }
        for geom in &contacts[last] {
            let _ = writeln!(xml, "{pad}  {geom}");
        }
        stack.push((None, depth));
        for &c in children[last].iter().rev() {
            stack.push((Some(c), depth + 1));
        }
    }
    equalities
}
