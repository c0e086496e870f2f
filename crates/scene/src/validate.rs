//! The scene's checks against the plausible ranges and a run's limits (`limits.rs`), and each
//! block's check, every refusal naming the field, its value and what is allowed.

use super::*;

/// The range checks' vocabulary: each refusal names the scene, the field, the value and what is
/// allowed.
pub(crate) struct Check<'a> {
    pub(crate) origin: &'a str,
}

impl Check<'_> {
    pub(crate) fn err(&self, field: &str, value: String, allowed: &str) -> SceneError {
        SceneError::Range {
            origin: self.origin.into(),
            field: field.into(),
            value,
            allowed: allowed.into(),
        }
    }
    pub(crate) fn positive(&self, field: &str, v: f64, unit: &str) -> Result<(), SceneError> {
        if v.is_finite() && v > 0.0 {
            Ok(())
        } else {
            Err(self.err(field, num(v), &format!("must be finite and > 0 ({unit})")))
        }
    }
    /// A name used for folders: letters, digits, `-`, `_`.
    pub(crate) fn name(&self, name: &str) -> Result<(), SceneError> {
        if name.trim().is_empty()
            || !name.chars().all(|c| c.is_ascii_alphanumeric() || c == '-' || c == '_')
        {
            return Err(self.err(
                "name",
                format!("{name:?}"),
                "must be non-empty ASCII letters, digits, '-' or '_'",
            ));
        }
        Ok(())
    }
    /// The first of `(refused, field, value, allowed)` that is refused, its `allowed` worded by
    /// `say`.
    pub(crate) fn first_refusal(
        &self,
        checks: &[(bool, &str, String, &str)],
        say: impl Fn(&str) -> String,
    ) -> Result<(), SceneError> {
        match checks.iter().find(|c| c.0) {
            Some((_, field, value, allowed)) => Err(self.err(field, value.clone(), &say(allowed))),
            None => Ok(()),
        }
    }
    /// A rolling speed [m/s]: from 0 to [`MAX_SPEED_M_S`].
    pub(crate) fn speed(&self, field: &str, u: f64) -> Result<(), SceneError> {
        if u.is_finite() && (0.0..=MAX_SPEED_M_S).contains(&u) {
            Ok(())
        } else {
            Err(self.err(field, num(u), &format!("must be in [0, {MAX_SPEED_M_S}] (m/s)")))
        }
    }
    /// A time [s]: from 0 to [`MAX_TIME_S`].
    pub(crate) fn time(&self, field: &str, t: f64) -> Result<(), SceneError> {
        self.own("", ehl_core::check::within(field, t, 0.0, MAX_TIME_S, "s"))
    }
    /// A solver's own check ([`ehl_core::FieldError`]), its field put under `prefix`.
    pub(crate) fn own(
        &self,
        prefix: &str,
        r: Result<(), ehl_core::FieldError>,
    ) -> Result<(), SceneError> {
        r.map_err(|e| {
            let e = e.under(prefix);
            self.err(&e.field, e.value, &e.allowed)
        })
    }
    /// A physical input within its plausible range ([`PLAUSIBLE`]).
    pub(crate) fn plausible(&self, field: &str, v: f64) -> Result<(), SceneError> {
        let Some(&(_, lo, hi, unit, why)) = PLAUSIBLE.iter().find(|p| p.0 == field) else {
            return Ok(());
        };
        if v.is_finite() && v >= lo && v <= hi {
            return Ok(());
        }
        Err(self.err(
            field,
            num(v),
            &format!("must be in [{}, {}] ({unit}): {why}", num(lo), num(hi)),
        ))
    }
    pub(crate) fn nonneg(&self, field: &str, v: f64, unit: &str) -> Result<(), SceneError> {
        if v.is_finite() && v >= 0.0 {
            Ok(())
        } else {
            Err(self.err(field, num(v), &format!("must be finite and >= 0 ({unit})")))
        }
    }
}

