//! `vito sweep`: a grid of hopper solves with a failing and a hanging point, killed and
//! resumed; shards collected into one table; the report's plot.

use std::path::Path;
use std::process::{Command, Stdio};
use std::time::{Duration, Instant, SystemTime};

use crate::cli::util::{TestDir, hopper_text, says};

/// The hopper as a family over its number of knots `n` (T = 1 s whatever n): n = 1 divides
/// by zero (the run fails with an input error), n = 2000 takes far longer than a few seconds.
pub fn hopper_family() -> String {
    hopper_text()
        .replace("knots = 21", "knots = \"= n\"")
        .replace(
            "time_step = 0.05          # fixed h [s], T = 1 s",
            "time_step = \"= 1 / (n - 1)\"",
        )
        + "\n[parameters]\nn = 21\n"
}

/// A one-point sweep of the hopper (`p.toml` of the test directory) into `out` whose run
/// stops after two iterations: quick, not solved (exit 1), no neighbour pass.
pub fn one_point_sweep(out: &str) -> [&str; 10] {
    [
        "sweep",
        "p.toml",
        "--grid",
        "contacts.friction=0.5",
        "--out",
        out,
        "--neighbour-rounds",
        "0",
        "--set",
        "solver.ipopt.max_iter=2",
    ]
}

/// The grid of the resume test: finished, timeout (on the resumed sweep), failed (its run
/// directory holds a file that is not vito's), finished.
const GRID: [&str; 6] = ["sweep", "fam.toml", "--grid", "n=5,2000,7,6", "--out", "sw"];
const ONE_AT_A_TIME: [&str; 4] = ["--jobs", "1", "--neighbour-rounds", "0"];

fn table(dir: &Path) -> serde_json::Value {
    let text = std::fs::read_to_string(dir.join("sweep.json")).expect("sweep.json");
    serde_json::from_str(&text).expect("sweep.json is JSON")
}

fn statuses(dir: &Path) -> Vec<String> {
    table(dir)["rows"]
        .as_array()
        .unwrap()
        .iter()
        .map(|r| r["status"].as_str().unwrap().to_owned())
        .collect()
}

/// Waits until a run's log shows an iteration line: the event the tests synchronise on. The
/// 10 min bound only turns a hang into a failure; no outcome depends on it.
fn wait_until_iterating(log: &Path) {
    let deadline = Instant::now() + Duration::from_secs(600);
    while !std::fs::read_to_string(log)
        .is_ok_and(|l| l.lines().any(crate::cli::util::is_iteration_line))
    {
        assert!(
            Instant::now() < deadline,
            "{} shows no iteration after 10 min",
            log.display()
        );
        std::thread::sleep(Duration::from_millis(50));
    }
}

fn modified(path: &Path) -> SystemTime {
    std::fs::metadata(path).unwrap().modified().unwrap()
}

