//! The domain and grid each sweep point needs, from the point's own scales, and the two check
//! runs that measure how much its answer still depends on them.
//!
//! **The rule.** The inlet must lie beyond the distance at which the film starts to starve; each
//! model states its own need (`ContactModel::inlet_distance`), the point takes the largest:
//! - Reynolds: Hamrock & Dowson's starvation boundary for a circular contact (Isothermal EHL of
//!   point contacts, Part IV: starvation results, J. Lubr. Technol. 99 (1977) 15–23) is
//!   `m* = 1 + 3.06 [(R/b)² H]^0.58`, `H = h/R`; for `b = a`, `(R/a)² h/R` is the film in Hertz
//!   units `h / (a²/R)`, here the Nijenbanning–Venner–Moes central film. At `m*` itself the film
//!   is still a few per cent short, so the inlet goes to `1 + 2 (m* − 1)` (docs/decisions.md,
//!   "The accuracy rule's constants").
//! - Layer: nothing happens before the layer touches the ball, where the Hertz separation equals
//!   the supply thickness `l0`; the inlet goes where the separation is `2 l0`.
//!
//! So `x_min = −max(|x_min of the scene|, each listed model's inlet)`; the outlet is kept. The cells are
//! never coarser than the scene's (its author's resolution: 0.0098 `a` in the seed scenes, the
//! ~0.01 `a` the thin-film regime needs); a grown domain gets more points, rounded up to a count
//! the multigrid coarsens well (`c·2^k + 1`, `c` odd ≤ 9: steps of at most 1.125×). When the scene has square cells and as
//! many points in `y` as in `x` (the Reynolds solver needs both), the domain stays square: `y`
//! grows symmetrically with `x`. A point that needs nothing more than the scene runs on the
//! scene's own domain and grid.
//!
//! **The grid rule** (with the sweep's `resolve`, on by default). Each model states the largest
//! cell on which its answer exists and is within the sweep's flag limit
//! (`ContactModel::cell_needed`); the point's cells are refined to the smallest, the domain kept.
//! The Reynolds solver's is `ρ H_c^{2/3}` `a` (`H_c` the NVM central film in Hertz units: the
//! width of the side lobes' and inlet's constrictions), `ρ = √(change / K)` from the measured
//! grid change `K ρ²` of the central film, the change the one whose estimated error is the limit
//! ([`super::gci::change_allowed`]; 0.106 at 2 %), never above 0.25, where the film's
//! existence ends (`ehl_reynolds::formulas::cell_for_change` says how both were measured).
//! The layer and the dry contact need none.
//!
//! **The checks.** The rule is a measured estimate, not a proof, so each point is run three times
//! more for each model: at half and at a quarter of the points per side on the same domain (the
//! grid's share: the order the answer converges at and its estimated error, [`super::gci`]),
//! and at the half's cells on a domain whose inlet distance is 1.5 times the point's, `y` grown
//! by as much in total, half on each side (against the half-points run: the domain's share). The
//! estimated errors and the domain's relative changes of `h_c`, `h_min`, `p_max` are reported,
//! and a point is flagged when one exceeds the sweep's `flag_change_above`. Each check runs as an
//! estimate's coarser grids do ([`super::run_check`]: from the point's answer where the model
//! can, within the estimate's bounds).

use ehl_scene::{Domain, GridSpec, Model, Scene};

/// The inlet distance [a] the models of `scene` need: the largest any of them asks for
/// ([`crate::model::ContactModel::inlet_distance`]); 0 when none does.
pub fn inlet_needed(scene: &Scene) -> f64 {
    models(scene).map(|m| m.inlet_distance(scene)).fold(0.0, f64::max)
}

/// The registered models `scene` lists.
fn models(scene: &Scene) -> impl Iterator<Item = &'static dyn crate::model::ContactModel> {
    scene.models().into_iter().filter_map(|m| crate::run::model(m).ok())
}

