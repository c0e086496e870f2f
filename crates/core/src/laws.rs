//! Lubricant laws in Hertz units (pressures in `p_h`): viscosity `η̄ = η/η0` and density
//! `ρ̄ = ρ/ρ0` as functions of `P`. Written once: the Reynolds solver's fluid and the layer
//! model's Roelands-shaped damper evaluate the same functions.

use serde::{Deserialize, Serialize};

/// Pressure–viscosity law.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
#[serde(rename_all = "kebab-case")]
pub enum Viscosity {
    /// Roelands: `η̄ = exp((ln η0 + 9.67)(−1 + (1 + P p_h/p0)^z))`; `s = ln η0 + 9.67`,
    /// `p0` in units of `p_h`.
    Roelands {
        /// `ln η0 + 9.67` (η0 in Pa s).
        s: f64,
        /// The Roelands index `z`.
        z: f64,
        /// The Roelands pressure `p0` [p_h].
        p0: f64,
    },
    /// Barus: `η̄ = exp(ᾱ P)`, `ᾱ = α p_h`.
    Barus {
        /// `ᾱ = α p_h`.
        alpha_bar: f64,
    },
    /// Constant viscosity.
    Isoviscous,
}

impl Viscosity {
    /// Roelands for `lub` with pressures in units of `p_h` [Pa].
    pub fn roelands(lub: &crate::Lubricant, p_h: f64) -> Self {
        Viscosity::Roelands {
            s: lub.eta0.ln() + 9.67,
            z: lub.roelands_z(),
            p0: lub.p0_roelands / p_h,
        }
    }

    /// `η / η0` at `P` [p_h]; negative (cavitated) pressures read as zero.
    #[inline]
    pub fn eta(&self, p: f64) -> f64 {
        let p = p.max(0.0);
        match *self {
            Viscosity::Roelands { s, z, p0 } => (s * (-1.0 + (1.0 + p / p0).powf(z))).exp(),
            Viscosity::Barus { alpha_bar } => (alpha_bar * p).exp(),
            Viscosity::Isoviscous => 1.0,
        }
    }

    /// `ln(η / η0)` at `P` [p_h], without the round trip through `exp`: where only the
    /// logarithm is needed (the layer's sub-steps interpolate it) this saves an `exp` and a
    /// `ln` per point and cannot overflow.
    #[inline]
    pub fn ln_eta(&self, p: f64) -> f64 {
        let p = p.max(0.0);
        match *self {
            Viscosity::Roelands { s, z, p0 } => s * (-1.0 + (1.0 + p / p0).powf(z)),
            Viscosity::Barus { alpha_bar } => alpha_bar * p,
            Viscosity::Isoviscous => 0.0,
        }
    }
}

/// Pressure–density law.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
#[serde(rename_all = "kebab-case")]
pub enum Density {
    /// Dowson–Higginson: `ρ̄ = (5.9e8 + 1.34 p) / (5.9e8 + p)`, `p = P p_h` in Pa.
    DowsonHigginson {
        /// The Hertz pressure [Pa] that `P` is in units of.
        p_h: f64,
    },
    /// Constant density.
    Incompressible,
}

impl Density {
    #[inline]
    /// `ρ̄` at pressure `p` [p_h].
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
    fn laws_against_hand_computed_values() {
        // References computed by hand (Python, 17 digits) from the published forms, not from
        // this code: Roelands with η0 = 40 mPa s, z = 0.68, p0 = 0.196 GPa at P = 2, p_h = 0.5 GPa
        // is exp(6.45112 (−1 + 6.10204^0.68)) = 6.0565274e6; Barus exp(10 · 0.3) = 20.085537;
        // Dowson–Higginson at 1 GPa (5.9e8 + 1.34e9)/(5.9e8 + 1e9) = 1.2138365. Relative 1e-7: the
        // references' printed digits.
        let r = Viscosity::Roelands { s: (40e-3f64).ln() + 9.67, z: 0.68, p0: 1.96e8 / 0.5e9 };
        let rel = |a: f64, b: f64| (a / b - 1.0).abs();
        assert!(rel(r.eta(2.0), 6.0565274e6) < 1e-7, "{}", r.eta(2.0));
        assert_eq!(r.eta(0.0), 1.0);
        // Cavitated (negative) pressures read as zero.
        assert_eq!(r.eta(-1.0), 1.0);
        let b = Viscosity::Barus { alpha_bar: 10.0 };
        assert!(rel(b.eta(0.3), 20.085537) < 1e-7, "{}", b.eta(0.3));
        assert_eq!(Viscosity::Isoviscous.eta(3.0), 1.0);
        let d = Density::DowsonHigginson { p_h: 0.5e9 };
        assert!(rel(d.rho(2.0), 1.2138365) < 1e-7, "{}", d.rho(2.0));
        assert_eq!(d.rho(-1.0), 1.0);
        assert_eq!(Density::Incompressible.rho(2.0), 1.0);
        // The logarithms: ln 6.0565274e6 = 15.6166472 and ln 20.085537 = 3 (by hand), the
        // iso-viscous 0, negative pressures as zero.
        assert!((r.ln_eta(2.0) - 15.6166472).abs() < 1e-7, "{}", r.ln_eta(2.0));
        assert_eq!(r.ln_eta(-1.0), 0.0);
        assert!((b.ln_eta(0.3) - 3.0).abs() < 1e-15);
        assert_eq!(Viscosity::Isoviscous.ln_eta(3.0), 0.0);
    }
}
