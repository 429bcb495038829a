//! `vito simulate`: outputs in the solve's format, replaying a solved plan, and one clear
//! error (exit 2) for bad input before simulating.

use std::path::PathBuf;

use crate::cli::util::{TestDir, problems_dir, summary};

/// The brick of brick_3d.toml simulated for 1 s at 1 kHz: trajectory.csv with the solve's
/// columns, summary.json with the per-step record, the plots; it comes to rest on the ground.
#[test]
fn simulate_writes_trajectory_summary_and_plots() {
    let t = TestDir::new("simulate-brick");
    let out = t.path().join("out");
    let problem = problems_dir().join("brick_3d.toml");
    let run = t
        .vito()
        .args(
            [problem.as_os_str(), "--out".as_ref(), out.as_os_str()]
                .iter()
                .fold(vec![std::ffi::OsStr::new("simulate")], |mut v, a| {
                    v.push(a);
                    v
                }),
        )
        .args(["--rate", "1000", "--duration", "1", "--quiet"])
        .assert_exit(0);
    let s = summary(&out);
    assert_eq!(s["steps"], 1000, "{}", run.stdout);
    assert!(s["max_penetration"].as_f64().unwrap() <= 1e-6);
    assert!(s["max_dynamics_residual"].as_f64().unwrap() < 1e-9);
    assert!(
        s["energy"].is_null(),
        "contact dissipates: no drift to report"
    );
    let csv = std::fs::read_to_string(out.join("trajectory.csv")).unwrap();
    let header = csv.lines().next().unwrap();
    assert!(header.starts_with("time [s],base_x [m]"), "{header}");
    assert!(header.ends_with(",slack"), "{header}");
    assert_eq!(csv.lines().count(), 1002);
    // At rest on a face: base_z is a half-thickness (0.025, 0.05 or 0.1 m) above the ground.
    let last: Vec<f64> = csv
        .lines()
        .last()
        .unwrap()
        .split(',')
        .take(4)
        .map(|x| x.parse().unwrap())
        .collect();
    assert!(
        [0.025, 0.05, 0.1]
            .iter()
            .any(|h| (last[3] - h).abs() < 1e-6),
        "rest height {}",
        last[3]
    );
    // The brick has no inputs: no (empty) inputs.svg, and the summary says so in one line.
    assert!(!out.join("inputs.svg").exists());
    let said: Vec<&str> = run
        .stdout
        .lines()
        .filter(|l| l.contains("inputs.svg"))
        .collect();
    assert_eq!(
        said,
        ["plots          no inputs.svg (the robot has no inputs)"],
        "{}",
        run.stdout
    );
    for svg in ["coordinates.svg", "contact_modes.svg"] {
        assert!(out.join(svg).is_file(), "{svg}");
    }
}

/// Bad options end with one message naming the option and exit 2, before anything is
/// written.
#[test]
fn simulate_rejects_bad_input_before_simulating() {
    let t = TestDir::with_hopper("simulate-errors");
    t.write("hopper.toml", &crate::cli::util::hopper_text());
    let out = t.path().join("out");
    let cases: [(&[&str], &str); 4] = [
        (&["--rate=-5"], "--rate"),
        (&["--duration", "nan"], "--duration"),
        (&["--inputs", "missing.csv"], "missing.csv"),
        (&["--track", "plan.csv", "--gains", "elbow=1,1"], "elbow"),
    ];
    t.write(
        "plan.csv",
        "time [s],x [m],z [m],theta [rad],r [m],u_theta [N·m],u_r [N]\n0,0,0.5,0,0.5,0,0\n1,0,0.5,0,0.5,,\n",
    );
    for (args, named) in cases {
        let run = t
            .vito()
            .args(["simulate", "hopper.toml", "--quiet", "--out"])
            .args([out.as_os_str()])
            .args(args)
            .assert_exit(2);
        assert!(run.stderr.contains(named), "{args:?}: {}", run.stderr);
        assert_eq!(
            run.stderr
                .lines()
                .filter(|l| l.starts_with("error"))
                .count(),
            1
        );
        assert!(!out.exists(), "{args:?} wrote output");
    }
}

/// A two-knot hopper plan (the leg swings 0.1 rad and shortens 5 cm in 50 ms, no
/// feed-forward input) for the tracking tests.
const HOPPER_SWING_PLAN: &str = "time [s],x [m],z [m],theta [rad],r [m],u_theta [N·m],u_r [N]\n\
    0,0,0.5,0,0.5,0,0\n0.05,0,0.5,0.1,0.45,,\n";