/// Whether the Reynolds solver's shape rules apply (square cells, `nx = ny`).
fn square(scene: &Scene) -> bool {
    let (d, g) = (&scene.domain, &scene.grid);
    g.nx == g.ny
        && ((d.x_a[1] - d.x_a[0]) / (g.nx - 1) as f64 - (d.y_a[1] - d.y_a[0]) / (g.ny - 1) as f64)
            .abs()
            < 1e-12
}

/// The smallest point count `c·2^k + 1` (`c` odd ≤ 9, coarsest level ≥ 17 points) of at least `n`.
pub fn multigrid_count(n: usize) -> usize {
    let mut best = usize::MAX;
    for base in [1usize, 3, 5, 7, 9] {
        // Intervals `c·2^k` with at least 16 of them (17 points) on the coarsest level …
        let mut m = base;
        while m < 16 {
            m *= 2;
        }
        // … doubled until the count reaches `n`.
        while m + 1 < n {
            m *= 2;
        }
        best = best.min(m + 1);
    }
    best
}

/// The largest cell [a] the models of `scene` need for answers whose estimated grid error is
/// within `error` (relative): each model's cell for the half-grid change that estimate allows
/// ([`super::gci::change_allowed`], [`crate::model::ContactModel::cell_needed`]), the
/// smallest any of them asks for; infinite when none does.
pub fn cell_needed(scene: &Scene, error: f64) -> f64 {
    let change = super::gci::change_allowed(error);
    models(scene).map(|m| m.cell_needed(scene, change)).fold(f64::INFINITY, f64::min)
}

/// The point's scene with the domain and grid the rules ask for (the grid rule only when
/// `resolve`, for answers within `error`: the sweep's flag limit), and what changed (`None`
/// when the scene's own already suffice).
pub fn adapt(scene: &Scene, resolve: bool, error: f64) -> (Scene, Option<String>) {
    let cell = if resolve { cell_needed(scene, error) } else { f64::INFINITY };
    adapt_to(scene, inlet_needed(scene), cell, error)
}

/// The one-model scene `m` runs a point of `scene` on: the point's domain (the inlet every
/// model of `scene` needs, so that all answer over the same rectangle) with the cells `m`
/// itself needs (the grid rule when `resolve`, for answers within `error`), never coarser
/// than the scene's. A model that needs no finer cells than the scene's (the layer, the dry
/// contact) is not run on the grid a thin Reynolds film asks for: its own checks say how good
/// its answer is there.
pub fn adapt_model(scene: &Scene, m: Model, resolve: bool, error: f64) -> Scene {
    let one = scene.for_model(m);
    let cell = if resolve { cell_needed(&one, error) } else { f64::INFINITY };
    adapt_to(&one, inlet_needed(scene), cell, error).0
}

/// `scene` with its inlet at least `inlet` [a] upstream and its cells at most `cell` [a].
fn adapt_to(scene: &Scene, inlet: f64, cell: f64, error: f64) -> (Scene, Option<String>) {
    let (d, g) = (scene.domain, scene.grid);
    let dx = (d.x_a[1] - d.x_a[0]) / (g.nx - 1) as f64;
    let dy = (d.y_a[1] - d.y_a[0]) / (g.ny - 1) as f64;
    let (longer, finer) = (-d.x_a[0] < inlet, cell < dx.max(dy));
    if !longer && !finer {
        return (scene.clone(), None);
    }
    let mut s = scene.clone();
    let x_min = if longer { -inlet } else { d.x_a[0] };
    let len = d.x_a[1] - x_min;
    // 1e-9: a length that is a whole number of cells up to rounding keeps its count.
    let count = |len: f64, cell: f64| multigrid_count((len / cell - 1e-9).ceil() as usize + 1);
    let nx = count(len, dx.min(cell));
    if square(scene) {
        let grow = 0.5 * (len - (d.x_a[1] - d.x_a[0]));
        s.domain = Domain { x_a: [x_min, d.x_a[1]], y_a: [d.y_a[0] - grow, d.y_a[1] + grow] };
        s.grid = GridSpec { nx, ny: nx };
    } else {
        s.domain.x_a[0] = x_min;
        s.grid.nx = nx;
        if finer {
            s.grid.ny = count(d.y_a[1] - d.y_a[0], dy.min(cell));
        }
    }
    let mut what = format!(
        "{}{}x{} over [{:.3}, {:.3}] x [{:.3}, {:.3}] a",
        if longer { format!("inlet at {x_min:.3} a, ") } else { String::new() },
        s.grid.nx,
        s.grid.ny,
        s.domain.x_a[0],
        s.domain.x_a[1],
        s.domain.y_a[0],
        s.domain.y_a[1]
    );
    if finer {
        what += &if error.is_finite() {
            format!(" (cells <= {cell:.4} a for the film within {:.1} %)", 100.0 * error)
        } else {
            format!(" (cells <= {cell:.4} a for the thinnest film)")
        };
    }
    (s, Some(what))
}

