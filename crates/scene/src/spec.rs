//! The scene's blocks: conditions, lubricant, the run and its time, stop and motion, domain,
//! grid and outputs.

use super::*;

/// Conditions in SI; each field's unit is in its name.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Conditions {
    /// Ball radius `R` [m].
    pub ball_radius_m: f64,
    /// Normal load `F` [N].
    pub load_n: f64,
    /// Reduced modulus `E'` [Pa].
    pub reduced_modulus_pa: f64,
    /// Rolling velocity `u1` [m/s] of both surfaces (pure rolling); 0 or absent: none.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub rolling_velocity_m_s: Option<f64>,
}

/// Lubricant in SI.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct LubricantSpec {
    /// Viscosity at ambient pressure `η0` [Pa s].
    pub eta0_pa_s: f64,
    /// Pressure–viscosity coefficient `α` [1/Pa].
    pub alpha_per_pa: f64,
    /// Roelands pressure constant `p0` [Pa].
    pub p0_roelands_pa: f64,
}

impl LubricantSpec {
    /// The lubricant in the core's terms.
    pub fn lubricant(&self) -> Lubricant {
        Lubricant {
            eta0: self.eta0_pa_s,
            alpha: self.alpha_per_pa,
            p0_roelands: self.p0_roelands_pa,
        }
    }
}

/// How time advances.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct TimeSettings {
    /// The layer model's scheme (the Reynolds solver steps by second-order backward differences).
    #[serde(default)]
    pub scheme: Scheme,
    /// Rolling: time steps per spatial interval `n_t`, `Δt = ΔX a / (n_t u1)` (every model).
    #[serde(default = "default_nt")]
    pub steps_per_cell: f64,
    /// Squeeze (layer model): a fixed step [s]; when absent, error control sets it.
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

/// When a march stops (every model reads it: the workbench's one driver applies it).
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
    /// Stop once every feature has left the domain (its centre a reach beyond `x` max), rather
    /// than at steady state …
    #[serde(default)]
    pub until_features_passed: bool,
    /// … or once the first feature's centre reaches this `x` [a].
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub until_feature_at_a: Option<f64>,
    /// Time limit [s]: a run that is not steady by then stops and says so. Required unless a
    /// feature ends the run.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub max_time_s: Option<f64>,
}

impl Default for StopSettings {
    fn default() -> Self {
        Self {
            steady_tolerance: default_steady_tol(),
            window_travel_a: default_window_a(),
            window_time_s: default_window_s(),
            until_features_passed: false,
            until_feature_at_a: None,
            max_time_s: Some(10.0),
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

/// Initial state of a layer run.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "kebab-case")]
pub enum StartState {
    /// Unstrained layer of the supply thickness (`ε = 0`).
    Uniform,
    /// The fully squeezed state `ε = min(p/Eo, 1)`.
    Squeezed,
    /// Steady rolling at the scene's velocity, solved directly.
    SteadyRolling,
}

/// How a layer run is solved.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "kebab-case")]
pub enum Method {
    /// Steady rolling solved directly (`∂ε/∂t = 0`): no history, no snapshots in time.
    Steady,
    /// Time stepping from a start state: histories, snapshots, features passing, squeeze.
    March,
}

/// What the surfaces do, stated once for every model: pure rolling (both surfaces at one
/// speed), at `conditions.rolling_velocity_m_s` unless a table gives the speeds. The core's
/// [`Kinematics`] is what the models read ([`RunSpec::kinematics`]).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(rename_all = "kebab-case")]
pub enum Motion {
    /// Pure rolling at `conditions.rolling_velocity_m_s`.
    Rolling,
    /// Squeeze: the rolling stops (suddenly) at the start, the load stays (a stop at 0 s).
    Squeeze,
    /// No time stepping: the start state is the result (e.g. the steady squeeze).
    None,
    /// Rolling at the scene's speed, then a sudden stop at `at_s` [s] (`{"stop": {"at_s": 0.05}}`).
    #[serde(rename = "stop")]
    StopAt {
        /// When the surfaces stop [s].
        at_s: f64,
    },
    /// From rest to the scene's speed in a linear ramp over `ramp_s` [s] (0: at once).
    StartUp {
        /// How long the ramp takes [s].
        ramp_s: f64,
    },
    /// The speed as a piecewise-linear table of `[t [s], u [m/s]]` knots (two at one time: a
    /// jump); after the last knot its speed holds.
    Table {
        /// The knots `[t, u]`, times non-decreasing from 0.
        knots: Vec<[f64; 2]>,
    },
}

impl Motion {
    /// Whether anything marches in time (all but `none`).
    pub fn marches(&self) -> bool {
        *self != Motion::None
    }
    /// The name used in reports (`rolling`, `squeeze`, `stop`, `start-up`, `table`, `none`).
    pub fn label(&self) -> &'static str {
        match self {
            Motion::Rolling => "rolling",
            Motion::Squeeze => "squeeze",
            Motion::None => "none",
            Motion::StopAt { .. } => "stop",
            Motion::StartUp { .. } => "start-up",
            Motion::Table { .. } => "table",
        }
    }
}

/// A layer run.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct RunSpec {
    /// `steady` or `march`; absent: `steady` when the scene asks only for the steady rolling
    /// state (rolling, no start, no features, no snapshots in time), else `march`.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub method: Option<Method>,
    /// Where the march starts (required by `march`; `steady` has no start).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub start: Option<StartState>,
    /// How the surfaces move (docs/scenes.md, Motion).
    pub motion: Motion,
    #[serde(default)]
    /// Dents in the ball passing.
    pub features: Vec<Feature>,
    #[serde(default)]
    /// Steps: scheme, steps per cell, fixed step or error control.
    pub time: TimeSettings,
    #[serde(default)]
    /// When the march stops.
    pub stop: StopSettings,
    /// Times [s, from the start of the motion] at which fields are written …
    #[serde(default)]
    pub snapshots_s: Vec<f64>,
    /// … and positions [a] of the first feature's centre at which fields are written (a
    /// feature travels with the surfaces: the time is when the motion has carried it there).
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub snapshots_a: Vec<f64>,
    /// The direct steady solve (method `steady`, and a `steady-rolling` start).
    #[serde(default)]
    pub steady: Tiered<SteadySettings>,
}

impl RunSpec {
    /// The motion as the models read it, built on the reference speed `u_ref` [m/s] (the
    /// scene's rolling speed; for a table without one, its largest speed).
    pub fn kinematics(&self, u_ref: f64) -> Result<Kinematics, KinematicsError> {
        match &self.motion {
            Motion::Rolling => Kinematics::constant(u_ref),
            Motion::None => Kinematics::constant(0.0),
            Motion::Squeeze => Kinematics::stop_at(u_ref, 0.0),
            Motion::StopAt { at_s } => Kinematics::stop_at(u_ref, *at_s),
            Motion::StartUp { ramp_s } => Kinematics::start_up(u_ref, *ramp_s),
            Motion::Table { knots } => {
                let k: Vec<(f64, f64)> = knots.iter().map(|k| (k[0], k[1])).collect();
                let reference =
                    if u_ref > 0.0 { u_ref } else { k.iter().map(|k| k.1).fold(0.0, f64::max) };
                Kinematics::table(&k, reference)
            }
        }
    }

