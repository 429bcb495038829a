//! Ipopt options: values, vito's defaults (`vendor-config/ipopt-defaults.opt`, embedded at
//! compile time) and the options the wrapper refuses before Ipopt sees them.

use super::IpoptError;

/// The text of `vendor-config/ipopt-defaults.opt`, an `ipopt.opt`-style file.
pub const DEFAULTS_FILE: &str = include_str!("../../vendor-config/ipopt-defaults.opt");

/// Options every solve sets before vito's defaults and the caller's options (which may
/// override them): read no `ipopt.opt` from the working directory (an empty
/// `option_file_name` disables the options file), and print no banner (`sb`).
pub(super) const FORCED: [(&str, &str); 2] = [("option_file_name", ""), ("sb", "yes")];

/// A value for one Ipopt option: Ipopt's three option types, as a problem file's
/// `[solver.ipopt]` gives them (`ProblemSpec::solver_options`) and as vito sets its own.
///
/// An integer given for a number option (or an integral number for an integer option) is
/// converted when Ipopt accepts the other type, so `max_cpu_time = 600` works.
#[derive(Debug, Clone, PartialEq)]
pub enum OptionValue {
    /// A string option, e.g. `mu_strategy = "adaptive"`; yes/no options are strings too.
    Str(String),
    /// A number option, e.g. `tol = 1e-6`.
    Num(f64),
    /// An integer option, e.g. `max_iter = 3000` (Ipopt's integers are 32-bit).
    Int(i64),
}

impl std::fmt::Display for OptionValue {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            OptionValue::Str(s) => write!(f, "{s:?}"),
            OptionValue::Num(x) => write!(f, "{x:e}"),
            OptionValue::Int(i) => write!(f, "{i}"),
        }
    }
}

/// A borrowed value (a problem's `[solver.ipopt]` entry), for `Solver::set_option`.
impl From<&OptionValue> for OptionValue {
    fn from(value: &OptionValue) -> Self {
        value.clone()
    }
}

impl From<&str> for OptionValue {
    fn from(value: &str) -> Self {
        OptionValue::Str(value.to_string())
    }
}

impl From<String> for OptionValue {
    fn from(value: String) -> Self {
        OptionValue::Str(value)
    }
}

impl From<f64> for OptionValue {
    fn from(value: f64) -> Self {
        OptionValue::Num(value)
    }
}

impl From<i64> for OptionValue {
    fn from(value: i64) -> Self {
        OptionValue::Int(value)
    }
}

impl From<i32> for OptionValue {
    fn from(value: i32) -> Self {
        OptionValue::Int(i64::from(value))
    }
}

impl From<bool> for OptionValue {
    /// Ipopt's yes/no options: `true` → `"yes"`, `false` → `"no"`.
    fn from(value: bool) -> Self {
        OptionValue::Str(if value { "yes" } else { "no" }.to_string())
    }
}

/// Parses an `ipopt.opt`-style text: one `name value` pair per line, `#` to the end of a
/// line is a comment. A value that parses as an integer is an `Int`, else as a float a
/// `Num`, else a `Str`.
///
/// Errors give the 1-based line number and the line.
pub fn parse_option_file(text: &str) -> Result<Vec<(String, OptionValue)>, String> {
    let mut options = Vec::new();
    for (index, raw_line) in text.lines().enumerate() {
        let line = raw_line.split('#').next().unwrap_or("").trim();
        if line.is_empty() {
            continue;
        }
        let mut words = line.split_whitespace();
        let (Some(name), Some(value), None) = (words.next(), words.next(), words.next()) else {
            return Err(format!(
                "line {}: expected `name value`, found `{raw_line}`",
                index + 1
            ));
        };
        let value = if let Ok(i) = value.parse::<i64>() {
            OptionValue::Int(i)
        } else if let Ok(x) = value.parse::<f64>() {
            OptionValue::Num(x)
        } else {
            OptionValue::Str(value.to_string())
        };
        options.push((name.to_string(), value));
    }
    Ok(options)
}

