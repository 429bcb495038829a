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
        // The integrator's comment offers every integrator the file accepts.
        let text = std::fs::read_to_string(&out).unwrap();
        assert!(
            text.contains("integrator = \"midpoint\"   # midpoint | euler | galerkin4 | galerkin6"),
            "{text}"
        );
        // The base as the file writes it, not the enum's debug name.
        assert!(
            run.stdout.contains(&format!("({base} base)")),
            "{}",
            run.stdout
        );
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
/// repository (`problems/robots/`: the original paper files too, with `-pi/4` limits and
/// spaced collision origins, beside their normalised copies) and every base that `inspect` loads it with, `init` writes a
/// starter that `vito check` accepts.
#[test]
fn init_accepts_every_urdf_that_inspect_loads() {
    let t = TestDir::new("init_accepts_every_urdf_that_inspect_loads");
    let mut urdfs = Vec::new();
    urdfs_under(&problems_dir().join("robots"), &mut urdfs);
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
            let made = init(&t, urdf, base, &out).run();
            // The one documented refusal: nothing moves (the brick welded to the world).
            if made.code == 2 && made.stderr.contains("the robot has no coordinates") {
                assert_eq!(base, "fixed", "{}", urdf.display());
                assert!(!out.exists(), "{}", out.display());
                continue;
            }
            assert_eq!(made.code, 0, "{} ({base}): {}", urdf.display(), made.stderr);
            let run = t
                .vito()
                .args([std::ffi::OsStr::new("check"), out.as_os_str()])
                .run();
            assert_eq!(run.code, 0, "{} ({base}): {}", urdf.display(), run.stderr);
            assert!(run.stdout.contains(": ok ("), "{}", run.stdout);
            initialised += 1;
        }
    }
    // 2 + 10 URDFs in problems/robots, each with at least one base.
    assert!(initialised >= 12, "only {initialised} starters");
}

/// A `<link>` with a diagonal inertia about its centre of mass at `com`, and `extra` inside.
fn urdf_link(name: &str, mass: f64, inertia: [f64; 3], com: &str, extra: &str) -> String {
    format!(
        r#"<link name="{name}"><inertial><origin xyz="{com}"/><mass value="{mass}"/><inertia ixx="{}" ixy="0" ixz="0" iyy="{}" iyz="0" izz="{}"/></inertial>{extra}</link>
"#,
        inertia[0], inertia[1], inertia[2]
    )
}

fn urdf_joint(
    name: &str,
    parent: &str,
    child: &str,
    xyz: &str,
    axis: &str,
    limits: [f64; 2],
) -> String {
    format!(
        r#"<joint name="{name}" type="revolute"><parent link="{parent}"/><child link="{child}"/><origin xyz="{xyz}"/><axis xyz="{axis}"/><limit lower="{}" upper="{}" effort="100" velocity="20"/></joint>
"#,
        limits[0], limits[1]
    )
}

