//! Mass matrices against closed forms and against the Hessian of the kinetic-energy
//! recursion; momentum, inverse dynamics and the Euler–Lagrange equations against each
//! other; forward-mode AD against central finite differences.

use std::f64::consts::PI;

use crate::common::robots::{paper_robots, robot};

use num_dual::{Dual64, HyperDual64};
use vito::autodiff::finite_differences::{Differenced, along, central};
use vito::model::{
    BaseType, Model, generalized_damping_force, generalized_input_force, generalized_momentum,
    generalized_point_force, inverse_dynamics, kinetic_energy, loop_residual, mass_matrix,
    point_position, potential_energy, sample,
};
use vito::random::SeededRng;

fn from_str(xml: &str, base: BaseType) -> Model {
    Model::from_urdf_str(xml, base).unwrap_or_else(|e| panic!("{e}"))
}

/// The models every cross-check runs on: fixtures, the reference robots and the paper's.
fn all_models() -> Vec<(&'static str, Model)> {
    let mut models = vec![
        ("pendulum", from_str(&sample::pendulum(), BaseType::Fixed)),
        (
            "double_pendulum",
            from_str(&sample::double_pendulum(), BaseType::Fixed),
        ),
        ("four_bar", from_str(&sample::four_bar(), BaseType::Fixed)),
        ("cart_pole", from_str(&sample::cart_pole(), BaseType::Fixed)),
        (
            "chain5_planar",
            from_str(&sample::planar_chain(5), BaseType::Planar),
        ),
        ("hopper", from_str(sample::hopper_2d(), BaseType::Fixed)),
        ("brick", from_str(sample::brick(), BaseType::Floating)),
    ];
    for (name, mut model) in paper_robots() {
        if name == "hamr" {
            // HAMR's lengths are in mm and its times in ms.
            model.set_gravity([0.0, 0.0, -9.81e-3]);
        }
        models.push((name, model));
    }
    models
}

fn dual_at(x: &[f64], dir: &[f64]) -> Vec<Dual64> {
    x.iter()
        .zip(dir)
        .map(|(&a, &d)| Dual64::new(a, d))
        .collect()
}

fn constant(x: &[f64]) -> Vec<Dual64> {
    x.iter().map(|&a| Dual64::from(a)).collect()
}

fn unit(n: usize, i: usize) -> Vec<f64> {
    let mut e = vec![0.0; n];
    e[i] = 1.0;
    e
}

/// ∂T/∂q̇ by forward duals.
fn dt_dqdot(model: &Model, q: &[f64], v: &[f64]) -> Vec<f64> {
    let n = model.nq();
    (0..n)
        .map(|i| kinetic_energy(model, &constant(q), &dual_at(v, &unit(n, i))).eps)
        .collect()
}

/// ∂T/∂q by forward duals.
fn dt_dq(model: &Model, q: &[f64], v: &[f64]) -> Vec<f64> {
    let n = model.nq();
    (0..n)
        .map(|i| kinetic_energy(model, &dual_at(q, &unit(n, i)), &constant(v)).eps)
        .collect()
}

/// ∂V/∂q by forward duals.
fn dv_dq(model: &Model, q: &[f64]) -> Vec<f64> {
    let n = model.nq();
    (0..n)
        .map(|i| potential_energy(model, &dual_at(q, &unit(n, i))).eps)
        .collect()
}

fn close(a: f64, b: f64, rel: f64, abs: f64) -> bool {
    (a - b).abs() <= abs + rel * a.abs().max(b.abs())
}

// ---- closed forms -------------------------------------------------------------------------

#[test]
fn pendulum_mass_matrix_and_potential() {
    let m = from_str(&sample::pendulum(), BaseType::Fixed);
    for q in [-2.0, -0.3, 0.0, 0.7, 3.0] {
        let mm = mass_matrix(&m, &[q]);
        assert!(close(mm[(0, 0)], 1.0 / 3.0, 1e-14, 0.0), "{}", mm[(0, 0)]);
        let v: f64 = potential_energy(&m, &[q]);
        assert!(close(v, -9.81 * 0.5 * q.cos(), 1e-14, 1e-15));
    }
}

