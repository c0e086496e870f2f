//! The layer model's parameters in Hertz units, its fields, and its contact solve.
//!
//! Gap: `H = H0 + f + b(t) + W − L`, `L = L0(x, t) (1 − ε)` (all in `a²/R`); strain law
//! `η(p) Dε/Dt + E(p, ε) ε = p`, `Dε/Dt = ∂ε/∂t + u1 ∂ε/∂x`. Pressures in `p_h`, lengths in `a`,
//! time in seconds (rolling and squeeze share a clock, and squeeze has no velocity scale).

use crate::laws::{Damper, DamperReading, LawParameters, LawSet, ModulusLaw};
use ehl_core::params::oedometric_modulus;
use ehl_core::{
    Contact, DryProblem, DryReport, DrySettings, DrySolver, Grid, HertzScales, Kinematics,
    Lubricant, NumericError, Start,
    features::{Hole, Relief, Supply},
};
use ndarray::{Array2, Zip};
use serde::{Deserialize, Serialize};

/// The layer's conditions in SI (Table 1's layer rows).
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct LayerSpec {
    /// Layer modulus `E_layer` [Pa] (at ε = 0).
    pub modulus_pa: f64,
    /// Layer Poisson ratio `ν` [-].
    pub poisson_ratio: f64,
    /// Damper constant κ: dimensionless factor, or Pa s under the literal reading. Required
    /// with the `reconstruction` laws; the `seed-fit` laws fix it.
    #[serde(default)]
    pub damper_constant: Option<f64>,
    /// Scale `σ` of the damper's pressure dependence: `η = κ η0 exp(σ (ln η0 + 9.67)(−1 + (1 +
    /// p/p0)^z))`; 1 is Roelands' (the reconstruction), 0 a pressure-independent damper.
    #[serde(default = "one")]
    pub damper_pressure_scale: f64,
    /// Which law set: the scene's own parameters (`reconstruction`), or the parameters
    /// identified from the seed's reported numbers (`seed-fit`, `reference/seed-fit.json`).
    #[serde(default)]
    pub laws: LawSet,
    #[serde(default)]
    /// How the damper constant is read: a factor of `η0`, or Pa s (docs/model.md §3.3).
    pub damper_reading: DamperReading,
    #[serde(default)]
    /// The modulus law `E(p, ε)` (docs/model.md §3.3).
    pub modulus_law: ModulusLaw,
    /// Reference pressure `p_ref` [Pa] of the modulus law; `None`: `p_h` (the paper's choice).
    #[serde(default)]
    pub reference_pressure_pa: Option<f64>,
    /// Regularisation, not in the paper (0: off, the model as published). `E` and `η` are
    /// evaluated at the pressure smoothed by a Gaussian of this standard deviation [a]. The
    /// published model is ill-posed where `α_eff (p − E ε) > 1 − ε ∂E/∂p` (higher pressure,
    /// slower compression): grid-scale streaks grow there; smoothing over a length removes the
    /// feedback for shorter waves. See docs/model.md §3.4 and docs/layer.md.
    #[serde(default)]
    pub coefficient_smoothing_a: f64,
}

/// The seed's Table 1 supply: a 25 nm layer on the track [m].
pub const SEED_SUPPLY_THICKNESS_M: f64 = 25e-9;

/// The seed's Table 1 layer (100 MPa, ν = 0.3, κ = 5.5e5 read as a factor, the power modulus
/// law), unsmoothed: the model as published. Its supply is [`SEED_SUPPLY_THICKNESS_M`].
pub const SEED_LAYER: LayerSpec = LayerSpec {
    modulus_pa: 1e8,
    poisson_ratio: 0.3,
    damper_constant: Some(5.5e5),
    damper_pressure_scale: 1.0,
    laws: LawSet::Reconstruction,
    damper_reading: DamperReading::Factor,
    modulus_law: ModulusLaw::Power,
    reference_pressure_pa: None,
    coefficient_smoothing_a: 0.0,
};

