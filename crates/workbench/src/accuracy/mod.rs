//! How good an answer is, and the grid an answer needs.
//!
//! - [`gci`]: an observable's discretisation error from three grids (the observed order,
//!   Roache's grid convergence index), with the fallbacks where the grids show no order.
//! - [`rule`]: the domain and grid a scene needs for answers within an accuracy (each model's
//!   own rule), and the check runs that measure how much an answer still depends on them.
//! - [`estimate`]: every standard observable of an answer with its estimated error, from the
//!   answer's own grid and the same model on half and a quarter of the points per side; the
//!   flags an answer carries (an error beyond the limit, with the grid that would meet it; a
//!   film that went below zero; an error that could not be estimated).

pub mod gci;
pub mod rule;

use crate::model::Outcome;
use ehl_core::Observables;
use ehl_core::Passage;
use ehl_core::observe::{ErrorBar, Estimate, PassageErrors};
use ehl_scene::Scene;

pub use ehl_core::observe::OBSERVED;

/// The estimated error beyond which an answer is flagged when no accuracy was asked for.
pub const DEFAULT_LIMIT: f64 = 0.05;

/// The least scale a film's change is judged on [m]: a nanometre, a few molecular diameters
/// of a mineral oil. Below it neither model's continuum film has digits that mean anything,
/// and a relative change there measures the solver's rounding: a layer squeezed out to a
/// fifth of a nanometre, its solids touching to picometres, would otherwise be flagged for
/// its picometres (the sweep's test
/// `picometre_changes_of_a_squeezed_out_film_are_judged_on_a_nanometre_not_flagged`). No
/// Reynolds film is that thin.
pub const FILM_SCALE_FLOOR_M: f64 = 1e-9;

/// The scale an answer's film changes are judged on: its central film, at least
/// [`FILM_SCALE_FLOOR_M`].
pub fn film_scale(central_film_m: f64) -> f64 {
    central_film_m.max(FILM_SCALE_FLOOR_M)
}

/// The observables of [`OBSERVED`] of an answer, in their order.
fn values(o: &Observables) -> [f64; 5] {
    o.standard()
}

/// The scales the observables' errors are relative to: the films' the film scale
/// ([`film_scale`]: a minimum film near zero, the solids touching, has no relative change of
/// its own), the others their own value.
fn scales(o: &Observables) -> [f64; 5] {
    let film = film_scale(o.central_film_m);
    [film, film, o.max_pressure_pa, o.contact_extent_x_m, o.contact_extent_y_m]
}

/// The relative changes from `b` to `a` of [`OBSERVED`], over `b`'s scales; films
/// only where there is a film (`lubricated`: not the dry contact's zero gap).
pub fn changes(a: &Observables, b: &Observables, lubricated: bool) -> [Option<f64>; 5] {
    let (va, vb, sb) = (values(a), values(b), scales(b));
    std::array::from_fn(|k| {
        Some((va[k] - vb[k]) / sb[k]).filter(|v| v.is_finite() && (lubricated || k >= 2))
    })
}

/// The estimated grid errors of [`OBSERVED`] of the answer `point` from the half grid's answer
/// and the quarter's (when it answered), each relative to the answer's scale;
/// films only for lubricated models.
pub fn grid_errors(
    point: &Observables,
    half: &Observables,
    quarter: Option<&Observables>,
    lubricated: bool,
) -> [Option<gci::GridError>; 5] {
    let (f1, f2, f3, sc) = (values(point), values(half), quarter.map(values), scales(point));
    std::array::from_fn(|k| {
        (lubricated || k >= 2)
            .then(|| gci::grid_error(f1[k], f2[k], f3.map(|f| f[k]), sc[k]))
            .flatten()
    })
}

/// The half grid of `n` points per side: the multigrid's next coarser (`(n − 1)/2 + 1`).
fn half(n: usize) -> usize {
    (n - 1).div_ceil(2) + 1
}

/// The coarsest grid an estimate runs on: below it no model's answer means anything.
const LEAST_POINTS: usize = 5;

