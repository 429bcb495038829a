//! The hand-written reverse sweep (model/energy_adjoint.rs, discrete/midpoint_derivatives.rs) against the forward-dual path:
//! gradients of T, V and L, the midpoint slot derivatives, and the Hessian and contracted
//! third derivative of Ld taken through it, on the reference robots and the paper's robots.

use crate::common::robots::{paper_robots, robot};
use vito::autodiff::finite_differences::{self as fd, relative_step, values};

use nalgebra::DMatrix;
use num_dual::Dual64;
use vito::autodiff::{
    ScalarFunction, gradient, gradient_hessian, gradient_hessian_third, jacobian, weighted_hessian,
};
use vito::discrete::{
    LdBuffers, MidpointGradient, MidpointSegment, d1_ld, d2_ld, ld, midpoint_gradient_hessian,
    midpoint_ld_gradient, midpoint_third_order, midpoint_third_order_into,
};
use vito::model::{
    BaseType, Model, SweepBuffers, kinetic_energy, kinetic_energy_gradient, lagrangian_gradient,
    potential_energy, potential_energy_gradient, sample,
};
use vito::random::SeededRng;

/// A floating robot that exercises every branch of the sweep: joint origins with rpy,
/// a revolute and a prismatic joint about tilted (non-coordinate) axes, a negative
/// coordinate axis, a link welded by a fixed joint, full inertia tensors and a spring.
const TWISTED: &str = r#"<?xml version="1.0"?>
<robot name="twisted">
  <link name="body">
    <inertial>
      <origin xyz="0.1 -0.05 0.02" rpy="0.2 0.1 -0.3"/>
      <mass value="3.0"/>
      <inertia ixx="0.3" ixy="0.01" ixz="-0.02" iyy="0.25" iyz="0.015" izz="0.2"/>
    </inertial>
  </link>
  <link name="arm">
    <inertial>
      <origin xyz="0.2 0.05 -0.1" rpy="0 0.4 0"/>
      <mass value="1.2"/>
      <inertia ixx="0.05" ixy="0.002" ixz="0" iyy="0.04" iyz="-0.003" izz="0.03"/>
    </inertial>
  </link>
  <link name="slider">
    <inertial>
      <origin xyz="0 0.03 0.01" rpy="0 0 0"/>
      <mass value="0.7"/>
      <inertia ixx="0.01" ixy="0" ixz="0.001" iyy="0.012" iyz="0" izz="0.008"/>
    </inertial>
  </link>
  <link name="cap">
    <inertial>
      <origin xyz="0.05 0 0" rpy="0 0 0"/>
      <mass value="0.4"/>
      <inertia ixx="0.002" ixy="0" ixz="0" iyy="0.003" iyz="0" izz="0.004"/>
    </inertial>
  </link>
  <link name="hand">
    <inertial>
      <origin xyz="0 0 -0.08" rpy="0 0 0"/>
      <mass value="0.3"/>
      <inertia ixx="0.001" ixy="0" ixz="0" iyy="0.001" iyz="0" izz="0.0005"/>
    </inertial>
  </link>
  <joint name="shoulder" type="revolute">
    <parent link="body"/>
    <child link="arm"/>
    <origin xyz="0.3 0.1 -0.2" rpy="0.5 -0.3 0.8"/>
    <axis xyz="0.48 0.6 0.64"/>
    <limit lower="-3" upper="3" effort="10" velocity="10"/>
  </joint>
  <joint name="extend" type="prismatic">
    <parent link="arm"/>
    <child link="slider"/>
    <origin xyz="0.4 0 0" rpy="-0.2 0.1 0.3"/>
    <axis xyz="0 0.6 -0.8"/>
    <limit lower="-1" upper="1" effort="10" velocity="10"/>
  </joint>
  <joint name="weld" type="fixed">
    <parent link="slider"/>
    <child link="cap"/>
    <origin xyz="0.1 0.02 0" rpy="0.3 0 -0.2"/>
  </joint>
  <joint name="wrist" type="continuous">
    <parent link="cap"/>
    <child link="hand"/>
    <origin xyz="0.05 0 0" rpy="0 0 0"/>
    <axis xyz="-1 0 0"/>
  </joint>
  <force_element name="wrist_spring">
    <torsional_spring stiffness="2.5" rest_angle="0.3">
      <joint name="wrist"/>
    </torsional_spring>
  </force_element>
</robot>
"#;