fn one() -> f64 {
    1.0
}

impl LayerSpec {
    /// Range checks, each naming its field: the layer's elastic constants where the oedometric
    /// law holds, the law set's own inputs (the reconstruction needs its damper constant; the
    /// seed fit fixes those and refuses them), and a smoothing narrower than the contact.
    pub fn check(&self) -> Result<(), ehl_core::FieldError> {
        use ehl_core::check::{above, within};
        let err = |field: &str, value: String, allowed: &str| ehl_core::FieldError {
            field: field.into(),
            value,
            allowed: allowed.into(),
        };
        within("modulus_pa", self.modulus_pa, 1e3, 1e13, "Pa")?;
        if !(self.poisson_ratio.is_finite() && (0.0..0.5).contains(&self.poisson_ratio)) {
            return Err(err(
                "poisson_ratio",
                ehl_core::check::num(self.poisson_ratio),
                "must be in [0, 0.5) (the oedometric modulus diverges at 0.5)",
            ));
        }
        match self.laws {
            LawSet::Reconstruction => {
                let Some(k) = self.damper_constant else {
                    return Err(err(
                        "damper_constant",
                        "(missing)".into(),
                        "required with the reconstruction laws (a factor, or Pa s when literal)",
                    ));
                };
                above("damper_constant", k, 0.0, 1e15, "1, or Pa s when literal")?;
                if let Some(p) = self.reference_pressure_pa {
                    within("reference_pressure_pa", p, 1e3, 1e12, "Pa")?;
                }
                within(
                    "damper_pressure_scale",
                    self.damper_pressure_scale,
                    0.0,
                    5.0,
                    "1: Roelands' pressure dependence, 0: none",
                )?;
            }
            LawSet::SeedFit => {
                // The fit fixes these: a scene stating them too would be silently overridden.
                let fixed = [
                    ("damper_constant", self.damper_constant.is_some()),
                    ("reference_pressure_pa", self.reference_pressure_pa.is_some()),
                    ("damper_pressure_scale", self.damper_pressure_scale != 1.0),
                    ("damper_reading", self.damper_reading != DamperReading::Factor),
                    ("modulus_law", self.modulus_law != ModulusLaw::Power),
                ];
                if let Some((field, _)) = fixed.iter().find(|(_, set)| *set) {
                    return Err(err(
                        field,
                        "(given)".into(),
                        "the seed-fit laws fix it (reference/seed-fit.json): remove it, or use \"laws\": \"reconstruction\"",
                    ));
                }
            }
        }
        within(
            "coefficient_smoothing_a",
            self.coefficient_smoothing_a,
            0.0,
            0.5,
            "units of a; wider smooths the contact itself away",
        )
    }

    /// The law parameters this spec selects, with pressures in units of `p_h` [Pa]. `None` when
    /// the `reconstruction` laws lack a damper constant (a scene's checks refuse that first).
    pub fn law_parameters(&self, p_h: f64) -> Option<LawParameters> {
        match self.laws {
            LawSet::Reconstruction => Some(LawParameters {
                damper_constant: self.damper_constant?,
                damper_pressure_scale: self.damper_pressure_scale,
                reference_pressure_over_p_h: self.reference_pressure_pa.unwrap_or(p_h) / p_h,
            }),
            LawSet::SeedFit => Some(crate::laws::seed_fit()),
        }
    }
}

