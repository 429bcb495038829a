//! `vito bench`: its rows, the callback split, and the side-by-side CasADi column (run when
//! Python imports casadi; `tools/independent/spec_casadi.py`).

use std::process::Command;

use crate::cli::util::{TestDir, problems_dir};

/// Whether python3 imports casadi; says so on stderr when it does not (the test is skipped).
fn casadi_importable() -> bool {
    let ok = Command::new("python3")
        .args(["-c", "import casadi"])
        .output()
        .is_ok_and(|o| o.status.success());
    if !ok {
        eprintln!("skipped: python3 cannot import casadi (pip install casadi==3.8.2)");
    }
    ok
}

/// Without a Python that imports casadi the table says why the column is missing, and the
/// vito row still has its iterations and its callback split.
#[test]
fn bench_without_casadi_says_why() {
    let t = TestDir::new("bench_without_casadi_says_why");
    let hopper = problems_dir().join("hopper_2d.toml");
    let run = t
        .vito()
        .env("VITO_PYTHON", "/nonexistent/python3")
        .env("OPENBLAS_NUM_THREADS", "1")
        .args([std::ffi::OsStr::new("bench"), hopper.as_os_str()])
        .assert_exit(0);
    let row = run
        .stdout
        .lines()
        .find(|l| l.starts_with("hopper-2d"))
        .unwrap_or_else(|| panic!("no hopper row:\n{}", run.stdout));
    let fields: Vec<&str> = row.split_whitespace().collect();
    // The count differs between Ipopt versions (87 with Debian 12's 3.11.9, 111 with Debian
    // 13's 3.14.17); the split must show one Hessian per iteration, whichever it is.
    let iterations: usize = fields[9]
        .parse()
        .unwrap_or_else(|e| panic!("iterations field {:?}: {e}: {row}", fields[9]));
    assert!(iterations > 0, "iterations: {row}");
    assert!(
        run.stdout.contains("callbacks: objective")
            && run.stdout.contains(&format!("hessian {iterations} ×")),
        "{}",
        run.stdout
    );
    assert!(
        run.stdout
            .contains("CasADi column: cannot run /nonexistent/python3"),
        "{}",
        run.stdout
    );
    // `--set` changes the NLP: no CasADi solve then, and the reason is given.
    let run = t
        .vito()
        .args([
            std::ffi::OsStr::new("bench"),
            hopper.as_os_str(),
            "--set".as_ref(),
            "horizon.knots=11".as_ref(),
        ])
        .assert_exit(0);
    assert!(
        run.stdout.contains("CasADi column: left out: --set"),
        "{}",
        run.stdout
    );
}

/// With casadi importable: the hopper's CasADi row (the independent optimum 6.948567241 in
/// 109 iterations, recorded in tests/data/independent/hopper_2d.json) beside vito's.
#[test]
fn bench_prints_the_casadi_column_beside_vito() {
    if !casadi_importable() {
        return;
    }
    let t = TestDir::new("bench_prints_the_casadi_column_beside_vito");
    let hopper = problems_dir().join("hopper_2d.toml");
    let run = t
        .vito()
        .env_remove("VITO_PYTHON")
        .env("OPENBLAS_NUM_THREADS", "1")
        .args([std::ffi::OsStr::new("bench"), hopper.as_os_str()])
        .assert_exit(0);
    let rows: Vec<&str> = run
        .stdout
        .lines()
        .skip_while(|l| !l.starts_with("side by side"))
        .collect();
    let row = rows
        .iter()
        .find(|l| l.starts_with("hopper-2d"))
        .unwrap_or_else(|| panic!("no side-by-side hopper row:\n{}", run.stdout));
    let fields: Vec<&str> = row.split_whitespace().collect();
    // vito's count depends on the Ipopt version (87 with 3.11.9, 111 with 3.14.17).
    assert!(
        fields[1].parse::<usize>().is_ok_and(|n| n > 0),
        "vito iterations: {row}"
    );
    assert!(fields.contains(&"109"), "CasADi iterations: {row}");
    assert!(
        rows.iter()
            // Both Ipopts land on the hopper's optimum to 1e-7 (6.94856737 and 6.94856724).
            .any(|l| l.contains("vito objective 6.948567") && l.contains("CasADi 6.9485672412e0")),
        "{}",
        run.stdout
    );
}

/// The CasADi port of the URDF reference problems starts where docs/reference-problems.md says (objective, largest
/// violation, ‖equality residuals‖₂ at the initial guess), as the closed-form two do.
#[test]
fn casadi_port_matches_spec_initial_values() {
    if !casadi_importable() {
        return;
    }
    let script =
        std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join(vito::regress::independent::SCRIPT);
    let out = Command::new("python3")
        .arg(&script)
        .args([
            "--initial",
            "hopper-2d",
            "spring-flamingo-walk",
            "littledog-step",
        ])
        .output()
        .expect("run python3");
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let stdout = String::from_utf8_lossy(&out.stdout);
    let spec = [
        ("hopper-2d", 20.041640625, 1.65, 7.93069),
        (
            "spring-flamingo-walk",
            2400.099870703126,
            14.4959675,
            70.2622742619474,
        ),
        ("littledog-step", 87.026825, 3.67616331, 19.622737633992582),
    ];
    for (line, (name, objective, violation, residual)) in stdout.lines().zip(spec) {
        let v: serde_json::Value = serde_json::from_str(line).unwrap();
        assert_eq!(v["problem"], name);
        let close = |key: &str, want: f64, rel: f64| {
            let got = v[key].as_f64().unwrap();
            assert!(
                (got - want).abs() <= rel * want.abs(),
                "{name} {key}: {got} vs reference {want}"
            );
        };
        close("objective", objective, 1e-12);
        close("max_constraint_violation", violation, 1e-8);
        close("equality_residual_norm", residual, 1e-6);
    }
}
