//! The line relaxation's settings: where it switches between Gauss–Seidel and distributive
//! changes, and how much of each change it takes.

/// Relaxation controls.
#[derive(Clone, Copy, Debug, PartialEq, serde::Serialize, serde::Deserialize)]
#[serde(deny_unknown_fields, default)]
pub struct RelaxSettings {
    /// Points where (Poiseuille diagonal) / (wedge diagonal) falls below this relax
    /// distributively …
    pub distributive_threshold: f64,
    /// … and the time term's part of that diagonal (its elastic self-coupling `a0 ρ̄ K(0, 0)`,
    /// zero in a steady solve) counts with this threshold instead: counted at the steady
    /// threshold, Gauss–Seidel steps where the time term rivals the Poiseuille one made the
    /// V-cycle amplify the residual. `None` (the default): the finest grid's choice,
    /// [`RelaxSettings::transient_threshold_for`].
    pub transient_threshold: Option<f64>,
    /// … and at rest (no wedge term: the time term's coupling is the whole of it) with this
    /// one. At rest the coupling falls as the step grows (`a0 = 1/ΔT`), and points where it is
    /// still a fifth of the Poiseuille term cycle with Gauss–Seidel steps at the threshold of 1;
    /// a larger one lets the steps grow, at the price of a slower contraction per cycle. The
    /// default stays 1 because a restart after a long rest fails at its first rolling step at 3;
    /// `stop-compare`, which never rolls again, sets 3 (docs/decisions.md, "Steps at rest").
    pub transient_threshold_at_rest: f64,
    /// Under-relaxation of Gauss–Seidel changes: small enough that the outlet pressure spike
    /// keeps no limit cycle on fine grids (docs/decisions.md, "Three changes that made the
    /// steady cycles converge").
    pub omega_gs: f64,
    /// Under-relaxation of distributive changes.
    pub omega_jd: f64,
    /// Lagged laws: 0 (the default), the viscosity and density follow each pressure at once,
    /// also within a sweep; `θ` in (0, 1], they are held through a sweep and then follow `θ`
    /// of each point's pressure change (at convergence both are the same). The line Jacobian
    /// holds `ε̄` fixed, and where `η̄` rises steeply with `P` (high `L`, light loads) a
    /// checkerboard of a few tenths of `p_h` changes `ε̄` by orders of magnitude. Slower where
    /// not needed, hence a second attempt's setting
    /// ([`crate::ReynoldsSettings::fallback_lag`]; docs/decisions.md, "Why `L = 20` failed").
    pub coefficient_lag: f64,
    /// Mass conserving: passes of line relaxation, after each sweep, over windows of each row
    /// around the boundaries between full and partly filled gap (the menisci), which the row
    /// sweeps move a cell at a time (docs/decisions.md, "Passes around the menisci").
    pub meniscus_passes: usize,
    /// Mass conserving: after each sweep, a pass of line relaxation along the columns
    /// (the column pass, `relax_columns`, says why).
    pub column_pass: bool,
    /// Under-relaxation of the gap's changes where the solids touch. The line solve sees the
    /// elastic response of the line's nearest five points only, less than the whole line's.
    pub omega_contact: f64,
    /// Mass conserving: points whose Poiseuille diagonal exceeds this many times the wedge's
    /// take full Gauss–Seidel steps (0: none).
    pub poiseuille_full_step: f64,
}

impl RelaxSettings {
    /// Range checks, each naming its field: thresholds and factors where the relaxation they
    /// steer can converge, pass counts that end.
    pub fn check(&self) -> Result<(), ehl_core::FieldError> {
        use ehl_core::check::{above, count, within};
        within(
            "distributive_threshold",
            self.distributive_threshold,
            0.0,
            1000.0,
            "Poiseuille over wedge diagonal",
        )?;
        if let Some(t) = self.transient_threshold {
            above(
                "transient_threshold",
                t,
                0.0,
                1000.0,
                "times the time term's elastic self-coupling",
            )?;
        }
        above(
            "transient_threshold_at_rest",
            self.transient_threshold_at_rest,
            0.0,
            1000.0,
            "times the time term's elastic self-coupling",
        )?;
        above("omega_gs", self.omega_gs, 0.0, 1.5, "Gauss-Seidel under-relaxation")?;
        above("omega_jd", self.omega_jd, 0.0, 1.5, "distributive under-relaxation")?;
        within("coefficient_lag", self.coefficient_lag, 0.0, 1.0, "0: laws follow at once")?;
        count("meniscus_passes", self.meniscus_passes, 0, 32, "passes")?;
        above(
            "omega_contact",
            self.omega_contact,
            0.0,
            1.5,
            "under-relaxation where the solids touch",
        )?;
        within("poiseuille_full_step", self.poiseuille_full_step, 0.0, 1e6, "0: none")
    }
}

/// The time term's threshold in a rolling step's relaxation switch, by the finest grid: from
/// so many points per side on, this threshold (1 below the first). At one step a cell the time
/// term's self-coupling `a0 K(0, 0)` stays the same on every grid while the Poiseuille diagonal
/// grows as `1/h²`, so the threshold that keeps the time term's points distributive grows
/// fourfold each time the cells halve, from 1025 points on as measured (docs/decisions.md, "The
/// time term in the relaxation switch").
pub const TRANSIENT_THRESHOLDS: [(usize, f64); 3] = [(257, 4.0), (1025, 16.0), (2049, 64.0)];

impl RelaxSettings {
    /// The time term's threshold in a rolling step on a finest grid of `points` per side: the
    /// one set, else [`TRANSIENT_THRESHOLDS`]. Measured on the seed's contact over
    /// `[−1.25, 1.25]²` (docs/decisions.md, "The time term in the relaxation switch"): at 1 a
    /// march on 513² diverges within five steps at one step a cell and the flooded wave's fails
    /// its first at four, and 257² fails the wave's first step at 0.3 and 1 m/s; at 4 all of
    /// them go, and 257²'s dent march costs the same; 1025² diverges at its fourth step at 4
    /// and goes at 16, 2049² fails its fifth at 16 and goes at 64. Below 257², 4 fails: the
    /// wave's first step on 65² and the first rolling step after a squeezed rest on 129².
    pub fn transient_threshold_for(&self, points: usize) -> f64 {
        self.transient_threshold.unwrap_or_else(|| {
            TRANSIENT_THRESHOLDS.iter().rev().find(|(from, _)| points >= *from).map_or(1.0, |t| t.1)
        })
    }
}

impl Default for RelaxSettings {
    fn default() -> Self {
        Self {
            distributive_threshold: 0.3,
            transient_threshold: None,
            transient_threshold_at_rest: 1.0,
            omega_gs: 0.4,
            omega_jd: 0.3,
            coefficient_lag: 0.0,
            meniscus_passes: 4,
            column_pass: true,
            omega_contact: 0.7,
            poiseuille_full_step: 30.0,
        }
    }
}
