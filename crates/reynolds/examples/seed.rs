//! Development probe: the seed's conditions (Table 1, u_s = 0.02 m/s: M ≈ 2223, L ≈ 2.49).
use ehl_core::{Contact, Grid, Lubricant};
use ehl_reynolds::*;
fn main() {
    let n: usize = std::env::args().nth(1).map(|s| s.parse().unwrap()).unwrap_or(65);
    let contact = Contact { ball_radius: 9.525e-3, load: 20.0, reduced_modulus: 1.17e11 };
    let lub = Lubricant { eta0: 44.7e-3, alpha: 2.25e-8, p0_roelands: 1.96e8 };
    let prm = ReynoldsParams::from_si(
        &contact,
        &lub,
        0.02,
        ViscosityLaw::Roelands,
        DensityLaw::DowsonHigginson,
    );
    let grid = Grid::new(n, n, (-4.5, 1.5), (-3.0, 3.0));
    let mut s = ReynoldsSolver::new(grid, prm, ReynoldsSettings::default());
    let a2r = prm.scales.delta;
    let rep = s.solve(&mut |c| {
        if c.cycle % 10 == 1 {
            println!(
                "{:>4} res {:.3e} load {:+.3e} Hc {:.4e} ({:.2} nm) Hmin {:.4e}",
                c.cycle,
                c.residual,
                c.load_error,
                c.central_film,
                c.central_film * a2r * 1e9,
                c.minimum_film
            )
        }
    });
    println!("{:?}", rep.map(|r| (r.converged, r.cycles, r.wall_time_s, r.diagnosis)));
}
