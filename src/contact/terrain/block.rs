//! A raised block: `[[terrain.block]]`.

use serde::Deserialize;

use super::{Requirement, TerrainFeature};
use crate::autodiff::Scalar;
use crate::contact::sin_cos_degrees;

/// A block of `height` on the ground with a `size[0]` × `size[1]` rectangular top centred at
/// `center`, its sides turned by `yaw` degrees from world x and y, its edges smoothed over
/// `width`: H = height · B(a, size₀) · B(b, size₁) with (a, b) the point in the block's axes
/// and B(v, L) = ½ (tanh((v + L/2)/w) − tanh((v − L/2)/w)). A negative height makes a pit.
/// Its fields are the problem file's `[[terrain.block]]` entry.
#[derive(Debug, Clone, Copy, PartialEq, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Block {
    /// World (x, y) of the top's centre [length].
    pub center: [f64; 2],
    /// The top's sides along the block's own x and y [length], > 0.
    pub size: [f64; 2],
    /// Height of the top over the ground [length].
    pub height: f64,
    /// Smoothing length of the edges [length], > 0.
    pub width: f64,
    /// Turn of the block's sides from world x and y [deg] (default 0).
    #[serde(default)]
    pub yaw: f64,
}

impl TerrainFeature for Block {
    const NAME: &'static str = "block";

    fn height<D: Scalar>(&self, x: D, y: D) -> D {
        let (s, c) = sin_cos_degrees(self.yaw);
        let (dx, dy) = (x - D::from(self.center[0]), y - D::from(self.center[1]));
        let a = dx * D::from(c) + dy * D::from(s);
        let b = dy * D::from(c) - dx * D::from(s);
        let w = D::from(self.width);
        let boxcar = |v: D, length: f64| {
            let half = D::from(0.5 * length);
            (((v + half) / w).tanh() - ((v - half) / w).tanh()) * D::from(0.5)
        };
        boxcar(a, self.size[0]) * boxcar(b, self.size[1]) * D::from(self.height)
    }

    fn heading(&self) -> Option<f64> {
        None
    }

    fn edges(&self) -> Vec<(f64, f64)> {
        Vec::new()
    }

    fn requirements(&self) -> Vec<(&'static str, f64, Requirement)> {
        vec![
            ("center[0]", self.center[0], Requirement::Finite),
            ("center[1]", self.center[1], Requirement::Finite),
            ("size[0]", self.size[0], Requirement::Positive),
            ("size[1]", self.size[1], Requirement::Positive),
            ("height", self.height, Requirement::Finite),
            ("width", self.width, Requirement::Positive),
            ("yaw", self.yaw, Requirement::Finite),
        ]
    }
}
