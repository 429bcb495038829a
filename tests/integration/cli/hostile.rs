//! Hostile or careless input ends in one clear error (exit 2) naming the file and field,
//! before any solving, with nothing written; one test per kind of input at least.

use crate::cli::errors::solve_fails;
use crate::cli::util::{TestDir, hopper_text};

/// `vito check` on `text` (as `bad.toml` next to the hopper's URDF) fails with exit 2 and
/// one error line, which it returns.
fn check_fails(name: &str, text: &str, extra: &[&str]) -> String {
    let t = TestDir::with_hopper(name);
    t.write("bad.toml", text);
    let run = t
        .vito()
        .args(["check", "bad.toml"])
        .args(extra)
        .assert_exit(2);
    let errors = run
        .stderr
        .lines()
        .filter(|l| l.starts_with("error:"))
        .count();
    assert_eq!(errors, 1, "one error expected:\n{}", run.stderr);
    run.stderr
}

/// Options that read or write files are refused in `check` and `solve`, naming the
/// option; the file named is neither created nor read.
#[test]
fn ipopt_options_outside_the_allow_list_are_refused() {
    let victim = std::env::temp_dir().join("vito-hostile-victim-output-file");
    let _ = std::fs::remove_file(&victim);
    for (key, value) in [
        ("output_file", format!("\"{}\"", victim.display())),
        ("option_file_name", "\"/etc/passwd\"".to_owned()),
        ("file_print_level", "12".to_owned()),
        ("linear_solver", "\"ma97\"".to_owned()),
        ("nlp_scaling_method", "\"equilibration-based\"".to_owned()),
    ] {
        let text = hopper_text()
            .replace("linear_solver = \"mumps\"\n", "")
            .replace("max_iter = 3000", &format!("{key} = {value}"));
        let err = check_fails(&format!("ipopt_allow_{key}"), &text, &[]);
        assert!(
            err.contains(&format!("field `solver.ipopt.{key}`")),
            "{err}"
        );
        assert!(err.contains("refused"), "{err}");
        let err = solve_fails(&format!("ipopt_allow_solve_{key}"), &text);
        assert!(err.contains(&format!("`solver.ipopt.{key}`")), "{err}");
        assert!(!victim.exists());
    }
    // Through --set as well.
    let err = check_fails(
        "ipopt_allow_set",
        &hopper_text(),
        &["--set", "solver.ipopt.output_file=\"x.log\""],
    );
    assert!(
        err.contains("solver.ipopt.output_file") && err.contains("--set"),
        "{err}"
    );
}

/// Ipopt never reads an `ipopt.opt` from the working directory (one that would stop
/// the solve after one iteration changes nothing), and `--ipopt-log` writes Ipopt's log into
/// the output directory (the polish's as `ipopt.polish.log`, a continuation's later solves'
/// as `ipopt.solve<k>.log`).
#[test]
fn ipopt_log_goes_into_the_output_directory_and_cwd_ipopt_opt_is_ignored() {
    let t = TestDir::with_hopper("ipopt_log");
    t.write("p.toml", &hopper_text());
    t.write("ipopt.opt", "max_iter 1\nlinear_solver ma97\n");
    let run = t
        .vito()
        .args(["solve", "p.toml", "--quiet", "--ipopt-log", "--out", "res"])
        .assert_exit(0);
    assert!(run.stdout.contains("solve_succeeded"), "{}", run.stdout);
    let log = std::fs::read_to_string(t.path().join("res/ipopt.log")).unwrap();
    assert!(log.contains("EXIT: Optimal Solution Found"), "{log}");
    assert!(log.contains("iter    objective"), "{log}");
    // The relaxed solve's log is ipopt.log, the polish's beside it: each names its own
    // iterations, which add up to the summary's.
    let iterations = |log: &str| -> u64 {
        let line = log
            .lines()
            .find(|l| l.starts_with("Number of Iterations"))
            .unwrap_or_else(|| panic!("no iteration count in {log}"));
        line.rsplit(' ').next().unwrap().trim().parse().unwrap()
    };
    let polish_log = std::fs::read_to_string(t.path().join("res/ipopt.polish.log")).unwrap();
    let s = crate::cli::util::summary(&t.path().join("res"));
    let polish = s["polish"]["iterations"].as_u64().unwrap();
    assert_eq!(iterations(&polish_log), polish);
    assert_eq!(iterations(&log) + polish, s["iterations"].as_u64().unwrap());
    // A slack continuation's solves each keep their log: ipopt.log the first, then
    // ipopt.solve2.log, …, each with the iterations `continuation` records for it.
    t.vito()
        .args(["solve", "p.toml", "--quiet", "--ipopt-log", "--out", "res"])
        .args(["--set", "slack.homotopy=true"])
        .assert_exit(0);
    let s = crate::cli::util::summary(&t.path().join("res"));
    let solves = s["continuation"].as_array().unwrap();
    assert!(solves.len() >= 2, "{solves:?}");
    for (k, solve) in solves.iter().enumerate() {
        let name = match k {
            0 => "ipopt.log".to_owned(),
            _ => format!("ipopt.solve{}.log", k + 1),
        };
        let log = std::fs::read_to_string(t.path().join("res").join(&name)).unwrap();
        assert_eq!(
            iterations(&log),
            solve["iterations"].as_u64().unwrap(),
            "{name}"
        );
    }
    assert!(
        !t.path()
            .join(format!("res/ipopt.solve{}.log", solves.len() + 1))
            .exists()
    );
    // Without the flag there is no log.
    t.vito()
        .args(["solve", "p.toml", "--quiet", "--out", "res"])
        .assert_exit(0);
    assert!(!t.path().join("res/ipopt.log").exists());
}

/// Non-finite numeric Ipopt options are input errors (`tol = nan` hung in MUMPS).
#[test]
fn non_finite_ipopt_options_are_input_errors() {
    for value in ["nan", "inf", "-inf"] {
        let text = hopper_text().replace("tol = 1e-6", &format!("tol = {value}"));
        let err = check_fails(
            &format!("ipopt_nonfinite_{}", value.replace('-', "m")),
            &text,
            &[],
        );
        assert!(err.contains("field `solver.ipopt.tol`"), "{err}");
        assert!(err.contains("finite"), "{err}");
    }
}

/// A horizon whose NLP cannot fit in memory is refused by `check` and `solve`
/// before anything per knot is allocated, saying how much it would need.
#[test]
fn huge_horizons_are_refused_with_the_memory_they_need() {
    for knots in ["10000000", "1000000000", "9223372036854775807"] {
        let set = format!("horizon.knots={knots}");
        let err = check_fails(
            &format!("huge_knots_{}", knots.len()),
            &hopper_text(),
            &["--set", &set],
        );
        assert!(err.contains("field `horizon.knots`"), "{err}");
        assert!(err.contains("GiB of memory"), "{err}");
        let text = hopper_text().replace("knots = 21", &format!("knots = {knots}"));
        let err = solve_fails(&format!("huge_knots_solve_{}", knots.len()), &text);
        assert!(err.contains("bad.toml:18: field `horizon.knots`"), "{err}");
    }
}