#[test]
#[cfg(unix)]
fn sweep_isolates_failures_and_resumes_after_a_kill() {
    use std::os::unix::process::CommandExt;
    let t = TestDir::with_hopper("sweep_isolates_failures_and_resumes_after_a_kill");
    t.write("fam.toml", &hopper_family());
    let sw = t.path().join("sw");
    std::fs::create_dir_all(sw.join("runs/n-7")).unwrap();
    t.write("sw/.vito-sweep", "");
    t.write("sw/runs/n-7/notes.txt", "mine");

    // Kill the sweep and its solve (SIGKILL to its process group: no chance to clean up)
    // while its second run, 2000 knots without a time limit (minutes), iterates: the first
    // run is finished and the last two have not started, whatever the machine's speed.
    let mut sweep = Command::new(env!("CARGO_BIN_EXE_vito"))
        .args(GRID)
        .args(ONE_AT_A_TIME)
        .current_dir(t.path())
        .process_group(0)
        .stdout(Stdio::null())
        .stderr(Stdio::null())
        .spawn()
        .unwrap();
    wait_until_iterating(&sw.join("logs/n-2000.log"));
    rustix::process::kill_process_group(
        rustix::process::Pid::from_child(&sweep),
        rustix::process::Signal::KILL,
    )
    .unwrap();
    sweep.wait().unwrap();
    let first = sw.join("runs/n-5/summary.json");
    let first_written = modified(&first);
    assert_eq!(statuses(&sw).first().map(String::as_str), Some("finished"));
    assert!(
        !sw.join("runs/n-6").exists(),
        "a run started after the kill"
    );

    // The rerun keeps the finished run, redoes the others; the failing and the hanging
    // point end up in the table without taking the others down.
    let run = t
        .vito()
        .args(GRID)
        .args(ONE_AT_A_TIME)
        .args(["--time-limit", "8"])
        .assert_exit(1);
    assert!(
        run.stdout
            .contains("4 runs: 2 finished (1 of them before this sweep), 1 failed, 1 timed out"),
        "{}",
        run.stdout
    );
    assert_eq!(modified(&first), first_written, "a finished run was redone");
    assert_eq!(statuses(&sw), ["finished", "timeout", "failed", "finished"]);
    let rows = table(&sw)["rows"].as_array().unwrap().clone();
    let note = rows[2]["note"].as_str().unwrap();
    assert!(
        note.starts_with("exit 2: error:") && note.contains("n-7"),
        "{note}"
    );
    assert_eq!(
        std::fs::read_to_string(sw.join("runs/n-7/notes.txt")).unwrap(),
        "mine"
    );
    assert!(
        rows[1]["note"]
            .as_str()
            .unwrap()
            .contains("time limit of 8 s")
    );
    // The run at the time limit stopped itself as Ctrl-C stops it: its iterate is on disk
    // with status `timeout`, and the row holds that run's own numbers.
    let timed = crate::cli::util::summary(&sw.join(rows[1]["dir"].as_str().unwrap()));
    assert_eq!(timed["status"], "timeout");
    assert_eq!(timed["ipopt_status"], "maximum_wall_time_exceeded");
    assert_eq!(timed["knots"], 2000);
    assert_eq!(rows[1]["solver_status"], "timeout");
    assert_eq!(rows[1]["iterations"], timed["iterations"]);
    assert_eq!(rows[1]["wall_time_s"], timed["wall_time_s"]);

    // The report: 6 knots solve (the polish turns their relaxed optimum into a plan), 5 knots
    // relax contact; each unsolved point is a marker of its class, and the exit code says so.
    let run = t.vito().args(["sweep", "report", "sw"]).assert_exit(1);
    assert!(
        run.stdout.contains(
            "not solved   3 of 4 points: 0 (n=5: relaxed), 1 (n=2000: timeout), 2 (n=7: failed)"
        ),
        "{}",
        run.stdout
    );
    let svg = std::fs::read_to_string(sw.join("sweep-objective.svg")).unwrap();
    let doc = roxmltree::Document::parse(&svg).expect("the report's SVG parses");
    let count = |class: &str| {
        doc.descendants()
            .filter(|n| n.attribute("class") == Some(class))
            .count()
    };
    assert_eq!(
        [
            "marker solved",
            "marker relaxed",
            "marker failed",
            "marker timeout",
            "line"
        ]
        .map(count),
        [1, 1, 1, 1, 0],
        "{svg}"
    );
    for (row, n) in [(&rows[0], 5), (&rows[3], 6)] {
        let summary = crate::cli::util::summary(&sw.join(row["dir"].as_str().unwrap()));
        assert_eq!(summary["knots"], n);
        assert_eq!(summary["ipopt_status"], "solve_succeeded");
        assert_eq!(row["objective"], summary["objective"]);
        assert_eq!(row["iterations"], summary["iterations"]);
        assert_eq!(row["max_slack"], summary["max_slack"]);
    }
    let csv = std::fs::read_to_string(sw.join("sweep.csv")).unwrap();
    let lines: Vec<&str> = csv.lines().collect();
    assert_eq!(lines.len(), 5, "{csv}");
    assert!(lines[0].starts_with(
        "index,n,status,solver_status,objective,iterations,wall_time_s,max_slack,start,settled,dir,note"
    ));
    assert!(
        lines[4].starts_with(&format!(
            "3,6,finished,{},",
            crate::cli::util::summary(&sw.join("runs/n-6"))["status"]
                .as_str()
                .unwrap()
        )),
        "{csv}"
    );
    // The killed run left no staging directory behind it and no solve is running.
    let leftovers: Vec<_> = std::fs::read_dir(sw.join("runs"))
        .unwrap()
        .map(|e| e.unwrap().file_name().into_string().unwrap())
        .filter(|n| n.starts_with('.'))
        .collect();
    assert!(leftovers.is_empty(), "{leftovers:?}");

    // A third run redoes only what did not finish (exit 1: at 5 and 6 knots the hopper's
    // plans relax contact).
    says(
        &t,
        &[
            "sweep",
            "fam.toml",
            "--grid",
            "n=5,6",
            "--out",
            "sw",
            "--neighbour-rounds",
            "0",
        ],
        1,
        "2 runs: 2 finished (2 of them before this sweep)",
    );
    assert_eq!(modified(&first), first_written);
}

