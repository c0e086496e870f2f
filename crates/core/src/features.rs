//! What passes through the contact, shared by every model: dents (or bumps) in the ball's
//! surface, and the oil supply with its holes. Both travel with the surfaces (pure rolling):
//! a feature's centre at time `t` is `x_start + travel(t)/a` ([`crate::Kinematics::travel`]).
//! Depths and thicknesses in m (SI, as the scene gives them), positions in units of `a`.

use crate::grid::dent_profile;
use serde::{Deserialize, Serialize};

/// A dent in the ball (seed Eq. 14, reconstructed): a gap added of
/// `depth · 10^(−10 ((x − x_c)² + (y − y_c)²) / W²)`; a negative depth is a bump.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Dent {
    /// Depth at the centre [m].
    pub depth_m: f64,
    /// Width factor `W` [a].
    pub width_a: f64,
    /// Centre at `t = 0` [a].
    pub x_start_a: f64,
    /// Centre across the rolling direction [a].
    #[serde(default)]
    pub y_a: f64,
}

impl Dent {
    /// Gap added at `(x, y)` [a] with the centre at `x_c` [a], in units of `delta` [m] (the
    /// solvers' `a²/R`).
    #[inline]
    pub fn gap(&self, x: f64, y: f64, x_c: f64, delta: f64) -> f64 {
        let r2 = (x - x_c).powi(2) + (y - self.y_a).powi(2);
        self.depth_m / delta * dent_profile(r2, self.width_a)
    }
    /// Radius beyond which the dent is below 1e-6 of its depth [a].
    pub fn reach_a(&self) -> f64 {
        self.width_a * (0.6f64).sqrt()
    }
}

/// A circular hole in the supplied oil (no oil inside), carried with the surfaces.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Hole {
    /// Radius [a].
    pub radius_a: f64,
    /// Centre at `t = 0` [a].
    pub x_start_a: f64,
    /// Centre across the rolling direction [a].
    #[serde(default)]
    pub y_a: f64,
}

impl Hole {
    /// Whether `(x, y)` [a] is inside the hole when its centre is at `x_c` [a].
    #[inline]
    pub fn inside(&self, x: f64, y: f64, x_c: f64) -> bool {
        (x - x_c).powi(2) + (y - self.y_a).powi(2) < self.radius_a * self.radius_a
    }
}

/// The oil supplied to the contact: a layer of `thickness_m` on the track, arriving with the
/// surfaces, with holes where there is none. Every model that has a supply reads this one.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Supply {
    /// Thickness of the supplied layer `l0` (the inlet layer `h_oil`) [m].
    pub thickness_m: f64,
    /// Holes in it (the seed's dry spot).
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub holes: Vec<Hole>,
}

impl Supply {
    /// A uniform supply of `thickness_m` [m].
    pub fn uniform(thickness_m: f64) -> Self {
        Self { thickness_m, holes: vec![] }
    }
    /// The thickness at `(x, y)` [a] with the holes' centres moved by `travel_a` [a] [m].
    pub fn thickness_at(&self, x: f64, y: f64, travel_a: f64) -> f64 {
        if self.holes.iter().any(|h| h.inside(x, y, h.x_start_a + travel_a)) {
            0.0
        } else {
            self.thickness_m
        }
    }
}

/// Where a passing feature starts and how far beyond its centre it acts [a]: what a march
/// needs to know to end when features have passed, or when one has reached a place.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Passing {
    /// Centre at `t = 0` [a].
    pub x_start_a: f64,
    /// Half-size beyond which it has no effect [a].
    pub reach_a: f64,
}

impl From<&Dent> for Passing {
    fn from(d: &Dent) -> Self {
        Passing { x_start_a: d.x_start_a, reach_a: d.reach_a() }
    }
}

impl From<&Hole> for Passing {
    fn from(h: &Hole) -> Self {
        Passing { x_start_a: h.x_start_a, reach_a: h.radius_a }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_dent_is_its_depth_at_the_centre_and_a_millionth_at_its_reach() {
        let d = Dent { depth_m: 2e-8, width_a: 0.1, x_start_a: -1.0, y_a: 0.2 };
        assert_eq!(d.gap(0.5, 0.2, 0.5, 1e-9), 20.0);
        let at_reach = d.gap(0.5 + d.reach_a(), 0.2, 0.5, 1e-9);
        assert!((at_reach / 20.0 - 1e-6).abs() < 1e-15, "{at_reach}");
        assert_eq!(Passing::from(&d), Passing { x_start_a: -1.0, reach_a: d.reach_a() });
    }

    #[test]
    fn the_supply_has_no_oil_in_its_holes_wherever_they_have_travelled() {
        let s = Supply {
            thickness_m: 2.5e-8,
            holes: vec![Hole { radius_a: 0.2, x_start_a: -1.0, y_a: 0.0 }],
        };
        assert_eq!(s.thickness_at(-1.0, 0.0, 0.0), 0.0);
        assert_eq!(s.thickness_at(-1.0, 0.0, 0.5), 2.5e-8);
        assert_eq!(s.thickness_at(-0.45, 0.1, 0.5), 0.0);
        assert_eq!(s.thickness_at(-0.45, 0.21, 0.5), 2.5e-8);
        assert_eq!(Supply::uniform(1e-8).thickness_at(0.0, 0.0, 0.0), 1e-8);
    }
}