impl Scene {
    /// Range checks, each naming the field and what it allows.
    pub fn validate(&self, origin: &str) -> Result<(), SceneError> {
        let ck = Check { origin };
        ck.name(&self.name)?;
        match (self.model, self.models.is_empty()) {
            (Some(_), false) => {
                return Err(ck.err(
                    "models",
                    format!("{:?}", self.models),
                    "give either `model` (one model) or `models` (a comparison), not both",
                ));
            }
            (None, true) => {
                return Err(ck.err(
                    "model",
                    "(missing)".into(),
                    "one of \"dry\", \"layer\", \"reynolds\"; or `models`, a list of them",
                ));
            }
            (None, false) => {
                if let Some(c) = &self.comparison {
                    return Err(ck.err(
                        "comparison",
                        c.clone(),
                        "only on a one-model scene (a comparison is its own)",
                    ));
                }
                for (k, m) in self.models.iter().enumerate() {
                    if self.models[..k].contains(m) {
                        return Err(ck.err(
                            &format!("models[{k}]"),
                            format!("{m:?}"),
                            "each model once",
                        ));
                    }
                }
                if self.reynolds.as_ref().is_some_and(|r| r.moes.is_some()) {
                    return Err(ck.err(
                        "reynolds.moes",
                        "(given)".into(),
                        "not in a comparison: every model must run the same load and velocity (give conditions.load_n and rolling_velocity_m_s)",
                    ));
                }
                // Each model checks the scene as it would run it alone: the field names are the
                // scene's own.
                for &m in &self.models {
                    self.for_model(m).validate(origin)?;
                }
                return Ok(());
            }
            (Some(_), true) => {}
        }
        let c = &self.conditions;
        ck.positive("conditions.ball_radius_m", c.ball_radius_m, "m")?;
        ck.positive("conditions.load_n", c.load_n, "N")?;
        ck.positive("conditions.reduced_modulus_pa", c.reduced_modulus_pa, "Pa")?;
        ck.plausible("conditions.ball_radius_m", c.ball_radius_m)?;
        ck.plausible("conditions.load_n", c.load_n)?;
        ck.plausible("conditions.reduced_modulus_pa", c.reduced_modulus_pa)?;
        let load = ("conditions.load_n", c.load_n);
        self.validate_contact_size(&ck, &self.conditions.contact(), load)?;
        if let Some(a) = self.accuracy {
            ck.own(
                "",
                ehl_core::check::within(
                    "accuracy",
                    a,
                    1e-3,
                    0.5,
                    "relative error of the answer, 0.02: 2 %",
                ),
            )?;
        }
        self.validate_domain(&ck)?;
        ck.own("solver", self.solver.check().map_err(Tiered::<DrySettings>::placed))?;
        if let Some(u) = c.rolling_velocity_m_s {
            ck.speed("conditions.rolling_velocity_m_s", u)?;
        }
        if let Some(l) = &self.lubricant {
            ck.positive("lubricant.eta0_pa_s", l.eta0_pa_s, "Pa s")?;
            ck.nonneg("lubricant.alpha_per_pa", l.alpha_per_pa, "1/Pa")?;
            ck.positive("lubricant.p0_roelands_pa", l.p0_roelands_pa, "Pa")?;
            ck.plausible("lubricant.eta0_pa_s", l.eta0_pa_s)?;
            ck.plausible("lubricant.alpha_per_pa", l.alpha_per_pa)?;
            ck.plausible("lubricant.p0_roelands_pa", l.p0_roelands_pa)?;
        }
        if let Some(sup) = &self.supply {
            // Zero is no oil at all: the Reynolds answer is the dry contact (the layer model,
            // whose layer is this oil, refuses it below).
            ck.nonneg("supply.thickness_m", sup.thickness_m, "m")?;
            if sup.thickness_m > 0.0 {
                ck.plausible("supply.thickness_m", sup.thickness_m)?;
            }
            for (k, h) in sup.holes.iter().enumerate() {
                let f = |n: &str| format!("supply.holes[{k}].{n}");
                ck.own(
                    "",
                    ehl_core::check::above(&f("radius_a"), h.radius_a, 0.0, 100.0, "units of a"),
                )?;
                for (n, v) in [("x_start_a", h.x_start_a), ("y_a", h.y_a)] {
                    ck.own(
                        "",
                        ehl_core::check::within(&f(n), v, -MAX_PLACE_A, MAX_PLACE_A, "units of a"),
                    )?;
                }
            }
        }
        if let Some(l) = &self.layer {
            ck.own("layer", l.check())?;
        }
        match self.model {
            Some(Model::Reynolds | Model::ReynoldsFlooded) => self.validate_reynolds(&ck),
            Some(Model::Layer) => self.validate_layer(&ck),
            _ => Ok(()),
        }
    }

