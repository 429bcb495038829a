//! Where each variable and constraint row lives in the NLP vectors.
//!
//! Variables, in this order (knots k = 0..N−1, intervals j = 0..N−2, 0-based):
//! all q_k (n each), v_0 (n), all h_j, all u_j (m each), then per interval j the contact
//! block [c (nc), β (nc·nd, contact-major), ψ (nc), η (nc·nd)], then the loop impulses γ_j
//! (nl each), then the slacks (1 per interval, or 3·nc per interval in per-contact mode,
//! ordered contact-major as [ηᵀβ, c·φ, ψ·(μc − eᵀβ)]; none in penalty mode), then with a Galerkin integrator of
//! degree s the interior control points q_j^1 … q_j^{s−1} of every interval (n each).
//!
//! Constraint rows: per interval j, the dynamics rows (n rows: the first step for j = 0, the
//! DEL equation at knot j after, or eq. (1) at knot j with `Integrator::Euler`; all holding
//! J(q_{j+1})ᵀλ_j), then the rows each block kind owns in every interval ([`IntervalRows`],
//! declared in the kind's file, in the kinds' list order: loop closure a(q_{j+1}) (nl),
//! tangential velocity (nc·nd), non-penetration φ(q_{j+1}) (nc), friction cone (nc),
//! complementarity (3, or 3·nc per contact, none in penalty mode)); then after all intervals: N−2 equal-step rows
//! (free steps only), the loop closure at q_0 (nl), and the rows of the problem file's
//! constraints (`problem::constraints`), in their order.

use std::ops::Range;

use crate::problem::SlackMode;

/// The per-knot sizes a layout is built from.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Dims {
    /// Coordinates n.
    pub n: usize,
    /// Inputs m.
    pub m: usize,
    /// Contacts nc.
    pub nc: usize,
    /// Friction directions per contact nd.
    pub nd: usize,
    /// Loop-closure constraints nl.
    pub nl: usize,
    /// Interior control points per interval: s − 1 for a Galerkin integrator of degree s,
    /// 0 for the midpoint rule and Euler.
    pub interior: usize,
}

/// The rows one block kind owns in every interval, after the dynamics rows.
#[derive(Debug, Clone, Copy)]
pub struct IntervalRows {
    /// The owning kind's name (its `NAME`), by which its blocks find their rows.
    pub kind: &'static str,
    /// Rows per interval.
    pub count: usize,
    /// Whether they are equalities (g = 0) or inequalities (g ≥ 0).
    pub equality: bool,
    /// The name of its row `local` (0..count) of interval j, for messages.
    pub name: fn(&Layout, usize, usize, EntryNames) -> String,
}

/// Sizes and offsets of the variable vector and the constraint rows.
#[derive(Debug, Clone)]
pub struct Layout {
    /// Coordinates n.
    pub n: usize,
    /// Inputs m.
    pub m: usize,
    /// Contacts nc.
    pub nc: usize,
    /// Friction directions per contact nd.
    pub nd: usize,
    /// Loop-closure constraints nl.
    pub nl: usize,
    /// Interior control points per interval (s − 1 for a Galerkin integrator of degree s).
    pub interior: usize,
    /// Knots N.
    pub knots: usize,
    /// Slack mode.
    pub slack_mode: SlackMode,
    /// Whether the N−2 equal-step rows are present.
    pub equal_steps: bool,
    /// The label of each row of the problem file's constraints, in order.
    pub constraint_rows: Vec<String>,
    /// The rows each kind owns per interval after the dynamics rows, in row order.
    pub interval_rows: Vec<IntervalRows>,
}

