//! Answers a researcher can trust: a relaxed plan is not solved, a failed solve names its
//! worst rows, the trajectory file's columns mean what their names say, and one input gives
//! one answer whatever the machine's thread settings.

use std::path::{Path, PathBuf};

use crate::cli::util::{TestDir, problems_dir, summary};

/// `tests/data/problems/`: fixture problems.
fn fixture(name: &str) -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("tests/data/problems")
        .join(name)
}

fn solve(t: &TestDir, file: &Path, extra: &[&str], code: i32) -> (PathBuf, crate::cli::util::Run) {
    let out = t.path().join("out");
    let mut args: Vec<String> = vec![
        "solve".into(),
        file.display().to_string(),
        "--out".into(),
        out.display().to_string(),
        "--quiet".into(),
    ];
    args.extend(extra.iter().map(|s| s.to_string()));
    let run = t.vito().args(&args).assert_exit(code);
    (out, run)
}

/// The hopper jumping onto a 0.15 m platform from its linear guess: Ipopt reports an optimum
/// (`solve_succeeded`) of the relaxed problem whose slack is 0.034 (0.044 with Ipopt 3.14), the
/// foot pushing while above the ground. That is `relaxed_contact`, exit 1, with the contact, interval and slack named
/// and what to try; `summary.json` says so too.
#[test]
fn platform_hop_with_open_slack_is_relaxed_contact_not_solved() {
    let t = TestDir::new("relaxed-contact");
    let (out, run) = solve(&t, &fixture("hop_up.toml"), &[], 1);
    for text in [
        "status       relaxed_contact (Ipopt: solve_succeeded)",
        "contact `foot_contact` at interval ",
        "above slack.tolerance 1e-4",
        "--starts",
        "warm start",
        "slack weight",
    ] {
        assert!(run.stdout.contains(text), "{text:?} in\n{}", run.stdout);
    }
    let s = summary(&out);
    assert_eq!(s["status"], "relaxed_contact");
    assert_eq!(s["solved"], false);
    assert_eq!(s["ipopt_status"], "solve_succeeded");
    assert_eq!(s["slack_tolerance"], 1e-4);
    assert!(
        s["max_slack"].as_f64().unwrap() > 0.01,
        "{}",
        s["max_slack"]
    );
    assert_eq!(s["max_slack_at"]["contact"], "foot_contact");
    // Which interval holds it is Ipopt's path (3 with Debian 12's Ipopt 3.11, 5 with Debian
    // 13's 3.14): the terminal names the one summary.json records, with its knots and times.
    let j = s["max_slack_at"]["interval"].as_u64().unwrap();
    let named = format!(
        "at interval {j} (knots {j}–{}, t = {:.1}–{:.1} s,",
        j + 1,
        0.1 * j as f64,
        0.1 * (j + 1) as f64
    );
    assert!(run.stdout.contains(&named), "{named:?} in\n{}", run.stdout);
    // The slack variables hold it, not only products cancelled in the rows' sums: a higher
    // weight can close it.
    assert_eq!(s["max_slack_at"]["hidden"], false);
    // The page says so too: a plan, not solved, the verdict's word, in amber.
    let page = std::fs::read_to_string(out.join("animation.html")).unwrap();
    let data = crate::view::page_data_of(&page);
    let track = &data["tracks"][0];
    assert_eq!(track["standing"], "relaxed");
    assert_eq!(track["simulation"], false);
    let detail = track["detail"].as_str().unwrap();
    let slack = s["max_slack"].as_f64().unwrap();
    assert!(
        detail.starts_with(&format!(
            "plan, NOT SOLVED: relaxed_contact (slack {slack:.2e} above tolerance 1e-4"
        )),
        "{detail}"
    );
    // The tolerance is the problem's: raised above the slack, the same optimum is solved.
    let t = TestDir::new("relaxed-contact-tolerance");
    let (out, _) = solve(
        &t,
        &fixture("hop_up.toml"),
        &["--set", "slack.tolerance=1"],
        0,
    );
    assert_eq!(summary(&out)["status"], "solve_succeeded");
}

/// A solve Ipopt calls infeasible (the hopper must move 0.5 m with its inputs held at zero)
/// names its most violated rows as `vito check --derivatives` names them.
#[test]
fn infeasible_solve_names_its_worst_rows() {
    let t = TestDir::new("infeasible-rows");
    let (out, run) = solve(
        &t,
        &problems_dir().join("hopper_2d.toml"),
        &[
            "--set",
            "horizon.knots=6",
            "--set",
            "horizon.time_step=0.2",
            "--set",
            "inputs.bounds.theta=[0.0, 0.0]",
            "--set",
            "inputs.bounds.r=[0.0, 0.0]",
        ],
        1,
    );
    assert!(
        run.stdout
            .contains("status       infeasible_problem_detected"),
        "{}",
        run.stdout
    );
    assert!(run.stdout.contains("worst rows:"), "{}", run.stdout);
    let s = summary(&out);
    let rows = s["worst_rows"].as_array().unwrap();
    assert!(!rows.is_empty() && rows.len() <= 5, "{rows:?}");
    let worst = &rows[0];
    let violation = worst["violation"].as_f64().unwrap();
    // The worst row's violation is the summary's largest one, and the line names it.
    assert_eq!(violation, s["max_constraint_violation"].as_f64().unwrap());
    assert!(violation > 1.0, "{worst}");
    let name = worst["row"].as_str().unwrap();
    assert!(
        name.starts_with("DEL ") || name.starts_with("first step "),
        "{name}"
    );
    assert!(run.stdout.contains(&format!("[{name}]")), "{}", run.stdout);
    for pair in rows.windows(2) {
        assert!(pair[0]["violation"].as_f64() >= pair[1]["violation"].as_f64());
    }
}

