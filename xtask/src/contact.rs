//! The solids touching in a steady Reynolds solve: the seed's contact fed supplies thinner than
//! the discrete dry gap's error at the contact's edge, each solved with contact (the default:
//! the solids touch where the lubricated cycles stall with the film closed) and without it,
//! on two grids; and its dry limits: the contact at vanishing speed, flooded, fed almost no
//! oil and none, against the core's dry contact on the same grid. Writes
//! `docs/measured/steady-contact.md` and the rows as JSON into `--out`.

use crate::measured::{self, Table};
use anyhow::{Context, Result};
use ehl_scene::Model;
use ehl_workbench::{reynolds::ReynoldsOutcome, run_scene};
use serde_json::json;
use std::path::Path;

/// What stopped a failed solve's last attempt, in its diagnosis' words: the start from the dry
/// contact's when it was tried (its note closes the text), else the first the text names.
fn last_attempt_failure(text: &str) -> &'static str {
    let last = text.rfind("then from the dry contact:").map_or(text, |at| &text[at..]);
    let kinds = ["the film closed", "diverged", "stalled", "limit cycle", "cycle limit"];
    let why = kinds.iter().filter_map(|k| last.find(k).map(|at| (at, *k))).min();
    why.map_or("failed", |(_, k)| k)
}

/// The share of the supply the touching points took (`–` flooded or without contact): oil the
/// equations destroy, the contact edge's error on the grid.
fn oil_taken(r: &ReynoldsOutcome) -> String {
    r.oil_into_contact().map_or("–".into(), |v| format!("{v:.2e}"))
}

/// One solve: the seed's contact, the Reynolds model fed `h_oil` [m] on `n`², contact on or
/// off; its row's cells and JSON.
fn solve(h_oil: f64, n: usize, contact: bool) -> Result<(Vec<String>, serde_json::Value)> {
    let mut s = ehl_scene::builtin("seed")?.for_model(Model::Reynolds).with_points(n)?;
    s.name = format!("seed-fed-{:.0}pm-{n}", h_oil * 1e12);
    s.outputs.figures = false;
    s.supply.as_mut().context("the seed's scene has a supply")?.thickness_m = h_oil;
    s.reynolds.as_mut().context("a Reynolds scene")?.solver.contact = contact;
    let t = std::time::Instant::now();
    let answer = run_scene(&s);
    let wall = t.elapsed().as_secs_f64();
    let head = vec![
        format!("{:.1}", h_oil * 1e9),
        format!("{n}²"),
        if contact { "on" } else { "off" }.to_string(),
    ];
    let o = match answer {
        Ok(o) => o,
        Err(e) => {
            let text = e.to_string();
            let why = last_attempt_failure(&text);
            let mut row = head;
            row.extend([format!("failed: {why}"), String::new(), String::new(), String::new()]);
            row.extend([String::new(), String::new(), String::new(), String::new()]);
            row.push(format!("{wall:.1}"));
            let v = json!({"h_oil_m": h_oil, "points": n, "contact": contact,
                           "answered": false, "diagnosis": e.to_string(), "wall_s": wall});
            return Ok((row, v));
        }
    };
    let r = o.downcast_ref::<ReynoldsOutcome>().context("a Reynolds outcome")?;
    let ob = o.observables();
    let c = o.solid_contact().unwrap_or_default();
    let g = &r.grid;
    let (j, i) = (g.row_nearest(0.0), g.col_nearest(0.0));
    // The thin-supply limit: the oil crosses the contact at its own thickness, ρ̄ h_c = h_oil.
    let carried = r.prm.density.rho(r.p[[j, i]]) * ob.central_film_m / h_oil;
    let mut row = head;
    row.extend([
        format!("{:.4}", ob.central_film_m * 1e9),
        format!("{carried:.4}"),
        format!("{:.3}", ob.film_overlap_m * 1e9),
        format!("{:.2e}", c.load_share),
        format!("{:.3e}", c.area_m2),
        oil_taken(r),
        r.report.touched_from.map(|k| k.to_string()).unwrap_or_else(|| "–".into()),
        r.report.cycles.to_string(),
        format!("{wall:.1}"),
    ]);
    let v = json!({"h_oil_m": h_oil, "points": n, "contact": contact, "answered": true,
                   "central_film_m": ob.central_film_m, "carried_over_supply": carried,
                   "solid_contact": c, "oil_into_contact": r.oil_into_contact(),
                   "touched_from_cycle": r.report.touched_from,
                   "cycles": r.report.cycles, "wall_s": wall});
    Ok((row, v))
}