impl Layout {
    /// A layout for these sizes; `constraint_rows` labels the rows of the problem file's
    /// constraints, `interval_rows` the rows the block kinds own in every interval.
    pub fn new(
        dims: Dims,
        knots: usize,
        slack_mode: SlackMode,
        equal_steps: bool,
        constraint_rows: Vec<String>,
        interval_rows: Vec<IntervalRows>,
    ) -> Layout {
        let Dims {
            n,
            m,
            nc,
            nd,
            nl,
            interior,
        } = dims;
        Layout {
            n,
            m,
            nc,
            nd,
            nl,
            interior,
            knots,
            slack_mode,
            equal_steps,
            constraint_rows,
            interval_rows,
        }
    }

    /// Number of intervals N−1.
    pub fn intervals(&self) -> usize {
        self.knots - 1
    }

    /// Contact variables per interval: nc·(2 + 2·nd).
    fn contact_block(&self) -> usize {
        self.nc * (2 + 2 * self.nd)
    }

    /// Slack variables per interval: 1, 3·nc per contact, or none in penalty mode.
    pub fn slacks_per_interval(&self) -> usize {
        match self.slack_mode {
            SlackMode::PerInterval => 1,
            SlackMode::PerContact => 3 * self.nc,
            SlackMode::Penalty => 0,
        }
    }

    fn v0_offset(&self) -> usize {
        self.knots * self.n
    }
    fn h_offset(&self) -> usize {
        self.v0_offset() + self.n
    }
    fn u_offset(&self) -> usize {
        self.h_offset() + self.intervals()
    }
    fn contact_offset(&self) -> usize {
        self.u_offset() + self.intervals() * self.m
    }
    fn gamma_offset(&self) -> usize {
        self.contact_offset() + self.intervals() * self.contact_block()
    }
    fn slack_offset(&self) -> usize {
        self.gamma_offset() + self.intervals() * self.nl
    }

    fn interior_offset(&self) -> usize {
        self.slack_offset() + self.intervals() * self.slacks_per_interval()
    }

    /// Total number of variables.
    pub fn num_variables(&self) -> usize {
        self.interior_offset() + self.intervals() * self.interior * self.n
    }

    /// Configuration q_k (length n).
    pub fn q(&self, k: usize) -> Range<usize> {
        k * self.n..(k + 1) * self.n
    }
    /// Initial velocity v_0 (length n).
    pub fn v0(&self) -> Range<usize> {
        self.v0_offset()..self.v0_offset() + self.n
    }
    /// Time step h_j.
    pub fn h(&self, j: usize) -> usize {
        self.h_offset() + j
    }
    /// Input u_j (length m).
    pub fn u(&self, j: usize) -> Range<usize> {
        let a = self.u_offset() + j * self.m;
        a..a + self.m
    }
    /// Normal impulse c_{j,i}.
    pub fn c(&self, j: usize, i: usize) -> usize {
        self.contact_offset() + j * self.contact_block() + i
    }
    /// Friction impulses β_{j,i} (length nd).
    pub fn beta(&self, j: usize, i: usize) -> Range<usize> {
        let a = self.contact_offset() + j * self.contact_block() + self.nc + i * self.nd;
        a..a + self.nd
    }
    /// ψ_{j,i}.
    pub fn psi(&self, j: usize, i: usize) -> usize {
        self.contact_offset() + j * self.contact_block() + self.nc * (1 + self.nd) + i
    }
    /// η_{j,i} (length nd).
    pub fn eta(&self, j: usize, i: usize) -> Range<usize> {
        let a = self.contact_offset()
            + j * self.contact_block()
            + self.nc * (2 + self.nd)
            + i * self.nd;
        a..a + self.nd
    }
    /// All contact variables of interval j.
    pub fn contact_vars(&self, j: usize) -> Range<usize> {
        let a = self.contact_offset() + j * self.contact_block();
        a..a + self.contact_block()
    }
    /// Loop-closure impulses γ_j (length nl).
    pub fn gamma(&self, j: usize) -> Range<usize> {
        let a = self.gamma_offset() + j * self.nl;
        a..a + self.nl
    }
    /// Slacks of interval j (length `slacks_per_interval`).
    pub fn slack(&self, j: usize) -> Range<usize> {
        let a = self.slack_offset() + j * self.slacks_per_interval();
        a..a + self.slacks_per_interval()
    }
    /// All slack variables.
    pub fn slacks(&self) -> Range<usize> {
        self.slack_offset()..self.interior_offset()
    }
    /// Interior control point q_j^{ν+1} of interval j, ν = 0..interior (length n): the
    /// configuration at t_j + d_{ν+1}·h_j of a Galerkin integrator.
    pub fn interior(&self, j: usize, nu: usize) -> Range<usize> {
        let a = self.interior_offset() + (j * self.interior + nu) * self.n;
        a..a + self.n
    }
    /// All interior control points of interval j (length interior·n).
    pub fn interior_points(&self, j: usize) -> Range<usize> {
        let a = self.interior_offset() + j * self.interior * self.n;
        a..a + self.interior * self.n
    }