/// Estimates the error of `answer` (the outcome of the one-model `scene`) by running the same
/// model on half and a quarter of the points per side over the same domain ([`gci`]): three
/// grids give the order and the grid convergence index; a quarter grid without an answer (a
/// film that does not exist on it) leaves the half's change itself as the estimate, order 2
/// assumed; a half grid without one leaves no estimate, and says why. A film that went below
/// zero ([`Observables::film_overlap_m`]) counts as an error of the minimum film at least
/// that large.
pub fn estimate(scene: &Scene, answer: &dyn Outcome) -> Estimate {
    let t0 = std::time::Instant::now();
    let point = answer.observables();
    let lubricated = answer.lubricated();
    let model = scene.model().and_then(|k| crate::run::model(k).ok());
    let (grids, half, quarter) = coarser_answers(scene, model, answer);
    let law = model.and_then(|m| m.film_error_law(scene)).filter(|_| lubricated);
    let (mut errors, method) = match (&half, law) {
        (Err(why), Some((err, law))) => {
            // No coarser grid answers: the films' error from the model's measured law.
            let scale = film_scale(point.central_film_m);
            let bar = Some(ErrorBar { relative: err, absolute: err * scale, order: None });
            let mut es = [None; 5];
            es[0] = bar;
            es[1] = bar;
            (es, format!("of the films from {law}: no coarser grid answers ({why})"))
        }
        (Err(why), None) => ([None; 5], format!("not estimated: {why}")),
        (Ok(h), _) => {
            let q = quarter.as_ref().map(|q| &q.observables);
            let mut es = grid_errors(&point, &h.observables, q, lubricated);
            let verified = model.and_then(|m| m.verified_order());
            let method = match (&quarter, verified) {
                (Some(_), _) => format!(
                    "three grids ({}), the observed order and Roache's grid convergence index",
                    side_list(&grids)
                ),
                (None, Some((p, where_))) => {
                    // The change at the model's measured order, Roache's factor 1.25.
                    for e in es.iter_mut().flatten() {
                        e.error *= gci::SAFETY_THREE_GRIDS / (p.exp2() - 1.0);
                    }
                    format!(
                        "two grids ({}; the quarter grid has no answer) at the solver's order {p} ({where_}), Roache's factor 1.25",
                        side_list(&grids)
                    )
                }
                (None, None) => format!(
                    "two grids ({}; the quarter grid has no answer): the change itself, order 2 assumed",
                    side_list(&grids)
                ),
            };
            let sc = scales(&point);
            let bar = |k: usize| {
                es[k].map(|e| ErrorBar {
                    relative: e.error,
                    absolute: e.error * sc[k],
                    order: e.order,
                })
            };
            (std::array::from_fn(bar), method)
        }
    };
    floors(scene, answer, &mut errors);
    let method = match answer.film_resolution_m() {
        Some(0.0) => format!("{method}; the films: none on any grid (no oil)"),
        Some(r) => format!(
            "{method}; the films: the closed film, known to the thinnest film this grid tells from a closed gap ({:.3} nm)",
            r * 1e9
        ),
        None => method,
    };
    let passage = passage_errors(answer, half.as_ref().ok(), quarter.as_ref());
    Estimate { grids, errors, method, wall_time_s: t0.elapsed().as_secs_f64(), passage }
}

/// The least share of the load the solids' share is judged on: a thousandth. Below it the film
/// carries the contact by any standard (the mixed-lubrication map's shares from `λ` ≈ 1.7 up),
/// and a relative change of a share of a millionth would flag a full-film answer for the crest
/// or two its grid happens to close. The solids' area is judged on the same fraction of the
/// Hertz area `πa²`.
pub const SHARE_SCALE_FLOOR: f64 = 1e-3;