/// `vito simulate FILE --quiet --track plan.csv --rate 2000 --out OUT EXTRA…` in `t`, which
/// succeeds; the directory it wrote.
fn tracked(t: &TestDir, file: &str, extra: &[&str], out: &str) -> PathBuf {
    t.vito()
        .args(["simulate", file, "--quiet", "--track", "plan.csv"])
        .args(["--rate", "2000", "--out", out])
        .args(extra)
        .assert_exit(0);
    t.path().join(out)
}

/// `vito simulate FILE --quiet --track plan.csv --out OUT` in `t`, which is refused (exit 2)
/// naming the file, with nothing written; its standard error.
fn refused(t: &TestDir, file: &str, out: &str) -> String {
    let out = t.path().join(out);
    let failed = t
        .vito()
        .args(["simulate", file, "--quiet", "--track", "plan.csv", "--out"])
        .args([out.as_os_str()])
        .assert_exit(2);
    assert!(failed.stderr.contains(file), "{}", failed.stderr);
    assert!(!out.exists());
    failed.stderr
}

/// `[tracking] gains` in the problem file: the same simulation as the same gains given with
/// `--gains` (byte-identical trajectory); `--gains` overrides the file per input; an unknown
/// input name or a negative gain in the file, or `--track` without any gains, is one error
/// naming the file and field (exit 2) before anything is written.
#[test]
fn simulate_tracks_with_the_files_gains() {
    let t = TestDir::with_hopper("simulate-file-gains");
    let hopper = crate::cli::util::hopper_text();
    t.write("hopper.toml", &hopper);
    t.write(
        "gains.toml",
        &format!("{hopper}\n[tracking]\ngains = {{ all = [1000, 50], theta = [50, 5] }}\n"),
    );
    t.write("plan.csv", HOPPER_SWING_PLAN);
    let run = |file: &str, extra: &[&str], out: &str| {
        std::fs::read_to_string(tracked(&t, file, extra, out).join("trajectory.csv")).unwrap()
    };
    let from_file = run("gains.toml", &[], "file");
    let from_cli = run(
        "hopper.toml",
        &["--gains", "r=1000,50", "--gains", "theta=50,5"],
        "cli",
    );
    assert_eq!(from_file, from_cli);
    let overridden = run("gains.toml", &["--gains", "theta=0,0"], "override");
    assert_ne!(from_file, overridden, "--gains theta=0,0 changed nothing");

    for (text, named) in [
        ("gains = { elbow = [1, 1] }", "tracking.gains.elbow"),
        ("gains = { theta = [-1, 1] }", "tracking.gains.theta"),
        ("gain = { theta = [1, 1] }", "gain"),
    ] {
        t.write("bad.toml", &format!("{hopper}\n[tracking]\n{text}\n"));
        let stderr = refused(&t, "bad.toml", "bad-out");
        assert!(stderr.contains(named), "{named}: {stderr}");
    }
    let stderr = refused(&t, "hopper.toml", "none-out");
    assert!(stderr.contains("--gains"), "{stderr}");
    assert!(stderr.contains("[tracking] gains"), "{stderr}");
}

/// `[tracking] feedback = "implicit"` in the problem file runs the same simulation as
/// `--feedback implicit` (byte-identical trajectory), different from the explicit law at the
/// same gains, and summary.json names the law; `--feedback explicit` overrides the file; an
/// unknown value in the file is one error naming the file and field (exit 2).
#[test]
fn simulate_feedback_law_from_the_file_or_the_command_line() {
    let t = TestDir::with_hopper("simulate-feedback");
    let hopper = crate::cli::util::hopper_text();
    let gains = "[tracking]\ngains = { all = [1000, 50], theta = [50, 5] }\n";
    t.write("hopper.toml", &format!("{hopper}\n{gains}"));
    t.write(
        "implicit.toml",
        &format!("{hopper}\n{gains}feedback = \"implicit\"\n"),
    );
    t.write("plan.csv", HOPPER_SWING_PLAN);
    let run = |file: &str, extra: &[&str], out: &str| {
        let dir = tracked(&t, file, extra, out);
        let read = |name: &str| std::fs::read_to_string(dir.join(name)).unwrap();
        (read("trajectory.csv"), read("summary.json"))
    };
    let (from_file, summary) = run("implicit.toml", &[], "file");
    let (from_cli, _) = run("hopper.toml", &["--feedback", "implicit"], "cli");
    let (explicit, explicit_summary) = run("hopper.toml", &[], "explicit");
    let (overridden, _) = run("implicit.toml", &["--feedback", "explicit"], "override");
    assert_eq!(from_file, from_cli);
    assert_ne!(from_file, explicit, "the implicit law changed nothing");
    assert_eq!(overridden, explicit);
    assert!(summary.contains("\"feedback\": \"implicit\""), "{summary}");
    assert!(
        explicit_summary.contains("\"feedback\": \"explicit\""),
        "{explicit_summary}"
    );

    t.write(
        "bad.toml",
        &format!("{hopper}\n{gains}feedback = \"backward\"\n"),
    );
    let stderr = refused(&t, "bad.toml", "bad-out");
    assert!(stderr.contains("tracking.feedback"), "{stderr}");
}