/// A 12-joint quadruped as ROS packages ship it: no transmissions, massless foot links
/// (no `<inertial>`, no collision) at the ends of the legs, hip and knee limits that exclude
/// 0 (the starter bends them to mid-range, which puts each foot under its hip).
fn quadruped() -> String {
    let mut x = String::from("<?xml version=\"1.0\"?>\n<robot name=\"quadruped\">\n");
    x += &urdf_link("trunk", 8.0, [0.05, 0.15, 0.15], "0 0 0", "");
    for (leg, sx, sy) in [
        ("FL", 1.0, 1.0),
        ("FR", 1.0, -1.0),
        ("HL", -1.0, 1.0),
        ("HR", -1.0, -1.0),
    ] {
        x += &urdf_link(&format!("{leg}_hip"), 0.5, [1e-3; 3], "0 0 0", "");
        x += &urdf_link(
            &format!("{leg}_thigh"),
            1.0,
            [4e-3, 4e-3, 5e-4],
            "0 0 -0.1",
            "",
        );
        x += &urdf_link(
            &format!("{leg}_calf"),
            0.3,
            [1e-3, 1e-3, 1e-4],
            "0 0 -0.1",
            "",
        );
        x += &format!("<link name=\"{leg}_foot\"/>\n");
        x += &urdf_joint(
            &format!("{leg}_HAA"),
            "trunk",
            &format!("{leg}_hip"),
            &format!("{} {} 0", 0.2 * sx, 0.1 * sy),
            "1 0 0",
            [-0.8, 0.8],
        );
        x += &urdf_joint(
            &format!("{leg}_HFE"),
            &format!("{leg}_hip"),
            &format!("{leg}_thigh"),
            &format!("0 {} 0", 0.05 * sy),
            "0 1 0",
            [0.2, 1.0],
        );
        x += &urdf_joint(
            &format!("{leg}_KFE"),
            &format!("{leg}_thigh"),
            &format!("{leg}_calf"),
            "0 0 -0.2",
            "0 1 0",
            [-1.6, -0.8],
        );
        x += &format!(
            "<joint name=\"{leg}_foot_fixed\" type=\"fixed\"><parent link=\"{leg}_calf\"/><child link=\"{leg}_foot\"/><origin xyz=\"0 0 -0.2\"/></joint>\n"
        );
    }
    x + "</robot>\n"
}

/// A 6-joint biped with point feet (zero-radius collision spheres under its feet) and a
/// camera frame, straight-legged at 0.
fn biped() -> String {
    let mut x = String::from("<?xml version=\"1.0\"?>\n<robot name=\"biped\">\n");
    x += &urdf_link("pelvis", 10.0, [0.1, 0.08, 0.06], "0 0 0", "");
    x += "<link name=\"camera_optical_frame\"/>\n<joint name=\"camera\" type=\"fixed\"><parent link=\"pelvis\"/><child link=\"camera_optical_frame\"/><origin xyz=\"0.1 0 0.1\"/></joint>\n";
    for (leg, sy) in [("L", 1.0), ("R", -1.0)] {
        x += &urdf_link(
            &format!("{leg}_thigh"),
            2.0,
            [0.02, 0.02, 2e-3],
            "0 0 -0.2",
            "",
        );
        x += &urdf_link(
            &format!("{leg}_shin"),
            1.0,
            [0.01, 0.01, 1e-3],
            "0 0 -0.2",
            "",
        );
        x += &urdf_link(
            &format!("{leg}_foot"),
            0.3,
            [1e-3; 3],
            "0 0 -0.02",
            r#"<collision><origin xyz="0 0 -0.04"/><geometry><sphere radius="0"/></geometry></collision>"#,
        );
        x += &urdf_joint(
            &format!("{leg}_hip"),
            "pelvis",
            &format!("{leg}_thigh"),
            &format!("0 {} -0.05", 0.1 * sy),
            "0 1 0",
            [-1.5, 1.5],
        );
        x += &urdf_joint(
            &format!("{leg}_knee"),
            &format!("{leg}_thigh"),
            &format!("{leg}_shin"),
            "0 0 -0.4",
            "0 1 0",
            [-0.1, 2.2],
        );
        x += &urdf_joint(
            &format!("{leg}_ankle"),
            &format!("{leg}_shin"),
            &format!("{leg}_foot"),
            "0 0 -0.4",
            "0 1 0",
            [-1.0, 1.0],
        );
    }
    x + "</robot>\n"
}