/// Everything the layer model needs, in Hertz units, with the contact solver of its grid.
///
/// ```
/// use ehl_core::{DrySettings, Grid, Kinematics, SEED_CONTACT, SEED_LUBRICANT};
/// use ehl_layer::{LayerModel, SEED_LAYER, SEED_SUPPLY_THICKNESS_M, SteadySettings};
/// let rolling = Kinematics::constant(0.01).unwrap(); // u1 [m/s]
/// let (contact, lub, grid) = (SEED_CONTACT, SEED_LUBRICANT, Grid::square(65, 1.25));
/// let m = LayerModel::new(
///     &contact, &lub, &SEED_LAYER, SEED_SUPPLY_THICKNESS_M, rolling, grid,
///     DrySettings::default(),
/// )
/// .unwrap();
/// let (state, _) = ehl_layer::rolling_steady(&m, &SteadySettings::default()).unwrap();
/// // The layer carries the load as the dry contact would: a peak near Hertz's p_h (1 in these
/// // units), the strain within [0, 1].
/// let p_max = state.p.iter().cloned().fold(0.0, f64::max);
/// assert!((p_max - 1.0).abs() < 0.05, "{p_max}");
/// assert!(state.eps.iter().all(|e| (0.0..=1.0).contains(e)));
/// ```
pub struct LayerModel {
    /// Hertz scales of the contact.
    pub scales: HertzScales,
    /// The grid [a].
    pub grid: Grid,
    /// The supplied layer's thickness `l0 / (a²/R)`.
    pub l0: f64,
    /// The supply as given (thickness [m], the holes passing: [`LayerModel::set_passing`]).
    supply: Supply,
    /// `Eo / p_h`.
    pub eo: f64,
    /// `p_ref / p_h`.
    pub p_ref: f64,
    /// The modulus law.
    pub law: ModulusLaw,
    /// The damper `η(p)` [p_h s].
    pub damper: Damper,
    /// The layer as the scene gave it.
    pub spec: LayerSpec,
    /// How the surfaces move: the speed `u1(t)` [m/s] and the travel that carries the layer,
    /// its supply and the features.
    motion: Kinematics,
    /// The surfaces' relief passing (set with [`LayerModel::set_passing`]).
    relief: Relief,
    /// The dry contact solver of the grid.
    pub solver: DrySolver,
    /// `(X² + Y²)/2`.
    shape: Array2<f64>,
    /// `∬ P dX dY` for the scene's load.
    pub load: f64,
}

impl LayerModel {
    /// The model of a layer `spec` supplied `supply_thickness_m` [m] thick, moving by `motion`,
    /// on `grid`, with nothing passing (see [`LayerModel::set_passing`]); refused, naming the
    /// field, when `spec` is out of its ranges ([`LayerSpec::check`]) or the supply is not a
    /// positive thickness.
    pub fn new(
        contact: &Contact,
        lub: &Lubricant,
        spec: &LayerSpec,
        supply_thickness_m: f64,
        motion: Kinematics,
        grid: Grid,
        settings: DrySettings,
    ) -> Result<Self, crate::LayerError> {
        let refuse = |what: String| crate::LayerError::Setup(what);
        spec.check().map_err(|e| refuse(format!("layer.{e}")))?;
        if !(supply_thickness_m.is_finite() && supply_thickness_m > 0.0) {
            return Err(refuse(format!(
                "the supply's thickness {supply_thickness_m} m: must be finite and > 0"
            )));
        }
        let scales = HertzScales::new(contact);
        let laws = spec.law_parameters(scales.p_h).ok_or_else(|| {
            refuse("layer.damper_constant: required with the reconstruction laws".into())
        })?;
        let eta_zero_pa_s = match spec.damper_reading {
            DamperReading::Factor => laws.damper_constant * lub.eta0,
            DamperReading::Literal => laws.damper_constant,
        };
        let shape = match ehl_core::laws::Viscosity::roelands(lub, scales.p_h) {
            ehl_core::laws::Viscosity::Roelands { s, z, p0 } => {
                ehl_core::laws::Viscosity::Roelands { s: s * laws.damper_pressure_scale, z, p0 }
            }
            other => other,
        };
        let damper = Damper { eta_zero: eta_zero_pa_s / scales.p_h, shape };
        Ok(Self {
            l0: supply_thickness_m / scales.delta,
            supply: Supply::uniform(supply_thickness_m),
            eo: oedometric_modulus(spec.modulus_pa, spec.poisson_ratio) / scales.p_h,
            p_ref: laws.reference_pressure_over_p_h,
            law: spec.modulus_law,
            damper,
            spec: *spec,
            motion,
            relief: Relief::default(),
            solver: DrySolver::new(grid, settings),
            shape: grid.paraboloid(),
            load: scales.load_dimensionless(),
            scales,
            grid,
        })
    }