/// The grid check: the same domain with half the points per side (rounded up).
pub fn grid_check(scene: &Scene) -> Scene {
    let mut s = scene.clone();
    let half = |n: usize| (n - 1).div_ceil(2) + 1;
    s.grid = GridSpec { nx: half(scene.grid.nx), ny: half(scene.grid.ny) };
    s
}

/// The domain check: the grid check's cells, the inlet distance 1.5 times the point's, `y`
/// grown by as much in total (half on each side), the point count rounded up to a multigrid
/// count (the extra length goes to the inlet).
pub fn domain_check(scene: &Scene) -> Scene {
    let c = grid_check(scene);
    let mut s = c.clone();
    let (d, g) = (&c.domain, &c.grid);
    let (dx, dy) =
        ((d.x_a[1] - d.x_a[0]) / (g.nx - 1) as f64, (d.y_a[1] - d.y_a[0]) / (g.ny - 1) as f64);
    let grow = 0.5 * d.x_a[0].abs().max(dx);
    let nx = multigrid_count(g.nx + (grow / dx).ceil() as usize);
    let ny = if square(&c) { nx } else { multigrid_count(g.ny + (grow / dy).ceil() as usize) };
    s.grid = GridSpec { nx, ny };
    let wide = 0.5 * dy * (ny - g.ny) as f64;
    s.domain = Domain {
        x_a: [d.x_a[1] - dx * (nx - 1) as f64, d.x_a[1]],
        y_a: [d.y_a[0] - wide, d.y_a[1] + wide],
    };
    s
}

#[cfg(test)]
mod tests {
    use super::*;

    /// No accuracy asked: the grid rule's cells are those the film exists on.
    const EXISTS: f64 = f64::INFINITY;

    #[test]
    fn multigrid_counts() {
        for (n, m) in [
            (257, 257),
            (258, 289),
            (290, 321),
            (322, 385),
            (386, 449),
            (450, 513),
            (129, 129),
            (130, 145),
            // Small counts: never below the coarsest level's 17, never even (the old loop
            // returned 2 for 2 and 4 for 3).
            (2, 17),
            (5, 17),
            (17, 17),
            (18, 19),
            (20, 21),
        ] {
            assert_eq!(multigrid_count(n), m, "{n}");
        }
    }

    #[test]
    fn the_seed_point_gets_the_reynolds_inlet() {
        let seed = ehl_scene::builtin("seed").unwrap();
        // NVM 14.88 nm on a²/R = 1.905 µm: H = 0.00781, m* = 1 + 3.06 H^0.58 = 1.1836, inlet
        // 1 + 2 (m* − 1) = 1.367 a; the layer (2 l0 = 0.0262 a²/R) needs only ~1.06 a.
        let x = inlet_needed(&seed);
        assert!((x - 1.367).abs() < 2e-3, "{x}");
        let (s, what) = adapt(&seed, true, EXISTS);
        assert!(what.is_some());
        assert!((s.domain.x_a[0] + x).abs() < 1e-12 && s.domain.x_a[1] == 1.25);
        // 2.617 a at <= 2.5/256 a per cell: 268 cells, rounded up to 289 points (9·32 + 1).
        assert_eq!((s.grid.nx, s.grid.ny), (289, 289));
        s.validate("test").unwrap();
        // A scene that already reaches far enough is kept as it is.
        let mut wide = seed.clone();
        wide.domain = ehl_scene::Domain { x_a: [-1.5, 1.0], y_a: [-1.25, 1.25] };
        assert_eq!(adapt(&wide, true, EXISTS), (wide.clone(), None));
    }

