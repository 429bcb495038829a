//! Where the solve starts and what it may not leave: variable and constraint bounds, the
//! initial guess (linear or warm-started from a previous trajectory).

use super::TranscriptionError;
use super::blocks::Context;
use super::error::check_len;
use super::layout::Layout;
use crate::discrete::{MechanicsDerivatives, galerkin_interval};
use crate::problem::{InitialGuess, Interval, KnotSet, ProblemSpec, TimeSteps, WarmStart};

pub(super) fn intersect(a: Interval, b: Interval) -> Interval {
    Interval {
        lower: a.lower.max(b.lower),
        upper: a.upper.min(b.upper),
    }
}

/// The bounds of an NLP's variables and rows.
pub(crate) struct Bounds {
    pub x_lower: Vec<f64>,
    pub x_upper: Vec<f64>,
    pub g_lower: Vec<f64>,
    pub g_upper: Vec<f64>,
}

/// The variable bounds (joint limits, the file's bounds, fixed start, steps, inputs, contact
/// variables, flight windows, slacks) and the row bounds of `spec`'s NLP laid out as `l`.
pub(super) fn bounds<M: MechanicsDerivatives>(
    mech: &M,
    l: &Layout,
    spec: &ProblemSpec,
) -> Result<Bounds, TranscriptionError> {
    let nv = l.num_variables();
    let mut lo = vec![f64::NEG_INFINITY; nv];
    let mut hi = vec![f64::INFINITY; nv];
    let limits = mech.coordinate_limits();
    let last = l.knots - 1;
    // Coordinate c's joint limits and the file's bounds on it whose knots `applies` takes.
    let coordinate_bound = |c: usize, applies: &dyn Fn(&KnotSet) -> bool| {
        let mut b = Interval::FREE;
        if spec.joint_limits {
            let (lower, upper) = limits[c];
            b = intersect(b, Interval { lower, upper });
        }
        for cb in spec.bounds.iter().filter(|cb| cb.coordinate == c) {
            if applies(&cb.knots) {
                b = intersect(b, cb.bound);
            }
        }
        b
    };
    for k in 0..l.knots {
        for c in 0..l.n {
            let mut b = coordinate_bound(c, &|knots| match knots {
                KnotSet::All => true,
                KnotSet::Interior => k > 0 && k < last,
                KnotSet::First => k == 0,
                KnotSet::Last => k == last,
                KnotSet::List(list) => list.contains(&k),
            });
            if k == last {
                b = intersect(b, spec.q_final[c]);
            }
            if k == 0 && !spec.q_initial_free.get(c).copied().unwrap_or(false) {
                b = Interval::fixed(spec.q_initial[c]);
            }
            if b.lower > b.upper {
                return Err(TranscriptionError::EmptyBound {
                    coordinate: c,
                    knot: k,
                    lower: b.lower,
                    upper: b.upper,
                });
            }
            lo[l.q(k).start + c] = b.lower;
            hi[l.q(k).start + c] = b.upper;
        }
    }
    if let Some(v0) = &spec.v_initial {
        for (i, &v) in l.v0().zip(v0) {
            lo[i] = v;
            hi[i] = v;
        }
    }
    let (h_lo, h_hi) = match spec.time_steps {
        TimeSteps::Fixed(h) => (h, h),
        TimeSteps::FreeEqual { t_min, t_max } => {
            let intervals = l.intervals() as f64;
            (t_min / intervals, t_max / intervals)
        }
    };
    if !(h_lo > 0.0 && h_lo <= h_hi) {
        return Err(TranscriptionError::Invalid {
            field: "time_steps".into(),
            message: format!("step bounds [{h_lo}, {h_hi}] must satisfy 0 < min ≤ max"),
        });
    }
    for j in 0..l.intervals() {
        lo[l.h(j)] = h_lo;
        hi[l.h(j)] = h_hi;
        for (i, b) in l.u(j).zip(&spec.input_bounds) {
            lo[i] = b.lower;
            hi[i] = b.upper;
        }
        for i in l.contact_vars(j) {
            lo[i] = 0.0;
        }
        if let Some(v) = spec.max_slip_speed {
            for i in 0..l.nc {
                hi[l.psi(j, i)] = v;
            }
        }
    }
    // Flight windows: no normal impulse on the intervals ending at their knots.
    for &(i, j) in &spec.zero_impulse {
        if i < l.nc && j < l.intervals() {
            hi[l.c(j, i)] = 0.0;
        }
    }
    for i in l.slacks() {
        lo[i] = 0.0;
    }
    // A Galerkin interval's interior points are configurations strictly inside the
    // trajectory: the joint limits and the bounds on every (or every interior) knot hold
    // there too.
    for c in 0..l.n {
        let b = coordinate_bound(c, &|knots| {
            matches!(knots, KnotSet::All | KnotSet::Interior)
        });
        for j in 0..l.intervals() {
            for nu in 0..l.interior {
                lo[l.interior(j, nu).start + c] = b.lower;
                hi[l.interior(j, nu).start + c] = b.upper;
            }
        }
    }
    let nr = l.num_constraints();
    let mut g_lower = vec![0.0; nr];
    let mut g_upper: Vec<f64> = (0..nr)
        .map(|r| if l.is_equality(r) { 0.0 } else { f64::INFINITY })
        .collect();
    let rows = spec.constraints.iter().flat_map(|c| c.rows());
    let frame_rows = spec
        .frames
        .iter()
        .filter(|f| f.has_rows())
        .flat_map(|f| f.knots.iter().map(|_| (f.lower, f.upper)));
    let bounds = rows.map(|row| (row.lower, row.upper)).chain(frame_rows);
    for (r, (lower, upper)) in bounds.enumerate() {
        g_lower[l.constraint_row(r)] = lower;
        g_upper[l.constraint_row(r)] = upper;
    }
    Ok(Bounds {
        x_lower: lo,
        x_upper: hi,
        g_lower,
        g_upper,
    })
}