    /// What passes from now on: the surfaces' relief and holes in the supply.
    pub fn set_passing(&mut self, relief: Relief, holes: Vec<Hole>) {
        self.relief = relief;
        self.supply.holes = holes;
    }

    /// Whether anything passes (a relief or a hole).
    pub fn has_passing(&self) -> bool {
        !(self.relief.is_empty() && self.supply.holes.is_empty())
    }

    /// The same model on another grid (same laws, velocity, features and solver settings).
    pub fn on_grid(&self, grid: Grid) -> Self {
        Self {
            scales: self.scales,
            grid,
            l0: self.l0,
            supply: self.supply.clone(),
            eo: self.eo,
            p_ref: self.p_ref,
            law: self.law,
            damper: self.damper,
            spec: self.spec,
            motion: self.motion.clone(),
            relief: self.relief.clone(),
            solver: DrySolver::new(grid, self.solver.settings),
            shape: grid.paraboloid(),
            load: self.load,
        }
    }

    /// `E / p_h`.
    #[inline]
    pub fn modulus(&self, p: f64, eps: f64) -> f64 {
        self.law.modulus(p, eps, self.eo, self.p_ref)
    }
    /// `η / p_h` [s].
    #[inline]
    pub fn eta(&self, p: f64) -> f64 {
        self.damper.eta(p)
    }
    /// Strain rate of the Kelvin–Voigt element, `(p − E ε) / η` [1/s], with the material
    /// coefficients at pressure `pc` (= `p` unless regularised).
    #[inline]
    pub fn rate(&self, p: f64, pc: f64, eps: f64) -> f64 {
        (p - self.modulus(pc, eps) * eps) / self.eta(pc)
    }
    /// The strain rate at every point [1/s] (coefficients smoothed when asked).
    pub fn rate_field(&self, p: &Array2<f64>, eps: &Array2<f64>) -> Array2<f64> {
        let smoothed;
        let pc = if self.spec.coefficient_smoothing_a > 0.0 {
            smoothed = self.coefficient_pressure(p);
            &smoothed
        } else {
            p
        };
        Zip::from(p).and(pc).and(eps).par_map_collect(|&p, &pc, &e| self.rate(p, pc, e))
    }

    /// The pressure the material coefficients see: `p` itself, or its Gaussian smoothing when
    /// the regularisation is on.
    pub fn coefficient_pressure(&self, p: &Array2<f64>) -> Array2<f64> {
        let sigma = self.spec.coefficient_smoothing_a;
        if sigma <= 0.0 {
            return p.clone();
        }
        gaussian_smooth(p, &self.grid, sigma, sigma)
    }

    /// Local growth indicator of lateral short waves (from linearising the strain law with the
    /// layer held by a stiff contact): positive where a higher pressure slows the compression,
    /// `α_eff (p − E ε) − (1 − ε ∂E/∂p)`, `α_eff = d ln η / dp`. Dimensionless.
    pub fn instability_indicator(&self, p: f64, eps: f64) -> f64 {
        let dp = 1e-6;
        let alpha_eff = (self.eta(p + dp).ln() - self.eta(p).ln()) / dp;
        let e_p = (self.modulus(p + dp, eps) - self.modulus(p, eps)) / dp;
        alpha_eff * (p - self.modulus(p, eps) * eps) - (1.0 - eps * e_p)
    }

