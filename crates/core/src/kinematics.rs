//! The motion of the surfaces over time: the one place that knows how fast the ball and the disc
//! roll and how far they have travelled.
//!
//! Every model asks a [`Kinematics`] instead of writing `x·a/u`: the layer's transport, a
//! feature's position, the driver's steps and snapshot times, the Reynolds wedge term's speed
//! factor. The speed is a piecewise-linear function of time given by its knots; a jump (a sudden
//! stop) is two knots at one time. Before the first knot the first speed holds (the state a run
//! starts from was rolling at it), after the last knot the last speed holds. Travel is the exact
//! integral of that function, so a stop at `t_s` and a ramp both travel exactly what they should
//! (the trapezoid rule is exact on each linear piece).
//!
//! Times in s from the start of the motion (`t = 0`), speeds in m/s, distances in m (SI: models
//! divide by their own length scale).

/// How the surfaces move: the speed `u(t)` [m/s] of pure rolling (both surfaces at `u`; the
/// Reynolds mean velocity `u_m = u`).
#[derive(Clone, Debug, PartialEq)]
pub struct Kinematics {
    /// Knots `(t [s], u [m/s])`, times non-decreasing; two knots at one time are a jump.
    knots: Vec<(f64, f64)>,
    /// The speed the models' scales are built on [m/s] (the scene's rolling speed): never the
    /// instantaneous one, which may be 0.
    reference: f64,
}

/// A motion refused: which input, and what is allowed.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
#[error("motion: {what}")]
pub struct KinematicsError {
    /// What is wrong, naming the input.
    pub what: String,
}

impl Kinematics {
    /// Constant speed `u` [m/s] (0: at rest), `u` also the reference.
    pub fn constant(u: f64) -> Result<Self, KinematicsError> {
        Self::table(&[(0.0, u)], u)
    }

    /// Rolling at `u` [m/s] until `t_stop` [s], then at rest (a sudden stop; `t_stop = 0`: the
    /// motion starts stopped, from a state that rolled at `u`).
    pub fn stop_at(u: f64, t_stop: f64) -> Result<Self, KinematicsError> {
        if t_stop == 0.0 {
            return Self::table(&[(0.0, u), (0.0, 0.0)], u);
        }
        Self::table(&[(0.0, u), (t_stop, u), (t_stop, 0.0)], u)
    }

    /// From rest to `u` [m/s] in a linear ramp over `ramp` [s] starting at `t = 0` (`ramp = 0`:
    /// a sudden start).
    pub fn start_up(u: f64, ramp: f64) -> Result<Self, KinematicsError> {
        Self::table(&[(0.0, 0.0), (ramp, u)], u)
    }

    /// A piecewise-linear table of `(t [s], u [m/s])` knots and the reference speed [m/s].
    /// Times must be finite, start at 0 or later and never decrease (equal times: a jump); speeds
    /// finite and `>= 0` (the workbench rolls in one direction); the reference finite and `> 0`
    /// unless every speed is 0 (then 0 is allowed: nothing moves).
    pub fn table(knots: &[(f64, f64)], reference: f64) -> Result<Self, KinematicsError> {
        let err = |what: String| Err(KinematicsError { what });
        if knots.is_empty() {
            return err("the table has no knots: give at least one (t, u)".into());
        }
        for (k, &(t, u)) in knots.iter().enumerate() {
            if !(t.is_finite() && t >= 0.0) {
                return err(format!("knot {k}: time {t} s must be finite and >= 0"));
            }
            if !(u.is_finite() && u >= 0.0) {
                return err(format!("knot {k}: speed {u} m/s must be finite and >= 0"));
            }
            if k > 0 && t < knots[k - 1].0 {
                return err(format!(
                    "knot {k}: time {t} s is before the knot before it ({} s): times must not decrease",
                    knots[k - 1].0
                ));
            }
            if k > 1 && t == knots[k - 2].0 {
                return err(format!("knot {k}: three knots at {t} s (a jump is two)"));
            }
        }
        let moves = knots.iter().any(|k| k.1 > 0.0);
        if !(reference.is_finite() && (reference > 0.0 || (!moves && reference == 0.0))) {
            return err(format!(
                "reference speed {reference} m/s must be finite and > 0 (0 only if nothing moves)"
            ));
        }
        Ok(Self { knots: knots.to_vec(), reference })
    }

    /// The reference speed [m/s]: what dimensionless time and the Reynolds `λ̄` are built on.
    pub fn reference_speed(&self) -> f64 {
        self.reference
    }

