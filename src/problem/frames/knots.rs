//! Which knots a frame term or a contact window applies at: a named set, a list, or the
//! knots whose nominal time lies in a window [t0, t1] (seconds).

use super::FrameCheck;
use crate::problem::schema::KnotsName;
use crate::problem::{ProblemError, TimeSteps};

/// How far (s) a knot's nominal time may fall outside a window and still count: rounding
/// of t_k = k·h.
const TIME_ROUNDING: f64 = 1e-9;

/// The knots as the entry names them, with the key that named them (for errors).
#[derive(Debug, Clone)]
pub enum KnotChoice {
    /// `"all"`, `"interior"`, `"first"`, `"final"` or a list.
    Knots(&'static str, KnotsName),
    /// [t0, t1] in seconds.
    Window(&'static str, [f64; 2]),
}

/// The nominal time of every knot: t_k = k·h, h the fixed step or, with free steps, the
/// initial guess's t_max/(N − 1).
pub fn nominal_times(knots: usize, time_steps: &TimeSteps) -> Vec<f64> {
    let h = time_steps.guess_step(knots);
    (0..knots).map(|k| k as f64 * h).collect()
}

impl KnotChoice {
    /// The 0-based knots, ascending and distinct, or the error naming the key.
    pub(crate) fn resolve(
        &self,
        at: &FrameCheck,
        knots: usize,
        times: &[f64],
    ) -> Result<Vec<usize>, ProblemError> {
        match self {
            KnotChoice::Knots(key, KnotsName::Named(name)) => match name.as_str() {
                "all" => Ok((0..knots).collect()),
                "interior" => Ok((1..knots - 1).collect()),
                "first" => Ok(vec![0]),
                "final" | "last" => Ok(vec![knots - 1]),
                other => {
                    let valid = ["all", "interior", "first", "final"].map(String::from);
                    Err(at
                        .ctx
                        .unknown_name(&at.field(key), "knot set", other, &valid))
                }
            },
            KnotChoice::Knots(key, KnotsName::List(list)) => {
                if list.is_empty() {
                    return Err(at.invalid(
                        key,
                        "lists no knot: list 0-based knots, or use \"all\", \"interior\", \
                         \"first\" or \"final\"",
                    ));
                }
                let mut out = Vec::with_capacity(list.len());
                for &k in list {
                    if k < 0 || k as usize >= knots {
                        return Err(at.invalid(
                            key,
                            format!("knot {k} is outside 0..{} (knots are 0-based)", knots - 1),
                        ));
                    }
                    out.push(k as usize);
                }
                out.sort_unstable();
                out.dedup();
                Ok(out)
            }
            KnotChoice::Window(key, [t0, t1]) => {
                let end = times.last().copied().unwrap_or(0.0);
                if !t0.is_finite() || !t1.is_finite() || t0 > t1 {
                    return Err(at.invalid(
                        key,
                        format!("[{t0}, {t1}] is not a window: give [start, end] in seconds"),
                    ));
                }
                if *t0 < -TIME_ROUNDING || *t1 > end + TIME_ROUNDING {
                    return Err(at.invalid(
                        key,
                        format!(
                            "[{t0}, {t1}] s reaches outside the horizon [0, {end}] s; keep \
                             the window inside it"
                        ),
                    ));
                }
                let chosen: Vec<usize> = times
                    .iter()
                    .enumerate()
                    .filter(|(_, t)| **t >= t0 - TIME_ROUNDING && **t <= t1 + TIME_ROUNDING)
                    .map(|(k, _)| k)
                    .collect();
                if chosen.is_empty() {
                    return Err(at.invalid(
                        key,
                        format!(
                            "[{t0}, {t1}] s holds no knot (knots are {} s apart); widen it",
                            times.get(1).copied().unwrap_or(0.0)
                        ),
                    ));
                }
                Ok(chosen)
            }
        }
    }
}