#[test]
fn sweep_shards_collect_into_one_table_and_report_plots_it() {
    let t = TestDir::with_hopper("sweep_shards_collect_into_one_table_and_report_plots_it");
    t.write("fam.toml", &hopper_family());
    let grid = ["--grid", "n=7,8", "--grid", "contacts.friction=0.5,0.8"];
    for shard in ["0/2", "1/2"] {
        let out = format!("shard-{}", &shard[..1]);
        t.vito()
            .args(["sweep", "fam.toml"])
            .args(grid)
            .args(["--shard", shard, "--out", &out, "--jobs", "2"])
            .assert_exit(0);
        assert_eq!(statuses(&t.path().join(&out)), ["finished", "finished"]);
    }
    // One shard alone leaves half the grid missing: an error naming the points, unless
    // --partial accepts it.
    let run = says(
        &t,
        &["sweep", "collect", "shard-1", "--out", "half"],
        1,
        "2 finished, 0 failed, 0 timed out, 2 missing",
    );
    assert!(
        run.stderr.contains(
            "2 of 4 points have no result (a shard not run, not finished or not named): \
             0 (n=7 contacts.friction=0.5), 2 (n=8 contacts.friction=0.5)"
        ),
        "{}",
        run.stderr
    );
    says(
        &t,
        &["sweep", "collect", "shard-1", "--out", "half", "--partial"],
        0,
        "2 missing",
    );
    assert_eq!(
        statuses(&t.path().join("half")),
        ["pending", "finished", "pending", "finished"]
    );

    says(
        &t,
        &["sweep", "collect", "shard-0", "shard-1", "--out", "all"],
        0,
        "4 points from 2 directories: 4 finished",
    );
    let all = t.path().join("all");
    let mut entries: Vec<String> = std::fs::read_dir(&all)
        .unwrap()
        .map(|e| e.unwrap().file_name().into_string().unwrap())
        .collect();
    entries.sort();
    assert_eq!(entries, [".vito-sweep", "sweep.csv", "sweep.json"]);
    let rows = table(&all)["rows"].as_array().unwrap().clone();
    let points: Vec<(String, String)> = rows
        .iter()
        .map(|r| {
            (
                r["values"][0][1].as_str().unwrap().to_owned(),
                r["values"][1][1].as_str().unwrap().to_owned(),
            )
        })
        .collect();
    assert_eq!(
        points,
        [("7", "0.5"), ("7", "0.8"), ("8", "0.5"), ("8", "0.8")]
            .map(|(a, b)| (a.to_owned(), b.to_owned()))
    );
    for (i, r) in rows.iter().enumerate() {
        assert_eq!(r["index"], i);
        // Each row points at its run's own directory, relative to the collected table.
        let summary = crate::cli::util::summary(&all.join(r["dir"].as_str().unwrap()));
        assert_eq!(r["objective"], summary["objective"]);
        assert_eq!(
            summary["parameters"]["contacts.friction"].to_string(),
            points[i].1
        );
    }
    // The shards of another grid do not mix.
    t.vito()
        .args(["sweep", "fam.toml", "--grid", "n=9", "--out", "other"])
        .assert_exit(0);
    says(
        &t,
        &["sweep", "collect", "shard-0", "other", "--out", "mixed"],
        2,
        "are not shards of one sweep",
    );

    let run = says(
        &t,
        &["sweep", "report", "all", "--metric", "objective"],
        0,
        "objective of 4 runs plotted",
    );
    assert!(
        run.stdout
            .lines()
            .next()
            .unwrap()
            .starts_with("index  n  contacts.friction  status")
    );
    let svg = std::fs::read_to_string(all.join("sweep-objective.svg")).unwrap();
    assert!(
        svg.starts_with("<svg") && svg.contains("contacts.friction = 0.8"),
        "{}",
        &svg[..200.min(svg.len())]
    );
    says(
        &t,
        &["sweep", "report", "all", "--metric", "slip"],
        2,
        "choose one of: objective",
    );
}