    /// The contact small against the ball ([`MAX_A_OVER_R`]), `field` named as the cause.
    fn validate_contact_size(
        &self,
        ck: &Check,
        c: &Contact,
        (field, value): (&str, f64),
    ) -> Result<(), SceneError> {
        let a = ehl_core::HertzScales::new(c).a;
        let ratio = a / c.ball_radius;
        if ratio.is_finite() && ratio <= MAX_A_OVER_R {
            return Ok(());
        }
        Err(ck.err(
            field,
            num(value),
            &format!(
                "gives a Hertz radius a = {} m, {} of the ball's radius: the half-space contact needs a/R <= {MAX_A_OVER_R} (a lighter load, a stiffer pair or a larger ball)",
                num(a),
                num(ratio)
            ),
        ))
    }

    /// The domain holds the Hertz contact (±1 `a` either way) and lies within [`MAX_DOMAIN_A`];
    /// the grid has 5 to 4097 points a side and at least two cells across the contact.
    fn validate_domain(&self, ck: &Check) -> Result<(), SceneError> {
        for (field, r) in [("domain.x_a", self.domain.x_a), ("domain.y_a", self.domain.y_a)] {
            if !(r[0].is_finite() && r[1].is_finite() && r[0] < r[1]) {
                return Err(ck.err(
                    field,
                    format!("[{}, {}]", num(r[0]), num(r[1])),
                    "must be [min, max] with finite min < max (units of a)",
                ));
            }
            if !(r[0] <= -1.0 && r[1] >= 1.0 && r[0] >= -MAX_DOMAIN_A && r[1] <= MAX_DOMAIN_A) {
                return Err(ck.err(
                    field,
                    format!("[{}, {}]", num(r[0]), num(r[1])),
                    &format!("must hold the Hertz contact and stay within ±{MAX_DOMAIN_A}: min in [-{MAX_DOMAIN_A}, -1], max in [1, {MAX_DOMAIN_A}] (units of a)"),
                ));
            }
        }
        // 5 points is the least that resolves anything; 4097² fields are 128 MiB each.
        for (field, n, r) in
            [("grid.nx", self.grid.nx, self.domain.x_a), ("grid.ny", self.grid.ny, self.domain.y_a)]
        {
            if !(5..=4097).contains(&n) {
                return Err(ck.err(field, n.to_string(), "must be 5 ..= 4097 points"));
            }
            let cell = (r[1] - r[0]) / (n - 1) as f64;
            if cell > 1.0 {
                return Err(ck.err(
                    field,
                    n.to_string(),
                    &format!(
                        "gives cells of {} a: at least two cells across the Hertz contact's diameter need cells <= 1 a (more points, or a shorter domain)",
                        num(cell)
                    ),
                ));
            }
        }
        Ok(())
    }

    /// The Reynolds model's block and grid.
    fn validate_reynolds(&self, ck: &Check) -> Result<(), SceneError> {
        let c = &self.conditions;
        let missing = |f: &str| ck.err(f, "(missing)".into(), "required by the Reynolds model");
        let l = self.lubricant.ok_or_else(|| missing("lubricant"))?;
        let r = self.reynolds.as_ref().ok_or_else(|| missing("reynolds"))?;
        match r.moes {
            Some(m) => {
                if let Some(u) = c.rolling_velocity_m_s {
                    return Err(ck.err(
                        "conditions.rolling_velocity_m_s",
                        num(u),
                        "must be absent with reynolds.moes (M and L set the load and the velocity; conditions.load_n is replaced too, and the run says so)",
                    ));
                }
                ck.own(
                    "reynolds.moes",
                    ehl_core::check::above("m", m.m, 0.0, 1e5, "Moes' load parameter"),
                )?;
                ck.own(
                    "reynolds.moes",
                    ehl_core::check::above("l", m.l, 0.0, 1e3, "Moes' material parameter"),
                )?;
                ck.positive(
                    "lubricant.alpha_per_pa",
                    l.alpha_per_pa,
                    "1/Pa (Moes input derives U from L)",
                )?;
                let (contact, u_sum) = self.reynolds_conditions();
                self.validate_contact_size(ck, &contact, ("reynolds.moes.m", m.m))?;
                if ck.speed("reynolds.moes.l", 0.5 * u_sum).is_err() {
                    let u = num(0.5 * u_sum);
                    let why = format!(
                        "sets the rolling velocity {u} m/s with this lubricant and ball, outside [0, {MAX_SPEED_M_S}] m/s (a smaller L, or a larger lubricant.alpha_per_pa)"
                    );
                    return Err(ck.err("reynolds.moes.l", num(m.l), &why));
                }
            }
            None => {
                let u = c.rolling_velocity_m_s.unwrap_or(0.0);
                ck.positive(
                    "conditions.rolling_velocity_m_s",
                    u,
                    "m/s (a Reynolds film needs motion)",
                )?;
            }
        }
        if let Some(run) = &self.run {
            self.validate_reynolds_run(ck, run)?;
        }
        ck.own("reynolds.solver", r.solver.check().map_err(Tiered::<ReynoldsSettings>::placed))?;
        if self.grid.nx != self.grid.ny
            || ((self.domain.x_a[1] - self.domain.x_a[0]) / (self.grid.nx - 1) as f64
                - (self.domain.y_a[1] - self.domain.y_a[0]) / (self.grid.ny - 1) as f64)
                .abs()
                > 1e-12
        {
            return Err(ck.err(
                "grid",
                format!("{}x{}", self.grid.nx, self.grid.ny),
                "the Reynolds solver needs square cells (equal spacing in x and y)",
            ));
        }

        Ok(())
    }