/// The errors of the last passage's statistics of `answer` from the same passage on the
/// coarser grids ([`gci::grid_error`]: three grids, or the half grid's change itself): the mean
/// central film on the film's scale, the solids' mean share and area on theirs (at least
/// [`SHARE_SCALE_FLOOR`]), a wave's `A_d/A_i` on itself.
fn passage_errors(
    answer: &dyn Outcome,
    half: Option<&Coarse>,
    quarter: Option<&Coarse>,
) -> PassageErrors {
    let (Some(p1), Some(p2)) = (answer.passage(), half.and_then(|h| h.passage)) else {
        return PassageErrors::default();
    };
    let p3 = quarter.and_then(|q| q.passage);
    let bar = |get: fn(&Passage) -> Option<f64>, scale: &dyn Fn(f64) -> f64| {
        let (f1, f2) = (get(&p1)?, get(&p2)?);
        let scale = scale(f1);
        let e = gci::grid_error(f1, f2, p3.as_ref().and_then(get), scale)?;
        Some(ErrorBar { relative: e.error, absolute: e.error * scale, order: e.order })
    };
    let hertz_area = std::f64::consts::PI * answer.scales().a.powi(2);
    PassageErrors {
        central_film_mean: bar(|p| Some(p.central_film_mean_m), &film_scale),
        contact_load_share_mean: bar(|p| p.contact_load_share_mean, &|s| s.max(SHARE_SCALE_FLOOR)),
        contact_area_mean: bar(|p| p.contact_area_mean_m2, &|s| {
            s.max(SHARE_SCALE_FLOOR * hertz_area)
        }),
        amplitude_ratio: bar(|p| p.amplitude_ratio, &|r| r),
    }
}

/// A coarser grid's answer: its observables, and its last passage where a pattern rolled.
struct Coarse {
    observables: Observables,
    passage: Option<ehl_core::Passage>,
}

/// The answers of the same model on half and a quarter of the points per side (at once: neither
/// keeps both cores busy), with the grids that answered (the answer's own first): the half's
/// answer or why there is none, the quarter's when it answered. A coarser grid whose cells are
/// wider than the model's answer can exist on is not run: it would only fail, slowly (a Reynolds
/// film that closes runs its whole cascade of attempts). The models' rule asks for half the cell
/// where existence ends (docs/decisions.md, "The grid rule's constants"), so twice the rule's
/// cell.
fn coarser_answers(
    scene: &Scene,
    model: Option<&'static dyn crate::model::ContactModel>,
    answer: &dyn Outcome,
) -> (Vec<usize>, Result<Coarse, String>, Option<Coarse>) {
    let (n, m) = (scene.grid.nx, scene.grid.ny);
    let coarser = |k: usize| -> Option<Scene> {
        let (mut a, mut b) = (n, m);
        for _ in 0..k {
            (a, b) = (half(a), half(b));
        }
        (a.min(b) >= LEAST_POINTS && (a, b) != (n, m)).then(|| {
            let mut s = scene.clone();
            s.grid = ehl_scene::GridSpec { nx: a, ny: b };
            s.outputs = ehl_scene::Outputs { centreline: false, fields: false, figures: false };
            s
        })
    };
    let exists_on = model.map_or(f64::INFINITY, |m| 2.0 * m.cell_needed(scene, f64::INFINITY));
    let cell = |s: &Scene| {
        let d = &s.domain;
        ((d.x_a[1] - d.x_a[0]) / (s.grid.nx - 1) as f64)
            .max((d.y_a[1] - d.y_a[0]) / (s.grid.ny - 1) as f64)
    };
    // A coarser grid that cannot carry the surfaces' pattern answers for another surface.
    let shortest = scene.relief(answer.scales().a).ok().and_then(|r| r.shortest_wave_a());
    let run = |s: &Option<Scene>| -> Option<Result<Coarse, String>> {
        let s = s.as_ref()?;
        if cell(s) > exists_on * (1.0 + 1e-9) {
            return Some(Err(format!(
                "cells of {:.4} a, wider than the {:.4} a its answer can exist on",
                cell(s),
                exists_on
            )));
        }
        if let Some(w) = shortest.filter(|w| w / cell(s) < ehl_scene::MIN_CELLS_PER_WAVELENGTH) {
            return Some(Err(format!(
                "cells of {:.4} a carry the surfaces' shortest wave ({w:.4} a) on {:.1} of them, fewer than {}",
                cell(s),
                w / cell(s),
                ehl_scene::MIN_CELLS_PER_WAVELENGTH
            )));
        }
        let o = run_check(s, answer);
        let coarse =
            |o: Box<dyn Outcome>| Coarse { observables: o.observables(), passage: o.passage() };
        Some(o.map(coarse).map_err(|e| e.class().to_string()))
    };
    let (s1, s2) = (coarser(1), coarser(2));
    let (r1, r2) = rayon::join(|| run(&s1), || run(&s2));
    let mut grids = vec![n];
    match (r1, &s1) {
        (Some(Ok(h)), Some(s1)) => {
            grids.push(s1.grid.nx);
            let q = match (r2, &s2) {
                (Some(Ok(q)), Some(s2)) => {
                    grids.push(s2.grid.nx);
                    Some(q)
                }
                _ => None,
            };
            (grids, Ok(h), q)
        }
        (Some(Err(e)), Some(s1)) => {
            (grids, Err(format!("the half grid ({}²) has no answer: {e}", s1.grid.nx)), None)
        }
        _ => (grids, Err("the grid has no coarser one to compare with".to_string()), None),
    }
}

