//! Sweeps as data: a scene (built-in or file) and one or two of its parameters varied over a
//! list or a linear/logarithmic range. Checked like scenes (field-named errors) before anything
//! runs; every point's scene is built and validated up front.

use crate::{Check, GridSpec, Scene, SceneError, num};
use serde::{Deserialize, Serialize};
use std::path::Path;

/// A sweep. Unknown fields are refused.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Sweep {
    /// Short name, used for the output folder.
    pub name: String,
    #[serde(default)]
    /// One line on what the sweep asks.
    pub description: String,
    /// The scene: a built-in name or a path (relative to the sweep file's folder).
    pub scene: String,
    /// One or two parameters; with two, every combination runs (the first varies slowest).
    pub parameters: Vec<Axis>,
    /// Grow each point's domain and grid to what its physics needs (see `ehl_workbench::sweep`):
    /// on by default; off runs every point on the scene's own domain and grid.
    #[serde(default = "yes")]
    pub adapt: bool,
    /// With `adapt`, also refine each point's cells to what its thinnest film needs (the grid
    /// rule, `ehl_workbench::accuracy::rule`): on by default; off keeps the scene's cells (a coarse
    /// map on purpose).
    #[serde(default = "yes")]
    pub resolve: bool,
    /// Rerun each point on half the points and on a larger domain to measure how much its answer
    /// still depends on them: on by default.
    #[serde(default = "yes")]
    pub checks: bool,
    /// A point is flagged when the grid or domain check changes `h_c`, `h_min` or `p_max` by more
    /// than this (relative; default 0.02).
    #[serde(default = "default_flag")]
    pub flag_change_above: f64,
}

fn yes() -> bool {
    true
}
fn default_flag() -> f64 {
    0.02
}

/// A varied parameter and its values.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Axis {
    /// The field varied.
    pub parameter: Parameter,
    /// Explicit values …
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub values: Option<Vec<f64>>,
    /// … or `[from, to]` spaced evenly …
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub linear: Option<[f64; 2]>,
    /// … or `[from, to]` spaced evenly in the logarithm;
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub log: Option<[f64; 2]>,
    /// with this many points (ranges only).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub points: Option<usize>,
}

/// What a sweep can vary: the scene's own field names (SI), Moes' `M` and `L`, the grid.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
pub enum Parameter {
    #[serde(rename = "conditions.rolling_velocity_m_s")]
    /// The rolling speed [m/s].
    RollingVelocity,
    #[serde(rename = "conditions.load_n")]
    /// The load [N].
    Load,
    /// The oil supply's thickness (every model that reads a supply; the name it had when only
    /// the layer model did is still read).
    #[serde(rename = "supply.thickness_m", alias = "layer.supply_thickness_m")]
    SupplyThickness,
    #[serde(rename = "lubricant.eta0_pa_s")]
    /// The oil's viscosity at ambient pressure [Pa s].
    Eta0,
    #[serde(rename = "lubricant.alpha_per_pa")]
    /// The pressure–viscosity coefficient [1/Pa].
    Alpha,
    /// Moes' load parameter: sets the load and the velocity with `L`, `R`, `E'`, `η0`, `α` kept.
    #[serde(rename = "moes.m")]
    MoesM,
    /// Moes' lubricant parameter: sets the load and the velocity with `M`, `R`, `E'`, `η0`, `α` kept.
    #[serde(rename = "moes.l")]
    MoesL,
    /// Points per side (square grids).
    #[serde(rename = "grid.n")]
    GridPoints,
    /// The wavelength of the scene's waviness [m] (every wave of it).
    #[serde(rename = "run.features.waviness.wavelength_m")]
    Wavelength,
}

impl Parameter {
    /// The field name as written in sweep files.
    pub fn name(self) -> String {
        serde_json::to_value(self).unwrap().as_str().unwrap().to_string()
    }
    /// The unit, for tables and axes.
    pub fn unit(self) -> &'static str {
        match self {
            Self::RollingVelocity => "m/s",
            Self::Load => "N",
            Self::SupplyThickness | Self::Wavelength => "m",
            Self::Eta0 => "Pa s",
            Self::Alpha => "1/Pa",
            Self::MoesM | Self::MoesL | Self::GridPoints => "1",
        }
    }
}