/// `vito init ROBOT --base floating` then `vito solve` unchanged: the robot stands in place
/// on its feet. Returns the largest foot and base displacement from the first knot.
fn init_and_stand(t: &TestDir, name: &str, urdf: &str, feet: usize) -> (f64, f64) {
    std::fs::create_dir_all(t.path().join("robots")).unwrap();
    std::fs::create_dir_all(t.path().join("problems")).unwrap();
    t.write(&format!("robots/{name}.urdf"), urdf);
    let problem = t.path().join(format!("problems/{name}.toml"));
    init(
        t,
        Path::new(&format!("robots/{name}.urdf")),
        "floating",
        &problem,
    )
    .assert_exit(0);
    let text = std::fs::read_to_string(&problem).unwrap();
    assert!(
        text.contains(&format!("urdf = \"../robots/{name}.urdf\"")),
        "{text}"
    );
    // No transmissions: the starter says which rule chose the inputs (every joint).
    assert!(
        text.contains("the inputs are from every movable joint ("),
        "{text}"
    );
    let check = t
        .vito()
        .args([std::ffi::OsStr::new("check"), problem.as_os_str()])
        .assert_exit(0);
    assert!(
        check.stdout.contains(&format!("contacts:    {feet} (")),
        "{}",
        check.stdout
    );
    assert!(
        !check.stderr.contains("below the terrain"),
        "{}",
        check.stderr
    );
    t.vito()
        .args([
            std::ffi::OsStr::new("solve"),
            problem.as_os_str(),
            "--quiet".as_ref(),
            "--out".as_ref(),
            name.as_ref(),
        ])
        .env("OPENBLAS_NUM_THREADS", "1")
        .assert_exit(0);
    let out = t.path().join(name);
    let s = crate::cli::util::summary(&out);
    assert_eq!(s["status"], "solve_succeeded", "{name}");
    assert!(
        s["max_slack"].as_f64().unwrap() <= 1e-4,
        "{name}: {}",
        s["max_slack"]
    );
    // Feet and base from the trajectory, by the problem's own mechanics.
    let loaded = vito::problem::load(&problem, &[]).unwrap();
    let mech = vito::pipeline::mechanics(&loaded.spec).unwrap();
    let csv = std::fs::read_to_string(out.join("trajectory.csv")).unwrap();
    let q = vito::files::trajectory_csv::read_trajectory(&csv, &loaded.robot.coordinates, &[])
        .unwrap()
        .q;
    use vito::discrete::Mechanics;
    let (mut foot_moved, mut base_moved) = (0.0f64, 0.0f64);
    for qk in &q {
        for i in 0..feet {
            let (a, b) = (
                mech.contact_position(i, &q[0]),
                mech.contact_position(i, qk),
            );
            foot_moved = foot_moved.max((0..3).map(|k| (a[k] - b[k]).abs()).fold(0.0, f64::max));
        }
        base_moved = base_moved.max((0..3).map(|k| (qk[k] - q[0][k]).abs()).fold(0.0, f64::max));
    }
    // The feet start on the ground.
    for i in 0..feet {
        assert!(
            mech.contact_position(i, &q[0])[2].abs() < 1e-12,
            "{name}: foot {i}"
        );
    }
    eprintln!("{name}: feet moved {foot_moved:.3e}, base {base_moved:.3e}");
    (foot_moved, base_moved)
}

#[test]
fn a_quadruped_starter_stands_in_place() {
    let t = TestDir::new("a_quadruped_starter_stands_in_place");
    let (feet, base) = init_and_stand(&t, "quadruped", &quadruped(), 4);
    assert!(
        feet <= 1e-3 && base <= 1e-2,
        "feet moved {feet:e} m, base {base:e} m"
    );
}

#[test]
fn a_biped_starter_stands_in_place() {
    let t = TestDir::new("a_biped_starter_stands_in_place");
    let (feet, base) = init_and_stand(&t, "biped", &biped(), 2);
    assert!(
        feet <= 1e-3 && base <= 1e-2,
        "feet moved {feet:e} m, base {base:e} m"
    );
}

