//! Ipopt options: values, vito's defaults (`vendor-config/ipopt-defaults.opt`, embedded at
//! compile time) and the options the wrapper refuses before Ipopt sees them.

use super::IpoptError;

/// The text of `vendor-config/ipopt-defaults.opt`, an `ipopt.opt`-style file.
pub const DEFAULTS_FILE: &str = include_str!("../../vendor-config/ipopt-defaults.opt");

/// Options every solve sets before vito's defaults and the caller's options (which may
/// override them): read no `ipopt.opt` from the working directory (an empty
/// `option_file_name` disables the options file), and print no banner (`sb`).
pub(super) const FORCED: [(&str, &str); 2] = [("option_file_name", ""), ("sb", "yes")];

/// A value for one Ipopt option: Ipopt's three option types.
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
}