/// The starting point of `spec`'s NLP: its initial guess on the knots, steps at their guess,
/// contact variables and slacks at 0.01, fixed variables at their values, a Galerkin
/// integrator's interior points set ([`interior_points`]).
pub(super) fn initial_guess<M: MechanicsDerivatives>(
    mech: &M,
    ctx: &Context,
    l: &Layout,
    bounds: &Bounds,
    spec: &ProblemSpec,
) -> Result<Vec<f64>, TranscriptionError> {
    let mut x = vec![0.0; l.num_variables()];
    let mut h_guess = match spec.time_steps {
        TimeSteps::Fixed(h) => h,
        TimeSteps::FreeEqual { t_max, .. } => t_max / l.intervals() as f64,
    };
    let last = l.knots - 1;
    // A warm start's contact impulses, per interval, where it carries its forces.
    let mut impulses: Vec<Option<Vec<Vec<f64>>>> = vec![None; l.intervals()];
    match &spec.initial_guess {
        InitialGuess::Linear { from, to } => {
            check_len("initial_guess.from", l.n, from.len())?;
            check_len("initial_guess.to", l.n, to.len())?;
            for k in 0..l.knots {
                let s = k as f64 / last as f64;
                for (c, i) in l.q(k).enumerate() {
                    x[i] = from[c] + s * (to[c] - from[c]);
                }
            }
        }
        // Until `pipeline::resolve_initial_guess` has run the simulation (`solve` and
        // `bench` do; `check` does not, since sizes and structure do not depend on it):
        // q_1 held at every knot.
        InitialGuess::Simulation(_) => {
            for k in 0..l.knots {
                for (c, i) in l.q(k).enumerate() {
                    x[i] = spec.q_initial[c];
                }
            }
        }
        InitialGuess::WarmStart(w) => {
            // Free steps take the previous solution's duration (within the window) and
            // resample it over the knots; fixed steps sample it at their own times.
            let duration =
                w.times.last().copied().unwrap_or(0.0) - w.times.first().copied().unwrap_or(0.0);
            if let TimeSteps::FreeEqual { t_min, t_max } = spec.time_steps
                && duration > 0.0
            {
                h_guess = duration.clamp(t_min, t_max) / l.intervals() as f64;
            }
            let stretch = match spec.time_steps {
                TimeSteps::FreeEqual { .. } if duration > 0.0 => {
                    duration / (h_guess * l.intervals() as f64)
                }
                _ => 1.0,
            };
            let times: Vec<f64> = (0..l.knots)
                .map(|k| w.times.first().copied().unwrap_or(0.0) + k as f64 * h_guess * stretch)
                .collect();
            for (k, &t) in times.iter().enumerate() {
                // With its impulses carried, q keeps the accelerations they go with.
                let q = if w.forces.is_empty() {
                    interpolate(&w.times, &w.q, t)
                } else {
                    interpolate_cubic(&w.times, &w.q, t)
                };
                check_len("initial_guess.q", l.n, q.len())?;
                for (c, i) in l.q(k).enumerate() {
                    x[i] = q[c];
                }
                if k < last && !w.u.is_empty() {
                    let u = interpolate(&w.times[..w.u.len()], &w.u, t);
                    check_len("initial_guess.u", l.m, u.len())?;
                    for (c, i) in l.u(k).enumerate() {
                        x[i] = u[c];
                    }
                }
                if k < last {
                    let middle = t + 0.5 * h_guess * stretch;
                    impulses[k] = forces_at(w, middle, l).map(|forces| {
                        forces
                            .iter()
                            .map(|f| f.iter().map(|f| f * h_guess).collect())
                            .collect()
                    });
                }
            }
        }
    }
    for j in 0..l.intervals() {
        x[l.h(j)] = h_guess;
        for i in l.contact_vars(j) {
            x[i] = 0.01;
        }
        if let Some(impulses) = &impulses[j] {
            for (i, impulse) in impulses.iter().enumerate() {
                x[l.c(j, i)] = impulse[0];
                x[l.beta(j, i)].copy_from_slice(&impulse[1..]);
            }
        }
    }
    for i in l.slacks() {
        x[i] = 0.01;
    }
    // A fixed variable starts at its fixed value (docs/reference-problems.md).
    for ((xi, &lo), &hi) in x.iter_mut().zip(&bounds.x_lower).zip(&bounds.x_upper) {
        if lo == hi {
            *xi = lo;
        }
    }
    // From the linear guess the chord is the better start (hopper galerkin4: 91 iterations
    // against 250 from the stationary points).
    let warm = matches!(spec.initial_guess, InitialGuess::WarmStart(_));
    interior_points(mech, ctx, l, &mut x, warm);
    Ok(x)
}