#[test]
fn double_pendulum_mass_matrix_closed_form() {
    use sample::{DOUBLE_PENDULUM_L1 as L1, DOUBLE_PENDULUM_L2 as L2};
    use sample::{DOUBLE_PENDULUM_M1 as M1, DOUBLE_PENDULUM_M2 as M2};
    let m = from_str(&sample::double_pendulum(), BaseType::Fixed);
    assert_eq!(m.coordinate_names(), ["shoulder", "elbow"]);
    let (i1, i2) = (M1 * L1 * L1 / 12.0, M2 * L2 * L2 / 12.0);
    let (c1, c2) = (L1 / 2.0, L2 / 2.0);
    let mut rng = SeededRng::new(3);
    for _ in 0..20 {
        let q = rng.symmetric_vec(2, PI);
        let cq = q[1].cos();
        let m11 = i1 + M1 * c1 * c1 + i2 + M2 * (L1 * L1 + c2 * c2 + 2.0 * L1 * c2 * cq);
        let m12 = i2 + M2 * (c2 * c2 + L1 * c2 * cq);
        let m22 = i2 + M2 * c2 * c2;
        let mm = mass_matrix(&m, &q);
        for (got, want) in [
            (mm[(0, 0)], m11),
            (mm[(0, 1)], m12),
            (mm[(1, 0)], m12),
            (mm[(1, 1)], m22),
        ] {
            assert!(close(got, want, 1e-13, 0.0), "{got} vs {want}");
        }
        // V = −g (M1 c1 cos q1 + M2 (L1 cos q1 + c2 cos(q1 + q2))).
        let v = -9.81 * (M1 * c1 * q[0].cos() + M2 * (L1 * q[0].cos() + c2 * (q[0] + q[1]).cos()));
        assert!(close(potential_energy(&m, &q), v, 1e-13, 1e-14));
    }
}

#[test]
fn cart_pole_mass_matrix_closed_form() {
    let m = from_str(&sample::cart_pole(), BaseType::Fixed);
    assert_eq!(m.coordinate_names(), ["slider", "hinge"]);
    assert_eq!(m.coordinate_limits()[0], (-5.0, 5.0));
    assert_eq!(m.effort_limits(), [50.0]);
    let (mc, mp, len) = (2.0, 0.5, 1.2);
    let c = len / 2.0;
    let ip = mp * len * len / 12.0;
    let mut rng = SeededRng::new(5);
    for _ in 0..20 {
        let q = rng.symmetric_vec(2, 3.0);
        let mm = mass_matrix(&m, &q);
        let m12 = -mp * c * q[1].cos();
        assert!(close(mm[(0, 0)], mc + mp, 1e-14, 0.0));
        assert!(close(mm[(0, 1)], m12, 1e-13, 1e-15) && close(mm[(1, 0)], m12, 1e-13, 1e-15));
        assert!(close(mm[(1, 1)], ip + mp * c * c, 1e-14, 0.0));
    }
}

#[test]
fn free_body_planar_mass_matrix() {
    let m = from_str(sample::brick(), BaseType::Planar);
    assert_eq!(m.coordinate_names(), ["base_x", "base_z", "base_pitch"]);
    let iyy = (0.2f64 * 0.2 + 0.05 * 0.05) / 12.0;
    let mut rng = SeededRng::new(9);
    for _ in 0..10 {
        let q = rng.symmetric_vec(3, 2.0);
        let mm = mass_matrix(&m, &q);
        let want = [[1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, iyy]];
        for i in 0..3 {
            for j in 0..3 {
                assert!(close(mm[(i, j)], want[i][j], 1e-14, 1e-16), "{mm}");
            }
        }
    }
}

#[test]
fn free_body_floating_mass_matrix() {
    // M = diag(m I, Eᵀ I_c E) with ω_b = E(roll, pitch)·[roll, pitch, yaw]ᵀ rates.
    let m = from_str(sample::brick(), BaseType::Floating);
    let (a, b, c) = (0.2f64, 0.1f64, 0.05f64);
    let inertia = [
        (b * b + c * c) / 12.0,
        (a * a + c * c) / 12.0,
        (a * a + b * b) / 12.0,
    ];
    let mut rng = SeededRng::new(13);
    for _ in 0..20 {
        let q = rng.symmetric_vec(6, 1.5);
        let (sr, cr) = q[3].sin_cos();
        let (sp, cp) = q[4].sin_cos();
        let e = [[1.0, 0.0, -sp], [0.0, cr, sr * cp], [0.0, -sr, cr * cp]];
        let mm = mass_matrix(&m, &q);
        for i in 0..6 {
            for j in 0..6 {
                let want = match (i < 3, j < 3) {
                    (true, true) => f64::from(u8::from(i == j)),
                    (false, false) => (0..3).map(|k| e[k][i - 3] * inertia[k] * e[k][j - 3]).sum(),
                    _ => 0.0,
                };
                assert!(
                    close(mm[(i, j)], want, 1e-12, 1e-15),
                    "({i},{j}): {} vs {want}",
                    mm[(i, j)]
                );
            }
        }
    }
}

