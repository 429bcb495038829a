//! What a solve returns: the trajectory by knot, with names, and the numbers a summary needs;
//! read off Ipopt's final iterate ([`Solution::read_off`]).

use super::blocks::complementarity_penalty::{interval_products, interval_slack};
use super::{MechanicsDerivatives, Transcription};
use crate::contact::{Own, Partner, Products, cone, gap_product};
use crate::ipopt::{self, Status};
use crate::problem::{ProblemSpec, SlackMode};

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
    /// Each interval's impulse per contact as a world vector at the point where it acts
    /// (N−1 × nc, [`crate::contact::interval_world_impulses`]).
    pub world_impulse: Vec<Vec<[f64; 3]>>,
    /// Slacks per interval (N−1 × slacks per interval: 1, or 3·nc in per-contact mode; in
    /// penalty mode 1, the largest of the interval's three complementarity product sums).
    pub slack: Vec<Vec<f64>>,
    /// Largest interval slack (at least 0): the larger of the interval's slack variables
    /// (Ipopt's bound relaxation leaves them at −1e-8) and of its complementarity product sums
    /// with factors at or below [`crate::contact::FACTOR_FLOOR`] zeroed; in penalty mode the
    /// product sums alone.
    pub max_slack: f64,
    /// Where the largest slack sits (None without slacks).
    pub slack_peak: Option<super::SlackPeak>,
    /// The problem's `slack.tolerance`: the largest slack of a solved plan.
    pub slack_tolerance: f64,
    /// Largest contact complementarity residual Σ_i max(c, 0)·max(φ, 0) over intervals (the
    /// clipped c·φ, docs/reference-problems.md). ηᵀβ and ψ(μc − eᵀβ) are not reported: ψ and η are
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
    /// The mode-fixed re-solve that ended the solve (`[slack] polish`), kept or not.
    #[serde(default)]
    pub polish: Option<super::PolishRecord>,
    /// Each Ipopt solve of the slack continuation, in order (empty without `[slack] target`
    /// or `homotopy`; the polish is not one of them: `polish`); `solves` is their number.
    #[serde(default)]
    pub continuation: Vec<super::ContinuationSolve>,
    /// A passive problem's solve from its simulation, kept or not
    /// ([`super::passive::SimulationStart`]).
    #[serde(default)]
    pub simulation_start: Option<super::SimulationStart>,
    /// The grid continuation that led to this plan, coarsest level first, this plan's level
    /// last (empty when it was solved on its own grid alone).
    #[serde(default)]
    pub levels: Vec<GridLevel>,
    /// A finer level's solve with the contact modes of the level below fixed, kept or not
    /// ([`super::CarriedModes`]).
    #[serde(default)]
    pub carried_modes: Option<super::CarriedModes>,
}

/// One level of a grid continuation: a solve on a coarser grid whose plan started the next.
#[derive(Debug, Clone, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct GridLevel {
    /// Knots N of the level.
    pub knots: usize,
    /// Its verdict.
    pub verdict: super::SolveVerdict,
    pub objective: f64,
    pub max_slack: f64,
    pub iterations: usize,
    pub wall_time_s: f64,
    /// The largest |q(t) − q_previous(t)| over the previous level's knot times (q of this
    /// level interpolated linearly between its knots) and coordinates; None on the first.
    pub max_q_difference: Option<f64>,
    /// Whether its plan is the solve with the contact modes of the level below fixed
    /// ([`super::CarriedModes`]) rather than the relaxed solve; None where that solve was not
    /// made.
    #[serde(default)]
    pub carried_modes_kept: Option<bool>,
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
            forces: Vec::new(),
        }
    }

    /// [`Solution::warm_start`] with its contact impulses as forces (each interval's
    /// impulses divided by its step), for a start on another grid of the same problem.
    pub fn warm_start_with_forces(&self, source: std::path::PathBuf) -> crate::problem::WarmStart {
        let forces = self
            .normal_impulse
            .iter()
            .zip(&self.friction_impulse)
            .zip(&self.time_steps)
            .map(|((normal, friction), &h)| {
                normal
                    .iter()
                    .zip(friction)
                    .map(|(&c, beta)| {
                        std::iter::once(c)
                            .chain(beta.iter().copied())
                            .map(|impulse| impulse / h)
                            .collect()
                    })
                    .collect()
            })
            .collect();
        crate::problem::WarmStart {
            forces,
            ..self.warm_start(source)
        }
    }

    /// Add `other`'s Ipopt work (iterations, wall, callback and Ipopt time, the callbacks'
    /// split) to this solution's: an answer's cost is that of every solve that led to it.
    pub(crate) fn add_work(&mut self, other: &Solution) {
        self.iterations += other.iterations;
        self.wall_time_s += other.wall_time_s;
        self.callback_time_s += other.callback_time_s;
        self.callback_split = self.callback_split.plus(&other.callback_split);
        self.ipopt_time_s += other.ipopt_time_s;
    }

    /// The tolerance `[slack] tied_tolerances` loosened for the last solve of its
    /// continuation, if it did (the solve ended loose).
    pub fn loose_tol(&self) -> Option<f64> {
        self.continuation.last().and_then(|c| c.tied_tol)
    }

    /// How many of the most violated rows a solution keeps.
    pub const WORST_ROWS: usize = 5;

    /// Whether this solution is solved ([`super::SolveVerdict`]: Ipopt's optimum with every
    /// slack within `slack.tolerance`).
    pub fn verdict(&self) -> super::SolveVerdict {
        super::SolveVerdict::new(self.status, self.max_slack, self.slack_tolerance)
    }
}