/// Printed to stdout redirected into a file, the starter names the URDF relative to that
/// file; printed to a pipe, by its absolute path.
#[test]
fn a_printed_starter_names_the_urdf_from_where_it_is_saved() {
    let t = TestDir::new("a_printed_starter_names_the_urdf");
    std::fs::create_dir_all(t.path().join("robots")).unwrap();
    std::fs::create_dir_all(t.path().join("problems")).unwrap();
    t.write("robots/biped.urdf", &biped());
    let file = std::fs::File::create(t.path().join("problems/biped.toml")).unwrap();
    let status = std::process::Command::new(env!("CARGO_BIN_EXE_vito"))
        .current_dir(t.path())
        .args(["init", "robots/biped.urdf", "--base", "floating"])
        .stdout(file)
        .status()
        .unwrap();
    assert!(status.success());
    let text = std::fs::read_to_string(t.path().join("problems/biped.toml")).unwrap();
    assert!(text.contains("urdf = \"../robots/biped.urdf\""), "{text}");
    let run = t
        .vito()
        .args(["init", "robots/biped.urdf", "--base", "floating"])
        .assert_exit(0);
    let absolute = std::path::absolute(t.path().join("robots/biped.urdf")).unwrap();
    assert!(
        run.stdout
            .contains(&format!("urdf = {:?}", absolute.display().to_string())),
        "{}",
        run.stdout
    );
}

/// `--out` into a directory that does not exist names the directory and how to make it.
#[test]
fn init_into_a_missing_directory_names_it() {
    let t = TestDir::new("init_missing_directory");
    let urdf = problems_dir().join("robots/hopper_2d.urdf");
    let out = t.path().join("my_robot").join("problem.toml");
    let run = init(&t, &urdf, "fixed", &out).assert_exit(2);
    let dir = t.path().join("my_robot");
    assert!(
        run.stderr
            .contains(&format!("the directory {} does not exist", dir.display())),
        "{}",
        run.stderr
    );
    assert!(!dir.exists());
}

/// `inspect` prints the total mass in kg without the sum's round-off digits (LittleDog's
/// links sum to 2.7464000000000004 in floating point).
#[test]
fn inspect_prints_the_total_mass_in_kg() {
    let t = TestDir::new("inspect_total_mass");
    let urdf = problems_dir().join("robots/littledog/LittleDog.normalized.urdf");
    let run = t
        .vito()
        .args([
            std::ffi::OsStr::new("inspect"),
            urdf.as_os_str(),
            "--base".as_ref(),
            "floating".as_ref(),
        ])
        .assert_exit(0);
    assert!(
        run.stdout.contains("total mass: 2.7464 kg\n"),
        "{}",
        run.stdout
    );
}

/// The starter's commented clearance term and gait load as they stand once uncommented, for
/// the robot's own contacts.
#[test]
fn starter_steering_examples_check_once_uncommented() {
    let t = TestDir::new("starter_steering_examples");
    for (urdf, base, contact) in [
        ("robots/hopper_2d.urdf", "fixed", "foot_contact"),
        (
            "robots/littledog/LittleDog.normalized.urdf",
            "floating",
            "front_left",
        ),
    ] {
        let out = t.path().join(format!("{base}.toml"));
        init(&t, &problems_dir().join(urdf), base, &out).assert_exit(0);
        let text = std::fs::read_to_string(&out).unwrap();
        let start = text.find("# [[frame]]").expect("a commented frame term");
        let end = start + text[start..].find("# offsets").expect("commented offsets");
        let end = end + text[end..].find('\n').unwrap();
        let block = &text[start..end];
        assert!(block.contains(contact), "{block}");
        let uncommented: String = block
            .lines()
            .map(|line| {
                let rest = line.strip_prefix("# ").unwrap_or("");
                if rest.starts_with('[') || rest.split(" = ").count() > 1 {
                    format!("{rest}\n")
                } else {
                    "\n".to_string()
                }
            })
            .collect();
        let edited = out.with_file_name(format!("{base}-steered.toml"));
        std::fs::write(&edited, text.replace(block, &uncommented)).unwrap();
        let run = t
            .vito()
            .args([std::ffi::OsStr::new("check"), edited.as_os_str()])
            .assert_exit(0);
        assert!(run.stdout.contains(": ok ("), "{}", run.stdout);
    }
}

