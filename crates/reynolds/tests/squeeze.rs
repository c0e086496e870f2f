//! The pure squeeze (the surfaces at rest, the load held, the approach `H00` the unknown of the
//! force balance) against the analytic rigid isoviscous squeeze: a sphere approaching a flat
//! through an incompressible film of constant viscosity, the solids rigid.
mod common;

use ehl_core::{Grid, SEED_CONTACT, SEED_LUBRICANT};
use ehl_reynolds::*;
use std::f64::consts::PI;

/// The radius [a] of the circle on which the film's pressure vanishes (see `squeeze`).
const EDGE: f64 = 3.0;

/// The gap `H(T)` [a²/R] of a rigid sphere squeezing an isoviscous, incompressible film whose
/// pressure vanishes on a circle where the gap is `H + c` (`c = r_e²/2`): Reynolds' equation
/// gives `p = 3 η V R (1/h² − 1/h_e²)` and `F = 6π η V R² (h_e − h)² / (h h_e²)`, so
/// `dH/dT = −k H (H + c)² / c²`, which integrates to `ln(H/(H + c)) + c/(H + c) = const − kT`
/// (`k = 4/(3λ̄)`: with `c → ∞` the unbounded film's `h0 exp(−F t / (6π η0 R²))` in Hertz
/// units). Solved by Newton from the unbounded answer.
fn circular_edge(h0: f64, c: f64, kt: f64) -> f64 {
    let g = |h: f64| (h / (h + c)).ln() + c / (h + c);
    let target = g(h0) - kt;
    let mut h = h0 * (-kt).exp();
    for _ in 0..60 {
        let step = (g(h) - target) * h * (h + c) * (h + c) / (c * c);
        h = (h - step).max(0.1 * h);
        if step.abs() < 1e-14 * h {
            break;
        }
    }
    h
}

/// Squeezes from `H = 0.2` for one decade of the unbounded answer in 40 equal BDF2 steps on
/// `n²`, the solids rigid, the laws constant: the film's relative error against
/// [`circular_edge`] at every step.
///
/// The domain is `[−3.25, 3.25]²` with the gap raised by 20 `a²/R` outside the circle of radius
/// 3: the pressure there is ~1/90 of the edge's (conductance `∝ H³`), so the film's pressure
/// vanishes on that circle as the reference assumes. (A square domain's corners put it between
/// the circle's answer and the unbounded one: +1.6 % and −1.3 % on 257²; a higher wall, 50,
/// broke the line relaxation on the jump.)
fn squeeze(n: usize) -> Vec<f64> {
    let prm = ReynoldsParams::from_si(
        &SEED_CONTACT,
        &SEED_LUBRICANT,
        0.02,
        ViscosityLaw::Isoviscous,
        DensityLaw::Incompressible,
    );
    let settings = ReynoldsSettings {
        time_scheme: TimeScheme::Bdf2,
        film_tolerance: 1e-7,
        load_tolerance: 1e-7,
        // The coarsest grid must hold the pressure zone (`√(2H)` wide, 0.2 a at the end).
        coarsest_points: 33,
        max_cycles: 400,
        // Its steps converge slowly under the weak force-balance gain below: the same limit.
        step_max_cycles: 400,
        ..Default::default()
    };
    let mut s = ReynoldsSolver::new(Grid::square(n, EDGE + 0.25), prm, settings);
    s.set_rigid();
    s.set_extra_gap(|x, y| if x * x + y * y > EDGE * EDGE { 20.0 } else { 0.0 });
    s.set_speed(0.0);
    let h0 = 0.2;
    s.start_from_gap(h0);
    let k = 4.0 / (3.0 * prm.lambda_bar);
    let steps = 40;
    let dt = 10f64.ln() / k / steps as f64;
    (1..=steps)
        .map(|m| {
            // The force balance's gain at 0.3 of the rigid squeeze's own stiffness
            // `∂(∬P)/∂H00 = (3/2) π λ̄ / (2 ΔT H)` (BDF2's `1.5/ΔT`): the default gain is built
            // on the Hertz compliance `1/π`, 6–60× too stiff a guess here, and cycles.
            let stiffness = 1.5 * PI * prm.lambda_bar / (2.0 * dt * s.h00);
            s.settings.step_h00_gain = (0.3 * PI / stiffness).min(0.1);
            s.step(dt, &mut |_| {}).unwrap_or_else(|e| panic!("{n}²: step {m}: {e}"));
            s.h00 / circular_edge(h0, 0.5 * EDGE * EDGE, k * m as f64 * dt) - 1.0
        })
        .collect()
}