    /// The scenario as the Reynolds model runs it: the steady solve, then (method `march`) time
    /// steps from it while dents in the ball pass at the mean velocity.
    fn validate_reynolds_run(&self, ck: &Check, r: &RunSpec) -> Result<(), SceneError> {
        if r.method() == Method::March {
            ck.first_refusal(
                &[
                    (!matches!(r.start, Some(StartState::SteadyRolling | StartState::Squeezed)), "run.start", format!("{:?}", r.start), "steady-rolling or squeezed"),
                ],
                |allowed| format!("must be {allowed} for the Reynolds model (its march starts from its steady solve at the speed the motion starts with; squeezed: then stopped and left at rest until the squeeze is steady)"),
            )?;
        }
        let marching = self.run.as_ref().is_some_and(|r| r.method == Some(Method::March));
        if marching && self.supply.is_some() && self.oil_m().is_none() {
            // Each step would be a dry contact solved by Reynolds' line relaxation, which
            // converges that slowly (a dent entering: the force balance 7e-5 off after 30 cycles).
            return Err(ck.err(
                "supply.thickness_m",
                "0".into(),
                "must be > 0 in a Reynolds march (with no oil each step is the dry contact's: run the `dry` model; a steady Reynolds solve takes none)",
            ));
        }
        if let Some(k) = self.supply.as_ref().and_then(|s| (!s.holes.is_empty()).then_some(0))
            && !marching
        {
            return Err(ck.err(
                &format!("supply.holes[{k}]"),
                "(given)".into(),
                "only in a march for the Reynolds model (run.method \"march\"): a hole passes the contact; a steady solve has none",
            ));
        }
        let (_, u_sum) = self.reynolds_conditions();
        self.validate_run(ck, r, 0.5 * u_sum)
    }

    /// The layer model's blocks: the layer and the run.
    fn validate_layer(&self, ck: &Check) -> Result<(), SceneError> {
        let missing = |f: &str| ck.err(f, "(missing)".into(), "required by the layer model");
        if self.lubricant.is_none() {
            return Err(missing("lubricant"));
        }
        if self.supply.is_none() {
            return Err(ck.err(
                "supply",
                "(missing)".into(),
                "required by the layer model: its layer is the supplied oil (supply.thickness_m, m)",
            ));
        }
        if let Some(sup) = self.supply.as_ref().filter(|s| s.thickness_m <= 0.0) {
            return Err(ck.err(
                "supply.thickness_m",
                num(sup.thickness_m),
                "must be > 0 for the layer model: its layer is the supplied oil, the unit of its thicknesses (no oil at all is the dry contact: the dry or Reynolds model)",
            ));
        }
        if self.layer.is_none() {
            return Err(missing("layer"));
        }
        let r = self.run.as_ref().ok_or_else(|| missing("run"))?;
        self.validate_run(ck, r, self.conditions.rolling_velocity_m_s.unwrap_or(0.0))
    }

    /// The scenario every marching model reads (method, start, motion, features, steps, stop
    /// rule, snapshots), the motion built on the rolling velocity `u` [m/s].
    fn validate_run(&self, ck: &Check, r: &RunSpec, u: f64) -> Result<(), SceneError> {
        Self::validate_motion(ck, r, u)?;
        let kin = r
            .kinematics(u)
            .map_err(|e| ck.err("run.motion", format!("{:?}", r.motion), &e.what))?;
        let a = ehl_core::HertzScales::new(&self.conditions.contact()).a;
        let passing = self.passing();
        self.validate_features(ck, r, a)?;
        Self::validate_method(ck, r, &kin, !(passing.is_empty() && r.features.is_empty()))?;
        Self::validate_steps(ck, r)?;
        Self::validate_stop(ck, r, &kin, a, passing.first())?;
        Self::validate_snapshots(ck, r, &kin, a, passing.first())
    }