/// Signed distance φ_i(q) of every contact at q.
fn distances<M: MechanicsDerivatives>(t: &Transcription<M>, q: &[f64]) -> Vec<f64> {
    (0..t.layout().nc)
        .map(|i| crate::contact::distance(t.mechanics(), &t.context().contact, i, q))
        .collect()
}

impl Solution {
    /// The solution at Ipopt's final iterate of `t` (`report`): the trajectory by knot, the
    /// contact quantities, slack and its peak, violations and the worst rows, named.
    pub(super) fn read_off<M: MechanicsDerivatives>(
        t: &Transcription<M>,
        spec: &ProblemSpec,
        report: &ipopt::SolveReport,
    ) -> Solution {
        let l = t.layout();
        let x = &report.x;
        let q: Vec<Vec<f64>> = (0..l.knots).map(|k| x[l.q(k)].to_vec()).collect();
        let time_steps: Vec<f64> = (0..l.intervals()).map(|j| x[l.h(j)]).collect();
        let times: Vec<f64> = match time_steps.first() {
            // Equal steps (fixed, or free steps that ended equal): t_k = k·h, in decimal.
            Some(&h) if time_steps.iter().all(|&s| s == h) => (0..l.knots)
                .map(|k| crate::files::trajectory_csv::knot_time(k, h))
                .collect(),
            _ => {
                let mut times = vec![0.0];
                for h in &time_steps {
                    times.push(times.last().copied().unwrap_or(0.0) + h);
                }
                times
            }
        };
        let mut v = vec![x[l.v0()].to_vec()];
        for j in 0..l.intervals() {
            v.push(
                q[j + 1]
                    .iter()
                    .zip(&q[j])
                    .map(|(b, a)| (b - a) / time_steps[j])
                    .collect(),
            );
        }
        let mut normal_impulse = Vec::new();
        let mut friction_impulse = Vec::new();
        let mut slack = Vec::new();
        let mut max_complementarity = 0.0_f64;
        // φ at every knot; the impulses of interval j are complementary to φ at knot j + 1.
        let signed_distance: Vec<Vec<f64>> = q.iter().map(|qk| distances(t, qk)).collect();
        for j in 0..l.intervals() {
            let phi = &signed_distance[j + 1];
            let c: Vec<f64> = (0..l.nc).map(|i| x[l.c(j, i)]).collect();
            let beta: Vec<Vec<f64>> = (0..l.nc).map(|i| x[l.beta(j, i)].to_vec()).collect();
            // Report the slack and the clipped c·φ. The other two products (ηᵀβ and
            // ψ(μc − eᵀβ)) are not meaningful per contact: ψ and η are undetermined in flight
            // and stick and drift to 1e5–1e8, where Ipopt's 1e-8 bound relaxation shows as
            // O(1e-2) terms that cancel within a row.
            let contact_gap: f64 = (0..l.nc)
                .map(|i| gap_product(c[i].max(0.0), phi[i].max(0.0)))
                .sum();
            max_complementarity = max_complementarity.max(contact_gap);
            normal_impulse.push(c);
            friction_impulse.push(beta);
            // A slack is ≥ 0; Ipopt's bound relaxation leaves it at −1e-8 where it is 0.
            slack.push(x[l.slack(j)].iter().map(|s| s.max(0.0)).collect());
        }
        let contact_names: Vec<String> = spec.contacts.iter().map(|c| c.name.clone()).collect();
        // The slack a plan relies on: an interval's slack variables, and the sums of its
        // complementarity products with noise-level factors zeroed (`Products::clipped`),
        // whichever is larger. The rows bound the raw sums over the contacts, where a flight
        // foot's product of a huge ψ or η with a factor at Ipopt's relaxed bound −1e-8 can
        // cancel another contact's real one; penalty mode has no slack variables, and its
        // interval slack is the one the elastic form would hold there.
        let products = interval_products(l, t.context(), x, &signed_distance);
        let product_peak = product_peak(&products, &contact_names);
        let (max_slack, slack_peak) = if l.slack_mode == SlackMode::Penalty {
            slack = products.iter().map(|p| vec![interval_slack(p)]).collect();
            (product_peak.as_ref().map_or(0.0, |p| p.slack), product_peak)
        } else {
            let variables = x[l.slacks()].iter().fold(0.0_f64, |a, &b| a.max(b));
            let peak = slack_peak(t, x, &signed_distance, &contact_names);
            match product_peak {
                Some(p) if p.slack > variables => {
                    // Hidden: the slack variables pass the tolerance, the products do not.
                    let hidden = variables <= spec.slack_tolerance;
                    (
                        p.slack,
                        Some(crate::transcription::SlackPeak { hidden, ..p }),
                    )
                }
                _ => (variables, peak),
            }
        };
        let contact_positions: Vec<Vec<[f64; 3]>> = q
            .iter()
            .map(|qk| {
                (0..l.nc)
                    .map(|i| t.mechanics().contact_position(i, qk))
                    .collect()
            })
            .collect();
        let world_impulse = crate::contact::interval_world_impulses(
            &t.context().contact,
            &contact_positions,
            &normal_impulse,
            &friction_impulse,
        );
        let (row_violations, _) = t.row_violations(x);
        let max_constraint_violation = row_violations.iter().fold(0.0_f64, |a, &b| a.max(b));
        let coordinate_names = t.mechanics().coordinate_names();
        let input_names = t.mechanics().input_names();
        let worst_rows = worst_rows(
            l,
            &row_violations,
            crate::transcription::EntryNames {
                coordinates: &coordinate_names,
                inputs: &input_names,
                contacts: &contact_names,
            },
        );
        Solution {
            status: report.status,
            objective: report.objective,
            objective_terms: t.objective_terms(x),
            iterations: report.iterations,
            wall_time_s: report.wall_time_s,
            callback_time_s: report.callback_time_s,
            ipopt_time_s: report.ipopt_time_s,
            callback_split: report.callback_split,
            size: t.size(),
            coordinate_names,
            input_names,
            contact_names,
            friction_directions: l.nd,
            times,
            time_steps,
            u: (0..l.intervals()).map(|j| x[l.u(j)].to_vec()).collect(),
            q,
            v,
            normal_impulse,
            friction_impulse,
            signed_distance,
            contact_positions,
            world_impulse,
            slack,
            max_slack,
            slack_peak,
            slack_tolerance: spec.slack_tolerance,
            max_complementarity,
            max_constraint_violation,
            worst_rows,
            slack_weight: t.slack_weight(),
            solves: 1,
            starts: Vec::new(),
            best_start: 0,
            polish: None,
            carried_modes: None,
            continuation: Vec::new(),
            simulation_start: None,
            levels: Vec::new(),
        }
    }
}

