//! Lubricant laws in Hertz units (pressures in `p_h`): viscosity `η̄ = η/η0` and density
//! `ρ̄ = ρ/ρ0` as functions of `P`.

use serde::{Deserialize, Serialize};

/// Pressure–viscosity law.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
#[serde(rename_all = "kebab-case")]
pub enum Viscosity {
    /// Roelands: `η̄ = exp((ln η0 + 9.67)(−1 + (1 + P p_h/p0)^z))`; `s = ln η0 + 9.67`,
    /// `p0` in units of `p_h`.
    Roelands { s: f64, z: f64, p0: f64 },
    /// Barus: `η̄ = exp(ᾱ P)`, `ᾱ = α p_h`.
    Barus { alpha_bar: f64 },
    /// Constant viscosity.
    Isoviscous,
}

impl Viscosity {
    #[inline]
    pub fn eta(&self, p: f64) -> f64 {
        let p = p.max(0.0);
        match *self {
            Viscosity::Roelands { s, z, p0 } => (s * (-1.0 + (1.0 + p / p0).powf(z))).exp(),
            Viscosity::Barus { alpha_bar } => (alpha_bar * p).exp(),
            Viscosity::Isoviscous => 1.0,
        }
    }
}

/// Pressure–density law.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
#[serde(rename_all = "kebab-case")]
pub enum Density {
    /// Dowson–Higginson: `ρ̄ = (5.9e8 + 1.34 p) / (5.9e8 + p)`, `p = P p_h` in Pa.
    DowsonHigginson {
        p_h: f64,
    },
    Incompressible,
}

impl Density {
    #[inline]
    pub fn rho(&self, p: f64) -> f64 {
        match *self {
            Density::DowsonHigginson { p_h } => {
                let pp = p.max(0.0) * p_h;
                (5.9e8 + 1.34 * pp) / (5.9e8 + pp)
            }
            Density::Incompressible => 1.0,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn laws_at_zero_and_limits() {
        let r = Viscosity::Roelands { s: (40e-3f64).ln() + 9.67, z: 0.68, p0: 1.96e8 / 0.5e9 };
        assert_eq!(r.eta(0.0), 1.0);
        assert_eq!(Viscosity::Barus { alpha_bar: 10.0 }.eta(0.0), 1.0);
        // Roelands grows more slowly than Barus with the same initial slope at high pressure.
        assert!(r.eta(2.0) > 1e3);
        let d = Density::DowsonHigginson { p_h: 0.5e9 };
        assert_eq!(d.rho(0.0), 1.0);
        assert!((d.rho(1e6) - 1.34).abs() < 1e-3, "tends to 1.34");
    }
}
