//! `vito init` writes a starter problem that `vito check` accepts.

use std::path::Path;

use crate::cli::util::{TestDir, VitoCmd, problems_dir};

/// `vito init URDF --base BASE --out OUT`.
fn init(t: &TestDir, urdf: &Path, base: &str, out: &Path) -> VitoCmd {
    t.vito().args([
        std::ffi::OsStr::new("init"),
        urdf.as_os_str(),
        "--base".as_ref(),
        base.as_ref(),
        "--out".as_ref(),
        out.as_os_str(),
    ])
}

#[test]
fn starter_problem_checks() {
    let t = TestDir::new("starter_problem_checks");
    for (urdf, base) in [
        ("robots/hopper_2d.urdf", "fixed"),
        ("robots/littledog/LittleDog.normalized.urdf", "floating"),
        (
            "robots/spring_flamingo/spring_flamingo_passive_ankle.normalized.urdf",
            "planar",
        ),
    ] {
        let out = t.path().join(format!("{base}.toml"));
        let urdf = problems_dir().join(urdf);
        init(&t, &urdf, base, &out).assert_exit(0);
        let run = t
            .vito()
            .args([std::ffi::OsStr::new("check"), out.as_os_str()])
            .assert_exit(0);
        assert!(run.stdout.contains(": ok ("), "{}", run.stdout);
        // Never overwrites.
        t.vito()
            .args([
                std::ffi::OsStr::new("init"),
                urdf.as_os_str(),
                "--out".as_ref(),
                out.as_os_str(),
            ])
            .assert_exit(2);
    }
}

/// Every `.urdf` under `dir`, recursively, sorted.
fn urdfs_under(dir: &Path, found: &mut Vec<std::path::PathBuf>) {
    let Ok(entries) = std::fs::read_dir(dir) else {
        return;
    };
    for entry in entries {
        let path = entry.unwrap().path();
        if path.is_dir() {
            urdfs_under(&path, found);
        } else if path.extension().and_then(|e| e.to_str()) == Some("urdf") {
            found.push(path);
        }
    }
    found.sort();
}

/// `vito init` reads URDFs as `vito inspect` does (one reader): for every URDF of the
/// repository and of `../shared/robots` (the original paper files too, with `-pi/4` limits
/// and spaced collision origins) and every base that `inspect` loads it with, `init` writes a
/// starter that `vito check` accepts.
#[test]
fn init_accepts_every_urdf_that_inspect_loads() {
    let t = TestDir::new("init_accepts_every_urdf_that_inspect_loads");
    let mut urdfs = Vec::new();
    urdfs_under(&problems_dir().join("robots"), &mut urdfs);
    urdfs_under(
        &Path::new(env!("CARGO_MANIFEST_DIR")).join("../shared/robots"),
        &mut urdfs,
    );
    let original_hamr = urdfs
        .iter()
        .filter(|p| p.to_string_lossy().ends_with("hamr/HAMR_scaledV2.urdf"))
        .count();
    assert!(original_hamr >= 1, "{urdfs:?}");
    let mut initialised = 0;
    for (i, urdf) in urdfs.iter().enumerate() {
        for base in ["fixed", "planar", "floating"] {
            let inspect = t
                .vito()
                .args([
                    std::ffi::OsStr::new("inspect"),
                    urdf.as_os_str(),
                    "--base".as_ref(),
                    base.as_ref(),
                ])
                .run();
            if inspect.code != 0 {
                continue;
            }
            let out = t.path().join(format!("{i}_{base}.toml"));
            init(&t, urdf, base, &out).assert_exit(0);
            let run = t
                .vito()
                .args([std::ffi::OsStr::new("check"), out.as_os_str()])
                .run();
            // The one documented refusal: nothing moves (the brick welded to the world).
            if run.code == 2 && run.stderr.contains("the robot has no coordinates") {
                assert_eq!(base, "fixed", "{}", urdf.display());
                continue;
            }
            assert_eq!(run.code, 0, "{} ({base}): {}", urdf.display(), run.stderr);
            assert!(run.stdout.contains(": ok ("), "{}", run.stdout);
            initialised += 1;
        }
    }
    // 2 + 10 URDFs in problems/robots, each with at least one base.
    assert!(initialised >= 12, "only {initialised} starters");
}
