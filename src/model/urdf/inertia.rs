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
/// it), each with its "line N: " prefix. A body that is not is listed in `flawed`, to be
/// reported with what it does to the mass matrix ([`mass_matrix_defect`]).
pub(super) fn check_body(body: &MassPiece, links: &[(String, String)], flawed: &mut Vec<String>) {
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
    flawed.push(format!(
        "{at}<link name=\"{first}\"> <inertial>: the rigid body{lumped} has an inertia that is \
         not positive definite ({})",
        describe(inertia)
    ));
}

/// What the mass matrix of `model` is at the nominal pose (every coordinate at 0, or
/// mid-range where 0 is outside its limits), when it is not positive definite.
pub(super) struct MassMatrixDefect {
    /// The coordinates along which it is singular or indefinite: those with the largest
    /// components of the eigenvectors whose eigenvalues are at most 1e-12 of the largest.
    pub(super) coordinates: Vec<String>,
    /// Its most negative eigenvalue, when one is below −1e-9 of the largest (kinetic
    /// energy that can be negative).
    pub(super) negative: Option<f64>,
}

/// The mass matrix's defect at the nominal pose; `None` when it is positive definite.
pub(super) fn mass_matrix_defect(model: &crate::model::Model) -> Option<MassMatrixDefect> {
    let q: Vec<f64> = model
        .coordinate_limits()
        .iter()
        .map(|&(lo, hi)| {
            if lo.is_finite() && hi.is_finite() && !(lo..=hi).contains(&0.0) {
                0.5 * (lo + hi)
            } else {
                0.0_f64.clamp(lo, hi)
            }
        })
        .collect();
    let eigen = crate::model::mass_matrix(model, &q).symmetric_eigen();
    let largest = eigen
        .eigenvalues
        .iter()
        .fold(0.0_f64, |m, e| m.max(e.abs()));
    let mut coordinates: Vec<String> = Vec::new();
    let mut negative: Option<f64> = None;
    for (k, &value) in eigen.eigenvalues.iter().enumerate() {
        if value > 1e-12 * largest {
            continue;
        }
        if value < -1e-9 * largest {
            negative = Some(negative.map_or(value, |n| n.min(value)));
        }
        let direction = eigen.eigenvectors.column(k);
        let biggest = direction.iter().fold(0.0_f64, |m, x| m.max(x.abs()));
        for (i, x) in direction.iter().enumerate() {
            let name = &model.coordinate_names()[i];
            if x.abs() >= 0.5 * biggest && !coordinates.contains(name) {
                coordinates.push(name.clone());
            }
        }
    }
    (!coordinates.is_empty()).then_some(MassMatrixDefect {
        coordinates,
        negative,
    })
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