#[test]
fn sweep_refuses_foreign_directories_and_bad_grids() {
    let t = TestDir::with_hopper("sweep_refuses_foreign_directories_and_bad_grids");
    t.write("fam.toml", &hopper_family());
    std::fs::create_dir(t.path().join("mine")).unwrap();
    t.write("mine/notes.txt", "keep");
    says(
        &t,
        &["sweep", "fam.toml", "--grid", "n=5", "--out", "mine"],
        2,
        "holds no `.vito-sweep`",
    );
    assert_eq!(std::fs::read_dir(t.path().join("mine")).unwrap().count(), 1);
    for (args, message) in [
        (vec!["--grid", "slack.wieght=1,2"], "did you mean `weight`"),
        (vec!["--grid", "n=5,5"], "listed twice"),
        (vec!["--grid", "n=5", "--shard", "2/2"], "0 <= I < N"),
        (
            vec!["--grid", "n=5", "--time-limit", "0"],
            "positive number",
        ),
        // Beyond what a duration can hold (it panicked in Duration::from_secs_f64).
        (
            vec!["--grid", "n=5", "--time-limit", "1e20"],
            "--time-limit 100000000000000000000: give a positive number up to 1e9",
        ),
        // Every value is checked before the first run: n = 1 divides by zero.
        (
            vec!["--grid", "n=5,1", "--jobs", "1"],
            "--grid n=5,1: the value `1` is not valid here",
        ),
        (
            vec!["--grid", "contacts.friction=0.3,abc"],
            "--grid contacts.friction=0.3,abc: the value `abc` is not valid here",
        ),
        // A bare key: the full key path and the file's [parameters] are suggested.
        (
            vec!["--grid", "friction=0.3,0.6"],
            "did you mean `contacts.friction`? A swept key is a full key path as for --set \
             (e.g. `contacts.friction`) or a name of the file's [parameters]: `n`",
        ),
    ] {
        let run = t
            .vito()
            .args(["sweep", "fam.toml", "--out", "new"])
            .args(&args)
            .assert_exit(2);
        assert!(run.stderr.contains(message), "{args:?}: {}", run.stderr);
        assert!(!t.path().join("new").exists(), "{args:?}");
    }
    // Report and collect on a directory without a sweep table: input errors.
    says(
        &t,
        &["sweep", "report", "mine"],
        2,
        "is not a sweep directory",
    );
    says(
        &t,
        &["sweep", "collect", "mine", "--out", "all"],
        2,
        "is not a sweep directory",
    );
    assert!(!t.path().join("all").exists());
}

/// A swept key holding `=` is not a sweep's: `--set` and `--grid` read `key=value` up to the
/// first `=`, so no command line gives one and each run's `--set` would set another key. A
/// table whose axis has one (an edited `sweep.json`) is refused by `sweep report` and
/// `sweep collect` naming the key (exit 2); it was shown and merged verbatim.
#[test]
fn swept_keys_holding_an_equals_sign_are_refused() {
    let t = TestDir::with_hopper("swept_keys_holding_an_equals_sign");
    t.write("p.toml", &hopper_text());
    t.vito().args(one_point_sweep("sw")).assert_exit(1);
    let path = t.path().join("sw/sweep.json");
    let edited = std::fs::read_to_string(&path).unwrap().replace(
        "\"key\": \"contacts.friction\"",
        "\"key\": \"contacts.friction=2\"",
    );
    assert!(edited.contains("contacts.friction=2"));
    std::fs::write(&path, &edited).unwrap();
    for args in [
        &["sweep", "report", "sw"][..],
        &["sweep", "collect", "sw", "--out", "all"],
    ] {
        let run = says(&t, args, 2, "the key `contacts.friction=2` holds `=`");
        assert!(run.stdout.is_empty(), "{}", run.stdout);
    }
    assert!(!t.path().join("all").exists());
}