/// vito's default options, parsed from [`DEFAULTS_FILE`].
pub fn default_options() -> Vec<(String, OptionValue)> {
    // The file is part of the source tree, not user input; a unit test parses it and checks
    // that Ipopt accepts every line.
    parse_option_file(DEFAULTS_FILE).unwrap_or_else(|e| {
        panic!("vendor-config/ipopt-defaults.opt is malformed ({e}); fix the file")
    })
}

/// Refuses the options that Debian's Ipopt cannot take safely, before Ipopt sees them.
///
/// Only MUMPS is built in: `linear_solver = ma97` makes Ipopt 3.11 print "Abort..." and call
/// `exit(1)`, and makes 3.14.17 return `InvalidOption` and then segfault in
/// `FreeIpoptProblem`, ending the whole process either way; ma27, ma57, ma77, ma86, pardiso,
/// wsmp and custom end the solve with `InvalidOption`. Option names are case-sensitive in
/// Ipopt, values are not.
pub fn check_allowed(name: &str, value: &OptionValue) -> Result<(), IpoptError> {
    if name == "linear_solver" {
        let is_mumps =
            matches!(value, OptionValue::Str(s) if s.trim().eq_ignore_ascii_case("mumps"));
        if !is_mumps {
            return Err(IpoptError::Refused {
                name: name.to_string(),
                value: value.to_string(),
                reason: "Debian's Ipopt is built with MUMPS only (ma97 would end the process: \
                         Ipopt 3.11 calls exit(1), 3.14 crashes; the other HSL, Pardiso and \
                         WSMP solvers are missing); use \"mumps\""
                    .to_string(),
            });
        }
    }
    Ok(())
}