    /// Rows per interval.
    pub fn rows_per_interval(&self) -> usize {
        self.n + self.interval_rows.iter().map(|r| r.count).sum::<usize>()
    }
    fn interval_row(&self, j: usize) -> usize {
        j * self.rows_per_interval()
    }
    /// Dynamics rows of interval j (first step for j = 0, DEL at knot j after).
    pub fn dynamics_rows(&self, j: usize) -> Range<usize> {
        let a = self.interval_row(j);
        a..a + self.n
    }
    /// The rows kind `kind` owns in interval j ([`IntervalRows`]; empty if it owns none).
    pub fn rows_of(&self, kind: &str, j: usize) -> Range<usize> {
        let mut a = self.interval_row(j) + self.n;
        for rows in &self.interval_rows {
            if rows.kind == kind {
                return a..a + rows.count;
            }
            a += rows.count;
        }
        a..a
    }
    /// The owner of local row `local` (≥ n) of an interval and the row's index within it.
    fn interval_rows_at(&self, local: usize) -> Option<(&IntervalRows, usize)> {
        let mut local = local.checked_sub(self.n)?;
        for rows in &self.interval_rows {
            if local < rows.count {
                return Some((rows, local));
            }
            local -= rows.count;
        }
        None
    }
    /// Equal-step row h_j − h_{j+1} = 0, j = 0..N−3 (only when steps are free).
    pub fn equal_step_row(&self, j: usize) -> usize {
        self.intervals() * self.rows_per_interval() + j
    }
    fn num_equal_step_rows(&self) -> usize {
        if self.equal_steps {
            self.knots.saturating_sub(2)
        } else {
            0
        }
    }
    /// Loop-closure rows a(q_0) at the first knot.
    pub fn first_loop_rows(&self) -> Range<usize> {
        let a = self.intervals() * self.rows_per_interval() + self.num_equal_step_rows();
        a..a + self.nl
    }
    /// Row r of the problem file's constraints (in `constraint_rows` order).
    pub fn constraint_row(&self, r: usize) -> usize {
        self.first_loop_rows().end + r
    }
    /// Total number of constraint rows.
    pub fn num_constraints(&self) -> usize {
        self.constraint_row(self.constraint_rows.len())
    }

    /// Whether row `r` of the model's own rows is an equality (g = 0) or an inequality
    /// (g ≥ 0). The problem file's constraints carry their own bounds.
    pub fn is_equality(&self, r: usize) -> bool {
        let per = self.intervals() * self.rows_per_interval();
        if r >= per {
            return true;
        }
        self.interval_rows_at(r % self.rows_per_interval())
            .is_none_or(|(rows, _)| rows.equality)
    }
}

/// The names a layout's entries are printed with: coordinates, inputs and contacts of the
/// robot, in NLP order.
#[derive(Debug, Clone, Copy)]
pub struct EntryNames<'a> {
    /// Coordinate names (length n).
    pub coordinates: &'a [String],
    /// Input names (length m).
    pub inputs: &'a [String],
    /// Contact names (length nc).
    pub contacts: &'a [String],
}

