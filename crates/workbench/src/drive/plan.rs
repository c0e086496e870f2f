//! The march's plan: the scene's `run` block and motion as phases of steps (per cell while
//! rolling, fixed or error-controlled at rest), the stop rules and the snapshot times, the same
//! for every model.

use crate::error::{Diagnosis, Result};
use ehl_core::{Grid, Kinematics, Passing};
use ehl_scene::RunSpec;

/// How the step size is chosen.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Steps {
    /// Equal steps [s].
    Fixed {
        /// The step [s].
        dt_s: f64,
    },
    /// Error control: the local error estimate kept below `tolerance`, a method of `order`
    /// (the error scales as `dt^order`), starting from `dt0_s`.
    Controlled {
        /// The first step [s].
        dt0_s: f64,
        /// The local error to stay below.
        tolerance: f64,
        /// The order of the error estimate in the step.
        order: f64,
    },
}

/// Steady when every monitor changes less than `tolerance` over `window_s`, once `min_time_s`
/// has passed.
#[derive(Clone, Debug, PartialEq)]
pub struct SteadyRule {
    /// Largest change of a monitor over the window that counts as steady.
    pub tolerance: f64,
    /// The window [s].
    pub window_s: f64,
    /// No verdict before this time [s].
    pub min_time_s: f64,
    /// The window as the scene states it, for the stop reason.
    pub window_text: String,
    /// Compare with the state exactly one window back, interpolated between the records
    /// around it: a periodic pattern's window is whole passages, and the nearest record's
    /// phase would differ by up to a step.
    pub periodic: bool,
}

impl SteadyRule {
    /// A steady (not periodic) rule.
    pub fn new(tolerance: f64, window_s: f64, min_time_s: f64, window_text: String) -> Self {
        Self { tolerance, window_s, min_time_s, window_text, periodic: false }
    }
}

/// The most fixed steps a feature's passage may plan: far beyond any scene (the hole's
/// passage on 257² takes 2970), and a plan that asks for more is a mistaken input (a dent
/// `1e20 a` wide never leaves the domain), not a run to start.
pub const MAX_STEPS: f64 = 1e6;

/// A stretch of the march with one way of choosing steps: the driver plans a phase for every
/// piece of the motion on which the speed is linear ([`Kinematics::pieces`]).
#[derive(Clone, Debug, PartialEq)]
pub struct Phase {
    /// Start [s].
    pub t0_s: f64,
    /// End [s]; infinite for the last phase of a run with no planned end. Fixed steps land on
    /// a finite end.
    pub t1_s: f64,
    /// How the steps are chosen in it.
    pub steps: Steps,
}

/// A march: its phases, end, limits, snapshots. Times in s from the start of the motion.
#[derive(Clone, Debug, PartialEq)]
pub struct Plan {
    /// In time order, covering `[0, end)`.
    pub phases: Vec<Phase>,
    /// Where a feature ends the run, and why; with fixed steps the last step lands on it.
    pub end: Option<(f64, String)>,
    /// The steady rule, for runs no feature ends.
    pub steady: Option<SteadyRule>,
    /// A run not finished by then stops and says so.
    pub max_time_s: Option<f64>,
    /// Fixed steps: the nearest step to each; controlled steps land on each.
    pub snapshot_times_s: Vec<f64>,
}

impl Plan {
    /// One phase of equal steps from 0 on (what most tests want).
    pub fn single(steps: Steps) -> Plan {
        Plan {
            phases: vec![Phase { t0_s: 0.0, t1_s: f64::INFINITY, steps }],
            end: None,
            steady: None,
            max_time_s: None,
            snapshot_times_s: vec![],
        }
    }

