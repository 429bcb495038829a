//! Contact windows and gaits: optional hints on top of contact-implicit planning. A flight
//! window holds a contact's normal impulse at zero on the intervals ending at its knots and
//! keeps its distance to the terrain at least `clearance` there; a stance window keeps its
//! distance at zero. A `[gait]` builds such windows from a period, a duty factor and each
//! contact's phase offset. Both expand into clearance frame terms plus the (contact,
//! interval) pairs whose impulse is zero; a contact in stance and flight at one knot is
//! refused, naming both windows.

use std::collections::BTreeMap;

use serde::Deserialize;

use super::{Clearance, FramePoint, FrameQuantity, FrameScope, FrameTerm, KnotChoice};
use crate::problem::ProblemError;
use crate::problem::schema::ProblemFile;
use crate::problem::validate::context::Context;
use crate::problem::validate::values::{finite, nonnegative};

/// `[[contact_window]]`: one contact in flight or in stance over a time window.
#[derive(Debug, Clone, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct ContactWindowEntry {
    /// The contact's name.
    pub contact: String,
    /// `"flight"` or `"stance"`.
    pub phase: String,
    /// [t0, t1] in seconds: the knots whose nominal time lies in it.
    #[serde(deserialize_with = "crate::problem::schema::exact")]
    pub window: [f64; 2],
    /// Flight only: the distance to the terrain kept at every knot of the window [length]
    /// (default 0).
    pub clearance: Option<f64>,
}

/// `[gait]`: a periodic contact schedule. Contact i is in stance while the phase
/// s = frac((t − start)/period − offset_i) is below `duty`, in swing after.
#[derive(Debug, Clone, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct GaitEntry {
    /// The gait period [s].
    pub period: f64,
    /// The fraction of the period each contact is in stance, in (0, 1).
    pub duty: f64,
    /// Per contact, its phase offset as a fraction of the period in [0, 1); contacts not
    /// named get no windows.
    pub offsets: BTreeMap<String, f64>,
    /// The distance to the terrain every swing keeps at its knots but the first and last
    /// (lift-off and touch-down) [length] (default 0).
    pub clearance: Option<f64>,
    /// When the gait starts [s] (default 0); earlier knots and knot 0 get no window.
    pub start: Option<f64>,
}

/// The windows' frame terms and the (contact, interval) pairs whose normal impulse is zero.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct Windows {
    /// Clearance rows: ≥ clearance in flight, = 0 in stance.
    pub frames: Vec<FrameTerm>,
    /// (contact, interval j): c_{j,contact} = 0.
    pub zero_impulse: Vec<(usize, usize)>,
}

/// One window after expansion.
struct Window {
    /// How messages name it.
    name: String,
    /// The field an error about it names.
    field: String,
    contact: usize,
    flight: bool,
    /// Knots it covers.
    knots: Vec<usize>,
    /// Knots where the clearance holds (flight) or the distance is 0 (stance).
    rows: Vec<usize>,
    clearance: f64,
}

/// `[[contact_window]]` and `[gait]`, expanded and checked for overlaps.
pub(crate) fn check_windows(
    scope: &FrameScope,
    raw: &ProblemFile,
) -> Result<Windows, ProblemError> {
    let ctx = scope.ctx;
    let mut windows = Vec::new();
    for (i, entry) in raw.contact_window.iter().enumerate() {
        let at = scope.check(format!("contact_window[{i}]"));
        let contact = at.contact("contact", &entry.contact)?;
        let flight = match entry.phase.as_str() {
            "flight" => true,
            "stance" => false,
            other => {
                let valid = ["flight", "stance"].map(String::from);
                return Err(ctx.unknown_name(&at.field("phase"), "phase", other, &valid));
            }
        };
        let clearance = match (entry.clearance, flight) {
            (Some(_), false) => {
                return Err(at.invalid(
                    "clearance",
                    "a stance window keeps the distance at 0; `clearance` is for flight",
                ));
            }
            (Some(c), true) => nonnegative(ctx, &at.field("clearance"), c)?,
            (None, _) => 0.0,
        };
        let covered = at.knots(KnotChoice::Window("window", entry.window))?;
        windows.push(Window {
            name: format!(
                "contact_window[{i}] ({} {} over [{}, {}] s)",
                entry.contact, entry.phase, entry.window[0], entry.window[1]
            ),
            field: at.field("window"),
            contact,
            flight,
            rows: covered.clone(),
            knots: covered,
            clearance,
        });
    }
    if let Some(gait) = &raw.gait {
        windows.extend(gait_windows(scope, gait)?);
    }
    refuse_overlaps(ctx, &windows)?;
    Ok(expand(&windows))
}

