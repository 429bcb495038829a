//! A trajectory CSV read back as a point of the NLP (`vito check --derivatives --at`).

use crate::transcription::{MechanicsDerivatives, Transcription};

/// The NLP point a trajectory CSV (as `vito solve` writes it, with one row per knot of this
/// problem) describes: q, h from the times, u, the normal and friction impulses and the
/// slacks from their columns where present; ψ, η and anything absent keep the NLP's initial
/// guess. The message names the column or the row count at fault.
pub fn point_from_trajectory<M: MechanicsDerivatives>(
    nlp: &Transcription<M>,
    robot: &crate::problem::RobotInfo,
    contacts: &[String],
    text: &str,
) -> Result<Vec<f64>, String> {
    use crate::files::trajectory_csv::{friction_direction_names, read_csv, read_trajectory};
    let l = nlp.layout();
    let recorded = read_trajectory(text, &robot.coordinates, &robot.inputs)?;
    if recorded.times.len() != l.knots {
        return Err(format!(
            "it has {} rows, the problem has {} knots (run the problem with `--set knots={}`, or solve it first)",
            recorded.times.len(),
            l.knots,
            recorded.times.len()
        ));
    }
    let table = read_csv(text)?;
    let mut x = nlp.initial_point().to_vec();
    for (k, q) in recorded.q.iter().enumerate() {
        for (i, v) in l.q(k).zip(q) {
            x[i] = *v;
        }
    }
    let (lower, upper) = nlp.variable_bounds();
    for j in 0..l.intervals() {
        let h = recorded.times[j + 1] - recorded.times[j];
        // The problem's step bounds, with the round-off of times written as decimals.
        let slack = 1e-9 * upper[l.h(j)].abs().max(1.0);
        if !(lower[l.h(j)] - slack..=upper[l.h(j)] + slack).contains(&h) {
            return Err(format!(
                "rows {} and {} are {h} apart in time, outside the problem's step [{}, {}]",
                j + 2,
                j + 3,
                lower[l.h(j)],
                upper[l.h(j)]
            ));
        }
        x[l.h(j)] = h;
        if let Some(u) = recorded.u.get(j) {
            for (i, v) in l.u(j).zip(u) {
                x[i] = *v;
            }
        }
    }
    let set = |x: &mut Vec<f64>, column: &str, index: &dyn Fn(usize) -> usize| {
        if let Some(values) = table.column(column) {
            for (j, v) in values.iter().take(l.intervals()).enumerate() {
                if v.is_finite() {
                    x[index(j)] = *v;
                }
            }
        }
    };
    let directions = friction_direction_names(l.nd);
    for (i, name) in contacts.iter().enumerate() {
        set(&mut x, &format!("{name}_normal"), &|j| l.c(j, i));
        for (d, dir) in directions.iter().enumerate() {
            set(&mut x, &format!("{name}_friction_{dir}"), &|j| {
                l.beta(j, i).start + d
            });
        }
    }
    // Penalty mode has no slack variables (its `slack` column is the products' largest sum).
    if l.slacks_per_interval() > 0 {
        set(&mut x, "slack", &|j| l.slack(j).start);
    }
    for s in 0..l.slacks_per_interval() {
        set(&mut x, &format!("slack_{s}"), &|j| l.slack(j).start + s);
    }
    // A Galerkin member's interior points (not in the file) where the trajectory's intervals
    // put them.
    nlp.set_interior_points(&mut x, true);
    Ok(x)
}