/// A 10⁶-point grid is checked axis by axis (the problem loaded with a few values of each
/// axis, not once per point): a bad value on the last axis is found before anything runs,
/// also with --shard.
/// Grids of 10^6 and 2^64 points (a product that wraps to 0) are refused before anything is
/// loaded, run or written (exit 2, naming the limit); a bad value in a grid within the limit
/// is found axis by axis.
#[test]
fn sweep_refuses_oversized_grids_up_front() {
    let t = TestDir::with_hopper("sweep_refuses_oversized_grids_up_front");
    t.write("fam.toml", &hopper_family());
    let values = |n: usize| {
        (0..n)
            .map(|i| format!("{}", 0.3 + i as f64 * 1e-4))
            .collect::<Vec<_>>()
            .join(",")
    };
    let friction = format!("contacts.friction={}", values(1000));
    let weight = format!("slack.weight={},-1", values(999));
    let run = t
        .vito()
        .args(["sweep", "fam.toml", "--out", "big", "--shard", "3/7"])
        .args(["--grid", &friction, "--grid", &weight])
        .assert_exit(2);
    assert!(run.stderr.contains("1000000 points"), "{}", run.stderr);
    assert!(run.stderr.contains("100000"), "{}", run.stderr);
    let mut args: Vec<String> = ["sweep", "fam.toml", "--out", "big"]
        .map(String::from)
        .to_vec();
    for i in 0..64 {
        args.push("--grid".into());
        args.push(format!("k{i}=1,2"));
    }
    let run = t.vito().args(&args).assert_exit(2);
    assert!(run.stderr.contains("more than 2^64"), "{}", run.stderr);
    assert!(!t.path().join("big").exists());
    let weight = format!("slack.weight={},-1", values(99));
    let run = t
        .vito()
        .args(["sweep", "fam.toml", "--out", "big"])
        .args(["--grid", &format!("contacts.friction={}", values(100))])
        .args(["--grid", &weight])
        .assert_exit(2);
    assert!(
        run.stderr.contains("the value `-1` is not valid here"),
        "{}",
        run.stderr
    );
    assert!(!t.path().join("big").exists());
}

/// Symbolic links planted inside a sweep directory are refused, never followed.
#[test]
fn sweep_refuses_links_planted_in_its_directory() {
    let t = TestDir::with_hopper("sweep_refuses_links_planted_in_its_directory");
    t.write("fam.toml", &hopper_family());
    std::fs::create_dir(t.path().join("elsewhere")).unwrap();
    t.write("elsewhere/n-5.log", "precious");
    for planted in ["logs", "runs"] {
        let sw = t.path().join(format!("sw-{planted}"));
        std::fs::create_dir(&sw).unwrap();
        std::fs::write(sw.join(".vito-sweep"), "").unwrap();
        std::os::unix::fs::symlink(t.path().join("elsewhere"), sw.join(planted)).unwrap();
        let out = format!("sw-{planted}");
        says(
            &t,
            &["sweep", "fam.toml", "--grid", "n=5", "--out", &out],
            2,
            "which vito did not create",
        );
    }
    // A link planted at a run's log name.
    let sw = t.path().join("sw-log");
    std::fs::create_dir_all(sw.join("logs")).unwrap();
    std::fs::write(sw.join(".vito-sweep"), "").unwrap();
    std::os::unix::fs::symlink(t.path().join("elsewhere/n-5.log"), sw.join("logs/n-5.log"))
        .unwrap();
    says(
        &t,
        &["sweep", "fam.toml", "--grid", "n=5", "--out", "sw-log"],
        2,
        "which vito did not create",
    );
    assert_eq!(
        std::fs::read_to_string(t.path().join("elsewhere/n-5.log")).unwrap(),
        "precious"
    );
    let left: Vec<_> = std::fs::read_dir(t.path().join("elsewhere"))
        .unwrap()
        .map(|e| e.unwrap().file_name())
        .collect();
    assert_eq!(left.len(), 1, "{left:?}");
}

