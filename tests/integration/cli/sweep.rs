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

/// The grid of the resume test: finished, failed, finished, timeout.
const GRID: [&str; 6] = ["sweep", "fam.toml", "--grid", "n=5,1,6,2000", "--out", "sw"];
const OPTIONS: [&str; 4] = ["--jobs", "1", "--time-limit", "8"];

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

fn modified(path: &Path) -> SystemTime {
    std::fs::metadata(path).unwrap().modified().unwrap()
}

#[test]
fn sweep_isolates_failures_and_resumes_after_a_kill() {
    let t = TestDir::with_hopper("sweep_isolates_failures_and_resumes_after_a_kill");
    t.write("fam.toml", &hopper_family());
    let sw = t.path().join("sw");

    // Kill the sweep (SIGKILL: no chance to clean up) once its first run is finished.
    let mut sweep = Command::new(env!("CARGO_BIN_EXE_vito"))
        .args(GRID)
        .args(OPTIONS)
        .current_dir(t.path())
        .stdout(Stdio::null())
        .stderr(Stdio::null())
        .spawn()
        .unwrap();
    let first = sw.join("runs/n-5/summary.json");
    let deadline = Instant::now() + Duration::from_secs(60);
    while !(first.exists() && statuses(&sw).first().is_some_and(|s| s == "finished")) {
        assert!(Instant::now() < deadline, "the first run did not finish");
        std::thread::sleep(Duration::from_millis(20));
    }
    sweep.kill().unwrap();
    sweep.wait().unwrap();
    let first_written = modified(&first);
    assert!(
        !sw.join("runs/n-2000").exists(),
        "the sweep was killed early"
    );

    // The rerun keeps the finished run, redoes the others; the failing and the hanging
    // point end up in the table without taking the others down.
    let run = t.vito().args(GRID).args(OPTIONS).assert_exit(1);
    assert!(
        run.stdout
            .contains("4 runs: 2 finished (1 of them before this sweep), 1 failed, 1 timed out"),
        "{}",
        run.stdout
    );
    assert_eq!(modified(&first), first_written, "a finished run was redone");
    assert_eq!(statuses(&sw), ["finished", "failed", "finished", "timeout"]);
    let rows = table(&sw)["rows"].as_array().unwrap().clone();
    let note = rows[1]["note"].as_str().unwrap();
    assert!(
        note.starts_with("exit 2: error:") && note.contains("field `horizon.time_step`"),
        "{note}"
    );
    assert!(
        rows[3]["note"]
            .as_str()
            .unwrap()
            .contains("time limit of 8 s")
    );
    for (row, n) in [(&rows[0], 5), (&rows[2], 6)] {
        let summary = crate::cli::util::summary(&sw.join(row["dir"].as_str().unwrap()));
        assert_eq!(summary["knots"], n);
        assert_eq!(summary["status"], "solve_succeeded");
        assert_eq!(row["objective"], summary["objective"]);
        assert_eq!(row["iterations"], summary["iterations"]);
        assert_eq!(row["max_slack"], summary["max_slack"]);
    }
    let csv = std::fs::read_to_string(sw.join("sweep.csv")).unwrap();
    let lines: Vec<&str> = csv.lines().collect();
    assert_eq!(lines.len(), 5, "{csv}");
    assert!(lines[0].starts_with(
        "index,n,status,solver_status,objective,iterations,wall_time_s,max_slack,dir,note"
    ));
    assert!(
        lines[3].starts_with("2,6,finished,solve_succeeded,"),
        "{csv}"
    );
    // The killed run left no staging directory behind it and no solve is running.
    let leftovers: Vec<_> = std::fs::read_dir(sw.join("runs"))
        .unwrap()
        .map(|e| e.unwrap().file_name().into_string().unwrap())
        .filter(|n| n.starts_with('.'))
        .collect();
    assert!(leftovers.is_empty(), "{leftovers:?}");

    // A third run redoes only what did not finish.
    says(
        &t,
        &["sweep", "fam.toml", "--grid", "n=5,6", "--out", "sw"],
        0,
        "2 runs: 2 finished (2 of them before this sweep)",
    );
    assert_eq!(modified(&first), first_written);
}

#[test]
fn sweep_shards_collect_into_one_table_and_report_plots_it() {
    let t = TestDir::with_hopper("sweep_shards_collect_into_one_table_and_report_plots_it");
    t.write("fam.toml", &hopper_family());
    let grid = ["--grid", "n=5,6", "--grid", "contacts.friction=0.5,0.8"];
    for shard in ["0/2", "1/2"] {
        let out = format!("shard-{}", &shard[..1]);
        t.vito()
            .args(["sweep", "fam.toml"])
            .args(grid)
            .args(["--shard", shard, "--out", &out, "--jobs", "2"])
            .assert_exit(0);
        assert_eq!(statuses(&t.path().join(&out)), ["finished", "finished"]);
    }
    // One shard alone leaves half the grid missing.
    says(
        &t,
        &["sweep", "collect", "shard-1", "--out", "half"],
        0,
        "2 finished, 0 failed, 0 timed out, 2 missing",
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
        [("5", "0.5"), ("5", "0.8"), ("6", "0.5"), ("6", "0.8")]
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
        .args(["sweep", "fam.toml", "--grid", "n=5", "--out", "other"])
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
    ] {
        let run = t
            .vito()
            .args(["sweep", "fam.toml", "--out", "new"])
            .args(&args)
            .assert_exit(2);
        assert!(run.stderr.contains(message), "{args:?}: {}", run.stderr);
        assert!(!t.path().join("new").exists(), "{args:?}");
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
        &["--out", "warm", "--jobs", "1", "--warm-start", "neighbour"],
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
    let cold = [&grid[..], &["--out", "warm"]].concat();
    says(&t, &cold, 0, "3 finished (3 of them before this sweep)");
}
