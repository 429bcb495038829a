//! Ipopt's return status (`ApplicationReturnStatus`) as a Rust enum.

use super::compat;
use super::sys;

/// How a solve ended: one variant per Ipopt `ApplicationReturnStatus` (Ipopt 3.11 to 3.14;
/// [`Status::MaximumWallTimeExceeded`] only from 3.14).
///
/// Each variant quotes the line Ipopt prints at the end of the solve (`print_level` ≥ 1).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, serde::Serialize, serde::Deserialize)]
pub enum Status {
    /// "EXIT: Optimal Solution Found." The point satisfies the convergence tolerance `tol`.
    SolveSucceeded,
    /// "EXIT: Solved To Acceptable Level." Converged only to the looser `acceptable_*`
    /// tolerances, after `acceptable_iter` iterations without reaching `tol`.
    SolvedToAcceptableLevel,
    /// "EXIT: Converged to a point of local infeasibility. Problem may be infeasible."
    /// The restoration phase found a local minimiser of the constraint violation that is not
    /// feasible (also "Problem has only fixed variables and constraints are infeasible.").
    InfeasibleProblemDetected,
    /// "EXIT: Search Direction is becoming Too Small." Steps stopped making progress; the
    /// point may still be close to optimal.
    SearchDirectionBecomesTooSmall,
    /// "EXIT: Iterates diverging; problem might be unbounded." An iterate exceeded
    /// `diverging_iterates_tol`.
    DivergingIterates,
    /// "EXIT: Stopping optimization at current point as requested by user." The intermediate
    /// callback returned false (the problem's `intermediate`, or the cancel flag was set); the
    /// current iterate is returned.
    UserRequestedStop,
    /// "EXIT: Feasible point for square problem found." For a problem with as many equality
    /// constraints as free variables.
    FeasiblePointFound,
    /// "EXIT: Maximum Number of Iterations Exceeded." `max_iter` was reached.
    MaximumIterationsExceeded,
    /// "EXIT: Restoration Failed!" The restoration phase could not reduce the infeasibility.
    RestorationFailed,
    /// "EXIT: Error in step computation (regularization becomes too large?)!" The KKT system
    /// could not be solved, even after regularisation.
    ErrorInStepComputation,
    /// "EXIT: Maximum CPU time exceeded." `max_cpu_time` was reached.
    MaximumCpuTimeExceeded,
    /// "EXIT: Maximum wallclock time exceeded." `max_wall_time` was reached (option and status
    /// new in Ipopt 3.14; never returned by 3.11).
    MaximumWallTimeExceeded,
    /// "EXIT: Problem has too few degrees of freedom." More active equality constraints than
    /// free variables.
    NotEnoughDegreesOfFreedom,
    /// No EXIT line of its own in Ipopt 3.11: the C interface returns it when the problem
    /// data handed to `IpoptSolve` is unusable (the wrapper checks sizes, bounds and sparsity
    /// itself first, so this should not be seen).
    InvalidProblemDefinition,
    /// "EXIT: Invalid option encountered." An option value was rejected when the solve
    /// started (for example a linear solver this Ipopt was built without).
    InvalidOption,
    /// "EXIT: Invalid number in NLP function or derivative detected." An evaluation failed
    /// (a callback returned NaN/Inf or panicked) where Ipopt could not backtrack, e.g. at the
    /// starting point.
    InvalidNumberDetected,
    /// "EXIT: Some uncaught Ipopt exception encountered." Ipopt raised an exception it did not
    /// handle (in 3.11 also for a lower bound above its upper bound, which the wrapper refuses
    /// before the solve).
    UnrecoverableException,
    /// "Unknown Exception caught in Ipopt": a C++ exception from outside Ipopt (for example
    /// from the linear solver).
    NonIpoptExceptionThrown,
    /// "EXIT: Not enough memory." An allocation failed.
    InsufficientMemory,
    /// "EXIT: INTERNAL ERROR: Unknown SolverReturn value - Notify IPOPT Authors."
    InternalError,
}

