//! Published central-film formulas for a circular contact: curve fits to numerical solutions,
//! good to several percent; references, not exact targets.

use ehl_core::{Contact, Lubricant, Moes};

/// Hamrock & Dowson (1977), central film [m], circular contact (`k = 1`):
/// `h_c / R = 2.69 U^0.67 G^0.53 W^−0.067 (1 − 0.61 e^−0.73)`, `U = η0 u_m / (E' R)` with the
/// **mean** velocity `u_m`, `G = α E'`, `W = F / (E' R²)`.
pub fn hamrock_dowson_central(c: &Contact, lub: &Lubricant, u_mean: f64) -> f64 {
    let (r, e) = (c.ball_radius, c.reduced_modulus);
    let u = lub.eta0 * u_mean / (e * r);
    let g = lub.alpha * e;
    let w = c.load / (e * r * r);
    r * 2.69 * u.powf(0.67) * g.powf(0.53) * w.powf(-0.067) * (1.0 - 0.61 * (-0.73f64).exp())
}

/// Hamrock & Dowson (1977), minimum film [m], circular contact (`k = 1`):
/// `h_min / R = 3.63 U^0.68 G^0.49 W^−0.073 (1 − e^−0.68)`, the same `U`, `G`, `W` as
/// [`hamrock_dowson_central`].
pub fn hamrock_dowson_minimum(c: &Contact, lub: &Lubricant, u_mean: f64) -> f64 {
    let (r, e) = (c.ball_radius, c.reduced_modulus);
    let u = lub.eta0 * u_mean / (e * r);
    let g = lub.alpha * e;
    let w = c.load / (e * r * r);
    r * 3.63 * u.powf(0.68) * g.powf(0.49) * w.powf(-0.073) * (1.0 - (-0.68f64).exp())
}

/// Hamrock & Dowson's starvation boundary for a circular contact (Isothermal EHL of point
/// contacts, Part IV: starvation results, J. Lubr. Technol. 99 (1977) 15–23): the inlet distance
/// [a] beyond which the film is fully flooded, `m* = 1 + 3.06 [(R/b)² H]^0.58` with `H = h/R`;
/// for `b = a`, `(R/a)² h/R` is the central film in Hertz units `h_hertz` [a²/R].
pub fn starvation_boundary(h_hertz: f64) -> f64 {
    1.0 + 3.06 * h_hertz.max(0.0).powf(0.58)
}

/// The grid rule's constant: cells no larger than this times `H_c^{2/3}` [a] (`H_c` the NVM
/// central film in Hertz units): half the cell at which the film's existence was measured to end
/// (docs/decisions.md, "The grid rule's constants"). It is a rule for an answer, not for its
/// accuracy (the rule for accuracy is [`cell_for_change`]).
pub const CELLS_PER_FILM: f64 = 0.25;
/// The grid rule: the largest cell [a] on which a steady film of central thickness `h_hertz`
/// (Hertz units [a²/R], the NVM estimate) exists, [`CELLS_PER_FILM`] `· h_hertz^{2/3}`: the
/// width of the side lobes' constriction, where the film is thinnest, over which the gap
/// outside a Hertzian contact rises by the film (`g ∝ (x − a)^{3/2}`).
pub fn cell_needed(h_hertz: f64) -> f64 {
    CELLS_PER_FILM * h_hertz.max(0.0).powf(2.0 / 3.0)
}

/// The discrete dry gap's error at a contact's edge over the cell squared [a²/R per a²]: the
/// seed's contact on 129² carried films of −2e-4 to −4e-4 a²/R along its edge rows where the
/// oil made 1e-4 (docs/decisions.md, "The solids touching in the steady cycles"), the lower
/// end over 0.0195² a²; second order, as the dry contact's approach converges
/// (docs/measured/dry-convergence.md). A film thinner than this is one the grid cannot tell from
/// a closed gap.
pub const DRY_GAP_ERROR_PER_CELL2: f64 = 0.5;

/// The discrete dry gap's error at a contact's edge on cells of `cell` [a], in a²/R
/// ([`DRY_GAP_ERROR_PER_CELL2`] times the cell squared): the thinnest film the grid tells from
/// a closed gap.
pub fn dry_gap_error(cell: f64) -> f64 {
    DRY_GAP_ERROR_PER_CELL2 * cell * cell
}

/// The grid error's constant: the flooded central film's change from half the points per side,
/// `|h_c,2h / h_c − 1|`, is at most this times `ρ²`, `ρ` the cell over `H_c^{2/3}` (`H_c` the
/// NVM central film in Hertz units, the grid rule's width). Measured on `seed-speed-load` (35
/// points, 2 mm/s … 1 m/s, 5 … 80 N, `ρ` = 0.016 … 0.25): the ratio is 2.5–4.3
/// over three decades of speed, growing mildly with the load (2.5–2.8 at 5 N, 3.1–4.3 at 80 N).
/// The fed films change less (starved ones by 0.06–1.8 ρ²): the flooded constant covers both.
pub const GRID_CHANGE_PER_CELL2: f64 = 4.3;