impl Axis {
    /// The values, in the order given.
    pub fn values(&self) -> Vec<f64> {
        match (&self.values, self.linear, self.log, self.points) {
            (Some(v), ..) => v.clone(),
            (_, Some([a, b]), _, Some(n)) => (0..n)
                .map(|k| if n == 1 { a } else { a + (b - a) * k as f64 / (n - 1) as f64 })
                .collect(),
            (_, _, Some([a, b]), Some(n)) => (0..n)
                .map(|k| {
                    if k == 0 {
                        a
                    } else if k + 1 == n {
                        b
                    } else {
                        (a.ln() + (b.ln() - a.ln()) * k as f64 / (n - 1) as f64).exp()
                    }
                })
                .collect(),
            _ => vec![],
        }
    }
    /// Whether charts use a log axis: a `log` range, or positive values spanning a decade or more
    /// (a 1-2-5 list).
    pub fn is_log(&self) -> bool {
        let v = self.values();
        let (lo, hi) = v.iter().fold((f64::INFINITY, 0.0f64), |(l, h), &x| (l.min(x), h.max(x)));
        self.log.is_some() || (lo > 0.0 && hi / lo >= 10.0)
    }
}

/// The most points a sweep may hold: a 100 × 100 map; more is a typo, not a study.
pub const MAX_POINTS: usize = 10_000;

impl Sweep {
    /// Parses and checks; `origin` names the source in error messages.
    pub fn from_json(text: &str, origin: &str) -> Result<Sweep, SceneError> {
        let sweep: Sweep = crate::parse(text, origin)?;
        sweep.validate(origin)?;
        Ok(sweep)
    }

    /// The sweep as JSON.
    pub fn to_json(&self) -> String {
        serde_json::to_string_pretty(self).unwrap()
    }

    /// Range checks of the sweep itself (the points' scenes are checked by [`Sweep::points`]).
    pub fn validate(&self, origin: &str) -> Result<(), SceneError> {
        let ck = Check { origin };
        ck.name(&self.name)?;
        if !(1..=2).contains(&self.parameters.len()) {
            return Err(ck.err(
                "parameters",
                format!("{} entries", self.parameters.len()),
                "one or two parameters",
            ));
        }
        if self.parameters.len() == 2
            && self.parameters[0].parameter == self.parameters[1].parameter
        {
            return Err(ck.err(
                "parameters[1].parameter",
                self.parameters[1].parameter.name(),
                "a different parameter from parameters[0]",
            ));
        }
        let moes: Vec<_> = self
            .parameters
            .iter()
            .filter(|a| matches!(a.parameter, Parameter::MoesM | Parameter::MoesL))
            .collect();
        if !moes.is_empty()
            && let Some(other) = self.parameters.iter().find(|a| {
                matches!(
                    a.parameter,
                    Parameter::RollingVelocity
                        | Parameter::Load
                        | Parameter::Eta0
                        | Parameter::Alpha
                )
            })
        {
            return Err(ck.err(
                    "parameters",
                    format!("{} with {}", moes[0].parameter.name(), other.parameter.name()),
                    "Moes' M and L set the load and the velocity from R, E', eta0 and alpha: vary them with each other or with the grid or supply thickness, not with load, velocity, eta0 or alpha",
                ));
        }
        let mut total = 1usize;
        for (k, a) in self.parameters.iter().enumerate() {
            let f = |s: &str| format!("parameters[{k}].{s}");
            let given = [a.values.is_some(), a.linear.is_some(), a.log.is_some()];
            if given.iter().filter(|&&g| g).count() != 1 {
                return Err(ck.err(
                    &f("values"),
                    "(none or several)".into(),
                    "give exactly one of `values`, `linear` or `log`",
                ));
            }
            match (&a.values, a.points) {
                (Some(_), Some(n)) => {
                    return Err(ck.err(
                        &f("points"),
                        n.to_string(),
                        "only with `linear` or `log` (a `values` list gives its own count)",
                    ));
                }
                (None, None) => {
                    return Err(ck.err(&f("points"), "(missing)".into(), "required with a range"));
                }
                (None, Some(n)) if !(2..=100).contains(&n) => {
                    return Err(ck.err(&f("points"), n.to_string(), "must be 2 ..= 100"));
                }
                _ => {}
            }
            if let Some(v) = &a.values
                && (v.is_empty() || v.len() > 100)
            {
                return Err(ck.err(
                    &f("values"),
                    format!("{} values", v.len()),
                    "1 ..= 100 values",
                ));
            }
            if let Some([lo, hi]) = a.linear
                && !(lo.is_finite() && hi.is_finite() && lo != hi)
            {
                return Err(ck.err(
                    &f("linear"),
                    format!("[{lo}, {hi}]"),
                    "two different finite numbers",
                ));
            }
            if let Some([lo, hi]) = a.log
                && !(lo.is_finite() && hi.is_finite() && lo > 0.0 && hi > 0.0 && lo != hi)
            {
                return Err(ck.err(
                    &f("log"),
                    format!("[{lo}, {hi}]"),
                    "two different finite numbers > 0",
                ));
            }
            for v in a.values() {
                let ok = match a.parameter {
                    Parameter::GridPoints => v.fract() == 0.0 && (5.0..=4097.0).contains(&v),
                    Parameter::Alpha => v.is_finite() && v >= 0.0,
                    _ => v.is_finite() && v > 0.0,
                };
                if !ok {
                    let allowed = match a.parameter {
                        Parameter::GridPoints => {
                            "whole numbers 5 ..= 4097 (points per side)".to_string()
                        }
                        Parameter::Alpha => "finite and >= 0 (1/Pa)".to_string(),
                        p => format!("finite and > 0 ({})", p.unit()),
                    };
                    return Err(ck.err(&f("values"), num(v), &allowed));
                }
            }
            total = total.saturating_mul(a.values().len());
        }
        if total > MAX_POINTS {
            return Err(ck.err(
                "parameters",
                format!("{total} points"),
                &format!("at most {MAX_POINTS} points"),
            ));
        }
        let fl = self.flag_change_above;
        if !(fl.is_finite() && fl > 0.0 && fl < 1.0) {
            return Err(ck.err(
                "flag_change_above",
                num(fl),
                "must be in (0, 1) (relative change)",
            ));
        }
        Ok(())
    }