    #[test]
    fn a_fast_point_gets_a_longer_inlet_at_no_coarser_cells() {
        let seed = ehl_scene::builtin("seed").unwrap();
        let fast = seed.with_parameter(ehl_scene::Parameter::RollingVelocity, 1.0).unwrap();
        let (s, what) = adapt(&fast, true, EXISTS);
        assert!(what.is_some());
        // NVM at 1 m/s: H ≈ 0.175 a²/R, m* ≈ 2.11, inlet ≈ 3.23 a.
        assert!(s.domain.x_a[0] < -3.1 && s.domain.x_a[0] > -3.35, "{:?}", s.domain);
        assert_eq!(s.domain.x_a[1], 1.25);
        let dx = (s.domain.x_a[1] - s.domain.x_a[0]) / (s.grid.nx - 1) as f64;
        let dy = (s.domain.y_a[1] - s.domain.y_a[0]) / (s.grid.ny - 1) as f64;
        assert!(dx <= 2.5 / 256.0 + 1e-12 && (dx - dy).abs() < 1e-12, "{dx} {dy}");
        s.validate("test").unwrap();
    }

    #[test]
    fn the_grid_rule_refines_where_the_film_is_thin_and_keeps_the_seed_s_cells() {
        let seed = ehl_scene::builtin("seed").unwrap();
        let at = |u: f64, w: f64| {
            seed.with_parameter(ehl_scene::Parameter::RollingVelocity, u)
                .and_then(|s| s.with_parameter(ehl_scene::Parameter::Load, w))
                .unwrap()
        };
        // The seed's own cells (2.5/256 a) are finer than its rule (0.25 · 0.00781^(2/3) =
        // 0.00985 a): only the inlet grows, as without the rule.
        assert_eq!(adapt(&seed, true, EXISTS), adapt(&seed, false, EXISTS));
        // 2 mm/s, 80 N: H_c = 9.4e-4, cells <= 0.0024 a: 1025 points over ~2.5 a (measured: the
        // film closes on 257², goes negative on 513², is +0.50 nm on 1025²).
        let (s, what) = adapt(&at(0.002, 80.0), true, EXISTS);
        assert!(s.grid.nx >= 1025 && s.grid.nx == s.grid.ny, "{what:?}");
        assert!(what.unwrap().contains("thinnest film"));
        s.validate("test").unwrap();
        // Off, the scene's cells stay.
        assert_eq!(adapt(&at(0.002, 80.0), false, EXISTS).0.grid.nx, 257);
    }

    #[test]
    fn the_accuracy_rule_refines_the_seed_to_its_measured_two_per_cent_grid() {
        // The seed point: 0.106 · 0.00781^(2/3) = 0.00417 a over 2.617 a: 628 cells, 641
        // points (5·128 + 1). Measured there (flooded, 10 mm/s): h_c moves 4 % from 257² to
        // 513², 1.1 % from 513² to 1025², so the three-grid estimate of 2 % is first met near
        // 513²-641²; a rule asking for 289² again (the existence rule) would fail here.
        let seed = ehl_scene::builtin("seed").unwrap();
        let (s, what) = adapt(&seed, true, 0.02);
        assert_eq!((s.grid.nx, s.grid.ny), (641, 641), "{what:?}");
        assert!(what.unwrap().contains("within 2.0 %"));
        // A looser limit asks for less, never less than the film's existence.
        let (loose, _) = adapt(&seed, true, 0.05);
        assert!(loose.grid.nx < 641 && loose.grid.nx >= 289, "{:?}", loose.grid);
        assert_eq!(adapt(&seed, true, 10.0), adapt(&seed, true, EXISTS));
        s.validate("test").unwrap();
    }