/// Row k of `trajectory.csv` holds knot k's quantities: the foot's distance column equals
/// the foot's height computed here from the row's own q (the hopper's foot sits at
/// z − r·cos θ: the leg turns about −y by θ and extends along −z by r, see
/// problems/robots/hopper_2d.urdf), on every row, the last included. Times are the decimal
/// k·h, slacks are never negative, and every number reads back exactly as summary.json has it.
#[test]
fn trajectory_rows_hold_their_own_knot() {
    let t = TestDir::new("csv-rows");
    let (out, _) = solve(&t, &problems_dir().join("hopper_2d.toml"), &[], 0);
    let text = std::fs::read_to_string(out.join("trajectory.csv")).unwrap();
    let table = vito::report::read_csv(&text).unwrap();
    let column = |name: &str| table.column(name).unwrap_or_else(|| panic!("{name}"));
    let (z, r, theta) = (column("z"), column("r"), column("theta"));
    let distance = column("foot_contact_distance");
    assert_eq!(distance.len(), 21);
    let mut touching = 0;
    for k in 0..21 {
        let height = z[k] - r[k] * theta[k].cos();
        assert!(
            (distance[k] - height).abs() <= 1e-12,
            "row {k}: distance {} but the foot is at {height}",
            distance[k]
        );
        touching += usize::from(height.abs() < 1e-6);
    }
    // Both the on-ground and the in-air knots are compared.
    assert!(
        (2..19).contains(&touching),
        "{touching} knots on the ground"
    );
    let times: Vec<&str> = text
        .lines()
        .skip(1)
        .map(|l| l.split(',').next().unwrap())
        .collect();
    assert_eq!(times[3], "0.15");
    assert_eq!(times[20], "1");
    let slack = column("slack");
    assert!(slack[..20].iter().all(|&s| s >= 0.0), "{slack:?}");
    let s = summary(&out);
    let max = slack[..20].iter().fold(0.0_f64, |a, &b| a.max(b));
    assert_eq!(max, s["max_slack"].as_f64().unwrap());
    assert_eq!(column("x")[20], s["final_q"]["x"].as_f64().unwrap());
}

/// vito runs the linear algebra on one thread whatever OPENBLAS_NUM_THREADS and
/// OMP_NUM_THREADS say, and records it.
#[test]
fn summary_records_one_blas_thread_whatever_the_environment() {
    let t = TestDir::new("threads");
    let out = t.path().join("out");
    let file = problems_dir().join("hopper_2d.toml");
    t.vito()
        .args([
            "solve".as_ref(),
            file.as_os_str(),
            "--out".as_ref(),
            out.as_os_str(),
            "--quiet".as_ref(),
        ])
        .env("OPENBLAS_NUM_THREADS", "2")
        .env("OMP_NUM_THREADS", "2")
        .assert_exit(0);
    let threads = &summary(&out)["threads"];
    assert_eq!(threads["openblas"], 1, "{threads}");
    assert!(
        threads["openblas_config"]
            .as_str()
            .is_some_and(|c| c.starts_with("OpenBLAS")),
        "{threads}"
    );
}

/// One trajectory whatever the machine's thread settings: LittleDog's step solved under
/// OPENBLAS_NUM_THREADS 1, 2 and unset, RAYON_NUM_THREADS 1 and 2 and `taskset -c 0` writes
/// the same `trajectory.csv`, byte for byte (about 20 s per solve):
/// `cargo test --release --test integration cli::trust::same_trajectory -- --ignored`.
#[test]
#[ignore]
fn same_trajectory_under_any_thread_settings() {
    let file = problems_dir().join("littledog_step.toml");
    let t = TestDir::new("same-trajectory");
    /// (name, environment: a value or removed, run under `taskset -c 0`).
    type Variant<'a> = (&'a str, &'a [(&'a str, Option<&'a str>)], bool);
    let variants: [Variant; 6] = [
        ("blas1", &[("OPENBLAS_NUM_THREADS", Some("1"))], false),
        ("blas2", &[("OPENBLAS_NUM_THREADS", Some("2"))], false),
        (
            "unset",
            &[("OPENBLAS_NUM_THREADS", None), ("OMP_NUM_THREADS", None)],
            false,
        ),
        ("rayon1", &[("RAYON_NUM_THREADS", Some("1"))], false),
        ("rayon2", &[("RAYON_NUM_THREADS", Some("2"))], false),
        ("taskset", &[], true),
    ];
    let mut first: Option<(String, String)> = None;
    for (name, env, taskset) in variants {
        let out = t.path().join(name);
        let mut cmd = if taskset {
            let mut c = std::process::Command::new("taskset");
            c.args(["-c", "0", env!("CARGO_BIN_EXE_vito")]);
            c
        } else {
            std::process::Command::new(env!("CARGO_BIN_EXE_vito"))
        };
        cmd.args(["solve".as_ref(), file.as_os_str(), "--quiet".as_ref()])
            .arg("--out")
            .arg(&out);
        for (key, value) in env {
            match value {
                Some(v) => cmd.env(key, v),
                None => cmd.env_remove(key),
            };
        }
        let status = cmd.status().expect("run vito");
        assert!(status.code().is_some(), "{name}: {status:?}");
        let csv = std::fs::read_to_string(out.join("trajectory.csv")).expect("trajectory.csv");
        let objective = summary(&out)["objective"].to_string();
        match &first {
            None => first = Some((csv, objective)),
            Some((csv0, objective0)) => {
                assert_eq!(&objective, objective0, "{name}: objective");
                assert!(csv == *csv0, "{name}: trajectory.csv differs");
            }
        }
    }
}
