//! The lines under a comparison's table, per model: how its error was estimated, where its
//! solids touch, its last passage through a pattern with the passage's errors, and its flags.

use super::Comparison;
use ehl_core::observe::ErrorBar;

impl Comparison {
    /// The lines under the table, per model: how its error was estimated, where its solids
    /// touch (a lubricated model), and its flag.
    pub(super) fn notes(&self) -> String {
        let mut t = String::new();
        for e in &self.entries {
            let o = match e.outcome.as_ref() {
                Ok(o) => o,
                Err(err) => {
                    if let Some(p) = err.partial() {
                        t += &format!(
                            "  {}: its march failed after {} steps (t = {:.6e} s): the record up to there and that state's fields are in {}/ (failure.json)\n",
                            e.name(),
                            p.steps,
                            p.t_s,
                            e.name()
                        );
                    }
                    continue;
                }
            };
            if let Some((est, limit)) = o.estimate() {
                let within = est.worst().is_some_and(|w| w <= limit);
                t += &format!(
                    "  {}: error {}{}\n",
                    e.name(),
                    est.method,
                    if within { format!("; within {:.1} %", 100.0 * limit) } else { String::new() }
                );
            }
            // A lubricated model whose solids touch somewhere: the contact apart from the fluid.
            if let Some(c) = o.solid_contact().filter(|c| o.lubricated() && c.area_m2 > 0.0) {
                t += &format!(
                    "  {}: the solids touch: {:.2e} of the load on {:.3e} m², contact pressure up to {:.4} GPa\n",
                    e.name(),
                    c.load_share,
                    c.area_m2,
                    c.max_pressure_pa * 1e-9
                );
            }
            // A march through a patterned relief: its last passage, the answer to compare,
            // each statistic with its error where one was estimated.
            if let Some(p) = o.passage() {
                let est = o.estimate().map(|(e, _)| e.passage);
                let bars = est.unwrap_or_default();
                let with_bar = crate::accuracy::with_bar;
                let film = bars.central_film_mean;
                let lambda = p.lambda.map_or(String::new(), |l| {
                    // λ is the mean film over a fixed height: the film's error over it.
                    let b = film.filter(|_| p.central_film_mean_m > 0.0).map(|b| ErrorBar {
                        absolute: b.absolute / p.central_film_mean_m * l,
                        ..b
                    });
                    format!(", λ {}", with_bar(l, b.as_ref(), 1.0, 2))
                });
                let amp = match (p.deformed_amplitude_m, p.amplitude_ratio) {
                    (Some(d), Some(r)) => format!(
                        ", wave at the centre {:.3} nm (A_d/A_i {})",
                        d * 1e9,
                        with_bar(r, bars.amplitude_ratio.as_ref(), 1.0, 3),
                    ),
                    _ => String::new(),
                };
                let solids = match (p.contact_load_share_mean, p.contact_area_mean_m2) {
                    (Some(s), Some(a)) => format!(
                        ", the solids carry {} % of the load (mean; {:.2} % at most) on {} m²",
                        with_bar(s, bars.contact_load_share_mean.as_ref(), 100.0, 2),
                        100.0 * p.contact_load_share_max.unwrap_or(s),
                        match bars.contact_area_mean {
                            Some(b) => format!("{:.3e} ± {:.1e}", a, b.absolute),
                            None => format!("{a:.3e}"),
                        }
                    ),
                    _ => String::new(),
                };
                let unestimated = if est.is_some() && bars.is_empty() {
                    "; its error not estimated (no coarser grid carried the pattern through a passage)"
                } else {
                    ""
                };
                t += &format!(
                    "  {}: last passage ({:.3} mm): h_c {} nm mean ({:.3}–{:.3}), h_min {:.3} nm{lambda}{amp}{solids}{unestimated}\n",
                    e.name(),
                    p.travel_m * 1e3,
                    with_bar(p.central_film_mean_m, film.as_ref(), 1e9, 3),
                    p.central_film_min_m * 1e9,
                    p.central_film_max_m * 1e9,
                    p.minimum_film_m * 1e9,
                );
            }
            if let Some(c) = o.caveat() {
                t += &format!("  {}: FLAGGED: {c}\n", e.name());
            }
        }
        t
    }
}
