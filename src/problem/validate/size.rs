//! Whether the NLP a problem asks for can fit in memory, estimated from its sizes before
//! anything per knot is allocated (a billion knots must be an error, not an abort).

use super::context::Context;
use crate::problem::{ProblemError, RobotInfo};

/// Bytes per Jacobian or Hessian nonzero across vito's and Ipopt's copies (triplets, the KKT
/// matrix) and MUMPS's factor (its fill is several times the matrix): an estimate whose only
/// job is to tell a problem that may fit from one that cannot.
const BYTES_PER_NONZERO: f64 = 200.0;

/// Memory the NLP for `knots` knots of `robot` with `contacts` contacts would need, with
/// its variable count: per interval the coordinates, step, inputs, contact block (with four
/// friction directions, the 3D count) and per-contact slacks; the dynamics rows read three
/// knots of coordinates, the inputs and the contact forces, the contact rows a knot of
/// coordinates and their own block; the Hessian couples three knots' worth of variables.
pub(super) fn nlp_estimate(robot: &RobotInfo, contacts: usize, knots: usize) -> (f64, f64) {
    let n = robot.coordinates.len() as f64;
    let m = robot.inputs.len() as f64;
    let nc = contacts as f64;
    let nd = 4.0;
    let contact_vars = nc * (2.0 + 2.0 * nd) + 3.0 * nc;
    let per_interval_vars = n + 1.0 + m + contact_vars;
    let contact_rows = nc * (nd + 5.0);
    let jacobian = n * (3.0 * n + 1.0 + m + nc * (1.0 + nd)) + contact_rows * (n + 2.0 + 2.0 * nd);
    let hessian = (3.0 * n + m + contact_vars).powi(2) / 2.0;
    let intervals = knots as f64 - 1.0;
    let variables = per_interval_vars * intervals + 2.0 * n;
    let bytes = (jacobian + hessian) * intervals * BYTES_PER_NONZERO + 8.0 * 20.0 * variables;
    (variables, bytes)
}

/// The memory this process may use: the least of the machine's RAM (`MemTotal`), the
/// address-space limit (`ulimit -v`, `RLIMIT_AS`) and the memory limit of its cgroup (v2
/// `memory.max`, v1 `memory.limit_in_bytes`: a Slurm job's `--mem`, a container's); 16 GiB
/// where none can be read.
pub fn memory_available() -> f64 {
    let ram = std::fs::read_to_string("/proc/meminfo")
        .ok()
        .and_then(|text| {
            let line = text.lines().find(|l| l.starts_with("MemTotal:"))?;
            let kib: f64 = line.split_whitespace().nth(1)?.parse().ok()?;
            Some(kib * 1024.0)
        });
    let address_space = rustix::process::getrlimit(rustix::process::Resource::As)
        .current
        .map(|b| b as f64);
    [ram, address_space, cgroup_limit()]
        .into_iter()
        .flatten()
        .reduce(f64::min)
        .unwrap_or(16.0 * 1024.0 * 1024.0 * 1024.0)
}

/// The memory limit of this process's cgroup and its ancestors (the least), if any is set.
fn cgroup_limit() -> Option<f64> {
    let membership = std::fs::read_to_string("/proc/self/cgroup").ok()?;
    let mut limits = Vec::new();
    for line in membership.lines() {
        // `hierarchy-id:controllers:path`; v2 is `0::path`, v1's memory line names `memory`.
        let mut parts = line.splitn(3, ':');
        let (_, controllers, path) = (parts.next()?, parts.next()?, parts.next()?);
        let (root, file) = if controllers.is_empty() {
            ("/sys/fs/cgroup", "memory.max")
        } else if controllers.split(',').any(|c| c == "memory") {
            ("/sys/fs/cgroup/memory", "memory.limit_in_bytes")
        } else {
            continue;
        };
        let mut dir = std::path::PathBuf::from(root);
        dir.push(path.trim_start_matches('/'));
        // The limit of every cgroup from this one up to the root of the hierarchy.
        loop {
            if let Some(bytes) = std::fs::read_to_string(dir.join(file))
                .ok()
                .and_then(|t| t.trim().parse::<u64>().ok())
            {
                limits.push(bytes as f64);
            }
            if dir == std::path::Path::new(root) || !dir.pop() {
                break;
            }
        }
    }
    limits.into_iter().reduce(f64::min)
}

/// Refuses a horizon whose NLP would need more memory than the machine has, saying how much.
pub(super) fn check_nlp_fits(
    ctx: &Context,
    robot: &RobotInfo,
    contacts: usize,
    knots: usize,
) -> Result<(), ProblemError> {
    let (variables, bytes) = nlp_estimate(robot, contacts, knots);
    let available = memory_available();
    if bytes > available {
        let gib = |b: f64| b / (1024.0 * 1024.0 * 1024.0);
        return Err(ctx.invalid(
            "horizon.knots",
            format!(
                "{knots} knots make an NLP of about {variables:.2e} variables that would need \
                 about {:.3e} GiB of memory, more than the {:.1} GiB this process may use (RAM, `ulimit -v`, cgroup): use fewer knots",
                gib(bytes),
                gib(available)
            ),
        ));
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::problem::Interval;

    fn hopper() -> RobotInfo {
        RobotInfo {
            urdf: "h.urdf".into(),
            coordinates: ["x", "z", "theta", "r"].map(String::from).to_vec(),
            coordinate_kinds: Vec::new(),
            coordinate_limits: vec![Interval::FREE; 4],
            inputs: ["theta", "r"].map(String::from).to_vec(),
            actuation: Default::default(),
            actuatable_joints: ["x", "z", "theta", "r"].map(String::from).to_vec(),
            input_kinds: Vec::new(),
            effort_limits: vec![f64::INFINITY; 2],
            links: Vec::new(),
            contacts: Vec::new(),
            warnings: Vec::new(),
            moves_in_xz_plane: true,
        }
    }

    /// The hopper's 21 knots (288 variables in the solver's NLP) are estimated within a factor of two,
    /// and memory grows linearly with the knots.
    #[test]
    fn estimate_is_near_the_hopper_and_linear() {
        let (variables, bytes) = nlp_estimate(&hopper(), 1, 21);
        assert!((200.0..=600.0).contains(&variables), "{variables}");
        let (_, bytes_10x) = nlp_estimate(&hopper(), 1, 201);
        assert!(
            (bytes_10x / bytes - 10.0).abs() < 0.5,
            "{bytes} {bytes_10x}"
        );
        let (_, huge) = nlp_estimate(&hopper(), 1, i64::MAX as usize);
        assert!(huge.is_finite() && huge > 1e20);
    }
}
