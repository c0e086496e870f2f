//! Conditions in SI and the scales derived from them (Hertz, Moes, Roelands).

use serde::{Deserialize, Serialize};
use std::f64::consts::PI;

/// The dry contact of a ball on a flat: what Hertz needs.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Contact {
    /// Ball radius `R` [m].
    pub ball_radius: f64,
    /// Normal load `F` [N].
    pub load: f64,
    /// Reduced modulus `E'` [Pa], with `w = (2/(π E')) ∬ p / |x − x'|`.
    pub reduced_modulus: f64,
}

/// The seed's ball-on-disc contact (Table 1): the reference conditions of tests and examples
/// (the built-in scenes carry the same values as data).
pub const SEED_CONTACT: Contact =
    Contact { ball_radius: 9.525e-3, load: 20.0, reduced_modulus: 1.17e11 };

/// The seed's lubricant (Table 1: HVI60 at 25 °C).
pub const SEED_LUBRICANT: Lubricant =
    Lubricant { eta0: 44.7e-3, alpha: 2.25e-8, p0_roelands: 1.96e8 };

/// Lubricant (or layer damper) viscosity: Roelands' law and the Dowson–Higginson density.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Lubricant {
    /// Viscosity at ambient pressure `η0` [Pa s].
    pub eta0: f64,
    /// Pressure–viscosity coefficient `α` [1/Pa].
    pub alpha: f64,
    /// Roelands pressure constant `p0` [Pa] (1.96e8 Pa in the literature).
    pub p0_roelands: f64,
}

impl Lubricant {
    /// Roelands pressure index `z = α p0 / (ln η0 + 9.67)` [-].
    pub fn roelands_z(&self) -> f64 {
        self.alpha * self.p0_roelands / (self.eta0.ln() + 9.67)
    }
    /// Roelands viscosity `η(p)` [Pa s] at pressure `p` [Pa].
    pub fn roelands(&self, p: f64) -> f64 {
        // The Hertz-unit law with p_h = 1 Pa: pressures in Pa.
        self.eta0 * crate::laws::Viscosity::roelands(self, 1.0).eta(p)
    }
}

/// Hertzian scales of a [`Contact`]: the bridge between SI and the dimensionless solvers.
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
pub struct HertzScales {
    /// Hertz contact radius `a = (3 F R / (2 E'))^(1/3)` [m].
    pub a: f64,
    /// Maximum Hertz pressure `p_h = 3 F / (2 π a²)` [Pa].
    pub p_h: f64,
    /// Hertz approach `δ = a² / R` [m]: the unit of gaps and deformations inside the solvers.
    pub delta: f64,
    /// Ball radius `R` [m].
    pub r: f64,
    /// Load `F` [N].
    pub f: f64,
}

impl HertzScales {
    /// The scales of `c`: `a`, `p_h`, `a²/R`.
    pub fn new(c: &Contact) -> Self {
        let a = (3.0 * c.load * c.ball_radius / (2.0 * c.reduced_modulus)).cbrt();
        let p_h = 3.0 * c.load / (2.0 * PI * a * a);
        Self { a, p_h, delta: a * a / c.ball_radius, r: c.ball_radius, f: c.load }
    }
    /// The load in dimensionless form, `∬ P dX dY = F / (p_h a²) = 2π/3`.
    pub fn load_dimensionless(&self) -> f64 {
        self.f / (self.p_h * self.a * self.a)
    }
    /// Length [m] from `X` [-].
    pub fn x_si(&self, x: f64) -> f64 {
        x * self.a
    }
    /// `X` [-] from a length [m].
    pub fn x_dimless(&self, x: f64) -> f64 {
        x / self.a
    }
    /// Pressure [Pa] from `P` [-].
    pub fn p_si(&self, p: f64) -> f64 {
        p * self.p_h
    }
    /// `P` [-] from a pressure [Pa].
    pub fn p_dimless(&self, p: f64) -> f64 {
        p / self.p_h
    }
    /// Gap or deformation [m] from `H` [-] (units of `a²/R`).
    pub fn h_si(&self, h: f64) -> f64 {
        h * self.delta
    }
    /// `H` [-] from a gap [m].
    pub fn h_dimless(&self, h: f64) -> f64 {
        h / self.delta
    }
}

/// Moes' dimensionless load `M` and material parameter `L` (the Reynolds solver's inputs).
///
/// Defined with the **sum** velocity `u_s = u1 + u2`: `U = η0 u_s / (E' R)`,
/// `M = F / (E' R²) U^(−3/4)`, `L = α E' U^(1/4)`.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
pub struct Moes {
    /// Moes' dimensionless load `M`.
    pub m: f64,
    /// Moes' material parameter `L`.
    pub l: f64,
}