/// Sets a Galerkin integrator's interior points in `x` from its knots: on the chord between
/// each interval's knots, or with `from_dynamics` where the interval's dynamics put them
/// given its knots, input and step (stationary, as at a solution: a plan of the same
/// integrator gets its interior points back), on the chord where that Newton solve fails.
/// Nothing for another integrator.
pub(super) fn interior_points<M: MechanicsDerivatives>(
    mech: &M,
    ctx: &Context,
    l: &Layout,
    x: &mut [f64],
    from_dynamics: bool,
) {
    let Some(rule) = &ctx.galerkin else {
        return;
    };
    for j in 0..l.intervals() {
        let (qa, qb) = (&x[l.q(j)], &x[l.q(j + 1)]);
        let chord = || rule.chord_interior(qa, qb);
        let interior = if from_dynamics {
            galerkin_interval(mech, rule, qa, qb, &x[l.u(j)], x[l.h(j)], None)
                .map_or_else(|_| chord(), |interval| interval.interior)
        } else {
            chord()
        };
        x[l.interior_points(j)].copy_from_slice(&interior);
    }
}

/// The forces of the warm start's interval holding time `t` (nc × (1 + nd), each contact's
/// normal then friction force), or None when it carries none or its sizes are not `l`'s.
fn forces_at<'a>(w: &'a WarmStart, t: f64, l: &Layout) -> Option<&'a Vec<Vec<f64>>> {
    let intervals = w.forces.len().min(w.times.len().saturating_sub(1));
    if intervals == 0 {
        return None;
    }
    let j = w.times[1..=intervals]
        .partition_point(|&s| s <= t)
        .min(intervals - 1);
    let forces = &w.forces[j];
    (forces.len() == l.nc && forces.iter().all(|f| f.len() == 1 + l.nd)).then_some(forces)
}