/// A horizon T = time_step·(knots − 1) that overflows is found at validation.
#[test]
fn overflowing_horizon_is_an_input_error() {
    let err = check_fails(
        "overflowing_horizon",
        &hopper_text(),
        &["--set", "horizon.time_step=1e307"],
    );
    assert!(err.contains("field `horizon.time_step`"), "{err}");
    let err = check_fails(
        "overflowing_horizon_2",
        &hopper_text(),
        &[
            "--set",
            "horizon.time_step=1e11",
            "--set",
            "horizon.knots=1000",
        ],
    );
    assert!(
        err.contains("field `horizon.time_step`") && err.contains("horizon T"),
        "{err}"
    );
}

/// Extreme finite values are refused against the README's sane ranges, naming the
/// field.
#[test]
fn extreme_finite_values_are_refused_by_range() {
    for (name, set, field) in [
        ("tiny_step", "horizon.time_step=5e-324", "horizon.time_step"),
        ("huge_slack", "slack.weight=1e308", "slack.weight"),
        (
            "huge_gravity",
            "robot.gravity=[0, 0, -1e308]",
            "robot.gravity[2]",
        ),
        (
            "tiny_total",
            "horizon.total_time=[5e-324, 1]",
            "horizon.total_time[0]",
        ),
        (
            "huge_friction",
            "contacts.friction=1e300",
            "contacts.friction",
        ),
        (
            "tiny_width",
            "terrain.step=[{edge_x = 0.2, rise = 0.1, width = 1e-320}]",
            "terrain.step[0].width",
        ),
    ] {
        // total_time replaces time_step, so it is written into the file.
        let (text, args) = match set.strip_prefix("horizon.total_time=") {
            Some(window) => (
                hopper_text().replace("time_step = 0.05 ", &format!("total_time = {window}")),
                vec![],
            ),
            None => (hopper_text(), vec!["--set", set]),
        };
        let err = check_fails(&format!("extreme_{name}"), &text, &args);
        assert!(err.contains(&format!("field `{field}`")), "{name}: {err}");
        assert!(!err.contains("time_steps"), "{err}");
    }
}

/// Bound ends that are not a range are blamed on the bound itself, not on
/// `initial.q`; `knots = []` applies nowhere and is an error.
#[test]
fn bad_bounds_name_the_bound() {
    let text = hopper_text().replace("lower = 0.0\n", "lower = inf\n");
    let err = solve_fails("bound_lower_inf", &text);
    assert!(err.contains("field `bounds[0].lower`"), "{err}");
    assert!(!err.contains("initial.q"), "{err}");
    let text = hopper_text().replace("lower = 0.3\n", "lower = 1e300\n");
    let err = solve_fails("bound_lower_huge", &text);
    assert!(
        err.contains("field `bounds[1]`") && err.contains("1e12"),
        "{err}"
    );
    let text = hopper_text().replace("theta = [-10.0, 10.0]", "theta = [nan, 10.0]");
    let err = solve_fails("input_bound_nan", &text);
    assert!(err.contains("field `inputs.bounds.theta`"), "{err}");
    let text = hopper_text().replace("knots = \"all\"\nlower = 0.0", "knots = []\nlower = 0.0");
    let err = solve_fails("bound_no_knots", &text);
    assert!(
        err.contains("field `bounds[0].knots`") && err.contains("no knot"),
        "{err}"
    );
    let text = hopper_text().replace("tolerance = 0.0", "tolerance = inf");
    let err = solve_fails("final_tolerance_inf", &text);
    assert!(
        err.contains("field `final.tolerance`") && err.contains("[0, 1e12]"),
        "{err}"
    );
}

/// A URDF nested 100,000 deep is an error naming the file and line in `inspect`,
/// `init` and `check`/`solve` (it overflowed the stack); more than 10,000 links is refused;
/// a 10,000-link chain loads.
#[test]
fn deep_or_huge_urdfs_are_clear_errors() {
    let t = TestDir::with_hopper("deep_urdf");
    let deep = format!(
        "<robot name=\"d\">\n{}{}</robot>\n",
        "<a>".repeat(100_000),
        "</a>".repeat(100_000)
    );
    t.write("deep.urdf", &deep);
    for args in [vec!["inspect", "deep.urdf"], vec!["init", "deep.urdf"]] {
        let run = t.vito().args(&args).assert_exit(2);
        assert!(
            run.stderr
                .contains("deep.urdf: elements nest more than 64 deep at line 2"),
            "{}",
            run.stderr
        );
    }
    t.write("robots/hopper_2d.urdf", &deep);
    t.write("p.toml", &hopper_text());
    let run = t.vito().args(["check", "p.toml"]).assert_exit(2);
    assert!(
        run.stderr.contains("field `robot.urdf`") && run.stderr.contains("nest more than 64"),
        "{}",
        run.stderr
    );

    let inertial = "<inertial><mass value=\"1\"/><inertia ixx=\"1\" iyy=\"1\" izz=\"1\" ixy=\"0\" ixz=\"0\" iyz=\"0\"/></inertial>";
    let chain = |n: usize| {
        let mut s = String::from("<robot name=\"chain\">\n");
        for i in 0..n {
            s.push_str(&format!("<link name=\"l{i}\">{inertial}</link>\n"));
        }
        for i in 1..n {
            s.push_str(&format!(
                "<joint name=\"j{i}\" type=\"revolute\"><parent link=\"l{}\"/><child link=\"l{i}\"/><axis xyz=\"0 1 0\"/></joint>\n",
                i - 1
            ));
        }
        s + "</robot>\n"
    };
    // Within the links read, a chain is bounded by its coordinates (100, measured): 94
    // revolute joints on a floating base (six) are 100.
    t.write("chain.urdf", &chain(95));
    let run = t
        .vito()
        .args(["inspect", "chain.urdf", "--json"])
        .assert_exit(0);
    assert!(run.stdout.contains("\"j94\""));
    t.write("chain.urdf", &chain(10_001));
    let run = t.vito().args(["inspect", "chain.urdf"]).assert_exit(2);
    assert!(
        run.stderr
            .contains("chain.urdf: it has 10001 <link> elements"),
        "{}",
        run.stderr
    );
}

/// A FIFO or a device as the problem file or the URDF is refused at once
/// (it blocked forever), saying what it is; a directory is not "does not exist".
#[test]
fn fifos_devices_and_directories_are_not_read() {
    let t = TestDir::with_hopper("fifo_inputs");
    let fifo = t.path().join("fifo");
    assert!(
        std::process::Command::new("mkfifo")
            .arg(&fifo)
            .status()
            .unwrap()
            .success()
    );
    let run = t.vito().args(["check", "fifo"]).assert_exit(2);
    assert!(run.stderr.contains("fifo: it is a FIFO"), "{}", run.stderr);
    // Trajectory CSVs given on the command line are read the same way.
    t.write("p.toml", &crate::cli::util::hopper_text());
    for args in [
        ["check", "p.toml", "--derivatives", "--at", "fifo"].as_slice(),
        ["simulate", "p.toml", "--inputs", "fifo", "--out", "s"].as_slice(),
    ] {
        let run = t.vito().args(args).assert_exit(2);
        assert!(
            run.stderr.contains("it is a FIFO"),
            "{args:?}: {}",
            run.stderr
        );
    }
    let run = t
        .vito()
        .args(["solve", "/dev/zero", "--out", "o"])
        .assert_exit(2);
    assert!(
        run.stderr.contains("/dev/zero: it is a character device"),
        "{}",
        run.stderr
    );
    for args in [["inspect", "fifo"], ["init", "fifo"], ["inspect", "robots"]] {
        let run = t.vito().args(args).assert_exit(2);
        assert!(run.stderr.contains("not a regular file"), "{}", run.stderr);
    }
    for (urdf, what) in [
        ("fifo", "a FIFO"),
        ("/dev/null", "a character device"),
        ("robots", "a directory"),
    ] {
        let text = hopper_text().replace("robots/hopper_2d.urdf", urdf);
        t.write("p.toml", &text);
        let run = t.vito().args(["check", "p.toml"]).assert_exit(2);
        assert!(
            run.stderr.contains("field `robot.urdf`") && run.stderr.contains(what),
            "{}",
            run.stderr
        );
        assert!(!run.stderr.contains("does not exist"), "{}", run.stderr);
    }
    assert!(!t.path().join("o").exists());
}