/// The gait's stance and swing runs per contact, from knot 1 (or `start`) on.
fn gait_windows(scope: &FrameScope, gait: &GaitEntry) -> Result<Vec<Window>, ProblemError> {
    let ctx = scope.ctx;
    let period = finite(ctx, "gait.period", gait.period)?;
    if period <= 0.0 {
        return Err(ctx.invalid("gait.period", format!("must be > 0 s, got {period}")));
    }
    // Below two steps the knots cannot tell stance from swing: at one step (or a fraction of
    // one) every knot has the same phase, and in between the phases alias to a slower gait.
    let step = scope.times.get(1).copied().unwrap_or(0.0);
    if period < 2.0 * step {
        use crate::files::trajectory_csv::number;
        return Err(ctx.invalid(
            "gait.period",
            format!(
                "{} s is shorter than two time steps (2 × {} s): the knots cannot tell its \
                 stance from its swing (at one step or less every knot has the same phase); \
                 give a period of at least {} s, or more knots",
                number(period),
                number(step),
                number(2.0 * step)
            ),
        ));
    }
    let duty = finite(ctx, "gait.duty", gait.duty)?;
    if !(duty > 0.0 && duty < 1.0) {
        return Err(ctx.invalid(
            "gait.duty",
            format!("the stance fraction must lie in (0, 1), got {duty}"),
        ));
    }
    let clearance = nonnegative(ctx, "gait.clearance", gait.clearance.unwrap_or(0.0))?;
    let start = finite(ctx, "gait.start", gait.start.unwrap_or(0.0))?;
    let times = &scope.times;
    let end = times.last().copied().unwrap_or(0.0);
    if start < 0.0 || start >= end {
        return Err(ctx.invalid(
            "gait.start",
            format!("{start} s is outside the horizon [0, {end}) s"),
        ));
    }
    if gait.offsets.is_empty() {
        return Err(ctx.invalid(
            "gait.offsets",
            "names no contact: give each contact that follows the gait its phase offset, \
             e.g. { front_left_foot = 0.0, front_right_foot = 0.5 }",
        ));
    }
    let names: Vec<String> = scope.contacts.iter().map(|c| c.name.clone()).collect();
    let mut windows = Vec::new();
    for (name, &offset) in &gait.offsets {
        let field = format!("gait.offsets.{name}");
        let contact = names
            .iter()
            .position(|n| n == name)
            .ok_or_else(|| ctx.unknown_name("gait.offsets", "contact", name, &names))?;
        let offset = finite(ctx, &field, offset)?;
        if !(0.0..1.0).contains(&offset) {
            return Err(ctx.invalid(
                &field,
                format!("a phase offset is a fraction of the period in [0, 1), got {offset}"),
            ));
        }
        // Runs of knots in one phase, from the first gait knot on.
        let mut runs: Vec<(bool, Vec<usize>)> = Vec::new();
        for (k, &t) in times.iter().enumerate().skip(1) {
            if t < start - 1e-9 {
                continue;
            }
            let phase = ((t - start) / period - offset).rem_euclid(1.0);
            let swing = phase >= duty - 1e-9;
            match runs.last_mut() {
                Some((s, run)) if *s == swing => run.push(k),
                _ => runs.push((swing, vec![k])),
            }
        }
        for (swing, run) in runs {
            let (first, last) = (run[0], run[run.len() - 1]);
            let span = format!(
                "{:.3}–{:.3} s, knots {first}–{last}",
                times[first], times[last]
            );
            let rows = if swing {
                if run.len() < 3 && clearance > 0.0 {
                    return Err(ctx.invalid(
                        &field,
                        format!(
                            "the swing of `{name}` at {span} has no knot between lift-off and \
                             touch-down to clear {clearance}: lengthen the period, lower the \
                             duty factor or add knots"
                        ),
                    ));
                }
                run[1..run.len().saturating_sub(1).max(1)].to_vec()
            } else {
                run.clone()
            };
            windows.push(Window {
                name: format!(
                    "the gait's {} of `{name}` ({span})",
                    if swing { "swing" } else { "stance" }
                ),
                field: field.clone(),
                contact,
                flight: swing,
                knots: run,
                rows,
                clearance,
            });
        }
    }
    Ok(windows)
}