    /// The scene's run, with `passing` what passes through the contact (the scene's
    /// [`ehl_scene::Scene::passing`]: dents, then holes), for a model whose surfaces (and the
    /// features) move by `motion` on the Hertz radius `a` [m] over `grid` [a]. Where the surfaces roll, `n_t` steps per cell at the
    /// piece's largest speed (so no step carries the layer more than `1/n_t` of a cell); where
    /// they rest, `run.time.dt_s` or, absent, error control from `controlled` (the model's first
    /// step [s] and order), refused when the model has none.
    pub fn from_run(
        run: &RunSpec,
        passing: &[Passing],
        grid: &Grid,
        a: f64,
        motion: &Kinematics,
        controlled: Option<(f64, f64)>,
    ) -> Result<Plan> {
        let st = &run.stop;
        let reach = |s_m: f64, what: &str| {
            motion.time_at_travel(s_m).ok_or_else(|| {
                Diagnosis::Plan(format!(
                    "run.stop: {what} needs {:.4} a of travel, but run.motion `{}` stops after {:.4} a",
                    s_m / a,
                    run.motion.label(),
                    motion.travel_limit().unwrap_or(f64::INFINITY) / a
                ))
            })
        };
        // Where a feature ends the run: the first of the two rules.
        let mut end: Option<(f64, String)> = None;
        let mut first = |t: f64, why: String| {
            if end.as_ref().is_none_or(|e| t < e.0) {
                end = Some((t, why));
            }
        };
        if st.until_features_passed {
            let mut t = 0.0f64;
            for f in passing {
                t = t.max(reach(
                    (grid.x_max + f.reach_a - f.x_start_a) * a,
                    "every feature leaving",
                )?);
            }
            first(t, "every feature has left the domain".into());
        }
        if let (Some(x), Some(f)) = (st.until_feature_at_a, passing.first()) {
            let t = reach((x - f.x_start_a) * a, &format!("the first feature reaching x = {x} a"))?;
            first(t, format!("the first feature is at x = {x} a"));
        }
        let t_end = end.as_ref().map_or(f64::INFINITY, |e| e.0);
        let mut phases = vec![];
        for piece in motion.pieces(t_end) {
            let steps = if piece.max_speed > 0.0 {
                let dt = grid.dx() * a / (run.time.steps_per_cell * piece.max_speed);
                // A speed so small that a cell's transit overflows (5e-324 m/s) has no step.
                if !(dt.is_finite() && dt > 0.0) {
                    return Err(Diagnosis::Plan(format!(
                        "conditions.rolling_velocity_m_s (or run.motion): a cell's transit at {:.3e} m/s is {dt:.3e} s, not a step",
                        piece.max_speed
                    ))
                    .into());
                }
                let span = piece.t1 - piece.t0;
                // A phase that runs until steady may still run to the time limit: its steps to
                // there are held to the same budget, or a fast scene runs for as long as one
                // waits.
                let to_limit = st.max_time_s.map_or(f64::INFINITY, |m| m - piece.t0);
                if !span.is_finite() && to_limit / dt > MAX_STEPS {
                    return Err(Diagnosis::Plan(format!(
                        "run.stop.max_time_s: rolling from {:.4e} s to the time limit {:.4e} s takes {:.3e} steps of {dt:.3e} s (at most {MAX_STEPS:e}): check conditions.rolling_velocity_m_s, run.time.steps_per_cell and run.stop.max_time_s",
                        piece.t0,
                        piece.t0 + to_limit,
                        to_limit / dt
                    ))
                    .into());
                }
                if span.is_finite() {
                    let n = span / dt;
                    if !(n <= MAX_STEPS) {
                        return Err(Diagnosis::Plan(format!(
                            "run.stop: the phase from {:.4e} s to {:.4e} s takes {n:.3e} steps of {dt:.3e} s (at most {MAX_STEPS:e}): check run.features (a dent's `width_a` sets how far beyond the domain it reaches), run.stop.until_feature_at_a and run.motion",
                            piece.t0,
                            piece.t1
                        ))
                        .into());
                    }
                    // The last step lands on the phase's end: equal steps a little shorter.
                    Steps::Fixed { dt_s: span / (n - 1e-9).ceil().max(1.0) }
                } else {
                    Steps::Fixed { dt_s: dt }
                }
            } else {
                match (run.time.dt_s, controlled) {
                    (Some(dt), _) => {
                        // At rest the steps are held to the same budget as rolling: to the
                        // phase's end, or to the time limit when it runs until steady.
                        let to = if (piece.t1 - piece.t0).is_finite() {
                            piece.t1 - piece.t0
                        } else {
                            st.max_time_s.map_or(f64::INFINITY, |m| m - piece.t0)
                        };
                        if !(to / dt <= MAX_STEPS) {
                            return Err(Diagnosis::Plan(format!(
                                "run.time.dt_s: resting from {:.4e} s to {:.4e} s takes {:.3e} steps of {dt:.3e} s (at most {MAX_STEPS:e}): a longer run.time.dt_s, or a shorter run.stop.max_time_s",
                                piece.t0,
                                piece.t0 + to,
                                to / dt
                            ))
                            .into());
                        }
                        Steps::Fixed { dt_s: dt }
                    }
                    (None, Some((dt0, order))) => {
                        Steps::Controlled { dt0_s: dt0, tolerance: run.time.error_tolerance, order }
                    }
                    (None, None) => return Err(Diagnosis::Plan(
                        "run.time.dt_s: required (s) while the surfaces rest: this model has no error control to choose the step".into()
                    ).into()),
                }
            };
            phases.push(Phase { t0_s: piece.t0, t1_s: piece.t1, steps });
        }
        let steady = end.is_none().then(|| {
            // From the last knot on the motion is constant: steady is judged there.
            let (u, settled) = (motion.final_speed(), motion.settled_from());
            let (window_s, window_text) = if u > 0.0 {
                (st.window_travel_a * a / u, format!("{} a of travel", st.window_travel_a))
            } else {
                (st.window_time_s, format!("{} s", st.window_time_s))
            };
            // Rolling from any start: the domain's material must have been replaced once.
            let min_time_s =
                settled + if u > 0.0 { (grid.x_max - grid.x_min) * a / u } else { window_s };
            SteadyRule::new(st.steady_tolerance, window_s, min_time_s, window_text)
        });
        let snapshot_times_s = run.snapshot_times(a, motion, passing.first());
        Ok(Plan { phases, end, steady, max_time_s: st.max_time_s, snapshot_times_s })
    }