/// Every robot of the comparison, with its name.
fn robots() -> Vec<(&'static str, Model)> {
    let sampled = |xml: &str, base| Model::from_urdf_str(xml, base).expect("sample loads");
    let mut robots = vec![
        ("pendulum", sampled(&sample::pendulum(), BaseType::Fixed)),
        (
            "double_pendulum",
            sampled(&sample::double_pendulum(), BaseType::Fixed),
        ),
        (
            "planar_chain(5)",
            sampled(&sample::planar_chain(5), BaseType::Fixed),
        ),
        (
            "planar_chain(3), planar base",
            sampled(&sample::planar_chain(3), BaseType::Planar),
        ),
        ("brick", sampled(sample::brick(), BaseType::Floating)),
        ("twisted", sampled(TWISTED, BaseType::Floating)),
        (
            "gripper (mimic joints)",
            sampled(sample::gripper(), BaseType::Floating),
        ),
    ];
    robots.extend(paper_robots());
    robots
}

/// `m` with the entries between two marked columns kept and every other entry zero.
fn between_marked(m: &DMatrix<f64>, columns: &[bool]) -> DMatrix<f64> {
    DMatrix::from_fn(m.nrows(), m.ncols(), |i, j| {
        if columns[i] && columns[j] {
            m[(i, j)]
        } else {
            0.0
        }
    })
}

/// Forward-dual gradient of a scalar function of a vector: one `Dual64` pass per input.
fn dual_gradient(x: &[f64], f: impl Fn(&[Dual64]) -> Dual64) -> Vec<f64> {
    (0..x.len())
        .map(|i| {
            let xd: Vec<Dual64> = x
                .iter()
                .enumerate()
                .map(|(j, &v)| Dual64::new(v, if i == j { 1.0 } else { 0.0 }))
                .collect();
            f(&xd).eps
        })
        .collect()
}

/// Asserts |a − b| ≤ tol·max(‖b‖∞, floor) entrywise (relative to the vector's scale).
fn assert_close(what: &str, a: &[f64], b: &[f64], tol: f64) {
    assert_eq!(a.len(), b.len(), "{what}: lengths");
    let scale = b.iter().fold(0.0f64, |m, x| m.max(x.abs())).max(1e-300);
    for (i, (x, y)) in a.iter().zip(b).enumerate() {
        assert!(
            (x - y).abs() <= tol * scale,
            "{what}[{i}]: {x} vs {y} (scale {scale:e}, diff {:e})",
            (x - y).abs() / scale
        );
    }
}

fn assert_matrix_close(what: &str, a: &DMatrix<f64>, b: &DMatrix<f64>, tol: f64) {
    assert_eq!(a.shape(), b.shape(), "{what}: shapes");
    let scale = b.amax().max(1e-300);
    let diff = (a - b).amax();
    assert!(
        diff <= tol * scale,
        "{what}: max difference {diff:e}, scale {scale:e} (relative {:e})",
        diff / scale
    );
}

/// A configuration and velocity of moderate size for the model (HAMR's mm units scale
/// base positions up, its ms units scale velocities down).
fn state(model: &Model, rng: &mut SeededRng) -> (Vec<f64>, Vec<f64>) {
    let n = model.nq();
    (rng.symmetric_vec(n, 0.8), rng.symmetric_vec(n, 1.5))
}

#[test]
fn kinetic_energy_gradient_matches_forward_duals() {
    let mut rng = SeededRng::new(11);
    for (name, model) in robots() {
        let n = model.nq();
        for _ in 0..3 {
            let (q, qdot) = state(&model, &mut rng);
            let mut dq = vec![f64::NAN; n];
            let mut dqdot = vec![f64::NAN; n];
            let t = kinetic_energy_gradient(&model, &q, &qdot, &mut dq, &mut dqdot);
            let t_ref = kinetic_energy(&model, &q, &qdot);
            assert!(
                (t - t_ref).abs() <= 1e-13 * t_ref.abs(),
                "{name}: T {t} vs {t_ref}"
            );
            let qdot_d: Vec<Dual64> = qdot.iter().map(|&v| Dual64::from(v)).collect();
            let dq_ref = dual_gradient(&q, |x| kinetic_energy(&model, x, &qdot_d));
            let q_d: Vec<Dual64> = q.iter().map(|&v| Dual64::from(v)).collect();
            let dqdot_ref = dual_gradient(&qdot, |x| kinetic_energy(&model, &q_d, x));
            // Relative to the whole gradient: ∂T/∂q vanishes for a single pendulum.
            let both = [dq.as_slice(), &dqdot].concat();
            let both_ref = [dq_ref.as_slice(), &dqdot_ref].concat();
            assert_close(
                &format!("{name}: [dT/dq; dT/dqdot]"),
                &both,
                &both_ref,
                1e-12,
            );
            // T is quadratic in q̇: q̇·∂T/∂q̇ = 2T (Euler's theorem).
            let twice: f64 = qdot.iter().zip(&dqdot).map(|(a, b)| a * b).sum();
            assert!((twice - 2.0 * t).abs() <= 1e-12 * t.abs(), "{name}: Euler");
        }
    }
}