// ---- cross-checks on every model ----------------------------------------------------------

fn random_state(model: &Model, rng: &mut SeededRng) -> (Vec<f64>, Vec<f64>, Vec<f64>) {
    let n = model.nq();
    (
        rng.symmetric_vec(n, 0.8),
        rng.symmetric_vec(n, 1.5),
        rng.symmetric_vec(n, 2.0),
    )
}

#[test]
fn mass_matrix_is_the_hessian_of_the_kinetic_energy_recursion() {
    let mut rng = SeededRng::new(21);
    for (name, model) in all_models() {
        let n = model.nq();
        let (q, v, _) = random_state(&model, &mut rng);
        let mm = mass_matrix(&model, &q);
        let scale = mm.amax();
        let qh: Vec<HyperDual64> = q.iter().map(|&x| HyperDual64::from(x)).collect();
        for i in 0..n {
            for j in 0..=i {
                let vh: Vec<HyperDual64> = (0..n)
                    .map(|k| {
                        let d1 = if k == i { 1.0 } else { 0.0 };
                        let d2 = if k == j { 1.0 } else { 0.0 };
                        HyperDual64::new(v[k], d1, d2, 0.0)
                    })
                    .collect();
                let h = kinetic_energy(&model, &qh, &vh).eps1eps2;
                assert!(
                    close(mm[(i, j)], h, 1e-12, 1e-13 * scale) && mm[(i, j)] == mm[(j, i)],
                    "{name}: M[{i},{j}] = {} but ∂²T/∂q̇² = {h}",
                    mm[(i, j)]
                );
            }
        }
        let t: f64 = kinetic_energy(&model, &q, &v);
        let vmv = (mm.clone() * nalgebra::DVector::from_column_slice(&v))
            .dot(&nalgebra::DVector::from_column_slice(&v));
        assert!(
            close(t, 0.5 * vmv, 1e-12, 1e-15),
            "{name}: T = {t}, ½vᵀMv = {}",
            0.5 * vmv
        );
        let eig = mm.symmetric_eigenvalues();
        assert!(
            eig.min() > 1e-9 * eig.max(),
            "{name}: M not positive definite: {eig}"
        );
    }
}

#[test]
fn momentum_is_the_velocity_gradient_of_kinetic_energy() {
    let mut rng = SeededRng::new(22);
    for (name, model) in all_models() {
        let (q, v, _) = random_state(&model, &mut rng);
        let p = generalized_momentum(&model, &q, &v);
        let g = dt_dqdot(&model, &q, &v);
        let scale = g.iter().fold(1e-300f64, |m, x| m.max(x.abs()));
        for (i, (a, b)) in p.iter().zip(&g).enumerate() {
            assert!(
                close(*a, *b, 1e-12, 1e-12 * scale),
                "{name}: p[{i}] = {a} vs {b}"
            );
        }
    }
}

#[test]
fn inverse_dynamics_matches_mass_matrix_and_potential_gradient() {
    let mut rng = SeededRng::new(23);
    for (name, model) in all_models() {
        let n = model.nq();
        let (q, _, a) = random_state(&model, &mut rng);
        let zero = vec![0.0; n];
        let static_force = inverse_dynamics(&model, &q, &zero, &zero);
        let grad_v = dv_dq(&model, &q);
        let with_a = inverse_dynamics(&model, &q, &zero, &a);
        let ma = mass_matrix(&model, &q) * nalgebra::DVector::from_column_slice(&a);
        let scale = grad_v
            .iter()
            .chain(ma.iter())
            .fold(1e-300f64, |m, x| m.max(x.abs()));
        for i in 0..n {
            assert!(
                close(static_force[i], grad_v[i], 1e-11, 1e-12 * scale),
                "{name}: ID(q,0,0)[{i}] = {} vs ∂V/∂q = {}",
                static_force[i],
                grad_v[i]
            );
            assert!(
                close(with_a[i] - static_force[i], ma[i], 1e-11, 1e-12 * scale),
                "{name}: ID(q,0,a) − ID(q,0,0) = {} vs (M a) = {}",
                with_a[i] - static_force[i],
                ma[i]
            );
        }
    }
}

