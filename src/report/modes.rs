//! Contact modes per interval (flight, stick, slide), as in the paper's figure 4.
//!
//! Thresholds (stated in `summary.json` too):
//! - flight: the normal impulse c ≤ `FLIGHT_RELATIVE` × the largest normal impulse of the
//!   whole trajectory (and ≤ 1e-9 absolute when no contact ever pushes);
//! - slide: the friction impulse fills the cone, eᵀβ ≥ `SLIDE_CONE_FRACTION` × μ c
//!   (Coulomb friction at its limit is what sliding needs; stick rarely saturates it);
//! - stick: in contact and not sliding.

use crate::files::trajectory_csv::Trajectory;

/// Flight when c ≤ this fraction of the trajectory's largest normal impulse.
pub const FLIGHT_RELATIVE: f64 = 1e-3;
/// Slide when eᵀβ ≥ this fraction of μ c.
pub const SLIDE_CONE_FRACTION: f64 = 0.99;

/// One contact's mode over one interval.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum ContactMode {
    /// No normal impulse.
    Flight,
    /// In contact, friction inside the cone.
    Stick,
    /// In contact, friction on the cone's edge.
    Slide,
}

impl ContactMode {
    /// Lower-case name.
    pub fn name(self) -> &'static str {
        match self {
            ContactMode::Flight => "flight",
            ContactMode::Stick => "stick",
            ContactMode::Slide => "slide",
        }
    }
}

/// Modes per interval and contact (N−1 × nc); `friction` holds μ per contact.
pub fn contact_modes(solution: &Trajectory<'_>, friction: &[f64]) -> Vec<Vec<ContactMode>> {
    let largest = solution
        .normal_impulse
        .iter()
        .flatten()
        .fold(0.0_f64, |a, &b| a.max(b));
    let flight_below = (FLIGHT_RELATIVE * largest).max(1e-9);
    solution
        .normal_impulse
        .iter()
        .enumerate()
        .map(|(k, normals)| {
            normals
                .iter()
                .enumerate()
                .map(|(i, &c)| {
                    if c <= flight_below {
                        return ContactMode::Flight;
                    }
                    let beta: f64 = solution
                        .friction_impulse
                        .get(k)
                        .and_then(|b| b.get(i))
                        .map_or(0.0, |b| b.iter().sum());
                    let mu = friction.get(i).copied().unwrap_or(1.0);
                    if beta >= SLIDE_CONE_FRACTION * mu * c {
                        ContactMode::Slide
                    } else {
                        ContactMode::Stick
                    }
                })
                .collect()
        })
        .collect()
}
