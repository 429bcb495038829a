//! The transcription as Ipopt's sparse NLP, with progress reporting at each iteration.

use super::Transcription;
use crate::discrete::MechanicsDerivatives;
use crate::ipopt::{IterationInfo, Nlp, Scaling};
use crate::problem::HessianMode;

/// Numbers reported after each Ipopt iteration.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Progress {
    /// Iteration count (0 is the starting point).
    pub iteration: usize,
    /// Objective at the current iterate.
    pub objective: f64,
    /// Primal infeasibility.
    pub inf_pr: f64,
    /// Dual infeasibility.
    pub inf_du: f64,
    /// Largest slack at the latest point Ipopt evaluated (Ipopt 3.11's C intermediate
    /// callback does not pass the iterate, so this is the last x seen by an evaluation); in
    /// penalty mode the largest interval's complementarity product sum
    /// ([`Transcription::max_slack`]).
    pub max_slack: f64,
}

/// A progress callback (shared, so it takes `&self`: e.g. a progress bar).
pub type ProgressFn = dyn Fn(&Progress) + Send + Sync;

/// Borrowing adapter that presents a [`Transcription`] to the solver.
pub struct TranscriptionNlp<'a, M> {
    transcription: &'a Transcription<M>,
    last_x: Vec<f64>,
    progress: Option<&'a ProgressFn>,
    scaling: Option<Scaling>,
}

impl<'a, M: MechanicsDerivatives> TranscriptionNlp<'a, M> {
    /// Wrap `transcription`; `progress` is called once per iteration.
    pub fn new(transcription: &'a Transcription<M>, progress: Option<&'a ProgressFn>) -> Self {
        TranscriptionNlp {
            last_x: transcription.initial_point().to_vec(),
            transcription,
            progress,
            scaling: None,
        }
    }

    /// Hand Ipopt this scaling (`[solver] scaling = "units"`).
    pub fn with_scaling(mut self, scaling: Option<Scaling>) -> Self {
        self.scaling = scaling;
        self
    }

    fn remember(&mut self, x: &[f64], new_x: bool) {
        if new_x || self.last_x.len() != x.len() {
            self.last_x.clear();
            self.last_x.extend_from_slice(x);
        }
    }
}

impl<M: MechanicsDerivatives> Nlp for TranscriptionNlp<'_, M> {
    fn num_variables(&self) -> usize {
        self.transcription.layout().num_variables()
    }
    fn num_constraints(&self) -> usize {
        self.transcription.layout().num_constraints()
    }
    fn variable_bounds(&self, lower: &mut [f64], upper: &mut [f64]) {
        let (l, u) = self.transcription.variable_bounds();
        lower.copy_from_slice(l);
        upper.copy_from_slice(u);
    }
    fn constraint_bounds(&self, lower: &mut [f64], upper: &mut [f64]) {
        let (l, u) = self.transcription.constraint_bounds();
        lower.copy_from_slice(l);
        upper.copy_from_slice(u);
    }
    fn initial_point(&self, x: &mut [f64]) {
        x.copy_from_slice(self.transcription.initial_point());
    }
    fn objective(&mut self, x: &[f64], new_x: bool) -> f64 {
        self.remember(x, new_x);
        self.transcription.objective(x)
    }
    fn gradient(&mut self, x: &[f64], new_x: bool, grad: &mut [f64]) {
        self.remember(x, new_x);
        self.transcription.gradient(x, grad);
    }
    fn constraints(&mut self, x: &[f64], new_x: bool, g: &mut [f64]) {
        self.remember(x, new_x);
        self.transcription.constraints(x, g);
    }
    fn jacobian_nnz(&self) -> usize {
        self.transcription.jacobian_pattern().nnz()
    }
    fn jacobian_structure(&self, rows: &mut [usize], cols: &mut [usize]) {
        let p = self.transcription.jacobian_pattern();
        rows.copy_from_slice(&p.rows);
        cols.copy_from_slice(&p.cols);
    }
    fn jacobian_values(&mut self, x: &[f64], new_x: bool, values: &mut [f64]) {
        self.remember(x, new_x);
        self.transcription.jacobian_values(x, values);
    }
    fn hessian_nnz(&self) -> Option<usize> {
        match self.transcription.hessian_mode() {
            HessianMode::Exact => Some(self.transcription.hessian_pattern().nnz()),
            HessianMode::Lbfgs => None,
        }
    }
    fn hessian_structure(&self, rows: &mut [usize], cols: &mut [usize]) {
        let p = self.transcription.hessian_pattern();
        rows.copy_from_slice(&p.rows);
        cols.copy_from_slice(&p.cols);
    }
    fn hessian_values(
        &mut self,
        x: &[f64],
        new_x: bool,
        obj_factor: f64,
        lambda: &[f64],
        _new_lambda: bool,
        values: &mut [f64],
    ) {
        self.remember(x, new_x);
        self.transcription
            .hessian_values(x, obj_factor, lambda, values);
    }
    fn scaling(&self) -> Option<Scaling> {
        self.scaling.clone()
    }
    fn intermediate(&mut self, info: &IterationInfo) -> bool {
        if let Some(progress) = self.progress {
            let max_slack = self.transcription.max_slack(&self.last_x);
            progress(&Progress {
                iteration: info.iteration,
                objective: info.objective,
                inf_pr: info.inf_pr,
                inf_du: info.inf_du,
                max_slack,
            });
        }
        true
    }
}
