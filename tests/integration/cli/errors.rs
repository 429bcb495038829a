//! Bad input: each gives one clear error naming file, line and field, exit code 2, and an
//! existing output directory is left untouched.

use crate::cli::util::{TestDir, hopper_text};

/// Writes `text` as `bad.toml`, runs `vito solve bad.toml --out out` over an existing `out/`
/// and returns stderr after checking exit 2, a single error line and the untouched directory.
pub(crate) fn solve_fails(name: &str, text: &str) -> String {
    let t = TestDir::with_hopper(name);
    t.write("bad.toml", text);
    std::fs::create_dir(t.path().join("out")).unwrap();
    t.write("out/keep.txt", "previous results");
    let run = t
        .vito()
        .args(["solve", "bad.toml", "--out", "out"])
        .assert_exit(2);
    let errors: Vec<&str> = run
        .stderr
        .lines()
        .filter(|l| l.starts_with("error:"))
        .collect();
    assert_eq!(errors.len(), 1, "one error expected:\n{}", run.stderr);
    assert_eq!(
        std::fs::read_to_string(t.path().join("out/keep.txt")).unwrap(),
        "previous results"
    );
    assert_eq!(std::fs::read_dir(t.path().join("out")).unwrap().count(), 1);
    // Nothing else appeared next to it (no staging directory left behind).
    let entries: Vec<_> = std::fs::read_dir(t.path())
        .unwrap()
        .map(|e| e.unwrap().file_name().into_string().unwrap())
        .collect();
    assert!(entries.iter().all(|e| !e.starts_with('.')), "{entries:?}");
    run.stderr
}

#[test]
fn toml_syntax_error() {
    let text = hopper_text().replace("knots = 21", "knots = 21 x");
    let err = solve_fails("toml_syntax_error", &text);
    assert!(err.contains("bad.toml:18"), "{err}");
    assert!(err.contains("TOML syntax error"), "{err}");
}

#[test]
fn unknown_key_suggests_the_nearest() {
    let text = hopper_text().replace("friction = 0.8", "frition = 0.8");
    let err = solve_fails("unknown_key_suggests_the_nearest", &text);
    assert!(
        err.contains("bad.toml:15: field `contacts.frition`"),
        "{err}"
    );
    assert!(err.contains("did you mean `friction`?"), "{err}");
}

#[test]
fn unknown_joint_name() {
    let text = hopper_text().replace(
        "weights = { theta = 0.1, r = 0.01 }",
        "weights = { theta = 0.1, rr = 0.01 }",
    );
    let err = solve_fails("unknown_joint_name", &text);
    assert!(
        err.contains("field `cost[1].weights.rr`: unknown input `rr`, did you mean `r`?"),
        "{err}"
    );
    let text = hopper_text().replace(
        "q = { x = 0.0, z = 0.5, theta = 0.0, r = 0.5 }",
        "q = { x = 0.0, z = 0.5, tehta = 0.0, r = 0.5 }",
    );
    let err = solve_fails("unknown_joint_name_2", &text);
    assert!(err.contains("bad.toml:22: field `initial.q.tehta`: unknown coordinate `tehta`, did you mean `theta`?"), "{err}");
}

#[test]
fn missing_urdf() {
    let text = hopper_text().replace("robots/hopper_2d.urdf", "robots/hoper.urdf");
    let err = solve_fails("missing_urdf", &text);
    assert!(err.contains("bad.toml:8: field `robot.urdf`"), "{err}");
    assert!(err.contains("hoper.urdf does not exist"), "{err}");
}

#[test]
fn negative_time_step() {
    let text = hopper_text().replace("time_step = 0.05 ", "time_step = -0.05 ");
    let err = solve_fails("negative_time_step", &text);
    assert!(
        err.contains(
            "bad.toml:19: field `horizon.time_step`: must be a number in [1e-12, 1e12], got -0.05"
        ),
        "{err}"
    );
}

#[test]
fn inconsistent_vector_length() {
    let text = hopper_text().replace(
        "q = { x = 0.0, z = 0.5, theta = 0.0, r = 0.5 }",
        "q = [0.0, 0.5, 0.0]",
    );
    let err = solve_fails("inconsistent_vector_length", &text);
    assert!(
        err.contains(
            "bad.toml:22: field `initial.q`: has 3 values but the robot has 4 coordinates"
        ),
        "{err}"
    );
}