#[test]
fn potential_energy_gradient_matches_forward_duals() {
    let mut rng = SeededRng::new(23);
    for (name, model) in robots() {
        let n = model.nq();
        for _ in 0..3 {
            let (q, _) = state(&model, &mut rng);
            let mut dq = vec![f64::NAN; n];
            let v = potential_energy_gradient(&model, &q, &mut dq);
            let v_ref = potential_energy(&model, &q);
            assert!(
                (v - v_ref).abs() <= 1e-13 * v_ref.abs().max(1e-300),
                "{name}: V {v} vs {v_ref}"
            );
            let dq_ref = dual_gradient(&q, |x| potential_energy(&model, x));
            assert_close(&format!("{name}: dV/dq"), &dq, &dq_ref, 1e-12);
        }
    }
}

#[test]
fn springs_and_gravity_both_enter_the_potential_gradient() {
    // The twisted robot's wrist spring: ½·2.5·(q − 0.3)², and gravity along −z on 5.6 kg.
    let model = Model::from_urdf_str(TWISTED, BaseType::Floating).expect("loads");
    assert_eq!(model.springs().len(), 1);
    let wrist = model.coordinate_index("wrist").expect("wrist");
    let z = model.coordinate_index("base_z").expect("base_z");
    let q = vec![0.0; model.nq()];
    let mut dq = vec![0.0f64; model.nq()];
    potential_energy_gradient(&model, &q, &mut dq);
    // ∂V/∂base_z = m g for a pure translation of everything.
    assert!((dq[z] - 5.6 * 9.81).abs() < 1e-12, "{}", dq[z]);
    let mut no_gravity = model.clone();
    no_gravity.set_gravity([0.0; 3]);
    potential_energy_gradient(&no_gravity, &q, &mut dq);
    assert!((dq[wrist] - 2.5 * (0.0 - 0.3)).abs() < 1e-15);
}

#[test]
fn lagrangian_gradient_is_kinetic_minus_potential() {
    let mut rng = SeededRng::new(5);
    for (name, model) in robots() {
        let n = model.nq();
        let (q, v) = state(&model, &mut rng);
        let (mut tq, mut tv, mut vq) = (vec![0.0; n], vec![0.0; n], vec![0.0; n]);
        let t = kinetic_energy_gradient(&model, &q, &v, &mut tq, &mut tv);
        let pot = potential_energy_gradient(&model, &q, &mut vq);
        let (mut lq, mut lv) = (vec![f64::NAN; n], vec![f64::NAN; n]);
        let l = lagrangian_gradient(
            &model,
            &q,
            &v,
            &mut lq,
            &mut lv,
            &mut SweepBuffers::default(),
        );
        assert!(
            (l - (t - pot)).abs() <= 1e-13 * (t.abs() + pot.abs()),
            "{name}"
        );
        let diff: Vec<f64> = tq.iter().zip(&vq).map(|(a, b)| a - b).collect();
        assert_close(&format!("{name}: dL/dq"), &lq, &diff, 1e-13);
        assert_close(&format!("{name}: dL/dv"), &lv, &tv, 0.0);
    }
}

/// A midpoint segment z = [qa; qb; h] with qb near qa and h of the robot's time scale.
fn segment(model: &Model, rng: &mut SeededRng) -> Vec<f64> {
    let n = model.nq();
    let qa = rng.symmetric_vec(n, 0.8);
    let step = rng.symmetric_vec(n, 0.05);
    let h = if model.name().to_lowercase().contains("hamr") {
        0.3 // ms
    } else {
        0.02
    };
    let mut z = qa.clone();
    z.extend(qa.iter().zip(&step).map(|(a, d)| a + d));
    z.push(h);
    z
}