    /// Every combination of the parameters' values, the first parameter varying slowest.
    pub fn combinations(&self) -> Vec<Vec<f64>> {
        let mut out: Vec<Vec<f64>> = vec![vec![]];
        for a in &self.parameters {
            out = out
                .into_iter()
                .flat_map(|head| {
                    a.values().into_iter().map(move |v| {
                        let mut h = head.clone();
                        h.push(v);
                        h
                    })
                })
                .collect();
        }
        out
    }

    /// The base scene, the sweep file's folder resolving a relative path.
    pub fn base_scene(&self, sweep_dir: Option<&Path>) -> Result<Scene, SceneError> {
        if crate::builtin_names().contains(&self.scene.as_str()) {
            return crate::builtin(&self.scene);
        }
        let p = Path::new(&self.scene);
        let p = match sweep_dir {
            Some(d) if p.is_relative() => d.join(p),
            _ => p.to_path_buf(),
        };
        crate::load(&p.to_string_lossy())
    }

    /// Each point's scene (the base with the point's values set), validated; the first
    /// refusal names the point and its values.
    pub fn points(&self, base: &Scene) -> Result<Vec<(Vec<f64>, Scene)>, SceneError> {
        self.combinations()
            .into_iter()
            .enumerate()
            .map(|(k, vals)| {
                let mut s = base.clone();
                for (a, &v) in self.parameters.iter().zip(&vals) {
                    s = s.with_parameter(a.parameter, v).map_err(|e| SceneError::Range {
                        origin: format!("of sweep {} point {k}", self.name),
                        field: a.parameter.name(),
                        value: num(v),
                        allowed: e,
                    })?;
                }
                let origin = format!(
                    "of sweep {} point {k} ({})",
                    self.name,
                    self.parameters
                        .iter()
                        .zip(&vals)
                        .map(|(a, &v)| format!("{} = {}", a.parameter.name(), num(v)))
                        .collect::<Vec<_>>()
                        .join(", ")
                );
                s.validate(&origin)?;
                Ok((vals, s))
            })
            .collect()
    }
}