impl EntryNames<'_> {
    /// The name of coordinate i.
    pub fn coordinate(&self, i: usize) -> String {
        self.coordinates
            .get(i)
            .cloned()
            .unwrap_or_else(|| format!("q{i}"))
    }
    /// The name of input i.
    pub fn input(&self, i: usize) -> String {
        self.inputs
            .get(i)
            .cloned()
            .unwrap_or_else(|| format!("u{i}"))
    }
    /// The name of contact i.
    pub fn contact(&self, i: usize) -> String {
        self.contacts
            .get(i)
            .cloned()
            .unwrap_or_else(|| format!("contact {i}"))
    }
}

/// Names of the per-contact slacks and complementarity rows, in their layout order.
pub const COMPLEMENTARITY_NAMES: [&str; 3] = ["eta·beta", "c·phi", "psi·(mu c - e'beta)"];

impl Layout {
    /// What variable `v` is, e.g. "q base_x, knot 19" or "c front_left_foot, interval 19"
    /// (knots and intervals counted from 0).
    pub fn variable_name(&self, v: usize, names: EntryNames) -> String {
        let (n, nc, nd) = (self.n, self.nc, self.nd);
        if v < self.v0_offset() {
            return format!("q {}, knot {}", names.coordinate(v % n), v / n);
        }
        if v < self.h_offset() {
            return format!("v0 {}", names.coordinate(v - self.v0_offset()));
        }
        if v < self.u_offset() {
            return format!("h, interval {}", v - self.h_offset());
        }
        if v < self.contact_offset() {
            let local = v - self.u_offset();
            return format!(
                "u {}, interval {}",
                names.input(local % self.m),
                local / self.m
            );
        }
        if v < self.gamma_offset() {
            let local = v - self.contact_offset();
            let (j, r) = (local / self.contact_block(), local % self.contact_block());
            let (what, i, d) = if r < nc {
                ("c", r, None)
            } else if r < nc * (1 + nd) {
                ("beta", (r - nc) / nd, Some((r - nc) % nd))
            } else if r < nc * (2 + nd) {
                ("psi", r - nc * (1 + nd), None)
            } else {
                let e = r - nc * (2 + nd);
                ("eta", e / nd, Some(e % nd))
            };
            let dir = d.map_or(String::new(), |d| format!(" direction {d}"));
            return format!("{what} {}{dir}, interval {j}", names.contact(i));
        }
        if v < self.slack_offset() {
            let local = v - self.gamma_offset();
            return format!("gamma {}, interval {}", local % self.nl, local / self.nl);
        }
        if v >= self.interior_offset() {
            let local = v - self.interior_offset();
            let (point, c) = (local / n, local % n);
            return format!(
                "q {}, interval {} interior point {}",
                names.coordinate(c),
                point / self.interior,
                point % self.interior + 1
            );
        }
        let local = v - self.slack_offset();
        // Penalty mode has no slack variables (`per` is 0): no index reaches here.
        let per = self.slacks_per_interval().max(1);
        let j = local / per;
        match self.slack_mode {
            SlackMode::PerInterval | SlackMode::Penalty => format!("s, interval {j}"),
            SlackMode::PerContact => {
                let r = local % per;
                format!(
                    "s {} {}, interval {j}",
                    COMPLEMENTARITY_NAMES[r % 3],
                    names.contact(r / 3)
                )
            }
        }
    }

