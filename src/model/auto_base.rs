//! `--base auto`: the base a URDF asks for, with the reason `vito inspect` prints. A free
//! body (no moving joints) floats; a robot bolted down (its root link is `world`, it moves its root itself, or nothing but its root
//! can touch the ground) keeps a fixed base; a robot that stands on its end links gets a
//! floating one.

use serde::Serialize;

use super::{BaseType, Model, point_position};

/// How far below the root link an end link or contact must reach, in the nominal pose, to
/// count as something the robot can stand on, as a fraction of the robot's size (the
/// largest distance of an end link or contact from the root; at least 1 mm).
const BELOW_ROOT: f64 = 0.1;

/// The base `--base auto` chose and why.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct BaseChoice {
    /// The base chosen.
    #[serde(skip)]
    pub base: BaseType,
    /// Why, and how to choose the other, in one sentence.
    pub reason: String,
}

impl Model {
    /// The base `--base auto` gives this robot, read from the model loaded with a fixed
    /// base: floating for a robot without moving joints (a free body); fixed when its root link is named `world` (it is bolted to the world), when
    /// its own prismatic joints move its root (the planar hopper's x and z), or when no end
    /// link and no contact reaches below its root link in the nominal pose (an arm or a
    /// hand, whose root is where it is mounted); floating otherwise (a legged robot,
    /// standing on the end links below its trunk).
    pub fn auto_base(&self) -> BaseChoice {
        let fixed = |reason: String| BaseChoice {
            base: BaseType::Fixed,
            reason: format!("{reason}; `--base floating` frees it"),
        };
        let root = self.link_names().first().cloned().unwrap_or_default();
        if self.slides_its_root() {
            return fixed("its own prismatic joints move its root link".into());
        }
        if root.eq_ignore_ascii_case("world") {
            return fixed(format!("its root link `{root}` bolts it to the world"));
        }
        if self.nq() == self.base().coordinate_names().len() {
            return BaseChoice {
                base: BaseType::Floating,
                reason: "it has no moving joints: a free body (a brick, a drone); \
                         `--base planar` keeps it in the x-z plane"
                    .into(),
            };
        }
        let q = self.nominal_pose();
        // Each end link's origin and each contact's lowest point, with its height below
        // the root; the robot's size is the farthest of them from the root.
        let mut points: Vec<(String, f64)> = Vec::new();
        let mut size: f64 = 1e-3;
        let ends = self.leaf_links().iter().map(|l| (l, l, [0.0; 3], 0.0));
        let contacts =
            (self.contact_points().iter()).map(|c| (&c.name, &c.link, c.point, c.radius));
        // The root's own frame: links welded to it are part of it (a mount's collision
        // spheres), and cannot lift it.
        let root_frame = self.link_frame.first().map(|p| p.frame);
        for (name, link, point, radius) in ends.chain(contacts) {
            if let Some(link) = self.link_index(link)
                && Some(self.link_frame[link.index()].frame) != root_frame
            {
                let p = point_position(self, link, &point, &q);
                size = size.max(p.iter().map(|x| x * x).sum::<f64>().sqrt() + radius);
                points.push((name.clone(), p[2] - radius));
            }
        }
        let mut below: Vec<&(String, f64)> = points
            .iter()
            .filter(|(_, z)| *z < -BELOW_ROOT * size)
            .collect();
        if below.is_empty() {
            return fixed(format!(
                "no end link or contact reaches below its root link `{root}` in the nominal \
                 pose, so only its root can touch the ground (an arm or a hand, mounted by \
                 its root)"
            ));
        }
        below.sort_by(|a, b| a.1.total_cmp(&b.1));
        let mut names: Vec<&str> = Vec::with_capacity(below.len());
        for (name, _) in below {
            if !names.contains(&name.as_str()) {
                names.push(name);
            }
        }
        BaseChoice {
            base: BaseType::Floating,
            reason: format!(
                "{} {} below its root link `{root}` in the nominal pose: a robot that \
                 stands on {}; `--base fixed` bolts its root down",
                crate::files::names::list_names(&names, 4),
                if names.len() == 1 { "reaches" } else { "reach" },
                if names.len() == 1 { "it" } else { "them" },
            ),
        }
    }

    /// The nominal pose: every coordinate at 0, or mid-range where 0 is outside its
    /// limits (at the finite limit when the other is open).
    pub fn nominal_pose(&self) -> Vec<f64> {
        self.coordinate_limits()
            .iter()
            .map(|&(lo, hi)| {
                if (lo..=hi).contains(&0.0) {
                    0.0
                } else if lo.is_finite() && hi.is_finite() {
                    0.5 * (lo + hi)
                } else if lo.is_finite() {
                    lo
                } else {
                    hi
                }
            })
            .collect()
    }
}
