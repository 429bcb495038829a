//! What a user checks first about a model (`vito inspect`).

use std::fmt;

use serde::Serialize;

use super::{CoordinateKind, Model, loop_residual};

/// The SI unit of a coordinate of this kind and of the effort on it.
fn si_units(kind: CoordinateKind) -> (&'static str, &'static str) {
    match kind {
        CoordinateKind::Linear => ("m", "N"),
        CoordinateKind::Angular => ("rad", "N·m"),
    }
}

/// One coordinate with its limits and damping (`None` = unbounded).
#[derive(Debug, Clone, Serialize)]
pub struct CoordinateInfo {
    /// Coordinate name.
    pub name: String,
    /// Lower limit, `None` if unbounded.
    pub lower: Option<f64>,
    /// Upper limit, `None` if unbounded.
    pub upper: Option<f64>,
    /// Viscous damping (0 if none).
    pub damping: f64,
    /// The unit of the coordinate and its limits in the URDF's SI: `m` or `rad`.
    pub unit: &'static str,
}

/// One spring.
#[derive(Debug, Clone, Serialize)]
pub struct SpringInfo {
    /// `<force_element>` name.
    pub name: String,
    /// `torsional` or `prismatic`.
    pub kind: super::SpringKind,
    /// Coordinate name.
    pub coordinate: String,
    /// Stiffness.
    pub stiffness: f64,
    /// Rest angle or length.
    pub rest: f64,
}

/// One contact of the URDF: a collision sphere.
#[derive(Debug, Clone, Serialize)]
pub struct ContactInfo {
    /// Contact name.
    pub name: String,
    /// The link it is fixed to.
    pub link: String,
    /// The sphere's centre in the link frame [length].
    pub point: [f64; 3],
    /// The sphere's radius [length] (0: a point).
    pub radius: f64,
}

/// One loop closure and its residual at q = 0.
#[derive(Debug, Clone, Serialize)]
pub struct LoopInfo {
    /// `<loop_joint>` name.
    pub name: String,
    /// First link.
    pub link1: String,
    /// Second link.
    pub link2: String,
    /// Largest |residual row| at q = 0.
    pub residual_at_zero: f64,
}

/// The summary printed by `vito inspect` (Display) or serialised with `--json`.
#[derive(Debug, Clone, Serialize)]
pub struct Inspection {
    /// Robot name.
    pub robot: String,
    /// Base type (`fixed`, `planar`, `floating`).
    pub base: String,
    /// Why `--base auto` chose it, and how to choose the other (`None` for a base asked
    /// for).
    pub base_reason: Option<String>,
    /// Coordinate names in order.
    pub coordinates: Vec<String>,
    /// Coordinates with limits and damping.
    pub coordinate_details: Vec<CoordinateInfo>,
    /// Input names in order.
    pub inputs: Vec<String>,
    /// The rule that chose them (e.g. "the URDF's transmissions").
    pub actuation: String,
    /// The unit of each input's effort limit in SI: `N` or `N·m`.
    pub effort_units: Vec<&'static str>,
    /// Effort limit per input (`None` = unbounded).
    pub effort_limits: Vec<Option<f64>>,
    /// Total mass.
    pub total_mass: f64,
    /// Number of springs.
    pub n_springs: usize,
    /// The springs.
    pub springs: Vec<SpringInfo>,
    /// Names of coordinates with non-zero damping.
    pub dampers: Vec<String>,
    /// Contact point names.
    pub contact_points: Vec<String>,
    /// The contacts (collision spheres) with their centres and radii.
    pub contacts: Vec<ContactInfo>,
    /// Collision elements that give no contact (not spheres), by link.
    pub ignored_collisions: Vec<super::IgnoredCollision>,
    /// Number of loop-closure rows.
    pub n_loop_constraints: usize,
    /// The loop closures.
    pub loop_closures: Vec<LoopInfo>,
    /// Largest |loop residual| at q = 0 (0 without loops).
    pub max_loop_residual: f64,
    /// Loader warnings.
    pub warnings: Vec<String>,
}

/// Collects the [`Inspection`] of a model.
pub fn inspect(model: &Model) -> Inspection {
    let finite = |x: f64| x.is_finite().then_some(x);
    let names = model.coordinate_names();
    let kinds = model.coordinate_kinds();
    let coordinate_details = names
        .iter()
        .zip(model.coordinate_limits())
        .zip(model.damping())
        .zip(&kinds)
        .map(
            |(((name, &(lower, upper)), &damping), &kind)| CoordinateInfo {
                name: name.clone(),
                lower: finite(lower),
                upper: finite(upper),
                damping,
                unit: si_units(kind).0,
            },
        )
        .collect();
    let springs = model
        .springs()
        .iter()
        .map(|s| SpringInfo {
            name: s.name.clone(),
            kind: s.kind,
            coordinate: names[s.coordinate].clone(),
            stiffness: s.stiffness,
            rest: s.rest,
        })
        .collect();
    let residual: Vec<f64> = loop_residual(model, &vec![0.0; model.nq()]);
    let loop_closures: Vec<LoopInfo> = model
        .loop_closures()
        .iter()
        .zip(residual.chunks(2))
        .map(|(l, rows)| LoopInfo {
            name: l.name.clone(),
            link1: model.link_names()[l.link1.index()].clone(),
            link2: model.link_names()[l.link2.index()].clone(),
            residual_at_zero: rows.iter().fold(0.0, |m: f64, r: &f64| m.max(r.abs())),
        })
        .collect();
    let base = model.base().name();
    Inspection {
        robot: model.name().to_string(),
        base: base.to_string(),
        base_reason: None,
        coordinates: names.to_vec(),
        coordinate_details,
        inputs: model.input_names().to_vec(),
        actuation: model.actuation().to_string(),
        effort_limits: model.effort_limits().iter().map(|&e| finite(e)).collect(),
        effort_units: model
            .input_coordinates()
            .iter()
            .map(|&c| si_units(kinds[c]).1)
            .collect(),
        total_mass: model.total_mass(),
        n_springs: model.springs().len(),
        springs,
        dampers: names
            .iter()
            .zip(model.damping())
            .filter(|(_, d)| **d != 0.0)
            .map(|(n, _)| n.clone())
            .collect(),
        contact_points: model
            .contact_points()
            .iter()
            .map(|c| c.name.clone())
            .collect(),
        contacts: model
            .contact_points()
            .iter()
            .map(|c| ContactInfo {
                name: c.name.clone(),
                link: c.link.clone(),
                point: c.point,
                radius: c.radius,
            })
            .collect(),
        ignored_collisions: model.ignored_collisions().to_vec(),
        n_loop_constraints: model.num_loop_constraints(),
        max_loop_residual: residual.iter().fold(0.0, |m: f64, r: &f64| m.max(r.abs())),
        loop_closures,
        warnings: model.warnings().to_vec(),
    }
}

