//! Plan-quality figures of solved plans, from their `trajectory.csv` and the robot's
//! kinematics: the number of contact-mode switches and the largest stance slip speed (the
//! `contacts.mode_block` row of BENCHMARKS.md's Tried and dropped table). Usage:
//! `cargo run --release --example mode_quality -- PROBLEM.toml RUN_DIR...`
//!
//! Per contact and interval k, the contact is *in contact* when its normal impulse c_k exceeds
//! 1e-6 or its signed distance φ(q_{k+1}) (at the knot the impulse acts on, computed here from
//! q) is below 1e-6; a switch is a change of that state between neighbouring intervals
//! (touchdowns plus lift-offs, summed over the contacts). The stance slip speed of an interval
//! with c_k > 1e-6 is the horizontal distance the contact point moves from q_k to q_{k+1} over
//! h_k (problem units: m/s, or mm/ms for HAMR). Only the problem's robot, contacts and terrain
//! are read from PROBLEM.toml, so overrides that change neither need not be repeated.

use std::path::{Path, PathBuf};
use std::process::ExitCode;

use vito::contact::signed_distance;
use vito::discrete::{Mechanics, ModelMechanics};
use vito::files::trajectory_csv::read_csv;

/// Threshold on c and φ for "in contact" (problem units).
const IN_CONTACT: f64 = 1e-6;

fn main() -> ExitCode {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let [problem, runs @ ..] = args.as_slice() else {
        eprintln!("usage: mode_quality PROBLEM.toml RUN_DIR...");
        return ExitCode::from(2);
    };
    match run(Path::new(problem), runs) {
        Ok(()) => ExitCode::SUCCESS,
        Err(e) => {
            eprintln!("mode_quality: {e}");
            ExitCode::from(2)
        }
    }
}

fn run(problem: &Path, runs: &[String]) -> Result<(), String> {
    let loaded = vito::problem::load(problem, &[]).map_err(|e| e.to_string())?;
    let spec = &loaded.spec;
    let mech = ModelMechanics::load(spec).map_err(|e| e.to_string())?;
    println!("run,switches,max_stance_slip_speed");
    for run in runs {
        let path = PathBuf::from(run).join("trajectory.csv");
        let text =
            std::fs::read_to_string(&path).map_err(|e| format!("{}: {e}", path.display()))?;
        let table = read_csv(&text).map_err(|e| format!("{}: {e}", path.display()))?;
        let column = |name: &str| {
            table
                .column(name)
                .ok_or_else(|| format!("{}: no column `{name}`", path.display()))
        };
        let time = column("time")?;
        let coordinates = loaded
            .robot
            .coordinates
            .iter()
            .map(|name| column(name))
            .collect::<Result<Vec<_>, _>>()?;
        let q: Vec<Vec<f64>> = (0..time.len())
            .map(|k| coordinates.iter().map(|c| c[k]).collect())
            .collect();
        let intervals = time.len() - 1;
        let (mut switches, mut slip) = (0usize, 0.0_f64);
        for (i, contact) in spec.contacts.iter().enumerate() {
            let normal = column(&format!("{}_normal", contact.name))?;
            let mut previous = None;
            for k in 0..intervals {
                let (a, b) = (
                    mech.contact_position(i, &q[k]),
                    mech.contact_position(i, &q[k + 1]),
                );
                let phi = signed_distance(&spec.terrain, &b);
                let touching = normal[k] > IN_CONTACT || phi < IN_CONTACT;
                if previous.is_some_and(|p| p != touching) {
                    switches += 1;
                }
                previous = Some(touching);
                if normal[k] > IN_CONTACT {
                    let h = time[k + 1] - time[k];
                    slip = slip.max((b[0] - a[0]).hypot(b[1] - a[1]) / h);
                }
            }
        }
        println!("{run},{switches},{slip:.6e}");
    }
    Ok(())
}
