//! Loop-closure residuals and their derivatives.

use super::Model;
use super::kinematics::{check_len, frame_pose};
use super::point_jet::{PointJet, point_jet, vector_jet};
use super::spatial::{add, mat_mul, mat_mul_const, mat_t_vec, mat_vec_const, sub};
use crate::autodiff::Scalar;

/// Loop-closure residual, length `model.num_loop_constraints()`: for each loop (document
/// order) the two components of R_Bᵀ(p1 − p2) perpendicular to the pin axis (see
/// [`super::LoopClosure`]); zero when every loop is closed. Length units of the model.
pub fn loop_residual<D: Scalar>(model: &Model, q: &[D]) -> Vec<D> {
    check_len(model, q.len(), "q");
    let mut out = Vec::with_capacity(model.num_loop_constraints());
    for closure in &model.loop_closures {
        let place1 = &model.link_frame[closure.link1.0];
        let place2 = &model.link_frame[closure.link2.0];
        let pose1 = frame_pose(model, place1.frame, q);
        let pose2 = frame_pose(model, place2.frame, q);
        let in_frame1 = place1.point_in_frame(&closure.point1);
        let in_frame2 = place2.point_in_frame(&closure.point2);
        let p1 = add(pose1.origin, mat_vec_const(&pose1.rotation, &in_frame1));
        let p2 = add(pose2.origin, mat_vec_const(&pose2.rotation, &in_frame2));
        // Frame B's axes in the tree frame of link2, then in the world.
        let b_in_frame2: [[f64; 3]; 3] = mat_mul(&place2.rotation, &closure.rotation2);
        let frame_b = mat_mul_const(&pose2.rotation, &b_in_frame2);
        let gap = mat_t_vec(&frame_b, sub(p1, p2));
        for direction in &closure.directions {
            out.push(gap[0] * direction[0] + gap[1] * direction[1] + gap[2] * direction[2]);
        }
    }
    out
}

/// Residual rows of one group of loop closures and their derivatives in the coordinates
/// `coords` they depend on (every other coordinate has zero derivatives); local index a
/// stands for q[`coords[a]`], u = `coords.len()`, r counts the group's rows.
#[derive(Debug, Clone, PartialEq)]
pub struct LoopJet {
    /// Coordinates the rows depend on.
    pub coords: Vec<usize>,
    /// Index of the group's first row in [`loop_residual`].
    pub first_row: usize,
    /// Residual of each row.
    pub value: Vec<f64>,
    /// ∂a_r/∂q_a at `[r * u + a]`.
    pub first: Vec<f64>,
    /// ∂²a_r/∂q_a∂q_b at `[(r * u + a) * u + b]`; empty below order 2.
    pub second: Vec<f64>,
    /// Σ_e along_e ∂³a_r/∂q_a∂q_b∂q_e at `[(r * u + a) * u + b]`; empty below order 3.
    pub third_along: Vec<f64>,
}

impl LoopJet {
    /// Number of rows.
    pub fn rows(&self) -> usize {
        self.value.len()
    }
}

/// [`loop_residual`]'s rows at q, one [`LoopJet`] per loop (its two rows, over the
/// coordinates of both links' chains), with derivatives up to `order` (1 to 3); the third
/// derivatives contracted with `along` (length n; read at order 3 only).
///
/// Row d of a loop is a_d = e_d(q)·(p1(q) − p2(q)), e_d = R_B d the world direction carried
/// by link2: the points' jets and the direction's ([`vector_jet`]) combine by the product
/// rule, so no dual numbers run through the chains (generic AD over all n coordinates and
/// the multipliers was most of HAMR's callback time).
pub fn loop_closure_jets(model: &Model, q: &[f64], order: usize, along: &[f64]) -> Vec<LoopJet> {
    check_len(model, q.len(), "q");
    if order >= 3 {
        check_len(model, along.len(), "along");
    }
    let mut jets = Vec::with_capacity(model.loop_closures.len());
    let mut first_row = 0;
    for closure in &model.loop_closures {
        let p1 = point_jet(model, closure.link1, &closure.point1, q, order);
        let p2 = point_jet(model, closure.link2, &closure.point2, q, order);
        let mut coords = p2.coords.clone();
        for &c in &p1.coords {
            if !coords.contains(&c) {
                coords.push(c);
            }
        }
        let local = |jet: &PointJet| -> Vec<usize> {
            jet.coords
                .iter()
                .map(|c| coords.iter().position(|x| x == c).unwrap_or(0))
                .collect()
        };
        let (map1, map2) = (local(&p1), local(&p2));
        let u = coords.len();
        let along_local: Vec<f64> = if order >= 3 {
            coords.iter().map(|&c| along[c]).collect()
        } else {
            Vec::new()
        };
        let mut gap = DenseJet::zeros(u, order);
        gap.add(&p1, &map1, 1.0, &along_local, order);
        gap.add(&p2, &map2, -1.0, &along_local, order);
        let rows = closure.directions.len();
        let mut jet = LoopJet {
            coords: coords.clone(),
            first_row,
            value: vec![0.0; rows],
            first: vec![0.0; rows * u],
            second: if order >= 2 {
                vec![0.0; rows * u * u]
            } else {
                Vec::new()
            },
            third_along: if order >= 3 {
                vec![0.0; rows * u * u]
            } else {
                Vec::new()
            },
        };
        for (r, direction) in closure.directions.iter().enumerate() {
            let in_link2 = mat_vec_const(&closure.rotation2, direction);
            let e_jet = vector_jet(model, closure.link2, &in_link2, q, order);
            let mut e = DenseJet::zeros(u, order);
            e.add(&e_jet, &map2, 1.0, &along_local, order);
            e.product_into(&gap, r, &mut jet, order);
        }
        first_row += rows;
        jets.push(jet);
    }
    jets
}

