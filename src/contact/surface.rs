//! The contact frame of the terrain's surface, one definition for every contact row, the
//! simulator, the frame terms and the reports: the signed distance φ(p) of a point and its
//! tangential coordinates τ(p), whose gradients are the unit normal and the friction
//! directions.
//!
//! With H(x, y) the terrain's height and σ = √(1 + |∇H|²), by the terrain's [`Shape`]:
//! - **Flat**: φ = z − H, τ = (x, y): normal +z, tangents world x and y.
//! - **Plane** (a [`crate::contact::Slope`]): φ = n·(p − o), τ_d = t_d·p with the plane's
//!   constant frame: exact.
//! - **Profile** (heights that vary along one horizontal direction u only: steps and stairs
//!   sharing a heading): with s = u·(x, y) and w = u⊥·(x, y), φ = (z − H(s))/σ and the
//!   tangential coordinates τ_u = S(s) + (H′/σ)(z − H), τ_w = w, where S′ = σ (arc length).
//!   On the surface ∇φ is the unit normal and ∇τ_u, ∇τ_w are the unit tangents up the
//!   profile and along its edges: the Coulomb cone of the surface, exactly, also on a step's
//!   face. Off the surface φ is the distance to first order. Only τ's derivatives enter the
//!   rows; its value carries s for S (S's derivatives to fourth order are exact, from σ).
//! - **General** (blocks, a height map, crossing features): φ = (z − H)/σ (unit normal on the
//!   surface, distance to first order), τ_x = x + H_x (z − H)/σ², τ_y = y + H_y (z − H)/σ²:
//!   on the surface ∇τ are world x and y projected onto the tangent plane, tangent but
//!   shorter than 1 (by the cosine of the tilt across them) and not perpendicular where the
//!   ground tilts along both axes. Where the ground is level they are exactly x and y.
//!
//! The tangents are ordered as world x and y are on flat ground: t₁ the one closest to +x,
//! t₂ to +y, t₁ × t₂ = n (for a profile, the pair of ±u-tangent and ±edge-tangent that
//! fits).

use num_dual::{Dual, Dual3, DualNum, third_derivative};

use super::{ContactModel, FrictionBasis, Shape, Terrain, along};
use crate::autodiff::Scalar;
use crate::contact::sin_cos_degrees;

/// Signed distance φ of a world point `p` (length units) to the terrain: positive above,
/// zero on, negative below the surface; along the surface's unit normal (module docs).
pub fn signed_distance<D: Scalar>(terrain: &Terrain, p: &[D; 3]) -> D {
    match terrain.shape() {
        Shape::Flat => p[2] - D::from(terrain.ground_height),
        Shape::Plane(slope) => {
            let [_, _, n] = slope.frame;
            p[0] * D::from(n[0])
                + p[1] * D::from(n[1])
                + (p[2] - D::from(terrain.ground_height)) * D::from(n[2])
        }
        Shape::Profile(heading) => {
            let (h, slope) = profile(terrain, heading, along(heading, p[0], p[1]));
            (p[2] - h) / (slope * slope + 1.0).sqrt()
        }
        Shape::General => {
            let (h, hx, hy) = height_gradient(terrain, p[0], p[1]);
            (p[2] - h) / (hx * hx + hy * hy + 1.0).sqrt()
        }
    }
}

