//! A surface pattern in the contact: every grid of the hierarchy carries it, and a steady
//! contact whose crests touch has an answer.
mod common;

use ehl_core::Grid;
use ehl_reynolds::*;

#[test]
fn every_grid_of_the_hierarchy_carries_the_shortest_wave_with_two_cells_a_wavelength() {
    let grid = Grid::new(129, 129, (-1.25, 1.25), (-1.25, 1.25));
    let s = ReynoldsSettings::default();
    // A wave of 0.25 a: 33² has 3.2 cells a wavelength, 17² 1.6: the hierarchy stops at 33².
    assert_eq!(s.carrying(&grid, 0.25).coarsest_points, 33);
    // A wave of 1 a: 17² has 6.4 cells a wavelength, the default coarsest grid stands.
    assert_eq!(s.carrying(&grid, 1.0).coarsest_points, 17);
    // A wave the finest grid barely carries (0.04 a: 2.05 cells on 129², 1.02 on 65²): no
    // coarser grid at all.
    assert_eq!(s.carrying(&grid, 0.04).coarsest_points, 129);
    // A coarsest grid set finer already stays.
    let fine = ReynoldsSettings { coarsest_points: 65, ..s };
    assert_eq!(fine.carrying(&grid, 1.0).coarsest_points, 65);
}

#[test]
fn a_steady_contact_whose_wave_crests_touch_has_an_answer_when_every_grid_carries_the_wave() {
    // The seed's contact fed 25 nm with a transverse wave of 20 nm and 34 µm (0.2525 a), on
    // 129², solved as a march's start is (the relief, then the supply; the coarser grids
    // holding the film content). The crests touch at the rim of the contact. Measured with the
    // hierarchy down to 17² (1.6 cells a wavelength): once the solids were let touch, the
    // coarsest grid's force balance ran away (`H00` down 1.5e-3 a²/R in one visit, the whole
    // contact closed), and every attempt after it failed: no answer. Carrying the wave (down
    // to 33²), the touching cycles stall settled after 162 cycles (the central film still to
    // 9e-10 over the last 40, the force balance within 4.8e-5): the answer is returned,
    // saying so.
    let prm = common::seed();
    let grid = Grid::new(129, 129, (-1.25, 1.25), (-1.25, 1.25));
    let (amplitude, wavelength) = (20e-9 / prm.scales.delta, 34e-6 / prm.scales.a);
    let settings = ReynoldsSettings { coarse_film_content: false, ..Default::default() }
        .carrying(&grid, wavelength);
    let mut s = ReynoldsSolver::new(grid, prm, settings);
    assert_eq!(s.depth(), 3, "129², 65², 33²");
    s.set_extra_gap(|x, _| amplitude * (std::f64::consts::TAU * x / wavelength).cos());
    let hd = 25e-9 / prm.scales.delta;
    s.set_supply(Some(&move |_y| hd));
    let r = s.solve(&mut |_| {}).expect("an answer");
    let settled = r.settled.expect("settled, if not converged");
    assert!(r.touched_from.is_some(), "{r:?}");
    assert!(settled.load_error < SETTLED_BOUND, "{settled:?}");
    // The crests touch at the contact's rim and carry a little of the load (measured 0.2 %);
    // the centre, at a trough, keeps its film (11.1 nm measured; the smooth contact's 9.6 nm
    // plus most of the trough's depth).
    let (share, area) = s.contact();
    assert!(share > 0.0 && share < 0.02 && area > 0.0, "{share:.3e} on {area:.3e}");
    let hc_nm = s.films().0 * prm.scales.delta * 1e9;
    assert!((9.6..20.0).contains(&hc_nm), "h_c {hc_nm:.3} nm");
}