    /// What constraint row `r` is, e.g. "DEL base_x, knot 19" (knots and intervals counted
    /// from 0; the dynamics rows of interval j > 0 hold the DEL equation at knot j).
    pub fn row_name(&self, r: usize, names: EntryNames) -> String {
        let per = self.intervals() * self.rows_per_interval();
        if r < per {
            let (j, local) = (r / self.rows_per_interval(), r % self.rows_per_interval());
            if local < self.n {
                let c = names.coordinate(local);
                return if j == 0 {
                    format!("first step {c}")
                } else {
                    format!("DEL {c}, knot {j}")
                };
            }
            return match self.interval_rows_at(local) {
                Some((rows, local)) => (rows.name)(self, local, j, names),
                None => format!("row {r}"),
            };
        }
        let local = r - per;
        if local < self.num_equal_step_rows() {
            return format!("equal steps h{local} = h{}", local + 1);
        }
        let local = local - self.num_equal_step_rows();
        if local < self.nl {
            return format!("loop closure {local}, knot 0");
        }
        match self.constraint_rows.get(local - self.nl) {
            Some(label) => label.clone(),
            None => format!("row {r}"),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::transcription::blocks::VectorKind;

    fn dims(n: usize, m: usize, nc: usize, nd: usize, nl: usize) -> Dims {
        Dims {
            n,
            m,
            nc,
            nd,
            nl,
            interior: 0,
        }
    }

    /// A layout with the rows the block kinds declare.
    fn layout(
        dims: Dims,
        knots: usize,
        slack_mode: SlackMode,
        equal_steps: bool,
        constraint_rows: Vec<String>,
    ) -> Layout {
        let rows = VectorKind::interval_rows(&dims, slack_mode);
        Layout::new(dims, knots, slack_mode, equal_steps, constraint_rows, rows)
    }

    /// spring-flamingo-walk (docs/reference-problems.md): 954 variables, 695 constraints (672 + 23).
    #[test]
    fn spring_flamingo_sizes_match_spec() {
        let l = layout(
            dims(9, 4, 4, 2, 0),
            25,
            SlackMode::PerInterval,
            true,
            vec![],
        );
        assert_eq!(l.num_variables(), 954);
        assert_eq!(l.num_constraints(), 695);
        assert_eq!(l.rows_per_interval() * 24, 672);
    }

    /// littledog-step (docs/reference-problems.md): 2124 variables, 1333 constraints (1305 + 28).
    #[test]
    fn littledog_sizes_match_spec() {
        let l = layout(
            dims(18, 12, 4, 4, 0),
            30,
            SlackMode::PerInterval,
            true,
            vec![],
        );
        assert_eq!(l.num_variables(), 2124);
        assert_eq!(l.num_constraints(), 1333);
    }

    #[test]
    fn every_variable_and_row_has_exactly_one_owner() {
        let constraint_rows = vec!["position".to_string(), "velocity".to_string()];
        let l = layout(
            dims(3, 2, 2, 4, 1),
            5,
            SlackMode::PerContact,
            true,
            constraint_rows,
        );
        let mut owner = vec![0usize; l.num_variables()];
        let mut mark = |r: Range<usize>| r.for_each(|i| owner[i] += 1);
        for k in 0..l.knots {
            mark(l.q(k));
        }
        mark(l.v0());
        for j in 0..l.intervals() {
            mark(l.h(j)..l.h(j) + 1);
            mark(l.u(j));
            for i in 0..l.nc {
                mark(l.c(j, i)..l.c(j, i) + 1);
                mark(l.beta(j, i));
                mark(l.psi(j, i)..l.psi(j, i) + 1);
                mark(l.eta(j, i));
            }
            mark(l.gamma(j));
            mark(l.slack(j));
        }
        assert!(owner.iter().all(|&c| c == 1));

        let mut rows = vec![0usize; l.num_constraints()];
        let mut mark = |r: Range<usize>| r.for_each(|i| rows[i] += 1);
        for j in 0..l.intervals() {
            mark(l.dynamics_rows(j));
            for owned in &l.interval_rows {
                mark(l.rows_of(owned.kind, j));
            }
        }
        for j in 0..l.knots - 2 {
            mark(l.equal_step_row(j)..l.equal_step_row(j) + 1);
        }
        mark(l.first_loop_rows());
        mark(l.constraint_row(0)..l.constraint_row(2));
        assert!(rows.iter().all(|&c| c == 1));
        // Interval 1's rows in order: dynamics (3), loop closure (1), tangential (2·4),
        // distance (2), cone (2), complementarity (3·2).
        let kinds: Vec<(&str, usize)> = l.interval_rows.iter().map(|r| (r.kind, r.count)).collect();
        assert_eq!(
            kinds,
            [
                ("LoopClosure", 1),
                ("TangentialRate", 8),
                ("Distance", 2),
                ("FrictionCone", 2),
                ("Complementarity", 6)
            ]
        );
        let start = l.rows_per_interval();
        assert_eq!(l.rows_per_interval(), 22);
        assert_eq!(l.rows_of("TangentialRate", 1), start + 4..start + 12);
        assert!(l.is_equality(start + 4 + 4));
        assert!(!l.is_equality(start + 14 + 1));
        assert!(l.is_equality(l.first_loop_rows().start));
        let names = EntryNames {
            coordinates: &["x".into(), "z".into(), "theta".into()],
            inputs: &[],
            contacts: &["left".into(), "right".into()],
        };
        let name = |r| l.row_name(r, names);
        assert_eq!(name(start + 1), "DEL z, knot 1");
        assert_eq!(name(start + 3), "loop closure 0, knot 2");
        assert_eq!(
            name(start + 4 + 5),
            "tangential velocity right direction 1, interval 1"
        );
        assert_eq!(name(start + 13), "phi right, knot 2");
        assert_eq!(name(start + 14), "friction cone left, interval 1");
        assert_eq!(name(start + 16 + 4), "s - c·phi right, interval 1");
    }

    /// A Galerkin layout (two interior points per interval): the interior points are the last
    /// variables, every variable and row has one owner, and the interior rows (stationarity,
    /// n per point; φ, nc per point) follow the dynamics rows and the distance rows.
    #[test]
    fn galerkin_interior_points_and_rows_have_one_owner() {
        let galerkin = Dims {
            interior: 2,
            ..dims(3, 2, 2, 2, 0)
        };
        let l = layout(galerkin, 4, SlackMode::PerInterval, false, vec![]);
        let plain = layout(
            dims(3, 2, 2, 2, 0),
            4,
            SlackMode::PerInterval,
            false,
            vec![],
        );
        assert_eq!(l.num_variables(), plain.num_variables() + 3 * 2 * 3);
        assert_eq!(l.interior(0, 0).start, plain.num_variables());
        assert_eq!(l.interior(2, 1).end, l.num_variables());
        assert_eq!(
            l.interior_points(1),
            l.interior(1, 0).start..l.interior(1, 1).end
        );
        assert_eq!(
            l.rows_per_interval(),
            plain.rows_per_interval() + 2 * 3 + 2 * 2
        );
        let mut rows = vec![0usize; l.num_constraints()];
        for j in 0..l.intervals() {
            l.dynamics_rows(j).for_each(|r| rows[r] += 1);
            for owned in &l.interval_rows {
                l.rows_of(owned.kind, j).for_each(|r| rows[r] += 1);
            }
        }
        assert!(rows.iter().all(|&c| c == 1));
        let stationarity = l.rows_of("GalerkinForce", 1);
        assert_eq!(stationarity.start, l.dynamics_rows(1).end);
        assert!(l.is_equality(stationarity.start));
        let phi = l.rows_of("InteriorDistance", 1);
        assert_eq!(phi.start, l.rows_of("Distance", 1).end);
        assert!(!l.is_equality(phi.start));
        let names = EntryNames {
            coordinates: &["x".into(), "z".into(), "theta".into()],
            inputs: &[],
            contacts: &["left".into(), "right".into()],
        };
        assert_eq!(
            l.row_name(stationarity.start + 4, names),
            "interior stationarity z, interval 1 interior point 2"
        );
        assert_eq!(
            l.row_name(phi.start + 3, names),
            "phi right, interval 1 interior point 2"
        );
        assert_eq!(
            l.variable_name(l.interior(2, 1).start + 2, names),
            "q theta, interval 2 interior point 2"
        );
    }
}