/// Runs `check`, the scene of `answer` on coarser cells (an estimate's coarser grid; a sweep's
/// grid or domain check, whose domain may hold the answer's), as an estimate runs its coarser
/// grids: within the bounds its model sets an estimate ([`ContactModel::for_estimate`]), started
/// from the answer where the model can ([`ContactModel::run_coarser`]).
///
/// [`ContactModel::for_estimate`]: crate::model::ContactModel::for_estimate
/// [`ContactModel::run_coarser`]: crate::model::ContactModel::run_coarser
pub fn run_check(check: &Scene, answer: &dyn Outcome) -> crate::error::Result<Box<dyn Outcome>> {
    match check.model().and_then(|k| crate::run::model(k).ok()) {
        Some(m) => crate::run::run_coarser(&m.for_estimate(check.clone()), answer),
        None => crate::run::run_scene(check),
    }
}

/// The least error a film is given, relative to the film's scale: the solvers stop at a change
/// of 1e-4 a cycle (the Reynolds solve) or settle within 1e-3 over a window (the layer's steady
/// solve), and below this the grids' differences measure those iterations, not the grid: below
/// it the three grids understated the actual film errors (`docs/measured/accuracy.md`).
pub const FILM_FLOOR: f64 = 3e-3;

/// The least each error can be, whatever the grids say. An extent ends where the pressure
/// crosses its threshold, somewhere inside a cell at each end: at least a cell's width wrong
/// (the grids can agree by chance: the dry contact's 2a is 1.34, 1.37, 1.29 % long on 33²,
/// 65², 129², then 0.46 % on 257²). A film is at least [`FILM_FLOOR`] wrong, and one that went
/// below zero at least that much.
fn floors(scene: &Scene, answer: &dyn Outcome, errors: &mut [Option<ErrorBar>; 5]) {
    let point = answer.observables();
    let has_bar = [errors[0].is_some(), errors[1].is_some()];
    if let Some(r) = answer.film_resolution_m() {
        // The closed film of a grid that cannot tell a thinner one from contact: known to that
        // film, whatever the coarser grids (closed as well) or the grid law (measured for
        // films the grid resolves) say.
        let film = film_scale(point.central_film_m);
        for (k, has) in [(0, has_bar[0]), (1, has_bar[1])] {
            if has {
                errors[k] = Some(ErrorBar { relative: r / film, absolute: r, order: None });
            }
        }
    }
    let mut at_least = |k: usize, absolute: f64, scale: f64| {
        let least = absolute / scale;
        let bar = errors[k].get_or_insert(ErrorBar { relative: 0.0, absolute: 0.0, order: None });
        if bar.relative < least {
            *bar = ErrorBar { relative: least, absolute, order: bar.order };
        }
    };
    let g = scene.grid();
    for (k, cell) in [(3, g.dx()), (4, g.dy())] {
        let extent = values(&point)[k];
        if extent > 0.0 {
            at_least(k, answer.scales().x_si(cell), extent);
        }
    }
    let film = film_scale(point.central_film_m);
    // Only films with an estimate: a film not estimated stays so, and says so.
    for (k, has) in [(0, has_bar[0]), (1, has_bar[1])] {
        if has {
            at_least(k, FILM_FLOOR * film, film);
        }
    }
    if answer.lubricated() && point.film_overlap_m > 0.0 {
        at_least(1, point.film_overlap_m, film);
    }
}

/// How an answer is checked: whether its error is estimated, and the limit it is judged
/// against (the accuracy asked, or [`DEFAULT_LIMIT`]).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Checking {
    /// Estimate the error (on by default: off saves the coarser runs, and says so).
    pub estimate: bool,
    /// The relative error beyond which an answer is flagged.
    pub limit: f64,
}