/// The accuracy rule: the largest cell [a] on which the steady film of central thickness
/// `h_hertz` (Hertz units [a²/R], the NVM estimate) moves by at most `change` (relative) from
/// half the points per side: with the change `K ρ²` ([`GRID_CHANGE_PER_CELL2`]),
/// `ρ = √(change / K)`, the width [`cell_needed`] measures cells in; never coarser than
/// [`cell_needed`]. (A sweep asks for the change whose estimated error is its flag limit:
/// `ehl_workbench::accuracy::gci::change_allowed`, 4.8 % for 2 %, `ρ` = 0.106.)
pub fn cell_for_change(h_hertz: f64, change: f64) -> f64 {
    let rho = (change.max(0.0) / GRID_CHANGE_PER_CELL2).sqrt();
    cell_needed(h_hertz) * (rho / CELLS_PER_FILM).min(1.0)
}

/// Nijenbanning, Venner & Moes (Wear 176 (1994) 217–229), central film in Moes' units
/// `H = h_c / R · U^(−1/2)` (`U` with the sum velocity), circular contact (`D = 1`): a blend of
/// the rigid/elastic, isoviscous/piezoviscous asymptotes.
pub fn nvm_central_moes(moes: &Moes) -> f64 {
    let (m, l) = (moes.m, moes.l);
    let d: f64 = 1.0;
    let c = 1.0 + 0.006 * d.ln() + 0.63 * d.powf(4.0 / 7.0);
    let h_ri = 145.0 * (1.0 + 0.796 * d.powf(14.0 / 15.0)).powf(-15.0 / 7.0) / d * m.powi(-2);
    let h_ei = 3.18 * c.powf(-14.0 / 25.0) * d.powf(-1.0 / 15.0) * m.powf(-2.0 / 15.0);
    let h_rp = 1.29 * (1.0 + 0.691 * d).powf(-2.0 / 3.0) * l.powf(2.0 / 3.0);
    let h_ep =
        1.48 * c.powf(-7.0 / 20.0) * d.powf(-1.0 / 24.0) * m.powf(-1.0 / 12.0) * l.powf(0.75);
    let s = 1.5 * (1.0 + (-1.2 * h_ei / h_ri).exp());
    let h00 = 1.8 / d;
    let iso = (h_ri.powf(1.5 * s) + (h_ei.powi(-4) + h00.powi(-4)).powf(-0.375 * s))
        .powf(2.0 / (3.0 * s));
    let piezo = (h_rp.powi(-8) + h_ep.powi(-8)).powf(-s / 8.0);
    (iso + piezo).powf(1.0 / s)
}

/// The same in SI [m]: `h_c = H R sqrt(U)`, `U = η0 u_s / (E' R)`.
pub fn nvm_central(c: &Contact, lub: &Lubricant, u_sum: f64) -> f64 {
    let moes = Moes::from_si(c, lub, u_sum);
    let u = lub.eta0 * u_sum / (c.reduced_modulus * c.ball_radius);
    nvm_central_moes(&moes) * c.ball_radius * u.sqrt()
}

/// Moes film `H_M = h/R · U^(−1/2)` to Hertz film `H = h R / a²`: `H = H_M · (π/ (3M/2)^(…))`.
/// Both are `h` in other units; this converts through `a²/R² = (3/2 W)^(2/3)` and `U`.
pub fn moes_to_hertz_film(h_moes: f64, moes: &Moes) -> f64 {
    // h/R = H_M U^(1/2);  a²/R² = (3 W / 2)^(2/3) with W = M U^(3/4).
    // H = (h/R) / (a²/R²) = H_M U^(1/2) / (1.5 M U^(3/4))^(2/3) = H_M / (1.5 M)^(2/3).
    h_moes / (1.5 * moes.m).powf(2.0 / 3.0)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn formulas_match_their_hand_evaluation_for_the_seed() {
        let c = ehl_core::SEED_CONTACT;
        let lub = ehl_core::SEED_LUBRICANT;
        let hd = hamrock_dowson_central(&c, &lub, 0.01);
        let nvm = nvm_central(&c, &lub, 0.02);
        // Evaluated by hand (Python, from the papers' printed forms, not from this code): Table 1
        // with u_m = 0.01 m/s gives Hamrock–Dowson 14.060099 nm; with u_s = 0.02 m/s (M = 2222.79,
        // L = 2.49138) NVM 14.882409 nm. Relative 1e-6: the references' printed digits.
        assert!((hd / 14.060099e-9 - 1.0).abs() < 1e-6, "HD {hd:e}");
        // The minimum-film fit, by hand the same way: 7.871681 nm.
        let hd_min = hamrock_dowson_minimum(&c, &lub, 0.01);
        assert!((hd_min / 7.871681e-9 - 1.0).abs() < 1e-6, "HD min {hd_min:e}");
        assert!((nvm / 14.882409e-9 - 1.0).abs() < 1e-6, "NVM {nvm:e}");
    }

    #[test]
    fn hertz_conversion_is_consistent() {
        let c = ehl_core::SEED_CONTACT;
        let lub = ehl_core::SEED_LUBRICANT;
        let moes = Moes::from_si(&c, &lub, 0.02);
        let h_si = nvm_central(&c, &lub, 0.02);
        let s = ehl_core::HertzScales::new(&c);
        let direct = s.h_dimless(h_si);
        let via = moes_to_hertz_film(nvm_central_moes(&moes), &moes);
        assert!((direct / via - 1.0).abs() < 1e-12, "{direct} vs {via}");
    }
}