#[test]
fn inverse_dynamics_satisfies_euler_lagrange_of_the_kinetic_energy() {
    // τ = d/dt ∂T/∂q̇ − ∂T/∂q + ∂V/∂q, the time derivative by central differences along
    // (q + εv, v + εa).
    let mut rng = SeededRng::new(24);
    let eps = 1e-5;
    for (name, model) in all_models() {
        let n = model.nq();
        let (q, v, a) = random_state(&model, &mut rng);
        let tau = inverse_dynamics(&model, &q, &v, &a);
        let shift = |s: f64| {
            let qs: Vec<f64> = q.iter().zip(&v).map(|(x, d)| x + s * d).collect();
            let vs: Vec<f64> = v.iter().zip(&a).map(|(x, d)| x + s * d).collect();
            dt_dqdot(&model, &qs, &vs)
        };
        let fd = central(shift, eps);
        let dtq = dt_dq(&model, &q, &v);
        let dvq = dv_dq(&model, &q);
        let el: Vec<f64> = (0..n).map(|i| fd[i] - dtq[i] + dvq[i]).collect();
        let scale = el.iter().fold(1e-300f64, |m, x| m.max(x.abs()));
        for i in 0..n {
            assert!(
                close(tau[i], el[i], 1e-6, 1e-7 * scale),
                "{name}: ID[{i}] = {} vs Euler–Lagrange {}",
                tau[i],
                el[i]
            );
        }
    }
}

#[test]
fn input_map_is_the_transmission_selection() {
    let m = from_str(sample::hopper_2d(), BaseType::Fixed);
    let f = generalized_input_force(&m, &[0.0; 4], &[2.5, -7.0]);
    assert_eq!(f, [0.0, 0.0, 2.5, -7.0]);
}

#[test]
fn damping_force_opposes_velocity() {
    let m = robot(
        "spring_flamingo/spring_flamingo_passive_ankle.normalized.urdf",
        BaseType::Planar,
    );
    let v: Vec<f64> = (0..9).map(|i| i as f64 - 4.0).collect();
    let f = generalized_damping_force(&m, &v);
    let want = [0.0, 0.0, 0.0, 0.0, 0.0, -0.1, 0.0, 0.0, -0.4];
    for (a, b) in f.iter().zip(want) {
        assert!((a - b).abs() < 1e-15, "{f:?}");
    }
}

#[test]
fn point_force_is_the_jacobian_transpose() {
    // Jᵀf = ∂(f·p(q))/∂q, the right side by forward duals.
    let mut rng = SeededRng::new(26);
    for (name, model) in all_models() {
        let n = model.nq();
        let (q, _, _) = random_state(&model, &mut rng);
        let force = [rng.symmetric(1.0), rng.symmetric(1.0), rng.symmetric(1.0)];
        let point = [0.1, 0.2, -0.3];
        for link_name in model.link_names() {
            let link = model.link_index(link_name).expect("own link");
            let got = generalized_point_force(&model, link, &point, force, &q);
            for (i, value) in got.iter().enumerate() {
                let p = point_position(&model, link, &point, &dual_at(&q, &unit(n, i)));
                let want = force[0] * p[0].eps + force[1] * p[1].eps + force[2] * p[2].eps;
                assert!(
                    close(*value, want, 1e-12, 1e-12),
                    "{name} {link_name}[{i}]: {value} vs {want}"
                );
            }
        }
    }
}

// ---- AD against finite differences --------------------------------------------------------