#[test]
fn midpoint_slot_derivatives_match_the_discrete_module() {
    let mut rng = SeededRng::new(77);
    for (name, model) in robots() {
        let n = model.nq();
        let z = segment(&model, &mut rng);
        let (qa, qb, h) = (&z[..n], &z[n..2 * n], z[2 * n]);
        let (mut d1, mut d2) = (vec![f64::NAN; n], vec![f64::NAN; n]);
        let (value, dh) = midpoint_ld_gradient(
            &model,
            qa,
            qb,
            h,
            &mut d1,
            &mut d2,
            &mut LdBuffers::default(),
        );
        let value_ref = ld(&model, qa, qb, h);
        assert!(
            (value - value_ref).abs() <= 1e-13 * value_ref.abs(),
            "{name}: Ld {value} vs {value_ref}"
        );
        // Against forward AD through Ld itself (d1_ld/d2_ld are this adjoint path now).
        let (_, grad) = gradient(&MidpointSegment { model: &model }, &z);
        assert_close(&format!("{name}: D1Ld"), &d1, &grad[..n], 1e-12);
        assert_close(&format!("{name}: D2Ld"), &d2, &grad[n..2 * n], 1e-12);
        assert_eq!(
            d1,
            d1_ld(&model, qa, qb, h),
            "{name}: d1_ld is the adjoint path"
        );
        assert_eq!(
            d2,
            d2_ld(&model, qa, qb, h),
            "{name}: d2_ld is the adjoint path"
        );
        assert!(
            (dh - grad[2 * n]).abs() <= 1e-12 * grad[2 * n].abs(),
            "{name}: dLd/dh {dh} vs {}",
            grad[2 * n]
        );
    }
}

/// The multiplier direction of the DEL rows: [λ_a; λ_b; 0].
fn direction(n: usize, rng: &mut SeededRng) -> Vec<f64> {
    let mut dir = rng.symmetric_vec(2 * n, 1.0);
    dir.push(0.0);
    dir
}

#[test]
fn hessian_and_third_derivative_through_the_adjoint_match_forward_duals() {
    let mut rng = SeededRng::new(91);
    for (name, model) in robots() {
        let n = model.nq();
        let z = segment(&model, &mut rng);
        let dir = direction(n, &mut rng);
        let reference = gradient_hessian_third(&MidpointSegment { model: &model }, &z, &dir);
        let f = MidpointGradient { model: &model };
        let (values, hess) = jacobian(&f, &z);
        assert_close(
            &format!("{name}: gradient"),
            &values,
            &reference.gradient,
            1e-12,
        );
        assert_matrix_close(&format!("{name}: Hessian"), &hess, &reference.hessian, 1e-9);
        let third = weighted_hessian(&f, &z, &dir);
        assert_matrix_close(
            &format!("{name}: contracted third derivative"),
            &third,
            &reference.contracted,
            1e-9,
        );
        let fast = midpoint_third_order(&model, &z, &dir);
        assert!(
            (fast.value - reference.value).abs() <= 1e-13 * reference.value.abs(),
            "{name}: value"
        );
        assert_close(
            &format!("{name}: fast gradient"),
            &fast.gradient,
            &reference.gradient,
            1e-12,
        );
        assert_matrix_close(
            &format!("{name}: fast Hessian"),
            &fast.hessian,
            &reference.hessian,
            1e-9,
        );
        assert_matrix_close(
            &format!("{name}: fast contracted"),
            &fast.contracted,
            &reference.contracted,
            1e-9,
        );
        assert_eq!(fast.hessian, fast.hessian.transpose(), "{name}: symmetric");
        assert_eq!(
            fast.contracted,
            fast.contracted.transpose(),
            "{name}: symmetric"
        );
    }
}