    /// How far the surfaces, and everything they carry, have travelled at time `t` [a].
    pub fn travel_a(&self, t: f64) -> f64 {
        self.motion.travel(t) / self.scales.a
    }

    /// The supplied layer's thickness `l0` [m].
    pub fn supply_thickness_m(&self) -> f64 {
        self.supply.thickness_m
    }

    /// How the surfaces move.
    pub fn motion(&self) -> &Kinematics {
        &self.motion
    }

    /// The speed steady rolling rolls at [m/s]: the speed before the motion starts (a
    /// steady-rolling start, then a stop, rolls at the scene's speed first).
    pub fn rolling_speed(&self) -> f64 {
        self.motion.speed_before()
    }

    /// Cells the layer moves in the step from `t` to `t + dt` [s].
    pub fn cells_in_step(&self, t: f64, dt: f64) -> f64 {
        self.motion.travel_in_step(t, dt) / (self.scales.a * self.grid.dx())
    }

    /// Supply thickness field `L0(x, t)` [a²/R]: `l0`, zero inside holes (the core's
    /// [`Supply::thickness_at`], in the model's units).
    pub fn supply(&self, t: f64) -> Array2<f64> {
        if self.supply.holes.is_empty() {
            return Array2::from_elem(self.grid.shape(), self.l0);
        }
        let (travel, delta) = (self.travel_a(t), self.scales.delta);
        self.grid.field(|x, y| self.supply.thickness_at(x, y, travel) / delta)
    }

    /// Rigid gap of the ball: `f + b(t)` [a²/R].
    pub fn ball(&self, t: f64) -> Array2<f64> {
        if self.relief.is_empty() {
            return self.shape.clone();
        }
        let (travel, delta) = (self.travel_a(t), self.scales.delta);
        &self.shape + &self.relief.gap_on(&self.grid, travel, delta)
    }

    /// Layer thickness `L = L0 (1 − ε)` [a²/R] at time `t`.
    pub fn thickness(&self, eps: &Array2<f64>, t: f64) -> Array2<f64> {
        let mut l = self.supply(t);
        Zip::from(&mut l).and(eps).for_each(|l, &e| *l *= 1.0 - e);
        l
    }

    /// Where the solids touch in state `s`: the loaded points with no layer left between them
    /// (thinner than a millionth of the supply), the load they carry, their area and pressure.
    pub fn solid_contact(&self, s: &LayerState) -> ehl_core::SolidContact {
        solid_contact(&self.grid, &self.scales, &s.p, &s.thickness(self), self.l0)
    }

    /// Solves the contact for a rigid gap `g0` and optional compliance (Hertz units).
    pub fn contact(
        &self,
        g0: &Array2<f64>,
        compliance: Option<&Array2<f64>>,
        p: &mut Array2<f64>,
        w: &mut Array2<f64>,
        start: Start,
    ) -> Result<DryReport, NumericError> {
        self.contact_to(g0, compliance, p, w, start, self.solver.settings.tolerance)
    }

    /// [`LayerModel::contact`] to the stop residual `tolerance` [a²/R].
    pub fn contact_to(
        &self,
        g0: &Array2<f64>,
        compliance: Option<&Array2<f64>>,
        p: &mut Array2<f64>,
        w: &mut Array2<f64>,
        start: Start,
        tolerance: f64,
    ) -> Result<DryReport, NumericError> {
        let prob = DryProblem {
            rigid_gap: g0.view(),
            compliance: compliance.map(|c| c.view()),
            load: self.load,
        };
        self.solver.solve_to(&prob, p, w, start, tolerance)
    }
}

