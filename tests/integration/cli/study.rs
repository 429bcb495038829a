//! `vito study tracking` and `vito study tracking-collect`: figure 6 over a set of gaits.

use super::util::{TestDir, says};
use crate::common::swing::write_pendulum_swing;

/// The rows of a study table CSV, `knots,method,rms_mean,rms_std`, as (knots, method, mean,
/// std).
fn table(path: &std::path::Path) -> Vec<(usize, String, f64, f64)> {
    let text = std::fs::read_to_string(path).expect("table");
    let mut lines = text.lines();
    assert_eq!(lines.next(), Some("knots,method,rms_mean,rms_std"));
    lines
        .map(|l| {
            let c: Vec<&str> = l.split(',').collect();
            (
                c[0].parse().unwrap(),
                c[1].to_owned(),
                c[2].parse().unwrap(),
                c[3].parse().unwrap(),
            )
        })
        .collect()
}

/// Two gaits of the pendulum's swing (goals 1.5 and 1.0 rad at the shoulder), each its own
/// `vito study tracking` at 5 and 10 knots, collected: each collected row is the mean and
/// population std of the two gaits' rows; every plan is listed with its gait and a
/// recorded deviation; none falls at 0.5 rad, all do at 1e-9 (and the table over the upright
/// plans is then empty). The collect refuses a directory that holds no study, a gait named
/// twice, a collected set as a gait, and an output that would replace a gait.
#[test]
fn tracking_collect_averages_gaits_and_counts_falls() {
    let t = TestDir::new("tracking-collect");
    write_pendulum_swing(t.path());
    for (gait, shoulder) in [("reach", "1.5"), ("short", "1.0")] {
        t.vito()
            .args([
                "study",
                "tracking",
                "--problem",
                "swing.toml",
                "--set",
                &format!("final.q.shoulder={shoulder}"),
                "--knots",
                "5,10",
                "--gains",
                "all=20,2",
                "-q",
                "--out",
                &format!("gaits/{gait}"),
            ])
            .assert_exit(0);
    }
    let run = t
        .vito()
        .args([
            "study",
            "tracking-collect",
            "gaits/reach",
            "gaits/short",
            "--out",
            "set",
        ])
        .assert_exit(0);
    assert!(
        run.stdout.contains("state error over 2 gaits"),
        "{}",
        run.stdout
    );
    let reach = table(&t.path().join("gaits/reach/tracking.csv"));
    let short = table(&t.path().join("gaits/short/tracking.csv"));
    let set = table(&t.path().join("set/tracking.csv"));
    assert_eq!(set.len(), 4, "2 knot counts × 2 methods");
    for ((a, b), s) in reach.iter().zip(&short).zip(&set) {
        assert_eq!((a.0, &a.1), (s.0, &s.1));
        assert_eq!((b.0, &b.1), (s.0, &s.1));
        let (mean, std) = ((a.2 + b.2) / 2.0, (a.2 - b.2).abs() / 2.0);
        assert!((s.2 - mean).abs() <= 1e-6 * mean, "{s:?}: mean {mean}");
        assert!((s.3 - std).abs() <= 1e-6 * mean, "{s:?}: std {std}");
        assert!(a.2 != b.2, "the gaits differ: {a:?} {b:?}");
    }
    let plans = std::fs::read_to_string(t.path().join("set/tracking_plans.csv")).unwrap();
    let mut lines = plans.lines();
    assert_eq!(
        lines.next(),
        Some("gait,knots,method,objective,max_slack,iterations,start,max_deviation,outcome,rms")
    );
    let rows: Vec<Vec<&str>> = lines.map(|l| l.split(',').collect()).collect();
    assert_eq!(rows.len(), 8);
    for r in &rows {
        assert!(["reach", "short"].contains(&r[0]), "{r:?}");
        let deviation: f64 = r[7].parse().expect("a recorded deviation");
        assert!(deviation > 0.0 && deviation < 0.5, "{r:?}");
    }
    let falls = std::fs::read_to_string(t.path().join("set/tracking_falls.csv")).unwrap();
    assert_eq!(
        falls,
        "knots,method,tracked,fell,unrecorded\n5,first_order,2,0,0\n5,variational,2,0,0\n\
         10,first_order,2,0,0\n10,variational,2,0,0\n"
    );
    assert_eq!(table(&t.path().join("set/tracking_upright.csv")), set);

    t.vito()
        .args([
            "study",
            "tracking-collect",
            "gaits/reach",
            "gaits/short",
            "--max-deviation",
            "1e-9",
            "--out",
            "strict",
        ])
        .assert_exit(0);
    let falls = std::fs::read_to_string(t.path().join("strict/tracking_falls.csv")).unwrap();
    assert!(
        falls.lines().skip(1).all(|l| l.ends_with(",2,2,0")),
        "{falls}"
    );
    assert!(table(&t.path().join("strict/tracking_upright.csv")).is_empty());

    std::fs::create_dir(t.path().join("empty")).unwrap();
    fn collect<'a>(args: &[&'a str]) -> Vec<&'a str> {
        let mut all = vec!["study", "tracking-collect"];
        all.extend_from_slice(args);
        all
    }
    says(
        &t,
        &collect(&["gaits/reach", "empty", "--out", "x"]),
        2,
        "give the output directory of a `vito study tracking` run",
    );
    says(
        &t,
        &collect(&["gaits/reach", "gaits/reach", "--out", "x"]),
        2,
        "each gait's directory needs its own name",
    );
    says(
        &t,
        &collect(&["set", "--out", "x"]),
        2,
        "collect one-gait studies, not a collected set",
    );
    says(
        &t,
        &collect(&["gaits/reach", "--out", "gaits/reach"]),
        2,
        "replacing it would delete it",
    );
    says(
        &t,
        &collect(&["gaits/reach", "--max-deviation=-1", "--out", "x"]),
        2,
        "--max-deviation",
    );
    assert!(!t.path().join("x").exists(), "nothing written on bad input");
}