/// The Hessian-only driver equals the forward-dual Hessian of Ld, `_into` overwrites a used
/// buffer, and a nonzero h component of the direction is handled (third derivative along h).
#[test]
fn hessian_driver_buffer_reuse_and_any_direction() {
    let model = Model::from_urdf_str(TWISTED, BaseType::Floating).expect("loads");
    let mut rng = SeededRng::new(3);
    let z = segment(&model, &mut rng);
    let segment_fn = MidpointSegment { model: &model };
    let (value, grad, hess) = midpoint_gradient_hessian(&model, &z);
    let (value_ref, grad_ref, hess_ref) = gradient_hessian(&segment_fn, &z);
    assert!((value - value_ref).abs() <= 1e-13 * value_ref.abs());
    assert_close("gradient", &grad, &grad_ref, 1e-12);
    assert_matrix_close("Hessian", &hess, &hess_ref, 1e-9);

    let dir = rng.symmetric_vec(z.len(), 1.0);
    let reference = gradient_hessian_third(&segment_fn, &z, &dir);
    let mut out = vito::autodiff::ThirdOrder::zeros(z.len());
    out.hessian.fill(7.0);
    out.contracted.fill(-3.0);
    out.gradient.fill(f64::NAN);
    midpoint_third_order_into(&model, &z, &dir, &mut out);
    assert_close("gradient", &out.gradient, &reference.gradient, 1e-12);
    assert_matrix_close("Hessian", &out.hessian, &reference.hessian, 1e-9);
    assert_matrix_close("contracted", &out.contracted, &reference.contracted, 1e-9);
}

/// Central differences of the adjoint gradient give its Jacobian (an independent check that
/// does not go through any dual number).
#[test]
fn adjoint_hessian_matches_central_differences() {
    let model = Model::from_urdf_str(TWISTED, BaseType::Floating).expect("loads");
    let mut rng = SeededRng::new(41);
    let z = segment(&model, &mut rng);
    let dir = direction(model.nq(), &mut rng);
    let fast = midpoint_third_order(&model, &z, &dir);
    let f = MidpointGradient { model: &model };
    let columns = fd::columns(|x| values(&f, x), &z, |_| 1e-6);
    for (j, column) in columns.iter().enumerate() {
        let exact: Vec<f64> = (0..z.len()).map(|i| fast.hessian[(i, j)]).collect();
        assert_close(&format!("column {j}"), &exact, column, 1e-6);
    }
    // And the value: Ld of the segment.
    let value = MidpointSegment { model: &model }.eval(&z);
    assert!((fast.value - value).abs() <= 1e-13 * value.abs());
}

/// The third-order driver over some columns only (the solve leaves out fixed variables):
/// entries between two computed columns equal the full driver's, entries with one computed
/// column mirror it, the rest are zero.
#[test]
fn third_order_over_some_columns() {
    let model = Model::from_urdf_str(TWISTED, BaseType::Floating).expect("loads");
    let mut rng = SeededRng::new(17);
    let z = segment(&model, &mut rng);
    let dir = rng.symmetric_vec(z.len(), 1.0);
    let full = midpoint_third_order(&model, &z, &dir);
    let columns: Vec<bool> = (0..z.len()).map(|i| i % 3 != 1).collect();
    let mut part = vito::autodiff::ThirdOrder::zeros(z.len());
    part.contracted.fill(5.0);
    vito::discrete::midpoint_third_order_columns(&model, &z, &dir, Some(&columns), &mut part);
    for i in 0..z.len() {
        for j in 0..z.len() {
            for (name, a, b) in [
                ("Hessian", &part.hessian, &full.hessian),
                ("contracted", &part.contracted, &full.contracted),
            ] {
                let expected = if columns[i] || columns[j] {
                    b[(i, j)]
                } else {
                    0.0
                };
                assert!(
                    (a[(i, j)] - expected).abs() <= 1e-9 * b.amax().max(1.0),
                    "{name} ({i}, {j}): {} vs {expected}",
                    a[(i, j)]
                );
            }
        }
    }
}

