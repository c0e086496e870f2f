//! Initial states, the direct steady-squeeze solve, and the run loop that stops when the scene
//! is steady (or a feature has passed), recording time series and snapshots.

use crate::model::{LayerModel, LayerState, Monitor};
use crate::stepper::{LayerError, Scheme, StepInfo, Stepper};
use ehl_core::Start;
use ndarray::{Array2, Zip};
use serde::{Deserialize, Serialize};
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

/// How time advances.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct TimeSettings {
    #[serde(default)]
    pub scheme: Scheme,
    /// Rolling: time steps per spatial interval `n_t`, `Δt = ΔX a / (n_t u1)`.
    #[serde(default = "default_nt")]
    pub steps_per_cell: f64,
    /// Squeeze: a fixed step [s]; when absent, error control sets it.
    #[serde(default)]
    pub dt_s: Option<f64>,
    /// Error control: RMS local strain error per step to aim for.
    #[serde(default = "default_err")]
    pub error_tolerance: f64,
    /// Extra Picard passes of the implicit scheme (0: coefficients extrapolated, still 2nd order).
    #[serde(default)]
    pub picard: usize,
}

fn default_nt() -> f64 {
    10.0
}
fn default_err() -> f64 {
    1e-4
}

impl Default for TimeSettings {
    fn default() -> Self {
        Self {
            scheme: Scheme::Implicit,
            steps_per_cell: default_nt(),
            dt_s: None,
            error_tolerance: default_err(),
            picard: 0,
        }
    }
}

/// When a run stops.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct StopSettings {
    /// Steady when central and minimum layer thickness (per `l0`), maximum pressure (per `p_h`)
    /// and contact diameter (per `2a`) all change less than this over the window.
    #[serde(default = "default_steady_tol")]
    pub steady_tolerance: f64,
    /// Window: travel [a] when rolling.
    #[serde(default = "default_window_a")]
    pub window_travel_a: f64,
    /// Window: time [s] in squeeze.
    #[serde(default = "default_window_s")]
    pub window_time_s: f64,
    /// Stop once every feature has left the domain, rather than at steady state.
    #[serde(default)]
    pub until_features_passed: bool,
    /// Safety limit [s]: a run that is not steady by then stops and says so.
    pub max_time_s: f64,
}

impl Default for StopSettings {
    fn default() -> Self {
        Self {
            steady_tolerance: default_steady_tol(),
            window_travel_a: default_window_a(),
            window_time_s: default_window_s(),
            until_features_passed: false,
            max_time_s: 10.0,
        }
    }
}

fn default_steady_tol() -> f64 {
    1e-3
}
fn default_window_a() -> f64 {
    0.5
}
fn default_window_s() -> f64 {
    0.5
}

/// A field snapshot, in Hertz units.
#[derive(Clone, Debug)]
pub struct Snapshot {
    pub t: f64,
    pub eps: Array2<f64>,
    pub p: Array2<f64>,
    /// Layer thickness [a²/R].
    pub l: Array2<f64>,
}

/// What a run did.
#[derive(Clone, Debug)]
pub struct Record {
    pub series: Vec<Monitor>,
    pub snapshots: Vec<Snapshot>,
    pub steps: usize,
    pub rejected_steps: usize,
    pub solves: usize,
    pub iterations: usize,
    pub wall_time_s: f64,
    pub steady: bool,
    pub stop_reason: String,
    /// Step sizes used [s]: (smallest, largest).
    pub dt_range: (f64, f64),
}