#[test]
fn bad_override_names_the_setting() {
    let t = TestDir::with_hopper("bad_override_names_the_setting");
    t.write("p.toml", &hopper_text());
    let run = t
        .vito()
        .args(["check", "p.toml", "--set", "slack.wieght=3"])
        .assert_exit(2);
    assert!(
        run.stderr.contains(
            "field `slack.wieght` (set with --set): unknown key `wieght`, did you mean `weight`?"
        ),
        "{}",
        run.stderr
    );
    let run = t
        .vito()
        .args(["check", "p.toml", "--set", "slack.weight"])
        .assert_exit(2);
    assert!(
        run.stderr
            .contains("--set slack.weight: expected key.path=value"),
        "{}",
        run.stderr
    );
}

#[test]
fn missing_problem_file_and_usage_errors_exit_2() {
    let t = TestDir::new("missing_problem_file_and_usage_errors_exit_2");
    let run = t.vito().args(["check", "nope.toml"]).assert_exit(2);
    assert!(
        run.stderr.contains("cannot read problem file nope.toml"),
        "{}",
        run.stderr
    );
    t.vito().args(["solve"]).assert_exit(2);
    t.vito().args(["frobnicate"]).assert_exit(2);
}

#[test]
fn infeasible_bounds_name_the_coordinate() {
    let text = hopper_text().replace("theta = 0.0, r = 0.5 }", "theta = 0.0, r = 0.8 }");
    let err = solve_fails("infeasible_bounds_name_the_coordinate", &text);
    assert!(
        err.contains(
            "bad.toml:22: field `initial.q.r`: q_1 r = 0.8 is outside URDF limits [0.3, 0.7]"
        ),
        "{err}"
    );
    let text = hopper_text().replace("lower = 0.3\nupper = 0.7", "lower = 0.6\nupper = 0.7");
    let err = solve_fails("infeasible_bounds_name_the_coordinate_2", &text);
    assert!(err.contains("field `initial.q.r`"), "{err}");
}

/// Ipopt itself checks `[solver.ipopt]` before any solve; a typo names its line.
#[test]
fn ipopt_option_typo() {
    let text = hopper_text().replace("mu_strategy = \"adaptive\"", "mu_strategy = \"adaptiv\"");
    let err = solve_fails("ipopt_option_typo", &text);
    assert!(err.contains("bad.toml:70: field `solver.ipopt.mu_strategy`: Ipopt option `mu_strategy` = \"adaptiv\" is invalid"), "{err}");
    let text = hopper_text().replace("linear_solver = \"mumps\"", "linear_solver = \"ma97\"");
    let err = solve_fails("ipopt_option_typo_2", &text);
    assert!(err.contains("field `solver.ipopt.linear_solver`"), "{err}");
}