/// The Ipopt options a problem file may set: those that steer the algorithm (termination,
/// barrier, line search, restoration, initialisation, scaling, Hessian approximation,
/// derivative test, MUMPS) and `print_level` (Ipopt's table on standard output). Anything
/// else, in particular `output_file`, `option_file_name` and `file_print_level` (which read
/// or write files named by the problem) is refused: a problem file is input, not code. The
/// docs/ipopt.md lists them (a unit test keeps the two in step).
pub const PROBLEM_FILE_OPTIONS: &[&str] = &[
    // Termination.
    "tol",
    "max_iter",
    "max_cpu_time",
    "max_wall_time",
    "dual_inf_tol",
    "constr_viol_tol",
    "compl_inf_tol",
    "acceptable_tol",
    "acceptable_iter",
    "acceptable_dual_inf_tol",
    "acceptable_constr_viol_tol",
    "acceptable_compl_inf_tol",
    "acceptable_obj_change_tol",
    "diverging_iterates_tol",
    "mu_target",
    // Output on standard output (vito's own progress is on stderr).
    "print_level",
    // NLP treatment.
    "bound_relax_factor",
    "honor_original_bounds",
    "check_derivatives_for_naninf",
    "fixed_variable_treatment",
    "kappa_d",
    "jac_c_constant",
    "jac_d_constant",
    "hessian_constant",
    // Scaling.
    "nlp_scaling_method",
    "obj_scaling_factor",
    "nlp_scaling_max_gradient",
    "nlp_scaling_obj_target_gradient",
    "nlp_scaling_constr_target_gradient",
    "nlp_scaling_min_value",
    // Barrier parameter.
    "mu_strategy",
    "mu_oracle",
    "fixed_mu_oracle",
    "mu_init",
    "mu_max_fact",
    "mu_max",
    "mu_min",
    "barrier_tol_factor",
    "mu_linear_decrease_factor",
    "mu_superlinear_decrease_power",
    "mu_allow_fast_monotone_decrease",
    "adaptive_mu_globalization",
    "adaptive_mu_monotone_init_factor",
    "adaptive_mu_kkterror_red_iters",
    "adaptive_mu_kkterror_red_fact",
    "adaptive_mu_safeguard_factor",
    "adaptive_mu_restore_previous_iterate",
    "quality_function_max_section_steps",
    "tau_min",
    "sigma_max",
    "sigma_min",
    // Initialisation and warm start.
    "bound_push",
    "bound_frac",
    "slack_bound_push",
    "slack_bound_frac",
    "constr_mult_init_max",
    "bound_mult_init_val",
    "bound_mult_init_method",
    "least_square_init_primal",
    "least_square_init_duals",
    "warm_start_init_point",
    "warm_start_bound_push",
    "warm_start_bound_frac",
    "warm_start_slack_bound_push",
    "warm_start_slack_bound_frac",
    "warm_start_mult_bound_push",
    "warm_start_mult_init_max",
    // Line search.
    "line_search_method",
    "alpha_red_factor",
    "accept_every_trial_step",
    "accept_after_max_steps",
    "alpha_for_y",
    "alpha_for_y_tol",
    "tiny_step_tol",
    "tiny_step_y_tol",
    "watchdog_shortened_iter_trigger",
    "watchdog_trial_iter_max",
    "theta_max_fact",
    "theta_min_fact",
    "eta_phi",
    "delta",
    "s_phi",
    "s_theta",
    "gamma_phi",
    "gamma_theta",
    "alpha_min_frac",
    "max_soc",
    "kappa_soc",
    "obj_max_inc",
    "max_filter_resets",
    "filter_reset_trigger",
    "corrector_type",
    "skip_corr_if_neg_curv",
    "skip_corr_in_monotone_mode",
    "corrector_compl_avrg_red_fact",
    "nu_init",
    "nu_inc",
    "rho",
    // Restoration phase.
    "expect_infeasible_problem",
    "expect_infeasible_problem_ctol",
    "expect_infeasible_problem_ytol",
    "start_with_resto",
    "soft_resto_pderror_reduction_factor",
    "max_soft_resto_iters",
    "required_infeasibility_reduction",
    "max_resto_iter",
    "evaluate_orig_obj_at_resto_trial",
    "resto_penalty_parameter",
    "resto_proximity_weight",
    "bound_mult_reset_threshold",
    "constr_mult_reset_threshold",
    "resto_failure_feasibility_threshold",
    // Linear solver (MUMPS only) and the step computation.
    "linear_solver",
    "linear_system_scaling",
    "linear_scaling_on_demand",
    "max_refinement_steps",
    "min_refinement_steps",
    "residual_ratio_max",
    "residual_ratio_singular",
    "residual_improvement_factor",
    "neg_curv_test_tol",
    "perturb_always_cd",
    "max_hessian_perturbation",
    "min_hessian_perturbation",
    "perturb_inc_fact_first",
    "perturb_inc_fact",
    "perturb_dec_fact",
    "first_hessian_perturbation",
    "jacobian_regularization_value",
    "jacobian_regularization_exponent",
    "mumps_pivtol",
    "mumps_pivtolmax",
    "mumps_mem_percent",
    "mumps_permuting_scaling",
    "mumps_pivot_order",
    "mumps_scaling",
    "mumps_dep_tol",
    // Hessian approximation.
    "hessian_approximation",
    "hessian_approximation_space",
    "limited_memory_update_type",
    "limited_memory_max_history",
    "limited_memory_max_skipping",
    "limited_memory_initialization",
    "limited_memory_init_val",
    "limited_memory_init_val_max",
    "limited_memory_init_val_min",
    "limited_memory_special_for_resto",
    // Derivative checker (prints on standard output).
    "derivative_test",
    "derivative_test_perturbation",
    "derivative_test_tol",
    "derivative_test_print_all",
    "derivative_test_first_index",
    "point_perturbation_radius",
];

/// The integer options of [`PROBLEM_FILE_OPTIONS`] (Ipopt's option types, the same in 3.11 and
/// 3.14): a value is offered to Ipopt as the option's own type first, so that a `max_iter =
/// 3000.0` or a `bound_push = 1` is set without Ipopt first printing that it has the other
/// type.
pub(super) const INTEGER_OPTIONS: &[&str] = &[
    "max_iter",
    "acceptable_iter",
    "print_level",
    "adaptive_mu_kkterror_red_iters",
    "quality_function_max_section_steps",
    "accept_after_max_steps",
    "watchdog_shortened_iter_trigger",
    "watchdog_trial_iter_max",
    "max_soc",
    "max_filter_resets",
    "filter_reset_trigger",
    "max_soft_resto_iters",
    "max_resto_iter",
    "max_refinement_steps",
    "min_refinement_steps",
    "mumps_mem_percent",
    "mumps_permuting_scaling",
    "mumps_pivot_order",
    "mumps_scaling",
    "limited_memory_max_history",
    "limited_memory_max_skipping",
    "derivative_test_first_index",
];

