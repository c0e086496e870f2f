//! The layer's material laws: the modulus `E(p, ε)` (paper Eq. 10) and the damper viscosity
//! `η(p)` (paper Eq. 11). Both equations were lost from the paper's text; what is here is the
//! reconstruction of docs/model.md §3.3, with its alternatives as named variants.
//! All pressures and moduli in units of `p_h`; viscosities as `η / p_h` [s].

use serde::{Deserialize, Serialize};

/// `E(p, ε)`. Every variant satisfies what the paper's text fixes: `E = Eo` for `p ≤ Eo`
/// (steady strain `p/Eo`), and `E → p` as `ε → 1` (the strain never passes 1).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize, Default)]
#[serde(rename_all = "kebab-case")]
pub enum ModulusLaw {
    /// Default reconstruction: `E = Eo + max(p − Eo, 0) ε^m`, `m = p_ref / Eo`.
    #[default]
    Power,
    /// The same with `m = 1`.
    PowerLinear,
    /// `E = max(Eo, Eo^(1−ε^m) p^(ε^m))`, `m = p_ref / Eo`: geometric interpolation.
    Geometric,
}

impl ModulusLaw {
    /// `E / p_h` at pressure `p` [p_h], strain `eps`, oedometric modulus `eo` [p_h] and
    /// reference pressure `p_ref` [p_h].
    #[inline]
    pub fn modulus(self, p: f64, eps: f64, eo: f64, p_ref: f64) -> f64 {
        if p <= eo {
            return eo;
        }
        let eps = eps.clamp(0.0, 1.0);
        match self {
            ModulusLaw::Power => eo + (p - eo).max(0.0) * eps.powf(p_ref / eo),
            ModulusLaw::PowerLinear => eo + (p - eo).max(0.0) * eps,
            ModulusLaw::Geometric => {
                if p <= eo {
                    eo
                } else {
                    let s = eps.powf(p_ref / eo);
                    eo.powf(1.0 - s) * p.powf(s)
                }
            }
        }
    }
}

/// Which law parameters a layer uses.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize, Default)]
#[serde(rename_all = "kebab-case")]
pub enum LawSet {
    /// The scene's own `damper_constant`, `damper_pressure_scale` and `reference_pressure_pa`
    /// (defaults: docs/model.md §3.3).
    #[default]
    Reconstruction,
    /// The damper prefactor, its pressure scale and the modulus law's reference pressure
    /// identified from the seed's reported numbers by `cargo xtask identify`
    /// (`reference/seed-fit.json`, its `laws` entry).
    SeedFit,
}

/// The damper and modulus parameters a model uses, after its law set is applied.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct LawParameters {
    /// κ: the damper's prefactor over `η0` (factor reading).
    pub damper_constant: f64,
    /// σ: the scale of the damper's Roelands exponent.
    pub damper_pressure_scale: f64,
    /// `p_ref / p_h` of the modulus law (exponent `m = p_ref / Eo`).
    pub reference_pressure_over_p_h: f64,
}

/// The `seed-fit` law parameters: read once from `reference/seed-fit.json` (compiled in), the
/// file `cargo xtask identify` writes, so the code and the recorded fit cannot drift apart.
pub fn seed_fit() -> LawParameters {
    static FIT: std::sync::OnceLock<LawParameters> = std::sync::OnceLock::new();
    *FIT.get_or_init(|| {
        let v: serde_json::Value =
            serde_json::from_str(include_str!("../../../reference/seed-fit.json"))
                .expect("reference/seed-fit.json is valid JSON");
        serde_json::from_value(v["laws"].clone())
            .expect("reference/seed-fit.json has a `laws` entry of law parameters")
    })
}

/// How Table 1's damper constant "5.5e5 Pa s" is read (docs/model.md §3.3).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize, Default)]
#[serde(rename_all = "kebab-case")]
pub enum DamperReading {
    /// `η = κ η0 exp((ln η0 + 9.67)(−1 + (1 + p/p0)^z))`, κ dimensionless ("for κ = 1 this is
    /// Roelands"). The default: it reproduces the paper's compression and squeeze timing.
    #[default]
    Factor,
    /// `η = κ exp(…)` with κ in Pa s replacing `κ η0`: a ~22× stiffer damper for the seed.
    Literal,
}

/// The damper viscosity law, Roelands-shaped, ready to evaluate in Hertz units.
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
pub struct Damper {
    /// Prefactor `η(0) / p_h` [s]: `κ η0 / p_h` or `κ / p_h` by the reading.
    pub eta_zero: f64,
    /// Its pressure dependence: the lubricant's Roelands law (the core's), pressures in `p_h`.
    pub shape: ehl_core::laws::Viscosity,
}

impl Damper {
    /// `η / p_h` [s] at pressure `p` [p_h].
    #[inline]
    pub fn eta(&self, p: f64) -> f64 {
        self.eta_zero * self.shape.eta(p)
    }
    /// `ln(η / p_h)` [ln s] at pressure `p` [p_h].
    #[inline]
    pub fn ln_eta(&self, p: f64) -> f64 {
        self.eta_zero.ln() + self.shape.ln_eta(p)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn modulus_laws_at_a_hand_computed_point() {
        // Eo = 0.25, p_ref = 1, p = 0.5, eps = 0.5: the exponent is p_ref/Eo = 4, eps^4 = 0.0625.
        // Power: 0.25 + 0.25 * 0.0625 = 0.265625; geometric: 0.25^0.9375 * 0.5^0.0625 =
        // 0.26106845 (by hand, Python); power-linear: 0.25 + 0.25 * 0.5 = 0.375.
        let e = |law: ModulusLaw| law.modulus(0.5, 0.5, 0.25, 1.0);
        assert!((e(ModulusLaw::Power) - 0.265625).abs() < 1e-15);
        assert!((e(ModulusLaw::Geometric) - 0.26106845).abs() < 1e-8);
        assert!((e(ModulusLaw::PowerLinear) - 0.375).abs() < 1e-15);
    }

    #[test]
    fn modulus_laws_meet_the_papers_constraints() {
        let (eo, p_ref) = (0.2557, 1.0); // Eo/p_h for the seed: 0.1346 / 0.5265
        for law in [ModulusLaw::Power, ModulusLaw::PowerLinear, ModulusLaw::Geometric] {
            // E = Eo for p <= Eo, whatever the strain.
            for eps in [0.0, 0.3, 1.0] {
                assert_eq!(law.modulus(0.2, eps, eo, p_ref), eo, "{law:?}");
            }
            // E -> p as eps -> 1, and E = Eo at eps = 0.
            for p in [0.3, 1.0, 1.5] {
                assert!((law.modulus(p, 1.0, eo, p_ref) - p).abs() < 1e-12, "{law:?}");
                assert!((law.modulus(p, 0.0, eo, p_ref) - eo).abs() < 1e-12, "{law:?}");
                // Monotone in strain: the layer stiffens as it is compressed.
                assert!(law.modulus(p, 0.6, eo, p_ref) <= law.modulus(p, 0.7, eo, p_ref));
            }
        }
    }

    #[test]
    fn steady_strain_never_exceeds_one() {
        // E(p, eps) eps = p has no root below 1 for p > Eo: the strain rises towards 1.
        let (eo, p_ref) = (0.2557, 1.0);
        for law in [ModulusLaw::Power, ModulusLaw::PowerLinear, ModulusLaw::Geometric] {
            for k in 0..100 {
                let eps = k as f64 / 100.0;
                assert!(law.modulus(0.8, eps, eo, p_ref) * eps < 0.8, "{law:?} at {eps}");
            }
        }
    }
}
