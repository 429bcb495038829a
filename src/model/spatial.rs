//! Small 3-D rotations and vectors over any [`Scalar`], as plain arrays (nested duals are not
//! nalgebra `RealField`).

use crate::autodiff::Scalar;

/// A 3-vector.
pub(crate) type Vec3<D> = [D; 3];
/// A row-major 3×3 matrix.
pub(crate) type Mat3<D> = [[D; 3]; 3];

/// Lifts an f64 vector.
pub(crate) fn lift3<D: Scalar>(v: &[f64; 3]) -> Vec3<D> {
    [D::from(v[0]), D::from(v[1]), D::from(v[2])]
}

/// a + b.
pub(crate) fn add<D: Scalar>(a: Vec3<D>, b: Vec3<D>) -> Vec3<D> {
    [a[0] + b[0], a[1] + b[1], a[2] + b[2]]
}

/// a − b.
pub(crate) fn sub<D: Scalar>(a: Vec3<D>, b: Vec3<D>) -> Vec3<D> {
    [a[0] - b[0], a[1] - b[1], a[2] - b[2]]
}

/// s·a.
pub(crate) fn scale<D: Scalar>(s: D, a: Vec3<D>) -> Vec3<D> {
    [s * a[0], s * a[1], s * a[2]]
}

/// a·b.
pub(crate) fn dot<D: Scalar>(a: Vec3<D>, b: Vec3<D>) -> D {
    a[0] * b[0] + a[1] * b[1] + a[2] * b[2]
}

/// a × b.
pub(crate) fn cross<D: Scalar>(a: Vec3<D>, b: Vec3<D>) -> Vec3<D> {
    [
        a[1] * b[2] - a[2] * b[1],
        a[2] * b[0] - a[0] * b[2],
        a[0] * b[1] - a[1] * b[0],
    ]
}

/// M·v.
pub(crate) fn mat_vec<D: Scalar>(m: &Mat3<D>, v: Vec3<D>) -> Vec3<D> {
    [dot(m[0], v), dot(m[1], v), dot(m[2], v)]
}

/// Mᵀ·v.
pub(crate) fn mat_t_vec<D: Scalar>(m: &Mat3<D>, v: Vec3<D>) -> Vec3<D> {
    [
        m[0][0] * v[0] + m[1][0] * v[1] + m[2][0] * v[2],
        m[0][1] * v[0] + m[1][1] * v[1] + m[2][1] * v[2],
        m[0][2] * v[0] + m[1][2] * v[1] + m[2][2] * v[2],
    ]
}

/// A·B.
pub(crate) fn mat_mul<D: Scalar>(a: &Mat3<D>, b: &Mat3<D>) -> Mat3<D> {
    let mut out = [[D::from(0.0); 3]; 3];
    for (i, row) in out.iter_mut().enumerate() {
        for (j, entry) in row.iter_mut().enumerate() {
            *entry = a[i][0] * b[0][j] + a[i][1] * b[1][j] + a[i][2] * b[2][j];
        }
    }
    out
}

/// The identity.
pub(crate) fn identity<D: Scalar>() -> Mat3<D> {
    let (o, z) = (D::from(1.0), D::from(0.0));
    [[o, z, z], [z, o, z], [z, z, o]]
}

/// Rotation by `angle` about the unit `axis` (Rodrigues: I cos + sin [a]× + (1 − cos) a aᵀ).
pub(crate) fn axis_angle<D: Scalar>(axis: &[f64; 3], angle: D) -> Mat3<D> {
    let (s, c) = (angle.sin(), angle.cos());
    let t = D::from(1.0) - c;
    let [x, y, z] = *axis;
    let [xd, yd, zd]: [D; 3] = lift3(axis);
    [
        [c + t * (x * x), t * (x * y) - s * zd, t * (x * z) + s * yd],
        [t * (x * y) + s * zd, c + t * (y * y), t * (y * z) - s * xd],
        [t * (x * z) - s * yd, t * (y * z) + s * xd, c + t * (z * z)],
    ]
}

/// R(rpy) = Rz(yaw)·Ry(pitch)·Rx(roll), the URDF convention.
pub(crate) fn rpy_to_matrix<D: Scalar>(roll: D, pitch: D, yaw: D) -> Mat3<D> {
    let (sr, cr) = (roll.sin(), roll.cos());
    let (sp, cp) = (pitch.sin(), pitch.cos());
    let (sy, cy) = (yaw.sin(), yaw.cos());
    [
        [cy * cp, cy * sp * sr - sy * cr, cy * sp * cr + sy * sr],
        [sy * cp, sy * sp * sr + cy * cr, sy * sp * cr - cy * sr],
        [-sp, cp * sr, cp * cr],
    ]
}

/// A·B with a constant B.
pub(crate) fn mat_mul_const<D: Scalar>(a: &Mat3<D>, b: &[[f64; 3]; 3]) -> Mat3<D> {
    let mut out = [[D::from(0.0); 3]; 3];
    for (i, row) in out.iter_mut().enumerate() {
        for (j, entry) in row.iter_mut().enumerate() {
            *entry = a[i][0] * b[0][j] + a[i][1] * b[1][j] + a[i][2] * b[2][j];
        }
    }
    out
}

/// M·v with a constant v.
pub(crate) fn mat_vec_const<D: Scalar>(m: &Mat3<D>, v: &[f64; 3]) -> Vec3<D> {
    [
        m[0][0] * v[0] + m[0][1] * v[1] + m[0][2] * v[2],
        m[1][0] * v[0] + m[1][1] * v[1] + m[1][2] * v[2],
        m[2][0] * v[0] + m[2][1] * v[1] + m[2][2] * v[2],
    ]
}