/// A 3-vector's jet over a loop's coordinates, dense, with the contractions along a
/// direction the third order needs (X_L = Σ_e along_e ∂X/∂q_e and so on).
struct DenseJet {
    u: usize,
    value: [f64; 3],
    first: Vec<[f64; 3]>,
    second: Vec<[f64; 3]>,
    along: [f64; 3],
    first_along: Vec<[f64; 3]>,
    second_along: Vec<[f64; 3]>,
}

impl DenseJet {
    fn zeros(u: usize, order: usize) -> Self {
        let sized = |len: usize, from: usize| vec![[0.0; 3]; if order >= from { len } else { 0 }];
        DenseJet {
            u,
            value: [0.0; 3],
            first: vec![[0.0; 3]; u],
            second: sized(u * u, 2),
            along: [0.0; 3],
            first_along: sized(u, 3),
            second_along: sized(u * u, 3),
        }
    }

    /// Adds sign × `jet`, whose local index a is this jet's `map[a]`.
    fn add(&mut self, jet: &PointJet, map: &[usize], sign: f64, along: &[f64], order: usize) {
        let c = jet.len();
        let axpy = |y: &mut [f64; 3], x: &[f64; 3], s: f64| {
            for m in 0..3 {
                y[m] += s * x[m];
            }
        };
        axpy(&mut self.value, &jet.position, sign);
        for (&ma, first) in map.iter().zip(&jet.first) {
            axpy(&mut self.first[ma], first, sign);
        }
        if order >= 2 {
            for a in 0..c {
                for b in 0..c {
                    let i = map[a] * self.u + map[b];
                    axpy(&mut self.second[i], &jet.second[a * c + b], sign);
                }
            }
        }
        if order >= 3 {
            for e in 0..c {
                let w = sign * along[map[e]];
                if w == 0.0 {
                    continue;
                }
                axpy(&mut self.along, &jet.first[e], w);
                for a in 0..c {
                    axpy(&mut self.first_along[map[a]], &jet.second[a * c + e], w);
                    for b in 0..c {
                        let i = map[a] * self.u + map[b];
                        axpy(
                            &mut self.second_along[i],
                            &jet.third[(a * c + b) * c + e],
                            w,
                        );
                    }
                }
            }
        }
    }

    /// Row `r` of `out` ← the jet of self·g (the product rule, term by term).
    fn product_into(&self, g: &DenseJet, r: usize, out: &mut LoopJet, order: usize) {
        let u = self.u;
        let dot = |x: &[f64; 3], y: &[f64; 3]| x[0] * y[0] + x[1] * y[1] + x[2] * y[2];
        out.value[r] = dot(&self.value, &g.value);
        for a in 0..u {
            out.first[r * u + a] = dot(&self.first[a], &g.value) + dot(&self.value, &g.first[a]);
        }
        if order >= 2 {
            for a in 0..u {
                for b in 0..u {
                    let ab = a * u + b;
                    out.second[r * u * u + ab] = dot(&self.second[ab], &g.value)
                        + dot(&self.first[a], &g.first[b])
                        + dot(&self.first[b], &g.first[a])
                        + dot(&self.value, &g.second[ab]);
                }
            }
        }
        if order >= 3 {
            for a in 0..u {
                for b in 0..u {
                    let ab = a * u + b;
                    out.third_along[r * u * u + ab] = dot(&self.second_along[ab], &g.value)
                        + dot(&self.second[ab], &g.along)
                        + dot(&self.first_along[a], &g.first[b])
                        + dot(&self.first_along[b], &g.first[a])
                        + dot(&self.first[a], &g.first_along[b])
                        + dot(&self.first[b], &g.first_along[a])
                        + dot(&self.along, &g.second[ab])
                        + dot(&self.value, &g.second_along[ab]);
                }
            }
        }
    }
}
