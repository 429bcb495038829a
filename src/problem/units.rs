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

/// SI: m, kg, s.
pub(crate) fn si_units() -> Units {
    Units {
        length: "m".into(),
        mass: "kg".into(),
        time: "s".into(),
    }
}
