//! A tilted ground plane: `[terrain.slope]`.

use serde::Deserialize;

use super::Requirement;

/// The ground tilted by `angle` degrees, falling along the horizontal direction `heading`
/// degrees from world +x towards +y (0: it falls along +x, 90: along +y), through
/// (0, 0, ground height). Its fields are the problem file's `[terrain.slope]` table.
///
/// Its contact frame is its own: the unit normal n = (sin θ cos ψ, sin θ sin ψ, cos θ), the
/// first tangent the plane's direction above world +x, t₁ = (eₓ − (eₓ·n) n)/|…|, the second
/// t₂ = n × t₁ (the direction above +y). On a slope the distance of a point is n·(p − o), the
/// normal impulse acts along n and the friction directions are ±t₁, ±t₂: the Coulomb cone of
/// the plane.
#[derive(Debug, Clone, Copy, PartialEq, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Slope {
    /// Tilt θ from the horizontal [deg], in [0, 80].
    pub angle: f64,
    /// Direction ψ the plane falls towards [deg], from world +x towards +y (default 0).
    #[serde(default)]
    pub heading: f64,
}

/// A [`Slope`] as the contact rows use it: its frame and its height's gradient, computed once
/// when the problem is checked rather than in every distance and tangential coordinate of
/// every callback.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct TiltedGround {
    /// The file's entry.
    pub slope: Slope,
    /// [`Slope::frame`]: [t₁, t₂, n].
    pub frame: [[f64; 3]; 3],
    /// [`Slope::gradient`]: (∂H/∂x, ∂H/∂y).
    pub gradient: (f64, f64),
}

/// Largest tilt accepted [deg]: steeper planes are walls, not ground.
pub const MAX_SLOPE_ANGLE: f64 = 80.0;

/// (sin, cos) of `degrees`, exact at multiples of 90° (a plane falling along +y has no x
/// part at all, as one falling along +x has no y part).
pub fn sin_cos_degrees(degrees: f64) -> (f64, f64) {
    let quarter = degrees / 90.0;
    if quarter == quarter.round() {
        return match (quarter.round() as i64).rem_euclid(4) {
            0 => (0.0, 1.0),
            1 => (1.0, 0.0),
            2 => (0.0, -1.0),
            _ => (-1.0, 0.0),
        };
    }
    degrees.to_radians().sin_cos()
}

impl Slope {
    /// The plane's contact frame [t₁, t₂, n] (unit vectors, right-handed: t₁ × t₂ = n).
    pub fn frame(&self) -> [[f64; 3]; 3] {
        let (s, c) = sin_cos_degrees(self.angle);
        let (sp, cp) = sin_cos_degrees(self.heading);
        let n = [s * cp, s * sp, c];
        // eₓ − (eₓ·n) n, normalised: |…|² = 1 − n_x².
        let scale = 1.0 / (1.0 - n[0] * n[0]).sqrt();
        let t1 = [
            (1.0 - n[0] * n[0]) * scale,
            -n[0] * n[1] * scale,
            -n[0] * n[2] * scale,
        ];
        let t2 = [
            n[1] * t1[2] - n[2] * t1[1],
            n[2] * t1[0] - n[0] * t1[2],
            n[0] * t1[1] - n[1] * t1[0],
        ];
        [t1, t2, n]
    }

    /// The ground it tilts, its frame and gradient computed.
    pub fn ground(self) -> TiltedGround {
        TiltedGround {
            slope: self,
            frame: self.frame(),
            gradient: self.gradient(),
        }
    }

    /// Its height's gradient (∂H/∂x, ∂H/∂y) = −tan θ (cos ψ, sin ψ): the height it adds at
    /// (x, y) is ∂H/∂x·x + ∂H/∂y·y.
    pub fn gradient(&self) -> (f64, f64) {
        let (s, c) = sin_cos_degrees(self.angle);
        let (sp, cp) = sin_cos_degrees(self.heading);
        let tan = s / c;
        (-tan * cp, -tan * sp)
    }