/// A sweep stopped by a signal stops its running runs after their current iteration (their
/// iterates kept), starts no new one, prints its state and exits 1; the stopped run is
/// `interrupted`, never "without a complete summary.json".
#[test]
#[cfg(unix)]
fn sweep_stopped_by_a_signal_keeps_the_iterates_and_says_so() {
    use std::os::unix::process::CommandExt;
    let t = TestDir::with_hopper("sweep_stopped_by_a_signal_keeps_the_iterates_and_says_so");
    t.write("fam.toml", &hopper_family());
    // SIGTERM to the sweep alone (`kill`), SIGINT to its whole group (a terminal's Ctrl-C).
    for (out, kill) in [("term", ["-TERM", "{pid}"]), ("int", ["-INT", "-{pid}"])] {
        let sw = t.path().join(out);
        let child = Command::new(env!("CARGO_BIN_EXE_vito"))
            .args(["sweep", "fam.toml", "--grid", "n=2000,5", "--jobs", "1"])
            .args(["--neighbour-rounds", "0"])
            .args(["--out", out])
            .current_dir(t.path())
            .process_group(0)
            .stdout(Stdio::piped())
            .stderr(Stdio::piped())
            .spawn()
            .unwrap();
        wait_until_iterating(&sw.join("logs/n-2000.log"));
        let pid = child.id().to_string();
        let args: Vec<String> = kill.iter().map(|a| a.replace("{pid}", &pid)).collect();
        let mut kill_cmd = Command::new("kill");
        if args[1].starts_with('-') {
            kill_cmd.arg(&args[0]).arg("--").arg(&args[1]);
        } else {
            kill_cmd.args(&args);
        }
        assert!(kill_cmd.status().unwrap().success());
        let output = child.wait_with_output().unwrap();
        let stdout = String::from_utf8_lossy(&output.stdout);
        let stderr = String::from_utf8_lossy(&output.stderr);
        assert_eq!(output.status.code(), Some(1), "{stdout}\n{stderr}");
        assert!(
            stderr.contains("interrupted: stopping the running runs"),
            "{stderr}"
        );
        assert!(
            stdout.contains("2 runs: 0 finished (0 of them before this sweep), 0 failed, 0 timed out, 1 interrupted, 1 not run"),
            "{stdout}"
        );
        assert!(
            stdout.contains("interrupted: the table holds every run"),
            "{stdout}"
        );
        assert_eq!(statuses(&sw), ["interrupted", "pending"]);
        let rows = table(&sw)["rows"].as_array().unwrap().clone();
        let note = rows[0]["note"].as_str().unwrap();
        assert!(note.starts_with("stopped by a signal"), "{note}");
        assert_eq!(rows[0]["solver_status"], "user_requested_stop");
        let summary = crate::cli::util::summary(&sw.join("runs/n-2000"));
        assert_eq!(summary["status"], "user_requested_stop");
        assert!(
            !sw.join("runs/n-5").exists(),
            "a run started after the stop"
        );
    }
}

#[test]
fn sweep_warm_starts_from_the_nearest_finished_neighbour() {
    let t = TestDir::with_hopper("sweep_warm_starts_from_the_nearest_finished_neighbour");
    t.write("fam.toml", &hopper_family());
    let grid = [
        "sweep",
        "fam.toml",
        "--grid",
        "contacts.friction=0.8,0.7,0.6",
    ];
    let warm = [
        &grid[..],
        &[
            "--out",
            "warm",
            "--jobs",
            "1",
            "--warm-start",
            "neighbour",
            "--neighbour-rounds",
            "0",
        ],
    ]
    .concat();
    says(&t, &warm, 0, "3 runs: 3 finished");
    let rows = table(&t.path().join("warm"))["rows"]
        .as_array()
        .unwrap()
        .clone();
    assert_eq!(rows[0]["note"], "");
    assert_eq!(rows[1]["note"], "warm start from contacts.friction-0.8");
    assert_eq!(rows[2]["note"], "warm start from contacts.friction-0.7");
    let summary = crate::cli::util::summary(&t.path().join("warm/runs/contacts.friction-0.6"));
    let from = summary["parameters"]["initial_guess.warm_start"]
        .as_str()
        .unwrap();
    assert!(
        from.ends_with("runs/contacts.friction-0.7/trajectory.csv"),
        "{from}"
    );
    // A warm-started run is still the same problem: a rerun without warm starts keeps it.
    let cold = [&grid[..], &["--out", "warm", "--neighbour-rounds", "0"]].concat();
    says(&t, &cold, 0, "3 finished (3 of them before this sweep)");
}