/// Joint names TOML cannot take as bare keys (the Allegro hand's `joint_0.0`, read as a
/// table) are quoted wherever the starter writes them as keys, and the starter checks.
#[test]
fn dotted_joint_names_are_quoted_keys() {
    let t = TestDir::new("dotted_joint_names_are_quoted_keys");
    let body = urdf_link("palm", 1.0, [0.01; 3], "0 0 0", "")
        + &urdf_link("link_0.0", 0.1, [0.001; 3], "0 0 0.05", "")
        + &urdf_link("link 1", 0.1, [0.001; 3], "0 0 0.05", "")
        + &urdf_joint(
            "joint_0.0",
            "palm",
            "link_0.0",
            "0 0 0.1",
            "0 1 0",
            [-1.0, 1.0],
        )
        + &urdf_joint(
            "joint 1",
            "link_0.0",
            "link 1",
            "0 0 0.1",
            "0 1 0",
            [-1.0, 1.0],
        );
    let urdf = t.path().join("hand.urdf");
    std::fs::write(&urdf, format!("<robot name=\"hand\">\n{body}</robot>\n")).unwrap();
    let out = t.path().join("hand.toml");
    init(&t, &urdf, "fixed", &out).assert_exit(0);
    let text = std::fs::read_to_string(&out).unwrap();
    assert!(text.contains("\n\"joint_0.0\" = 0.0   # [rad]"), "{text}");
    assert!(text.contains("\n\"joint 1\" = 0.0   # [rad]"), "{text}");
    assert!(text.contains("[final.q]\n\"joint_0.0\" = 0.0\n"), "{text}");
    assert!(
        text.contains("# bounds = { \"joint_0.0\" = [-1.0, 1.0] }"),
        "{text}"
    );
    t.vito()
        .args([std::ffi::OsStr::new("check"), out.as_os_str()])
        .assert_exit(0);
}

/// An end link named `base` stood on with a floating base would name the columns `base_x`
/// … of its impulses beside the base's coordinates: it becomes the foot `base_foot` (the
/// UR arms' `base` link), and the starter checks. A URDF contact named so is renamed the
/// same way, as a point of its own.
#[test]
fn feet_never_clash_with_coordinate_columns() {
    let t = TestDir::new("feet_never_clash_with_coordinate_columns");
    let sphere = r#"<collision><geometry><sphere radius="0"/></geometry></collision>"#;
    for (name, extra, from_urdf) in [
        ("end", "", "from_urdf = \"none\""),
        ("sphere", sphere, "from_urdf = [\"shin\"]"),
    ] {
        let body = urdf_link("trunk", 2.0, [0.02; 3], "0 0 0", "")
            + &urdf_link("base", 0.2, [0.001; 3], "0 0 -0.1", extra)
            + &urdf_link("shin", 0.2, [0.001; 3], "0 0 -0.1", extra)
            + &urdf_joint("hip", "trunk", "base", "0.1 0 -0.1", "0 1 0", [-1.0, 1.0])
            + &urdf_joint("knee", "trunk", "shin", "-0.1 0 -0.1", "0 1 0", [-1.0, 1.0]);
        let urdf = t.path().join(format!("{name}.urdf"));
        std::fs::write(&urdf, format!("<robot name=\"legs\">\n{body}</robot>\n")).unwrap();
        let out = t.path().join(format!("{name}.toml"));
        init(&t, &urdf, "floating", &out).assert_exit(0);
        let text = std::fs::read_to_string(&out).unwrap();
        assert!(
            text.contains("name = \"base_foot\"\nlink = \"base\"\n"),
            "{name}: {text}"
        );
        assert!(text.contains(from_urdf), "{name}: {text}");
        let run = t
            .vito()
            .args([std::ffi::OsStr::new("check"), out.as_os_str()])
            .assert_exit(0);
        assert!(run.stdout.contains(": ok ("), "{name}: {}", run.stdout);
    }
}
