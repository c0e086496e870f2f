//! The Reynolds answer's terminal report.

use super::ReynoldsOutcome;
use crate::model::Outcome;

/// The terminal report.
pub(super) fn reynolds_report(o: &ReynoldsOutcome) -> String {
    use std::fmt::Write;
    let mut out = String::new();

    let (hc, hmin, pmax) = o.films();
    let s = &o.prm.scales;
    let _ = writeln!(
        out,
        "scene {} ({}x{}): {} in {} cycles, {:.2} s (setup {:.2} s); M = {:.2}, L = {:.3}",
        o.scene.name,
        o.grid.nx,
        o.grid.ny,
        if o.report.converged { "converged" } else { "settled" },
        o.report.cycles,
        o.report.wall_time_s,
        o.setup_time_s,
        o.prm.moes.m,
        o.prm.moes.l
    );
    if let Some(c) = Outcome::caveat(o) {
        let _ = writeln!(out, "  caveat: {c}");
    }
    if o.scene.reynolds.as_ref().is_some_and(|r| r.moes.is_some()) {
        let (c, u_sum) = o.scene.reynolds_conditions();
        let _ = writeln!(
            out,
            "  load and velocity from Moes M, L: F = {:.4} N, u1 = u2 = {:.4e} m/s (conditions.load_n = {} N not used)",
            c.load,
            0.5 * u_sum,
            o.scene.conditions.load_n
        );
    }
    let _ = writeln!(
        out,
        "  central film {:.4e} m (H = {:.5}), minimum film {:.4e} m (H = {:.5}), max pressure {:.4e} Pa ({:.4} p_h)",
        s.h_si(hc),
        hc,
        s.h_si(hmin),
        hmin,
        s.p_si(pmax),
        pmax
    );
    let _ = writeln!(
        out,
        "  formulas: Hamrock-Dowson {:.4e} m, Nijenbanning-Venner-Moes {:.4e} m",
        o.formulas.0, o.formulas.1
    );
    // Where the solids touched during a march: the most of the load the contact carried.
    if let Some(t) = &o.transient
        && let Some(r) =
            t.rows.iter().max_by(|a, b| a.contact_load_share.total_cmp(&b.contact_load_share))
        && r.contact_area_m2 > 0.0
        && let Some(last) = t.rows.last()
    {
        let _ = writeln!(
            out,
            "  contact (the film closed, the solids touching): at most {:.2e} of the load on {:.3e} m² at t = {:.4} s; at the end {:.2e} on {:.3e} m²",
            r.contact_load_share,
            r.contact_area_m2,
            r.t_s,
            last.contact_load_share,
            last.contact_area_m2
        );
    }
    if o.report.inflow_filled {
        let _ = writeln!(
            out,
            "  flooded through the film content: the clamp's attempts failed on cells wider than the grid rule's; the answer is the mass-conserving solver's, the gap along the inflow boundary filled"
        );
    }
    // A steady answer whose lubricated cycles stalled with the film closed: the solids touch
    // there.
    if let Some(c) = Outcome::solid_contact(o).filter(|_| o.report.from_dry)
        && o.transient.is_none()
    {
        let why = if o.report.first_attempt.is_none() {
            "no oil supplied: the dry contact"
        } else {
            "every lubricated attempt failed, the film thinner than this grid tells from a closed gap; from the dry contact"
        };
        let _ = writeln!(
            out,
            "  contact ({why}): the solids carry {:.4} of the load on {:.3e} m², contact pressure up to {:.4e} Pa",
            c.load_share, c.area_m2, c.max_pressure_pa
        );
    } else if let (Some(k), Some(c)) = (o.report.touched_from, Outcome::solid_contact(o))
        && o.transient.is_none()
    {
        let _ = writeln!(
            out,
            "  contact (the cycles stalled with the film closed; the solids touch there from cycle {k}): {:.2e} of the load on {:.3e} m², contact pressure up to {:.4e} Pa",
            c.load_share, c.area_m2, c.max_pressure_pa
        );
    }
    // Where the supplied oil went: what the touching points took is oil the discrete
    // equations lost.
    if let Some(b) = o.oil {
        let share = |v: f64| 100.0 * v / b.reference_supply;
        let contact = match (&o.transient, o.oil_into_contact()) {
            (Some(_), Some(c)) => format!(
                "; the touching points took {:.3} % of the oil supplied over the march (at most {:.3} % of a step's)",
                100.0 * c,
                100.0 * o.oil_into_contact_in_a_step().unwrap_or(0.0)
            ),
            (None, _) => format!(", into the contact {:.3} %", share(b.into_contact)),
            _ => String::new(),
        };
        let _ = writeln!(
            out,
            "  oil (of the supply{}): carried out {:.3} %, pressed out at the edges {:.3} %{contact}, unaccounted {:.1e} %",
            if o.transient.is_some() { ", the last step" } else { "" },
            share(b.carried_out),
            share(b.pressed_out),
            share(b.unaccounted)
        );
    }

    out
}