    /// A stop's time, a ramp's length, a table's knots; the scene's speed where the motion
    /// rolls at it.
    fn validate_motion(ck: &Check, r: &RunSpec, u: f64) -> Result<(), SceneError> {
        match &r.motion {
            Motion::StopAt { at_s } => ck.time("run.motion.stop.at_s", *at_s)?,
            Motion::StartUp { ramp_s } => ck.time("run.motion.start-up.ramp_s", *ramp_s)?,
            Motion::Table { knots } if knots.is_empty() => {
                return Err(ck.err(
                    "run.motion.table.knots",
                    "[]".into(),
                    "at least one [t (s), u (m/s)] knot",
                ));
            }
            Motion::Table { knots } => {
                for (k, knot) in knots.iter().enumerate() {
                    ck.time(&format!("run.motion.table.knots[{k}][0]"), knot[0])?;
                    ck.speed(&format!("run.motion.table.knots[{k}][1]"), knot[1])?;
                }
            }
            _ => {}
        }
        let uses_scene_speed =
            matches!(r.motion, Motion::Rolling | Motion::StopAt { .. } | Motion::StartUp { .. });
        if uses_scene_speed && !(u > 0.0) {
            return Err(ck.err(
                "conditions.rolling_velocity_m_s",
                num(u),
                &format!("must be > 0 (m/s): run.motion `{}` rolls at it", r.motion.label()),
            ));
        }
        Ok(())
    }

    /// Method and start, the direct steady solve's settings, and the velocity rolling needs.
    fn validate_method(
        ck: &Check,
        r: &RunSpec,
        kin: &Kinematics,
        anything_passes: bool,
    ) -> Result<(), SceneError> {
        match (r.method(), r.start) {
            (Method::March, None) => {
                return Err(ck.err(
                    "run.start",
                    "(missing)".into(),
                    "required by the march method (uniform, squeezed or steady-rolling); a rolling scene with no start, features or snapshots is solved steady",
                ));
            }
            (Method::Steady, Some(s)) => {
                return Err(ck.err(
                    "run.start",
                    format!("{s:?}"),
                    "the steady method solves the steady state directly and has no start: remove run.start, or set run.method to \"march\"",
                ));
            }
            _ => {}
        }
        if r.method() == Method::Steady {
            ck.first_refusal(
                &[
                    (
                        r.motion != Motion::Rolling,
                        "run.motion",
                        format!("{:?}", r.motion),
                        "must be rolling",
                    ),
                    (
                        anything_passes,
                        "run.features",
                        format!("{} dent(s) and the supply's holes", r.features.len()),
                        "a feature or a hole passing is not steady: none allowed",
                    ),
                    (
                        !r.snapshots_s.is_empty(),
                        "run.snapshots_s",
                        format!("{:?}", r.snapshots_s),
                        "snapshots in time need a history: none allowed",
                    ),
                ],
                |allowed| format!("{allowed} with run.method \"steady\" (use \"march\")"),
            )?;
        }
        ck.own("run.steady", r.steady.check().map_err(Tiered::<SteadySettings>::placed))?;
        let u = kin.speed_before();
        if r.start == Some(StartState::SteadyRolling) && !(u > 0.0) {
            return Err(ck.err(
                "run.start",
                "steady-rolling".into(),
                &format!(
                    "a steady-rolling start needs the motion to roll before it starts; run.motion `{}` starts at rest (use a uniform or squeezed start)",
                    r.motion.label()
                ),
            ));
        }
        Ok(())
    }

    /// Steps: per cell (rolling), a fixed step or error control (squeeze).
    fn validate_steps(ck: &Check, r: &RunSpec) -> Result<(), SceneError> {
        let t = &r.time;
        if !(t.steps_per_cell.is_finite() && t.steps_per_cell >= 0.5 && t.steps_per_cell <= 1000.0)
        {
            return Err(ck.err(
                "run.time.steps_per_cell",
                format!("{}", t.steps_per_cell),
                "must be in [0.5, 1000] (time steps per grid interval)",
            ));
        }
        if let Some(dt) = t.dt_s {
            ck.positive("run.time.dt_s", dt, "s")?;
            ck.time("run.time.dt_s", dt)?;
        }
        if !(t.error_tolerance.is_finite() && t.error_tolerance > 0.0 && t.error_tolerance < 1.0) {
            return Err(ck.err(
                "run.time.error_tolerance",
                format!("{}", t.error_tolerance),
                "must be in (0, 1)",
            ));
        }
        if t.picard > 10 {
            return Err(ck.err("run.time.picard", t.picard.to_string(), "must be 0 ..= 10"));
        }
        Ok(())
    }