impl Scene {
    /// The scene with one sweep parameter set; the reason when this scene has no such parameter.
    pub fn with_parameter(&self, p: Parameter, v: f64) -> Result<Scene, String> {
        let mut s = self.clone();
        let moes_of_scene = |s: &Scene| -> Result<ehl_core::Moes, String> {
            let l = s.lubricant.ok_or("Moes parameters need the scene's lubricant")?;
            if let Some(m) = s.reynolds.as_ref().and_then(|r| r.moes) {
                return Ok(m);
            }
            let u = s.conditions.rolling_velocity_m_s.filter(|&u| u > 0.0);
            let u = u.ok_or("Moes parameters need a rolling velocity in the scene")?;
            Ok(ehl_core::Moes::from_si(&s.conditions.contact(), &l.lubricant(), 2.0 * u))
        };
        match p {
            Parameter::RollingVelocity => {
                if s.reynolds.as_ref().is_some_and(|r| r.moes.is_some()) {
                    return Err("the scene gives Moes M and L (they set the velocity): vary moes.m or moes.l".into());
                }
                // A march rolling at the scene's speed rolls the same travel at every point: its
                // time limit and snapshot times scale with the time the surfaces take over it.
                let before = s.conditions.rolling_velocity_m_s.filter(|&u| u > 0.0);
                if let (Some(u0), Some(run)) = (before, s.run.as_mut())
                    && run.motion == crate::Motion::Rolling
                    && v > 0.0
                {
                    let k = u0 / v;
                    run.stop.max_time_s = run.stop.max_time_s.map(|t| t * k);
                    run.snapshots_s.iter_mut().for_each(|t| *t *= k);
                }
                s.conditions.rolling_velocity_m_s = Some(v);
            }
            Parameter::Load => {
                if s.reynolds.as_ref().is_some_and(|r| r.moes.is_some()) {
                    return Err(
                        "the scene gives Moes M and L (they set the load): vary moes.m or moes.l"
                            .into(),
                    );
                }
                s.conditions.load_n = v;
            }
            Parameter::SupplyThickness => {
                let sup = s.supply.as_mut().ok_or("the scene has no supply to vary")?;
                sup.thickness_m = v;
            }
            Parameter::Eta0 => {
                s.lubricant.as_mut().ok_or("the scene has no lubricant")?.eta0_pa_s = v;
            }
            Parameter::Alpha => {
                s.lubricant.as_mut().ok_or("the scene has no lubricant")?.alpha_per_pa = v;
            }
            Parameter::MoesM | Parameter::MoesL => {
                let mut m = moes_of_scene(&s)?;
                if p == Parameter::MoesM {
                    m.m = v;
                } else {
                    m.l = v;
                }
                match s.reynolds.as_mut().filter(|r| r.moes.is_some()) {
                    Some(r) => r.moes = Some(m),
                    None => {
                        let l = s.lubricant.unwrap();
                        let c = &s.conditions;
                        let (load, u_sum) = m.to_load_and_velocity(
                            c.ball_radius_m,
                            c.reduced_modulus_pa,
                            l.eta0_pa_s,
                            l.alpha_per_pa,
                        );
                        s.conditions.load_n = load;
                        s.conditions.rolling_velocity_m_s = Some(0.5 * u_sum);
                    }
                }
            }
            Parameter::GridPoints => {
                let n = v as usize;
                s.grid = GridSpec { nx: n, ny: n };
            }
            Parameter::Wavelength => {
                let features = s.run.as_mut().map(|r| r.features.iter_mut());
                let waves: Vec<_> = features
                    .into_iter()
                    .flatten()
                    .filter_map(|f| match f {
                        crate::Feature::Waviness(w) => Some(w),
                        _ => None,
                    })
                    .collect();
                if waves.is_empty() {
                    return Err("the scene has no waviness to vary".into());
                }
                for w in waves {
                    w.wavelength_m = v;
                }
            }
        }
        Ok(s)
    }
}

macro_rules! builtin_sweeps {
    ($($name:literal),*) => {
        &[$(($name, include_str!(concat!("../../../validation/sweeps/", $name, ".json")))),*]
    };
}

const SWEEPS: &[(&str, &str)] = builtin_sweeps!(
    "seed-speed",
    "seed-speed-load",
    "seed-supply",
    "reynolds-thin",
    "waviness-reduction",
    "mixed-lubrication"
);

/// Names of the built-in sweeps.
pub fn builtin_sweep_names() -> Vec<&'static str> {
    SWEEPS.iter().map(|(n, _)| *n).collect()
}

