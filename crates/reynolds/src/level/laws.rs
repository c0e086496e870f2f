//! The laws' cache: viscosity and density at each point, followed at once or lagged.

use super::*;

/// The laws' entry at pressure `p` [p_h]: `[P, η̄ λ̄, ρ̄]`.
#[inline]
pub(super) fn laws_at(prm: &ReynoldsParams, p: f64) -> [f64; 3] {
    [p, prm.viscosity.eta(p) * prm.lambda_bar, prm.density.rho(p)]
}

impl Level {
    /// Lagged laws follow `theta` of each point's pressure change since they were evaluated
    /// (all of it once within rounding of the pressure, so that a converged state's laws are
    /// its own, bit for bit).
    pub(super) fn follow_laws(&mut self, prm: &ReynoldsParams, theta: f64) {
        let at = |c: &mut [f64; 3], &p: &f64| {
            let pc = if !c[0].is_finite() || (p - c[0]).abs() <= 1e-12 * p.abs().max(1e-3) {
                p
            } else {
                c[0] + theta * (p - c[0])
            };
            if pc.to_bits() != c[0].to_bits() {
                *c = laws_at(prm, pc);
            }
        };
        let zip = Zip::from(&mut self.laws).and(&self.p);
        if self.p.len() >= ehl_core::PAR_MIN_WORK { zip.par_for_each(at) } else { zip.for_each(at) }
    }

    /// Whether the laws lag the pressures.
    pub fn lagged(&self) -> bool {
        self.lagged
    }

    /// The pressure each point's laws are evaluated at: what a coarser grid's lagged laws
    /// start from.
    pub fn coefficient_pressures(&self) -> Array2<f64> {
        Zip::from(&self.p)
            .and(&self.laws)
            .map_collect(|&p, c| if self.lagged && c[0].is_finite() { c[0] } else { p })
    }

    /// Evaluates the laws at the coefficient pressures `pc` (a finer grid's, injected), to be
    /// held while they lag.
    pub fn set_coefficient_pressures(&mut self, prm: &ReynoldsParams, pc: &Array2<f64>) {
        self.laws_for(prm);
        self.lagged = true;
        Zip::from(&mut self.laws).and(pc).for_each(|c, &pc| *c = laws_at(prm, pc));
    }

    /// Back to an empty state (no pressure, film, right-hand side, history or laws), the rigid
    /// film kept.
    pub fn reset(&mut self) {
        for a in [&mut self.p, &mut self.film, &mut self.rhs, &mut self.history] {
            a.fill(0.0);
        }
        self.theta.fill(1.0);
        self.contact.fill(false);
        self.set_inflow_theta();
        self.time_a0 = 0.0;
        self.laws.fill([f64::NAN; 3]);
        self.laws_for = None;
        self.lagged = false;
    }

    /// Makes the law cache hold values of `prm`'s laws (emptied when they differ).
    pub(super) fn laws_for(&mut self, prm: &ReynoldsParams) {
        let key = Some((prm.lambda_bar, prm.viscosity, prm.density));
        if self.laws_for != key {
            self.laws.fill([f64::NAN; 3]);
            self.laws_for = key;
        }
    }
}