/// `vito check x | head -1` ends quietly with success when stdout closes.
#[test]
fn broken_pipe_is_not_an_error() {
    let t = TestDir::with_hopper("broken_pipe_is_not_an_error");
    t.write("p.toml", &hopper_text());
    let mut child = std::process::Command::new(env!("CARGO_BIN_EXE_vito"))
        .args(["check", "p.toml"])
        .current_dir(t.path())
        .stdout(std::process::Stdio::piped())
        .stderr(std::process::Stdio::piped())
        .spawn()
        .unwrap();
    drop(child.stdout.take());
    let out = child.wait_with_output().unwrap();
    assert_eq!(
        out.status.code(),
        Some(0),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
}

/// A solve whose stdout and stderr readers have gone (`vito solve p.toml 2>&1 | head -1`)
/// still writes its results and exits with its verdict's code: 1 for a solve stopped at its
/// iteration limit, neither a success nor an output failure.
#[test]
fn closed_pipes_leave_the_verdicts_exit_code() {
    let t = TestDir::with_hopper("closed_pipes_leave_the_verdicts_exit_code");
    t.write("p.toml", &hopper_text());
    let mut child = std::process::Command::new(env!("CARGO_BIN_EXE_vito"))
        .args(["solve", "p.toml", "--out", "out"])
        .args(["--set", "solver.ipopt.max_iter=2"])
        .current_dir(t.path())
        .stdout(std::process::Stdio::piped())
        .stderr(std::process::Stdio::piped())
        .spawn()
        .unwrap();
    drop(child.stdout.take());
    drop(child.stderr.take());
    assert_eq!(child.wait().unwrap().code(), Some(1));
    let s = crate::cli::util::summary(&t.path().join("out"));
    assert_eq!(s["status"], "maximum_iterations_exceeded", "{s}");
}

/// The continuation's and the ψ bound's settings are checked like every other field.
#[test]
fn bad_slack_target_and_slip_speed() {
    let text = hopper_text().replace(
        "mode = \"per_interval\"",
        "mode = \"per_interval\"\ntarget = -1e-5",
    );
    let err = solve_fails("bad_slack_target", &text);
    assert!(
        err.contains("field `slack.target`: must be a number in [1e-12, 1e12], got -0.00001"),
        "{err}"
    );
    let text = hopper_text().replace(
        "mode = \"per_interval\"",
        "mode = \"per_interval\"\ngrowth = 10.0",
    );
    let err = solve_fails("slack_growth_without_target", &text);
    assert!(
        err.contains("field `slack.growth`: has no effect without `slack.target`"),
        "{err}"
    );
    let text = hopper_text().replace(
        "mode = \"per_interval\"",
        "mode = \"per_interval\"\ntied_tolerances = true",
    );
    let err = solve_fails("slack_tied_tolerances_without_target", &text);
    assert!(
        err.contains(
            "field `slack.tied_tolerances`: has no effect without `slack.target` or \
             `slack.homotopy = true`"
        ),
        "{err}"
    );
    // `false` asks for what happens anyway (one solve, or the continuation at the file's
    // tolerances), so it is accepted with or without a continuation: a script can switch a
    // file that sets the tied homotopy back to one solve.
    let t = TestDir::with_hopper("slack_tied_tolerances_false_without_target");
    t.write(
        "plain.toml",
        &hopper_text().replace(
            "mode = \"per_interval\"",
            "mode = \"per_interval\"\nhomotopy = false\ntied_tolerances = false",
        ),
    );
    t.vito().args(["check", "plain.toml"]).assert_exit(0);
    let text = hopper_text().replace("friction = 0.8", "friction = 0.8\nmax_slip_speed = 0.0");
    let err = solve_fails("zero_slip_speed", &text);
    assert!(
        err.contains("field `contacts.max_slip_speed`: must be a number in [1e-12, 1e12], got 0"),
        "{err}"
    );
}

#[test]
fn terrain_and_cost_entries_name_their_field() {
    // Each terrain kind and cost term checks its own entry (contact/terrain/, problem/costs/).
    let step = hopper_text().replace(
        "[horizon]",
        "[[terrain.step]]\nedge_x = 0.5\nrise = 0.1\nwidth = -0.01\n\n[horizon]",
    );
    let err = solve_fails("terrain_step_width", &step);
    assert!(
        err.contains("field `terrain.step[0].width`: must be") && err.contains("got -0.01"),
        "{err}"
    );
    let time = hopper_text().replace(
        "[horizon]",
        "[[cost]]\ntype = \"time\"\nweight = -1.0\n\n[horizon]",
    );
    let err = solve_fails("cost_time_weight", &time);
    assert!(
        err.contains("cost[0].weight`: must be") && err.contains("got -1"),
        "{err}"
    );
    let unknown = hopper_text().replace(
        "[horizon]",
        "[[cost]]\ntype = \"time\"\nwieght = 1.0\n\n[horizon]",
    );
    let err = solve_fails("cost_unknown_key", &unknown);
    assert!(err.contains("unknown key `wieght`"), "{err}");
}

/// `impulse_rate`: its weight is a finite number ≥ 0, its weights name the problem's contacts,
/// exactly one of the two is given, and no other key: each is one error naming the file, line
/// and field, exit 2.
#[test]
fn impulse_rate_bad_weights_name_their_field() {
    for (name, keys, expected) in [
        (
            "impulse_rate_negative_weight",
            "weight = -0.5",
            "bad.toml:19: field `cost[0].weight`: must be a number in [0, 1e12], got -0.5",
        ),
        (
            "impulse_rate_nan_weight",
            "weight = nan",
            "bad.toml:19: field `cost[0].weight`: must be a number in [0, 1e12], got NaN",
        ),
        (
            "impulse_rate_negative_contact_weight",
            "weights = { default = 1.0, foot_contact = -2.0 }",
            "field `cost[0].weights`: weight of `foot_contact` is -2; weights must be ≥ 0",
        ),
        (
            "impulse_rate_unknown_contact",
            "weights = { foot_contat = 1.0 }",
            "field `cost[0].weights.foot_contat`: unknown contact `foot_contat`, did you mean `foot_contact`?",
        ),
        (
            "impulse_rate_both",
            "weight = 1.0\nweights = { foot_contact = 1.0 }",
            "bad.toml:20: field `cost[0].weights`: both `weight` and `weights` are given",
        ),
        (
            "impulse_rate_neither",
            "",
            "bad.toml:17: field `cost[0].weight`: missing; give `weight = w` (every contact)",
        ),
        (
            "impulse_rate_unknown_key",
            "weigth = 1.0",
            "field `cost[0]`: unknown key `weigth`, did you mean `weight`?",
        ),
    ] {
        cost_entry_fails(name, "[horizon]", "impulse_rate", keys, expected);
    }
}

/// The hopper with a `[[cost]]` entry of `kind` with `keys` inserted before `section` fails
/// (as [`solve_fails`]) with an error containing `expected`.
fn cost_entry_fails(name: &str, section: &str, kind: &str, keys: &str, expected: &str) {
    let entry = format!("[[cost]]\ntype = \"{kind}\"\n{keys}\n\n{section}");
    let err = solve_fails(name, &hopper_text().replace(section, &entry));
    assert!(err.contains(expected), "{name}: {err}");
}

/// `final_velocity` resolves its weights and target by coordinate name like the other terms:
/// an unknown name is one error naming the file, line, field and the nearest name.
#[test]
fn final_velocity_unknown_coordinate() {
    for (name, key, expected) in [
        (
            "final_velocity_unknown_weight",
            "weights = { z = 1.0, tehta = 2.0 }",
            "bad.toml:57: field `cost[2].weights.tehta`: unknown coordinate `tehta`, did you mean `theta`?",
        ),
        (
            "final_velocity_unknown_target",
            "weights = { default = 1.0 }\nv_target = { zz = 0.0 }",
            "field `cost[2].v_target.zz`: unknown coordinate `zz`, did you mean `z`?",
        ),
        (
            "final_velocity_negative_weight",
            "weights = { default = 1.0, r = -1.0 }",
            "field `cost[2].weights`: weight of `r` is -1; weights must be ≥ 0",
        ),
    ] {
        cost_entry_fails(name, "[slack]", "final_velocity", key, expected);
    }
}

#[test]
fn family_expression_errors_name_file_and_field() {
    let family = hopper_text().replace("friction = 0.8", "friction = \"= mu / scale\"")
        + "\n[parameters]\nmu = 0.8\nscale = 1\n";
    let err = solve_fails(
        "family_expression_errors_unknown",
        &family.replace("= mu / scale", "= mu / sclae"),
    );
    assert!(
        err.contains("bad.toml:15: field `contacts.friction`")
            && err.contains("unknown parameter `sclae`, did you mean `scale`?"),
        "{err}"
    );
    let t = TestDir::with_hopper("family_expression_errors_name_file_and_field");
    t.write("p.toml", &family);
    t.vito().args(["check", "p.toml"]).assert_exit(0);
    let run = t
        .vito()
        .args(["check", "p.toml", "--set", "scale=0"])
        .assert_exit(2);
    assert!(
        run.stderr.contains("field `contacts.friction`") && run.stderr.contains("inf"),
        "{}",
        run.stderr
    );
    let run = t
        .vito()
        .args(["check", "p.toml", "--set", "scale=1", "--set", "mu=0.25"])
        .assert_exit(0);
    assert!(run.stdout.contains("(mu 0.25)"), "{}", run.stdout);
}