/// `x` to `places` decimals without trailing zeros, so a printed sum or time loses its
/// round-off digits (2.7464, not 2.7464000000000004; 0.2, not 0.2000).
pub fn trimmed_decimal(x: f64, places: usize) -> String {
    let text = format!("{x:.places$}");
    text.trim_end_matches('0').trim_end_matches('.').to_string()
}

fn bound(x: Option<f64>, unbounded: &str) -> String {
    x.map_or_else(|| unbounded.to_string(), |v| format!("{v}"))
}

impl fmt::Display for Inspection {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        writeln!(f, "robot {} ({} base)", self.robot, self.base)?;
        if let Some(reason) = &self.base_reason {
            writeln!(f, "base {} (--base auto): {reason}", self.base)?;
        }
        writeln!(f, "total mass: {} kg", trimmed_decimal(self.total_mass, 9))?;
        writeln!(f, "coordinates ({}):", self.coordinates.len())?;
        for (i, c) in self.coordinate_details.iter().enumerate() {
            write!(
                f,
                "  {i:>3} {:<24} [{}, {}] {}",
                c.name,
                bound(c.lower, "-inf"),
                bound(c.upper, "inf"),
                c.unit
            )?;
            if c.damping != 0.0 {
                let unit = if c.unit == "m" {
                    "N·s/m"
                } else {
                    "N·m·s/rad"
                };
                write!(f, "  damping {} {unit}", c.damping)?;
            }
            writeln!(f)?;
        }
        writeln!(
            f,
            "inputs ({}), from {}:",
            self.inputs.len(),
            self.actuation
        )?;
        for ((name, effort), unit) in self
            .inputs
            .iter()
            .zip(&self.effort_limits)
            .zip(&self.effort_units)
        {
            writeln!(f, "  {name:<28} |u| <= {} {unit}", bound(*effort, "inf"))?;
        }
        writeln!(f, "springs ({}):", self.n_springs)?;
        for s in &self.springs {
            writeln!(
                f,
                "  {:<20} {:?} on {} k = {} rest = {}",
                s.name, s.kind, s.coordinate, s.stiffness, s.rest
            )?;
        }
        writeln!(
            f,
            "dampers ({}): {}",
            self.dampers.len(),
            self.dampers.join(", ")
        )?;
        writeln!(f, "contacts ({}):", self.contacts.len())?;
        for c in &self.contacts {
            writeln!(
                f,
                "  {:<20} on {:<20} at [{}, {}, {}]  radius {}",
                c.name, c.link, c.point[0], c.point[1], c.point[2], c.radius
            )?;
        }
        if !self.ignored_collisions.is_empty() {
            let listed: Vec<String> = self
                .ignored_collisions
                .iter()
                .map(|c| format!("{} ({})", c.link, c.shape))
                .collect();
            writeln!(
                f,
                "ignored collisions ({}, not spheres): {}",
                listed.len(),
                listed.join(", ")
            )?;
        }
        writeln!(
            f,
            "loop closures ({}, {} constraints):",
            self.loop_closures.len(),
            self.n_loop_constraints
        )?;
        for l in &self.loop_closures {
            writeln!(
                f,
                "  {:<20} {} - {}  |residual(q=0)| = {:e}",
                l.name, l.link1, l.link2, l.residual_at_zero
            )?;
        }
        writeln!(
            f,
            "max loop residual at q = 0: {:e}",
            self.max_loop_residual
        )?;
        for w in &self.warnings {
            writeln!(f, "warning: {w}")?;
        }
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::trimmed_decimal;

    #[test]
    fn trimmed_decimals_drop_round_off_and_trailing_zeros_only() {
        assert_eq!(trimmed_decimal(2.7464000000000004, 9), "2.7464");
        assert_eq!(trimmed_decimal(1.3124135483652837, 4), "1.3124");
        assert_eq!(trimmed_decimal(0.2, 4), "0.2");
        assert_eq!(trimmed_decimal(10.0, 4), "10");
        assert_eq!(trimmed_decimal(100.25, 4), "100.25");
    }
}