/// The hopper's URDF text, edited into bad inputs.
fn hopper_urdf() -> String {
    std::fs::read_to_string(crate::cli::util::problems_dir().join("robots/hopper_2d.urdf")).unwrap()
}

/// `vito check` of the hopper problem with `urdf` as its robot: exit 2, one error, returned.
fn check_with_urdf(name: &str, urdf: &str) -> String {
    let t = TestDir::with_hopper(name);
    t.write("robots/hopper_2d.urdf", urdf);
    t.write("p.toml", &hopper_text());
    let run = t.vito().args(["check", "p.toml"]).assert_exit(2);
    assert_eq!(
        run.stderr
            .lines()
            .filter(|l| l.starts_with("error:"))
            .count(),
        1,
        "{}",
        run.stderr
    );
    assert!(
        run.stderr.contains("field `robot.urdf`") && run.stderr.contains("hopper_2d.urdf"),
        "{}",
        run.stderr
    );
    run.stderr
}

/// Names whose trajectory.csv columns would clash (a joint called `time` or `slack`, a joint
/// called like a contact's position column) are input errors naming both, before solving: the
/// file could not be read back.
#[test]
fn names_that_clash_in_the_trajectory_csv_are_input_errors() {
    for (joint, says) in [
        ("time", "the time and coordinate `time`"),
        ("slack", "coordinate `slack` and the slack"),
        (
            "foot_contact_z",
            "coordinate `foot_contact_z` and contact `foot_contact`",
        ),
    ] {
        let urdf = hopper_urdf().replace(
            "<joint name=\"x\" type=\"prismatic\">",
            &format!("<joint name=\"{joint}\" type=\"prismatic\">"),
        );
        let stderr = check_with_urdf(&format!("clash_{joint}"), &urdf);
        assert!(stderr.contains(says), "{joint}: {stderr}");
    }
}

/// NaN or crossed URDF values are errors naming the URDF element (not
/// `initial.q`, not Ipopt's "invalid number" after solving).
#[test]
fn bad_urdf_numbers_name_the_element() {
    let u = hopper_urdf();
    for (name, from, to, expect) in [
        (
            "effort_negative",
            "effort=\"10\"",
            "effort=\"-10\"",
            "joint 'theta': <limit effort=\"-10\">",
        ),
        (
            "effort_nan",
            "effort=\"100\"",
            "effort=\"nan\"",
            "joint 'r': <limit effort=\"NaN\">",
        ),
        (
            "limit_nan",
            "lower=\"0.3\"",
            "lower=\"nan\"",
            "joint 'r': <limit lower=\"NaN\"",
        ),
        (
            "limit_crossed",
            "lower=\"0.3\" upper=\"0.7\"",
            "lower=\"0.7\" upper=\"0.3\"",
            "lower exceeds upper",
        ),
        (
            "origin_nan",
            "<axis xyz=\"0 0 -1\"/>",
            "<origin xyz=\"0 nan 0\"/><axis xyz=\"0 0 -1\"/>",
            "joint 'r': <origin",
        ),
        (
            "damping",
            "<axis xyz=\"0 0 -1\"/>",
            "<axis xyz=\"0 0 -1\"/><dynamics damping=\"-1\"/>",
            "damping",
        ),
    ] {
        assert!(u.contains(from), "{from}");
        let err = check_with_urdf(&format!("urdf_{name}"), &u.replacen(from, to, 1));
        assert!(err.contains(expect), "{name}: {err}");
        assert!(!err.contains("initial.q"), "{err}");
    }
    let collision = u.replacen(
        "<origin xyz=\"0 0 0\" rpy=\"0 0 0\"/>\n      <geometry>",
        "<origin xyz=\"inf 0 0\" rpy=\"0 0 0\"/>\n      <geometry>",
        1,
    );
    assert_ne!(collision, u);
    let err = check_with_urdf("urdf_collision_origin", &collision);
    assert!(err.contains("<origin"), "{err}");
}

/// What was accepted silently is an error naming the element.
#[test]
fn silently_accepted_urdf_mistakes_are_errors() {
    let u = hopper_urdf();
    let second = u.replacen(
        "</robot>",
        "<transmission name=\"again\"><joint name=\"r\"/></transmission>\n</robot>",
        1,
    );
    let err = check_with_urdf("urdf_two_transmissions", &second);
    assert!(
        err.contains("transmission 'again': acts on joint 'r' like transmission 'r_drive'"),
        "{err}"
    );
    let spring = u.replacen(
        "</robot>",
        "<force_element name=\"s\"><prismatic_spring stiffness=\"1\" rest_length=\"0\"><joint name=\"theta\"/></prismatic_spring></force_element>\n</robot>",
        1,
    );
    let err = check_with_urdf("urdf_spring_kind", &spring);
    assert!(
        err.contains("force_element 's': a prismatic spring on the revolute joint 'theta'"),
        "{err}"
    );
    let self_loop = u.replacen(
        "</robot>",
        "<loop_joint name=\"l\" type=\"continuous\"><axis xyz=\"0 1 0\"/><link1 link=\"body\" xyz=\"0 0 0\"/><link2 link=\"body\" xyz=\"0 0 0.1\"/></loop_joint>\n</robot>",
        1,
    );
    let err = check_with_urdf("urdf_self_loop", &self_loop);
    assert!(
        err.contains("loop_joint 'l'") && err.contains("to itself"),
        "{err}"
    );
}

/// The URDF reader's warnings are shown by `check` (and `solve`), not only `inspect`.
#[test]
fn model_warnings_are_shown_by_check() {
    let t = TestDir::with_hopper("model_warnings");
    let u = hopper_urdf().replacen(" effort=\"10\" velocity=\"1e20\"", " effort=\"10\"", 1);
    assert_ne!(u, hopper_urdf());
    t.write("robots/hopper_2d.urdf", &u);
    t.write("p.toml", &hopper_text());
    let run = t.vito().args(["check", "p.toml"]).assert_exit(0);
    assert!(
        run.stderr.contains("warning: ") && run.stderr.contains("hopper_2d.urdf"),
        "{}",
        run.stderr
    );
    assert!(run.stderr.contains("velocity"), "{}", run.stderr);
}