/// The largest pressure difference [p_h] of `r` from the core's dry contact on its grid (the
/// ball's rigid film, the same load).
fn from_dry_contact(r: &ReynoldsOutcome) -> Result<f64> {
    use ehl_core::{DryProblem, DrySettings, DrySolver, Start};
    let ball = r.grid.paraboloid();
    let load = 2.0 * std::f64::consts::PI / 3.0;
    let problem = DryProblem { rigid_gap: ball.view(), compliance: None, load };
    let (mut p, mut w) = (r.grid.zeros(), r.grid.zeros());
    DrySolver::new(r.grid, DrySettings::default()).solve(&problem, &mut p, &mut w, Start::Flat)?;
    Ok((&r.p - &p).iter().fold(0.0f64, |m, v| m.max(v.abs())))
}

/// One solve of the dry limit: the seed's contact rolling at `u1` [m/s] on `n`², flooded or
/// fed `h_oil` [m]; its row's cells and JSON.
fn dry_limit(u1: f64, h_oil: Option<f64>, n: usize) -> Result<(Vec<String>, serde_json::Value)> {
    let mut s = ehl_scene::builtin("seed")?.for_model(Model::Reynolds).with_points(n)?;
    s.name = format!("seed-dry-limit-{n}");
    s.outputs.figures = false;
    s.conditions.rolling_velocity_m_s = Some(u1);
    match h_oil {
        Some(h) => s.supply.as_mut().context("the seed's scene has a supply")?.thickness_m = h,
        None => s.supply = None,
    }
    let t = std::time::Instant::now();
    let answer = run_scene(&s);
    let wall = t.elapsed().as_secs_f64();
    let supply = match h_oil {
        None => "flooded".to_string(),
        Some(h) if h <= 0.0 => "none".to_string(),
        Some(h) => format!("{:.1} nm", h * 1e9),
    };
    let mut row = vec![format!("{u1:.0e}"), supply, format!("{n}²")];
    let v = match answer {
        Err(e) => {
            let text = e.to_string();
            row.push(format!("failed: {}", last_attempt_failure(&text)));
            row.extend(["", "", "", "", ""].map(String::from));
            json!({"u1_m_s": u1, "h_oil_m": h_oil, "points": n, "answered": false,
                   "diagnosis": text, "wall_s": wall})
        }
        Ok(o) => {
            let r = o.downcast_ref::<ReynoldsOutcome>().context("a Reynolds outcome")?;
            let c = o.solid_contact().unwrap_or_default();
            let diff = from_dry_contact(r)?;
            row.push(
                match (r.report.from_dry, &r.report.first_attempt) {
                    (true, None) => "the dry contact at once (no oil)",
                    (true, Some(_)) => "from the dry contact",
                    (false, _) if r.report.inflow_filled => "lubricated, the inflow filled",
                    (false, _) => "lubricated",
                }
                .into(),
            );
            row.extend([
                format!("{:.6}", c.load_share),
                format!("{diff:.1e}"),
                format!("{:.4}", c.max_pressure_pa / r.prm.scales.p_h),
                oil_taken(r),
                r.report.cycles.to_string(),
            ]);
            json!({"u1_m_s": u1, "h_oil_m": h_oil, "points": n, "answered": true,
                   "from_dry": r.report.from_dry, "solid_contact": c,
                   "pressure_from_dry_contact_p_h": diff, "cycles": r.report.cycles,
                   "oil_into_contact": r.oil_into_contact(),
                   "wall_s": wall})
        }
    };
    row.push(format!("{wall:.1}"));
    Ok((row, v))
}

