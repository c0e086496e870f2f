//! Start states (uniform, the direct steady squeeze) and the snapshot type. The run loop is the
//! workbench's one driver (`ehl_workbench::drive`), shared by every model.

use crate::model::{LayerModel, LayerState};
use crate::stepper::LayerError;
use ehl_core::Start;
use ndarray::{Array2, Zip};
use serde::Serialize;
use std::time::Instant;

/// Solves the contact with a uniform (unstrained) layer of the supply thickness: `ε = 0`.
pub fn uniform_state(m: &LayerModel) -> Result<LayerState, LayerError> {
    let eps = m.grid.zeros();
    let g0 = m.ball(0.0) - m.thickness(&eps, 0.0);
    let (mut p, mut w) = (m.grid.zeros(), m.grid.zeros());
    let r = m.contact(&g0, None, &mut p, &mut w, Start::Flat).map_err(|e| LayerError::Contact {
        step: 0,
        t: 0.0,
        source: e,
    })?;
    Ok(LayerState { t: 0.0, eps, p, w, h0: r.h0 })
}

/// What the direct steady-squeeze solve did.
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
pub struct SqueezeReport {
    /// Active-set passes over the "no layer left" set `{p ≥ Eo}`.
    pub passes: usize,
    /// Contact-solver iterations, all passes.
    pub iterations: usize,
    /// Wall time of the solve [s].
    pub wall_time_s: f64,
}

/// The fully squeezed state (`u1 = 0`, `t → ∞`), solved directly: `ε = min(p/Eo, 1)`, i.e.
/// `l = l0 (1 − min(p/Eo, 1))`. Independent of `η` and of `E` above `Eo`. Where `p < Eo` the
/// layer is a linear compliance `l0/Eo`; where `p ≥ Eo` it is gone. The set `{p ≥ Eo}` is found
/// by active-set passes, each a warm-started contact solve.
pub fn squeeze_steady(m: &LayerModel) -> Result<(LayerState, SqueezeReport), LayerError> {
    let t0 = Instant::now();
    let ball = m.ball(0.0);
    let supply = m.supply(0.0);
    let (mut p, mut w) = (m.grid.zeros(), m.grid.zeros());
    let mut dry = Array2::from_elem(p.dim(), false);
    let (mut passes, mut iterations) = (0, 0);
    let mut start = Start::Flat;
    let h0 = loop {
        let mut g0 = ball.clone();
        let mut c = m.grid.zeros();
        Zip::from(&mut g0).and(&mut c).and(&supply).and(&dry).for_each(|g, c, &l0, &d| {
            if !d {
                *g -= l0;
                *c = l0 / m.eo;
            }
        });
        let r = m
            .contact(&g0, Some(&c), &mut p, &mut w, start)
            .map_err(|e| LayerError::Contact { step: passes, t: 0.0, source: e })?;
        start = Start::Warm;
        passes += 1;
        iterations += r.iterations;
        let h0 = r.h0;
        let mut changed = 0;
        Zip::from(&mut dry).and(&p).and(&supply).for_each(|d, &p, &l0| {
            let now = p >= m.eo && l0 > 0.0;
            if now != *d {
                *d = now;
                changed += 1;
            }
        });
        if changed == 0 {
            break h0;
        }
        if passes >= 50 {
            return Err(LayerError::Setup(format!(
                "steady squeeze: the no-layer set {{p >= Eo}} still changes ({changed} points) after {passes} passes"
            )));
        }
    };
    let eps = p.mapv(|p| (p / m.eo).min(1.0));
    let state = LayerState { t: 0.0, eps, p, w, h0 };
    Ok((state, SqueezeReport { passes, iterations, wall_time_s: t0.elapsed().as_secs_f64() }))
}

/// A field snapshot, in Hertz units.
#[derive(Clone, Debug)]
pub struct Snapshot {
    /// Strain.
    pub eps: Array2<f64>,
    /// Pressure [p_h].
    pub p: Array2<f64>,
    /// Layer thickness [a²/R].
    pub l: Array2<f64>,
    /// Separation of the surfaces, the layer plus the gap above it [a²/R].
    pub film: Array2<f64>,
}

impl Snapshot {
    /// The snapshot of state `s`.
    pub fn of(m: &LayerModel, s: &LayerState) -> Self {
        let l = s.thickness(m);
        Snapshot { eps: s.eps.clone(), p: s.p.clone(), film: &l + &s.gap(m), l }
    }
}