/// `f` smoothed by a separable Gaussian of standard deviations `sigma_x`, `sigma_y` [a]
/// (0: not along that axis), truncated at 3σ, edge values held.
pub fn gaussian_smooth(f: &Array2<f64>, grid: &Grid, sigma_x: f64, sigma_y: f64) -> Array2<f64> {
    let weights = |sigma: f64, h: f64| -> Vec<f64> {
        if sigma <= 0.0 {
            return vec![1.0];
        }
        let r = (3.0 * sigma / h).ceil() as isize;
        let w: Vec<f64> = (-r..=r).map(|k| (-0.5 * (k as f64 * h / sigma).powi(2)).exp()).collect();
        let norm: f64 = w.iter().sum();
        w.into_iter().map(|v| v / norm).collect()
    };
    let (ny, nx) = f.dim();
    // Along x: each row on its own.
    let wx = weights(sigma_x, grid.dx());
    let rx = (wx.len() / 2) as isize;
    let mut tmp = Array2::zeros((ny, nx));
    Zip::from(tmp.rows_mut()).and(f.rows()).par_for_each(|mut o, f| {
        let f = f.to_vec();
        for i in 0..nx as isize {
            let mut s = 0.0;
            if i >= rx && i + rx < nx as isize {
                // Inside: a plain window, no edge clamping (same terms, same order).
                let win = &f[(i - rx) as usize..=(i + rx) as usize];
                for (w, v) in wx.iter().zip(win) {
                    s += w * v;
                }
            } else {
                for (k, w) in (-rx..=rx).zip(&wx) {
                    s += w * f[(i + k).clamp(0, nx as isize - 1) as usize];
                }
            }
            o[i as usize] = s;
        }
    });
    // Along y: each output row is a weighted sum of whole rows.
    let wy = weights(sigma_y, grid.dy());
    let ry = (wy.len() / 2) as isize;
    let mut out = Array2::zeros((ny, nx));
    Zip::indexed(out.rows_mut()).par_for_each(|j, mut o| {
        for (k, w) in (-ry..=ry).zip(&wy) {
            let jj = (j as isize + k).clamp(0, ny as isize - 1) as usize;
            o.scaled_add(*w, &tmp.row(jj));
        }
    });
    out
}

/// The contact solved with a layer whose strain is affine in the local pressure.
pub struct AffineLayerSolve {
    /// Strain `ε = min(A + B p, 1)`, 1 where no layer is left.
    pub eps: Array2<f64>,
    /// Approach `H0` [a²/R].
    pub h0: f64,
    /// Contact solves (one, plus one per growth of the no-layer set) and their iterations.
    pub solves: usize,
    /// Contact iterations of the step.
    pub iterations: usize,
}

impl LayerModel {
    /// Solves the contact with the layer `ε = A + B p` (per point, `p ≥ 0`) on the ball's rigid
    /// gap `ball` and supply `supply`: the layer is extra gap `−l0 (1 − A)` and local compliance
    /// `l0 B`. Where `ε` would pass 1 the layer is gone: those points are fixed at `ε = 1` (no
    /// layer, no compliance) and the contact is re-solved, up to 8 passes. Both the implicit
    /// time step and the direct steady solve reduce to this. `tolerance`: the contact's stop
    /// residual [a²/R] (`None`: the solver's settings).
    #[allow(clippy::too_many_arguments)]
    pub fn contact_with_affine_layer(
        &self,
        ball: &Array2<f64>,
        supply: &Array2<f64>,
        a: &Array2<f64>,
        b: &Array2<f64>,
        p: &mut Array2<f64>,
        w: &mut Array2<f64>,
        start: Start,
        tolerance: Option<f64>,
    ) -> Result<AffineLayerSolve, NumericError> {
        let tolerance = tolerance.unwrap_or(self.solver.settings.tolerance);
        // Points already at ε ≥ 1 for any p ≥ 0 start dry.
        let mut dry = a.mapv(|v| v >= 1.0);
        let (mut solves, mut iterations, mut start) = (0, 0, start);
        loop {
            let mut g0 = ball.clone();
            let mut c = Array2::zeros(p.dim());
            Zip::from(&mut g0).and(&mut c).and(supply).and(a).and(b).and(&dry).par_for_each(
                |g, c, &l0, &a, &b, &d| {
                    if !d {
                        *g -= l0 * (1.0 - a);
                        *c = l0 * b;
                    }
                },
            );
            let r = self.contact_to(&g0, Some(&c), p, w, start, tolerance)?;
            start = Start::Warm;
            solves += 1;
            iterations += r.iterations;
            let mut eps = Zip::from(a)
                .and(b)
                .and(&*p)
                .and(&dry)
                .par_map_collect(|&a, &b, &p, &d| if d { 1.0 } else { (a + b * p).max(0.0) });
            // Where the layer would be squeezed past nothing, fix it at nothing and re-solve.
            let mut grew = false;
            Zip::from(&mut dry).and(&eps).and(supply).for_each(|d, &e, &l0| {
                if !*d && e > 1.0 && l0 > 0.0 {
                    *d = true;
                    grew = true;
                }
            });
            if !grew || solves >= 8 {
                eps.mapv_inplace(|v| v.min(1.0));
                return Ok(AffineLayerSolve { eps, h0: r.h0, solves, iterations });
            }
        }
    }
}