/// Each Ipopt code with its variant and its snake-case name (the names used in reports).
const TABLE: [(sys::ApplicationReturnStatus, Status, &str); 20] = [
    (
        sys::ApplicationReturnStatus::Solve_Succeeded,
        Status::SolveSucceeded,
        "solve_succeeded",
    ),
    (
        sys::ApplicationReturnStatus::Solved_To_Acceptable_Level,
        Status::SolvedToAcceptableLevel,
        "solved_to_acceptable_level",
    ),
    (
        sys::ApplicationReturnStatus::Infeasible_Problem_Detected,
        Status::InfeasibleProblemDetected,
        "infeasible_problem_detected",
    ),
    (
        sys::ApplicationReturnStatus::Search_Direction_Becomes_Too_Small,
        Status::SearchDirectionBecomesTooSmall,
        "search_direction_becomes_too_small",
    ),
    (
        sys::ApplicationReturnStatus::Diverging_Iterates,
        Status::DivergingIterates,
        "diverging_iterates",
    ),
    (
        sys::ApplicationReturnStatus::User_Requested_Stop,
        Status::UserRequestedStop,
        "user_requested_stop",
    ),
    (
        sys::ApplicationReturnStatus::Feasible_Point_Found,
        Status::FeasiblePointFound,
        "feasible_point_found",
    ),
    (
        sys::ApplicationReturnStatus::Maximum_Iterations_Exceeded,
        Status::MaximumIterationsExceeded,
        "maximum_iterations_exceeded",
    ),
    (
        sys::ApplicationReturnStatus::Restoration_Failed,
        Status::RestorationFailed,
        "restoration_failed",
    ),
    (
        sys::ApplicationReturnStatus::Error_In_Step_Computation,
        Status::ErrorInStepComputation,
        "error_in_step_computation",
    ),
    (
        sys::ApplicationReturnStatus::Maximum_CpuTime_Exceeded,
        Status::MaximumCpuTimeExceeded,
        "maximum_cpu_time_exceeded",
    ),
    (
        compat::MAXIMUM_WALL_TIME_EXCEEDED,
        Status::MaximumWallTimeExceeded,
        "maximum_wall_time_exceeded",
    ),
    (
        sys::ApplicationReturnStatus::Not_Enough_Degrees_Of_Freedom,
        Status::NotEnoughDegreesOfFreedom,
        "not_enough_degrees_of_freedom",
    ),
    (
        sys::ApplicationReturnStatus::Invalid_Problem_Definition,
        Status::InvalidProblemDefinition,
        "invalid_problem_definition",
    ),
    (
        sys::ApplicationReturnStatus::Invalid_Option,
        Status::InvalidOption,
        "invalid_option",
    ),
    (
        sys::ApplicationReturnStatus::Invalid_Number_Detected,
        Status::InvalidNumberDetected,
        "invalid_number_detected",
    ),
    (
        sys::ApplicationReturnStatus::Unrecoverable_Exception,
        Status::UnrecoverableException,
        "unrecoverable_exception",
    ),
    (
        sys::ApplicationReturnStatus::NonIpopt_Exception_Thrown,
        Status::NonIpoptExceptionThrown,
        "non_ipopt_exception_thrown",
    ),
    (
        sys::ApplicationReturnStatus::Insufficient_Memory,
        Status::InsufficientMemory,
        "insufficient_memory",
    ),
    (
        sys::ApplicationReturnStatus::Internal_Error,
        Status::InternalError,
        "internal_error",
    ),
];

impl Status {
    /// Every status, in Ipopt's order (successes first, then failures by code).
    pub const ALL: [Status; 20] = {
        let mut all = [Status::SolveSucceeded; 20];
        let mut i = 0;
        while i < TABLE.len() {
            all[i] = TABLE[i].1;
            i += 1;
        }
        all
    };

    /// The variant for one of Ipopt's return codes, `None` for a code Ipopt 3.14 does not
    /// define.
    pub fn from_code(code: i32) -> Option<Status> {
        TABLE
            .iter()
            .find(|(raw, _, _)| raw.0 == code)
            .map(|&(_, status, _)| status)
    }

    /// Ipopt's integer return code (0 = solve succeeded, negative = failure).
    pub fn code(&self) -> i32 {
        self.entry().0.0
    }

    /// The name in snake case, as written in summaries: `"solve_succeeded"`.
    pub fn as_snake_case(&self) -> &'static str {
        self.entry().2
    }

    /// The variant named `name` in snake case (as [`Status::as_snake_case`] writes it).
    pub fn from_snake_case(name: &str) -> Option<Status> {
        TABLE
            .iter()
            .find(|(_, _, n)| *n == name)
            .map(|&(_, status, _)| status)
    }

    /// Whether the solve reached an optimum: [`Status::SolveSucceeded`] or
    /// [`Status::SolvedToAcceptableLevel`].
    pub fn is_success(&self) -> bool {
        matches!(
            self,
            Status::SolveSucceeded | Status::SolvedToAcceptableLevel
        )
    }

    fn entry(&self) -> &'static (sys::ApplicationReturnStatus, Status, &'static str) {
        // TABLE lists every variant once (checked by a test); the fallback is never taken.
        TABLE
            .iter()
            .find(|(_, status, _)| status == self)
            .unwrap_or(&TABLE[TABLE.len() - 1])
    }
}

impl std::fmt::Display for Status {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(self.as_snake_case())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn table_covers_each_variant_and_code_once() {
        for (i, status) in Status::ALL.iter().enumerate() {
            let hits = TABLE.iter().filter(|(_, s, _)| s == status).count();
            assert_eq!(hits, 1, "{status:?}");
            assert_eq!(Status::from_code(status.code()), Some(*status));
            assert_eq!(
                Status::from_snake_case(status.as_snake_case()),
                Some(*status)
            );
            for other in &Status::ALL[i + 1..] {
                assert_ne!(status.code(), other.code());
                assert_ne!(status.as_snake_case(), other.as_snake_case());
            }
        }
        assert_eq!(Status::from_code(7), None);
        assert_eq!(Status::from_code(-6), None);
        assert_eq!(Status::from_code(-5), Some(Status::MaximumWallTimeExceeded));
    }

    #[test]
    fn snake_case_follows_variant_name() {
        for status in Status::ALL {
            let camel = format!("{status:?}");
            let from_snake: String = status
                .as_snake_case()
                .split('_')
                .map(|word| {
                    let mut chars = word.chars();
                    chars
                        .next()
                        .map(|c| c.to_ascii_uppercase().to_string() + chars.as_str())
                        .unwrap_or_default()
                })
                .collect();
            assert_eq!(from_snake, camel);
        }
        assert_eq!(Status::SolveSucceeded.as_snake_case(), "solve_succeeded");
        assert_eq!(Status::SolveSucceeded.code(), 0);
        assert_eq!(Status::InvalidNumberDetected.code(), -13);
    }

    #[test]
    fn success_means_optimal_or_acceptable() {
        let successes: Vec<Status> = Status::ALL.into_iter().filter(Status::is_success).collect();
        assert_eq!(
            successes,
            [Status::SolveSucceeded, Status::SolvedToAcceptableLevel]
        );
    }
}