/// A built-in sweep name, or else a path to a sweep JSON file; with the folder a relative scene
/// path is resolved against.
pub fn load_sweep(name_or_path: &str) -> Result<(Sweep, Option<std::path::PathBuf>), SceneError> {
    let path = Path::new(name_or_path);
    if let Some((n, text)) = SWEEPS.iter().find(|(n, _)| *n == name_or_path) {
        if path.is_file() {
            return Err(SceneError::Ambiguous { name: name_or_path.into(), kind: "sweep" });
        }
        return Ok((Sweep::from_json(text, &format!("`{n}` (built-in sweep)"))?, None));
    }
    if !path.exists() {
        return Err(SceneError::Io {
            path: name_or_path.into(),
            message: format!(
                "no built-in sweep or file of that name (built-in sweeps: {})",
                builtin_sweep_names().join(", ")
            ),
        });
    }
    let text = std::fs::read_to_string(path)
        .map_err(|e| SceneError::Io { path: name_or_path.into(), message: e.to_string() })?;
    let sweep = Sweep::from_json(&text, &format!("sweep file {name_or_path}"))?;
    Ok((sweep, path.parent().map(Path::to_path_buf)))
}

#[cfg(test)]
mod tests {
    use super::*;

    fn sweep(params: &str) -> Result<Sweep, SceneError> {
        Sweep::from_json(
            &format!(r#"{{"name": "t", "scene": "seed", "parameters": [{params}]}}"#),
            "test",
        )
    }

    #[test]
    fn builtin_sweeps_parse_and_their_points_validate() {
        for n in builtin_sweep_names() {
            let (s, dir) = load_sweep(n).unwrap();
            let base = s.base_scene(dir.as_deref()).unwrap();
            let pts = s.points(&base).unwrap();
            // A map, not a pair of points.
            assert!(pts.len() >= 6, "{n}: {} points", pts.len());
        }
    }

    #[test]
    fn ranges_give_their_ends_exactly_and_log_spacing() {
        let s = sweep(
            r#"{"parameter": "conditions.rolling_velocity_m_s", "log": [0.002, 1.0], "points": 9}"#,
        )
        .unwrap();
        let v = s.parameters[0].values();
        assert_eq!((v[0], v[8]), (0.002, 1.0));
        // Equal ratios: (1/0.002)^(1/8) = 2.1739...
        for w in v.windows(2) {
            assert!((w[1] / w[0] / 500f64.powf(0.125) - 1.0).abs() < 1e-12);
        }
        let s = sweep(r#"{"parameter": "conditions.load_n", "linear": [10, 30], "points": 5}"#)
            .unwrap();
        assert_eq!(s.parameters[0].values(), vec![10.0, 15.0, 20.0, 25.0, 30.0]);
    }

    #[test]
    fn two_parameters_give_every_combination_first_slowest() {
        let s = sweep(
            r#"{"parameter": "conditions.load_n", "values": [10, 20]},
               {"parameter": "conditions.rolling_velocity_m_s", "values": [0.01, 0.02, 0.03]}"#,
        )
        .unwrap();
        let c = s.combinations();
        assert_eq!(c.len(), 6);
        assert_eq!(c[0], vec![10.0, 0.01]);
        assert_eq!(c[2], vec![10.0, 0.03]);
        assert_eq!(c[3], vec![20.0, 0.01]);
    }

    #[test]
    fn a_march_swept_over_speed_rolls_the_same_travel_at_every_point() {
        // roughness-compare rolls two transits at 0.01 m/s in 0.067 s: at 0.1 m/s the same
        // travel takes a tenth of the time, its snapshots too.
        let base = crate::builtin("roughness-compare").unwrap();
        let run = |sc: &Scene| sc.run.clone().unwrap();
        let (t0, snaps0) = (run(&base).stop.max_time_s.unwrap(), run(&base).snapshots_s);
        let fast = base.with_parameter(Parameter::RollingVelocity, 0.1).unwrap();
        assert!((run(&fast).stop.max_time_s.unwrap() - 0.1 * t0).abs() < 1e-15);
        for (a, b) in run(&fast).snapshots_s.iter().zip(&snaps0) {
            assert!((a - 0.1 * b).abs() < 1e-15, "{a} against {b}");
        }
        // A march to a steady state: its time limit is a travel too (10 s at 0.01 m/s).
        let seed = crate::builtin("seed").unwrap();
        let s2 = seed.with_parameter(Parameter::RollingVelocity, 0.1).unwrap();
        let limit = s2.run.and_then(|r| r.stop.max_time_s).unwrap();
        assert!((limit - 1.0).abs() < 1e-12, "{limit}");
    }

    #[test]
    fn a_sweep_over_the_wavelength_sets_the_waves_and_refuses_what_the_grid_cannot_carry() {
        let base = crate::builtin("waviness-compare").unwrap();
        let s = |values: &str| {
            Sweep::from_json(
                &format!(
                    r#"{{"name": "w", "scene": "waviness-compare", "parameters": [{{"parameter": "run.features.waviness.wavelength_m", "values": {values}}}]}}"#
                ),
                "test",
            )
            .unwrap()
        };
        let pts = s("[2e-5, 6e-5]").points(&base).unwrap();
        let wave = |sc: &Scene| match &sc.run.as_ref().unwrap().features[0] {
            crate::Feature::Waviness(w) => w.wavelength_m,
            _ => f64::NAN,
        };
        assert_eq!(pts.iter().map(|(_, sc)| wave(sc)).collect::<Vec<_>>(), vec![2e-5, 6e-5]);
        // 5 µm on 129² over 2.5 a (cells of 2.6 µm): two cells a wave, refused by the scene's
        // own check, naming the sweep's point.
        let e = s("[5e-6]").points(&base).unwrap_err().to_string();
        assert!(e.contains("point 0") && e.contains("wavelength"), "{e}");
        // A scene without waviness has nothing to vary.
        let e = sweep(r#"{"parameter": "run.features.waviness.wavelength_m", "values": [2e-5]}"#)
            .unwrap()
            .points(&crate::builtin("seed").unwrap())
            .unwrap_err()
            .to_string();
        assert!(
            e.contains("run.features.waviness.wavelength_m") && e.contains("no waviness"),
            "{e}"
        );
    }

    #[test]
    fn bad_sweeps_name_the_field() {
        let e = |p: &str| sweep(p).unwrap_err().to_string();
        assert!(
            e(r#"{"parameter": "conditions.load_n", "log": [0, 1], "points": 3}"#)
                .contains("parameters[0].log")
        );
        assert!(
            e(r#"{"parameter": "conditions.load_n", "log": [1, 2]}"#)
                .contains("parameters[0].points")
        );
        assert!(e(r#"{"parameter": "conditions.load_n", "values": [1], "linear": [1, 2], "points": 2}"#)
            .contains("exactly one"));
        assert!(
            e(r#"{"parameter": "conditions.speed", "values": [1]}"#)
                .contains("parameters[0].parameter")
        );
        assert!(e(r#"{"parameter": "conditions.load_n", "values": [-1]}"#).contains("> 0 (N)"));
        assert!(e(r#"{"parameter": "grid.n", "values": [64.5]}"#).contains("whole numbers"));
        assert!(e(r#"{"parameter": "moes.m", "values": [20]}, {"parameter": "conditions.load_n", "values": [1]}"#)
            .contains("Moes"));
        let many = r#"{"parameter": "conditions.load_n", "linear": [1, 2], "points": 101}"#;
        assert!(e(many).contains("2 ..= 100"));
    }

    #[test]
    fn points_set_the_parameter_and_refuse_what_the_scene_lacks() {
        let base = crate::builtin("seed").unwrap();
        let s = sweep(r#"{"parameter": "moes.m", "values": [100]}"#).unwrap();
        let (_, p) = &s.points(&base).unwrap()[0];
        let l = p.lubricant.unwrap().lubricant();
        let m = ehl_core::Moes::from_si(
            &p.conditions.contact(),
            &l,
            2.0 * p.conditions.rolling_velocity_m_s.unwrap(),
        );
        let m0 = ehl_core::Moes::from_si(&base.conditions.contact(), &l, 0.02);
        // M set, L kept (to rounding of the round trip through load and velocity).
        assert!((m.m / 100.0 - 1.0).abs() < 1e-12 && (m.l / m0.l - 1.0).abs() < 1e-12, "{m:?}");
        let hertz = sweep(r#"{"parameter": "supply.thickness_m", "values": [1e-8]}"#).unwrap();
        let e = hertz.points(&crate::builtin("hertz").unwrap()).unwrap_err().to_string();
        assert!(e.contains("supply.thickness_m") && e.contains("no supply"), "{e}");
        // A point whose scene fails validation is refused with its values named.
        let g = sweep(r#"{"parameter": "grid.n", "values": [129, 4]}"#);
        assert!(g.is_err());
    }
}