/// With the columns seeded in groups (from the dependency pattern of the Hessian of Ld:
/// legs couple only through the base), the segment's Hessian and contracted third
/// derivative equal the one-column-per-pass ones on the legged robots, in fewer passes
/// (LittleDog 19 instead of 37, HAMR 21 instead of 77), also with some columns left out.
#[test]
fn grouped_segment_derivatives_match_one_column_per_pass() {
    use vito::autodiff::dependency::{DependencyScalar, Trace};
    use vito::autodiff::{SymmetricGroups, VectorFunction};
    use vito::discrete::midpoint_third_order_columns;
    let mut rng = SeededRng::new(29);
    // More than 16 groups somewhere: the lanes' path sweeps them in several batches.
    let mut most_groups = 0;
    for (name, model) in robots()
        .into_iter()
        .filter(|(name, _)| ["littledog", "hamr"].contains(name))
    {
        let z = segment(&model, &mut rng);
        let dim = z.len();
        let dir = rng.symmetric_vec(dim, 1.0);
        // The Hessian pattern of Ld: the dependencies of its gradient's components.
        let trace = Trace::begin(dim);
        let mut out = vec![DependencyScalar::from(0.0); dim];
        MidpointGradient { model: &model }.eval(&trace.inputs(&z), &mut out);
        let pattern: Vec<bool> = out.iter().flat_map(|y| trace.dependencies(y)).collect();
        let (_, _, hessian) = midpoint_gradient_hessian(&model, &z);
        let full = midpoint_third_order(&model, &z, &dir);
        // All columns; h fixed (a fixed-step problem); and an irregular set, where a left-out
        // base column forces the leg columns it meets apart (no compression asked there).
        for (columns, compresses) in [
            (vec![true; dim], true),
            ((0..dim).map(|i| i != dim - 1).collect(), true),
            (
                (0..dim).map(|i| i % 5 != 2 && i != dim - 1).collect(),
                false,
            ),
        ] {
            let groups = SymmetricGroups::new(dim, &pattern, Some(&columns));
            most_groups = most_groups.max(groups.groups().len());
            assert!(
                !compresses || groups.groups().len() * 3 < dim * 2,
                "{name}: {} groups for {dim} columns",
                groups.groups().len()
            );
            let mut part = vito::autodiff::ThirdOrder::zeros(dim);
            midpoint_third_order_columns(&model, &z, &dir, Some(&columns), &mut part);
            let grouped = grouped_third_order(&model, &z, &dir, &groups);
            let grouped_hessian = grouped_hessian(&model, &z, &groups);
            // Entries between marked columns are exact; the others are left zero.
            for (what, ours, theirs) in [
                ("hessian", &grouped.hessian, &part.hessian),
                ("contracted", &grouped.contracted, &part.contracted),
            ] {
                assert_eq!(
                    ours,
                    &between_marked(ours, &columns),
                    "{name} {what}: outside entries"
                );
                let theirs = between_marked(theirs, &columns);
                assert_matrix_close(&format!("{name} {what}"), ours, &theirs, 1e-10);
            }
            if columns.iter().all(|&c| c) {
                assert_matrix_close(&format!("{name} J"), &grouped_hessian, &hessian, 1e-10);
                assert_matrix_close(&format!("{name} H"), &grouped.hessian, &full.hessian, 1e-10);
            }
        }
    }
    assert!(most_groups > 16, "at most {most_groups} groups");
}

/// The mass matrix from body Jacobians equals ∂²T/∂v² by nested forward duals, and its
/// generic form's derivative along a direction equals the duals' third derivative.
#[test]
fn mass_matrix_is_the_velocity_hessian_of_the_kinetic_energy() {
    use vito::model::{mass_matrix, mass_matrix_entries};
    let mut rng = SeededRng::new(404);
    for (name, model) in robots() {
        let n = model.nq();
        let (q, v) = state(&model, &mut rng);
        let along = rng.symmetric_vec(n, 1.0);
        // ∂²T/∂v² at (q, v) and its derivative along q: T as a function of [q; v].
        let energy = KineticOf { model: &model };
        let mut x = q.clone();
        x.extend(&v);
        let mut dir = along.clone();
        dir.extend(vec![0.0; n]);
        let reference = gradient_hessian_third(&energy, &x, &dir);
        let vv = reference.hessian.view((n, n), (n, n)).into_owned();
        let vv_along = reference.contracted.view((n, n), (n, n)).into_owned();
        let ours = mass_matrix(&model, &q);
        assert_matrix_close(&format!("{name}: M"), &ours, &vv, 1e-13);
        assert_eq!(ours, ours.transpose(), "{name}: M symmetric");
        let lifted: Vec<Dual64> = q
            .iter()
            .zip(&along)
            .map(|(&a, &d)| Dual64::new(a, d))
            .collect();
        let mut entries = Vec::new();
        mass_matrix_entries(&model, &lifted, &mut entries);
        let derivative = DMatrix::from_row_iterator(n, n, entries.iter().map(|e| e.eps));
        assert_matrix_close(
            &format!("{name}: dM along q"),
            &derivative,
            &vv_along,
            1e-12,
        );
    }
}

/// T(q, v) as a scalar function of [q; v].
struct KineticOf<'a> {
    model: &'a Model,
}