    /// The speed before the motion starts [m/s]: what a steady-rolling start rolls at.
    pub fn speed_before(&self) -> f64 {
        self.knots[0].1
    }

    /// The speed from the last knot on [m/s].
    pub fn final_speed(&self) -> f64 {
        self.knots[self.knots.len() - 1].1
    }

    /// The time of the last knot [s]: from then on the speed is constant.
    pub fn settled_from(&self) -> f64 {
        self.knots[self.knots.len() - 1].0
    }

    /// The speed `u(t)` [m/s]; at a jump, the speed after it.
    pub fn speed(&self, t: f64) -> f64 {
        let k = &self.knots;
        // The last knot at or before t (the later of a jump's two).
        match k.iter().rposition(|&(tk, _)| tk <= t) {
            None => k[0].1,
            Some(i) if i + 1 == k.len() => k[i].1,
            Some(i) => {
                let ((t0, u0), (t1, u1)) = (k[i], k[i + 1]);
                u0 + (u1 - u0) * (t - t0) / (t1 - t0)
            }
        }
    }

    /// Distance travelled from `t = 0` to `t` [m] (negative before 0, at the first speed).
    pub fn travel(&self, t: f64) -> f64 {
        let k = &self.knots;
        // Up to the first knot (and before 0): the first speed.
        if t <= k[0].0 {
            return t * k[0].1;
        }
        let mut s = k[0].0 * k[0].1;
        for w in k.windows(2) {
            let ((t0, u0), (t1, u1)) = (w[0], w[1]);
            if t1 <= t0 {
                continue;
            }
            if t <= t1 {
                let ut = u0 + (u1 - u0) * (t - t0) / (t1 - t0);
                return s + 0.5 * (u0 + ut) * (t - t0);
            }
            s += 0.5 * (u0 + u1) * (t1 - t0);
        }
        let (tl, ul) = k[k.len() - 1];
        s + ul * (t - tl)
    }

    /// Distance travelled in the step from `t0` to `t0 + dt` [m]: the trapezoid on each linear
    /// piece the step crosses, so that a constant speed gives `u·dt` to the last bit (a
    /// difference of two travels would round differently, and move every march's numbers).
    pub fn travel_in_step(&self, t0: f64, dt: f64) -> f64 {
        let t1 = t0 + dt;
        let inner: Vec<f64> =
            self.knots.iter().map(|k| k.0).filter(|&tk| tk > t0 && tk < t1).collect();
        if inner.is_empty() {
            return 0.5 * (self.speed(t0) + self.speed_left(t1)) * dt;
        }
        let mut s = 0.0;
        let mut a = t0;
        for b in inner.into_iter().chain(std::iter::once(t1)) {
            if b > a {
                s += 0.5 * (self.speed(a) + self.speed_left(b)) * (b - a);
            }
            a = b;
        }
        s
    }

    /// How far the motion ever gets from `t = 0` [m]: `None` when it keeps rolling.
    pub fn travel_limit(&self) -> Option<f64> {
        (self.final_speed() == 0.0).then(|| self.travel(self.settled_from()))
    }

    /// The first time `t >= 0` [s] at which the travel from 0 reaches `s` [m], or `None` when
    /// the motion never gets that far (it stops first).
    pub fn time_at_travel(&self, s: f64) -> Option<f64> {
        if s <= 0.0 {
            return Some(0.0);
        }
        let k = &self.knots;
        // Before the first knot: the first speed.
        let s_first = k[0].0 * k[0].1;
        if s <= s_first {
            return Some(s / k[0].1);
        }
        let mut acc = s_first;
        for w in k.windows(2) {
            let ((t0, u0), (t1, u1)) = (w[0], w[1]);
            if t1 <= t0 {
                continue;
            }
            let seg = 0.5 * (u0 + u1) * (t1 - t0);
            if s <= acc + seg && seg > 0.0 {
                // Solve acc + u0 τ + ½ g τ² = s on the piece, g its acceleration.
                let (need, g) = (s - acc, (u1 - u0) / (t1 - t0));
                // At constant speed the plain quotient, so that a constant motion's times are
                // exactly `s/u` (the root formula's `√(u²)` rounds).
                let tau = if g.abs() < 1e-300 {
                    need / u0
                } else {
                    // The root with τ ≥ 0, written without cancellation.
                    let disc = (u0 * u0 + 2.0 * g * need).max(0.0).sqrt();
                    2.0 * need / (u0 + disc)
                };
                return Some(t0 + tau.clamp(0.0, t1 - t0));
            }
            acc += seg;
        }
        let (tl, ul) = k[k.len() - 1];
        (ul > 0.0).then(|| tl + (s - acc) / ul)
    }

