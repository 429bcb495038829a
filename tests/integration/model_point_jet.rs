//! The analytic point jets (`vito::model::point_jet`: chain formulas from joint axes and
//! origins) equal forward AD through `point_position` to round-off, for every link of the
//! paper's robots and of vito's reference robots, in all three orders.

use crate::common::robots::robot;
use vito::discrete::{MechanicsDerivatives, ModelMechanics, contact_jet_by_autodiff};
use vito::model::{BaseType, Model, PointJet};
use vito::problem::ContactSpec;

/// Derivatives of p, one `[f64; 3]` per (multi-)index.
type Tensor = Vec<[f64; 3]>;

/// Dense derivatives of the jet over all n coordinates: (first, second, third).
fn dense(jet: &PointJet, n: usize) -> (Tensor, Tensor, Tensor) {
    let c = jet.len();
    let (mut first, mut second, mut third) = (
        vec![[0.0; 3]; n],
        vec![[0.0; 3]; n * n],
        vec![[0.0; 3]; n * n * n],
    );
    // A coordinate may appear twice (a mimic joint on its leader's path): sum its entries.
    let accumulate = |into: &mut [f64; 3], v: &[f64; 3]| {
        for m in 0..3 {
            into[m] += v[m];
        }
    };
    for a in 0..c {
        accumulate(&mut first[jet.coords[a]], &jet.first[a]);
        for b in 0..c {
            accumulate(
                &mut second[jet.coords[a] * n + jet.coords[b]],
                &jet.second[a * c + b],
            );
            for e in 0..c {
                let (qa, qb, qe) = (jet.coords[a], jet.coords[b], jet.coords[e]);
                accumulate(
                    &mut third[(qa * n + qb) * n + qe],
                    &jet.third[(a * c + b) * c + e],
                );
            }
        }
    }
    (first, second, third)
}

fn max_difference(a: &[[f64; 3]], b: &[[f64; 3]]) -> (f64, f64) {
    let mut diff: f64 = 0.0;
    let mut scale: f64 = 0.0;
    for (x, y) in a.iter().zip(b) {
        for m in 0..3 {
            diff = diff.max((x[m] - y[m]).abs());
            scale = scale.max(y[m].abs());
        }
    }
    (diff, scale)
}

fn check_robot(rel: &str, base: BaseType, links: usize) {
    check_model(rel, robot(rel, base), links);
}

fn check_model(rel: &str, model: Model, links: usize) {
    let n = model.nq();
    let names: Vec<String> = model.link_names().iter().take(links).cloned().collect();
    let contacts: Vec<ContactSpec> = names
        .iter()
        .map(|link| ContactSpec {
            name: link.clone(),
            link: link.clone(),
            point: [0.031, -0.022, 0.047],
            radius: 0.0,
            friction: 1.0,
        })
        .collect();
    let mech = ModelMechanics::new(model, &contacts).expect("every link resolves");
    let q: Vec<f64> = (0..n).map(|k| 0.9 * (1.7 * k as f64 + 0.4).sin()).collect();
    let mut deepest = 0;
    for (i, link) in names.iter().enumerate() {
        let analytic = mech.contact_jet(i, &q, 3);
        let reference = contact_jet_by_autodiff(&mech, i, &q, 3);
        deepest = deepest.max(analytic.len());
        let (d1, d2, d3) = dense(&analytic, n);
        for (order, ours, theirs) in [
            (0, vec![analytic.position], vec![reference.position]),
            (1, d1, reference.first),
            (2, d2, reference.second),
            (3, d3, reference.third),
        ] {
            let (diff, scale) = max_difference(&ours, &theirs);
            assert!(
                diff <= 1e-12 * scale.max(1.0),
                "{rel}, link {link}: order {order} differs by {diff:e} (scale {scale:e})"
            );
        }
        // A lower order leaves the higher tensors empty and the others unchanged.
        let first_only = mech.contact_jet(i, &q, 1);
        assert!(first_only.second.is_empty() && first_only.third.is_empty());
        assert_eq!(first_only.first, analytic.first);
    }
    assert!(
        deepest >= 4,
        "{rel}: no link deeper than {deepest} joints; the test proves too little"
    );
}

