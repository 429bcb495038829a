//! What a user checks first about a model (`vito inspect`).

use std::fmt;

use serde::Serialize;

use super::Model;

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
    /// Coordinate names in order.
    pub coordinates: Vec<String>,
    /// Coordinates with limits and damping.
    pub coordinate_details: Vec<CoordinateInfo>,
    /// Input names in order.
    pub inputs: Vec<String>,
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
    let _ = model;
    unimplemented!("inspect")
}

impl fmt::Display for Inspection {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "{}", self.robot)
    }
}