impl ScalarFunction for KineticOf<'_> {
    fn dim(&self) -> usize {
        2 * self.model.nq()
    }
    fn eval<D: vito::autodiff::Scalar>(&self, x: &[D]) -> D {
        let n = self.model.nq();
        kinetic_energy(self.model, &x[..n], &x[n..])
    }
}

/// The grouped Hessian of a segment's Ld and its third derivative contracted with `dir`, by
/// one sweep of [`MultiDual`](vito::autodiff::MultiDual) lanes per batch of groups (the
/// solver's path), checked equal, to the bit, to one `Dual64` / `Dual<Dual64>` sweep per
/// group.
fn grouped_third_order(
    model: &Model,
    z: &[f64],
    dir: &[f64],
    groups: &vito::autodiff::SymmetricGroups,
) -> vito::autodiff::ThirdOrder {
    use vito::discrete::{GroupSweeps, midpoint_third_order_grouped};
    let lanes = midpoint_third_order_grouped(model, z, dir, groups, GroupSweeps::Lanes);
    let per_group = midpoint_third_order_grouped(model, z, dir, groups, GroupSweeps::PerGroup);
    assert_bits_equal(&lanes.gradient, &per_group.gradient, "gradient");
    assert_bits_equal(&[lanes.value], &[per_group.value], "value");
    assert_bits_equal(lanes.hessian.as_slice(), per_group.hessian.as_slice(), "H");
    assert_bits_equal(
        lanes.contracted.as_slice(),
        per_group.contracted.as_slice(),
        "contracted",
    );
    lanes
}

/// [`grouped_third_order`]'s Hessian alone, from the first-order (Jacobian) sweeps.
fn grouped_hessian(
    model: &Model,
    z: &[f64],
    groups: &vito::autodiff::SymmetricGroups,
) -> DMatrix<f64> {
    use vito::discrete::{GroupSweeps, midpoint_gradient_hessian_grouped};
    let (gradient, lanes) = midpoint_gradient_hessian_grouped(model, z, groups, GroupSweeps::Lanes);
    let (per_group_gradient, per_group) =
        midpoint_gradient_hessian_grouped(model, z, groups, GroupSweeps::PerGroup);
    assert_bits_equal(&gradient, &per_group_gradient, "gradient (J)");
    assert_bits_equal(lanes.as_slice(), per_group.as_slice(), "H (J)");
    lanes
}

fn assert_bits_equal(a: &[f64], b: &[f64], what: &str) {
    assert_eq!(a.len(), b.len(), "{what}: lengths");
    for (i, (x, y)) in a.iter().zip(b).enumerate() {
        assert_eq!(
            x.to_bits(),
            y.to_bits(),
            "{what}[{i}]: lanes {x:e}, per group {y:e}"
        );
    }
}