    /// Stop rules: steady tolerance and windows, a feature's end, the time limit.
    fn validate_stop(
        ck: &Check,
        r: &RunSpec,
        kin: &Kinematics,
        a: f64,
        first: Option<&Passing>,
    ) -> Result<(), SceneError> {
        let st = &r.stop;
        if !(st.steady_tolerance.is_finite()
            && st.steady_tolerance > 0.0
            && st.steady_tolerance < 1.0)
        {
            return Err(ck.err(
                "run.stop.steady_tolerance",
                format!("{}", st.steady_tolerance),
                "must be in (0, 1)",
            ));
        }
        ck.positive("run.stop.window_travel_a", st.window_travel_a, "units of a")?;
        ck.positive("run.stop.window_time_s", st.window_time_s, "s")?;
        ck.time("run.stop.window_time_s", st.window_time_s)?;
        ck.own(
            "",
            ehl_core::check::within(
                "run.stop.window_travel_a",
                st.window_travel_a,
                0.0,
                1e6,
                "units of a",
            ),
        )?;
        let feature_ends = st.until_features_passed || st.until_feature_at_a.is_some();
        match st.max_time_s {
            Some(t) => {
                ck.positive("run.stop.max_time_s", t, "s")?;
                ck.time("run.stop.max_time_s", t)?;
            }
            None if !feature_ends && r.method() == Method::March && r.motion.marches() => {
                return Err(ck.err(
                    "run.stop.max_time_s",
                    "(missing)".into(),
                    "required unless a feature ends the run (until_features_passed or until_feature_at_a) (s)",
                ));
            }
            None => {}
        }
        if feature_ends && first.is_none() {
            return Err(ck.err(
                if st.until_features_passed {
                    "run.stop.until_features_passed"
                } else {
                    "run.stop.until_feature_at_a"
                },
                "(given)".into(),
                "needs a feature passing: a dent in run.features or a hole in supply.holes",
            ));
        }
        if st.until_features_passed && !(kin.final_speed() > 0.0) {
            return Err(ck.err(
                "run.motion",
                r.motion.label().into(),
                "must keep rolling (a final speed > 0) for every feature to leave the domain",
            ));
        }
        if let Some(x) = st.until_feature_at_a {
            let x0 = first.map_or(f64::NAN, |f| f.x_start_a);
            if !(x.is_finite() && x > x0) {
                return Err(ck.err(
                    "run.stop.until_feature_at_a",
                    num(x),
                    &format!("finite and > the first feature's start {x0} (a)"),
                ));
            }
            if kin.time_at_travel((x - x0) * a).is_none() {
                return Err(ck.err(
                    "run.stop.until_feature_at_a",
                    num(x),
                    &format!(
                        "a position run.motion `{}` carries the first feature to: it stops after {:.4} a",
                        r.motion.label(),
                        x0 + kin.travel_limit().unwrap_or(f64::INFINITY) / a
                    ),
                ));
            }
            if let Some((k, &xs)) = r.snapshots_a.iter().enumerate().find(|(_, xs)| **xs > x) {
                return Err(ck.err(
                    &format!("run.snapshots_a[{k}]"),
                    num(xs),
                    &format!("<= run.stop.until_feature_at_a = {x} (a): the run ends there"),
                ));
            }
        }
        Ok(())
    }