#[test]
fn gripper_with_mimic_joints_every_link() {
    // The tip's path holds `left` twice (its finger mimics it, and so does the tip).
    let model = Model::from_urdf_str(vito::model::sample::gripper(), BaseType::Floating)
        .expect("the gripper loads");
    check_model("gripper", model, 100);
}

#[test]
fn brick_floating_base() {
    check_robot("brick.urdf", BaseType::Floating, 10);
}

#[test]
fn hopper_planar_base_with_prismatic_leg() {
    check_robot("hopper_2d.urdf", BaseType::Planar, 10);
}

#[test]
fn spring_flamingo_every_link() {
    check_robot(
        "spring_flamingo/spring_flamingo_passive_ankle.normalized.urdf",
        BaseType::Planar,
        100,
    );
}

#[test]
fn littledog_every_link() {
    check_robot(
        "littledog/LittleDog.normalized.urdf",
        BaseType::Floating,
        100,
    );
}

#[test]
fn hamr_first_links() {
    check_robot("hamr/HAMR_scaledV2.normalized.urdf", BaseType::Floating, 12);
}

/// HAMR's loop-closure jets (points and link-fixed directions by the chain formulas,
/// combined by the product rule) equal forward AD through `loop_residual` in value, first,
/// second and third derivatives (contracted with a direction), on all 24 rows, away from
/// q = 0 where the loops are violated and no derivative vanishes by symmetry.
#[test]
fn hamr_loop_closure_jets_match_autodiff() {
    use vito::discrete::loop_jets_by_autodiff;
    let model = robot("hamr/HAMR_scaledV2_TYM.normalized.urdf", BaseType::Floating);
    let n = model.nq();
    let mech = ModelMechanics::new(model, &[]).expect("no contacts to resolve");
    let q: Vec<f64> = (0..n).map(|k| 0.3 * (1.3 * k as f64 + 0.2).sin()).collect();
    let along: Vec<f64> = (0..n).map(|k| (0.7 * k as f64 - 0.5).cos()).collect();
    let reference = loop_jets_by_autodiff(&mech, &q, 3, &along);
    let [reference] = reference.as_slice() else {
        panic!("the AD reference is one group of all rows");
    };
    let rows = reference.rows();
    assert_eq!(rows, 24);
    let jets = mech.loop_jets(&q, 3, &along);
    assert_eq!(jets.len(), 12, "one jet per loop");
    // Dense (rows × n, rows × n × n) copies of the analytic jets.
    let (mut value, mut first) = (vec![0.0; rows], vec![0.0; rows * n]);
    let (mut second, mut third) = (vec![0.0; rows * n * n], vec![0.0; rows * n * n]);
    let mut covered = 0;
    for jet in &jets {
        let u = jet.coords.len();
        assert!(u < n, "a loop depends on part of the robot only");
        for r in 0..jet.rows() {
            let row = jet.first_row + r;
            covered += 1;
            value[row] = jet.value[r];
            for (a, &ca) in jet.coords.iter().enumerate() {
                first[row * n + ca] = jet.first[r * u + a];
                for (b, &cb) in jet.coords.iter().enumerate() {
                    second[(row * n + ca) * n + cb] = jet.second[(r * u + a) * u + b];
                    third[(row * n + ca) * n + cb] = jet.third_along[(r * u + a) * u + b];
                }
            }
        }
    }
    assert_eq!(covered, rows);
    for (order, ours, theirs) in [
        (0, &value, &reference.value),
        (1, &first, &reference.first),
        (2, &second, &reference.second),
        (3, &third, &reference.third_along),
    ] {
        let scale = theirs.iter().fold(0.0_f64, |m, x| m.max(x.abs()));
        let diff = ours
            .iter()
            .zip(theirs.iter())
            .fold(0.0_f64, |m, (x, y)| m.max((x - y).abs()));
        assert!(scale > 1e-3, "order {order}: all zero proves nothing");
        assert!(
            diff <= 1e-12 * scale.max(1.0),
            "order {order}: differs by {diff:e} (scale {scale:e})"
        );
    }
    // Lower orders leave the higher arrays empty and the rest unchanged.
    let first_only = mech.loop_jets(&q, 1, &[]);
    assert!(
        first_only
            .iter()
            .all(|j| j.second.is_empty() && j.third_along.is_empty())
    );
    assert_eq!(first_only[3].first, jets[3].first);
}