/// At gains the explicit PD law cannot hold at 2 kHz (kp 1e6, kd 1e4 on the hopper), the run
/// stops as diverged, naming the coordinate and the remedies (exit 1), and writes nothing:
/// before the bound, the step solver's momentum-scaled tolerance accepted states 1e22 m
/// deep in the ground and the run exited 0. The implicit law runs the same gains through.
#[test]
fn simulate_stops_a_diverging_run() {
    let t = TestDir::with_hopper("simulate-diverges");
    t.write("hopper.toml", &crate::cli::util::hopper_text());
    t.write("plan.csv", HOPPER_SWING_PLAN);
    let run = |feedback: &str, out: &str, code: i32| {
        t.vito()
            .args(["simulate", "hopper.toml", "--quiet", "--track", "plan.csv"])
            .args([
                "--gains",
                "all=1e6,1e4",
                "--rate",
                "2000",
                "--duration",
                "0.2",
            ])
            .args(["--feedback", feedback, "--out", out])
            .assert_exit(code)
    };
    let failed = run("explicit", "explicit", 1);
    for text in ["diverged", "moves at", "--feedback implicit"] {
        assert!(failed.stderr.contains(text), "{text}: {}", failed.stderr);
    }
    assert!(!t.path().join("explicit").exists());
    run("implicit", "implicit", 0);
    assert!(t.path().join("implicit/trajectory.csv").exists());
}

/// `vito simulate --integrator galerkin4` on the brick problem (whose `[solver]` names the
/// midpoint rule): the summary names galerkin4, and the brick dropped onto the ground comes to
/// rest without penetrating it.
#[test]
fn simulate_steps_the_galerkin4_integrator() {
    let t = TestDir::new("simulate-galerkin4");
    let out = t.path().join("out");
    let problem = problems_dir().join("brick_3d.toml");
    let run = t
        .vito()
        .args([
            "simulate".as_ref(),
            problem.as_os_str(),
            "--out".as_ref(),
            out.as_os_str(),
        ])
        .args([
            "--integrator",
            "galerkin4",
            "--rate",
            "1000",
            "--duration",
            "0.5",
        ])
        .args(["--quiet"])
        .assert_exit(0);
    let s = summary(&out);
    assert_eq!(s["integrator"], "galerkin4", "{}", run.stdout);
    assert_eq!(s["steps"], 500);
    assert!(s["max_penetration"].as_f64().unwrap() <= 1e-6);
    assert!(s["max_dynamics_residual"].as_f64().unwrap() < 1e-9);
}

