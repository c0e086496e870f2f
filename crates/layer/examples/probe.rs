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
    let contact = Contact {
        ball_radius: 9.525e-3,
        load: 20.0,
        reduced_modulus: 1.17e11,
    };
    let lub = Lubricant {
        eta0: 44.7e-3,
        alpha: 2.25e-8,
        p0_roelands: 1.96e8,
    };
    let spec = LayerSpec {
        supply_thickness_m: 25e-9,
        modulus_pa: 1e8,
        poisson_ratio: 0.3,
        damper_constant: 5.5e5,
        damper_reading: DamperReading::Factor,
        modulus_law: ModulusLaw::Power,
        reference_pressure_pa: None,
    };
    let grid = Grid::square(n, 1.25);
    let m = LayerModel::new(
        &contact,
        &lub,
        &spec,
        0.01,
        grid,
        DrySettings::default(),
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
    let time = TimeSettings {
        scheme,
        steps_per_cell: nt,
        ..TimeSettings::default()
    };
    let stop = StopSettings {
        steady_tolerance: 1e-3,
        window_travel_a: 0.5,
        window_time_s: 0.5,
        until_features_passed: false,
        max_time_s: 0.2,
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
        }
        Err(e) => println!("error: {e}"),
    }
}