/// The dry-limit table's columns.
const DRY_LIMIT_COLUMNS: [&str; 10] = [
    "u1 [m/s]",
    "supply",
    "grid",
    "answer",
    "contact's share of the load",
    "largest P − P_dry, either sign [p_h]",
    "contact pressure max [p_h]",
    "oil into the contact [of the supply]",
    "cycles",
    "wall [s]",
];

/// The dry limits' cost on `n`² (`cargo xtask bench --only dry-limit`): the seed's contact at
/// 1e-6 m/s flooded and fed 1 nm, at 1e-5 m/s fed 1 nm, and with no oil at 1e-6 m/s and at
/// its own 0.01 m/s, each the whole steady solve (the lubricated attempts that fail, then the
/// start from the dry contact; with no oil that start alone); writes
/// `docs/measured/bench-dry-limit.md`.
pub fn bench(n: usize) -> Result<std::path::PathBuf> {
    let mut t = Table::new(&DRY_LIMIT_COLUMNS);
    // Quickly: flooded and with no oil (the fed ones run their failing attempts first:
    // seconds).
    let cases: &[(f64, Option<f64>)] = if crate::quick() {
        &[(1e-6, None), (0.01, Some(0.0))]
    } else {
        &[
            (1e-6, None),
            (1e-6, Some(1e-9)),
            (1e-5, Some(1e-9)),
            (1e-6, Some(0.0)),
            (0.01, Some(0.0)),
        ]
    };
    for &(u, h) in cases {
        println!("u1 {u:.0e} m/s, {h:?} m, on {n}²");
        t.rows.push(dry_limit(u, h, n)?.0);
    }
    let intro = format!(
        "The seed's contact (Table 1, 20 N) through the Reynolds solver at vanishing speed, \
         flooded and fed almost no oil, on {n}² over its own domain [-1.25, 1.25]² a: films \
         thinner than the grid's dry gap error at the contact's edge, where every lubricated \
         attempt fails and the last starts from the core's dry contact; and with no oil at \
         all, which starts there at once. Each row one whole steady solve (its failed attempts \
         counted in the cycles and the wall time), its answer against the core's dry contact \
         on the same grid; no error estimate."
    );
    measured::write(
        "bench-dry-limit",
        "The dry limits' cost",
        &format!("cargo xtask bench --only dry-limit --max-points {n}"),
        &intro,
        &[("Steady solves", &t)],
    )
}

