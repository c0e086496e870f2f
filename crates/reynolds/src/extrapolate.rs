//! A mass-conserving solve's slow mode, extrapolated.
//!
//! Fed a supply comparable to the film it needs, the steady solve's last error is one mode: the
//! ring of full film around the contact (its meniscus from the inlet round to the sides, where
//! Poiseuille flow governs) and the pressure inside it move together, and each cycle takes the
//! same small fraction off them. Coarse grids that hold the film content cannot move that ring;
//! the fine relaxation moves it by the oil the ring is short of, a little each sweep, and more
//! passes or sweeps do not change that rate. A steady solve's first attempt lets the coarse
//! grids that hold the film solve for the film content
//! ([`crate::ReynoldsSettings::coarse_film_content`]), and they move the ring; the jumps remain
//! for the attempts after a failed first one, for the start from the flooded answer, and for
//! solves with that setting off.
//!
//! A fixed-point iteration whose error is one mode `e` with `e_(k+1) = g e_k` changes its state
//! by `Δ_(k+1) = g Δ_k`, and its limit is `x_k + Δ_k g / (1 − g)` (Aitken's Δ² applied to the
//! whole state along the mode). When two successive changes of the pressure point the same way
//! (cosine ≥ [`MIN_COSINE`]) and their ratio `g` has held (to [`RATIO_DRIFT`] over three
//! cycles), the pressure, the film content and `H00` are moved along the last change by
//! `g / (1 − g)`, at most `cap` (pressures kept non-negative, film contents in `[0, 1]` and
//! full where the gap is loaded); the cycles then go on from there. A jump after which the
//! residual grows tenfold is undone, and the solve goes on without jumps. What it measured,
//! the cap's choice, and Anderson acceleration set aside in its place: `docs/decisions.md`,
//! "Jumps along the fed solve's slow mode" and "Anderson acceleration of the fed cycles".

use crate::level::Level;
use ndarray::{Array2, Zip};

/// The least cosine between successive pressure changes for one mode to be taken as governing.
pub const MIN_COSINE: f64 = 0.95;
/// How much the ratio of successive changes may drift from cycle to cycle (over the last three)
/// for the mode to be taken as settled.
pub const RATIO_DRIFT: f64 = 0.02;
/// The ratios for which a jump is worth taking: below, the cycles converge fast anyway; above,
/// the factor `g / (1 − g)` is too large to trust.
pub const RATIO_RANGE: (f64, f64) = (0.7, 0.995);
/// A jump is undone when the next cycle's residual exceeds the one before the jump this many
/// times.
pub const UNDO_GROWTH: f64 = 10.0;

/// One state of the iteration: pressure, film content, `H00`.
struct State {
    p: Array2<f64>,
    theta: Array2<f64>,
    h00: f64,
}

impl State {
    fn of(level: &Level, h00: f64) -> Self {
        Self { p: level.p.clone(), theta: level.theta.clone(), h00 }
    }
}

/// The slow-mode watch of one grid's cycles (see the module's documentation).
pub struct ModeExtrapolation {
    /// The largest factor of a jump (0: never jump).
    cap: f64,
    /// The state after the last cycle and the pressure change that led to it.
    last: Option<(State, Option<Array2<f64>>)>,
    /// Ratios `|Δ_(k+1)| / |Δ_k|` since the last jump.
    ratios: Vec<f64>,
    /// The state before the last jump and the residual there, until the next cycle has judged it.
    undo: Option<(State, f64)>,
    /// Jumps taken (and kept).
    pub jumps: usize,
}

impl ModeExtrapolation {
    /// A watch that jumps by at most `cap` times the last change (0: off).
    pub fn new(cap: f64) -> Self {
        Self { cap, last: None, ratios: Vec::new(), undo: None, jumps: 0 }
    }

    /// After a cycle on `level` whose RMS residual was `residual`: judge the last jump, then
    /// record the state and jump when one mode governs. Returns the new `H00` and whether the
    /// state moved (a jump taken or undone): the cycle's record then no longer describes it, and
    /// the caller must not stop on it.
    pub fn after_cycle(&mut self, level: &mut Level, h00: f64, residual: f64) -> (f64, bool) {
        if self.cap <= 0.0 || !level.mass_conserving() {
            return (h00, false);
        }
        if let Some((before, r0)) = self.undo.take()
            && residual > UNDO_GROWTH * r0
        {
            // The jump made things worse: back to where it started, and no more jumps.
            level.p = before.p;
            level.theta = before.theta;
            level.update_film(before.h00);
            self.cap = 0.0;
            self.jumps -= 1;
            return (before.h00, true);
        }
        let now = State::of(level, h00);
        let Some((prev, prev_change)) = self.last.take() else {
            self.last = Some((now, None));
            return (h00, false);
        };
        let change = &now.p - &prev.p;
        let governs = prev_change.as_ref().and_then(|d0| {
            let n1 = change.iter().map(|v| v * v).sum::<f64>().sqrt();
            let n0 = d0.iter().map(|v| v * v).sum::<f64>().sqrt();
            if n0 == 0.0 || n1 == 0.0 {
                return None;
            }
            let cosine = Zip::from(&change).and(d0).fold(0.0, |s, &a, &b| s + a * b) / (n1 * n0);
            let g = n1 / n0;
            self.ratios.push(g);
            let k = self.ratios.len();
            let held = k >= 3
                && (self.ratios[k - 1] - self.ratios[k - 2]).abs() < RATIO_DRIFT
                && (self.ratios[k - 2] - self.ratios[k - 3]).abs() < RATIO_DRIFT;
            (cosine >= MIN_COSINE && held && g > RATIO_RANGE.0 && g < RATIO_RANGE.1).then_some(g)
        });
        let Some(g) = governs else {
            self.last = Some((now, Some(change)));
            return (h00, false);
        };
        let factor = (g / (1.0 - g)).min(self.cap);
        let d_theta = &now.theta - &prev.theta;
        let h00_new = h00 + factor * (now.h00 - prev.h00);
        Zip::from(&mut level.p).and(&change).for_each(|p, &d| *p = (*p + factor * d).max(0.0));
        Zip::from(&mut level.theta).and(&d_theta).and(&level.p).for_each(|t, &d, &p| {
            *t = if p > 0.0 { 1.0 } else { (*t + factor * d).clamp(0.0, 1.0) };
        });
        level.update_film(h00_new);
        self.undo = Some((now, residual));
        self.ratios.clear();
        self.jumps += 1;
        (h00_new, true)
    }
}
