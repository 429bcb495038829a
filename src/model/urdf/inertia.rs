//! A link's mass and inertia, checked, and the lumping of rigidly attached masses into one
//! body (parallel-axis theorem).

use crate::model::ModelError;
use crate::model::spatial::{mat_mul, positive_definite, rpy_to_matrix, transpose};

/// Mass, centre of mass, and inertia about the centre of mass (in the axes of the frame the
/// centre is given in).
pub(super) type MassPiece = (f64, [f64; 3], [[f64; 3]; 3]);

/// A link's checked mass, centre of mass and inertia (about the centre of mass, in link
/// axes: the URDF inertia rotated by the inertial origin's rpy).
pub(super) fn link_inertia(link: &urdf_rs::Link) -> Result<MassPiece, ModelError> {
    let inertial = &link.inertial;
    let mass = inertial.mass.value;
    if !(mass > 0.0 && mass.is_finite()) {
        return Err(ModelError::NonPositiveMass {
            link: link.name.clone(),
            mass,
        });
    }
    let i = &inertial.inertia;
    let urdf_inertia = [
        [i.ixx, i.ixy, i.ixz],
        [i.ixy, i.iyy, i.iyz],
        [i.ixz, i.iyz, i.izz],
    ];
    if !positive_definite(&urdf_inertia) {
        return Err(ModelError::InertiaNotPositiveDefinite {
            link: link.name.clone(),
            ixx: i.ixx,
            iyy: i.iyy,
            izz: i.izz,
            ixy: i.ixy,
            ixz: i.ixz,
            iyz: i.iyz,
        });
    }
    let rpy = &inertial.origin.rpy;
    let r = rpy_to_matrix(rpy[0], rpy[1], rpy[2]);
    let rotated = mat_mul(&mat_mul(&r, &urdf_inertia), &transpose(&r));
    Ok((mass, *inertial.origin.xyz, rotated))
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