impl Checking {
    /// The checks a scene asks for: its `accuracy` as the limit (else [`DEFAULT_LIMIT`]), the
    /// error estimated unless `estimate` is false.
    pub fn of(scene: &Scene, estimate: bool) -> Self {
        Self { estimate, limit: scene.accuracy.unwrap_or(DEFAULT_LIMIT) }
    }
}

/// The scene an answer within its asked accuracy runs on: with `accuracy` set, the domain and
/// grid the accuracy rule gives for it ([`rule::adapt`], the finest any listed model needs,
/// never coarser than the scene's own); else the scene itself. `Some(what changed)` when the
/// grid or domain grew.
pub fn resolved(scene: &Scene) -> (Scene, Option<String>) {
    match scene.accuracy {
        Some(a) => rule::adapt(scene, true, a),
        None => (scene.clone(), None),
    }
}

/// An answer with what is known of its accuracy: the model's outcome, its estimated error,
/// the limit it was judged against and the flags it carries. Itself an [`Outcome`] (every
/// method the model's own), so the writer, a comparison and Python take it as any answer:
/// its caveat adds the flags, its summary's shared part the errors, its figures' footnotes the
/// error bars.
pub struct Checked {
    /// The model's own outcome.
    pub outcome: Box<dyn Outcome>,
    /// Its estimated error (`None` when not estimated: asked not to).
    pub estimate: Option<Estimate>,
    /// The limit it was judged against.
    pub limit: f64,
    /// What it is flagged for (empty: within the limit).
    pub flags: Vec<String>,
}

impl Checked {
    /// `outcome` (of the one-model `scene`) checked as `how` asks.
    pub fn new(scene: &Scene, outcome: Box<dyn Outcome>, how: Checking) -> Self {
        let estimate = how.estimate.then(|| estimate(scene, outcome.as_ref()));
        let ob = outcome.observables();
        let flags = match &estimate {
            Some(e) => flags(scene, &ob, outcome.passage().as_ref(), e, how.limit),
            None => vec!["error not estimated (asked not to)".into()],
        };
        Self { outcome, estimate, limit: how.limit, flags }
    }

    /// The error bars in a line, for a figure's footnote: `; grid error: h_c ±0.31 nm
    /// (2.6 %), …`; empty without an estimate.
    pub fn footnote(&self) -> String {
        let Some(e) = &self.estimate else { return String::new() };
        let ob = self.outcome.observables();
        let v = [ob.central_film_m, ob.minimum_film_m, ob.max_pressure_pa];
        let parts: Vec<String> = (0..3)
            .filter_map(|k| {
                let b = e.errors[k]?;
                let (scale, unit) = if k == 2 { (1e-9, "GPa") } else { (1e9, "nm") };
                Some(format!(
                    "{} {} {unit}",
                    OBSERVED[k].0,
                    with_bar(v[k], Some(&b), scale, if k == 2 { 4 } else { 3 })
                ))
            })
            .collect();
        if parts.is_empty() {
            return format!("; error {}", e.method);
        }
        format!(
            "; grid error ({}): {}{}",
            side_list(&e.grids),
            parts.join(", "),
            self.passage_note()
        )
    }

    /// The last passage's mean film and solids' share with their error bars, for the footnote:
    /// `; last passage: h_c mean 9.230 ± 2.761 nm, solids' share 0.84 ± 0.83 %`; empty
    /// without a passage.
    fn passage_note(&self) -> String {
        let (Some(p), Some(e)) = (self.outcome.passage(), &self.estimate) else {
            return String::new();
        };
        let b = &e.passage;
        let film = with_bar(p.central_film_mean_m, b.central_film_mean.as_ref(), 1e9, 3);
        let share = p.contact_load_share_mean.map_or(String::new(), |s| {
            format!(
                ", solids' share {} %",
                with_bar(s, b.contact_load_share_mean.as_ref(), 100.0, 2)
            )
        });
        format!("; last passage: h_c mean {film} nm{share}")
    }
}

