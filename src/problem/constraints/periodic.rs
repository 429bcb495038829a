//! Periodicity of one coordinate between the first and the last knot: its position (up to an
//! offset, e.g. a stride length) and its finite-difference velocity.

use serde::Deserialize;

use super::{
    CheckConstraint, ConstraintCheck, ConstraintFunction, ConstraintInput, ConstraintRow, KnotRef,
};
use crate::autodiff::Scalar;
use crate::discrete::Mechanics;
use crate::problem::ProblemError;

/// `[[periodic]]`, or `[[constraint]] type = "periodic"`: q_N[c] − q_1[c] = offset and/or
/// equal first and last finite-difference velocities.
#[derive(Debug, Clone, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Entry {
    /// Coordinate name.
    pub coordinate: String,
    /// Constrain q_N − q_1 = offset (default true).
    pub position: Option<bool>,
    /// The offset (default 0), e.g. a stride length.
    pub offset: Option<f64>,
    /// Constrain the last interval's velocity to equal the first's (default false).
    pub velocity: Option<bool>,
}

/// Rows, in order: q_N[c] − q_1[c] − offset = 0 when `offset` is set, then
/// (q_N[c] − q_{N−1}[c])/h_{N−1} − (q_2[c] − q_1[c])/h_1 = 0 when `velocity`.
#[derive(Debug, Clone, PartialEq)]
pub struct Periodic {
    /// The coordinate's index.
    pub coordinate: usize,
    /// Its name (for row labels).
    pub name: String,
    /// The position row's offset; `None` without a position row.
    pub offset: Option<f64>,
    /// Whether the velocity row is present.
    pub velocity: bool,
}

impl CheckConstraint for Periodic {
    type Entry = Entry;
    fn check(entry: &Entry, at: &ConstraintCheck) -> Result<Self, ProblemError> {
        let coordinate = at.coordinate("coordinate", &entry.coordinate)?;
        let offset = at.finite("offset", entry.offset.unwrap_or(0.0))?;
        Ok(Periodic {
            coordinate,
            name: entry.coordinate.clone(),
            offset: entry.position.unwrap_or(true).then_some(offset),
            velocity: entry.velocity.unwrap_or(false),
        })
    }
}

impl ConstraintFunction for Periodic {
    const NAME: &'static str = "periodic";

    /// z = [q_1[c]; q_N[c]], and with the velocity row also [q_2[c]; h_1; q_{N−1}[c]; h_{N−1}].
    fn inputs(&self) -> Vec<ConstraintInput> {
        let coordinate = |knot| ConstraintInput::Coordinate {
            knot,
            coordinate: self.coordinate,
        };
        let mut z = vec![coordinate(KnotRef::First(0)), coordinate(KnotRef::Last(0))];
        if self.velocity {
            z.extend([
                coordinate(KnotRef::First(1)),
                ConstraintInput::Step(KnotRef::First(0)),
                coordinate(KnotRef::Last(1)),
                ConstraintInput::Step(KnotRef::Last(0)),
            ]);
        }
        z
    }

    fn rows(&self) -> Vec<ConstraintRow> {
        let mut rows = Vec::new();
        if self.offset.is_some() {
            rows.push(ConstraintRow::equality(format!(
                "periodic {} position",
                self.name
            )));
        }
        if self.velocity {
            rows.push(ConstraintRow::equality(format!(
                "periodic {} velocity",
                self.name
            )));
        }
        rows
    }

    fn value<D: Scalar, M: Mechanics>(&self, _: &M, z: &[D], out: &mut [D]) {
        let mut row = 0;
        if let Some(offset) = self.offset {
            out[row] = z[1] - z[0] - D::from(offset);
            row += 1;
        }
        if self.velocity {
            out[row] = (z[1] - z[4]) / z[5] - (z[2] - z[0]) / z[3];
        }
    }
}