/// The state of a run: strain, pressure and deformation at time `t`.
#[derive(Clone, Debug)]
pub struct LayerState {
    /// Time [s].
    pub t: f64,
    /// Strain `ε ∈ [0, 1]`.
    pub eps: Array2<f64>,
    /// Pressure `P` [p_h].
    pub p: Array2<f64>,
    /// Deformation `W` [a²/R].
    pub w: Array2<f64>,
    /// Approach term `H0` [a²/R].
    pub h0: f64,
}

/// "No layer left": a layer thinner than this share of the supply, where the solids touch.
pub const NO_LAYER_LEFT: f64 = 1e-6;

/// Where the solids touch under pressure `p` [p_h] with layer thickness `l` [a²/R] on `grid`
/// (a supply `l0` [a²/R]): the loaded points with no layer left ([`NO_LAYER_LEFT`]).
pub fn solid_contact(
    grid: &ehl_core::Grid,
    scales: &ehl_core::HertzScales,
    p: &Array2<f64>,
    l: &Array2<f64>,
    l0: f64,
) -> ehl_core::SolidContact {
    let touching = l.mapv(|v| v <= NO_LAYER_LEFT * l0);
    ehl_core::SolidContact::from_mask(grid, scales, p, &touching)
}

impl LayerState {
    /// Layer thickness `L` [a²/R].
    pub fn thickness(&self, model: &LayerModel) -> Array2<f64> {
        model.thickness(&self.eps, self.t)
    }

    /// Gap `H = H0 + f + b(t) + W − L` [a²/R] (zero where the surfaces carry pressure).
    pub fn gap(&self, model: &LayerModel) -> Array2<f64> {
        model.ball(self.t) + &self.w - &self.thickness(model) + self.h0
    }
}

/// What only the layer model has to report about a state, in SI: the layer itself, the dry
/// zone, the approach, the lateral wiggle. The quantities every model shares (films, maximum
/// pressure, contact extents) are the core's observables (`ehl_core::Observables`), defined
/// once, and not repeated here.
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
pub struct Monitor {
    /// Time [s].
    #[serde(skip)]
    pub t: f64,
    /// Layer thickness at the contact centre [m].
    #[serde(rename = "central_layer_thickness_m")]
    pub central_thickness: f64,
    /// Smallest layer thickness where the surfaces carry pressure [m].
    #[serde(rename = "minimum_layer_thickness_loaded_m")]
    pub minimum_thickness: f64,
    /// Extent of the loaded zone with no layer left along `y = 0` [m].
    #[serde(rename = "dry_diameter_m")]
    pub dry_diameter: f64,
    /// The share of the load the solids carry where no layer is left between them (the
    /// layer model's mixed lubrication: [`ehl_core::SolidContact`] over the loaded points
    /// with no layer) [-] …
    #[serde(rename = "contact_load_share")]
    pub contact_load_share: f64,
    /// … and their area [m²].
    #[serde(rename = "contact_area_m2")]
    pub contact_area: f64,
    /// Mutual approach `−h0` [m].
    #[serde(rename = "approach_m")]
    pub approach: f64,
    /// Pressure at the contact centre [Pa].
    #[serde(rename = "central_pressure_pa")]
    pub central_pressure: f64,
    /// Row-to-row odd-even wiggle of the pressure [Pa] (see [`lateral_wiggle`]): the signature
    /// of the lateral short-wave instability; ~0 for smooth fields.
    #[serde(rename = "lateral_wiggle_pa")]
    pub lateral_wiggle: f64,
    /// Contact-solver iterations spent on the step that led here.
    pub iterations: usize,
}

