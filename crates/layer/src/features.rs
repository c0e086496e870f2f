//! Features that pass through the contact: a dent (or bump) on the ball, which moves with the
//! ball surface, and a hole in the supplied layer, which moves with the layer. Under pure rolling
//! both move at `u1`. Positions in units of `a`.

use serde::{Deserialize, Serialize};

/// A dent in the ball (paper Eq. 14, reconstructed):
/// `b = A l0 10^(−10 ((x − x_b(t))² + (y − y_b)²) / W²)` with `x_b(t) = x_start + u1 t / a`.
/// `A > 0` deepens the gap (a dent); `A < 0` is a bump. The depth is given either as the seed's
/// factor `A` or in metres (`depth_m`, the Reynolds dent's unit): exactly one of the two.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Dent {
    /// Height factor `A` [-]: depth in units of the supply thickness `l0` …
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub amplitude: Option<f64>,
    /// … or the depth at the centre [m].
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub depth_m: Option<f64>,
    /// Width factor `W` [a].
    pub width_a: f64,
    /// Centre at `t = 0` [a].
    pub x_start_a: f64,
    #[serde(default)]
    pub y_a: f64,
}

impl Dent {
    /// The same dent with its depth as the factor `A` for a supply thickness `l0_m` [m] (what
    /// the model holds: [`crate::LayerModel::new`] resolves every dent).
    pub fn resolved(&self, l0_m: f64) -> Dent {
        let a = self.amplitude.or(self.depth_m.map(|d| d / l0_m));
        Dent { amplitude: a, depth_m: None, ..*self }
    }
    /// Gap added [units of `l0`] at `(x, y)` with the dent centre at `xc` (NaN, caught by the
    /// solvers' finiteness checks, for a dent not [`Dent::resolved`]).
    #[inline]
    pub fn depth(&self, x: f64, y: f64, xc: f64) -> f64 {
        let r2 = (x - xc).powi(2) + (y - self.y_a).powi(2);
        self.amplitude.unwrap_or(f64::NAN) * ehl_core::grid::dent_profile(r2, self.width_a)
    }
    /// Radius beyond which the dent is below 1e-6 of its depth [a].
    pub fn reach(&self) -> f64 {
        self.width_a * (0.6f64).sqrt()
    }
}

/// A circular hole (zero supply) in the layer, carried with the layer.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Hole {
    pub radius_a: f64,
    /// Centre at `t = 0` [a].
    pub x_start_a: f64,
    #[serde(default)]
    pub y_a: f64,
}

impl Hole {
    #[inline]
    pub fn inside(&self, x: f64, y: f64, xc: f64) -> bool {
        (x - xc).powi(2) + (y - self.y_a).powi(2) < self.radius_a * self.radius_a
    }
}

/// Either feature.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
#[serde(rename_all = "kebab-case")]
pub enum Feature {
    Dent(Dent),
    Hole(Hole),
}

impl Feature {
    /// Centre at `t = 0` [a].
    pub fn x_start_a(&self) -> f64 {
        match self {
            Feature::Dent(d) => d.x_start_a,
            Feature::Hole(h) => h.x_start_a,
        }
    }
}

impl Feature {
    pub fn x_start(&self) -> f64 {
        match self {
            Feature::Dent(d) => d.x_start_a,
            Feature::Hole(h) => h.x_start_a,
        }
    }
    /// Half-size beyond which the feature has no effect [a].
    pub fn reach(&self) -> f64 {
        match self {
            Feature::Dent(d) => d.reach(),
            Feature::Hole(h) => h.radius_a,
        }
    }
}
