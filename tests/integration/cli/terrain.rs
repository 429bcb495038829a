//! Terrain beyond a plane: stairs along any heading, blocks and height maps. The trajectory
//! file's world-frame impulse columns close the brick's momentum balance on stairs, computed
//! from the file alone; bad terrain entries are input errors naming their field.

use std::path::{Path, PathBuf};

use crate::cli::util::{TestDir, column_named, csv_columns, hopper_text, says};

fn fixture(name: &str) -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("tests/data/problems")
        .join(name)
}

/// The largest residual of the brick's linear momentum balance over every interior knot,
/// m (x_{k+1} − 2x_k + x_{k−1})/h − m g h ẑ − Σ_c F_c (row k's world impulses), from the
/// trajectory file's `base_*` and `<c>_fx/_fy/_fz` columns alone, and the same with the
/// impulse rebuilt as if the ground's frame were world x, y, z (normal along +z, friction
/// along x and y).
fn momentum_residuals(dir: &Path) -> (f64, f64) {
    let columns = csv_columns(&std::fs::read_to_string(dir.join("trajectory.csv")).unwrap());
    let column = |name: &str| column_named(&columns, name);
    let corners: Vec<String> = columns
        .iter()
        .filter_map(|(n, _)| n.strip_suffix("_fx").map(str::to_owned))
        .collect();
    assert_eq!(corners.len(), 8);
    let (mass, h, g) = (1.0, 0.025, 9.81);
    let base = ["base_x", "base_y", "base_z"].map(column);
    let world: Vec<[Vec<f64>; 3]> = corners
        .iter()
        .map(|c| ["fx", "fy", "fz"].map(|a| column(&format!("{c}_{a}"))))
        .collect();
    let flat: Vec<[Vec<f64>; 3]> = corners
        .iter()
        .map(|c| {
            let f = |d: &str| column(&format!("{c}_friction_{d}"));
            let (px, py, mx, my) = (f("+x"), f("+y"), f("-x"), f("-y"));
            [
                px.iter().zip(&mx).map(|(a, b)| a - b).collect(),
                py.iter().zip(&my).map(|(a, b)| a - b).collect(),
                column(&format!("{c}_normal")),
            ]
        })
        .collect();
    let knots = base[0].len();
    let residual = |impulses: &[[Vec<f64>; 3]]| {
        let mut worst = 0.0_f64;
        for k in 1..knots - 1 {
            for i in 0..3 {
                let change = mass * (base[i][k + 1] - 2.0 * base[i][k] + base[i][k - 1]) / h;
                let gravity = if i == 2 { -mass * g * h } else { 0.0 };
                let contact: f64 = impulses.iter().map(|f| f[i][k]).sum();
                worst = worst.max((change - gravity - contact).abs());
            }
        }
        worst
    };
    (residual(&world), residual(&flat))
}

/// The brick thrown across stairs that climb along 30°, their edges smoothed over 3 cm so that
/// its corners land where the normal turns: simulated and planned, the file's world impulses
/// close its momentum balance to 1e-8 N·s, where the ground's frame read as world x, y, z
/// misses it by more than 1e-3 N·s.
#[test]
fn world_impulses_close_the_momentum_balance_on_stairs() {
    let t = TestDir::new("world_impulses_close_the_momentum_balance_on_stairs");
    let file = fixture("brick_stairs.toml");
    let file = file.to_str().unwrap();
    for (command, out) in [("simulate", "sim"), ("solve", "plan")] {
        let dir = t.path().join(out);
        t.vito()
            .args([command, file, "-q", "--out", dir.to_str().unwrap()])
            .assert_exit(0);
        let (world, flat) = momentum_residuals(&dir);
        assert!(world <= 1e-8, "{command}: residual {world:e} N·s");
        assert!(
            flat > 1e-3,
            "{command}: the flat reading misses by only {flat:e}"
        );
    }
}