    /// The steady rule of surfaces carrying a pattern that repeats every `period_a` [a] of
    /// travel: a passage is periodic when the state repeats after whole passages, so the
    /// window grows to the fewest whole passages that cover it (on a contact of half-width
    /// `a` [m]); and a pattern rolling in over a smooth surface is judged only once it fills
    /// the grid `g` (the smooth contact before it repeats too). Without a period, or without a
    /// steady rule, the plan as it is.
    pub fn per_passage(
        mut self,
        relief: &ehl_core::Relief,
        g: &Grid,
        a: f64,
        motion: &Kinematics,
    ) -> Self {
        let u = motion.final_speed();
        let (Some(p), Some(rule)) = (relief.period_a(), self.steady.as_mut()) else { return self };
        if !(u > 0.0 && p > 0.0) {
            return self;
        }
        let n = (rule.window_s * u / (p * a) - 1e-9).ceil().max(1.0);
        rule.window_s = n * p * a / u;
        rule.window_text = format!("{n} passages of the pattern ({:.4} a of travel)", n * p);
        rule.periodic = true;
        let filled_s = motion.settled_from() + relief.filled_after_a(g.x_max) * a / u;
        rule.min_time_s = rule.min_time_s.max(filled_s + rule.window_s);
        self
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn rolling_until_steady_is_held_to_the_step_budget_up_to_its_time_limit() {
        // The seed's squeezed restart at 4097 m/s: one step a cell is 5e-9 s, and its 0.2 s
        // limit would take 4e7 of them; refused at once, naming the fields to look at.
        let scene = ehl_scene::builtin("rolling-from-squeezed-compare").unwrap();
        let run = scene.run.as_ref().unwrap();
        let (g, a) = (scene.grid(), 1.347e-4);
        let fast = run.kinematics(0.5 * 4097.0).unwrap();
        let e = Plan::from_run(run, &scene.passing(), &g, a, &fast, Some((1e-9, 2.0))).unwrap_err();
        assert!(e.to_string().contains("run.stop.max_time_s"), "{e}");
        let seed = run.kinematics(0.005).unwrap();
        Plan::from_run(run, &scene.passing(), &g, a, &seed, Some((1e-6, 2.0))).unwrap();
        // And a speed whose cell transit overflows has no step at all.
        let crawl = run.kinematics(5e-324).unwrap();
        let e = Plan::from_run(run, &scene.passing(), &g, a, &crawl, Some((1e-6, 2.0)));
        assert!(e.unwrap_err().to_string().contains("rolling_velocity_m_s"));
    }

    #[test]
    fn a_rolling_run_becomes_equal_steps_ending_where_the_feature_stops() {
        let scene = ehl_scene::builtin("reynolds-m20-l10-dent").unwrap();
        let run = scene.run.as_ref().unwrap();
        let g = scene.grid();
        let (a, u) = (1e-4, 0.5);
        let k = Kinematics::constant(u).unwrap();
        let p = Plan::from_run(run, &scene.passing(), &g, a, &k, None).unwrap();
        // From x = −2 a to 1 a at u: 3 a / u; one step per cell of 6/128 a: 64 steps exactly.
        let (t_end, why) = p.end.clone().unwrap();
        assert!((t_end - 3.0 * a / u).abs() < 1e-15, "{t_end}");
        assert!(why.contains("x = 1"), "{why}");
        let [Phase { steps: Steps::Fixed { dt_s }, t1_s, .. }] = p.phases[..] else {
            panic!("{:?}", p.phases)
        };
        assert_eq!(t1_s, t_end, "the phase ends where the feature does");
        assert!((t_end / dt_s - 64.0).abs() < 1e-9, "{}", t_end / dt_s);
        // A feature ends it: no steady rule; snapshots at the dent positions' times.
        assert!(p.steady.is_none());
        assert!((p.snapshot_times_s[0] - 1.0 * a / u).abs() < 1e-15);
        // A squeeze needs a step or error control.
        let mut sq = run.clone();
        sq.motion = ehl_scene::Motion::Squeeze;
        sq.stop.until_feature_at_a = None;
        let stop = sq.kinematics(u).unwrap();
        let e = Plan::from_run(&sq, &scene.passing(), &g, a, &stop, None).unwrap_err();
        assert!(e.to_string().contains("run.time.dt_s"), "{e}");
        let p = Plan::from_run(&sq, &scene.passing(), &g, a, &stop, Some((1e-3, 3.0))).unwrap();
        assert!(matches!(p.phases[0].steps, Steps::Controlled { dt0_s: 1e-3, order: 3.0, .. }));
        assert!(p.steady.as_ref().is_some_and(|s| s.min_time_s == s.window_s));
    }

    #[test]
    fn a_start_up_ramp_takes_the_top_speeds_steps_and_a_feature_ends_it_by_travel() {
        let scene = ehl_scene::builtin("reynolds-m20-l10-dent").unwrap();
        let mut run = scene.run.clone().unwrap();
        let (g, a, u) = (scene.grid(), 1e-4, 0.5);
        // Ramp over the time the dent needs at full speed for 1 a: the dent, from x = −2 a to
        // 1 a, travels ½ u T = 0.5 a on the ramp and the rest (2.5 a) at u.
        let ramp = a / u;
        run.motion = ehl_scene::Motion::StartUp { ramp_s: ramp };
        let k = run.kinematics(u).unwrap();
        let p = Plan::from_run(&run, &scene.passing(), &g, a, &k, None).unwrap();
        let (t_end, _) = p.end.clone().unwrap();
        assert!((t_end - (ramp + 2.5 * a / u)).abs() < 1e-15, "{t_end}");
        assert_eq!(p.phases.len(), 2);
        assert_eq!((p.phases[0].t1_s, p.phases[1].t0_s, p.phases[1].t1_s), (ramp, ramp, t_end));
        // Both take steps no longer than a cell at the top speed (one step a cell here).
        for ph in &p.phases {
            let Steps::Fixed { dt_s } = ph.steps else { panic!("{ph:?}") };
            assert!(dt_s <= g.dx() * a / u * (1.0 + 1e-12), "{dt_s}");
        }
        // Snapshots by position become times along the ramp: x = −1.75 a is 0.25 a of
        // travel, reached at t with ½ (u/T) t² = 0.25 a.
        run.snapshots_a = vec![-1.75];
        let p = Plan::from_run(&run, &scene.passing(), &g, a, &k, None).unwrap();
        let want = (2.0 * 0.25 * a * ramp / u).sqrt();
        assert!((p.snapshot_times_s[0] - want).abs() < 1e-15, "{:?}", p.snapshot_times_s);
        // A motion that stops before the feature gets there: refused, saying how far it goes.
        run.motion = ehl_scene::Motion::StopAt { at_s: a / u };
        let e = Plan::from_run(&run, &scene.passing(), &g, a, &run.kinematics(u).unwrap(), None)
            .unwrap_err();
        let e = format!("{e:#}");
        assert!(e.contains("run.stop") && e.contains("stops after 1.0000 a"), "{e}");
    }

    #[test]
    fn a_passage_that_would_never_end_is_refused_before_it_starts() {
        // A dent 1e20 a wide (a fuzzed scene) reaches 1e20 a beyond the outlet: its passage
        // would take ~1e21 steps. The plan says which fields set that, and runs nothing.
        let scene = ehl_scene::builtin("dent-shallow").unwrap();
        let run = scene.run.clone().unwrap();
        let g = scene.grid();
        let (a, u) = (1.3e-4, 0.01);
        let k = Kinematics::constant(u).unwrap();
        assert!(Plan::from_run(&run, &scene.passing(), &g, a, &k, None).is_ok());
        let mut wide = scene.clone();
        let Some(ehl_scene::Feature::Dent(d)) = wide.run.as_mut().map(|r| &mut r.features[0])
        else {
            panic!("a dent scene")
        };
        d.width_a = 1e20;
        let e =
            format!("{:#}", Plan::from_run(&run, &wide.passing(), &g, a, &k, None).unwrap_err());
        assert!(e.contains("run.stop") && e.contains("width_a") && e.contains("steps"), "{e}");
    }
}
