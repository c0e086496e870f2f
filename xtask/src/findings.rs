//! What the comparisons of the seed's scenes show, measured: each built-in comparison that
//! moves (a stop, a start, a hole, a dent) through every model, each model's history reduced to
//! its start, end and extremes with their times. Writes `docs/measured/findings.md`, which
//! docs/findings.md reads from.

use crate::measured::{self, Table};
use anyhow::Result;
use ehl_workbench::compare;

/// The comparisons, in the order docs/findings.md tells them.
const SCENES: &[&str] = &[
    "hole-compare",
    "hole-starved-compare",
    "stop-compare",
    "stop-start-compare",
    "rolling-from-squeezed-compare",
    "startup-ramp-compare",
    "dent-shallow-compare",
];

/// The value of `pick` at its extreme (`max` or not) over `rows`, with its time.
fn extreme(rows: &[(f64, f64)], max: bool) -> Option<(f64, f64)> {
    rows.iter()
        .copied()
        .filter(|r| r.1.is_finite())
        .reduce(|a, b| if (b.1 > a.1) == max && b.1 != a.1 { b } else { a })
}

/// Runs every comparison and writes the page.
pub fn run(out: &std::path::Path) -> Result<()> {
    let mut tables = vec![];
    // Quickly, one of them: the code path (a hole that closes the film, where the solids
    // touch; every scene's rows are made the same way).
    let scenes: &[&str] = if crate::quick() { &["hole-starved-compare"] } else { SCENES };
    for name in scenes {
        let scene = ehl_scene::builtin(name)?;
        let scene = scene.with_points(crate::scene_points(&scene))?;
        let c = compare::run(&scene);
        // The histories and figures behind the page's rows.
        c.write(&out.join(name))?;
        let u = scene.conditions.rolling_velocity_m_s.unwrap_or(0.0);
        let mut t = Table::new(&[
            "model",
            "h_c start → end [nm]",
            "h_c least (at)",
            "h_c most (at)",
            "h_min least (at)",
            "p_max most [GPa] (at)",
            "the solids' share of the load, most (at)",
            "wall [s]",
        ]);
        for e in &c.entries {
            let Ok(o) = &e.outcome else {
                let why = e.outcome.as_ref().err().map(|e| e.to_string()).unwrap_or_default();
                t.rows.push(vec![
                    e.name(),
                    format!("failed: {}", why.chars().take(100).collect::<String>()),
                ]);
                continue;
            };
            let a = o.scales().a;
            // Times in s and, rolling, in transits `a/u` of the scene's speed.
            let at = |t: f64| {
                if u > 0.0 {
                    format!("{t:.4} s, {:.2} a/u", t * u / a)
                } else {
                    format!("{t:.4} s")
                }
            };
            let Some(h) = o.history() else {
                let ob = o.observables();
                t.rows.push(vec![
                    e.name(),
                    format!("{:.3} (steady)", ob.central_film_m * 1e9),
                    "-".into(),
                    "-".into(),
                    format!("{:.3}", ob.minimum_film_m * 1e9),
                    format!("{:.4}", ob.max_pressure_pa * 1e-9),
                    "-".into(),
                    format!("{:.1}", e.wall_time_s),
                ]);
                continue;
            };
            let series = |f: fn(&ehl_core::observe::Observables) -> f64| -> Vec<(f64, f64)> {
                h.iter().map(|(t, ob)| (*t, f(ob))).collect()
            };
            let hc = series(|o| o.central_film_m * 1e9);
            let hm = series(|o| o.minimum_film_m * 1e9);
            let pm = series(|o| o.max_pressure_pa * 1e-9);
            let cell = |v: Option<(f64, f64)>, d: usize| {
                v.map_or("-".into(), |(tt, x)| format!("{x:.d$} ({})", at(tt)))
            };
            let share: Vec<(f64, f64)> = o
                .time_series()?
                .unwrap_or_default()
                .iter()
                .filter_map(|r| Some((r["t_s"].as_f64()?, r["contact_load_share"].as_f64()?)))
                .collect();
            t.rows.push(vec![
                e.name(),
                format!(
                    "{:.3} → {:.3}",
                    hc.first().map_or(f64::NAN, |v| v.1),
                    hc.last().map_or(f64::NAN, |v| v.1)
                ),
                cell(extreme(&hc, false), 3),
                cell(extreme(&hc, true), 3),
                cell(extreme(&hm, false), 3),
                cell(extreme(&pm, true), 4),
                if share.is_empty() {
                    "-".into()
                } else {
                    cell(extreme(&share, true).map(|(tt, s)| (tt, 100.0 * s)), 2) + " %"
                },
                format!("{:.1}", e.wall_time_s),
            ]);
        }
        let g = scene.grid();
        tables.push((
            format!("`{name}` ({}², {}): {}", g.nx, scene.model_names(), scene.description),
            t,
        ));
    }
    let refs: Vec<(&str, &Table)> = tables.iter().map(|(c, t)| (c.as_str(), t)).collect();
    measured::write(
        "findings",
        "What the comparisons show, measured",
        "cargo xtask findings",
        "Each built-in comparison that moves (a hole or a dent passing, a stop, a start) through \
         every model on its own grid, the models at once. Each model's history (after every step) \
         reduced to the central film at its start and end, its least and most, the least minimum \
         film, the largest pressure and, for the Reynolds solver, the largest share of the load \
         the solids carry where its film closed; times from the start of the motion, in s and \
         in `a/u` (the time the scene's rolling speed takes to carry the surfaces over a contact \
         radius). What they show: docs/findings.md.",
        &refs,
    )?;
    Ok(())
}