    /// Whether it tilts across the x–z plane (a planar robot cannot stand on it).
    pub fn tilts_along_y(&self) -> bool {
        sin_cos_degrees(self.heading).0 != 0.0 && self.angle != 0.0
    }

    /// Each number of the table with what it must satisfy.
    pub fn requirements(&self) -> Vec<(&'static str, f64, Requirement)> {
        vec![
            ("angle", self.angle, Requirement::Finite),
            ("heading", self.heading, Requirement::Finite),
        ]
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn dot(a: [f64; 3], b: [f64; 3]) -> f64 {
        a.iter().zip(b).map(|(x, y)| x * y).sum()
    }

    /// The frame is orthonormal and right-handed at any tilt and heading, n is the plane's
    /// normal (perpendicular to its height's gradient directions), t₁ lies over +x; at
    /// headings 0 and 90 the frame is the hand-computed one, its zero parts exactly zero.
    #[test]
    fn the_frame_is_the_planes_own() {
        for (angle, heading) in [
            (15.0, 0.0),
            (15.0, 90.0),
            (30.0, 37.0),
            (0.0, 0.0),
            (60.0, -120.0),
        ] {
            let slope = Slope { angle, heading };
            let [t1, t2, n] = slope.frame();
            for (a, b, expected) in [
                (t1, t1, 1.0),
                (t2, t2, 1.0),
                (n, n, 1.0),
                (t1, t2, 0.0),
                (t1, n, 0.0),
                (t2, n, 0.0),
            ] {
                assert!((dot(a, b) - expected).abs() < 1e-15, "{angle} {heading}");
            }
            let cross = [
                t1[1] * t2[2] - t1[2] * t2[1],
                t1[2] * t2[0] - t1[0] * t2[2],
                t1[0] * t2[1] - t1[1] * t2[0],
            ];
            assert!(cross.iter().zip(n).all(|(a, b)| (a - b).abs() < 1e-15));
            // The plane's own directions (1, 0, ∂H/∂x) and (0, 1, ∂H/∂y) are normal to n.
            let (gx, gy) = slope.gradient();
            assert!(dot([1.0, 0.0, gx], n).abs() < 1e-15);
            assert!(dot([0.0, 1.0, gy], n).abs() < 1e-15);
            assert!(t1[1].abs() < 1e-15 || heading != 0.0);
        }
        let (s, c) = (15f64.to_radians().sin(), 15f64.to_radians().cos());
        let close = |a: [[f64; 3]; 3], b: [[f64; 3]; 3]| {
            a.iter()
                .flatten()
                .zip(b.iter().flatten())
                .all(|(x, y)| (x - y).abs() < 1e-15)
        };
        let along_x = Slope {
            angle: 15.0,
            heading: 0.0,
        }
        .frame();
        assert!(
            close(along_x, [[c, 0.0, -s], [0.0, 1.0, 0.0], [s, 0.0, c]]),
            "{along_x:?}"
        );
        let along_y = Slope {
            angle: 15.0,
            heading: 90.0,
        }
        .frame();
        assert!(
            close(along_y, [[1.0, 0.0, 0.0], [0.0, c, -s], [0.0, s, c]]),
            "{along_y:?}"
        );
        // No x part in a plane falling along +y, no y part in one falling along +x.
        assert_eq!(
            (along_y[0][1], along_y[0][2], along_y[2][0]),
            (0.0, 0.0, 0.0)
        );
        assert_eq!(
            (along_x[1][0], along_x[1][2], along_x[2][1]),
            (0.0, 0.0, 0.0)
        );
        assert!(
            !Slope {
                angle: 15.0,
                heading: 180.0
            }
            .tilts_along_y()
        );
        assert!(
            Slope {
                angle: 15.0,
                heading: 90.0
            }
            .tilts_along_y()
        );
    }
}