    /// Features: dents (depth in one unit, an amplitude with a supply to refer to), each with a
    /// finite place; waviness and roughness with their heights and lengths, the lengths on at
    /// least [`MIN_CELLS_PER_WAVELENGTH`] cells of the grid (on a contact of half-width `a`
    /// [m]); a hole is refused here (it is in the supply).
    fn validate_features(&self, ck: &Check, r: &RunSpec, a: f64) -> Result<(), SceneError> {
        use ehl_core::check::{above, within};
        let grid = self.grid();
        let cell_m = grid.dx().max(grid.dy()) * a;
        // A length the grid must resolve: refused with its cells and the grid that would.
        let resolved = |field: &str, length_m: f64, need: f64, what: &str| {
            let cells = length_m / cell_m;
            if cells >= need {
                return Ok(());
            }
            let n = ((grid.shape().1 - 1) as f64 * need / cells).ceil() as usize + 1;
            Err(ck.err(
                field,
                num(length_m),
                &format!(
                    "{what} spans {cells:.2} cells of the grid ({cell_m:.3e} m each): at least {need} are needed to carry it; refine the grid to about {n} points per side, or lengthen it"
                ),
            ))
        };
        for (k, f) in r.features.iter().enumerate() {
            match f {
                Feature::Waviness(w) => {
                    let f = |n: &str| format!("run.features[{k}].waviness.{n}");
                    ck.own("", within(&f("amplitude_m"), w.amplitude_m, 0.0, 1e-3, "m"))?;
                    ck.own("", above(&f("wavelength_m"), w.wavelength_m, 0.0, 1.0, "m"))?;
                    let deg = "degrees";
                    ck.own("", within(&f("angle_deg"), w.angle_deg, -360.0, 360.0, deg))?;
                    ck.own("", within(&f("phase_deg"), w.phase_deg, -360.0, 360.0, deg))?;
                    if let Some(x) = w.enters_at_x_m {
                        ck.own("", within(&f("enters_at_x_m"), x, -1.0, 1.0, "m"))?;
                    }
                    let need = MIN_CELLS_PER_WAVELENGTH;
                    resolved(&f("wavelength_m"), w.wavelength_m, need, "a wavelength")?;
                }
                Feature::Roughness(g) => {
                    let f = |n: &str| format!("run.features[{k}].roughness.{n}");
                    ck.own("", within(&f("rq_m"), g.rq_m, 0.0, 1e-3, "m"))?;
                    let (bx, by) = ("correlation_length_m", "correlation_length_y_m");
                    ck.own("", above(&f(bx), g.correlation_length_m, 0.0, 1.0, "m"))?;
                    if let Some(b) = g.correlation_length_y_m {
                        ck.own("", above(&f(by), b, 0.0, 1.0, "m"))?;
                    }
                    if let Some(x) = g.enters_at_x_m {
                        ck.own("", within(&f("enters_at_x_m"), x, -1.0, 1.0, "m"))?;
                    }
                    // The Gaussian spectrum's shortest wavelengths (two standard deviations
                    // out) are about 2.2 β: half the cells per β that a wave needs.
                    let need = MIN_CELLS_PER_WAVELENGTH / 2.0;
                    let field =
                        if g.correlation_length_y_m.is_some_and(|b| b < g.correlation_length_m) {
                            by
                        } else {
                            bx
                        };
                    resolved(&f(field), g.shortest_m(), need, "a correlation length")?;
                }
                Feature::Dent(d) => self.validate_dent(ck, d, k)?,
                Feature::HeightMap(m) => {
                    let f = |n: &str| format!("run.features[{k}].height-map.{n}");
                    check_height_map(ck, m, &f)?;
                    // Its shortest wave is two samples: the grid's cells no coarser than a
                    // sample's spacing.
                    let spacing = m.spacing_m.min(m.spacing_y());
                    let field =
                        if m.spacing_y() < m.spacing_m { "spacing_y_m" } else { "spacing_m" };
                    resolved(&f(field), 2.0 * spacing, 2.0, "two samples of the height map")?;
                }
                Feature::Hole(_) => {
                    return Err(ck.err(
                        &format!("run.features[{k}]"),
                        "hole".into(),
                        "a dent: a hole is in the oil supply, not the ball (move it to supply.holes)",
                    ));
                }
            }
        }
        Ok(())
    }

    /// A dent's fields: its depth given once (in metres or as the seed's factor of the supply),
    /// finite and within range, its width and place.
    fn validate_dent(&self, ck: &Check, d: &DentSpec, k: usize) -> Result<(), SceneError> {
        let f = |n: &str| format!("run.features[{k}].dent.{n}");
        match (d.amplitude, d.depth_m) {
            (Some(_), Some(_)) | (None, None) => {
                return Err(ck.err(
                    &f("depth_m"),
                    format!("amplitude {:?}, depth_m {:?}", d.amplitude, d.depth_m),
                    "give exactly one of `depth_m` (m) and `amplitude` (units of the supply thickness l0)",
                ));
            }
            (Some(a), None) if !a.is_finite() => {
                return Err(ck.err(&f("amplitude"), num(a), "must be finite"));
            }
            (Some(_), None) if self.oil_m().is_none() => {
                return Err(ck.err(
                    &f("amplitude"),
                    "(given)".into(),
                    "in units of supply.thickness_m: give a supply thicker than zero, or the depth in metres (`depth_m`)",
                ));
            }
            (None, Some(m)) if !m.is_finite() => {
                return Err(ck.err(&f("depth_m"), num(m), "must be finite (m)"));
            }
            _ => {}
        }
        use ehl_core::check::{above, within};
        if let Some(m) = d.depth_m {
            ck.own("", within(&f("depth_m"), m, -1e-3, 1e-3, "m, negative a bump"))?;
        }
        if let Some(a) = d.amplitude {
            ck.own(
                "",
                within(
                    &f("amplitude"),
                    a,
                    -1e6,
                    1e6,
                    "units of supply.thickness_m, negative a bump",
                ),
            )?;
        }
        ck.own("", above(&f("width_a"), d.width_a, 0.0, 100.0, "units of a"))?;
        for (n, v) in [("x_start_a", d.x_start_a), ("y_a", d.y_a)] {
            ck.own("", within(&f(n), v, -MAX_PLACE_A, MAX_PLACE_A, "units of a"))?;
        }
        Ok(())
    }

