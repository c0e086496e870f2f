//! Times the deformation operator's FFT convolution (one thread) on 257², 513², 1025².
fn main() {
    let pool = rayon::ThreadPoolBuilder::new().num_threads(1).build().unwrap();
    pool.install(|| {
        for n in [257usize, 513, 1025] {
            let g = ehl_core::Grid::square(n, 1.25);
            let op = ehl_core::deformation::Deformation::new(g);
            let p = g.field(ehl_core::hertz::pressure);
            let mut w = g.zeros();
            op.apply(p.view(), w.view_mut());
            let reps = (200_000_000 / (n * n)).max(3);
            let t0 = std::time::Instant::now();
            for _ in 0..reps {
                op.apply(p.view(), w.view_mut());
            }
            println!("{n}²: {:.3} ms per apply", t0.elapsed().as_secs_f64() / reps as f64 * 1e3);
        }
    });
}
