//! A link's mass and inertia, checked, and the lumping of rigidly attached masses into one
//! body (parallel-axis theorem).

use crate::model::spatial::{mat_mul, positive_definite, rpy_to_matrix, transpose};

/// Mass, centre of mass, and inertia about the centre of mass (in the axes of the frame the
/// centre is given in).
pub(super) type MassPiece = (f64, [f64; 3], [[f64; 3]; 3]);

/// A link's mass, centre of mass and inertia (about the centre of mass, in link axes: the
/// URDF inertia rotated by the inertial origin's rpy); `None` for a massless frame (mass 0).
/// Numbers vito cannot use go to `problems`; whether the inertia is positive definite is
/// checked later, on the rigid body the link is lumped into ([`check_body`]).
pub(super) fn link_inertia(
    link: &urdf_rs::Link,
    at: &str,
    problems: &mut Vec<String>,
    warnings: &mut Vec<String>,
) -> Option<MassPiece> {
    let inertial = &link.inertial;
    let mass = inertial.mass.value;
    let i = &inertial.inertia;
    let urdf_inertia = [
        [i.ixx, i.ixy, i.ixz],
        [i.ixy, i.iyy, i.iyz],
        [i.ixz, i.iyz, i.izz],
    ];
    let element = format!("{at}<link name=\"{}\"> <inertial>", link.name);
    if !(mass.is_finite() && mass >= 0.0) {
        problems.push(format!(
            "{element}: mass {mass} must be a finite number ≥ 0 (0 makes a massless frame)"
        ));
        return None;
    }
    if !urdf_inertia.iter().flatten().all(|x| x.is_finite()) {
        problems.push(format!(
            "{element}: the <inertia> entries must be finite numbers ({})",
            describe(&urdf_inertia)
        ));
        return None;
    }
    if mass == 0.0 {
        if urdf_inertia.iter().flatten().any(|&x| x != 0.0) {
            warnings.push(format!(
                "{element}: mass 0 with a nonzero inertia ({}); read as a massless frame, \
                 the inertia ignored",
                describe(&urdf_inertia)
            ));
        }
        return None;
    }
    let rpy = &inertial.origin.rpy;
    let r = rpy_to_matrix(rpy[0], rpy[1], rpy[2]);
    let rotated = mat_mul(&mat_mul(&r, &urdf_inertia), &transpose(&r));
    Some((mass, *inertial.origin.xyz, rotated))
}

fn describe(i: &[[f64; 3]; 3]) -> String {
    format!(
        "ixx={} iyy={} izz={} ixy={} ixz={} iyz={}",
        i[0][0], i[1][1], i[2][2], i[0][1], i[0][2], i[1][2]
    )
}

/// Checks the lumped inertia of one moving rigid body: positive definite when it has mass.
/// `links` are the body's URDF links with mass (the moving one first, then those fixed to
/// it), each with its "line N: " prefix.
pub(super) fn check_body(body: &MassPiece, links: &[(String, String)], problems: &mut Vec<String>) {
    let (mass, _, inertia) = body;
    if *mass == 0.0 || positive_definite(inertia) {
        return;
    }
    let Some((at, first)) = links.first() else {
        return;
    };
    let lumped = if links.len() > 1 {
        let others: Vec<String> = links[1..]
            .iter()
            .map(|(a, l)| match a.trim_end_matches(": ") {
                "" => format!("'{l}'"),
                line => format!("'{l}' ({line})"),
            })
            .collect();
        format!(" (with {} fixed to it)", others.join(", "))
    } else {
        String::new()
    };
    problems.push(format!(
        "{at}<link name=\"{first}\"> <inertial>: the rigid body{lumped} has an inertia that is \
         not positive definite ({}); fix the <inertia> values (a body that turns needs \
         rotational inertia about every axis)",
        describe(inertia)
    ));
}

/// Combines rigidly attached masses into one body: total mass, centre of mass, and the
/// inertia about it (parallel-axis theorem). Massless for no pieces.
pub(super) fn lump(parts: &[MassPiece]) -> MassPiece {
    let mass: f64 = parts.iter().map(|p| p.0).sum();
    if mass == 0.0 {
        return (0.0, [0.0; 3], [[0.0; 3]; 3]);
    }
    if let [single] = parts {
        return *single;
    }
    let mut com = [0.0; 3];
    for (m, c, _) in parts {
        for k in 0..3 {
            com[k] += m * c[k] / mass;
        }
    }
    let mut inertia = [[0.0; 3]; 3];
    for (m, c, i) in parts {
        let d = [c[0] - com[0], c[1] - com[1], c[2] - com[2]];
        let d2 = d[0] * d[0] + d[1] * d[1] + d[2] * d[2];
        for a in 0..3 {
            for b in 0..3 {
                let delta = if a == b { 1.0 } else { 0.0 };
                inertia[a][b] += i[a][b] + m * (d2 * delta - d[a] * d[b]);
            }
        }
    }
    (mass, com, inertia)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn lumping_two_point_masses() {
        // Two 1 kg points at x = ±1: mass 2, centre 0, Iyy = Izz = 2, Ixx = 0.
        let zero = [[0.0; 3]; 3];
        let (m, c, i) = lump(&[(1.0, [1.0, 0.0, 0.0], zero), (1.0, [-1.0, 0.0, 0.0], zero)]);
        assert_eq!((m, c), (2.0, [0.0; 3]));
        assert_eq!(i, [[0.0, 0.0, 0.0], [0.0, 2.0, 0.0], [0.0, 0.0, 2.0]]);
    }
}