/// Extent `(last − first + 1) ΔX` of the points of `row` where `pred` holds [a].
fn extent(row: impl Iterator<Item = bool>, dx: f64) -> f64 {
    let idx: Vec<usize> = row.enumerate().filter(|(_, b)| *b).map(|(i, _)| i).collect();
    match (idx.first(), idx.last()) {
        (Some(a), Some(b)) => (b - a + 1) as f64 * dx,
        _ => 0.0,
    }
}

/// Row-to-row odd-even wiggle of `p`: with `w_j = p_j − (p_{j−1} + p_{j+1})/2`, the largest
/// `min(|w_j|, |w_{j+1}|)` where `w_j` and `w_{j+1}` have opposite signs. A smooth field, even
/// with the square-root edge of a contact, gives same-signed neighbours and ~0; the lateral
/// short-wave instability gives alternating signs. In the units of `p`.
pub fn lateral_wiggle(p: &Array2<f64>) -> f64 {
    let ny = p.nrows();
    let w = |j: usize, i: usize| p[[j, i]] - 0.5 * (p[[j - 1, i]] + p[[j + 1, i]]);
    let mut m = 0.0f64;
    for j in 1..ny.saturating_sub(2) {
        for i in 0..p.ncols() {
            let (a, b) = (w(j, i), w(j + 1, i));
            if a * b < 0.0 {
                m = m.max(a.abs().min(b.abs()));
            }
        }
    }
    m
}

impl Monitor {
    /// The monitor of state `s` (SI), with the step's contact iterations.
    pub fn of(model: &LayerModel, s: &LayerState, iterations: usize) -> Self {
        let g = &model.grid;
        let sc = &model.scales;
        let l = s.thickness(model);
        let (j0, i0) = (g.row_nearest(0.0), g.col_nearest(0.0));
        let mut lmin = f64::INFINITY;
        Zip::from(&l).and(&s.p).for_each(|&l, &p| {
            if p > 0.0 {
                lmin = lmin.min(l);
            }
        });
        if !lmin.is_finite() {
            lmin = l.iter().cloned().fold(f64::INFINITY, f64::min);
        }
        let prow = s.p.row(j0);
        let lrow = l.row(j0);
        let dry_tol = NO_LAYER_LEFT * model.l0;
        let contact = solid_contact(g, sc, &s.p, &l, model.l0);
        Self {
            t: s.t,
            central_thickness: sc.h_si(l[[j0, i0]]),
            minimum_thickness: sc.h_si(lmin),
            dry_diameter: sc.x_si(extent(
                prow.iter().zip(lrow.iter()).map(|(&p, &l)| p > 0.0 && l <= dry_tol),
                g.dx(),
            )),
            contact_load_share: contact.load_share,
            contact_area: contact.area_m2,
            approach: sc.h_si(-s.h0),
            central_pressure: sc.p_si(s.p[[j0, i0]]),
            lateral_wiggle: sc.p_si(lateral_wiggle(&s.p)),
            iterations,
        }
    }
}