    /// The pieces of `[0, t_end]` on which the motion is smooth, split at every knot: what a
    /// driver plans its phases on (each with its largest speed [m/s]).
    pub fn pieces(&self, t_end: f64) -> Vec<Piece> {
        let mut cuts: Vec<f64> = self.knots.iter().map(|k| k.0).filter(|&t| t > 0.0).collect();
        cuts.dedup();
        let mut out = vec![];
        let mut t0 = 0.0;
        for t1 in cuts.into_iter().chain(std::iter::once(f64::INFINITY)) {
            let end = t1.min(t_end);
            if end > t0 || (out.is_empty() && t1 == f64::INFINITY) {
                // Just after t0 and just before the end: the speed's extremes on a linear piece.
                let u_start = self.speed(t0);
                let u_end = if end.is_finite() { self.speed_left(end) } else { u_start };
                out.push(Piece { t0, t1: end, max_speed: u_start.max(u_end) });
            }
            if t1 >= t_end {
                break;
            }
            t0 = t1;
        }
        out
    }

    /// The times the surfaces come to rest (`"stop"`) and begin to move from rest (`"start"`)
    /// [s], in order: what a history marks.
    pub fn events(&self) -> Vec<(f64, &'static str)> {
        self.knots
            .windows(2)
            .filter_map(|w| {
                let ((ta, ua), (tb, ub)) = (w[0], w[1]);
                if ua > 0.0 && ub == 0.0 {
                    Some((tb, "stop"))
                } else if ua == 0.0 && ub > 0.0 {
                    Some((ta, "start"))
                } else {
                    None
                }
            })
            .collect()
    }

    /// The speed just before `t` [m/s] (at a jump, the speed before it).
    fn speed_left(&self, t: f64) -> f64 {
        let k = &self.knots;
        match k.iter().position(|&(tk, _)| tk >= t) {
            None => k[k.len() - 1].1,
            Some(0) => k[0].1,
            Some(i) => {
                let ((t0, u0), (t1, u1)) = (k[i - 1], k[i]);
                if t1 <= t0 { u0 } else { u0 + (u1 - u0) * (t - t0) / (t1 - t0) }
            }
        }
    }
}