/// C·v with a constant matrix C.
pub(crate) fn const_mat_vec<D: Scalar>(c: &[[f64; 3]; 3], v: Vec3<D>) -> Vec3<D> {
    [
        v[0] * c[0][0] + v[1] * c[0][1] + v[2] * c[0][2],
        v[0] * c[1][0] + v[1] * c[1][1] + v[2] * c[1][2],
        v[0] * c[2][0] + v[2] * c[2][2] + v[1] * c[2][1],
    ]
}

/// Unit vector, or `None` for a zero or non-finite vector.
pub(crate) fn normalized(v: [f64; 3]) -> Option<[f64; 3]> {
    let norm = (v[0] * v[0] + v[1] * v[1] + v[2] * v[2]).sqrt();
    (norm.is_finite() && norm > 1e-12).then(|| [v[0] / norm, v[1] / norm, v[2] / norm])
}

/// Two unit vectors perpendicular to the unit `axis`: the other two coordinate axes when
/// `axis` is a coordinate axis, else an orthonormal pair.
pub(crate) fn perpendicular_pair(axis: [f64; 3]) -> [[f64; 3]; 2] {
    let unit = |k: usize| {
        let mut e = [0.0; 3];
        e[k] = 1.0;
        e
    };
    for (k, component) in axis.iter().enumerate() {
        if (component.abs() - 1.0).abs() < 1e-12 {
            let others: Vec<usize> = (0..3).filter(|&j| j != k).collect();
            return [unit(others[0]), unit(others[1])];
        }
    }
    let k = (0..3)
        .min_by(|&a, &b| axis[a].abs().total_cmp(&axis[b].abs()))
        .unwrap_or(0);
    let cross = |a: [f64; 3], b: [f64; 3]| {
        [
            a[1] * b[2] - a[2] * b[1],
            a[2] * b[0] - a[0] * b[2],
            a[0] * b[1] - a[1] * b[0],
        ]
    };
    let e1 = normalized(cross(axis, unit(k))).unwrap_or(unit(0));
    [e1, cross(axis, e1)]
}

/// Whether a symmetric 3×3 matrix is positive definite (Sylvester's criterion).
pub(crate) fn positive_definite(m: &[[f64; 3]; 3]) -> bool {
    let d1 = m[0][0];
    let d2 = m[0][0] * m[1][1] - m[0][1] * m[1][0];
    let d3 = m[0][0] * (m[1][1] * m[2][2] - m[1][2] * m[2][1])
        - m[0][1] * (m[1][0] * m[2][2] - m[1][2] * m[2][0])
        + m[0][2] * (m[1][0] * m[2][1] - m[1][1] * m[2][0]);
    d1 > 0.0 && d2 > 0.0 && d3 > 0.0 && m.iter().flatten().all(|x| x.is_finite())
}

/// The transpose of a 3×3 matrix.
pub(crate) fn transpose(m: &[[f64; 3]; 3]) -> [[f64; 3]; 3] {
    let mut t = [[0.0; 3]; 3];
    for (i, row) in m.iter().enumerate() {
        for (j, &x) in row.iter().enumerate() {
            t[j][i] = x;
        }
    }
    t
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn rpy_is_the_product_of_axis_rotations() {
        let (r, p, y) = (0.3f64, -1.1f64, 2.0f64);
        let composed = mat_mul(
            &mat_mul(
                &axis_angle(&[0.0, 0.0, 1.0], y),
                &axis_angle(&[0.0, 1.0, 0.0], p),
            ),
            &axis_angle(&[1.0, 0.0, 0.0], r),
        );
        let direct = rpy_to_matrix(r, p, y);
        for i in 0..3 {
            for j in 0..3 {
                assert!((composed[i][j] - direct[i][j]).abs() < 1e-15);
            }
        }
    }

    #[test]
    fn axis_angle_turns_the_perpendicular_plane() {
        // About (1, 1, 1)/√3 by 2π/3 the coordinate axes cycle x → y → z.
        let a = 1.0 / 3f64.sqrt();
        let r = axis_angle(&[a, a, a], 2.0 * std::f64::consts::PI / 3.0);
        let x_image = mat_vec(&r, [1.0, 0.0, 0.0]);
        assert!(
            (x_image[0]).abs() < 1e-15
                && (x_image[1] - 1.0).abs() < 1e-15
                && x_image[2].abs() < 1e-15
        );
    }

    #[test]
    fn perpendicular_pairs_are_orthonormal() {
        assert_eq!(
            perpendicular_pair([0.0, 1.0, 0.0]),
            [[1.0, 0.0, 0.0], [0.0, 0.0, 1.0]]
        );
        assert_eq!(
            perpendicular_pair([0.0, 0.0, -1.0]),
            [[1.0, 0.0, 0.0], [0.0, 1.0, 0.0]]
        );
        let axis = normalized([1.0, 2.0, -0.5]).expect("non-zero");
        let [e1, e2] = perpendicular_pair(axis);
        let dot = |a: [f64; 3], b: [f64; 3]| a[0] * b[0] + a[1] * b[1] + a[2] * b[2];
        for (a, b, want) in [
            (e1, e1, 1.0),
            (e2, e2, 1.0),
            (e1, e2, 0.0),
            (e1, axis, 0.0),
            (e2, axis, 0.0),
        ] {
            assert!((dot(a, b) - want).abs() < 1e-15);
        }
    }
}
