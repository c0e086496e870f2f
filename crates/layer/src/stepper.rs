//! Time integration of the layer, with the contact solved at every stage.
//!
//! Both schemes share the semi-Lagrangian transport ([`crate::transport`]) and differ only in the
//! Kelvin–Voigt relaxation along each material path:
//! - [`Scheme::Explicit`] (the paper's kind): Heun's second-order Runge–Kutta, a contact solve per
//!   stage. Its stability limit comes from the layer: see [`stability_estimate`].
//! - [`Scheme::Implicit`]: variable-step BDF2 (L-stable, second order). With `E` and `η` taken at
//!   the state extrapolated to the new time (second order), the new strain is affine in the new
//!   pressure, `ε = A + B p`, so the layer enters the contact solve as a local compliance
//!   `c = l0 B`. Points where `ε` would pass 1 are fixed at 1 (no layer) and the contact re-solved.

use crate::model::{LayerModel, LayerState};
use crate::transport::{shift, shift_strain};
use ehl_core::{NumericError, Start, check_finite};
use ndarray::{Array2, Zip};
use serde::{Deserialize, Serialize};

/// Time-integration scheme.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize, Default)]
#[serde(rename_all = "kebab-case")]
pub enum Scheme {
    /// Heun (RK2), explicit in the layer, two contact solves per step.
    Explicit,
    /// BDF2 with the layer as a local compliance, one contact solve per step (more where the
    /// layer runs out or with Picard passes).
    #[default]
    Implicit,
}

/// Why a run stopped before its end.
#[derive(Debug, Clone, thiserror::Error, PartialEq)]
pub enum LayerError {
    #[error("at step {step} (t = {t:.6e} s): {source}")]
    /// A contact solve failed inside a step.
    Contact {
        /// The step it failed in (1 the first).
        step: usize,
        /// Time at the end of that step [s].
        t: f64,
        /// The contact solver's diagnosis.
        source: NumericError,
    },
    #[error(
        "explicit stepping is unstable at step {step} (t = {t:.6e} s): the strain at (x = {x:.4} a, y = {y:.4} a) oscillates with growing amplitude ({amplitude:.3e}) for {count} steps; Δt = {dt:.3e} s exceeds the stability limit (estimate {limit:.3e} s). Use a smaller step (more steps per cell) or the implicit scheme."
    )]
    /// The explicit scheme's strain oscillates with growing amplitude: its step is too long.
    Unstable {
        /// The step it was seen at.
        step: usize,
        /// Time [s].
        t: f64,
        /// Where: `x` [a].
        x: f64,
        /// Where: `y` [a].
        y: f64,
        /// The last strain change there.
        amplitude: f64,
        /// Growing sign flips in a row.
        count: usize,
        /// The step [s].
        dt: f64,
        /// The estimated stability limit [s].
        limit: f64,
    },
    #[error(
        "steady solve did not converge at iteration {iteration}: the strain the contact carried and the strain marched from its pressure differ by {residual:.3e} (tolerance {tolerance:.1e}) at (x = {x:.4} a, y = {y:.4} a); {trend}"
    )]
    /// The direct steady solve did not converge.
    Steady {
        /// The iteration it stopped at.
        iteration: usize,
        /// The largest strain difference.
        residual: f64,
        /// The tolerance asked for.
        tolerance: f64,
        /// Where: `x` [a].
        x: f64,
        /// Where: `y` [a].
        y: f64,
        /// What the recent iterations did (stall, slow, cycle) …
        trend: String,
        /// … and that as a kind, for whoever counts failures.
        kind: SteadyFailure,
    },
    #[error("{0}")]
    /// A model that cannot be run as asked (no rolling, a feature in a steady solve).
    Setup(String),
}

/// How a direct steady solve failed to converge.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum SteadyFailure {
    /// No new best mismatch over the stall window, or flat over the last iterations.
    Stalled,
    /// The mismatch grows.
    Diverging,
    /// Still falling (or too few iterations to judge) when the limit came.
    IterationLimit,
}

/// What one step cost, and its error estimate where the scheme gives one.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct StepInfo {
    /// Contact solves.
    pub solves: usize,
    /// Contact iterations, summed over the solves.
    pub iterations: usize,
    /// Estimated local strain error of the step (RMS over the layer's active points).
    pub error_estimate: Option<f64>,
}

/// A past level, for BDF2 and the predictors: strain and pressure, the step that left it, and
/// the cells the layer moved in that step (each level keeps its own shift: with a speed that
/// changes, the past is not `u dt` behind at today's speed).
#[derive(Clone)]
struct Level {
    eps: Array2<f64>,
    p: Array2<f64>,
    dt: f64,
    cells: f64,
}