/// A stretch of time on which the speed is linear.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Piece {
    /// Start [s].
    pub t0: f64,
    /// End [s] (may be infinite: the motion's last piece with no end given).
    pub t1: f64,
    /// The largest speed on it [m/s].
    pub max_speed: f64,
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn constant_speed_travels_u_t_and_inverts_exactly() {
        let k = Kinematics::constant(0.01).unwrap();
        assert_eq!(k.speed(3.0), 0.01);
        assert_eq!(k.travel(2.0), 0.02);
        assert_eq!(k.travel(-1.0), -0.01);
        assert_eq!(k.time_at_travel(0.02), Some(2.0));
        assert_eq!(k.pieces(5.0), vec![Piece { t0: 0.0, t1: 5.0, max_speed: 0.01 }]);
    }

    #[test]
    fn a_stop_travels_until_it_and_never_after() {
        let k = Kinematics::stop_at(0.01, 0.5).unwrap();
        assert_eq!(k.speed(0.49), 0.01);
        // At the jump: the speed after it.
        assert_eq!(k.speed(0.5), 0.0);
        assert_eq!(k.speed_left(0.5), 0.01);
        assert!((k.travel(10.0) - 0.005).abs() < 1e-18);
        assert_eq!(k.time_at_travel(0.004), Some(0.4));
        assert_eq!(k.time_at_travel(0.006), None, "never reached: it stopped at 5 mm");
        let p = k.pieces(2.0);
        assert_eq!(p.len(), 2);
        assert_eq!((p[0].t1, p[0].max_speed, p[1].t0, p[1].max_speed), (0.5, 0.01, 0.5, 0.0));
        // Stopped from the start: rolled before, rests after.
        let s = Kinematics::stop_at(0.01, 0.0).unwrap();
        assert_eq!((s.speed_before(), s.speed(0.0), s.travel(1.0)), (0.01, 0.0, 0.0));
        assert_eq!(s.pieces(1.0), vec![Piece { t0: 0.0, t1: 1.0, max_speed: 0.0 }]);
        assert_eq!(s.reference_speed(), 0.01);
    }

    #[test]
    fn a_ramp_travels_half_u_t_and_inverts_through_the_quadratic() {
        let k = Kinematics::start_up(0.02, 0.1).unwrap();
        assert_eq!(k.speed(0.05), 0.01);
        // ½ g t² on the ramp (g = 0.2 m/s²): 2.5e-4 m at 0.05 s; then u t.
        assert!((k.travel(0.05) - 2.5e-4).abs() < 1e-18);
        assert!((k.travel(0.3) - (1e-3 + 0.02 * 0.2)).abs() < 1e-17);
        let t = k.time_at_travel(2.5e-4).unwrap();
        assert!((t - 0.05).abs() < 1e-15, "{t}");
        let t = k.time_at_travel(1e-3 + 0.02 * 0.2).unwrap();
        assert!((t - 0.3).abs() < 1e-14, "{t}");
        // Travel is the integral of the speed: a midpoint sum on a fine partition agrees. The
        // midpoint rule is exact on linear pieces; the one cell holding the ramp's end (a kink
        // of slope 0.2 m/s²) is off by at most 0.2 dt²/8 = 2.3e-11 m (measured 1.0e-11). A
        // travel that missed the ramp's half (u t instead of ½ u t) is off by 1e-3 m.
        let n = 10_000;
        let dt = 0.3 / n as f64;
        let sum: f64 = (0..n).map(|i| k.speed((i as f64 + 0.5) * dt) * dt).sum();
        assert!((sum - k.travel(0.3)).abs() < 2.3e-11, "{sum}");
    }

    /// Up to 0.02 m/s in 0.1 s, held, a jump down to 0.01 m/s at 0.2 s, to rest at 0.4 s.
    fn ramp_hold_jump_slowdown() -> Kinematics {
        let knots = [(0.0, 0.0), (0.1, 0.02), (0.2, 0.02), (0.2, 0.01), (0.4, 0.0)];
        Kinematics::table(&knots, 0.02).unwrap()
    }

    #[test]
    fn a_step_travels_what_the_travel_differences_say() {
        let k = ramp_hold_jump_slowdown();
        // Steps inside one piece, across a kink, across the jump, past the last knot.
        for (t0, dt) in [(0.02, 0.03), (0.05, 0.1), (0.15, 0.1), (0.35, 0.3), (0.0, 1.0)] {
            let want = k.travel(t0 + dt) - k.travel(t0);
            let got = k.travel_in_step(t0, dt);
            assert!((got - want).abs() < 1e-18, "{t0} + {dt}: {got} against {want}");
        }
        // Constant speed: u·dt exactly, as the march always had it.
        let c = Kinematics::constant(0.01).unwrap();
        assert_eq!(c.travel_in_step(0.37, 1.3e-5), 0.01 * 1.3e-5);
    }

    #[test]
    fn a_table_with_a_jump_and_a_slowdown() {
        let k = ramp_hold_jump_slowdown();
        assert_eq!(k.speed(0.2), 0.01);
        let total = 0.5 * 0.02 * 0.1 + 0.02 * 0.1 + 0.5 * 0.01 * 0.2;
        assert!((k.travel(1.0) - total).abs() < 1e-18);
        assert_eq!(k.final_speed(), 0.0);
        assert_eq!(k.settled_from(), 0.4);
        let p = k.pieces(1.0);
        let spans: Vec<_> = p.iter().map(|p| (p.t0, p.t1, p.max_speed)).collect();
        assert_eq!(
            spans,
            vec![(0.0, 0.1, 0.02), (0.1, 0.2, 0.02), (0.2, 0.4, 0.01), (0.4, 1.0, 0.0)]
        );
    }

    #[test]
    fn bad_tables_are_refused_naming_the_knot() {
        let e = |k: &[(f64, f64)], r| Kinematics::table(k, r).unwrap_err().what;
        assert!(e(&[], 1.0).contains("no knots"));
        assert!(e(&[(0.0, 1.0), (-1.0, 1.0)], 1.0).contains("knot 1"));
        assert!(e(&[(0.0, 1.0), (2.0, 1.0), (1.0, 1.0)], 1.0).contains("must not decrease"));
        assert!(e(&[(0.0, -1.0)], 1.0).contains(">= 0"));
        assert!(e(&[(0.0, f64::NAN)], 1.0).contains("knot 0"));
        assert!(e(&[(0.0, 1.0), (1.0, 1.0), (1.0, 0.0), (1.0, 2.0)], 1.0).contains("three"));
        assert!(e(&[(0.0, 1.0)], 0.0).contains("reference"));
        assert!(Kinematics::constant(0.0).is_ok(), "at rest, nothing to refer to");
    }
}
