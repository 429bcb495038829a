//! The unit names of a problem (`robot.units`), for labels in outputs.

#![warn(missing_docs)]

/// Unit names for labels in outputs.
#[derive(Debug, Clone, PartialEq)]
pub struct Units {
    /// Length unit, e.g. `m`.
    pub length: String,
    /// Mass unit, e.g. `kg`.
    pub mass: String,
    /// Time unit, e.g. `s`.
    pub time: String,
}

impl Units {
    /// Force unit name: N in SI, else mass·length/time².
    pub fn force(&self) -> String {
        if self.is_si() {
            "N".into()
        } else {
            format!("{}·{}/{}²", self.mass, self.length, self.time)
        }
    }
    fn is_si(&self) -> bool {
        self.length == "m" && self.mass == "kg" && self.time == "s"
    }
}

/// Length unit names `robot.units` accepts.
pub const LENGTH_UNITS: &[&str] = &["km", "m", "dm", "cm", "mm", "um", "µm", "nm", "in", "ft"];
/// Mass unit names `robot.units` accepts.
pub const MASS_UNITS: &[&str] = &["t", "kg", "g", "mg", "ug", "µg", "lb"];
/// Time unit names `robot.units` accepts, with seconds per unit.
pub const TIME_UNITS: &[(&str, f64)] = &[
    ("h", 3600.0),
    ("min", 60.0),
    ("s", 1.0),
    ("ms", 1e-3),
    ("us", 1e-6),
    ("µs", 1e-6),
];

/// Seconds per time unit `name` (1 for a name not in [`TIME_UNITS`]).
pub fn seconds_per(name: &str) -> f64 {
    TIME_UNITS
        .iter()
        .find(|(n, _)| *n == name)
        .map_or(1.0, |(_, s)| *s)
}

/// Metres per length unit `name` (1 for a name not in [`LENGTH_UNITS`]).
pub fn metres_per(name: &str) -> f64 {
    match name {
        "km" => 1e3,
        "dm" => 0.1,
        "cm" => 1e-2,
        "mm" => 1e-3,
        "um" | "µm" => 1e-6,
        "nm" => 1e-9,
        "in" => 0.0254,
        "ft" => 0.3048,
        _ => 1.0,
    }
}

/// SI: m, kg, s.
pub(crate) fn si_units() -> Units {
    Units {
        length: "m".into(),
        mass: "kg".into(),
        time: "s".into(),
    }
}