/// Where the largest slack of x sits: its interval, and the contact it relaxes (its own in
/// per-contact mode; else the contact with the largest of c·φ with both factors clipped at 0,
/// ηᵀβ and ψ(μc − eᵀβ) of that interval alone, when one is positive).
fn slack_peak<M: MechanicsDerivatives>(
    t: &Transcription<M>,
    x: &[f64],
    distance: &[Vec<f64>],
    contacts: &[String],
) -> Option<crate::transcription::SlackPeak> {
    let l = t.layout();
    let per = l.slacks_per_interval();
    let (index, slack) = x[l.slacks()].iter().copied().enumerate().fold(
        None,
        |best: Option<(usize, f64)>, (i, s)| match best {
            Some((_, b)) if s <= b || s.is_nan() => best,
            _ => Some((i, s)),
        },
    )?;
    let interval = index / per;
    let contact = if per > 1 {
        // Per-contact mode: three slacks per contact, in contact order.
        Some((index % per) / 3)
    } else {
        let j = interval;
        // c·φ of the clipped factors (c and φ both at Ipopt's relaxed bound −1e-8 would make
        // a positive product); ηᵀβ and ψ(μc − eᵀβ) raw, as the slack's rows have them, so an
        // interval where they are ≤ 0 names no contact.
        let product = |i: usize| {
            let own = Own {
                c: x[l.c(j, i)],
                psi: x[l.psi(j, i)],
                eta: &x[l.eta(j, i)],
            };
            let beta = &x[l.beta(j, i)];
            let mu = t.context().contact.friction[i];
            let partner = Partner {
                phi: distance[j + 1][i],
                beta,
                cone: cone(mu, own.c, beta),
            };
            let raw = Products::new(&own, &partner);
            let clipped = Products::clipped(&own, [partner]);
            clipped.gap.max(raw.eta_beta).max(raw.cone)
        };
        (0..l.nc)
            .map(|i| (i, product(i)))
            .filter(|&(_, p)| p > 0.0)
            .max_by(|a, b| a.1.total_cmp(&b.1))
            .map(|(i, _)| i)
    };
    Some(crate::transcription::SlackPeak {
        interval,
        contact: contact.and_then(|i| contacts.get(i).cloned()),
        slack: slack.max(0.0),
        hidden: false,
    })
}