impl Moes {
    /// `M`, `L` from SI conditions; `u_sum` [m/s] is `u1 + u2`.
    pub fn from_si(c: &Contact, lub: &Lubricant, u_sum: f64) -> Self {
        let u = lub.eta0 * u_sum / (c.reduced_modulus * c.ball_radius);
        Self {
            m: c.load / (c.reduced_modulus * c.ball_radius.powi(2)) * u.powf(-0.75),
            l: lub.alpha * c.reduced_modulus * u.powf(0.25),
        }
    }
    /// The other way, for a scene given in Moes parameters: the load `F`, `R`, `E'` and `η0` are
    /// kept, `U` follows from `M` and then `α` from `L`. Returns `(u_sum [m/s], alpha [1/Pa])`.
    pub fn to_velocity_and_alpha(&self, c: &Contact, eta0: f64) -> (f64, f64) {
        let u = (c.load / (c.reduced_modulus * c.ball_radius.powi(2)) / self.m).powf(4.0 / 3.0);
        let u_sum = u * c.reduced_modulus * c.ball_radius / eta0;
        let alpha = self.l / (c.reduced_modulus * u.powf(0.25));
        (u_sum, alpha)
    }
    /// The other way with the lubricant fixed (`R`, `E'`, `η0`, `α` kept): `U` follows from `L`,
    /// then the load from `M`. Returns `(load [N], u_sum [m/s])`.
    pub fn to_load_and_velocity(
        &self,
        radius: f64,
        e_prime: f64,
        eta0: f64,
        alpha: f64,
    ) -> (f64, f64) {
        let u = (self.l / (alpha * e_prime)).powi(4);
        let load = self.m * e_prime * radius * radius * u.powf(0.75);
        (load, u * e_prime * radius / eta0)
    }
    /// Hertzian `λ̄ = (128 π³ / (3 M⁴))^(1/3)` (equals `12 η0 u_m R² / (a³ p_h)` with the mean
    /// velocity `u_m = u_s / 2`).
    pub fn lambda_bar(&self) -> f64 {
        (128.0 * PI.powi(3) / (3.0 * self.m.powi(4))).cbrt()
    }
    /// `ᾱ = α p_h = L / π · (3 M / 2)^(1/3)`.
    pub fn alpha_bar(&self) -> f64 {
        self.l / PI * (1.5 * self.m).cbrt()
    }
}

/// Hertzian `λ̄ = 12 η0 u_m R² / (a³ p_h)` [-] from SI, with the mean velocity `u_m` [m/s].
pub fn lambda_bar_si(c: &Contact, eta0: f64, u_mean: f64) -> f64 {
    let s = HertzScales::new(c);
    12.0 * eta0 * u_mean * c.ball_radius.powi(2) / (s.a.powi(3) * s.p_h)
}

/// Oedometric (constrained) modulus `Eo = E (1 − ν) / ((1 + ν)(1 − 2ν))` [Pa].
pub fn oedometric_modulus(e: f64, nu: f64) -> f64 {
    e * (1.0 - nu) / ((1.0 + nu) * (1.0 - 2.0 * nu))
}

#[cfg(test)]
mod tests {
    use super::*;

    fn table1() -> (Contact, Lubricant) {
        (SEED_CONTACT, SEED_LUBRICANT)
    }

    #[test]
    fn table1_derived_values_match_the_notes() {
        let (c, lub) = table1();
        let s = HertzScales::new(&c);
        // The notes print 4–5 significant figures: compare to their last digit.
        assert!((s.a - 0.13467e-3).abs() < 0.00001e-3, "a = {}", s.a);
        assert!((s.p_h - 0.5265e9).abs() < 0.0001e9, "p_h = {}", s.p_h);
        assert!((lub.roelands_z() - 0.6720).abs() < 1e-4);
        assert!((oedometric_modulus(1e8, 0.3) - 0.1346e9).abs() < 0.0001e9);
        let moes = Moes::from_si(&c, &lub, 0.02);
        assert!((moes.m - 2223.0).abs() < 1.0, "M = {}", moes.m);
        assert!((moes.l - 2.49).abs() < 0.01, "L = {}", moes.l);
        assert!((moes.lambda_bar() - 3.784e-4).abs() < 0.001e-4);
        assert!((moes.alpha_bar() - 11.85).abs() < 0.01);
        assert!((s.load_dimensionless() - 2.0 * PI / 3.0).abs() < 1e-14);
    }

    #[test]
    fn lambda_bar_identity_and_moes_round_trip() {
        let (c, lub) = table1();
        let moes = Moes::from_si(&c, &lub, 0.02);
        let direct = lambda_bar_si(&c, lub.eta0, 0.01);
        assert!((direct / moes.lambda_bar() - 1.0).abs() < 1e-12);
        assert!((moes.alpha_bar() / (lub.alpha * HertzScales::new(&c).p_h) - 1.0).abs() < 1e-12);
        let (u_sum, alpha) = moes.to_velocity_and_alpha(&c, lub.eta0);
        assert!((u_sum / 0.02 - 1.0).abs() < 1e-12);
        assert!((alpha / lub.alpha - 1.0).abs() < 1e-12);
        let (load, u_sum) =
            moes.to_load_and_velocity(c.ball_radius, c.reduced_modulus, lub.eta0, lub.alpha);
        assert!((load / c.load - 1.0).abs() < 1e-12 && (u_sum / 0.02 - 1.0).abs() < 1e-12);
    }

    #[test]
    fn si_conversions_scale_by_a_and_p_h() {
        let s = HertzScales::new(&crate::SEED_CONTACT);
        // a = 0.13466 mm and p_h = 0.52655 GPa for Table 1 (table1_derived_values_match_the_notes).
        assert_eq!(s.x_si(2.0), 2.0 * s.a);
        assert_eq!(s.p_si(0.5), 0.5 * s.p_h);
        assert_eq!(s.h_si(3.0), 3.0 * s.delta);
        for v in [0.3, -1.7] {
            assert!((s.x_dimless(s.x_si(v)) - v).abs() < 1e-15);
            assert!((s.p_dimless(s.p_si(v)) - v).abs() < 1e-15);
            assert!((s.h_dimless(s.h_si(v)) - v).abs() < 1e-15);
        }
    }

    #[test]
    fn roelands_is_eta0_at_zero_pressure() {
        let (_, lub) = table1();
        assert!((lub.roelands(0.0) / lub.eta0 - 1.0).abs() < 1e-14);
        assert!(lub.roelands(1e9) > 1e3 * lub.eta0);
    }
}