/// The link between a sweep and its runs is a hidden option, not an environment variable: a
/// `VITO_SWEEP_PARENT` in a user's environment changes nothing.
#[test]
fn solve_ignores_a_sweep_marker_in_the_environment() {
    let t = TestDir::with_hopper("solve_ignores_a_sweep_marker_in_the_environment");
    t.write("hop.toml", &hopper_text());
    t.vito()
        .args(["solve", "hop.toml", "--quiet", "--out", "out"])
        .env("VITO_SWEEP_PARENT", "1")
        .assert_exit(0);
    assert_eq!(
        crate::cli::util::summary(&t.path().join("out"))["status"],
        "solve_succeeded"
    );
}

/// The neighbour pass on a friction family of the hopper, cold from its linear guess: every
/// answer is at least as good as the point's own solve (read from its own run directory),
/// an answer taken from a neighbour is that attempt's result and says where it came from, and
/// at the end no neighbour's plan improves any point by more than 1 % (settled). A rerun finds
/// every attempt on disk and solves nothing.
#[test]
fn sweep_neighbour_pass_improves_points_from_their_neighbours_plans_until_settled() {
    let t = TestDir::with_hopper(
        "sweep_neighbour_pass_improves_points_from_their_neighbours_plans_until_settled",
    );
    t.write("hopper.toml", &hopper_text());
    let args = [
        "sweep",
        "hopper.toml",
        "--grid",
        "contacts.friction=0.2,0.3,0.5,0.8,1.0",
        "--jobs",
        "2",
        "--out",
        "sw",
    ];
    let run = t.vito().args(args).assert_exit(0);
    assert!(
        run.stderr.contains("neighbour pass, round 1:"),
        "{}",
        run.stderr
    );
    let sw = t.path().join("sw");
    let rows = table(&sw)["rows"].as_array().unwrap().clone();
    let rank = |status: &str| match status {
        "solve_succeeded" | "solved_to_acceptable_level" => 0,
        "relaxed_contact" => 1,
        _ => 2,
    };
    let mut from_neighbours = 0;
    for row in &rows {
        assert_eq!(row["solver_status"], "solve_succeeded", "{row}");
        assert_eq!(row["settled"], true, "{row}");
        let own = crate::cli::util::summary(&sw.join("runs").join(format!(
            "contacts.friction-{}",
            row["values"][0][1].as_str().unwrap()
        )));
        let (objective, own_objective) = (
            row["objective"].as_f64().unwrap(),
            own["objective"].as_f64().unwrap(),
        );
        let own_rank = rank(own["status"].as_str().unwrap());
        assert!(
            own_rank > 0 || objective <= own_objective,
            "the answer {objective} is worse than the point's own solve {own_objective}"
        );
        let dir = row["dir"].as_str().unwrap();
        let start = row["start"].as_str().unwrap();
        if dir.starts_with("attempts/") {
            from_neighbours += 1;
            // It improved on the point's own solve by more than the settle ratio.
            assert!(
                own_rank > 0 || objective < own_objective * 0.99,
                "{objective} against {own_objective}"
            );
            let summary = crate::cli::util::summary(&sw.join(dir));
            assert_eq!(row["objective"], summary["objective"]);
            let source = summary["parameters"]["initial_guess.warm_start"]
                .as_str()
                .unwrap();
            let label = start.strip_prefix("neighbour ").unwrap();
            let mu = label.strip_prefix("contacts.friction=").unwrap();
            assert!(
                source.contains(&format!("contacts.friction-{mu}")),
                "{source} is not the plan of {label}"
            );
        } else {
            assert_eq!(start, "guess");
        }
    }
    assert!(
        from_neighbours > 0,
        "no point was improved by a neighbour's plan"
    );
    // The rerun replays the rounds from the attempts on disk.
    let again = t.vito().args(args).assert_exit(0);
    assert!(
        again
            .stdout
            .contains("5 finished (5 of them before this sweep)"),
        "{}",
        again.stdout
    );
    assert!(
        !again.stderr.contains("neighbour re-solves"),
        "the rerun solved again: {}",
        again.stderr
    );
    assert_eq!(table(&sw)["rows"].as_array().unwrap(), &rows);
}