/// Where the largest sum of products sits ([`interval_slack`] of each interval's products):
/// its interval and the contact with the largest product there (None when no product is
/// positive).
fn product_peak(
    products: &[Vec<[f64; 3]>],
    contacts: &[String],
) -> Option<crate::transcription::SlackPeak> {
    let (interval, slack) = products
        .iter()
        .map(|p| interval_slack(p))
        .enumerate()
        .fold(None, |best: Option<(usize, f64)>, (j, s)| match best {
            Some((_, b)) if s <= b || s.is_nan() => best,
            _ => Some((j, s)),
        })?;
    let contact = products[interval]
        .iter()
        .map(|p| p.iter().copied().fold(0.0_f64, f64::max))
        .enumerate()
        .filter(|&(_, p)| p > 0.0)
        .max_by(|a, b| a.1.total_cmp(&b.1))
        .and_then(|(i, _)| contacts.get(i).cloned());
    Some(crate::transcription::SlackPeak {
        interval,
        contact,
        slack,
        hidden: false,
    })
}

/// A row violated by at most this much is not listed among the worst rows: Ipopt relaxes
/// bounds by 1e-8 (`bound_relax_factor`), so solved points show violations of that order.
const LISTED_VIOLATION: f64 = 1e-6;

/// The most violated rows (at most [`Solution::WORST_ROWS`], each by more than
/// [`LISTED_VIOLATION`]), worst first, named as `vito check --derivatives` names them.
fn worst_rows(
    l: &crate::transcription::Layout,
    violations: &[f64],
    names: crate::transcription::EntryNames,
) -> Vec<crate::transcription::RowViolation> {
    let mut rows: Vec<usize> = (0..violations.len())
        .filter(|&r| violations[r] > LISTED_VIOLATION)
        .collect();
    rows.sort_by(|&a, &b| violations[b].total_cmp(&violations[a]).then(a.cmp(&b)));
    rows.truncate(Solution::WORST_ROWS);
    rows.into_iter()
        .map(|r| crate::transcription::RowViolation {
            row: l.row_name(r, names),
            violation: violations[r],
        })
        .collect()
}