/// Steps a [`LayerState`]; holds the history the multistep scheme needs.
#[derive(Clone)]
pub struct Stepper {
    /// Explicit or implicit.
    pub scheme: Scheme,
    /// Extra passes re-evaluating `E`, `η` at the new state (implicit scheme).
    pub picard: usize,
    /// Most recent first.
    history: Vec<Level>,
    /// Explicit-instability watch: per point, consecutive growing sign flips of the strain change.
    flips: Option<(Array2<f64>, Array2<u32>)>,
    /// Steps taken.
    pub steps: usize,
    /// Compute the local error estimate (error control); off for fixed steps, it costs shifts.
    pub estimate_error: bool,
}

/// Estimated explicit stability limit [s] (docs/model.md §3.5): a strain perturbation feeds back
/// through the contact with stiffness `E + k l0`, `k = 1 / K(0,0)` the stiffness of one cell,
/// so Heun (like Euler on the real axis) needs `Δt < 2 η / (E + k l0)`, tightest where η is
/// smallest (unloaded inlet, `p → 0`).
pub fn stability_estimate(m: &LayerModel) -> f64 {
    let k = 1.0 / m.solver.operator().self_influence();
    2.0 * m.eta(0.0) / (m.eo + k * m.l0)
}

impl Stepper {
    /// A stepper with no history yet.
    pub fn new(scheme: Scheme, picard: usize) -> Self {
        Self { scheme, picard, history: vec![], flips: None, steps: 0, estimate_error: false }
    }

    /// Forget the history (after a change of motion, e.g. a sudden stop): the next step starts
    /// the multistep scheme afresh.
    pub fn reset(&mut self) {
        self.history.clear();
        self.flips = None;
    }

    /// Advances `s` by `dt` [s].
    pub fn step(
        &mut self,
        m: &LayerModel,
        s: &mut LayerState,
        dt: f64,
    ) -> Result<StepInfo, LayerError> {
        let before = s.eps.clone();
        let info = match self.scheme {
            Scheme::Explicit => self.explicit(m, s, dt),
            Scheme::Implicit => self.implicit(m, s, dt),
        }?;
        self.steps += 1;
        check_finite("strain", &s.eps, self.steps)
            .and_then(|_| check_finite("pressure", &s.p, self.steps))
            .map_err(|e| LayerError::Contact { step: self.steps, t: s.t, source: e })?;
        if self.scheme == Scheme::Explicit {
            self.watch(m, &before, s, dt)?;
        }
        Ok(info)
    }

    /// Pressure extrapolated to the new time from the last two levels (warm start, coefficients).
    fn p_predict(&self, s: &LayerState, dt: f64) -> Array2<f64> {
        match self.history.first() {
            Some(prev) => {
                let om = dt / prev.dt;
                Zip::from(&s.p).and(&prev.p).par_map_collect(|&a, &b| (a + om * (a - b)).max(0.0))
            }
            None => s.p.clone(),
        }
    }

    fn push_history(&mut self, s: &LayerState, dt: f64, cells: f64) {
        self.history.insert(0, Level { eps: s.eps.clone(), p: s.p.clone(), dt, cells });
        self.history.truncate(2);
    }

    fn explicit(
        &mut self,
        m: &LayerModel,
        s: &mut LayerState,
        dt: f64,
    ) -> Result<StepInfo, LayerError> {
        let k = m.cells_in_step(s.t, dt);
        let t1 = s.t + dt;
        let step = self.steps + 1;
        let rate = m.rate_field(&s.p, &s.eps);
        let eps_d = shift_strain(&s.eps, k);
        let rate_d = shift(&rate, k, 0.0);
        let eps_star =
            Zip::from(&eps_d).and(&rate_d).par_map_collect(|&e, &r| (e + dt * r).clamp(0.0, 1.0));
        let ball = m.ball(t1);
        let mut p = self.p_predict(s, dt);
        let mut w = s.w.clone();
        // The contact with the layer of strain `eps` at the new time, from the pressure in `p`.
        let mut solve = |eps: &Array2<f64>, p: &mut Array2<f64>| {
            m.contact(&(&ball - &m.thickness(eps, t1)), None, p, &mut w, Start::Warm)
                .map_err(|e| LayerError::Contact { step, t: t1, source: e })
        };
        let r1 = solve(&eps_star, &mut p)?;
        let rate_star = m.rate_field(&p, &eps_star);
        let eps_new = Zip::from(&eps_d)
            .and(&rate_d)
            .and(&rate_star)
            .par_map_collect(|&e, &r0, &r1| (e + 0.5 * dt * (r0 + r1)).clamp(0.0, 1.0));
        let r2 = solve(&eps_new, &mut p)?;
        // Heun minus Euler: the local error of the Euler stage, a conservative estimate.
        let err = self.estimate_error.then(|| rms_active(&eps_new, &eps_star, &p));
        self.push_history(s, dt, k);
        *s = LayerState { t: t1, eps: eps_new, p, w, h0: r2.h0 };
        Ok(StepInfo { solves: 2, iterations: r1.iterations + r2.iterations, error_estimate: err })
    }

