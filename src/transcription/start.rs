//! Where the solve starts and what it may not leave: variable and constraint bounds, the
//! initial guess (linear or warm-started from a previous trajectory).

use super::TranscriptionError;
use super::blocks::Context;
use super::error::check_len;
use super::layout::Layout;
use crate::discrete::{MechanicsDerivatives, galerkin_interval};
use crate::problem::{InitialGuess, Interval, KnotSet, ProblemSpec, TimeSteps};

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
                let q = interpolate(&w.times, &w.q, t);
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
            }
        }
    }
    for j in 0..l.intervals() {
        x[l.h(j)] = h_guess;
        for i in l.contact_vars(j) {
            x[i] = 0.01;
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