/// Whether Ipopt option `name` is an integer option: `Some(true)` for [`INTEGER_OPTIONS`],
/// `Some(false)` for the rest of [`PROBLEM_FILE_OPTIONS`] (numbers and strings), `None` for a
/// name outside vito's lists (tried as the value's type first, as Ipopt may know it).
pub(super) fn known_integer(name: &str) -> Option<bool> {
    if INTEGER_OPTIONS.contains(&name) {
        Some(true)
    } else if PROBLEM_FILE_OPTIONS.contains(&name) {
        Some(false)
    } else {
        None
    }
}

/// String options of [`PROBLEM_FILE_OPTIONS`] with only some values allowed: the others need
/// HSL routines Debian's Ipopt does not have (and `ma97` ends the process).
const RESTRICTED_VALUES: &[(&str, &[&str])] = &[
    ("linear_solver", &["mumps"]),
    (
        "nlp_scaling_method",
        &["none", "user-scaling", "gradient-based"],
    ),
    ("linear_system_scaling", &["none"]),
];

/// Whether a problem file may set Ipopt option `name` to `value`: the name must be in
/// [`PROBLEM_FILE_OPTIONS`], a number must be finite (Ipopt takes `tol = nan` and then hangs
/// in MUMPS), and a restricted string option must have one of its allowed values. On top of
/// this, [`check_allowed`] and Ipopt's own check apply.
pub fn check_problem_option(name: &str, value: &OptionValue) -> Result<(), IpoptError> {
    let refused = |reason: String| IpoptError::Refused {
        name: name.to_string(),
        value: value.to_string(),
        reason,
    };
    if !PROBLEM_FILE_OPTIONS.contains(&name) {
        return Err(refused(
            "a problem file may set only the options that steer the algorithm (docs/ipopt.md \
             lists them); Ipopt's files (`output_file`, `option_file_name`, \
             `file_print_level`) are not among them: for Ipopt's log use \
             `vito solve --ipopt-log`, which writes `ipopt.log` into the output directory"
                .to_string(),
        ));
    }
    if let OptionValue::Num(x) = value
        && !x.is_finite()
    {
        return Err(refused("must be a finite number".to_string()));
    }
    if let Some((_, allowed)) = RESTRICTED_VALUES.iter().find(|(n, _)| *n == name) {
        let ok = matches!(value, OptionValue::Str(s)
            if allowed.iter().any(|a| s.trim().eq_ignore_ascii_case(a)));
        if !ok {
            return Err(refused(format!(
                "Debian's Ipopt has no HSL routines; allowed values: {}",
                allowed
                    .iter()
                    .map(|a| format!("\"{a}\""))
                    .collect::<Vec<_>>()
                    .join(", ")
            )));
        }
    }
    check_allowed(name, value)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn defaults_are_the_spec_comparison_options() {
        let defaults = default_options();
        let get = |name: &str| {
            defaults
                .iter()
                .find(|(n, _)| n == name)
                .map(|(_, v)| v.clone())
        };
        assert_eq!(get("tol"), Some(OptionValue::Num(1e-6)));
        assert_eq!(get("max_iter"), Some(OptionValue::Int(3000)));
        assert_eq!(get("mu_strategy"), Some(OptionValue::from("adaptive")));
        assert_eq!(get("linear_solver"), Some(OptionValue::from("mumps")));
        assert_eq!(get("print_level"), Some(OptionValue::Int(0)));
        // The returned point is the one Ipopt checked (see the defaults file for why).
        assert_eq!(get("honor_original_bounds"), Some(OptionValue::from("no")));
        // Exact Hessian is Ipopt's own default; the file must not change it.
        assert_eq!(get("hessian_approximation"), None);
        assert_eq!(defaults.len(), 6);
    }

    #[test]
    fn option_file_types_and_comments() {
        let parsed =
            parse_option_file("# comment\n\n  tol 1e-8  # trailing\nmax_iter 10\nmu_strategy monotone\nbound_push 1\n")
                .unwrap();
        assert_eq!(
            parsed,
            vec![
                ("tol".to_string(), OptionValue::Num(1e-8)),
                ("max_iter".to_string(), OptionValue::Int(10)),
                ("mu_strategy".to_string(), OptionValue::from("monotone")),
                ("bound_push".to_string(), OptionValue::Int(1)),
            ]
        );
        let err = parse_option_file("tol\n").unwrap_err();
        assert!(err.contains("line 1"), "{err}");
        let err = parse_option_file("tol 1 2\n").unwrap_err();
        assert!(err.contains("tol 1 2"), "{err}");
    }

    #[test]
    fn only_mumps_passes_the_linear_solver_check() {
        for ok in ["mumps", "MUMPS", " mumps"] {
            assert!(check_allowed("linear_solver", &OptionValue::from(ok)).is_ok());
        }
        for bad in [
            "ma27", "ma57", "ma77", "ma86", "ma97", "MA97", "pardiso", "wsmp", "custom",
        ] {
            let err = check_allowed("linear_solver", &OptionValue::from(bad)).unwrap_err();
            assert!(matches!(err, IpoptError::Refused { .. }));
            assert!(err.to_string().contains(bad), "{err}");
        }
        assert!(check_allowed("linear_solver", &OptionValue::Int(27)).is_err());
        assert!(check_allowed("tol", &OptionValue::Num(1e-3)).is_ok());
    }

    #[test]
    fn problem_files_set_only_algorithm_options_with_finite_values() {
        for name in [
            "output_file",
            "option_file_name",
            "file_print_level",
            "sb",
            "Tol",
        ] {
            let err = check_problem_option(name, &OptionValue::from("x")).unwrap_err();
            assert!(err.to_string().contains(&format!("`{name}`")), "{err}");
        }
        for x in [f64::NAN, f64::INFINITY, f64::NEG_INFINITY] {
            let err = check_problem_option("tol", &OptionValue::Num(x)).unwrap_err();
            assert!(err.to_string().contains("finite"), "{err}");
        }
        assert!(check_problem_option("tol", &OptionValue::Num(1e-8)).is_ok());
        assert!(check_problem_option("nlp_scaling_method", &"gradient-based".into()).is_ok());
        assert!(check_problem_option("nlp_scaling_method", &"equilibration-based".into()).is_err());
        assert!(check_problem_option("linear_solver", &"ma97".into()).is_err());
    }

    /// Every allowed option is one Ipopt knows (3.11 to 3.14) and docs/ipopt.md lists it.
    #[test]
    fn allowed_options_are_ipopts_and_documented() {
        let listed = include_str!("../../docs/ipopt.md");
        for name in PROBLEM_FILE_OPTIONS {
            assert!(
                listed.contains(&format!("`{name}`")),
                "docs/ipopt.md does not list `{name}`"
            );
        }
        let mut names = PROBLEM_FILE_OPTIONS.to_vec();
        names.sort_unstable();
        names.dedup();
        assert_eq!(names.len(), PROBLEM_FILE_OPTIONS.len(), "a duplicate entry");
    }

    /// The integer options are problem-file options, and Ipopt takes each as an integer: a
    /// value of 1 (in range for all of them) offered as a number comes back as an integer.
    #[test]
    fn integer_options_are_ipopts_integers() {
        let mut solver = crate::ipopt::Solver::new();
        for name in INTEGER_OPTIONS {
            assert_eq!(known_integer(name), Some(true));
            solver.set_option(name, 1.0).unwrap();
            let set = solver.options().iter().find(|(n, _)| n == name);
            assert_eq!(set.map(|(_, v)| v), Some(&OptionValue::Int(1)), "{name}");
        }
        assert_eq!(known_integer("bound_push"), Some(false));
        assert_eq!(known_integer("mu_strategy"), Some(false));
        assert_eq!(known_integer("sb"), None);
    }
}