    fn implicit(
        &mut self,
        m: &LayerModel,
        s: &mut LayerState,
        dt: f64,
    ) -> Result<StepInfo, LayerError> {
        let k = m.cells_in_step(s.t, dt);
        let t1 = s.t + dt;
        let step = self.steps + 1;
        let eps_d = shift_strain(&s.eps, k);
        // BDF2 weights for a step ratio ω = dt / dt_prev; BDF1 on the first step.
        let (a0, rhs, eps_pred) = match self.history.first() {
            None => (1.0, eps_d.clone(), eps_d.clone()),
            Some(prev) => {
                let om = dt / prev.dt;
                let eps_dd = shift_strain(&prev.eps, k + prev.cells);
                let rhs = Zip::from(&eps_d)
                    .and(&eps_dd)
                    .par_map_collect(|&e1, &e0| (1.0 + om) * e1 - om * om / (1.0 + om) * e0);
                let pred = Zip::from(&eps_d)
                    .and(&eps_dd)
                    .par_map_collect(|&e1, &e0| (e1 + om * (e1 - e0)).clamp(0.0, 1.0));
                ((1.0 + 2.0 * om) / (1.0 + om), rhs, pred)
            }
        };
        let mut p = self.p_predict(s, dt);
        let mut w = s.w.clone();
        let ball = m.ball(t1);
        let supply = m.supply(t1);
        let (mut solves, mut iterations) = (0, 0);
        let mut coef_p = m.coefficient_pressure(&p);
        let mut coef_eps = eps_pred.clone();
        let mut eps_new;
        let mut h0;
        let mut pass = 0;
        loop {
            // ε = A + B p with E, η frozen at (coef_p, coef_eps).
            let mut a = Array2::zeros(p.dim());
            let mut b = Array2::zeros(p.dim());
            Zip::from(&mut a).and(&mut b).and(&rhs).and(&coef_p).and(&coef_eps).par_for_each(
                |a, b, &r, &pc, &ec| {
                    let eta = m.eta(pc);
                    let d = a0 + dt * m.modulus(pc, ec) / eta;
                    *a = r / d;
                    *b = dt / eta / d;
                },
            );
            let r = m
                .contact_with_affine_layer(
                    &ball,
                    &supply,
                    &a,
                    &b,
                    &mut p,
                    &mut w,
                    Start::Warm,
                    None,
                )
                .map_err(|e| LayerError::Contact { step, t: t1, source: e })?;
            solves += r.solves;
            iterations += r.iterations;
            h0 = r.h0;
            eps_new = r.eps;
            if pass >= self.picard {
                break;
            }
            pass += 1;
            coef_p = m.coefficient_pressure(&p);
            coef_eps = eps_new.clone();
        }
        // Milne's device: quadratic extrapolation along the paths against BDF2; for constant
        // steps BDF2's local error is 2/7 of their difference.
        let err = if self.estimate_error && self.history.len() == 2 {
            let (l1, l2) = (&self.history[0], &self.history[1]);
            let (h, h1, h2) = (dt, l1.dt, l2.dt);
            let e1 = shift_strain(&l1.eps, k + l1.cells);
            let e2 = shift_strain(&l2.eps, k + l1.cells + l2.cells);
            // Nodes at -h, -(h+h1), -(h+h1+h2) relative to the new time; Lagrange weights at 0.
            let (x0, x1, x2) = (-h, -(h + h1), -(h + h1 + h2));
            let w0 = x1 * x2 / ((x0 - x1) * (x0 - x2));
            let w1 = x0 * x2 / ((x1 - x0) * (x1 - x2));
            let w2 = x0 * x1 / ((x2 - x0) * (x2 - x1));
            let pred = Zip::from(&eps_d)
                .and(&e1)
                .and(&e2)
                .par_map_collect(|&a, &b, &c| w0 * a + w1 * b + w2 * c);
            Some(2.0 / 7.0 * rms_active(&eps_new, &pred, &p))
        } else {
            None
        };
        self.push_history(s, dt, k);
        *s = LayerState { t: t1, eps: eps_new, p, w, h0 };
        Ok(StepInfo { solves, iterations, error_estimate: err })
    }