/// Runs `state` forward with `stepper` until the stop rule holds, taking snapshots at
/// `snapshot_times` [s, from the run's start]. `progress(t, t_hint)` is called every step.
pub fn run(
    m: &LayerModel,
    state: &mut LayerState,
    stepper: &mut Stepper,
    time: &TimeSettings,
    stop: &StopSettings,
    snapshot_times: &[f64],
    progress: &mut dyn FnMut(f64),
) -> Result<Record, LayerError> {
    let t_start = Instant::now();
    let t_begin = state.t;
    let rolling = m.u1 > 0.0;
    let a = m.scales.a;
    let dt_roll = if rolling { m.grid.dx() * a / (time.steps_per_cell * m.u1) } else { f64::NAN };
    let window = if rolling { stop.window_travel_a * a / m.u1 } else { stop.window_time_s };
    // Rolling from any start: the whole domain's material must have been replaced once.
    let min_time = if rolling { (m.grid.x_max - m.grid.x_min) * a / m.u1 } else { window };
    let mut dt = match (rolling, time.dt_s) {
        (true, _) => dt_roll,
        (false, Some(dt)) => dt,
        // Error control from a step the layer resolves at the inlet: η(0)/Eo / 100.
        (false, None) => m.eta(0.0) / m.eo * 1e-2,
    };
    let adaptive = !rolling && time.dt_s.is_none();
    stepper.estimate_error = adaptive;
    let mut series = vec![Monitor::of(m, state, 0)];
    let mut snaps = vec![];
    let mut pending: Vec<f64> = snapshot_times.to_vec();
    pending.sort_by(|a, b| a.partial_cmp(b).unwrap());
    let (mut steps, mut rejected, mut solves, mut iterations) = (0, 0, 0, 0);
    let mut dt_range = (f64::INFINITY, 0.0f64);
    let take =
        |s: &LayerState| Snapshot { t: s.t, eps: s.eps.clone(), p: s.p.clone(), l: s.thickness(m) };
    while let Some(&ts) = pending.first() {
        if ts <= 0.0 {
            snaps.push(take(state));
            pending.remove(0);
        } else {
            break;
        }
    }
    let (steady, reason) = loop {
        let elapsed = state.t - t_begin;
        if elapsed >= stop.max_time_s {
            break (false, format!("not steady by the time limit {} s", stop.max_time_s));
        }
        let info: StepInfo = if adaptive {
            loop {
                let (save_s, save_st) = (state.clone(), stepper.clone());
                let info = stepper.step(m, state, dt)?;
                let err = info.error_estimate.unwrap_or(0.0);
                let order = if stepper.scheme == Scheme::Implicit { 3.0 } else { 2.0 };
                let factor = if err > 0.0 {
                    0.9 * (time.error_tolerance / err).powf(1.0 / order)
                } else {
                    2.0
                };
                if err <= time.error_tolerance {
                    dt_range = (dt_range.0.min(dt), dt_range.1.max(dt));
                    // BDF2 stays zero-stable for step ratios below 1 + √2: grow by 2 at most.
                    dt *= factor.clamp(0.5, 2.0);
                    break info;
                }
                rejected += 1;
                *state = save_s;
                *stepper = save_st;
                dt *= factor.clamp(0.1, 0.9);
                if dt < 1e-12 {
                    return Err(LayerError::Setup(format!(
                        "error control: step size fell below 1e-12 s at t = {:.6e} s",
                        state.t
                    )));
                }
            }
        } else {
            dt_range = (dt_range.0.min(dt), dt_range.1.max(dt));
            stepper.step(m, state, dt)?
        };
        steps += 1;
        solves += info.solves;
        iterations += info.iterations;
        let mon = Monitor::of(m, state, info.iterations);
        series.push(mon);
        let elapsed = state.t - t_begin;
        while let Some(&ts) = pending.first() {
            if ts <= elapsed + 1e-12 {
                snaps.push(take(state));
                pending.remove(0);
            } else {
                break;
            }
        }
        progress(elapsed);
        if stop.until_features_passed {
            let passed =
                m.features.iter().all(|f| m.feature_x(f, state.t) - f.reach() > m.grid.x_max);
            if passed {
                break (true, "every feature has left the domain".into());
            }
            continue;
        }
        if elapsed >= min_time {
            // Compare with the last record at least one window back.
            let target = state.t - window;
            if let Some(old) = series.iter().rev().find(|r| r.t <= target + 1e-15) {
                let sc = &m.scales;
                let l0 = m.spec.supply_thickness_m;
                let change = [
                    (mon.central_thickness - old.central_thickness).abs() / l0,
                    (mon.minimum_thickness - old.minimum_thickness).abs() / l0,
                    (mon.max_pressure - old.max_pressure).abs() / sc.p_h,
                    (mon.contact_diameter - old.contact_diameter).abs() / (2.0 * sc.a),
                ];
                let worst = change.iter().cloned().fold(0.0, f64::max);
                if worst < stop.steady_tolerance {
                    break (
                        true,
                        format!(
                            "steady: largest change {worst:.2e} < {} over the last {}",
                            stop.steady_tolerance,
                            if rolling {
                                format!("{} a of travel", stop.window_travel_a)
                            } else {
                                format!("{} s", stop.window_time_s)
                            }
                        ),
                    );
                }
            }
        }
    };
    snaps.push(take(state));
    Ok(Record {
        series,
        snapshots: snaps,
        steps,
        rejected_steps: rejected,
        solves,
        iterations,
        wall_time_s: t_start.elapsed().as_secs_f64(),
        steady,
        stop_reason: reason,
        dt_range,
    })
}
