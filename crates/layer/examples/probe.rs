use ehl_core::*;
use ehl_layer::*;
fn main() {
    let args: Vec<String> = std::env::args().collect();
    let n: usize = args.get(1).map(|s| s.parse().unwrap()).unwrap_or(129);
    let scheme = if args.get(2).map(|s| s.as_str()) == Some("explicit") {
        Scheme::Explicit
    } else {
        Scheme::Implicit
    };
    let nt: f64 = args.get(3).map(|s| s.parse().unwrap()).unwrap_or(10.0);
    let contact = Contact { ball_radius: 9.525e-3, load: 20.0, reduced_modulus: 1.17e11 };
    let lub = Lubricant { eta0: 44.7e-3, alpha: 2.25e-8, p0_roelands: 1.96e8 };
    let spec = LayerSpec {
        supply_thickness_m: 25e-9,
        modulus_pa: 1e8,
        poisson_ratio: 0.3,
        damper_constant: 5.5e5,
        damper_reading: DamperReading::Factor,
        modulus_law: ModulusLaw::Power,
        reference_pressure_pa: None,
        coefficient_smoothing_a: args.get(6).map(|s| s.parse().unwrap()).unwrap_or(0.0),
    };
    let grid = Grid::square(n, 1.25);
    let m = LayerModel::new(
        &contact,
        &lub,
        &spec,
        0.01,
        grid,
        DrySettings {
            tolerance: args.get(5).map(|s| s.parse().unwrap()).unwrap_or(1e-8),
            ..DrySettings::default()
        },
        vec![],
    );
    println!(
        "stability estimate {:.3e} s; dt(n_t) {:.3e}",
        stability_estimate(&m),
        grid.dx() * m.scales.a / (nt * 0.01)
    );
    let (sq, rep) = squeeze_steady(&m).unwrap();
    let mon = Monitor::of(&m, &sq, 0);
    println!("squeeze steady {n}: {:?}\n  {:?}", rep, mon);
    let mut st = uniform_state(&m).unwrap();
    let mut stepper = Stepper::new(scheme, 0);
    let time = TimeSettings { scheme, steps_per_cell: nt, ..TimeSettings::default() };
    let stop = StopSettings {
        steady_tolerance: 1e-3,
        window_travel_a: 0.5,
        window_time_s: 0.5,
        until_features_passed: false,
        max_time_s: args.get(4).map(|s| s.parse().unwrap()).unwrap_or(0.2),
    };
    let rec = run(&m, &mut st, &mut stepper, &time, &stop, &[], &mut |_| {});
    match rec {
        Ok(rec) => {
            let last = rec.series.last().unwrap();
            println!(
                "rolling {scheme:?}: {} steps, {} solves, {} its, {:.2} s wall, {}\n  {:?}",
                rec.steps, rec.solves, rec.iterations, rec.wall_time_s, rec.stop_reason, last
            );
            println!("  ms/step {:.2}", rec.wall_time_s / rec.steps as f64 * 1e3);
            let ((j, i), pm) =
                st.p.indexed_iter()
                    .fold(((0, 0), 0.0), |a, (ix, &v)| if v > a.1 { (ix, v) } else { a });
            println!("  max P {pm:.4} at x={:.4} y={:.4}", grid.x(i), grid.y(j));
            let l = st.thickness(&m);
            for di in -3i64..=3 {
                let ii = (i as i64 + di) as usize;
                println!(
                    "   x={:.4} P={:.4} L/L0={:.4} eps={:.4}",
                    grid.x(ii),
                    st.p[[j, ii]],
                    l[[j, ii]] / m.l0,
                    st.eps[[j, ii]]
                );
            }
            ndarray_npy::write_npy("/tmp/p.npy", &st.p).unwrap();
            ndarray_npy::write_npy("/tmp/eps.npy", &st.eps).unwrap();
            let j0 = grid.row_nearest(0.0);
            for ii in (0..grid.nx).step_by(grid.nx / 16) {
                println!(
                    "   cl x={:.3} P={:.4} L/L0={:.4}",
                    grid.x(ii),
                    st.p[[j0, ii]],
                    l[[j0, ii]] / m.l0
                );
            }
        }
        Err(e) => println!("error: {e}"),
    }
}