/// Tangential coordinates of a world point: [τ₁] (planar) or [τ₁, τ₂] (spatial), written into
/// `out` (length `basis.num_tangents()`); their gradients on the surface are the friction
/// directions (module docs). On flat ground and a plane they are linear in p, so the same
/// map takes a direction (a rolling sphere's spin column) to its tangential components;
/// validation keeps spheres on those.
pub fn tangential_coordinates<D: Scalar>(
    basis: FrictionBasis,
    terrain: &Terrain,
    p: &[D; 3],
    out: &mut [D],
) {
    let tangents = basis.num_tangents();
    match terrain.shape() {
        Shape::Flat => {
            out[0] = p[0];
            if tangents == 2 {
                out[1] = p[1];
            }
        }
        Shape::Plane(slope) => {
            for (o, t) in out.iter_mut().zip(&slope.frame[..tangents]) {
                *o = p[0] * D::from(t[0]) + p[1] * D::from(t[1]) + p[2] * D::from(t[2]);
            }
        }
        Shape::Profile(heading) => {
            let s = along(heading, p[0], p[1]);
            let w = along(heading + 90.0, p[0], p[1]);
            let (h, slope) = profile(terrain, heading, s);
            let sigma = (slope * slope + 1.0).sqrt();
            let up = arc_length(terrain, heading, s) + slope / sigma * (p[2] - h);
            // t₁ closest to +x, t₂ to +y: the quarter turn nearest the heading.
            let pair = match ((heading / 90.0).round() as i64).rem_euclid(4) {
                0 => [up, w],
                1 => [-w, up],
                2 => [-up, -w],
                _ => [w, -up],
            };
            out[..tangents].copy_from_slice(&pair[..tangents]);
        }
        Shape::General => {
            let (h, hx, hy) = height_gradient(terrain, p[0], p[1]);
            let scale = (p[2] - h) / (hx * hx + hy * hy + 1.0);
            out[0] = p[0] + hx * scale;
            if tangents == 2 {
                out[1] = p[1] + hy * scale;
            }
        }
    }
}

/// The surface's frame at a world point, [t₁, t₂, n]: the gradients of τ and φ there
/// (unit normal; tangents as the module docs say; t₂ of a planar robot is world y). For
/// drawing and for the world-frame impulse ([`world_impulse`]).
pub fn surface_frame(basis: FrictionBasis, terrain: &Terrain, p: [f64; 3]) -> [[f64; 3]; 3] {
    let mut frame = [[0.0, 1.0, 0.0]; 3];
    for axis in 0..3 {
        let mut q = p.map(Dual::<f64>::from_re);
        q[axis].eps = 1.0;
        let mut t = [Dual::from_re(0.0); 2];
        tangential_coordinates(basis, terrain, &q, &mut t);
        for (d, row) in frame.iter_mut().enumerate().take(basis.num_tangents()) {
            row[axis] = t[d].eps;
        }
        frame[2][axis] = signed_distance(terrain, &q).eps;
    }
    frame
}

/// The impulse of one contact as a world vector [length·mass/time units]: c along the normal
/// and (β⁺_d − β⁻_d) along friction direction d, at the contact point `p` where it acts
/// (the gradient of the contact work c φ + Σ_d (β⁺_d − β⁻_d) τ_d in p).
pub fn world_impulse(
    basis: FrictionBasis,
    terrain: &Terrain,
    p: [f64; 3],
    normal: f64,
    friction: &[f64],
) -> [f64; 3] {
    let [t1, t2, n] = surface_frame(basis, terrain, p);
    let nt = basis.num_tangents();
    let mut out = n.map(|x| x * normal);
    for (d, t) in [t1, t2].iter().enumerate().take(nt) {
        let net =
            friction.get(d).copied().unwrap_or(0.0) - friction.get(d + nt).copied().unwrap_or(0.0);
        for (o, x) in out.iter_mut().zip(t) {
            *o += net * x;
        }
    }
    out
}

/// Every interval's impulses as world vectors (N−1 × nc): interval k's normal and friction
/// impulses ([`world_impulse`]) at the contact points of knot k + 1 (`positions`, N × nc),
/// where they act. Empty when the positions are unknown.
pub fn interval_world_impulses(
    model: &ContactModel,
    positions: &[Vec<[f64; 3]>],
    normal: &[Vec<f64>],
    friction: &[Vec<Vec<f64>>],
) -> Vec<Vec<[f64; 3]>> {
    normal
        .iter()
        .zip(friction)
        .zip(positions.iter().skip(1))
        .map(|((c, beta), points)| {
            c.iter()
                .zip(beta)
                .zip(points)
                .map(|((&c, beta), &p)| world_impulse(model.basis, &model.terrain, p, c, beta))
                .collect()
        })
        .collect()
}

