//! A solution as a trajectory CSV (the format is [`crate::files::trajectory_csv`]'s).

pub use crate::files::trajectory_csv::Trajectory;
use crate::files::trajectory_csv::write_trajectory;
pub use crate::files::trajectory_csv::{
    ColumnUnits, CsvTable, friction_direction_names, input_column_name, read_csv,
};
use crate::transcription::Solution;

/// Renders the trajectory CSV of a solution.
pub fn trajectory_csv(solution: &Solution, units: &ColumnUnits) -> String {
    write_trajectory(&solution_trajectory(solution), units)
}

/// A solution's knots and intervals as the trajectory file holds them.
pub fn solution_trajectory(s: &Solution) -> Trajectory<'_> {
    Trajectory {
        times: &s.times,
        coordinate_names: &s.coordinate_names,
        q: &s.q,
        v: &s.v,
        input_names: &s.input_names,
        u: &s.u,
        contact_names: &s.contact_names,
        friction_directions: s.friction_directions,
        normal_impulse: &s.normal_impulse,
        friction_impulse: &s.friction_impulse,
        world_impulse: &s.world_impulse,
        signed_distance: &s.signed_distance,
        contact_positions: &s.contact_positions,
        slack: &s.slack,
    }
}