    /// Explicit instability: a point whose strain change flips sign and grows, step after step.
    fn watch(
        &mut self,
        m: &LayerModel,
        before: &Array2<f64>,
        s: &LayerState,
        dt: f64,
    ) -> Result<(), LayerError> {
        let d = s.eps.clone() - before;
        let (prev_d, count) =
            self.flips.get_or_insert_with(|| (Array2::zeros(d.dim()), Array2::zeros(d.dim())));
        Zip::from(&mut *count).and(&d).and(&*prev_d).for_each(|c, &dn, &dp| {
            if dn * dp < 0.0 && dn.abs() > dp.abs() && dn.abs() > 1e-3 {
                *c += 1;
            } else {
                *c = 0;
            }
        });
        *prev_d = d;
        const LIMIT: u32 = 4;
        if let Some(((j, i), &c)) = count.indexed_iter().find(|(_, c)| **c >= LIMIT) {
            return Err(LayerError::Unstable {
                step: self.steps,
                t: s.t,
                x: m.grid.x(i),
                y: m.grid.y(j),
                amplitude: prev_d[[j, i]].abs(),
                count: c as usize,
                dt,
                limit: stability_estimate(m),
            });
        }
        Ok(())
    }
}

/// RMS of `a − b` over the points where the layer is active (loaded, or strained).
fn rms_active(a: &Array2<f64>, b: &Array2<f64>, p: &Array2<f64>) -> f64 {
    let (mut s, mut n) = (0.0, 0usize);
    Zip::from(a).and(b).and(p).for_each(|&a, &b, &p| {
        if p > 0.0 || a > 1e-9 {
            s += (a - b).powi(2);
            n += 1;
        }
    });
    if n == 0 { 0.0 } else { (s / n as f64).sqrt() }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn error_rms_counts_only_where_the_layer_is_active() {
        // Loaded (the first, unstrained at the new state), or strained (the second): those two;
        // the third is neither and does not dilute.
        let a = ndarray::arr2(&[[0.0, 0.2, 0.0]]);
        let b = ndarray::arr2(&[[0.3, 0.0, 0.0]]);
        let p = ndarray::arr2(&[[1.0, 0.0, 0.0]]);
        let want = ((0.09 + 0.04) / 2.0f64).sqrt();
        assert!((rms_active(&a, &b, &p) - want).abs() < 1e-15);
        assert_eq!(rms_active(&b, &b, &b), 0.0);
    }

    /// Feeds the watch a history of strain changes at one point of a 9² grid; returns the step
    /// it fired at (1-based), if any.
    fn watch_fires(changes: &[f64]) -> Option<(usize, LayerError)> {
        let (c, l) = (ehl_core::SEED_CONTACT, ehl_core::SEED_LUBRICANT);
        let grid = ehl_core::Grid::square(9, 1.25);
        let m = LayerModel::new(
            &c,
            &l,
            &crate::SEED_LAYER,
            crate::SEED_SUPPLY_THICKNESS_M,
            ehl_core::Kinematics::constant(0.01).unwrap(),
            grid,
            ehl_core::DrySettings::default(),
        )
        .unwrap();
        let mut st = Stepper::new(Scheme::Explicit, 0);
        let mut s = LayerState {
            t: 0.0,
            eps: m.grid.zeros(),
            p: m.grid.zeros(),
            w: m.grid.zeros(),
            h0: 0.0,
        };
        for (k, &d) in changes.iter().enumerate() {
            let before = s.eps.clone();
            s.eps[[2, 6]] += d;
            st.steps = k + 1;
            if let Err(e) = st.watch(&m, &before, &s, 1e-6) {
                return Some((k + 1, e));
            }
        }
        None
    }

    #[test]
    fn the_watch_fires_on_a_growing_flip_only() {
        // Four flips in a row, each larger than the last and above 1e-3: diagnosed at the fifth
        // change (the first has nothing to flip against) with the point's place and amplitude.
        let (k, e) = watch_fires(&[0.01, -0.02, 0.04, -0.08, 0.16]).expect("a growing flip");
        assert_eq!(k, 5);
        let x6 = ehl_core::Grid::square(9, 1.25).x(6);
        assert!(
            matches!(e, LayerError::Unstable { step: 5, count: 4, x, amplitude, .. }
                if x == x6 && amplitude == 0.16),
            "{e:?}"
        );
        // A decaying oscillation, one of constant amplitude, a steady growth without flips, a
        // flip series interrupted by a change of the same sign or started from no change (a
        // sign test by quotient would count that), and flips below 1e-3 are not instabilities.
        assert!(watch_fires(&[0.16, -0.08, 0.04, -0.02, 0.01, -0.005]).is_none());
        assert!(watch_fires(&[0.25, -0.25, 0.25, -0.25, 0.25, -0.25]).is_none());
        assert!(watch_fires(&[0.0, -0.02, 0.04, -0.08, 0.16]).is_none());
        assert!(watch_fires(&[0.01, 0.02, 0.04, 0.08, 0.16]).is_none());
        assert!(watch_fires(&[0.01, -0.02, 0.04, 0.08, -0.16, 0.32, -0.64]).is_none());
        assert!(watch_fires(&[1e-5, -2e-5, 4e-5, -8e-5, 1.6e-4, -3.2e-4]).is_none());
    }
}
