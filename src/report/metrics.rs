//! The paper's measures of a gait or a jump, from a solution's knots: what `[metrics]
//! report` asks for, in `summary.json` under `metrics` (units under `metric_units`).

use serde_json::{Map, Value, json};

use crate::problem::{Metric, MetricsSpec, Units};

/// A solved (or simulated) trajectory as the metrics read it.
pub struct MetricInputs<'a> {
    /// Knot times (N).
    pub times: &'a [f64],
    /// Configurations (N × n).
    pub q: &'a [Vec<f64>],
    /// World positions of the contact points (N × nc).
    pub contact_positions: &'a [Vec<[f64; 3]>],
}

/// The value of `metric`; NaN where it is undefined (slip without forward motion).
pub fn metric_value(metric: Metric, spec: &MetricsSpec, at: &MetricInputs) -> f64 {
    let (Some(first), Some(last)) = (at.q.first(), at.q.last()) else {
        return f64::NAN;
    };
    let forward = last[spec.forward] - first[spec.forward];
    match metric {
        Metric::ForwardPerCycle => forward,
        Metric::ForwardSpeed => {
            let duration = at.times.last().copied().unwrap_or(0.0) - at.times[0];
            forward / duration
        }
        Metric::Slip => slip(at.contact_positions, forward),
        Metric::JumpHeight => {
            let start = first[spec.vertical];
            at.q.iter()
                .map(|q| q[spec.vertical] - start)
                .fold(f64::NEG_INFINITY, f64::max)
        }
    }
}

/// Eq. 38 of the paper over the knots: for each contact, the sum of its backward world-x
/// displacements over the intervals (∫_ξ |v_x| dt with v_x piecewise constant), divided by
/// the body's forward distance, averaged over the contacts.
fn slip(positions: &[Vec<[f64; 3]>], forward: f64) -> f64 {
    let contacts = positions.first().map_or(0, Vec::len);
    if contacts == 0 || forward <= 0.0 {
        return f64::NAN;
    }
    let backward: f64 = positions
        .windows(2)
        .flat_map(|w| (0..contacts).map(move |i| (w[0][i][0] - w[1][i][0]).max(0.0)))
        .sum();
    backward / (contacts as f64 * forward)
}

/// The unit of `metric` in the problem's units.
pub fn metric_unit(metric: Metric, units: &Units) -> String {
    match metric {
        Metric::ForwardPerCycle => format!("{} per cycle", units.length),
        Metric::ForwardSpeed => format!("{}/{}", units.length, units.time),
        Metric::Slip => "1".into(),
        Metric::JumpHeight => units.length.clone(),
    }
}

/// `metrics` and `metric_units` of the summary: one number (null when undefined) and one
/// unit per metric the problem reports.
pub fn metrics_json(spec: &MetricsSpec, units: &Units, at: &MetricInputs) -> (Value, Value) {
    let mut values = Map::new();
    let mut unit_names = Map::new();
    for &metric in &spec.report {
        let v = metric_value(metric, spec, at);
        values.insert(
            metric.name().into(),
            if v.is_finite() { json!(v) } else { Value::Null },
        );
        unit_names.insert(metric.name().into(), json!(metric_unit(metric, units)));
    }
    (Value::Object(values), Value::Object(unit_names))
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::report::tests::sample_solution;

    fn spec() -> MetricsSpec {
        MetricsSpec {
            report: Metric::ALL.iter().map(|(_, m)| *m).collect(),
            forward: 0,
            vertical: 1,
        }
    }

    #[test]
    fn metrics_of_the_sample_solution_match_hand_values() {
        let s = sample_solution();
        let at = MetricInputs {
            times: &s.times,
            q: &s.q,
            contact_positions: &s.contact_positions,
        };
        let value = |m| metric_value(m, &spec(), &at);
        // x goes 0 → 0.3 over T = 0.3; theta (as "vertical") peaks 0.3 above its start.
        assert!((value(Metric::ForwardPerCycle) - 0.3).abs() < 1e-15);
        assert!((value(Metric::ForwardSpeed) - 1.0).abs() < 1e-12);
        assert!((value(Metric::JumpHeight) - 0.3).abs() < 1e-15);
        // The toe moves back 0.05 once, the heel never: (0.05 + 0) / (2 · 0.3).
        assert!((value(Metric::Slip) - 0.05 / 0.6).abs() < 1e-15);
    }

    #[test]
    fn slip_without_forward_motion_is_undefined_and_null_in_json() {
        let mut s = sample_solution();
        for q in &mut s.q {
            q[0] = 0.0;
        }
        let at = MetricInputs {
            times: &s.times,
            q: &s.q,
            contact_positions: &s.contact_positions,
        };
        assert!(metric_value(Metric::Slip, &spec(), &at).is_nan());
        let units = Units {
            length: "mm".into(),
            mass: "g".into(),
            time: "ms".into(),
        };
        let (values, unit_names) = metrics_json(&spec(), &units, &at);
        assert_eq!(values["slip"], Value::Null);
        assert_eq!(values["forward_per_cycle"], json!(0.0));
        assert_eq!(unit_names["forward_per_cycle"], "mm per cycle");
        assert_eq!(unit_names["forward_speed"], "mm/ms");
    }
}