    /// Snapshots by time, or by the first feature's position while it rolls.
    fn validate_snapshots(
        ck: &Check,
        r: &RunSpec,
        kin: &Kinematics,
        a: f64,
        first: Option<&Passing>,
    ) -> Result<(), SceneError> {
        let n = r.snapshots_s.len() + r.snapshots_a.len();
        if n > MAX_SNAPSHOTS {
            return Err(ck.err(
                "run.snapshots_s",
                format!("{n} snapshots (with run.snapshots_a)"),
                &format!("at most {MAX_SNAPSHOTS}: each holds whole fields"),
            ));
        }
        for (k, &ts) in r.snapshots_s.iter().enumerate() {
            ck.time(&format!("run.snapshots_s[{k}]"), ts)?;
        }
        if !r.snapshots_a.is_empty() {
            let Some(x0) = first.map(|f| f.x_start_a) else {
                return Err(ck.err(
                    "run.snapshots_a",
                    format!("{:?}", r.snapshots_a),
                    "positions of the first feature's centre: needs a dent in run.features or a hole in supply.holes",
                ));
            };
            for (k, &x) in r.snapshots_a.iter().enumerate() {
                if !(x.is_finite() && x >= x0) {
                    return Err(ck.err(
                        &format!("run.snapshots_a[{k}]"),
                        num(x),
                        &format!("finite and >= the first feature's start {x0} (a)"),
                    ));
                }
                if kin.time_at_travel((x - x0) * a).is_none() {
                    return Err(ck.err(
                        &format!("run.snapshots_a[{k}]"),
                        num(x),
                        &format!(
                            "a position run.motion `{}` carries the first feature to (features travel with the surfaces; it stops at {:.4} a): give run.snapshots_s instead",
                            r.motion.label(),
                            x0 + kin.travel_limit().unwrap_or(f64::INFINITY) / a
                        ),
                    ));
                }
            }
        }

        Ok(())
    }
}

/// A height map's own ranges and its file: readable, 2-D float64, at least 2 × 2 samples, every
/// height finite and within ±1 mm (`f` names a field of this feature).
fn check_height_map(
    ck: &Check,
    m: &crate::HeightMapSpec,
    f: &dyn Fn(&str) -> String,
) -> Result<(), SceneError> {
    use ehl_core::check::{above, within};
    ck.own("", above(&f("spacing_m"), m.spacing_m, 0.0, 1e-2, "m"))?;
    if let Some(s) = m.spacing_y_m {
        ck.own("", above(&f("spacing_y_m"), s, 0.0, 1e-2, "m"))?;
    }
    for (n, v) in [("origin_m[0]", m.origin_m[0]), ("origin_m[1]", m.origin_m[1])] {
        ck.own("", within(&f(n), v, -1.0, 1.0, "m"))?;
    }
    let h = m.read().map_err(|why| ck.err(&f("path"), m.path.clone(), &why))?;
    let (ny, nx) = h.dim();
    if nx < 2 || ny < 2 {
        let why = format!("{ny} × {nx} samples: at least 2 × 2");
        return Err(ck.err(&f("path"), m.path.clone(), &why));
    }
    if let Some(((j, i), v)) = h.indexed_iter().find(|(_, v)| !(v.is_finite() && v.abs() <= 1e-3)) {
        let why = format!(
            "heights in m, finite and within ±1e-3 m: the sample at row {j}, column {i} is {v:e}"
        );
        return Err(ck.err(&f("path"), m.path.clone(), &why));
    }
    Ok(())
}