/// The seed's contact at 2 mm/s under 80 N, fed 25 nm and flooded (its film closes at the side
/// lobes on the grids coarser than the rule's, 1153²) on 257², 513² and 1025² (quickly 257²
/// alone), each with its error estimate: how the solids' share of the load and their area go as the
/// grid refines. Writes `docs/measured/contact-grids.md` and the rows as JSON into `out`.
pub fn over_grids(out: &Path) -> Result<()> {
    let grids: &[usize] = if crate::quick() { &[257] } else { &[257, 513, 1025] };
    let mut t = Table::new(&[
        "supply",
        "grid",
        "answer",
        "h_c [nm]",
        "h_c's error bar [nm]",
        "film below zero [nm]",
        "contact's share of the load",
        "contact area [m²]",
        "oil into the contact [of the supply]",
        "cycles",
        "wall [s]",
    ]);
    let mut rows = vec![];
    for (fed, &n) in [true, false].into_iter().flat_map(|f| grids.iter().map(move |n| (f, n))) {
        let supply = if fed { "25 nm" } else { "flooded" };
        println!("2 mm/s, 80 N, {supply} on {n}²");
        let mut s = ehl_scene::builtin("seed")?.for_model(Model::Reynolds).with_points(n)?;
        s.name = format!("seed-2mm-80N-{n}");
        s.outputs.figures = false;
        s.conditions.rolling_velocity_m_s = Some(0.002);
        s.conditions.load_n = 80.0;
        if !fed {
            s.supply = None;
        }
        let t0 = std::time::Instant::now();
        use ehl_workbench::accuracy::{Checked, Checking};
        let answer = run_scene(&s).map(|o| Checked::new(&s, o, Checking::of(&s, true)));
        let wall = t0.elapsed().as_secs_f64();
        let (cells, v) = match answer {
            Err(e) => {
                let why = last_attempt_failure(&e.to_string());
                let mut cells = vec![supply.into(), format!("{n}²"), format!("failed: {why}")];
                cells.extend(std::iter::repeat_n(String::new(), 7));
                (
                    cells,
                    json!({"supply": supply, "points": n, "answered": false,
                               "diagnosis": e.to_string()}),
                )
            }
            Ok(checked) => {
                let o = &checked.outcome;
                let r = o.downcast_ref::<ReynoldsOutcome>().context("a Reynolds outcome")?;
                let (ob, c) = (o.observables(), o.solid_contact().unwrap_or_default());
                let bar = checked.estimate.as_ref().and_then(|e| e.errors[0]).map(|b| b.absolute);
                let state = match (r.report.converged, r.report.settled.is_some()) {
                    (true, _) if r.report.inflow_filled => "converged, the inflow filled",
                    (true, _) => "converged",
                    (false, true) => "settled",
                    _ => "returned",
                };
                let cells = vec![
                    supply.into(),
                    format!("{n}²"),
                    state.to_string(),
                    format!("{:.4}", ob.central_film_m * 1e9),
                    bar.map_or("–".into(), |b| format!("{:.3}", b * 1e9)),
                    format!("{:.3}", ob.film_overlap_m * 1e9),
                    format!("{:.2e}", c.load_share),
                    format!("{:.3e}", c.area_m2),
                    oil_taken(r),
                    r.report.cycles.to_string(),
                ];
                let v = json!({"supply": supply, "points": n, "answered": true, "state": state,
                               "central_film_m": ob.central_film_m, "central_film_error_m": bar,
                               "film_overlap_m": ob.film_overlap_m, "solid_contact": c,
                               "oil_into_contact": r.oil_into_contact(),
                               "cycles": r.report.cycles});
                (cells, v)
            }
        };
        t.rows.push(cells.into_iter().chain([format!("{wall:.1}")]).collect());
        rows.push(v);
    }
    std::fs::create_dir_all(out)?;
    let f = out.join("contact-grids.json");
    std::fs::write(&f, serde_json::to_string_pretty(&rows)? + "\n")?;
    let intro = "The seed's contact (Table 1) at 2 mm/s under 80 N, fed 25 nm (the \
        mass-conserving Reynolds solver) and flooded, on its own domain [-1.25, 1.25]² a, \
        steady: its film (NVM 4.5 nm flooded) closes at the side lobes on grids coarser than \
        the rule's (1153²), and the solids touch there. Flooded, where the clamp's attempts \
        fail on such a grid the answer is the mass-conserving solver's with the inflow filled \
        (\"the inflow filled\"), its solids touching. Each answer with its error estimate (the wall includes \
        it: the answer on half and a quarter of the points per side, where they answer). The \
        contact's share of the load and its area: where the solids touch, apart from the \
        fluid; the oil into the contact: the share of the supply the touching points took. \
        The film below zero: a touching point deeper than the grid's dry gap error, or \
        a closure returned without contact.";
    let p = measured::write(
        "contact-grids",
        "The touching contact as the grid refines",
        "cargo xtask contact --grids",
        intro,
        &[("Steady solves", &t)],
    )?;
    println!("wrote {}", p.display());
    Ok(())
}

