//! What a solve returns: the trajectory by knot, with names, and the numbers a summary needs.

use crate::ipopt::Status;

/// Sizes of the NLP as Ipopt sees it.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, serde::Serialize, serde::Deserialize)]
pub struct NlpSize {
    pub n_variables: usize,
    pub n_constraints: usize,
    pub nnz_jacobian: usize,
    pub nnz_hessian: usize,
}

/// A solved (or stopped) trajectory. Knot k = 0..N−1, interval k = 0..N−2 (0-based).
#[derive(Debug, Clone, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct Solution {
    pub status: Status,
    /// Total objective (problem cost + slack penalty).
    pub objective: f64,
    /// The objective split by term, named like "state_tracking", "input", "slack_penalty"
    /// ("complementarity_penalty" in penalty mode).
    pub objective_terms: Vec<(String, f64)>,
    pub iterations: usize,
    pub wall_time_s: f64,
    /// Time spent in vito's callbacks (function and derivative evaluation).
    pub callback_time_s: f64,
    /// Time spent inside Ipopt (linear algebra, line search), i.e. wall minus callbacks.
    pub ipopt_time_s: f64,
    /// The callback time by callback (f, ∇f, g, Jacobian, Hessian: calls and seconds).
    pub callback_split: crate::ipopt::CallbackSplit,
    pub size: NlpSize,
    /// Model coordinate names (length n), input names (m), contact names (nc).
    pub coordinate_names: Vec<String>,
    pub input_names: Vec<String>,
    pub contact_names: Vec<String>,
    /// Friction directions per contact (2 planar, 4 spatial: [+x, +y, −x, −y] or [+x, −x]).
    pub friction_directions: usize,
    /// Knot times t_k (length N), t_0 = 0.
    pub times: Vec<f64>,
    /// Time steps h_k (length N−1).
    pub time_steps: Vec<f64>,
    /// Configurations q_k (N × n).
    pub q: Vec<Vec<f64>>,
    /// Velocities at the knots (N × n): v_0 at knot 0, (q_k − q_{k−1})/h_{k−1} after.
    pub v: Vec<Vec<f64>>,
    /// Inputs u_k per interval (N−1 × m).
    pub u: Vec<Vec<f64>>,
    /// Normal impulses c_k,i (N−1 × nc).
    pub normal_impulse: Vec<Vec<f64>>,
    /// Friction impulses β_k,i (N−1 × nc × nd).
    pub friction_impulse: Vec<Vec<Vec<f64>>>,
    /// Signed distance φ_i(q_k) at every knot (N × nc); the normal impulse of interval k is
    /// complementary to the distance at knot k + 1.
    pub signed_distance: Vec<Vec<f64>>,
    /// World position of every contact point at every knot (N × nc).
    pub contact_positions: Vec<Vec<[f64; 3]>>,
    /// Slacks per interval (N−1 × slacks per interval: 1, or 3·nc in per-contact mode; in
    /// penalty mode 1, the largest of the interval's three complementarity product sums).
    pub slack: Vec<Vec<f64>>,
    /// Largest slack value (at least 0: Ipopt's bound relaxation leaves slacks at −1e-8); in
    /// penalty mode the largest interval's product sum.
    pub max_slack: f64,
    /// Where the largest slack sits (None without slacks).
    pub slack_peak: Option<super::SlackPeak>,
    /// The problem's `slack.tolerance`: the largest slack of a solved plan.
    pub slack_tolerance: f64,
    /// Largest contact complementarity residual Σ_i max(c, 0)·max(φ, 0) over intervals (the
    /// clipped c·φ of SPEC.md). ηᵀβ and ψ(μc − eᵀβ) are not reported: ψ and η are
    /// undetermined in flight and stick, and their rows are covered by the slack.
    pub max_complementarity: f64,
    /// Largest constraint-row violation at the point Ipopt returned.
    pub max_constraint_violation: f64,
    /// The most violated rows at that point, worst first (at most
    /// [`Solution::WORST_ROWS`], only rows violated by more than 1e-6: Ipopt's bound
    /// relaxation leaves 1e-8 on solved points).
    pub worst_rows: Vec<super::RowViolation>,
    /// Slack weight α of the last solve (the problem's, or raised by `[slack] target`).
    pub slack_weight: f64,
    /// Ipopt solves made (more than 1 with `[slack] target`); iterations and times are their
    /// sums.
    pub solves: usize,
    /// Every start of a multi-start solve (empty for one start); this solution is the best.
    pub starts: Vec<super::StartRecord>,
    /// Which of `starts` this solution is.
    pub best_start: usize,
}

impl Solution {
    /// This solution as a warm start (its knot times, configurations and inputs), as a
    /// `trajectory.csv` of it would give; `source` names it in messages.
    pub fn warm_start(&self, source: std::path::PathBuf) -> crate::problem::WarmStart {
        crate::problem::WarmStart {
            source,
            times: self.times.clone(),
            q: self.q.clone(),
            u: self.u.clone(),
        }
    }

    /// How many of the most violated rows a solution keeps.
    pub const WORST_ROWS: usize = 5;

    /// Whether this solution is solved ([`super::SolveVerdict`]: Ipopt's optimum with every
    /// slack within `slack.tolerance`).
    pub fn verdict(&self) -> super::SolveVerdict {
        super::SolveVerdict::new(self.status, self.max_slack, self.slack_tolerance)
    }
}