    #[test]
    fn the_flooded_film_s_grid_change_stays_within_the_accuracy_rule_s_constant() {
        // The seed's contact at 0.1 m/s, 20 N, flooded, on the inlet rule's domain: 385² against
        // 193² (`ρ` = 0.074 on 385²). Measured on `seed-speed-load`: the change is 3.24 ρ²
        // here and 2.5–4.3 ρ² over the map; the rule takes 4.3. A discretisation whose error
        // grew past the constant (a first-order term, a coarser deformation) fails the upper
        // bound; a change that no longer scales as the rule says (or vanished) the lower.
        let seed = ehl_scene::builtin("seed").unwrap().for_model(ehl_scene::Model::ReynoldsFlooded);
        let at = seed.with_parameter(ehl_scene::Parameter::RollingVelocity, 0.1).unwrap();
        let (fine, _) = adapt(&at, true, EXISTS);
        assert_eq!(fine.grid.nx, 385, "{:?}", fine.grid);
        let half = grid_check(&fine);
        let hc = |s: &Scene| crate::run::run_scene(s).unwrap().observables().central_film_m;
        let change = (hc(&half) / hc(&fine) - 1.0).abs();
        let dx = (fine.domain.x_a[1] - fine.domain.x_a[0]) / (fine.grid.nx - 1) as f64;
        let rho = dx / (cell_needed(&fine, EXISTS) / ehl_reynolds::formulas::CELLS_PER_FILM);
        let k = change / (rho * rho);
        assert!(
            (2.0..=ehl_reynolds::formulas::GRID_CHANGE_PER_CELL2).contains(&k),
            "change {change:.4} at rho {rho:.4}: K = {k:.2}"
        );
    }

    #[test]
    fn the_grid_rule_s_grid_holds_a_film_the_coarse_grid_closed() {
        // The seed at 10 mm/s, 20 N, flooded, on 65² (cells 0.039 a, 4× the rule's): the film
        // closes in the side lobes. On the grid the rule gives it, it converges with every film
        // positive. A rule that asked too little fails here.
        let mut coarse =
            ehl_scene::builtin("seed").unwrap().for_model(ehl_scene::Model::ReynoldsFlooded);
        coarse.grid = ehl_scene::GridSpec { nx: 65, ny: 65 };
        // The clamp alone: on cells wider than the rule's its failure would hand over to the
        // mass-conserving solver with the inflow filled.
        coarse.reynolds.as_mut().unwrap().solver.filled_inflow_fallback = false;
        let err = crate::run::run_scene(&coarse).err().expect("65² closes the film");
        assert!(format!("{err:#}").contains("film closed"), "{err:#}");
        let (fine, _) = adapt(&coarse, true, EXISTS);
        assert!(fine.grid.nx >= 257, "{:?}", fine.grid);
        let o = crate::run::run_scene(&fine).expect("the rule's grid holds the film");
        let ob = o.observables();
        assert!(ob.minimum_film_m > 0.0 && o.caveat().is_none(), "{ob:?}");
    }

    #[test]
    fn checks_halve_the_grid_and_grow_the_domain_at_the_same_cells() {
        let seed = ehl_scene::builtin("seed").unwrap();
        let g = grid_check(&seed);
        assert_eq!((g.grid.nx, g.domain), (129, seed.domain));
        let d = domain_check(&seed);
        // Inlet 1.25 → 1.875 a: 32 more cells of 2.5/128 a, 161 points (5·32 + 1).
        assert_eq!(d.grid.nx, 161);
        let dx = |s: &Scene| (s.domain.x_a[1] - s.domain.x_a[0]) / (s.grid.nx - 1) as f64;
        assert!((dx(&d) - dx(&g)).abs() < 1e-12);
        assert!((d.domain.x_a[0] + 1.875).abs() < 1e-12 && d.domain.x_a[1] == 1.25);
        assert!((d.domain.y_a[1] - 1.5625).abs() < 1e-12);
        d.validate("test").unwrap();
    }
}