/// H and H′ along the heading at distance s: the height on the line through the origin
/// (a profile's height is the same across it).
fn profile<D: Scalar>(terrain: &Terrain, heading: f64, s: D) -> (D, D) {
    let (sin, cos) = sin_cos_degrees(heading);
    let moving = Dual::new(s, D::from(1.0));
    let h = terrain.height(moving * cos, moving * sin);
    (h.re, h.eps)
}

/// S(s), the profile's arc length, as a quartic Taylor polynomial about s's real part: exact
/// derivatives to fourth order (S′ = σ), the value s's real part.
fn arc_length<D: Scalar>(terrain: &Terrain, heading: f64, s: D) -> D {
    let s0 = s.re();
    let (sigma, d1, d2, d3) = third_derivative(
        |s: Dual3<f64>| {
            let (_, slope) = profile(terrain, heading, s);
            (slope * slope + 1.0).sqrt()
        },
        s0,
    );
    let delta = s - D::from(s0);
    let d2x = delta * delta;
    D::from(s0)
        + delta * sigma
        + d2x * (d1 / 2.0)
        + d2x * delta * (d2 / 6.0)
        + d2x * d2x * (d3 / 24.0)
}

/// H, ∂H/∂x and ∂H/∂y at (x, y).
fn height_gradient<D: Scalar>(terrain: &Terrain, x: D, y: D) -> (D, D, D) {
    let along_x = terrain.height(Dual::new(x, D::from(1.0)), Dual::from_re(y));
    let along_y = terrain.height(Dual::from_re(x), Dual::new(y, D::from(1.0)));
    (along_x.re, along_x.eps, along_y.eps)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::contact::{Block, HeightMap, HeightMapEntry, Slope, Stairs, Step};
    use std::sync::Arc;

    fn dot(a: [f64; 3], b: [f64; 3]) -> f64 {
        a.iter().zip(b).map(|(x, y)| x * y).sum()
    }

    fn step_terrain(heading: f64) -> Terrain {
        Terrain {
            steps: vec![Step {
                edge: 0.25,
                rise: 0.11,
                width: 0.005,
                heading,
            }],
            ..Terrain::default()
        }
    }

    #[test]
    fn flat_ground_distance_is_height_above_ground() {
        let terrain = Terrain {
            ground_height: 0.1,
            ..Terrain::default()
        };
        assert!((signed_distance::<f64>(&terrain, &[3.0, -2.0, 0.35]) - 0.25).abs() < 1e-15);
        assert!((signed_distance::<f64>(&terrain, &[3.0, -2.0, 0.05]) + 0.05).abs() < 1e-15);
    }

    #[test]
    fn step_distance_far_past_the_edge_is_height_above_the_top() {
        let terrain = step_terrain(0.0);
        assert!((signed_distance::<f64>(&terrain, &[0.5, 0.0, 0.2]) - 0.09).abs() < 1e-12);
        assert!((signed_distance::<f64>(&terrain, &[0.0, 0.0, 0.2]) - 0.2).abs() < 1e-12);
    }

    /// On a step's face, at any heading, the frame is the surface's: n the unit normal
    /// (−H′u, 1)/σ by hand, t₁ and t₂ unit tangents, orthogonal, right-handed, t₁ nearest +x.
    #[test]
    fn a_steps_face_has_the_surfaces_frame() {
        for heading in [0.0, 90.0, 180.0, 270.0, 30.0, -135.0] {
            let terrain = step_terrain(heading);
            let (sin, cos) = sin_cos_degrees(heading);
            let s = 0.252;
            let (x, y) = (s * cos + 0.3 * sin, s * sin - 0.3 * cos);
            let z = terrain.height_at(x, y);
            let slope = 0.11 * 0.5 * (1.0 - ((s - 0.25) / 0.005_f64).tanh().powi(2)) / 0.005;
            let sigma = (1.0 + slope * slope).sqrt();
            let [t1, t2, n] = surface_frame(FrictionBasis::Spatial, &terrain, [x, y, z]);
            let expected = [-slope * cos / sigma, -slope * sin / sigma, 1.0 / sigma];
            for (a, b) in n.iter().zip(expected) {
                assert!((a - b).abs() < 1e-12, "{heading}: {n:?} {expected:?}");
            }
            for (a, b, e) in [
                (t1, t1, 1.0),
                (t2, t2, 1.0),
                (t1, t2, 0.0),
                (t1, n, 0.0),
                (t2, n, 0.0),
            ] {
                assert!((dot(a, b) - e).abs() < 1e-12, "{heading}: {a:?} {b:?}");
            }
            let cross = [
                t1[1] * t2[2] - t1[2] * t2[1],
                t1[2] * t2[0] - t1[0] * t2[2],
                t1[0] * t2[1] - t1[1] * t2[0],
            ];
            assert!(dot(cross, n) > 1.0 - 1e-12, "{heading}");
            assert!(t1[0] >= t1[1].abs() - 1e-12 || t2[1] >= t2[0].abs() - 1e-12);
        }
    }

    /// The distance's gradient is the unit normal on the surface and φ is the distance along
    /// it to first order: a point a small δ along the normal is δ away (to O(δ²)).
    #[test]
    fn the_distance_is_along_the_unit_normal() {
        let map_text = "0 0.02 0.05 0.03\n0.01 0.04 0.08 0.02\n0.0 0.03 0.06 0.01\n0 0 0.02 0.0\n";
        let map = HeightMap::parse(
            HeightMapEntry {
                file: "m.csv".into(),
                spacing: [0.1, 0.1],
                origin: [0.0, 0.0],
            },
            map_text,
        )
        .unwrap();
        let terrains = [
            step_terrain(30.0),
            Terrain {
                blocks: vec![Block {
                    center: [0.2, 0.1],
                    size: [0.2, 0.3],
                    height: 0.05,
                    width: 0.01,
                    yaw: 20.0,
                }],
                ..Terrain::default()
            },
            Terrain {
                height_map: Some(Arc::new(map)),
                ..Terrain::default()
            },
        ];
        for terrain in &terrains {
            for (x, y) in [(0.2484, 0.01), (0.11, 0.22), (0.27, 0.19)] {
                let p = [x, y, terrain.height_at(x, y)];
                let [_, _, n] = surface_frame(FrictionBasis::Spatial, terrain, p);
                assert!((dot(n, n) - 1.0).abs() < 1e-12);
                let delta = 1e-5;
                let moved = [0, 1, 2].map(|i| p[i] + delta * n[i]);
                let phi = signed_distance::<f64>(terrain, &moved);
                assert!((phi - delta).abs() < 1e-8, "{phi}");
                assert!(signed_distance::<f64>(terrain, &p).abs() < 1e-15);
                // Tangents lie in the tangent plane (general: projected world x and y).
                let [t1, t2, _] = surface_frame(FrictionBasis::Spatial, terrain, p);
                assert!(dot(t1, n).abs() < 1e-12 && dot(t2, n).abs() < 1e-12);
            }
        }
    }

    /// The gradients of φ and τ (by AD, in `surface_frame`) match central differences, also
    /// off the surface and on a step's edge, for every shape.
    #[test]
    fn gradients_match_finite_differences() {
        let stairs = Terrain {
            stairs: vec![Stairs {
                start: 0.1,
                count: 3,
                rise: 0.05,
                run: 0.2,
                width: 0.01,
                heading: 90.0,
            }],
            ..Terrain::default()
        };
        let slope = Terrain {
            slope: Some(
                Slope {
                    angle: 20.0,
                    heading: 40.0,
                }
                .ground(),
            ),
            ..Terrain::default()
        };
        let crossing = Terrain {
            steps: vec![Step::along_x(0.2, 0.05, 0.02)],
            stairs: stairs.stairs.clone(),
            ..Terrain::default()
        };
        for terrain in [&stairs, &slope, &crossing] {
            for p in [[0.13, 0.302, 0.08], [0.2, 0.1, -0.01], [0.21, 0.49, 0.2]] {
                let frame = surface_frame(FrictionBasis::Spatial, terrain, p);
                let e = 1e-6;
                for axis in 0..3 {
                    let at = |sign: f64| {
                        let mut q = p;
                        q[axis] += sign * e;
                        let mut t = [0.0; 2];
                        tangential_coordinates(FrictionBasis::Spatial, terrain, &q, &mut t);
                        [t[0], t[1], signed_distance(terrain, &q)]
                    };
                    let (plus, minus) = (at(1.0), at(-1.0));
                    for k in [0, 1, 2] {
                        // A profile's tangent up the slope has the value s, not S: its
                        // gradient is checked against the hand-computed frame instead.
                        if let Shape::Profile(h) = terrain.shape()
                            && k == ((h / 90.0).round() as i64).rem_euclid(2) as usize
                        {
                            continue;
                        }
                        let fd = (plus[k] - minus[k]) / (2.0 * e);
                        assert!(
                            (fd - frame[k][axis]).abs() < 1e-6,
                            "{k} {axis} {fd} {frame:?}"
                        );
                    }
                }
            }
        }
        assert!(matches!(stairs.shape(), Shape::Profile(_)));
        assert_eq!(crossing.shape(), Shape::General);
    }

    /// A world impulse is the normal impulse along n and the friction along the tangents.
    #[test]
    fn the_world_impulse_adds_normal_and_friction() {
        let terrain = step_terrain(0.0);
        let p = [0.251, 0.0, terrain.height_at(0.251, 0.0)];
        let [t1, t2, n] = surface_frame(FrictionBasis::Spatial, &terrain, p);
        let f = world_impulse(
            FrictionBasis::Spatial,
            &terrain,
            p,
            2.0,
            &[0.5, 0.1, 0.2, 0.4],
        );
        for i in 0..3 {
            let expected = 2.0 * n[i] + 0.3 * t1[i] - 0.3 * t2[i];
            assert!((f[i] - expected).abs() < 1e-15);
        }
        let flat = world_impulse(FrictionBasis::Planar, &Terrain::flat(), p, 2.0, &[0.5, 0.2]);
        assert_eq!(flat, [0.3, 0.0, 2.0]);
    }
}