/// A contact in stance and flight at one knot is impossible: the error names both windows.
fn refuse_overlaps(ctx: &Context, windows: &[Window]) -> Result<(), ProblemError> {
    let knots: Vec<(usize, bool, &[usize])> = windows
        .iter()
        .map(|w| (w.contact, w.flight, w.knots.as_slice()))
        .collect();
    let Some((b, a, k)) = first_overlap(&knots) else {
        return Ok(());
    };
    let (wb, wa) = (&windows[b], &windows[a]);
    Err(ctx.invalid(
        &wb.field,
        format!(
            "{} overlaps {} at knot {k}: a contact cannot be in stance and in flight at once; \
             shorten one of them",
            wb.name, wa.name
        ),
    ))
}

/// The first overlap of windows given as (contact, flight, knots): the first window b that
/// shares a knot with an earlier window a of its contact in the other phase, the first such
/// a, and the first knot of b in a. Each window's knots are looked up in, then added to, a
/// map from (contact, knot, phase) to the first window there: the work grows with the
/// windows' knots, never with their pairs.
fn first_overlap(windows: &[(usize, bool, &[usize])]) -> Option<(usize, usize, usize)> {
    let mut first: std::collections::HashMap<(usize, usize, bool), usize> =
        std::collections::HashMap::new();
    for (b, &(contact, flight, knots)) in windows.iter().enumerate() {
        let seen = &first;
        let earlier = || {
            knots
                .iter()
                .filter_map(move |&k| seen.get(&(contact, k, !flight)).map(|&a| (a, k)))
        };
        // At every knot b shares with the first overlapping window a, a is the first window
        // there (any earlier one would overlap first): its first such knot is b's first in a.
        if let Some(a) = earlier().map(|(a, _)| a).min() {
            let k = earlier().find(|&(x, _)| x == a).map(|(_, k)| k)?;
            return Some((b, a, k));
        }
        for &k in knots {
            first.entry((contact, k, flight)).or_insert(b);
        }
    }
    None
}

/// The windows as clearance terms and zero impulses.
fn expand(windows: &[Window]) -> Windows {
    let mut out = Windows::default();
    for w in windows {
        if w.flight {
            out.zero_impulse.extend(
                w.knots
                    .iter()
                    .filter(|&&k| k > 0)
                    .map(|&k| (w.contact, k - 1)),
            );
        }
        if w.rows.is_empty() || (w.flight && w.clearance == 0.0) {
            // A flight window without clearance: φ ≥ 0 is the contact's own row.
            continue;
        }
        let (lower, upper) = if w.flight {
            (w.clearance, f64::INFINITY)
        } else {
            (0.0, 0.0)
        };
        out.frames.push(FrameTerm {
            quantity: FrameQuantity::Clearance(Clearance {
                point: FramePoint::Contact(w.contact),
            }),
            label: w.name.clone(),
            knots: w.rows.clone(),
            target: 0.0,
            weight: 0.0,
            lower,
            upper,
        });
    }
    out.zero_impulse.sort_unstable();
    out.zero_impulse.dedup();
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The overlap found is the one the definition names: the first window b with an earlier
    /// window a of its contact and the other phase sharing a knot, the first such a, the first
    /// knot of b in a (checked pair by pair here, over seeded random windows).
    #[test]
    fn first_overlap_is_the_pairwise_definitions() {
        let mut rng = crate::random::SeededRng::new(3);
        let mut found = 0;
        for _ in 0..2000 {
            let windows: Vec<(usize, bool, Vec<usize>)> = (0..1 + rng.index(8))
                .map(|_| {
                    let start = rng.index(30);
                    let knots = (start..start + 1 + rng.index(5)).collect();
                    (rng.index(2), rng.index(2) == 0, knots)
                })
                .collect();
            let pairwise = windows.iter().enumerate().find_map(|(b, wb)| {
                windows[..b].iter().enumerate().find_map(|(a, wa)| {
                    if wa.0 != wb.0 || wa.1 == wb.1 {
                        return None;
                    }
                    wb.2.iter().find(|k| wa.2.contains(k)).map(|&k| (b, a, k))
                })
            });
            let given: Vec<(usize, bool, &[usize])> = windows
                .iter()
                .map(|(c, f, k)| (*c, *f, k.as_slice()))
                .collect();
            assert_eq!(first_overlap(&given), pairwise, "{windows:?}");
            found += usize::from(pairwise.is_some());
        }
        assert!((200..1800).contains(&found), "{found} of 2000 overlap");
    }
}