/// A table cell longer than a format width may be (65,535 characters) prints in full,
/// padded, from `sweep report` (and the same printer ends `vito sweep`).
#[test]
fn sweep_report_prints_a_cell_of_70000_characters() {
    use vito::sweep::{Axis, Grid, Row, Shard, Table};
    let t = TestDir::new("sweep_report_prints_a_cell_of_70000_characters");
    let long = "d".repeat(70_000);
    let grid = Grid::new(vec![
        Axis::parse(&format!("description={long},short")).unwrap(),
    ])
    .unwrap();
    let mut rows: Vec<Row> = grid
        .points()
        .map(|p| Row::pending(&p, "x".into()))
        .collect();
    rows[1].note = "n".repeat(70_000);
    let table = Table {
        problem: "p.toml".into(),
        problem_sha256: "00".into(),
        sets: Vec::new(),
        grid,
        shard: Shard::ALL,
        rows,
    };
    let dir = t.path().join("sw");
    std::fs::create_dir(&dir).unwrap();
    table.write(&dir).unwrap();
    let run = t
        .vito()
        .args(["sweep", "report", "sw", "--metric", "objective"])
        .run();
    assert_ne!(run.code, 3, "{}", run.stderr);
    assert!(!run.stderr.contains("panicked"), "{}", run.stderr);
    let lines: Vec<&str> = run
        .stdout
        .lines()
        .filter(|l| l.contains("pending") && l.trim_start().starts_with(char::is_numeric))
        .collect();
    assert_eq!(
        lines.len(),
        2,
        "{}",
        &run.stdout[..run.stdout.len().min(300)]
    );
    assert!(lines[0].contains(&long));
    assert!(lines[1].contains(&"n".repeat(70_000)));
}

/// A sweep whose runs start from other runs' plans (neighbour warm starts, or the neighbour
/// pass, on by default) names each plan in a TOML string, so an `--out` whose name is not
/// UTF-8 is refused before anything runs (exit 2, saying how to fix it), where the runs got
/// garbled paths; without warm starts such a directory is used as it is.
#[test]
fn a_sweep_with_warm_starts_refuses_an_out_that_is_not_utf8() {
    use std::ffi::OsStr;
    use std::os::unix::ffi::OsStrExt;
    let t = TestDir::with_hopper("a_sweep_with_warm_starts_refuses_an_out_that_is_not_utf8");
    t.write("p.toml", &hopper_text());
    let out = OsStr::from_bytes(b"sweep\xff");
    let sweep = |extra: &[&str]| {
        t.vito()
            .args([
                "sweep",
                "p.toml",
                "--grid",
                "contacts.friction=0.5",
                "--out",
            ])
            .args([out])
            .args(["--set", "solver.ipopt.max_iter=2"])
            .args(extra)
            .run()
    };
    for extra in [
        &["--warm-start", "neighbour", "--neighbour-rounds", "0"][..],
        &[][..],
    ] {
        let run = sweep(extra);
        assert_eq!(run.code, 2, "{extra:?}: {}", run.stderr);
        assert!(
            run.stderr.contains("the directory's name is not UTF-8")
                && run
                    .stderr
                    .contains("--warm-start none and --neighbour-rounds 0"),
            "{}",
            run.stderr
        );
        assert!(!t.path().join(out).exists());
    }
    let run = sweep(&["--neighbour-rounds", "0"]);
    assert_eq!(run.code, 1, "{}", run.stderr);
    assert!(t.path().join(out).join(vito::sweep::TABLE_CSV).exists());
}