/// Sets the sliding speeds ψ and their duals η of `x` from its q and steps: each tangential
/// row is linear in both (its rate + ψe − η), so η is read off the rows at η = 0 and η = 1,
/// and where that leaves η negative (a point moving away in some direction, with ψ 0), ψ is
/// raised to the fastest of them and every η with it.
pub(super) fn sliding_from_rows<M: MechanicsDerivatives>(
    t: &super::Transcription<M>,
    x: &mut [f64],
) {
    let l = t.layout();
    let at = |eta: f64, x: &mut [f64]| {
        for j in 0..l.intervals() {
            for i in 0..l.nc {
                for e in l.eta(j, i) {
                    x[e] = eta;
                }
            }
        }
        let mut g = vec![0.0; l.num_constraints()];
        t.constraints(x, &mut g);
        g
    };
    let g0 = at(0.0, x);
    let g1 = at(1.0, x);
    for j in 0..l.intervals() {
        let rows = l.rows_of("TangentialRate", j);
        for i in 0..l.nc {
            let eta: Vec<f64> = (0..l.nd)
                .map(|d| {
                    let r = rows.start + i * l.nd + d;
                    let slope = g1[r] - g0[r];
                    if slope != 0.0 { -g0[r] / slope } else { 0.0 }
                })
                .collect();
            let deficit = eta.iter().fold(0.0_f64, |m, &e| m.max(-e));
            x[l.psi(j, i)] += deficit;
            for (e, value) in l.eta(j, i).zip(eta) {
                x[e] = (value + deficit).max(0.0);
            }
        }
    }
}

/// Sets the slacks of `x` to the complementarity products they bound at `x` (at least 0),
/// so that a start carrying its impulses meets its complementarity rows.
pub(super) fn slacks_from_rows<M: MechanicsDerivatives>(
    t: &super::Transcription<M>,
    x: &mut [f64],
) {
    let l = t.layout();
    if l.slacks().is_empty() {
        return;
    }
    for s in l.slacks() {
        x[s] = 0.0;
    }
    let mut g = vec![0.0; l.num_constraints()];
    t.constraints(x, &mut g);
    for j in 0..l.intervals() {
        let rows = l.rows_of("Complementarity", j);
        let slacks = l.slack(j);
        if slacks.len() == 1 {
            // Each row is s − (a product sum) ≥ 0.
            let need = rows.clone().fold(0.0_f64, |m, r| m.max(-g[r]));
            x[slacks.start] = need;
        } else {
            for (s, r) in slacks.zip(rows) {
                x[s] = (-g[r]).max(0.0);
            }
        }
    }
}

/// Piecewise-linear interpolation of rows `values` given at `times`, clamped at the ends.
pub(super) fn interpolate(times: &[f64], values: &[Vec<f64>], t: f64) -> Vec<f64> {
    if times.is_empty() || values.is_empty() {
        return Vec::new();
    }
    let last = times.len().min(values.len()) - 1;
    if t <= times[0] {
        return values[0].clone();
    }
    if t >= times[last] {
        return values[last].clone();
    }
    let k = times[..=last].partition_point(|&s| s <= t).clamp(1, last);
    let (t0, t1) = (times[k - 1], times[k]);
    let s = if t1 > t0 { (t - t0) / (t1 - t0) } else { 0.0 };
    values[k - 1]
        .iter()
        .zip(&values[k])
        .map(|(a, b)| a + s * (b - a))
        .collect()
}