#[cfg(test)]
mod hessian_tests {
    use super::*;
    use crate::autodiff::{ScalarFunction, gradient_hessian_into};
    use crate::contact::Step;
    use nalgebra::DMatrix;

    struct Coordinate<'a>(&'a Terrain, usize);
    impl ScalarFunction for Coordinate<'_> {
        fn dim(&self) -> usize {
            3
        }
        fn eval<D: Scalar>(&self, p: &[D]) -> D {
            let p = [p[0], p[1], p[2]];
            if self.1 == 2 {
                return signed_distance(self.0, &p);
            }
            let mut t = [D::from(0.0); 2];
            tangential_coordinates(FrictionBasis::Spatial, self.0, &p, &mut t);
            t[self.1]
        }
    }

    /// Each coordinate's AD Hessian equals central differences of its AD gradient: the
    /// arc length's Taylor polynomial gives derivatives of one function.
    #[test]
    fn hessians_are_differences_of_gradients() {
        let terrain = Terrain {
            steps: vec![Step::along_x(0.05, 0.02, 0.1)],
            ..Terrain::default()
        };
        for k in 0..3 {
            let f = Coordinate(&terrain, k);
            let p = [0.07, 0.03, 0.09];
            let (mut g, mut h) = ([0.0; 3], DMatrix::zeros(3, 3));
            gradient_hessian_into::<3, _>(&f, &p, &mut g, &mut h);
            let e = 1e-6;
            for j in 0..3 {
                let at = |sign: f64| {
                    let mut q = p;
                    q[j] += sign * e;
                    let (mut g, mut hh) = ([0.0; 3], DMatrix::zeros(3, 3));
                    gradient_hessian_into::<3, _>(&f, &q, &mut g, &mut hh);
                    g
                };
                let (a, b) = (at(1.0), at(-1.0));
                for i in 0..3 {
                    let fd = (a[i] - b[i]) / (2.0 * e);
                    assert!(
                        (fd - h[(i, j)]).abs() < 1e-7,
                        "{k} {i} {j}: {fd} {}",
                        h[(i, j)]
                    );
                }
            }
        }
    }
}