/// The dry-limit table: the speeds and supplies on the grids.
fn dry_limits(rows: &mut Vec<serde_json::Value>) -> Result<Table> {
    let (speeds, grids): (&[f64], &[usize]) =
        if crate::quick() { (&[1e-6], &[65]) } else { (&[1e-6, 1e-5, 1e-4, 1e-3], &[65, 129]) };
    let mut t = Table::new(&DRY_LIMIT_COLUMNS);
    for &n in grids {
        for &u in speeds {
            for h in [None, Some(0.0), Some(1e-9), Some(10e-9)] {
                println!("u1 {u:.0e} m/s, {h:?} m, on {n}²");
                let (cells, v) = dry_limit(u, h, n)?;
                t.rows.push(cells);
                rows.push(v);
            }
        }
    }
    Ok(t)
}

/// Runs the supplies on the grids and writes the page. Quickly: 129² and two supplies.
pub fn run(out: &Path) -> Result<()> {
    let (supplies, grids): (&[f64], &[usize]) = if crate::quick() {
        (&[0.2e-9, 1e-9], &[129])
    } else {
        (&[0.1e-9, 0.2e-9, 0.5e-9, 1e-9, 2e-9], &[129, 257])
    };
    let mut t = Table::new(&[
        "supply [nm]",
        "grid",
        "contact",
        "h_c [nm]",
        "ρ̄ h_c / h_oil",
        "film below zero [nm]",
        "contact's share of the load",
        "contact area [m²]",
        "oil into the contact [of the supply]",
        "touching from cycle",
        "cycles",
        "wall [s]",
    ]);
    let mut rows = vec![];
    for &n in grids {
        for &h in supplies {
            for contact in [true, false] {
                println!("{:.1} nm on {n}², contact {contact}", h * 1e9);
                let (cells, v) = solve(h, n, contact)?;
                t.rows.push(cells);
                rows.push(v);
            }
        }
    }
    let dry = dry_limits(&mut rows)?;
    std::fs::create_dir_all(out)?;
    let f = out.join("steady-contact.json");
    std::fs::write(&f, serde_json::to_string_pretty(&rows)? + "\n")?;
    println!("wrote {}", f.display());
    let intro = "The seed's contact (Table 1, u1 = 0.01 m/s, 20 N) through the mass-conserving \
        Reynolds solver, fed supplies thinner than the discrete dry gap's error at the \
        contact's edge, on its own domain [-1.25, 1.25]² a, steady, each answer's error not \
        estimated. With contact (`reynolds.solver.contact`, the default) the solids touch \
        where the lubricated cycles stall with the film closed in an answer settled round the \
        closure; without, such a solve fails (\"the film closed\"). `ρ̄ h_c / h_oil`: the oil \
        crossing the contact at its own thickness (1 at the thin-supply limit). The \
        contact's share of the load and its area: where the solids touch, apart from the \
        fluid (`solid_contact` in `summary.json`); the oil into the contact: the share of the \
        supply the touching points took, which the equations destroy (the contact edge's error \
        on the grid; beyond the oil tolerance, 1 %, the answer is flagged). The film below zero: how far the film \
        went negative somewhere (the solids overlapping: a closure the answer was returned \
        with, flagged). A failed row gives what stopped its last attempt. The dry limits: the \
        same contact at vanishing speed, flooded, fed no oil, 1 and 10 nm, on 65² and 129²: where \
        every lubricated attempt fails and the film is thinner than the grid's dry gap error at \
        the contact's edge (half the cell squared: 7.6e-4 and 1.9e-4 a²/R; the flooded film is \
        2.4e-5 a²/R at 1e-6 m/s, 2.4e-3 at 1e-3 m/s), the last starts from the dry contact; its \
        answer against the core's dry contact on the same grid (the ball, the same load); with \
        no oil at all the solve starts there at once. Flooded, where the film is thicker than \
        that error but the cells wider than the grid rule's and the clamp's attempts fail, the \
        last is the mass-conserving solver with the inflow filled (\"the inflow filled\").";
    let p = measured::write(
        "steady-contact",
        "The solids touching in a steady Reynolds solve",
        "cargo xtask contact",
        intro,
        &[("Steady solves", &t), ("The dry limits", &dry)],
    )?;
    println!("wrote {}", p.display());
    Ok(())
}