/// The hopper planned with `solver.integrator = "galerkin4"` (interior points as NLP
/// variables) and its inputs replayed by `vito simulate` with the same integrator (interior
/// points solved inside each step): the simulated configurations equal the plan's at every
/// knot to the solver's tolerance (measured 4e-10 m at the first knot), and both summaries
/// name galerkin4.
#[test]
fn galerkin4_plan_replays_in_simulate() {
    let t = TestDir::with_hopper("galerkin4-replay");
    t.write("p.toml", &crate::cli::util::hopper_text());
    let set = ["--set", "solver.integrator=galerkin4"];
    t.vito()
        .args(["solve", "p.toml", "--quiet", "--out", "plan"])
        .args(set)
        .assert_exit(0);
    t.vito()
        .args(["simulate", "p.toml", "--quiet", "--out", "sim"])
        .args(["--inputs", "plan/trajectory.csv"])
        .args(set)
        .assert_exit(0);
    let plan = summary(&t.path().join("plan"));
    assert_eq!(plan["solved"], true, "{plan}");
    assert_eq!(plan["integrator"], "galerkin4");
    assert_eq!(summary(&t.path().join("sim"))["integrator"], "galerkin4");
    // Their overlay's legend: the plan is a plan (its summary names an integrator too), the
    // simulation a simulation, with its integrator and duration.
    t.vito()
        .args(["view", "plan", "sim", "--out", "both.html"])
        .assert_exit(0);
    let page = std::fs::read_to_string(t.path().join("both.html")).unwrap();
    let data = crate::view::page_data_of(&page);
    let legend = |i: usize| {
        let track = &data["tracks"][i];
        (
            track["standing"].as_str().unwrap().to_owned(),
            track["detail"].as_str().unwrap().to_owned(),
        )
    };
    let (standing, detail) = legend(0);
    assert_eq!(standing, "solved");
    assert!(
        detail.starts_with("plan, solve_succeeded, objective "),
        "{detail}"
    );
    assert_eq!(
        legend(1),
        (
            "simulation".to_owned(),
            "simulation (galerkin4), 1 s, 20 steps".to_owned()
        )
    );
    let read = |dir: &str| -> Vec<Vec<f64>> {
        let text = std::fs::read_to_string(t.path().join(dir).join("trajectory.csv")).unwrap();
        text.lines()
            .skip(1)
            .map(|line| {
                line.split(',')
                    .take(5)
                    .map(|v| v.parse().unwrap())
                    .collect()
            })
            .collect()
    };
    let (planned, simulated) = (read("plan"), read("sim"));
    assert_eq!(planned.len(), 21);
    assert_eq!(simulated.len(), 21);
    for (k, (p, s)) in planned.iter().zip(&simulated).enumerate() {
        // Columns: time, then the hopper's four coordinates.
        assert!(
            (p[0] - s[0]).abs() < 1e-12,
            "knot {k}: times {} and {}",
            p[0],
            s[0]
        );
        let error = p[1..]
            .iter()
            .zip(&s[1..])
            .fold(0.0_f64, |a, (x, y)| a.max((x - y).abs()));
        assert!(
            error < 1e-6,
            "knot {k}: simulated q differs from the plan by {error:e}"
        );
    }
}

/// Spring Flamingo at 2 kHz with the Galerkin members (h = 0.5 ms: the interior points'
/// stationarity sums momenta over h whose round-off, ~1e-11, is above a tolerance relative to
/// the end momenta): the interior Newton accepts its round-off floor instead of stopping the
/// simulation, and the steps' residuals stay at round-off.
#[test]
fn galerkin_steps_converge_at_the_round_off_floor() {
    let t = TestDir::new("simulate-galerkin-floor");
    let problem = problems_dir().join("spring_flamingo_walk.toml");
    for name in ["galerkin4", "galerkin6"] {
        let out = t.path().join(name);
        t.vito()
            .args(["simulate".as_ref(), problem.as_os_str(), "--out".as_ref()])
            .args([out.as_os_str()])
            .args(["--integrator", name, "--rate", "2000", "--duration", "0.05"])
            .args(["--quiet"])
            .assert_exit(0);
        let s = summary(&out);
        assert_eq!(s["steps"], 100);
        let residual = s["max_dynamics_residual"].as_f64().unwrap();
        assert!(residual < 1e-8, "{name}: residual {residual}");
    }
}

