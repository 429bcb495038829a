//! Terrain, signed distance and friction directions for point contacts.

/// A smoothed step in the ground: the height rises by `rise` across x = `edge_x`,
/// H(x) = rise · ½ (1 + tanh((x − edge_x)/width)). C∞, so Newton steps can cross it.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Step {
    pub edge_x: f64,
    pub rise: f64,
    pub width: f64,
}

/// The terrain: flat ground at `ground_height` plus smoothed steps (heights add up).
#[derive(Debug, Clone, PartialEq, Default)]
pub struct Terrain {
    pub ground_height: f64,
    pub steps: Vec<Step>,
}