/// The segment groups that leave qa columns unseeded ([`midpoint_segment_groups`]: the qa–qa
/// block from the midpoint identity H_aa = H_ab + H_abᵀ − H_bb + (4/h)·M(q̄) and its
/// derivative), the qa columns of base translations (minus their qb columns: L is at most
/// linear in them), and the h column when every column is needed (its entries from the q
/// blocks and the gradient), give the one-column-per-pass Hessian and contracted third derivative to
/// round-off (1e-12 of the largest entry) on every robot, the hopper of the problems
/// included, at random points and at hard ones (large angles and steps, a small h, a
/// direction along h), in fewer passes, also with h or the first configuration fixed; and
/// the Hessian agrees with central differences of the adjoint gradient.
#[test]
fn segment_groups_with_the_midpoint_identity_match_every_column() {
    use vito::autodiff::dependency::{DependencyScalar, Trace};
    use vito::autodiff::{SymmetricGroups, VectorFunction};
    use vito::discrete::midpoint_segment_groups;
    let mut all = robots();
    all.push(("hopper_2d", robot("hopper_2d.urdf", BaseType::Fixed)));
    let mut rng = SeededRng::new(1606);
    // Every lane width of the lanes' path (4, 8, 16) is exercised.
    let mut group_counts = Vec::new();
    for (name, model) in all {
        let n = model.nq();
        let dim = 2 * n + 1;
        // The base translations, from the structure: x, y, z of a floating base, x and z of
        // a planar one and of the hopper's prismatic root joints.
        let translations = model.translation_coordinates();
        let expected = match name {
            "brick" | "twisted" | "gripper (mimic joints)" | "littledog" | "hamr" => 3,
            "planar_chain(3), planar base" | "spring_flamingo" | "hopper_2d" => 2,
            _ => 0,
        };
        assert_eq!(
            translations.iter().filter(|&&t| t).count(),
            expected,
            "{name}: translations {translations:?}"
        );
        let random = segment(&model, &mut rng);
        // Hard: angles past π, a step of a quarter turn, a tenth of the usual h.
        let mut hard: Vec<f64> = rng.symmetric_vec(n, 4.0);
        hard.extend(
            hard.clone()
                .iter()
                .zip(rng.symmetric_vec(n, 1.5))
                .map(|(a, d)| a + d),
        );
        hard.push(random[2 * n] * 0.1);
        let trace = Trace::begin(dim);
        let mut out = vec![DependencyScalar::from(0.0); dim];
        MidpointGradient { model: &model }.eval(&trace.inputs(&random), &mut out);
        let pattern: Vec<bool> = out.iter().flat_map(|y| trace.dependencies(y)).collect();
        for (point, z) in [("random", random), ("hard", hard)] {
            let mut dir = rng.symmetric_vec(dim, 1.0);
            dir[2 * n] = 0.0;
            let full = midpoint_third_order(&model, &z, &dir);
            dir[2 * n] = 0.7;
            let full_h = midpoint_third_order(&model, &z, &dir);
            for columns in [
                vec![true; dim],
                (0..dim).map(|i| i != dim - 1).collect::<Vec<bool>>(),
                (0..dim).map(|i| i >= n).collect(),
            ] {
                let groups = midpoint_segment_groups(&pattern, &columns, &translations);
                group_counts.push(groups.groups().len());
                let previous = SymmetricGroups::new(dim, &pattern, Some(&columns));
                let marked = columns.iter().filter(|&&c| c).count();
                // Fewer passes than columns wherever a qa column is needed.
                assert!(
                    (groups.groups().len() < marked || !columns[0])
                        && groups.groups().len() <= previous.groups().len(),
                    "{name}: {} groups ({} before) for {marked} columns",
                    groups.groups().len(),
                    previous.groups().len()
                );
                if columns.iter().all(|&c| c) && point == "random" {
                    eprintln!(
                        "{name}: {} passes with the identity, {} without, {dim} columns",
                        groups.groups().len(),
                        previous.groups().len()
                    );
                }
                for (reference, along_h) in [(&full, false), (&full_h, true)] {
                    let mut d = dir.clone();
                    if !along_h {
                        d[2 * n] = 0.0;
                    }
                    let ours = grouped_third_order(&model, &z, &d, &groups);
                    // The contracted entries are sums whose terms are as large as the
                    // Hessian's (the kinetic part cancels to zero along q): round-off is
                    // measured against both.
                    let hessian_scale = reference.hessian.amax();
                    for (what, a, b, floor) in [
                        ("hessian", &ours.hessian, &reference.hessian, 0.0),
                        (
                            "contracted",
                            &ours.contracted,
                            &reference.contracted,
                            hessian_scale,
                        ),
                    ] {
                        let (a, b) = (between_marked(a, &columns), between_marked(b, &columns));
                        let scale = b.amax().max(floor);
                        let diff = (&a - &b).amax();
                        assert!(
                            diff <= 1e-12 * scale,
                            "{name} {point} {what} (along h: {along_h}): max difference \
                             {diff:e}, scale {scale:e} (relative {:e})",
                            diff / scale
                        );
                    }
                }
                let hessian = grouped_hessian(&model, &z, &groups);
                assert_matrix_close(
                    &format!("{name} {point} J"),
                    &between_marked(&hessian, &columns),
                    &between_marked(&full.hessian, &columns),
                    1e-12,
                );
            }
            // Central differences of the adjoint gradient (step 1e-6 of the scale).
            let fd = fd::jacobian(
                |x| values(&MidpointGradient { model: &model }, x),
                &z,
                relative_step,
            );
            let groups = midpoint_segment_groups(&pattern, &vec![true; dim], &translations);
            let hessian = grouped_hessian(&model, &z, &groups);
            assert_matrix_close(
                &format!("{name} {point} H against differences"),
                &hessian,
                &fd,
                1e-6,
            );
        }
    }
    for (low, high) in [(1, 4), (5, 8), (9, 16)] {
        assert!(
            group_counts.iter().any(|c| (low..=high).contains(c)),
            "no segment with {low}–{high} groups: {group_counts:?}"
        );
    }
}