#[test]
fn point_position_potential_and_loop_residual_ad_match_central_differences() {
    let mut rng = SeededRng::new(25);
    let h = 1e-6;
    for (name, model) in all_models() {
        let n = model.nq();
        let (q, _, _) = random_state(&model, &mut rng);
        let dir = rng.symmetric_vec(n, 1.0);
        let qd = dual_at(&q, &dir);
        let (qp, qm) = (along(&q, &dir, h), along(&q, &dir, -h));
        let check = |what: &str, ad: f64, plus: f64, minus: f64, scale: f64| {
            let fd = f64::central(plus, minus, h);
            assert!(
                close(ad, fd, 1e-6, 1e-7 * scale),
                "{name} {what}: AD {ad} vs FD {fd}"
            );
        };
        let v = potential_energy(&model, &qd);
        let (vp, vm): (f64, f64) = (potential_energy(&model, &qp), potential_energy(&model, &qm));
        check("V", v.eps, vp, vm, v.re.abs().max(1.0));
        for link_index in 0..model.link_names().len() {
            let link = model
                .link_index(&model.link_names()[link_index])
                .expect("own link");
            let point = [0.3, -0.2, 0.1];
            let p = point_position(&model, link, &point, &qd);
            let pp = point_position(&model, link, &point, &qp);
            let pm = point_position(&model, link, &point, &qm);
            for k in 0..3 {
                check("point", p[k].eps, pp[k], pm[k], 1.0);
            }
        }
        let r = loop_residual(&model, &qd);
        let rp = loop_residual(&model, &qp);
        let rm = loop_residual(&model, &qm);
        for k in 0..r.len() {
            check("loop", r[k].eps, rp[k], rm[k], 1.0);
        }
    }
}

#[test]
fn four_bar_closes_at_zero_and_opens_when_one_joint_moves() {
    let m = from_str(&sample::four_bar(), BaseType::Fixed);
    assert_eq!(m.coordinate_names(), ["crank", "coupler", "rocker"]);
    assert_eq!(m.num_loop_constraints(), 2);
    let r: Vec<f64> = loop_residual(&m, &[0.0; 3]);
    assert!(r.iter().all(|x| x.abs() < 1e-15), "{r:?}");
    // Crank by 0.1 alone: the rigid chain turns about O, its end E = Ry(0.1)·D with
    // D = (4.6, 0, −0.2); the gap E − D in ground axes.
    let r: Vec<f64> = loop_residual(&m, &[0.1, 0.0, 0.0]);
    let (s, c) = 0.1f64.sin_cos();
    let end = [4.6 * c - 0.2 * s, -4.6 * s - 0.2 * c];
    assert!(close(r[0], end[0] - 4.6, 1e-12, 1e-15), "{r:?}");
    assert!(close(r[1], end[1] + 0.2, 1e-12, 1e-15), "{r:?}");
    // Not an equilibrium at q = 0: gravity does work along the one feasible direction
    // (the null space of the 2×3 loop Jacobian).
    let jac: Vec<Vec<f64>> = (0..3)
        .map(|i| {
            loop_residual(&m, &dual_at(&[0.0; 3], &unit(3, i)))
                .iter()
                .map(|x| x.eps)
                .collect()
        })
        .collect();
    // Null direction = cross product of the two rows of J (J[row][col] = jac[col][row]).
    let (a, b) = (
        [jac[0][0], jac[1][0], jac[2][0]],
        [jac[0][1], jac[1][1], jac[2][1]],
    );
    let null = [
        a[1] * b[2] - a[2] * b[1],
        a[2] * b[0] - a[0] * b[2],
        a[0] * b[1] - a[1] * b[0],
    ];
    let grad = dv_dq(&m, &[0.0; 3]);
    let work: f64 = (0..3).map(|i| grad[i] * null[i]).sum();
    let norm = null.iter().map(|x| x * x).sum::<f64>().sqrt();
    assert!(norm > 1e-3, "loop Jacobian rank deficient at q = 0");
    assert!(
        (work / norm).abs() > 1.0,
        "four-bar in equilibrium at q = 0: {work}"
    );
}

/// R(rpy) = Rz(y)·Ry(p)·Rx(r), written out independently of the library.
fn rpy_matrix(r: f64, p: f64, y: f64) -> [[f64; 3]; 3] {
    let rx = [
        [1.0, 0.0, 0.0],
        [0.0, r.cos(), -r.sin()],
        [0.0, r.sin(), r.cos()],
    ];
    let ry = [
        [p.cos(), 0.0, p.sin()],
        [0.0, 1.0, 0.0],
        [-p.sin(), 0.0, p.cos()],
    ];
    let rz = [
        [y.cos(), -y.sin(), 0.0],
        [y.sin(), y.cos(), 0.0],
        [0.0, 0.0, 1.0],
    ];
    mul(&mul(&rz, &ry), &rx)
}

