//! Whether a solve is solved: the one definition `vito solve`, multi-start, `vito bench`,
//! sweeps, `vito regress` and the studies use.
//!
//! Ipopt's optimum of the relaxed NLP is a plan of the contact model only when its slacks are
//! (near) zero: a slack s lets a foot push while above the ground (c·φ ≤ s), slide without
//! friction's resistance or stick while sliding. A solve is solved when Ipopt reached an
//! optimum ([`Status::is_success`]) and its largest slack is within the problem's
//! `slack.tolerance` ([`DEFAULT_SLACK_TOLERANCE`] by default). An interval's slack is the
//! larger of its slack variables and of the sums over its contacts of its complementarity
//! products with noise-level factors zeroed ([`crate::contact::FACTOR_FLOOR`]): the rows bound
//! the raw sums, in which a flight foot's product can cancel another foot's
//! (`Solution::read_off`). Penalty mode (`SlackMode::Penalty`) has no slack variables; its
//! slack of an interval is the product sums alone (what the elastic slack would be at its
//! optimum), so the same verdict applies.

use crate::ipopt::Status;

/// Defined with the problem's slack settings; the verdict reads it from there.
pub use crate::problem::DEFAULT_SLACK_TOLERANCE;

/// The status name of a plan whose slack exceeds its tolerance.
pub const RELAXED_CONTACT: &str = "relaxed_contact";

/// The status name of a solve stopped at its wall-time limit (`vito solve --time-limit`, a
/// sweep's `--time-limit`, or Ipopt's own `max_wall_time`): Ipopt's
/// [`Status::MaximumWallTimeExceeded`], its iterate kept.
pub const TIMEOUT: &str = "timeout";

/// How a solve ended, judged.
#[derive(Debug, Clone, Copy, PartialEq, Eq, serde::Serialize, serde::Deserialize)]
pub enum SolveVerdict {
    /// Ipopt reached an optimum (its status) and every slack is within the tolerance.
    Solved(Status),
    /// Ipopt reached an optimum of the relaxed problem, but a slack exceeds the tolerance:
    /// the plan breaks the contact model.
    RelaxedContact,
    /// Ipopt did not reach an optimum (its status).
    NotSolved(Status),
}

impl SolveVerdict {
    /// The verdict on a solve that ended with Ipopt's `status` and largest slack `max_slack`
    /// (a NaN slack is not within any tolerance).
    pub fn new(status: Status, max_slack: f64, tolerance: f64) -> SolveVerdict {
        if !status.is_success() {
            SolveVerdict::NotSolved(status)
        } else if max_slack <= tolerance {
            SolveVerdict::Solved(status)
        } else {
            SolveVerdict::RelaxedContact
        }
    }

    /// Whether the plan can be used (exit code 0).
    pub fn is_solved(self) -> bool {
        matches!(self, SolveVerdict::Solved(_))
    }

    /// The status as reports print it: Ipopt's name in snake case, or
    /// [`RELAXED_CONTACT`].
    pub fn name(self) -> &'static str {
        match self {
            SolveVerdict::NotSolved(Status::MaximumWallTimeExceeded) => TIMEOUT,
            SolveVerdict::Solved(s) | SolveVerdict::NotSolved(s) => s.as_snake_case(),
            SolveVerdict::RelaxedContact => RELAXED_CONTACT,
        }
    }

    /// The verdict [`SolveVerdict::name`] names (None for a name it never gives).
    pub fn from_name(name: &str) -> Option<SolveVerdict> {
        if name == RELAXED_CONTACT {
            return Some(SolveVerdict::RelaxedContact);
        }
        if name == TIMEOUT {
            return Some(SolveVerdict::NotSolved(Status::MaximumWallTimeExceeded));
        }
        let status = Status::from_snake_case(name)?;
        Some(if status.is_success() {
            SolveVerdict::Solved(status)
        } else {
            SolveVerdict::NotSolved(status)
        })
    }

    /// The verdict a `summary.json` of a solve records: its `status` where it records
    /// `ipopt_status` beside it; in a summary written before vito judged the slack, from
    /// `status`, `max_slack` and [`DEFAULT_SLACK_TOLERANCE`]. None when the status is not one
    /// vito writes (or the summary is a simulation's, which has no status).
    pub fn of_summary(summary: &serde_json::Value) -> Option<SolveVerdict> {
        let status = summary["status"].as_str()?;
        if summary["ipopt_status"].is_string() {
            return SolveVerdict::from_name(status);
        }
        let max_slack = summary["max_slack"].as_f64().unwrap_or(f64::NAN);
        Some(SolveVerdict::new(
            Status::from_snake_case(status)?,
            max_slack,
            DEFAULT_SLACK_TOLERANCE,
        ))
    }

    /// The order in which multi-start prefers solves: solved, then relaxed, then the rest.
    pub fn rank(self) -> u8 {
        match self {
            SolveVerdict::Solved(_) => 0,
            SolveVerdict::RelaxedContact => 1,
            SolveVerdict::NotSolved(_) => 2,
        }
    }
}

impl std::fmt::Display for SolveVerdict {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(self.name())
    }
}

/// Where a solution relaxes its contact model most: the largest slack.
#[derive(Debug, Clone, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct SlackPeak {
    /// The interval (0-based; row `interval` of `trajectory.csv`) holding the largest slack.
    pub interval: usize,
    /// The contact relaxed there: the slack's own contact in per-contact mode, else the one
    /// whose complementarity products are largest; None when no contact's is positive.
    pub contact: Option<String>,
    /// The slack's value.
    pub slack: f64,
    /// True when the slack variables are within the tolerance and this slack, the interval's
    /// complementarity products (factors at noise level zeroed), is not: products of
    /// opposite sign cancel in the rows' sums, so a higher slack weight does not close it.
    pub hidden: bool,
}

/// A constraint row by name (as `vito check --derivatives` names rows) with its violation.
#[derive(Debug, Clone, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct RowViolation {
    /// The row, e.g. `DEL base_x, knot 19`.
    pub row: String,
    /// How far the row's value lies outside its bounds (problem units).
    pub violation: f64,
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn solved_needs_an_optimum_and_a_closed_slack() {
        let v = |s, slack| SolveVerdict::new(s, slack, 1e-4);
        assert!(v(Status::SolveSucceeded, 1e-4).is_solved());
        assert!(v(Status::SolvedToAcceptableLevel, 0.0).is_solved());
        assert_eq!(
            v(Status::SolveSucceeded, 0.307),
            SolveVerdict::RelaxedContact
        );
        assert_eq!(v(Status::SolveSucceeded, 0.307).name(), "relaxed_contact");
        assert_eq!(
            v(Status::SolveSucceeded, f64::NAN),
            SolveVerdict::RelaxedContact
        );
        let failed = v(Status::MaximumIterationsExceeded, 0.0);
        assert!(!failed.is_solved());
        assert_eq!(failed.name(), "maximum_iterations_exceeded");
        assert!(v(Status::SolveSucceeded, 0.0).rank() < v(Status::SolveSucceeded, 1.0).rank());
        assert!(v(Status::SolveSucceeded, 1.0).rank() < failed.rank());
        for verdict in [
            v(Status::SolveSucceeded, 0.0),
            v(Status::SolveSucceeded, 1.0),
            failed,
        ] {
            assert_eq!(SolveVerdict::from_name(verdict.name()), Some(verdict));
        }
        assert_eq!(SolveVerdict::from_name("solved"), None);
    }
}