/// Control characters in names the problem defines are refused; names from a URDF
/// are printed escaped.
#[test]
fn control_characters_never_reach_the_terminal() {
    let text = hopper_text().replace("name = \"hopper-2d\"", "name = \"hop\\u001b[31mper\"");
    let err = check_fails("control_in_name", &text, &[]);
    assert!(
        err.contains("field `name`") && err.contains("control or invisible formatting characters"),
        "{err}"
    );
    assert!(!err.contains('\u{1b}'), "{err:?}");
    let text = hopper_text().replace("from_urdf = \"all\"", "from_urdf = \"none\"").replace(
        "friction = 0.8",
        "friction = 0.8\n[[contacts.point]]\nname = \"toe\\u0007\"\nlink = \"foot\"\npoint = [0, 0, 0]",
    );
    let err = check_fails("control_in_contact", &text, &[]);
    assert!(err.contains("field `contacts.point[0].name`"), "{err}");
    let t = TestDir::with_hopper("control_in_urdf");
    // XML has no ESC; C1 controls such as CSI (U+009B, an escape to many terminals) it has.
    let u = hopper_urdf().replace("\"theta\"", "\"th\u{9b}2Jeta\"");
    t.write("r.urdf", &u);
    let run = t.vito().args(["inspect", "r.urdf"]).assert_exit(0);
    assert!(
        run.stdout.contains("th\\u{9b}2Jeta") && !run.stdout.contains('\u{9b}'),
        "{}",
        run.stdout
    );
}

/// `name` names `out/<name>`, so it is a plain file-name component.
#[test]
fn problem_name_is_a_plain_file_name() {
    for bad in ["", ".", "..", "../../x", "/abs/path", "a/b"] {
        let text = hopper_text().replace("name = \"hopper-2d\"", &format!("name = \"{bad}\""));
        let err = solve_fails(&format!("name_{}", bad.len()), &text);
        assert!(err.contains("field `name`"), "{bad}: {err}");
    }
}