fn mul(a: &[[f64; 3]; 3], b: &[[f64; 3]; 3]) -> [[f64; 3]; 3] {
    let mut c = [[0.0; 3]; 3];
    for i in 0..3 {
        for j in 0..3 {
            c[i][j] = (0..3).map(|k| a[i][k] * b[k][j]).sum();
        }
    }
    c
}

fn apply(a: &[[f64; 3]; 3], v: [f64; 3]) -> [f64; 3] {
    [0, 1, 2].map(|i| (0..3).map(|k| a[i][k] * v[k]).sum())
}

#[test]
fn links_welded_by_fixed_joints_keep_their_own_inertia() {
    // A massless arm on a y hinge carries two welded links with rotated inertials; about the
    // hinge M = Σ m (cx² + cz²) + (R I Rᵀ)_yy with c, R of each link in the arm frame.
    let xml = r#"<robot name="welded">
  <link name="base"/>
  <link name="arm"/>
  <link name="ball1">
    <inertial><origin xyz="0 0 0.5" rpy="0.1 0 0"/><mass value="2"/>
      <inertia ixx="0.1" ixy="0.01" ixz="0" iyy="0.2" iyz="0.02" izz="0.3"/></inertial>
  </link>
  <link name="ball2">
    <inertial><origin xyz="0.2 -0.1 0" rpy="0 0.4 -0.3"/><mass value="0.5"/>
      <inertia ixx="0.05" ixy="0" ixz="0.01" iyy="0.04" iyz="0" izz="0.03"/></inertial>
  </link>
  <joint name="hinge" type="continuous"><parent link="base"/><child link="arm"/><axis xyz="0 1 0"/></joint>
  <joint name="w1" type="fixed"><parent link="arm"/><child link="ball1"/><origin xyz="1 0 0" rpy="0.3 0.2 0.1"/></joint>
  <joint name="w2" type="fixed"><parent link="ball1"/><child link="ball2"/><origin xyz="0 0.3 -0.4" rpy="-0.5 0.1 0.7"/></joint>
</robot>"#;
    let m = from_str(xml, BaseType::Fixed);
    assert_eq!(m.nq(), 1);
    let r1 = rpy_matrix(0.3, 0.2, 0.1);
    let r2 = mul(&r1, &rpy_matrix(-0.5, 0.1, 0.7));
    let o2 = {
        let d = apply(&r1, [0.0, 0.3, -0.4]);
        [1.0 + d[0], d[1], d[2]]
    };
    let bodies = [
        (
            2.0,
            [1.0, 0.0, 0.0],
            r1,
            [0.0, 0.0, 0.5],
            rpy_matrix(0.1, 0.0, 0.0),
            [[0.1, 0.01, 0.0], [0.01, 0.2, 0.02], [0.0, 0.02, 0.3]],
        ),
        (
            0.5,
            o2,
            r2,
            [0.2, -0.1, 0.0],
            rpy_matrix(0.0, 0.4, -0.3),
            [[0.05, 0.0, 0.01], [0.0, 0.04, 0.0], [0.01, 0.0, 0.03]],
        ),
    ];
    let mut want = 0.0;
    for (mass, origin, rot, com, inertial_rot, inertia) in bodies {
        let c = apply(&rot, com);
        let c = [origin[0] + c[0], origin[1] + c[1], origin[2] + c[2]];
        let r = mul(&rot, &inertial_rot);
        let iyy: f64 = (0..3)
            .flat_map(|a| (0..3).map(move |b| (a, b)))
            .map(|(a, b)| r[1][a] * inertia[a][b] * r[1][b])
            .sum();
        want += mass * (c[0] * c[0] + c[2] * c[2]) + iyy;
    }
    for q in [-1.0, 0.0, 0.4, 2.5] {
        let got = mass_matrix(&m, &[q])[(0, 0)];
        assert!(close(got, want, 1e-13, 0.0), "{got} vs {want}");
    }
    // The welded link's origin moves with the hinge: Ry(q)·o2.
    let q = 0.7f64;
    let p = point_position(&m, m.link_index("ball2").expect("ball2"), &[0.0; 3], &[q]);
    let ry = rpy_matrix(0.0, q, 0.0);
    let want_p = apply(&ry, o2);
    for k in 0..3 {
        assert!(close(p[k], want_p[k], 1e-14, 1e-15));
    }
}
