//! Issue 11, items 5–17: hostile or careless input ends in one clear error (exit 2) naming
//! the file and field, before any solving, with nothing written; one test per item at least.

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

/// Item 5: options that read or write files are refused in `check` and `solve`, naming the
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

/// Item 5: Ipopt never reads an `ipopt.opt` from the working directory (one that would stop
/// the solve after one iteration changes nothing), and `--ipopt-log` writes Ipopt's log into
/// the output directory.
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
    // Without the flag there is no log.
    t.vito()
        .args(["solve", "p.toml", "--quiet", "--out", "res"])
        .assert_exit(0);
    assert!(!t.path().join("res/ipopt.log").exists());
}

/// Item 9: non-finite numeric Ipopt options are input errors (`tol = nan` hung in MUMPS).
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

/// Item 7: a horizon whose NLP cannot fit in memory is refused by `check` and `solve`
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

/// Item 8: a horizon T = time_step·(knots − 1) that overflows is found at validation.
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

/// Item 12: extreme finite values are refused against the README's sane ranges, naming the
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

/// Items 12, 14, 15: bound ends that are not a range are blamed on the bound itself, not on
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

/// Item 10: a URDF nested 100,000 deep is an error naming the file and line in `inspect`,
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
    t.write("chain.urdf", &chain(10_000));
    let run = t
        .vito()
        .args(["inspect", "chain.urdf", "--json"])
        .assert_exit(0);
    assert!(run.stdout.contains("\"j9999\""));
    t.write("chain.urdf", &chain(10_001));
    let run = t.vito().args(["inspect", "chain.urdf"]).assert_exit(2);
    assert!(
        run.stderr
            .contains("chain.urdf: it has 10001 <link> elements"),
        "{}",
        run.stderr
    );
}

/// Item 11 and 14: a FIFO or a device as the problem file or the URDF is refused at once
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

/// Items 12 and 14: NaN or crossed URDF values are errors naming the URDF element (not
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

/// Item 15: what was accepted silently is an error naming the element.
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

/// Item 15: the URDF reader's warnings are shown by `check` (and `solve`), not only `inspect`.
#[test]
fn model_warnings_are_shown_by_check() {
    let t = TestDir::with_hopper("model_warnings");
    let u = hopper_urdf().replacen(" effort=\"10\" velocity=\"inf\"", " effort=\"10\"", 1);
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

/// Item 6: control characters in names the problem defines are refused; names from a URDF
/// are printed escaped.
#[test]
fn control_characters_never_reach_the_terminal() {
    let text = hopper_text().replace("name = \"hopper-2d\"", "name = \"hop\\u001b[31mper\"");
    let err = check_fails("control_in_name", &text, &[]);
    assert!(
        err.contains("field `name`") && err.contains("control characters"),
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

/// Items 1–4 (open part): `name` names `out/<name>`, so it is a plain file-name component.
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

/// Item 13: output paths that cannot work are exit 2 before solving, the solver never runs.
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

/// Item 17: `inspect`, `init` and `check` fail (exit 2, a message) when stdout cannot be
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
        assert_eq!(out.status.code(), Some(2), "{args:?}: {stderr}");
        assert!(
            stderr.contains("cannot write to standard output"),
            "{stderr}"
        );
    }
}

/// Item 16: a regression record's non-finite objective, unknown status or negative/NaN
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

/// Item 14: serde's messages in the problem file's words: a 3-vector of the wrong length
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