#[test]
fn a_rigid_sphere_squeezes_an_isoviscous_film_as_the_analytic_answer_says() {
    // Measured: worst error 4.1 % on 129², 1.06 % on 257², both at the decade's end where the
    // pressure zone is 4 and 8 cells wide; the error falls 3.9× a halving of the cells (second
    // order, as the scheme). The grid-converged film (Richardson at the observed order) is
    // within 0.28 % of the analytic one all along. Issue target: 1 % over a decade; on 257²
    // alone the bound is 1.2 % (its discretisation error at the decade's end, 1.06 %).
    let (coarse, fine) = (squeeze(129), squeeze(257));
    let last = coarse.len() - 1;
    let order = (coarse[last] / fine[last]).log2();
    println!(
        "rigid squeeze: error at the decade's end {:+.3e} (129²), {:+.3e} (257²); observed order {order:.2}",
        coarse[last], fine[last]
    );
    assert!((1.6..2.4).contains(&order), "observed order {order:.2}");
    let p = 2f64.powf(order);
    let extrapolate = |c: f64, f: f64| f + (f - c) / (p - 1.0);
    let worst =
        coarse.iter().zip(&fine).map(|(c, f)| extrapolate(*c, *f).abs()).fold(0.0, f64::max);
    println!("grid-converged (Richardson): worst error {worst:.2e}");
    for (m, (c, f)) in coarse.iter().zip(&fine).enumerate() {
        let extrapolated = extrapolate(*c, *f);
        // 1 %, the bound asked of it: a rate off by a constant factor (a missing 6π, λ̄ taken with
        // the sum velocity) is off by tens of percent over the decade, a solver that lost the
        // squeeze term entirely does not move at all.
        assert!(
            extrapolated.abs() < 0.01,
            "step {}: {extrapolated:+.3e} ({c:+.3e}, {f:+.3e})",
            m + 1
        );
        assert!(f.abs() < 0.012, "257², step {}: {f:+.3e}", m + 1);
    }
}

#[test]
fn over_a_squeeze_and_a_start_the_oil_held_changes_by_what_crosses_the_edges() {
    // The seed's contact fed 25 nm on its own domain (129²), rolled to steady, then stopped:
    // 8 steps of 0.02 a/u (0.27 ms, a cell's transit at the rolling speed) at rest, then a
    // sudden start and 8 steps rolling. The squeeze moves oil out of the loaded zone into the
    // partly filled gap around it; at rest nothing is supplied and what leaves through the
    // edges is the Poiseuille flow there (none here: the pressure is zero at the edges);
    // rolling again, the supply enters and the Couette flow leaves at the outflow edge. The
    // oil held changes by the difference, to the solve's algebraic error. Measured: the misfit
    // is at most 1.3e-3 of the oil each step moves (`Σ |Δ(ρ̄θH)| h² / ΔT`) at rest and 1.1e-3
    // rolling. Bound 2e-2: a squeeze term on `ρ̄H` where it should be `ρ̄θH`, a wedge term
    // left on at rest or off after the start, makes or destroys oil at the scale of what moves.
    let prm = common::seed();
    let grid = Grid::new(129, 129, (-1.25, 1.25), (-1.25, 1.25));
    let mut s = ReynoldsSolver::new(grid, prm, ReynoldsSettings::default());
    let h_oil = 25e-9 / prm.scales.delta;
    s.set_supply(Some(&move |_y| h_oil));
    s.solve(&mut |_| {}).expect("the steady start converges");
    let dt = 0.02;
    let area = s.finest().h * s.finest().h;
    let mut before = s.finest().rho_film(&prm);
    for (phase, speed) in [("at rest", 0.0), ("rolling again", 1.0)] {
        s.set_speed(speed);
        let mut worst = 0.0f64;
        for m in 1..=8 {
            let held = common::oil_held(&prm, &s);
            s.step(dt, &mut |_| {}).unwrap_or_else(|e| panic!("{phase}, step {m}: {e}"));
            let now = s.finest().rho_film(&prm);
            let moved = (&now - &before).mapv(f64::abs).sum() * area / dt;
            let (supplied, left) = common::edge_flows(&prm, &s);
            if speed == 0.0 {
                assert_eq!(supplied, 0.0, "nothing is supplied at rest");
            }
            let misfit = ((held - common::oil_held(&prm, &s)) / dt - (left - supplied)) / moved;
            worst = worst.max(misfit.abs());
            assert!(
                misfit.abs() < 2e-2,
                "{phase}, step {m}: misfit {misfit:+.2e} of the oil moved {moved:.3e}"
            );
            before = now;
        }
        println!("oil balance {phase}: worst misfit {worst:.2e} of the oil moved per step");
    }
}