/// Runs the one-model `scene` on the grid its accuracy asks for ([`resolved`]) and checks its
/// answer as `how` asks: what `ehl run` and Python give.
pub fn run(scene: &Scene, estimate_error: bool) -> crate::error::Result<Checked> {
    let (scene, _) = resolved(scene);
    let outcome = crate::run::run_scene(&scene)?;
    Ok(Checked::new(&scene, outcome, Checking::of(&scene, estimate_error)))
}

impl Outcome for Checked {
    fn scene(&self) -> &Scene {
        self.outcome.scene()
    }
    fn scales(&self) -> ehl_core::HertzScales {
        self.outcome.scales()
    }
    fn grid(&self) -> &ehl_core::Grid {
        self.outcome.grid()
    }
    fn pressure(&self) -> &ndarray::Array2<f64> {
        self.outcome.pressure()
    }
    fn film(&self) -> ndarray::Array2<f64> {
        self.outcome.film()
    }
    fn lubricated(&self) -> bool {
        self.outcome.lubricated()
    }
    fn observables(&self) -> Observables {
        self.outcome.observables()
    }
    fn indicators(&self) -> Vec<(String, crate::model::Indicator)> {
        self.outcome.indicators()
    }
    fn caveat(&self) -> Option<String> {
        let own = self.outcome.caveat();
        let flags = (!self.flags.is_empty()).then(|| self.flags.join("; "));
        match (own, flags) {
            (Some(a), Some(b)) => Some(format!("{a}; {b}")),
            (a, b) => a.or(b),
        }
    }
    fn conditions_used(&self) -> (ehl_core::Contact, f64) {
        self.outcome.conditions_used()
    }
    fn solid_contact(&self) -> Option<ehl_core::SolidContact> {
        self.outcome.solid_contact()
    }
    fn wall_time_s(&self) -> f64 {
        self.outcome.wall_time_s()
    }
    fn summary(&self) -> serde_json::Value {
        self.outcome.summary()
    }
    fn centreline(&self) -> crate::model::Centreline {
        self.outcome.centreline()
    }
    fn fields(&self) -> Vec<(String, ndarray::Array2<f64>)> {
        self.outcome.fields()
    }
    fn time_series(&self) -> crate::error::Result<Option<Vec<serde_json::Value>>> {
        self.outcome.time_series()
    }
    fn history(&self) -> Option<&[(f64, Observables)]> {
        self.outcome.history()
    }
    fn approach_history(&self) -> Option<Vec<(f64, f64)>> {
        self.outcome.approach_history()
    }
    fn contact_history(&self) -> Option<Vec<(f64, f64)>> {
        self.outcome.contact_history()
    }
    fn snapshots(&self) -> Vec<(f64, &ndarray::Array2<f64>, ndarray::Array2<f64>)> {
        self.outcome.snapshots()
    }
    fn figures(
        &self,
        dir: &std::path::Path,
        prefix: &str,
        footnote: &str,
    ) -> crate::error::Result<Vec<std::path::PathBuf>> {
        self.outcome.figures(dir, prefix, &(self.footnote() + footnote))
    }
    fn report(&self) -> String {
        let mut r = self.outcome.report();
        if let Some(e) = &self.estimate {
            r += &format!("  estimated error: {}\n", e.method);
            let v = self.outcome.observables().standard();
            for (k, bar) in e.errors.iter().enumerate() {
                let Some(b) = bar else { continue };
                let (scale, unit) = if k == 2 {
                    (1e-9, "GPa")
                } else if k < 2 {
                    (1e9, "nm")
                } else {
                    (1e3, "mm")
                };
                r += &format!(
                    "    {:<6} {} {unit} ({:.2} %{})\n",
                    OBSERVED[k].0,
                    with_bar(v[k], Some(b), scale, 4),
                    100.0 * b.relative,
                    b.order.map_or(String::new(), |p| format!(", order {p:.2}"))
                );
            }
        }
        for f in &self.flags {
            r += &format!("  FLAG: {f}\n");
        }
        r
    }
    fn estimate(&self) -> Option<(&Estimate, f64)> {
        self.estimate.as_ref().map(|e| (e, self.limit))
    }
    fn inner(&self) -> Option<&dyn Outcome> {
        Some(self.outcome.as_ref())
    }
}

/// `257², 129², 65²`.
fn side_list(grids: &[usize]) -> String {
    grids.iter().map(|n| format!("{n}²")).collect::<Vec<_>>().join(", ")
}