/// The slope at knot `k` of the quadratic through knots k − 1, k, k + 1 (the two nearest
/// at an end): exact for a trajectory of constant acceleration.
fn knot_slope(times: &[f64], values: &[Vec<f64>], k: usize, c: usize) -> f64 {
    let last = times.len() - 1;
    let (a, b, d) = match k {
        0 => (0, 1, 2),
        k if k == last => (last - 2, last - 1, last),
        k => (k - 1, k, k + 1),
    };
    let (ta, tb, td) = (times[a], times[b], times[d]);
    let (ya, yb, yd) = (values[a][c], values[b][c], values[d][c]);
    if !(ta < tb && tb < td) {
        // Knots that share a time have no parabola through them: no slope.
        return 0.0;
    }
    let t = times[k];
    // Derivative of the Lagrange quadratic through the three knots, at t.
    ya * ((t - tb) + (t - td)) / ((ta - tb) * (ta - td))
        + yb * ((t - ta) + (t - td)) / ((tb - ta) * (tb - td))
        + yd * ((t - ta) + (t - tb)) / ((td - ta) * (td - tb))
}

/// `values` at time `t` on the C¹ cubic through the knots whose slope at each knot is that of
/// the quadratic through it and its neighbours (exact for constant acceleration), held at the
/// ends outside them; linear with fewer than three knots. A trajectory resampled on it keeps
/// its accelerations, so the finer grid's dynamics rows hold where the coarse one's did
/// (linear interpolation puts a whole interval's momentum change at the coarse knots).
pub(super) fn interpolate_cubic(times: &[f64], values: &[Vec<f64>], t: f64) -> Vec<f64> {
    let last = times.len().min(values.len()).saturating_sub(1);
    if last < 2 || t <= times[0] || t >= times[last] {
        return interpolate(times, values, t);
    }
    let times = &times[..=last];
    let k = times.partition_point(|&s| s <= t).clamp(1, last);
    let (t0, t1) = (times[k - 1], times[k]);
    let h = t1 - t0;
    if h <= 0.0 {
        return values[k - 1].clone();
    }
    let s = (t - t0) / h;
    let (h00, h10, h01, h11) = (
        (1.0 + 2.0 * s) * (1.0 - s) * (1.0 - s),
        s * (1.0 - s) * (1.0 - s),
        s * s * (3.0 - 2.0 * s),
        s * s * (s - 1.0),
    );
    (0..values[k - 1].len())
        .map(|c| {
            let (m0, m1) = (
                knot_slope(times, values, k - 1, c),
                knot_slope(times, values, k, c),
            );
            h00 * values[k - 1][c] + h10 * h * m0 + h01 * values[k][c] + h11 * h * m1
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::{interpolate, interpolate_cubic};

    /// A motion of constant acceleration (q = 1 + 2t − 3t², one coordinate, knots unevenly
    /// spaced) is reproduced exactly between its knots, where the linear interpolation is off
    /// by half the acceleration times the squared half step (0.03 in the longest interval).
    #[test]
    fn the_cubic_resampling_keeps_a_constant_acceleration() {
        let q = |t: f64| 1.0 + 2.0 * t - 3.0 * t * t;
        let times = [0.0, 0.1, 0.25, 0.3, 0.5];
        let values: Vec<Vec<f64>> = times.iter().map(|&t| vec![q(t)]).collect();
        let mut worst_linear = 0.0_f64;
        for i in 0..=50 {
            let t = 0.5 * i as f64 / 50.0;
            let cubic = interpolate_cubic(&times, &values, t)[0];
            assert!(
                (cubic - q(t)).abs() < 1e-14,
                "t {t}: {cubic} against {}",
                q(t)
            );
            worst_linear = worst_linear.max((interpolate(&times, &values, t)[0] - q(t)).abs());
        }
        assert!(worst_linear > 1e-2, "{worst_linear}");
        // At the knots and outside them: the knots' values.
        assert_eq!(interpolate_cubic(&times, &values, 0.25)[0], q(0.25));
        assert_eq!(interpolate_cubic(&times, &values, -1.0)[0], q(0.0));
        assert_eq!(interpolate_cubic(&times, &values, 2.0)[0], q(0.5));
    }
}