#[test]
fn where_a_squeeze_closes_the_gap_the_solids_touch_and_the_oil_balance_still_holds() {
    // The same contact, stopped for longer: 12 steps of 0.2 a/u (2.7 ms each, 32 ms at rest),
    // long enough for the side lobes and the exit constriction to close (about 11 ms after the
    // stop on 129²), then 8 steps rolling again. Where the gap closes the solids touch: the
    // film is held at 0 there (without contact it sank to −2.8 nm in 5 s), the contact carries
    // part of the load, and the oil held still changes by what crosses the edges. Measured:
    // contact up to 2.0e-4 of the load, the minimum film −6.1e-4 of the central one at most,
    // the misfit at most 6.6e-3 of the oil moved at rest and 1.1e-3 rolling. Bounds: the
    // film −1e-2 of the central one (the contact edge is decided before each sweep, so the point
    // beside it may end a sweep slightly shut; a film with no contact sinks by tenths of the
    // central film in these 32 ms), the misfit 2e-2 as above (a contact point that made or
    // destroyed its oil when it closed or opened misses by the whole of what it held).
    let prm = common::seed();
    let grid = Grid::new(129, 129, (-1.25, 1.25), (-1.25, 1.25));
    let mut s = ReynoldsSolver::new(grid, prm, ReynoldsSettings::default());
    let h_oil = 25e-9 / prm.scales.delta;
    s.set_supply(Some(&move |_y| h_oil));
    s.solve(&mut |_| {}).expect("the steady start converges");
    let area = s.finest().h * s.finest().h;
    let mut before = s.finest().rho_film(&prm);
    let (mut touched, mut shut) = (0.0f64, 0.0f64);
    for (phase, speed, steps, dt) in [("at rest", 0.0, 12, 0.2), ("rolling again", 1.0, 8, 0.02)] {
        s.set_speed(speed);
        let mut worst = 0.0f64;
        for m in 1..=steps {
            let held = common::oil_held(&prm, &s);
            s.step(dt, &mut |_| {}).unwrap_or_else(|e| panic!("{phase}, step {m}: {e}"));
            let now = s.finest().rho_film(&prm);
            let moved = (&now - &before).mapv(f64::abs).sum() * area / dt;
            let (supplied, left) = common::edge_flows(&prm, &s);
            let misfit = ((held - common::oil_held(&prm, &s)) / dt - (left - supplied)) / moved;
            worst = worst.max(misfit.abs());
            assert!(misfit.abs() < 2e-2, "{phase}, step {m}: misfit {misfit:+.2e}");
            let (hc, hmin) = s.films();
            shut = shut.min(hmin / hc);
            assert!(hmin > -1e-2 * hc, "{phase}, step {m}: the film shut to {hmin:.3e} ({hc:.3e})");
            if speed == 0.0 {
                touched = touched.max(s.contact().0);
            }
            before = now;
        }
        println!(
            "{phase}: worst misfit {worst:.2e}; contact up to {touched:.2e} of the load; film down to {shut:.1e} of the central"
        );
    }
    assert!(touched > 0.0, "the lobes never closed: no contact at rest");
}
