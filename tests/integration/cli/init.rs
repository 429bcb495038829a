//! `vito init` writes a starter problem that `vito check` accepts.

use crate::cli::util::{TestDir, problems_dir};

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
        t.vito()
            .args([
                std::ffi::OsStr::new("init"),
                urdf.as_os_str(),
                "--base".as_ref(),
                base.as_ref(),
                "--out".as_ref(),
                out.as_os_str(),
            ])
            .assert_exit(0);
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