/// `output.dir` is relative to the problem file's directory (as every path in it); `--out`
/// to the working directory.
#[test]
fn output_dir_is_relative_to_the_problem_file() {
    let t = TestDir::with_hopper("output_dir_relative");
    std::fs::create_dir(t.path().join("cwd")).unwrap();
    let text = hopper_text().replace("max_iter = 3000", "max_iter = 2")
        + "\n[output]\ndir = \"results\"\n";
    t.write("p.toml", &text);
    let out = std::process::Command::new(env!("CARGO_BIN_EXE_vito"))
        .current_dir(t.path().join("cwd"))
        .args(["solve", "../p.toml", "--quiet"])
        .output()
        .unwrap();
    assert_eq!(
        out.status.code(),
        Some(1),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    assert!(t.path().join("results/summary.json").exists());
    assert!(!t.path().join("cwd/results").exists());
    let out = std::process::Command::new(env!("CARGO_BIN_EXE_vito"))
        .current_dir(t.path().join("cwd"))
        .args(["solve", "../p.toml", "--quiet", "--out", "here"])
        .output()
        .unwrap();
    assert_eq!(out.status.code(), Some(1));
    assert!(t.path().join("cwd/here/summary.json").exists());
}

/// Output paths that cannot work are exit 2 before solving, the solver never runs.
#[test]
fn bad_output_paths_are_found_before_solving() {
    let t = TestDir::with_hopper("bad_output_paths");
    t.write("p.toml", &hopper_text());
    t.write("afile", "x");
    std::os::unix::fs::symlink("nowhere", t.path().join("dangling")).unwrap();
    let long = "n".repeat(300);
    for (out, expect) in [
        ("dangling", "symbolic link"),
        (long.as_str(), "bytes long"),
        ("afile/sub", "not a directory"),
        ("missing/../x", "`..`"),
        (".", "names no directory"),
    ] {
        let run = t
            .vito()
            .args(["solve", "p.toml", "--out", out])
            .assert_exit(2);
        assert!(run.stderr.contains(expect), "{out}: {}", run.stderr);
        assert!(!run.stderr.contains("iter"), "{}", run.stderr);
    }
    assert_eq!(
        std::fs::read_to_string(t.path().join("afile")).unwrap(),
        "x"
    );
}

/// `inspect`, `init` and `check` fail (exit 2, a message) when stdout cannot be
/// written.
#[test]
fn unwritable_stdout_is_an_error() {
    let t = TestDir::with_hopper("dev_full");
    t.write("p.toml", &hopper_text());
    for args in [
        vec!["inspect", "robots/hopper_2d.urdf"],
        vec!["init", "robots/hopper_2d.urdf"],
        vec!["check", "p.toml"],
    ] {
        let full = std::fs::OpenOptions::new()
            .write(true)
            .open("/dev/full")
            .unwrap();
        let out = std::process::Command::new(env!("CARGO_BIN_EXE_vito"))
            .current_dir(t.path())
            .args(&args)
            .stdout(full)
            .output()
            .unwrap();
        let stderr = String::from_utf8_lossy(&out.stderr);
        // Its own exit code (4): an output error, not an input error.
        assert_eq!(out.status.code(), Some(4), "{args:?}: {stderr}");
        assert!(
            stderr.contains("cannot write to standard output"),
            "{stderr}"
        );
    }
}

/// A regression record's non-finite objective, unknown status or negative/NaN
/// tolerance is an input error (exit 2) before anything is solved, also with `--bless`
/// (which so never keeps a negative tolerance).
#[test]
fn bad_regression_records_are_input_errors() {
    let t = TestDir::with_hopper("bad_records");
    t.write("p.toml", &hopper_text());
    let entry = |objective: &str, tolerance: &str, status: &str| {
        format!(
            "[[problem]]\nfile = \"p.toml\"\nobjective = {objective}\ntolerance = {tolerance}\nstatus = \"{status}\"\niterations = 1\nmax_slack = 0.0\n"
        )
    };
    let s = "solve_succeeded";
    for (name, objective, tolerance, status, field) in [
        ("inf", "inf", "1e-6", s, "objective"),
        ("banana", "1.0", "1e-6", "banana", "status"),
        ("negative", "1.0", "-1e-6", s, "tolerance"),
        ("nan", "1.0", "nan", s, "tolerance"),
    ] {
        let record = entry(objective, tolerance, status);
        let field = format!("problem[0].{field}");
        let path = t.write(&format!("{name}.toml"), &record);
        for bless in [false, true] {
            let mut args = vec!["regress", "--record", path.to_str().unwrap()];
            if bless {
                args.push("--bless");
            }
            let run = t.vito().args(&args).assert_exit(2);
            assert!(
                run.stderr.contains(&field) && run.stderr.contains("p.toml"),
                "{}",
                run.stderr
            );
            assert_eq!(std::fs::read_to_string(&path).unwrap(), record);
        }
    }
    let run = t
        .vito()
        .args(["regress", "--record", "/nonexistent/golden.toml"])
        .assert_exit(2);
    assert!(run.stderr.contains("does not exist"), "{}", run.stderr);
}

/// Serde's messages in the problem file's words: a 3-vector of the wrong length
/// names the 3-vector fields, `robot = 3` asks for a table.
#[test]
fn schema_messages_speak_the_files_language() {
    let err = check_fails(
        "short_gravity",
        &hopper_text(),
        &["--set", "robot.gravity=[0, 0]"],
    );
    assert!(
        err.contains("robot.gravity") && err.contains("[x, y, z]"),
        "{err}"
    );
    let text = hopper_text().replace("[robot]\n", "robot = 3\n[robotx]\n");
    let err = check_fails("robot_integer", &text, &[]);
    assert!(
        err.contains("field `robot`") && err.contains("expected a table"),
        "{err}"
    );
    assert!(!err.contains("RobotSection"), "{err}");
}

// Output streams that cannot be written, the default base of `init` and `inspect`, and
// inputs built to be slow to read.

/// `vito` with its standard output or error sent to `/dev/full`.
fn vito_into_dev_full(t: &TestDir, args: &[&str], stream: &str) -> i32 {
    let full = || {
        std::fs::OpenOptions::new()
            .write(true)
            .open("/dev/full")
            .unwrap()
    };
    let mut cmd = std::process::Command::new(env!("CARGO_BIN_EXE_vito"));
    cmd.current_dir(t.path()).args(args);
    match stream {
        "stdout" => cmd.stdout(full()),
        _ => cmd.stderr(full()),
    };
    cmd.status().unwrap().code().unwrap_or(-1)
}

/// `vito bench` imports no `casadi.py` and runs no `tools/independent/*.py` planted
/// in the working directory (a downloaded dataset's).
#[test]
fn bench_runs_no_python_from_the_working_directory() {
    let t = TestDir::new("bench_runs_no_python_from_the_working_directory");
    let marker = |name: &str| format!("open({name:?}, 'w').write('ran')\n");
    t.write("casadi.py", &marker("imported-casadi"));
    std::fs::create_dir_all(t.path().join("tools/independent")).unwrap();
    t.write(
        "tools/independent/spec_casadi.py",
        &marker("ran-planted-script"),
    );
    let hopper = crate::cli::util::problems_dir().join("hopper_2d.toml");
    let run = t
        .vito()
        .env("VITO_PYTHON", "python3")
        .env_remove("VITO_CASADI_SCRIPT")
        .env("OPENBLAS_NUM_THREADS", "1")
        .args([std::ffi::OsStr::new("bench"), hopper.as_os_str()])
        .assert_exit(0);
    assert!(!t.path().join("imported-casadi").exists(), "{}", run.stdout);
    assert!(
        !t.path().join("ran-planted-script").exists(),
        "{}",
        run.stdout
    );
}

/// A warm start that is not a trajectory CSV (here a passwd-like file) is refused
/// from its header, quoting none of it; a bad cell of a trajectory CSV is named by row and
/// column and quoted only when short and number-like.
#[test]
fn csv_errors_never_echo_another_files_contents() {
    let t = TestDir::with_hopper("csv_errors_never_echo_another_files_contents");
    t.write(
        "secret.txt",
        "root:x:0:0:SECRET-ONE:/root:/bin/bash\nuser:x:1:1:SECRET-TWO:/:/bin/sh\n",
    );
    t.write(
        "key.csv",
        "time [s],x [m]\n0,0\n1,AAAAB3NzaC1yc2EKEYMATERIAL0123456789abcdef\n",
    );
    let text = hopper_text().replace("to = \"final\"", "warm_start = \"secret.txt\"");
    assert!(text.contains("secret.txt"));
    t.write("p.toml", &text);
    let run = t.vito().args(["check", "p.toml"]).assert_exit(2);
    assert!(!run.stderr.contains("SECRET"), "{}", run.stderr);
    assert!(
        run.stderr.contains("secret.txt") && run.stderr.contains("trajectory CSV header"),
        "{}",
        run.stderr
    );
    t.write("p.toml", &text.replace("secret.txt", "key.csv"));
    let run = t.vito().args(["check", "p.toml"]).assert_exit(2);
    assert!(!run.stderr.contains("KEYMATERIAL"), "{}", run.stderr);
    assert!(
        run.stderr.contains("row 3, column 2 (`x`)") && run.stderr.contains("finite decimal"),
        "{}",
        run.stderr
    );
}

/// A regression record that is another file (a link to a passwd-like file, or a copy of
/// one) is refused naming its line, quoting none of it, also with `--bless`.
#[test]
fn regression_record_errors_never_echo_the_file() {
    let t = TestDir::with_hopper("regression_record_errors_never_echo_the_file");
    t.write("p.toml", &hopper_text());
    let secret = "root:x:0:0:SECRET-ONE:/root:/bin/bash\nuser:x:1:1:SECRET-TWO:/:/bin/sh\n";
    t.write("passwd", secret);
    std::os::unix::fs::symlink("passwd", t.path().join("linked.toml")).unwrap();
    t.write("copied.toml", secret);
    for (record, bless) in [
        ("linked.toml", false),
        ("copied.toml", false),
        ("copied.toml", true),
    ] {
        let mut args = vec!["regress", "--record", record];
        if bless {
            args.extend(["--bless", "p.toml"]);
        }
        let run = t.vito().args(&args).assert_exit(2);
        assert!(
            run.stderr.contains(&format!("{record}: line 1:")),
            "{args:?}: {}",
            run.stderr
        );
        assert!(
            !run.stderr.contains("SECRET") && !run.stderr.contains("root:x"),
            "{args:?}: {}",
            run.stderr
        );
    }
    assert_eq!(
        std::fs::read_to_string(t.path().join("copied.toml")).unwrap(),
        secret
    );
}

/// What the system refuses is never an "internal error" (exit 3): a record naming a file
/// with a NUL byte and an `--out` longer than PATH_MAX are input errors (exit 2, naming the
/// field or the length); a disk that takes no more while `solve`, `simulate`, a sweep's
/// resume and `sweep report` write their files (here a file-size limit, which fails a write
/// as a full disk does) is exit 4, every file already there kept.
#[test]
fn system_refusals_are_input_or_output_errors_never_internal() {
    let t = TestDir::with_hopper("system_refusals");
    t.write("p.toml", &hopper_text());
    t.write(
        "nul.toml",
        "[[problem]]\nfile = \"a\\u0000b.toml\"\nobjective = 1.0\ntolerance = 1e-6\nstatus = \"solve_succeeded\"\niterations = 1\nmax_slack = 0.0\n",
    );
    for bless in [&[][..], &["--bless"]] {
        let run = t
            .vito()
            .args(["regress", "--record", "nul.toml"])
            .args(bless)
            .assert_exit(2);
        assert!(
            run.stderr.contains("problem[0].file") && run.stderr.contains("NUL"),
            "{}",
            run.stderr
        );
    }
    let long = vec!["d".repeat(200); 25].join("/");
    for command in ["solve", "simulate"] {
        let run = t
            .vito()
            .args([command, "p.toml", "--quiet", "--out", &long])
            .assert_exit(2);
        assert!(run.stderr.contains("bytes long"), "{}", run.stderr);
    }
    // Results of earlier runs, then each command again on a full disk.
    let quiet = ["--quiet", "--set", "solver.ipopt.max_iter=3"];
    t.vito()
        .args(["solve", "p.toml", "--out", "plan"])
        .args(quiet)
        .assert_exit(1);
    t.vito()
        .args(["simulate", "p.toml", "--out", "sim", "--quiet"])
        .assert_exit(0);
    let sweep = crate::cli::sweep::one_point_sweep("sw");
    t.vito().args(sweep).assert_exit(1);
    t.vito().args(["sweep", "report", "sw"]).assert_exit(1);
    let files = |dir: &str| -> Vec<(std::path::PathBuf, Vec<u8>)> {
        let mut out: Vec<_> = std::fs::read_dir(t.path().join(dir))
            .unwrap()
            .map(|e| e.unwrap().path())
            .filter(|p| p.is_file())
            .map(|p| (p.clone(), std::fs::read(&p).unwrap()))
            .collect();
        out.sort();
        out
    };
    let before: Vec<_> = ["plan", "sim", "sw"].map(files).to_vec();
    for args in [
        &["solve", "p.toml", "--out", "plan", "--quiet"][..],
        &["simulate", "p.toml", "--out", "sim", "--quiet"],
        &sweep,
        &["sweep", "report", "sw"],
    ] {
        let run = t.vito_on_a_full_disk().args(args).assert_exit(4);
        assert!(
            run.stderr.contains("File too large") && !run.stderr.contains("internal error"),
            "{args:?}: {}",
            run.stderr
        );
    }
    assert_eq!(["plan", "sim", "sw"].map(files).to_vec(), before);
}

/// `vito init --out` onto a dangling symbolic link writes nothing through it.
#[test]
fn init_never_writes_through_a_dangling_link() {
    let t = TestDir::with_hopper("init_never_writes_through_a_dangling_link");
    let target = t.path().join("elsewhere.toml");
    std::os::unix::fs::symlink(&target, t.path().join("l.toml")).unwrap();
    let run = t
        .vito()
        .args(["init", "robots/hopper_2d.urdf", "--out", "l.toml"])
        .assert_exit(2);
    assert!(!target.exists(), "{}", run.stderr);
    assert!(run.stderr.contains("l.toml exists"), "{}", run.stderr);
    assert!(
        std::fs::symlink_metadata(t.path().join("l.toml"))
            .unwrap()
            .file_type()
            .is_symlink()
    );
}

/// 30,000 parentheses, 50,000 minus signs and a 20,000-part `--set` key are input
/// errors naming the field, not a stack overflow.
#[test]
fn deep_expressions_and_keys_are_input_errors() {
    let with_friction = |expression: String| {
        let text =
            hopper_text().replace("friction = 0.8", &format!("friction = \"= {expression}\""));
        assert!(text.contains("= ((") || text.contains("= --"));
        format!("{text}\n[parameters]\nmu = 0.5\n")
    };
    let parens = with_friction(format!("{}mu{}", "(".repeat(30_000), ")".repeat(30_000)));
    let err = check_fails("deep_parens", &parens, &[]);
    assert!(
        err.contains("`contacts.friction`") && err.contains("64 deep"),
        "{err}"
    );
    assert!(err.len() < 1000, "{} bytes", err.len());
    let minus = with_friction(format!("{}mu", "-".repeat(50_000)));
    let err = check_fails("deep_minus", &minus, &[]);
    assert!(
        err.contains("`contacts.friction`") && err.contains("64 deep"),
        "{err}"
    );
    let key = format!("{}b=1", "a.".repeat(20_000));
    let err = check_fails("deep_key", &hopper_text(), &["--set", &key]);
    assert!(err.contains("--set") && err.contains("64 parts"), "{err}");
    assert!(err.len() < 1000, "{} bytes", err.len());
}

/// A serial chain of `n` revolute links.
fn chain_urdf(n: usize) -> String {
    let inertial = "<inertial><mass value=\"1\"/><inertia ixx=\"0.01\" iyy=\"0.01\" izz=\"0.01\" ixy=\"0\" ixz=\"0\" iyz=\"0\"/></inertial>";
    let mut xml = String::from("<robot name=\"chain\">\n");
    for i in 0..=n {
        xml.push_str(&format!("<link name=\"l{i}\">{inertial}</link>\n"));
    }
    for i in 0..n {
        xml.push_str(&format!(
            "<joint name=\"j{i}\" type=\"revolute\"><parent link=\"l{i}\"/><child link=\"l{}\"/>\
             <origin xyz=\"0 0 -0.1\"/><axis xyz=\"0 1 0\"/>\
             <limit lower=\"-1\" upper=\"1\" effort=\"10\" velocity=\"10\"/></joint>\n",
            i + 1
        ));
    }
    xml.push_str("</robot>\n");
    xml
}

/// A 1,000-link chain (within the 10,000 links read) is refused at once by its
/// coordinate count, naming the limit, instead of aborting on a 4 GB allocation.
#[test]
fn long_chains_are_refused_by_their_coordinates() {
    let t = TestDir::new("long_chains_are_refused_by_their_coordinates");
    t.write("chain.urdf", &chain_urdf(1000));
    let run = t
        .vito()
        .args(["inspect", "chain.urdf", "--base", "fixed"])
        .assert_exit(2);
    assert!(
        run.stderr.contains("1000 coordinates") && run.stderr.contains("up to 100 coordinates"),
        "{}",
        run.stderr
    );
}

/// The memory guard reads the process's own limit (`ulimit -v`), not the machine's
/// RAM: 40,000 hopper knots (an estimated 4.4 GiB) under a 4 GiB limit are an input error.
#[test]
fn memory_guard_reads_the_process_limit() {
    let t = TestDir::with_hopper("memory_guard_reads_the_process_limit");
    t.write("p.toml", &hopper_text());
    let run = std::process::Command::new("sh")
        .current_dir(t.path())
        .args([
            "-c",
            &format!(
                "ulimit -v 4194304 && exec {} check p.toml --set horizon.knots=40000",
                env!("CARGO_BIN_EXE_vito")
            ),
        ])
        .output()
        .unwrap();
    let stderr = String::from_utf8_lossy(&run.stderr);
    assert_eq!(run.status.code(), Some(2), "{stderr}");
    assert!(
        stderr.contains("field `horizon.knots`") && stderr.contains("this process may use"),
        "{stderr}"
    );
}

/// 40,000 attributes on one element are refused before parsing, naming the line.
#[test]
fn many_attributes_on_an_element_are_refused() {
    let attributes: String = (0..40_000).map(|i| format!(" a{i}=\"1\"")).collect();
    let urdf = hopper_urdf().replacen("<robot name", &format!("<robot{attributes} name"), 1);
    let err = check_with_urdf("many_attributes", &urdf);
    assert!(
        err.contains("more than 64 attributes") && err.contains("line"),
        "{err}"
    );
}

/// A solved hopper trajectory (one row per knot of the hopper problem) in `t`, as text.
fn hopper_trajectory(t: &TestDir) -> String {
    t.write("p.toml", &hopper_text());
    t.vito()
        .env("OPENBLAS_NUM_THREADS", "1")
        .args(["solve", "p.toml", "--quiet", "--out", "plan"])
        .assert_exit(0);
    std::fs::read_to_string(t.path().join("plan/trajectory.csv")).unwrap()
}

/// `text` with cell (row, column) replaced (row 0 is the header).
fn with_cell(text: &str, row: usize, column: usize, cell: &str) -> String {
    let mut out = String::new();
    for (r, line) in text.lines().enumerate() {
        let mut cells: Vec<String> = line.split(',').map(str::to_owned).collect();
        if r == row {
            cells[column] = cell.to_owned();
        }
        out.push_str(&cells.join(","));
        out.push('\n');
    }
    out
}

/// The index of the column whose header starts with `name`.
fn column_index(text: &str, name: &str) -> usize {
    let header = text.lines().next().unwrap();
    header
        .split(',')
        .position(|h| h.starts_with(name))
        .unwrap_or_else(|| panic!("no column {name} in {header}"))
}

/// A simulation whose steps cannot fit in the memory the process may use (10⁶ hopper steps
/// under a 600 MB address space) is refused before its first step, naming the memory it
/// would need (it ran until an allocation failed and the process aborted).
#[test]
fn simulations_too_long_for_memory_are_refused() {
    let t = TestDir::with_hopper("simulations_too_long_for_memory_are_refused");
    t.write("p.toml", &hopper_text());
    let run = t
        .vito_with_address_space(600_000)
        .args(["simulate", "p.toml", "--quiet", "--out", "sim"])
        .args(["--duration", "10000", "--rate", "100"])
        .assert_exit(2);
    assert!(
        run.stderr.contains("1000000 steps") && run.stderr.contains("this process may use"),
        "{}",
        run.stderr
    );
    assert!(!t.path().join("sim").exists());
}

/// NaN and infinite inputs, an empty input cell and a `--track` file missing an
/// input column are input errors (exit 2) of `simulate`, as is `--rate 1e308`.
#[test]
fn simulate_refuses_non_finite_and_missing_inputs() {
    let t = TestDir::with_hopper("simulate_refuses_non_finite_and_missing_inputs");
    let plan = hopper_trajectory(&t);
    let u = column_index(&plan, "u_theta");
    let simulate = |flag: &str, csv: &str, extra: &[&str]| {
        t.write("bad.csv", csv);
        let mut args = vec![
            "simulate", "p.toml", flag, "bad.csv", "--quiet", "--out", "sim",
        ];
        if flag == "--track" {
            args.extend(["--gains", "all=10,1"]);
        }
        args.extend(extra);
        t.vito().args(&args).assert_exit(2).stderr
    };
    for flag in ["--inputs", "--track"] {
        for cell in ["NaN", "inf", "-inf"] {
            let err = simulate(flag, &with_cell(&plan, 3, u, cell), &[]);
            assert!(err.contains("row 4, column"), "{flag} {cell}: {err}");
        }
        let err = simulate(flag, &with_cell(&plan, 3, u, ""), &[]);
        assert!(
            err.contains("row 4, column `u_theta` is empty"),
            "{flag}: {err}"
        );
    }
    let missing: String = plan
        .lines()
        .map(|l| {
            let mut cells: Vec<&str> = l.split(',').collect();
            cells.remove(u);
            cells.join(",") + "\n"
        })
        .collect();
    let err = simulate("--track", &missing, &[]);
    assert!(err.contains("no column for every input"), "{err}");
    let run = t
        .vito()
        .args([
            "simulate", "p.toml", "--rate", "1e308", "--quiet", "--out", "sim",
        ])
        .assert_exit(2);
    assert!(run.stderr.contains("--rate"), "{}", run.stderr);
    assert!(!t.path().join("sim").exists());
}

/// `check --derivatives --at` refuses NaN cells, times scaled by 1e300 and a
/// duplicated column (it checked them and exited 0).
#[test]
fn check_at_refuses_nan_cells_scaled_times_and_duplicate_columns() {
    let t = TestDir::with_hopper("check_at_refuses_nan_scaled_times_duplicates");
    let plan = hopper_trajectory(&t);
    let check = |csv: &str| {
        t.write("at.csv", csv);
        t.vito()
            .args(["check", "p.toml", "--derivatives", "--at", "at.csv"])
            .assert_exit(2)
            .stderr
    };
    let z = column_index(&plan, "z");
    let err = check(&with_cell(&plan, 5, z, "nan"));
    assert!(err.contains("row 6, column"), "{err}");
    let scaled: String = plan
        .lines()
        .enumerate()
        .map(|(r, l)| {
            if r == 0 {
                return format!("{l}\n");
            }
            let (time, rest) = l.split_once(',').unwrap();
            format!("{},{rest}\n", time.parse::<f64>().unwrap() * 1e300)
        })
        .collect();
    let err = check(&scaled);
    assert!(err.contains("outside the problem's step"), "{err}");
    let duplicated: String = plan
        .lines()
        .map(|l| {
            let cells: Vec<&str> = l.split(',').collect();
            format!("{},{}\n", l, cells[z])
        })
        .collect();
    let err = check(&duplicated);
    assert!(err.contains("are both `z`"), "{err}");
}

/// A `--set` value holding a line break and more TOML is refused, not cut.
#[test]
fn set_values_with_line_breaks_are_refused() {
    let err = check_fails(
        "set_line_break",
        &hopper_text(),
        &["--set", "horizon.knots=3\n[robot]\nbase = \"planar\""],
    );
    assert!(err.contains("line break"), "{err}");
}

/// A full standard output or error is its own exit code (4), and a solve whose
/// standard error is full still writes its results.
#[test]
fn full_output_streams_are_exit_4_and_keep_the_results() {
    let t = TestDir::with_hopper("full_output_streams_are_exit_4");
    t.write("p.toml", &hopper_text());
    assert_eq!(vito_into_dev_full(&t, &["check", "p.toml"], "stdout"), 4);
    assert_eq!(
        vito_into_dev_full(&t, &["solve", "p.toml", "--out", "res"], "stderr"),
        4
    );
    let summary = crate::cli::util::summary(&t.path().join("res"));
    assert_eq!(summary["status"], "solve_succeeded", "{summary}");
    assert!(t.path().join("res/trajectory.csv").is_file());
}

/// `name` and `description` are text even when they begin with `=`; a name holding
/// a right-to-left override (or another invisible formatting character) is refused.
#[test]
fn text_fields_are_never_expressions_and_names_are_plain() {
    let t = TestDir::with_hopper("text_fields_are_never_expressions");
    let text = hopper_text()
        .replace("name = \"hopper-2d\"", "name = \"=hop\"")
        .replace("description = \"Planar", "description = \"= Planar");
    assert!(text.contains("=hop"));
    t.write("p.toml", &text);
    let run = t.vito().args(["check", "p.toml"]).assert_exit(0);
    assert!(run.stdout.contains("=hop"), "{}", run.stdout);
    for hidden in ['\u{202E}', '\u{200B}', '\u{2066}'] {
        let err = check_fails(
            "names_are_plain",
            &hopper_text().replace(
                "name = \"hopper-2d\"",
                &format!("name = \"hop{hidden}gpj.exe\""),
            ),
            &[],
        );
        assert!(
            err.contains("field `name`") && err.contains("invisible formatting"),
            "{err}"
        );
    }
}

/// Every exit code vito returns is in `vito --help` and in the README's table, the same
/// set (0 to 4), and each that the outside can cause is caused here.
#[test]
fn every_exit_code_is_documented_and_reached() {
    let t = TestDir::with_hopper("every_exit_code_is_documented_and_reached");
    let help = t.vito().args(["--help"]).assert_exit(0).stdout;
    let in_help: Vec<u8> = help
        .split("Exit codes:")
        .nth(1)
        .unwrap_or_else(|| panic!("{help}"))
        .lines()
        .filter_map(|l| l.split_whitespace().next()?.parse().ok())
        .collect();
    let readme =
        std::fs::read_to_string(std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("README.md"))
            .unwrap();
    let table = readme
        .split("| code | meaning |")
        .nth(1)
        .expect("the README's exit-code table");
    let in_readme: Vec<u8> = table
        .lines()
        .skip(2)
        .take_while(|l| l.starts_with('|'))
        .filter_map(|l| l.trim_matches('|').split('|').next()?.trim().parse().ok())
        .collect();
    assert_eq!(in_help, [0, 1, 2, 3, 4], "{help}");
    assert_eq!(in_readme, in_help);
    t.write("p.toml", &hopper_text());
    t.vito().args(["check", "p.toml"]).assert_exit(0);
    t.vito()
        .env("OPENBLAS_NUM_THREADS", "1")
        .args(["solve", "p.toml", "--quiet", "--out", "r"])
        .args(["--set", "solver.ipopt.max_iter=2"])
        .assert_exit(1);
    t.vito().args(["check", "missing.toml"]).assert_exit(2);
    t.vito().args(["solve", "--no-such-flag"]).assert_exit(2);
    // 3 is a bug (a panic) or the solver failing to start: nothing an input can cause.
    assert_eq!(vito_into_dev_full(&t, &["check", "p.toml"], "stdout"), 4);
}

/// `init` and `inspect` choose the same base by default: fixed for the
/// hopper, whose URDF slides its root itself (no six extra coordinates), standing on the
/// ground; a fixed-base starter whose contacts would start under the ground stands on
/// ground lowered to its lowest contact.
#[test]
fn init_base_defaults_to_inspects_and_lowers_the_ground_under_a_bolted_robot() {
    let t = TestDir::with_hopper("init_base_defaults_to_inspects");
    let inspect = t
        .vito()
        .args(["inspect", "robots/hopper_2d.urdf"])
        .assert_exit(0)
        .stdout;
    assert!(
        inspect.contains("(fixed base)")
            && inspect.contains("coordinates (4)")
            && inspect
                .contains("base fixed (--base auto): its own prismatic joints move its root link"),
        "{inspect}"
    );
    t.vito()
        .args(["init", "robots/hopper_2d.urdf", "--out", "h.toml"])
        .assert_exit(0);
    let starter = std::fs::read_to_string(t.path().join("h.toml")).unwrap();
    assert!(starter.contains("base = \"fixed\""), "{starter}");
    assert!(!starter.contains("base_x"), "{starter}");
    let check = t.vito().args(["check", "h.toml"]).assert_exit(0);
    assert!(
        !check.stderr.contains("below the terrain"),
        "{}",
        check.stderr
    );
    // An arm bolted down at z = 0 with a collision sphere 0.05 m under its mount: the
    // ground is lowered to it, and the starter checks.
    let arm = r#"<?xml version="1.0"?>
<robot name="arm">
  <link name="mount"><collision><origin xyz="0 0 -0.05"/><geometry><sphere radius="0"/></geometry></collision></link>
  <link name="upper"><inertial><origin xyz="0 0 0.2"/><mass value="1"/><inertia ixx="0.01" ixy="0" ixz="0" iyy="0.01" iyz="0" izz="0.01"/></inertial></link>
  <joint name="shoulder" type="revolute"><parent link="mount"/><child link="upper"/><axis xyz="0 1 0"/><limit lower="-1" upper="1" effort="10" velocity="1"/></joint>
</robot>
"#;
    std::fs::write(t.path().join("arm.urdf"), arm).unwrap();
    let inspect = t.vito().args(["inspect", "arm.urdf"]).assert_exit(0).stdout;
    assert!(
        inspect.contains(
            "base fixed (--base auto): no end link or contact reaches below its root link `mount`"
        ),
        "{inspect}"
    );
    t.vito()
        .args(["init", "arm.urdf", "--out", "a.toml"])
        .assert_exit(0);
    let starter = std::fs::read_to_string(t.path().join("a.toml")).unwrap();
    assert!(starter.contains("ground_height = -0.05   #"), "{starter}");
    let check = t.vito().args(["check", "a.toml"]).assert_exit(0);
    assert!(
        !check.stderr.contains("below the terrain"),
        "{}",
        check.stderr
    );
    // A fixed base without moving joints has nothing to plan: refused, naming the fix.
    let brick = crate::cli::util::problems_dir().join("robots/brick.urdf");
    let run = t
        .vito()
        .args([std::ffi::OsStr::new("init"), brick.as_os_str()])
        .args(["--base", "fixed", "--out", "b.toml"])
        .assert_exit(2);
    assert!(
        run.stderr.contains("no coordinates") && run.stderr.contains("--base floating"),
        "{}",
        run.stderr
    );
    assert!(!t.path().join("b.toml").exists());
}

/// 200,000 `<visual>` parts in one link (17 MB, within the 64 MiB read)
/// took 15.8 s to read; a URDF of more than 200,000 elements is refused before any parser
/// reads it, naming the file, the limit and the fix.
#[test]
fn urdfs_with_too_many_elements_are_refused() {
    let visuals =
        "<visual><geometry><box size=\"0.1 0.1 0.1\"/></geometry></visual>\n".repeat(70_000);
    let urdf = hopper_urdf().replacen(
        "</robot>",
        &format!("<link name=\"many\">{visuals}</link>\n</robot>"),
        1,
    );
    let err = check_with_urdf("too_many_elements", &urdf);
    assert!(
        err.contains("more than 200000 elements") && err.contains("remove the visuals"),
        "{err}"
    );
}

/// A fixed-joint star of 10,000 links (the documented link limit) is
/// read, and the line it names for an element it does not use is the element's line (the
/// line of each element was found by a scan from the file's start: 14 s for this file).
#[test]
fn a_ten_thousand_link_star_is_read_with_its_lines() {
    let t = TestDir::new("a_ten_thousand_link_star_is_read_with_its_lines");
    let inertial = "<inertial><mass value=\"0.1\"/><inertia ixx=\"0.01\" iyy=\"0.01\" \
                    izz=\"0.01\" ixy=\"0\" ixz=\"0\" iyz=\"0\"/></inertial>";
    let mut xml = format!("<robot name=\"star\">\n<link name=\"hub\">{inertial}</link>\n");
    for i in 0..9_999 {
        xml.push_str(&format!(
            "<link name=\"l{i}\">{inertial}</link>\n<joint name=\"j{i}\" type=\"fixed\">\
             <parent link=\"hub\"/><child link=\"l{i}\"/><origin xyz=\"{i} 0 0\"/></joint>\n"
        ));
    }
    // Line 2 + 2 × 9,999 + 1 = 20,001.
    xml.push_str("<sensor_rig/>\n</robot>\n");
    t.write("star.urdf", &xml);
    let run = t
        .vito()
        .args(["inspect", "star.urdf", "--base", "floating"])
        .assert_exit(0);
    // `inspect` lists the model's warnings in its report (standard output).
    assert!(
        run.stdout
            .contains("warning: line 20001: element <sensor_rig> is not used by vito"),
        "{}",
        run.stdout
    );
}

/// `robot.units` takes only known unit names: markup or a comma in a token is refused by
/// field, naming the units vito knows; known names load.
#[test]
fn robot_units_are_known_names_only() {
    for units in [
        "m kg s</text><script>alert(1)</script>",
        "m,x kg s",
        "m kg fortnight",
    ] {
        let text = hopper_text().replace(
            "gravity = [0.0, 0.0, -9.81]",
            &format!("gravity = [0.0, 0.0, -9.81]\nunits = {units:?}"),
        );
        let err = check_fails("robot_units_are_known_names_only", &text, &[]);
        assert!(
            err.contains("robot.units") && err.contains("give one of"),
            "{err}"
        );
    }
    let t = TestDir::with_hopper("robot_units_known_names_load");
    t.write(
        "ok.toml",
        &hopper_text().replace(
            "gravity = [0.0, 0.0, -9.81]",
            "gravity = [0.0, 0.0, -9.81e-3]\nunits = \"mm g ms\"",
        ),
    );
    t.vito().args(["check", "ok.toml"]).assert_exit(0);
}