/// A problem on stairs, a block and a height map passes the derivative check, with a corner
/// placed on a stair's edge.
#[test]
fn every_terrain_kind_has_exact_derivatives() {
    let t = TestDir::new("every_terrain_kind_has_exact_derivatives");
    let base = std::fs::read_to_string(fixture("brick_stairs.toml"))
        .unwrap()
        .replace(
            "../../../problems/robots/",
            &format!("{}/problems/robots/", env!("CARGO_MANIFEST_DIR")),
        )
        .replace("knots = 41", "knots = 6");
    let mut map = String::from("# heights [m]\n");
    for j in 0..8 {
        let row: Vec<String> = (0..10)
            .map(|i| format!("{}", 0.01 * (f64::from(i) * 0.7 + f64::from(j) * 1.3).sin()))
            .collect();
        map.push_str(&row.join(","));
        map.push('\n');
    }
    t.write("field.csv", &map);
    let extra = "\n[[terrain.block]]\ncenter = [0.3, -0.1]\nsize = [0.2, 0.3]\nheight = 0.05\nwidth = 0.02\nyaw = 25\n\n[terrain.height_map]\nfile = \"field.csv\"\nspacing = [0.1, 0.1]\norigin = [-0.2, -0.3]\n";
    let text = base.replace("\n[horizon]", &format!("{extra}\n[horizon]"));
    let problem = t.write("all.toml", &text);
    says(
        &t,
        &["check", "--derivatives", problem.to_str().unwrap()],
        0,
        "derivatives",
    );
    // The stairs alone, with the brick's lowest corner on the first edge at the start.
    let on_edge = base.replace(
        "q = [0.0, 0.0, 0.3, 0.3, -0.2, 0.1]",
        "q = [0.0866, 0.05, 0.045, 0.0, 0.0, 0.5236]",
    );
    let problem = t.write("edge.toml", &on_edge);
    says(
        &t,
        &["check", "--derivatives", problem.to_str().unwrap()],
        0,
        "derivatives",
    );
}

/// Bad terrain entries are input errors (exit 2) naming the field and what to do.
#[test]
fn bad_terrain_entries_name_their_field() {
    let t = TestDir::with_hopper("bad_terrain_entries_name_their_field");
    let hopper = t.write("hopper.toml", &hopper_text());
    let hopper = hopper.to_str().unwrap();
    for (set, field, text) in [
        (
            "terrain.stairs=[{start = 0.2, count = 0, rise = 0.1, run = 0.2, width = 0.01}]",
            "terrain.stairs[0].count",
            "whole number from 1 to 100",
        ),
        (
            "terrain.stairs=[{start = 0.2, count = 2, rise = 0.1, run = -0.2, width = 0.01}]",
            "terrain.stairs[0].run",
            "",
        ),
        (
            "terrain.step=[{edge = 0.2, rise = 0.1, width = 0.01, heading = 90}]",
            "terrain.step[0].heading",
            "heading 0 or 180",
        ),
        (
            "terrain.block=[{center = [0, 0], size = [0.1, 0], height = 0.1, width = 0.01}]",
            "terrain.block[0].size[1]",
            "",
        ),
    ] {
        let run = says(&t, &["check", hopper, "--set", set], 2, field);
        assert!(run.stderr.contains(text), "{set}: {}", run.stderr);
    }
    t.write("ragged.csv", "0 0.1\n0.2\n");
    for (file, text) in [
        ("missing.csv", "cannot read"),
        (
            "ragged.csv",
            "line 2 has 1 heights where the first row has 2",
        ),
    ] {
        let problem = t.write(
            "map.toml",
            &format!(
                "{}\n[terrain.height_map]\nfile = \"{file}\"\nspacing = [0.1, 0.1]\n",
                hopper_text()
            ),
        );
        let run = says(&t, &["check", problem.to_str().unwrap()], 2, text);
        assert!(
            run.stderr.contains("terrain.height_map.file"),
            "{}",
            run.stderr
        );
    }
}

/// Spheres stand on flat ground only, and features on a slope are refused.
#[test]
fn spheres_off_flat_ground_and_features_on_a_slope_are_refused() {
    let t = TestDir::new("spheres_off_flat_ground_and_features_on_a_slope_are_refused");
    let file = fixture("brick_stairs.toml");
    let file = file.to_str().unwrap();
    says(
        &t,
        &[
            "check",
            file,
            "--set",
            "contacts.point=[{name = \"ball\", link = \"brick\", point = [0, 0, 0], radius = 0.02}]",
        ],
        2,
        "spheres are supported on flat ground only",
    );
    says(
        &t,
        &["check", file, "--set", "terrain.slope.angle=10"],
        2,
        "features on a slope are not supported",
    );
}