    /// The method this run uses, the default resolved.
    pub fn method(&self) -> Method {
        self.method.unwrap_or(
            if self.motion == Motion::Rolling
                && self.start.is_none()
                && self.features.is_empty()
                && self.snapshots_s.is_empty()
                && self.snapshots_a.is_empty()
            {
                Method::Steady
            } else {
                Method::March
            },
        )
    }
    /// Every snapshot time [s]: `snapshots_s` and the times `snapshots_a` give for the `first`
    /// feature carried by `motion` on the Hertz radius `a` [m], in order; a
    /// position the motion never carries the feature to has no time (the scene's checks refuse
    /// it).
    pub fn snapshot_times(&self, a: f64, motion: &Kinematics, first: Option<&Passing>) -> Vec<f64> {
        let x0 = first.map_or(0.0, |f| f.x_start_a);
        let mut t: Vec<f64> = self.snapshots_s.clone();
        t.extend(self.snapshots_a.iter().filter_map(|&x| motion.time_at_travel((x - x0) * a)));
        t.sort_by(f64::total_cmp);
        t
    }
    /// The start state of a march (validated present).
    pub fn start(&self) -> StartState {
        self.start.unwrap_or(StartState::Uniform)
    }
}
impl Conditions {
    /// The contact in the core's terms.
    pub fn contact(&self) -> Contact {
        Contact {
            ball_radius: self.ball_radius_m,
            load: self.load_n,
            reduced_modulus: self.reduced_modulus_pa,
        }
    }
}

/// The computational rectangle in units of the Hertz radius `a`.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Domain {
    /// `[x_min, x_max]` [a], `x` the rolling direction.
    pub x_a: [f64; 2],
    /// `[y_min, y_max]` [a].
    pub y_a: [f64; 2],
}

/// Points per side.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct GridSpec {
    /// Points along `x`.
    pub nx: usize,
    /// Points along `y`.
    pub ny: usize,
}

/// Which files a run writes (`summary.json` always).
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields, default)]
pub struct Outputs {
    /// `centreline.csv`: the fields along `y = 0`.
    pub centreline: bool,
    /// Full fields as `.npy`.
    pub fields: bool,
    /// PNG figures.
    pub figures: bool,
}

impl Default for Outputs {
    fn default() -> Self {
        Self { centreline: true, fields: true, figures: true }
    }
}