/// The flags an answer carries: each error of the central and minimum film, the maximum
/// pressure and of its last passage's mean central film, solids' share and wave's `A_d/A_i`
/// beyond `limit` (relative), with the grid that would meet it at the order observed (2 where
/// none was); an error that could not be estimated, the passage's included; a film that went
/// below zero.
/// Empty when the answer is within `limit`.
pub fn flags(
    scene: &Scene,
    answer: &Observables,
    passage: Option<&Passage>,
    e: &Estimate,
    limit: f64,
) -> Vec<String> {
    let mut out = vec![];
    if e.errors.iter().all(Option::is_none) {
        out.push(format!("error {}", e.method));
    } else if passage.is_some() && e.passage.is_empty() {
        out.push(
            "the last passage's error not estimated: no coarser grid carried the pattern through a passage"
                .into(),
        );
    }
    let n = scene.grid.nx.max(scene.grid.ny);
    let named = e.errors.iter().take(3).enumerate().map(|(k, b)| (OBSERVED[k].0, *b));
    for (name, bar) in named.chain(e.passage.judged()) {
        let Some(b) = bar else { continue };
        if b.relative > limit {
            let p = b.order.unwrap_or(2.0).clamp(1.0, 2.0);
            let needed = ((n - 1) as f64 * (b.relative / limit).powf(1.0 / p)).ceil() as usize + 1;
            out.push(format!(
                "{} ±{:.1} % (over the {:.1} % asked): about {}² would meet it",
                name,
                100.0 * b.relative,
                100.0 * limit,
                rule::multigrid_count(needed)
            ));
        }
    }
    if answer.film_overlap_m > 0.0 && e.errors[1].is_some_and(|b| b.relative > limit) {
        out.push(format!(
            "the film went {:.3} nm below zero (reported as 0: the solids overlap there, a discretisation error)",
            answer.film_overlap_m * 1e9
        ));
    }
    out
}

/// A value with its error bar in a table's unit: `11.79 ± 0.31` (`scale` turns SI into the
/// table's unit); the value alone when there is no bar.
pub fn with_bar(value: f64, bar: Option<&ErrorBar>, scale: f64, digits: usize) -> String {
    match bar {
        Some(b) => format!("{:.*} ± {:.*}", digits, value * scale, digits, b.absolute * scale),
        None => format!("{:.*}", digits, value * scale),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_grid_that_would_meet_an_accuracy_follows_the_observed_order() {
        // h_c ±8 % at order 2 on 257²: 2 % needs (8/2)^(1/2) = 2 times the cells per side,
        // 513 points.
        let scene = ehl_scene::builtin("seed").unwrap().for_model(ehl_scene::Model::Reynolds);
        let bar = |r: f64, order: Option<f64>| Some(ErrorBar { relative: r, absolute: 0.0, order });
        let e = Estimate {
            grids: vec![257, 129, 65],
            errors: [bar(0.08, Some(2.0)), bar(0.01, Some(2.0)), bar(0.001, None), None, None],
            method: String::new(),
            wall_time_s: 0.0,
            passage: PassageErrors::default(),
        };
        let ob = Observables::default();
        let f = flags(&scene, &ob, None, &e, 0.02);
        assert_eq!(f.len(), 1, "{f:?}");
        assert!(f[0].starts_with("h_c ±8.0 % (over the 2.0 % asked): about 513²"), "{f:?}");
        // At order 1 the same error needs four times the cells.
        let e1 = Estimate { errors: [bar(0.08, Some(1.0)), None, None, None, None], ..e.clone() };
        assert!(flags(&scene, &ob, None, &e1, 0.02)[0].contains("about 1025²"));
        assert!(flags(&scene, &ob, None, &e, 0.1).is_empty());
    }

    #[test]
    fn a_value_reads_with_its_bar_in_the_table_s_unit() {
        let b = ErrorBar { relative: 0.026, absolute: 0.31e-9, order: Some(2.0) };
        assert_eq!(with_bar(11.79e-9, Some(&b), 1e9, 2), "11.79 ± 0.31");
        assert_eq!(with_bar(11.79e-9, None, 1e9, 2), "11.79");
    }
}