/// SIGTERM, SIGINT or SIGHUP stops a simulation after its current step: the steps made are
/// written (`stopped_by_signal` in the summary, the CSV's rows those knots) and the exit code
/// is 1, as `--help` says. The signal is sent once the run has said it started (its first
/// line on stderr, printed after its stop handler is in place: the process's signal mask
/// alone is no sign, since a library may catch a signal before vito does, as Debian 13's
/// OpenMPI catches SIGHUP). The run checks for a stop after each step, so it has made at
/// least one, and its 10^6 steps (minutes) cannot all be made before the signal arrives: no
/// timing decides the outcome.
#[test]
#[cfg(unix)]
fn signals_keep_the_simulated_part_and_exit_1() {
    use std::io::{BufRead, BufReader};
    for (signal, name) in [
        (rustix::process::Signal::TERM, "TERM"),
        (rustix::process::Signal::INT, "INT"),
        (rustix::process::Signal::HUP, "HUP"),
    ] {
        // The brick at rest on the ground: 10^6 steps of 1 ms, minutes.
        let t = TestDir::new("signals_keep_the_simulated_part_and_exit_1");
        let mut child = std::process::Command::new(env!("CARGO_BIN_EXE_vito"))
            .current_dir(t.path())
            .arg("simulate")
            .arg(problems_dir().join("brick_3d.toml"))
            .args(["--duration", "1000", "--rate", "1000"])
            .args(["--out", "r"])
            .stdout(std::process::Stdio::null())
            .stderr(std::process::Stdio::piped())
            .spawn()
            .unwrap();
        let mut lines = BufReader::new(child.stderr.take().unwrap()).lines();
        let started = lines
            .by_ref()
            .map(|l| l.unwrap())
            .find(|l| l.starts_with("simulating brick-3d: 1000000 steps"));
        assert!(started.is_some(), "{name}: the run never said it started");
        // Ask it to stop at once: the step in progress always completes, so one step or
        // more is written however soon the signal arrives.
        rustix::process::kill_process(rustix::process::Pid::from_child(&child), signal).unwrap();
        let reader = std::thread::spawn(move || lines.map(|l| l.unwrap()).collect::<Vec<_>>());
        let status = crate::cli::util::wait_after_stop(child);
        let stderr = reader.join().unwrap().join("\n");
        assert_eq!(status.code(), Some(1), "{name}: {stderr}");
        assert!(
            stderr.contains("interrupted: stopping after the current step"),
            "{name}: {stderr}"
        );
        let s = summary(&t.path().join("r"));
        assert_eq!(
            s["stopped_by_signal"]["steps_requested"], 1_000_000,
            "{name}"
        );
        let steps = s["steps"].as_u64().unwrap();
        assert!(steps > 0 && steps < 1_000_000, "{name}: {steps}");
        let csv = std::fs::read_to_string(t.path().join("r/trajectory.csv")).unwrap();
        assert_eq!(csv.lines().count() as u64, steps + 2, "{name}");
    }
}

/// `vito simulate`'s trajectory.csv gives each contact point's world position on every row,
/// under the plan's column names: on the hopper replaying its committed plan at 200 Hz, the
/// foot is where q puts it by hand, (x + r sin θ, 0, z − r cos θ), and its height above the
/// flat ground is the row's signed distance.
#[test]
fn simulate_writes_each_contacts_world_position() {
    let t = TestDir::with_hopper("simulate-contact-positions");
    t.write("hopper.toml", &crate::cli::util::hopper_text());
    let plan = std::path::Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("results/motion/hopper_2d/trajectory.csv");
    t.vito()
        .args([
            "simulate",
            "hopper.toml",
            "--quiet",
            "--rate",
            "200",
            "--inputs",
        ])
        .args([plan.as_os_str()])
        .args(["--out", "out"])
        .assert_exit(0);
    let csv = std::fs::read_to_string(t.path().join("out/trajectory.csv")).unwrap();
    let header = csv.lines().next().unwrap();
    assert!(
        header.contains(
            "foot_contact_distance [m],foot_contact_x [m],foot_contact_y [m],foot_contact_z [m],"
        ),
        "{header}"
    );
    let table = vito::files::trajectory_csv::read_csv(&csv).unwrap();
    let col = |name: &str| table.column(name).unwrap_or_else(|| panic!("{name}"));
    let (x, z, theta, r) = (col("x"), col("z"), col("theta"), col("r"));
    let (fx, fy, fz, distance) = (
        col("foot_contact_x"),
        col("foot_contact_y"),
        col("foot_contact_z"),
        col("foot_contact_distance"),
    );
    assert_eq!(table.rows(), 201);
    let mut lowest = f64::MAX;
    for k in 0..table.rows() {
        let foot = [
            x[k] + r[k] * theta[k].sin(),
            0.0,
            z[k] - r[k] * theta[k].cos(),
        ];
        for (axis, (got, want)) in [fx[k], fy[k], fz[k]].iter().zip(foot).enumerate() {
            assert!(
                (got - want).abs() < 1e-12,
                "row {k} axis {axis}: {got} against {want}"
            );
        }
        assert!((fz[k] - distance[k]).abs() < 1e-12, "row {k}");
        lowest = lowest.min(fz[k]);
    }
    // The replay touches the ground and leaves it: the rows are not all one pose.
    assert!(lowest.abs() < 1e-6, "lowest foot height {lowest}");
    assert!(fx[200] - fx[0] > 0.1, "the foot moved {}", fx[200] - fx[0]);
}
