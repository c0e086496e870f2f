//! Grid convergence studies, with observed orders printed.

use anyhow::Result;
use ehl_core::hertz::{self, observed_order};
use ehl_core::{DryProblem, DrySettings, DrySolver, Grid, Start};
use ehl_workbench::plot::{self, Mark, Panel, Series};
use std::path::{Path, PathBuf};
use std::time::Instant;

/// Dry Hertz contact on 65² … `max`² over `[-1.25a, 1.25a]²`: errors against Hertz, observed
/// orders between successive grids, a log–log plot of error against spacing and a JSON record.
pub fn dry(out: &Path, max: usize) -> Result<Vec<PathBuf>> {
    std::fs::create_dir_all(out)?;
    let load = 2.0 * std::f64::consts::PI / 3.0;
    let mut rows = vec![];
    println!("Dry Hertz contact, domain [-1.25a, 1.25a]^2, tolerance 1e-8 (RMS gap / (a^2/R))");
    println!(
        "{:>5} {:>9} {:>11} {:>11} {:>11} {:>11} {:>5} {:>9}",
        "n", "dX", "p_max-1", "a_c/a-1", "delta-1", "L2(p)", "its", "time[s]"
    );
    for n in crate::grid_sizes(max) {
        let g = Grid::square(n, 1.25);
        let solver = DrySolver::new(g, DrySettings::default());
        let f = g.paraboloid();
        let prob = DryProblem { rigid_gap: f.view(), compliance: None, load };
        let (mut p, mut w) = (g.zeros(), g.zeros());
        let t = Instant::now();
        let rep = solver.solve(&prob, &mut p, &mut w, Start::Flat)?;
        let time = t.elapsed().as_secs_f64();
        let c = hertz::compare(&g, &p, rep.h0);
        println!(
            "{:>5} {:>9.5} {:>+11.3e} {:>+11.3e} {:>+11.3e} {:>11.3e} {:>5} {:>9.4}",
            n,
            g.dx(),
            c.p_max_error,
            c.contact_radius_error,
            c.approach_error,
            c.pressure_l2_error,
            rep.iterations,
            time
        );
        rows.push((n, g.dx(), c, rep.iterations, time));
    }
    println!("Observed orders (log2 of successive error ratios):");
    println!("{:>11} {:>9} {:>9} {:>9} {:>9}", "grids", "p_max", "a_c", "delta", "L2(p)");
    let mut orders = vec![];
    for k in 1..rows.len() {
        let (a, b) = (&rows[k - 1].2, &rows[k].2);
        let o = [
            observed_order(a.p_max_error, b.p_max_error, 2.0),
            observed_order(a.contact_radius_error, b.contact_radius_error, 2.0),
            observed_order(a.approach_error, b.approach_error, 2.0),
            observed_order(a.pressure_l2_error, b.pressure_l2_error, 2.0),
        ];
        println!(
            "{:>5}->{:<5} {:>9.2} {:>9.2} {:>9.2} {:>9.2}",
            rows[k - 1].0,
            rows[k].0,
            o[0],
            o[1],
            o[2],
            o[3]
        );
        orders.push(serde_json::json!({
            "from": rows[k - 1].0, "to": rows[k].0,
            "max_pressure": o[0], "contact_radius": o[1], "approach": o[2], "pressure_l2": o[3],
        }));
    }
    let series = |label: &str, f: fn(&hertz::Comparison) -> f64| {
        Series::new(label, rows.iter().map(|r| (r.1, f(&r.2).abs())).collect(), Mark::LinePoints)
    };
    let png = out.join("dry_convergence.png");
    plot::charts(
        &png,
        &[Panel::new(
            "Dry Hertz contact: error against grid spacing",
            "grid spacing ΔX / a",
            "|error| (relative)",
            vec![
                series("max pressure", |c| c.p_max_error),
                series("contact radius (area-equivalent)", |c| c.contact_radius_error),
                series("approach", |c| c.approach_error),
                series("pressure L2", |c| c.pressure_l2_error),
            ],
        )
        .log_log()
        .legend(plotters::prelude::SeriesLabelPosition::LowerRight)],
        "Table 1 ball: R = 9.525 mm, F = 20 N, E' = 117 GPa; domain [-1.25a, 1.25a]^2; tolerance 1e-8",
    )?;
    let json = out.join("dry_convergence.json");
    let record = serde_json::json!({
        "study": "dry Hertz grid convergence",
        "domain_a": [-1.25, 1.25],
        "grids": rows.iter().map(|r| serde_json::json!({
            "n": r.0, "dx_a": r.1, "errors": r.2, "iterations": r.3, "solve_time_s": r.4,
        })).collect::<Vec<_>>(),
        "observed_orders": orders,
    });
    std::fs::write(&json, serde_json::to_string_pretty(&record)? + "\n")?;
    let mut grids = crate::measured::Table::new(&[
        "grid",
        "ΔX [a]",
        "p_max / p_h − 1",
        "contact radius / a − 1",
        "approach error",
        "pressure L2 error",
        "iterations",
        "solve [s]",
    ]);
    for (n, dx, c, its, t) in &rows {
        grids.rows.push(vec![
            format!("{n}²"),
            format!("{dx:.5}"),
            format!("{:+.2e}", c.p_max_error),
            format!("{:+.2e}", c.contact_radius_error),
            format!("{:+.2e}", c.approach_error),
            format!("{:.2e}", c.pressure_l2_error),
            its.to_string(),
            format!("{t:.4}"),
        ]);
    }
    let mut ord = crate::measured::Table::new(&[
        "grids",
        "maximum pressure",
        "contact radius",
        "approach",
        "pressure L2",
    ]);
    for o in &orders {
        let f = |k: &str| format!("{:.2}", o[k].as_f64().unwrap_or(f64::NAN));
        ord.rows.push(vec![
            format!("{}² → {}²", o["from"], o["to"]),
            f("max_pressure"),
            f("contact_radius"),
            f("approach"),
            f("pressure_l2"),
        ]);
    }
    let page = crate::measured::write(
        "dry-convergence",
        "The dry contact against Hertz",
        &format!("cargo xtask convergence dry --max-points {max}"),
        "The core's dry contact solver on the seed's ball (Table 1: R = 9.525 mm, F = 20 N, \
         E' = 117 GPa) over `[-1.25, 1.25]² a`, from a flat start to its tolerance (1e-8 RMS gap \
         over `a²/R`), against Hertz's analytic solution; the observed orders are log2 of \
         successive error ratios (the square-root edge of the Hertz pressure limits the pressure's \
         L2 order to about 1, and the contact's edge is known to a cell).",
        &[("Each grid", &grids), ("Observed orders", &ord)],
    )?;
    Ok(vec![png, json, page])
}
