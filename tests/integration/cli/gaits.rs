//! Contact windows and gaits from the command line: impossible windows refused with exit 2
//! naming them, and a flight window that lifts the hopper's foot, read back from
//! trajectory.csv (its distance, impulse and position columns).

use super::util::{TestDir, hopper_text, says};
use vito::files::trajectory_csv::read_csv;

#[test]
fn a_window_outside_the_horizon_is_refused_by_name() {
    let t = TestDir::with_hopper("window-outside");
    let text = hopper_text()
        + "\n[[contact_window]]\ncontact = \"foot_contact\"\nphase = \"flight\"\nwindow = [0.8, 1.2]\n";
    t.write("p.toml", &text);
    says(&t, &["check", "p.toml"], 2, "contact_window[0].window");
}

#[test]
fn stance_overlapping_flight_is_refused_naming_both() {
    let t = TestDir::with_hopper("window-overlap");
    let text = hopper_text()
        + "\n[[contact_window]]\ncontact = \"foot_contact\"\nphase = \"stance\"\nwindow = [0.2, 0.5]\n"
        + "\n[[contact_window]]\ncontact = \"foot_contact\"\nphase = \"flight\"\nwindow = [0.45, 0.6]\n";
    t.write("p.toml", &text);
    let run = says(&t, &["check", "p.toml"], 2, "contact_window[1].window");
    let all = run.stdout + &run.stderr;
    assert!(
        all.contains("contact_window[0]") && all.contains("knot 9"),
        "{all}"
    );
}

#[test]
fn a_flight_window_lifts_the_foot() {
    let t = TestDir::with_hopper("flight-window");
    let text = hopper_text()
        + "\n[[contact_window]]\ncontact = \"foot_contact\"\nphase = \"flight\"\nwindow = [0.3, 0.5]\nclearance = 0.05\n";
    t.write("p.toml", &text);
    t.vito()
        .args(["solve", "p.toml", "--quiet", "--out", "out"])
        .env("OPENBLAS_NUM_THREADS", "1")
        .assert_exit(0);
    let csv = std::fs::read_to_string(t.path().join("out/trajectory.csv")).unwrap();
    let table = read_csv(&csv).unwrap();
    let column = |name: &str| table.column(name).unwrap_or_else(|| panic!("no {name}"));
    let distance = column("foot_contact_distance");
    let normal = column("foot_contact_normal");
    // h = 0.05: knots 6..=10 lie in [0.3, 0.5] s; row k − 1 holds the impulse into knot k.
    for k in 6..=10 {
        assert!(distance[k] >= 0.05 - 1e-6, "knot {k}: {distance:?}");
        assert!(
            normal[k - 1].abs() <= 1e-6,
            "interval {}: {normal:?}",
            k - 1
        );
    }
    // The position columns against the hopper's foot from q: (x + r sin θ, 0, z − r cos θ).
    let (x, z, theta, r) = (column("x"), column("z"), column("theta"), column("r"));
    let (fx, fy, fz) = (
        column("foot_contact_x"),
        column("foot_contact_y"),
        column("foot_contact_z"),
    );
    for k in 0..x.len() {
        assert!(
            (fx[k] - (x[k] + r[k] * theta[k].sin())).abs() < 1e-9,
            "knot {k}"
        );
        assert!(fy[k].abs() < 1e-12, "knot {k}");
        assert!(
            (fz[k] - (z[k] - r[k] * theta[k].cos())).abs() < 1e-9,
            "knot {k}"
        );
        assert!(
            (fz[k] - distance[k]).abs() < 1e-9,
            "flat ground: z is the distance"
        );
    }
}
