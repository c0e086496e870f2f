//! The Reynolds problem's dimensionless parameters, from SI conditions or from Moes' `M`, `L`.

use crate::laws::{Density, Viscosity};
use ehl_core::{Contact, HertzScales, Lubricant, Moes};
use serde::Serialize;

/// Which laws a scene asks for.
#[derive(Clone, Copy, Debug, PartialEq, Eq, serde::Deserialize, Serialize, Default)]
#[serde(rename_all = "kebab-case")]
pub enum ViscosityLaw {
    #[default]
    /// Roelands' law.
    Roelands,
    /// Barus' law, with Roelands' slope at ambient pressure.
    Barus,
    /// Constant viscosity.
    Isoviscous,
}

#[derive(Clone, Copy, Debug, PartialEq, Eq, serde::Deserialize, Serialize, Default)]
#[serde(rename_all = "kebab-case")]
/// Which pressure–density law the fluid follows.
pub enum DensityLaw {
    #[default]
    /// Dowson–Higginson.
    DowsonHigginson,
    /// Constant density.
    Incompressible,
}

/// Everything the dimensionless Reynolds equation needs.
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
pub struct ReynoldsParams {
    /// Hertz scales of the contact.
    pub scales: HertzScales,
    /// Moes' `M`, `L`.
    pub moes: Moes,
    /// `λ̄ = 12 η0 u_m R² / (a³ p_h)`, `u_m` the mean velocity.
    pub lambda_bar: f64,
    /// The viscosity law in Hertz units.
    pub viscosity: Viscosity,
    /// The density law in Hertz units.
    pub density: Density,
}

impl ReynoldsParams {
    /// From SI: `u_sum = u1 + u2` [m/s].
    pub fn from_si(
        c: &Contact,
        lub: &Lubricant,
        u_sum: f64,
        visc: ViscosityLaw,
        dens: DensityLaw,
    ) -> Self {
        let scales = HertzScales::new(c);
        let moes = Moes::from_si(c, lub, u_sum);
        let viscosity = match visc {
            ViscosityLaw::Roelands => Viscosity::roelands(lub, scales.p_h),
            ViscosityLaw::Barus => Viscosity::Barus { alpha_bar: lub.alpha * scales.p_h },
            ViscosityLaw::Isoviscous => Viscosity::Isoviscous,
        };
        let density = match dens {
            DensityLaw::DowsonHigginson => Density::DowsonHigginson { p_h: scales.p_h },
            DensityLaw::Incompressible => Density::Incompressible,
        };
        Self { scales, moes, lambda_bar: moes.lambda_bar(), viscosity, density }
    }
}

impl ReynoldsParams {
    /// From Moes' `M`, `L`, keeping the load, `R`, `E'` and `η0` of `c`, `eta0`: the sum
    /// velocity follows from `M`, `α` from `L` (see [`Moes::to_velocity_and_alpha`]).
    pub fn from_moes(
        moes: &Moes,
        c: &Contact,
        eta0: f64,
        p0_roelands: f64,
        visc: ViscosityLaw,
        dens: DensityLaw,
    ) -> Self {
        let (u_sum, alpha) = moes.to_velocity_and_alpha(c, eta0);
        let lub = Lubricant { eta0, alpha, p0_roelands };
        Self::from_si(c, &lub, u_sum, visc, dens)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn seed_conditions_give_the_notes_values() {
        let c = ehl_core::SEED_CONTACT;
        let lub = ehl_core::SEED_LUBRICANT;
        let p = ReynoldsParams::from_si(
            &c,
            &lub,
            0.02,
            ViscosityLaw::Roelands,
            DensityLaw::DowsonHigginson,
        );
        assert!((p.lambda_bar - 3.784e-4).abs() < 0.001e-4);
        assert!((p.moes.m - 2223.0).abs() < 1.0);
    }
}
